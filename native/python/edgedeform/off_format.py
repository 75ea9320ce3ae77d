"""Object File Format (OFF and its ST/C/N prefixes), read and written back with only the
vertex positions changed.

Kept as they were: the header, comments, vertex colours and texture coordinates, the faces
(any corner count) with their colours, and anything after the faces. Replaced: the three
coordinates of each vertex line and, in NOFF files, the vertex normals, which are
recomputed from the deformed faces (area-weighted). One vertex and one face per line, as
every OFF writer we know produces; binary OFF and 4D/nD variants are refused by name.
Counts are checked against the lines that are there (negative or too large ones refused).
"""

import numpy as np

from .format_error import at_line, parse_index, parse_number, require_count
from .number_text import float_text, floats_text
from .polygons import vertex_normals
from .text_lines import line_ending, split_lines


class OffFile:
    def __init__(self, lines, v_lines, has_normals, sizes, corners, has):
        self.lines = lines
        self.v_lines = v_lines
        self.has_normals = has_normals
        self.sizes, self.corners = sizes, corners
        self.has = has

    def rewrite(self, positions):
        lines = list(self.lines)
        notes = []
        normals = None
        if self.has_normals:
            old = np.array([[float(t) for t in _data(lines[k]).split()[3:6]] for k in self.v_lines])
            normals = vertex_normals(positions, self.sizes, self.corners, old)
            notes.append("vertex normals (NOFF) recomputed from the deformed faces")
        for i, line_no in enumerate(self.v_lines):
            line = lines[line_no]
            data, comment = _data(line), line[len(_data(line)):].rstrip("\r\n")
            rest = data.split()[6 if self.has_normals else 3:]
            new = [float_text(c) for c in positions[i]]
            if normals is not None:
                new += [float_text(c) for c in normals[i]]
            lines[line_no] = " ".join(new + rest) + comment + line_ending(line)
        return "".join(lines), notes


def _data(line):
    return line.split("#", 1)[0].rstrip("\r\n")


def read(text):
    """Parse OFF text. Every count is checked against the lines that are there before any
    array is made; a bad file raises MeshFormatError naming the line."""
    lines = split_lines(text)
    data = ((k, _data(line).split()) for k, line in enumerate(lines))
    data = [(k, t) for k, t in data if t]
    if not data or not data[0][1][0].upper().endswith("OFF"):
        raise at_line(data[0][0] if data else 0, "missing OFF header")
    keyword = data[0][1][0]
    prefix = keyword[:-3]  # [ST][C][N][4][n]OFF
    if "BINARY" in (t.upper() for t in data[0][1][1:]):
        raise at_line(data[0][0], "binary OFF is not supported (write it as text OFF or PLY)")
    if "4" in prefix or prefix.endswith("n"):
        raise at_line(data[0][0], f"'{keyword}' (4D or nD vertices) is not supported")
    prefix = prefix.upper()
    if set(prefix) - set("STCN"):
        raise at_line(data[0][0], f"unknown OFF header '{keyword}'")
    has_normals = "N" in prefix
    counts_line, head, rows = data[0][0], data[0][1][1:], data[1:]
    if not head:
        if not rows:
            raise at_line(counts_line, "missing vertex and face counts")
        (counts_line, head), rows = rows[0], rows[1:]
    if len(head) < 2:
        raise at_line(counts_line, f"expected the vertex and face counts, found {' '.join(head)!r}")
    nv = require_count(head[0], counts_line, "vertices")
    nf = require_count(head[1], counts_line, "faces")
    if len(rows) < nv + nf:
        raise at_line(counts_line, f"{nv} vertices and {nf} faces declared, the file has "
                                   f"{len(rows)} lines of data after this one")
    per_vertex = 6 if has_normals else 3
    coords = []
    for k, t in rows[:nv]:
        if len(t) < per_vertex:
            raise at_line(k, f"a vertex line needs {per_vertex} numbers for '{keyword}', found {len(t)}")
        coords.append([parse_number(x, float, k, "a coordinate") for x in t[:per_vertex]][:3])
    sizes, corners, face_colours = [], [], False
    for k, t in rows[nv:nv + nf]:
        size = parse_number(t[0], int, k, "a face's corner count")
        if size < 3:
            raise at_line(k, f"a face needs at least 3 corners, this one declares {size}")
        if len(t) - 1 < size:
            raise at_line(k, f"the face declares {size} corners, the line has {len(t) - 1} numbers")
        corners += [parse_index(x, k) for x in t[1:1 + size]]
        sizes.append(size)
        face_colours = face_colours or len(t) > 1 + size
    has = set()
    if "C" in prefix:
        has.add("vertex colours")
    if "ST" in prefix:
        has.add("texture coordinates")
    if has_normals:
        has.add("vertex normals")
    if face_colours:
        has.add("face colours")
    return (OffFile(lines, [k for k, _ in rows[:nv]], has_normals, np.array(sizes, dtype=np.int64),
                    np.array(corners, dtype=np.int64), has),
            np.array(coords, dtype=np.float64).reshape(-1, 3))


def write_plain(positions, sizes, corners):
    out = ["OFF\n", f"{len(positions)} {len(sizes)} 0\n"]
    out += [floats_text(p) + "\n" for p in positions]
    ends = np.cumsum(sizes)
    text = np.asarray(corners).astype(str)
    out += [f"{s} " + " ".join(text[e - s:e]) + "\n" for s, e in zip(sizes, ends)]
    return "".join(out)
