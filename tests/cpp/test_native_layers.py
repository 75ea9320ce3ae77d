"""The core's layering: native/src is split into parts, each in its own folder with its headers
beside its sources, and a file may include the headers of its own part and of the parts
below it, never above.

    base < mesh < linear_algebra < local_fit < system < strategies < deformer

A file's part is its folder; an include names the part it reaches into ("mesh/node_graph.h").
The bindings (native/bindings) sit above all of them and are not checked."""
import pathlib
import re

ROOT = pathlib.Path(__file__).resolve().parents[2]
SRC = ROOT / "native" / "src"
PARTS = ["base", "mesh", "linear_algebra", "local_fit", "system", "strategies", "deformer"]
INCLUDE_LINE = re.compile(r'#include "([a-z_]+)/([a-z_0-9]+)\.h"')


def includes(path):
    """(part, name) of each project include of a file."""
    return INCLUDE_LINE.findall(path.read_text())


def core_files():
    return sorted(SRC.glob("*/*.cpp")) + sorted(SRC.glob("*/*.h"))


def test_every_file_lies_in_a_part_folder():
    loose = [p.name for p in SRC.iterdir() if p.is_file()]
    assert not loose, f"files directly in native/src: put them in their part's folder: {loose}"
    assert sorted(p.name for p in SRC.iterdir() if p.is_dir()) == sorted(PARTS)
    assert not (ROOT / "native" / "include").exists(), "headers live beside their sources now"


def test_every_include_names_an_existing_header():
    dead = [f"{path.relative_to(SRC)} includes {part}/{name}.h"
            for path in core_files() for part, name in includes(path)
            if not (SRC / part / f"{name}.h").is_file()]
    assert not dead, "\n".join(dead)


def upward_includes(files):
    """(path, part) pairs -> the includes of a part above the file's own, as messages."""
    rank = {part: k for k, part in enumerate(PARTS)}
    return [
        f"{path.name} ({part}) includes {inc_part}/{name}.h"
        for path, part in files
        for inc_part, name in includes(path)
        if inc_part in rank and rank[inc_part] > rank[part]
    ]


def test_no_file_includes_a_part_above_its_own():
    upward = upward_includes([(p, p.parent.name) for p in core_files()])
    assert not upward, "includes that point up:\n" + "\n".join(upward)


def test_the_check_sees_an_upward_include(tmp_path):
    # The rule itself: a base file that included the deformer would be reported.
    fake = tmp_path / "types.h"
    fake.write_text('#include "deformer/deformer.h"\n#include "base/errors.h"\n')
    assert upward_includes([(fake, "base")]) == ["types.h (base) includes deformer/deformer.h"]
