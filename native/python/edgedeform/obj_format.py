"""Wavefront OBJ, read and written back with only the vertex positions changed.

Every line of the file is kept as it was (faces with their vt/vn references, `vt`, groups,
objects, smoothing groups, `mtllib`/`usemtl`, comments), except:
- `v` lines get the new positions (any extra numbers on the line, such as vertex colours,
  are kept);
- `vn` normals are recomputed from the deformed faces: each `vn` becomes the unit sum of the
  area-weighted normals of the faces whose corners use it, so corners that shared a normal
  (smooth) still do, and split normals (hard edges) stay split. A `vn` no face uses is kept.
Negative (relative) indices are resolved. The file is handled as Latin-1 text, which maps
every byte to one character, so unknown bytes are written back unchanged. Every `v`, `vn`
and face corner is checked as it is read; a bad one raises MeshFormatError naming its line.
"""

import numpy as np

from .format_error import at_line, parse_number
from .number_text import floats_text
from .polygons import accumulate_unit, face_normals
from .text_lines import iter_lines, line_ending, split_lines


class ObjFile:
    def __init__(self, lines, v_lines, v_extra, vn_lines, normals, sizes, corners, corner_normals, has):
        self.lines = lines                # the file, one string per line (with its newline)
        self.v_lines = v_lines            # line number of each vertex
        self.v_extra = v_extra            # text after x y z on each v line ("" if none)
        self.vn_lines = vn_lines          # line number of each normal
        self.normals = normals            # (len(vn_lines), 3) as read
        self.sizes, self.corners = sizes, corners
        self.corner_normals = corner_normals  # vn index per corner, -1 where none
        self.has = has                    # which optional OBJ data the file holds

    def rewrite(self, positions):
        """The file's text with new positions. Returns (text, notes)."""
        lines = list(self.lines)
        for i, (line_no, extra) in enumerate(zip(self.v_lines, self.v_extra)):
            lines[line_no] = f"v {floats_text(positions[i])}{extra}{line_ending(lines[line_no])}"
        notes = []
        used = self.corner_normals >= 0
        if len(self.vn_lines) and used.any():
            N = face_normals(positions, self.sizes, self.corners)
            face = np.repeat(np.arange(len(self.sizes)), self.sizes)
            new = accumulate_unit(self.corner_normals[used], N[face[used]], len(self.vn_lines), self.normals)
            for j, line_no in enumerate(self.vn_lines):
                lines[line_no] = f"vn {floats_text(new[j])}{line_ending(lines[line_no])}"
            notes.append("normals (vn) recomputed from the deformed faces")
        return "".join(lines), notes


def _index(token, count, what, line_no):
    k = parse_number(token, int, line_no, f"a {what} index")
    if k < 0:
        k += count  # relative: -1 is the last one defined so far
    else:
        k -= 1
    if not 0 <= k < count:
        raise at_line(line_no, f"{what} index {token} out of range (1..{count} so far)")
    return k


def read(text):
    """Parse OBJ text. Raises MeshFormatError naming the line for malformed input, having
    read the file only up to that line."""
    v_lines, v_extra, coords, vn_lines, normals = [], [], [], [], []
    sizes, corners, corner_normals = [], [], []
    has = set()
    for line_no, (line, _) in enumerate(iter_lines(text)):
        tokens = line.split("#", 1)[0].split()
        if not tokens:
            continue
        key = tokens[0]
        if key == "v":
            if len(tokens) < 4:
                raise at_line(line_no, "a vertex needs 3 coordinates")
            coords.append([parse_number(t, float, line_no, "a coordinate") for t in tokens[1:4]])
            v_lines.append(line_no)
            v_extra.append("".join(" " + t for t in tokens[4:]))
        elif key == "vn":
            if len(tokens) < 4:
                raise at_line(line_no, "a normal (vn) needs 3 numbers")
            normals.append([parse_number(t, float, line_no, "a normal's component") for t in tokens[1:4]])
            vn_lines.append(line_no)
        elif key == "vt":
            has.add("texture coordinates (vt)")
        elif key == "f":
            if len(tokens) < 4:
                raise at_line(line_no, "a face needs at least 3 corners")
            for t in tokens[1:]:
                parts = t.split("/")
                corners.append(_index(parts[0], len(v_lines), "vertex", line_no))
                normal = parts[2] if len(parts) > 2 and parts[2] else None
                corner_normals.append(-1 if normal is None else
                                      _index(normal, len(vn_lines), "normal", line_no))
            sizes.append(len(tokens) - 1)
        elif key in ("g", "o"):
            has.add("groups and objects (g, o)")
        elif key in ("usemtl", "mtllib"):
            has.add("materials (mtllib, usemtl)")
    if vn_lines:
        has.add("normals (vn)")
    lines = split_lines(text)   # kept for the rewrite, once the file is known to be sound
    return ObjFile(lines, v_lines, v_extra, vn_lines, np.array(normals, dtype=np.float64).reshape(-1, 3),
                   np.array(sizes, dtype=np.int64),
                   np.array(corners, dtype=np.int64), np.array(corner_normals, dtype=np.int64),
                   has), np.array(coords, dtype=np.float64).reshape(-1, 3)


def write_plain(positions, sizes, corners):
    """A new OBJ file with only positions and faces."""
    out = [f"v {floats_text(p)}\n" for p in positions]
    ends = np.cumsum(sizes)
    one_based = (np.asarray(corners) + 1).astype(str)
    out += ["f " + " ".join(one_based[e - s:e]) + "\n" for s, e in zip(sizes, ends)]
    return "".join(out)
