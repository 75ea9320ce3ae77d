"""The core's layering: native/src is split into parts, each in its own folder, and a file
may include the headers of its own part and of the parts below it, never above.

    base < mesh < linear_algebra < local_fit < system < strategies < deformer

A header's part is the folder of its .cpp; the header-only ones are listed in HEADER_ONLY.
The bindings (native/bindings) sit above all of them and are not checked."""
import pathlib
import re

ROOT = pathlib.Path(__file__).resolve().parents[2]
SRC = ROOT / "native" / "src"
INCLUDE = ROOT / "native" / "include" / "edgedeform"
PARTS = ["base", "mesh", "linear_algebra", "local_fit", "system", "strategies", "deformer"]
HEADER_ONLY = {
    "errors": "base",
    "iteration_point": "base",
    "cotangent": "mesh",
    "lanes": "local_fit",
    "term_shares": "local_fit",
    "fixed_point_problem": "strategies",
}
INCLUDE_LINE = re.compile(r'#include "edgedeform/([a-z_]+)\.h"')


def part_of_each_name():
    parts = dict(HEADER_ONLY)
    for cpp in SRC.glob("*/*.cpp"):
        parts[cpp.stem] = cpp.parent.name
    return parts


def includes(path):
    return INCLUDE_LINE.findall(path.read_text())


def test_every_source_lies_in_a_part_folder():
    assert not list(SRC.glob("*.cpp")), "a .cpp directly in native/src: put it in its part's folder"
    assert sorted(p.name for p in SRC.iterdir() if p.is_dir()) == sorted(PARTS)


def test_every_header_has_a_part():
    parts = part_of_each_name()
    missing = sorted(h.stem for h in INCLUDE.glob("*.h") if h.stem not in parts)
    assert not missing, f"headers of no part (add a .cpp to a part folder or list them in HEADER_ONLY): {missing}"


def upward_includes(files, parts):
    """(path, part) pairs -> the includes of a part above the file's own, as messages."""
    rank = {part: k for k, part in enumerate(PARTS)}
    return [
        f"{path.name} ({part}) includes {name}.h ({parts[name]})"
        for path, part in files
        for name in includes(path)
        if rank[parts[name]] > rank[part]
    ]


def test_no_file_includes_a_part_above_its_own():
    parts = part_of_each_name()
    files = [(h, parts[h.stem]) for h in INCLUDE.glob("*.h")] + [(c, c.parent.name) for c in SRC.glob("*/*.cpp")]
    upward = upward_includes(files, parts)
    assert not upward, "includes that point up:\n" + "\n".join(upward)


def test_the_check_sees_an_upward_include(tmp_path):
    # The rule itself: a base file that included the deformer would be reported.
    fake = tmp_path / "types.h"
    fake.write_text('#include "edgedeform/deformer.h"\n#include "edgedeform/errors.h"\n')
    assert upward_includes([(fake, "base")], part_of_each_name()) == ["types.h (base) includes deformer.h (deformer)"]
