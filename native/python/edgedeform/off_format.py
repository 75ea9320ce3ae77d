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
from .text_lines import iter_lines, line_ending, lines_at_most


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
    """Parse OFF text. The counts are checked against the lines that are there before any
    line after them is parsed, and the lines are parsed one at a time, so a bad file is
    refused without splitting the rest of it; MeshFormatError names the line."""
    lines, rows = [], []   # every line read so far; (line number, tokens) of its data lines
    offset = 0
    for line, offset in iter_lines(text):
        lines.append(line)
        t = _data(line).split()
        if t:
            rows.append((len(lines) - 1, t))
        if len(rows) == 2 or (len(rows) == 1 and len(t) > 1):
            break
    keyword, has_normals, counts_line, head = _header(rows)
    nv = require_count(head[0], counts_line, "vertices")
    nf = require_count(head[1], counts_line, "faces")
    if nv + nf > lines_at_most(text, offset):
        raise at_line(counts_line, f"{nv} vertices and {nf} faces declared, the file has at most "
                                   f"{lines_at_most(text, offset)} lines after this one")
    per_vertex = 6 if has_normals else 3
    coords, v_lines, sizes, corners, face_colours = [], [], [], [], False
    lines_iter = iter_lines(text, offset)
    while len(v_lines) + len(sizes) < nv + nf:
        try:
            line, offset = next(lines_iter)
        except StopIteration:
            raise at_line(counts_line, f"{nv} vertices and {nf} faces declared, the file has "
                                       f"{len(v_lines) + len(sizes)} lines of data after this one") from None
        k = len(lines)
        lines.append(line)
        t = _data(line).split()
        if not t:
            continue
        if len(v_lines) < nv:
            if len(t) < per_vertex:
                raise at_line(k, f"a vertex line needs {per_vertex} numbers for '{keyword}', found {len(t)}")
            coords.append([parse_number(x, float, k, "a coordinate") for x in t[:per_vertex]][:3])
            v_lines.append(k)
            continue
        size = parse_number(t[0], int, k, "a face's corner count")
        if size < 3:
            raise at_line(k, f"a face needs at least 3 corners, this one declares {size}")
        if len(t) - 1 < size:
            raise at_line(k, f"the face declares {size} corners, the line has {len(t) - 1} numbers")
        corners += [parse_index(x, k) for x in t[1:1 + size]]
        sizes.append(size)
        face_colours = face_colours or len(t) > 1 + size
    if offset < len(text):
        lines.append(text[offset:])   # whatever follows the faces, kept as it is
    has = set()
    if "C" in keyword.upper()[:-3]:
        has.add("vertex colours")
    if "ST" in keyword.upper()[:-3]:
        has.add("texture coordinates")
    if has_normals:
        has.add("vertex normals")
    if face_colours:
        has.add("face colours")
    return (OffFile(lines, v_lines, has_normals, np.array(sizes, dtype=np.int64),
                    np.array(corners, dtype=np.int64), has),
            np.array(coords, dtype=np.float64).reshape(-1, 3))


def _header(rows):
    """(keyword, has normals, the counts' line number, the counts' tokens) from the first one
    or two data lines."""
    if not rows or not rows[0][1][0].upper().endswith("OFF"):
        raise at_line(rows[0][0] if rows else 0, "missing OFF header")
    line_no, tokens = rows[0]
    keyword = tokens[0]
    prefix = keyword[:-3]  # [ST][C][N][4][n]OFF
    if "BINARY" in (t.upper() for t in tokens[1:]):
        raise at_line(line_no, "binary OFF is not supported (write it as text OFF or PLY)")
    if "4" in prefix or prefix.endswith("n"):
        raise at_line(line_no, f"'{keyword}' (4D or nD vertices) is not supported")
    if set(prefix.upper()) - set("STCN"):
        raise at_line(line_no, f"unknown OFF header '{keyword}'")
    head = tokens[1:]
    if not head:
        if len(rows) < 2:
            raise at_line(line_no, "missing vertex and face counts")
        line_no, head = rows[1]
    if len(head) < 2:
        raise at_line(line_no, f"expected the vertex and face counts, found {' '.join(head)!r}")
    return keyword, "N" in prefix.upper(), line_no, head


def write_plain(positions, sizes, corners):
    out = ["OFF\n", f"{len(positions)} {len(sizes)} 0\n"]
    out += [floats_text(p) + "\n" for p in positions]
    ends = np.cumsum(sizes)
    text = np.asarray(corners).astype(str)
    out += [f"{s} " + " ".join(text[e - s:e]) + "\n" for s, e in zip(sizes, ends)]
    return "".join(out)
