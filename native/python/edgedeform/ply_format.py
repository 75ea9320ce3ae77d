"""PLY (ASCII, binary little- and big-endian), read and written back with only the vertex
positions changed.

The header, every element (vertex properties such as colours or texture coordinates,
faces of any corner count with their own properties, edges, anything else) and the storage
format are kept byte for byte, except the vertex x, y, z, which get the new positions in
the file's own type (float32 files stay float32), and nx, ny, nz, when present, which are
recomputed from the deformed faces (area-weighted vertex normals).

Reading trusts no declared count: the header is read line by line, element row counts and
list lengths must be non-negative and fit the bytes (binary) or numbers (ASCII) that are
there before anything of their size is made, and a bad file raises MeshFormatError naming
the line (ASCII) or the row.
"""

import numpy as np

from .format_error import MeshFormatError, at_line, parse_index, parse_number, require_count
from .number_text import float_text
from .polygons import vertex_normals
from .text_lines import split_lines

TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
         "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
         "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}
FACE_LISTS = ("vertex_indices", "vertex_index")
NORMALS = ("nx", "ny", "nz")


class Element:
    def __init__(self, name, count):
        self.name, self.count = name, count
        self.properties = []  # (name, type) or (name, (count type, item type))

    def is_scalar(self):
        return all(isinstance(t, str) for _, t in self.properties)

    def names(self):
        return [n for n, _ in self.properties]


class PlyFile:
    def __init__(self, header, fmt, elements, chunks, vertex_rows, sizes, corners):
        self.header = header          # bytes up to and including end_header's newline
        self.fmt = fmt                # "ascii", "binary_little_endian", "binary_big_endian"
        self.elements = elements
        self.chunks = chunks          # per element: its body (bytes; ASCII: list of lines)
        self.vertex_rows = vertex_rows  # binary: structured array; ASCII: token lists
        self.sizes, self.corners = sizes, corners
        names = elements[_find(elements, "vertex")].names()
        self.has = {"vertex properties " + ", ".join(n for n in names if n not in ("x", "y", "z"))} \
            if len(names) > 3 else set()
        if any(e.name not in ("vertex", "face") for e in elements):
            self.has.add("elements " + ", ".join(e.name for e in elements if e.name not in ("vertex", "face")))

    def rewrite(self, positions):
        vi = _find(self.elements, "vertex")
        vertex = self.elements[vi]
        names = vertex.names()
        notes = []
        values = {"x": positions[:, 0], "y": positions[:, 1], "z": positions[:, 2]}
        if all(n in names for n in NORMALS):
            old = np.stack([_column(self, vertex, n) for n in NORMALS], axis=1)
            N = vertex_normals(positions, self.sizes, self.corners, old)
            values.update({n: N[:, k] for k, n in enumerate(NORMALS)})
            notes.append("vertex normals (nx, ny, nz) recomputed from the deformed faces")
        chunks = list(self.chunks)
        if self.fmt == "ascii":
            col = {n: names.index(n) for n in values}
            lines = []
            for r, tokens in enumerate(self.vertex_rows):
                tokens = list(tokens)
                for n, c in col.items():
                    tokens[c] = _ascii_value(values[n][r], dict(vertex.properties)[n])
                lines.append(" ".join(tokens) + "\n")
            chunks[vi] = lines
        else:
            rows = self.vertex_rows.copy()
            for n, v in values.items():
                rows[n] = v  # cast to the file's type
            chunks[vi] = rows.tobytes()
            if any(dict(vertex.properties)[n] == "f4" for n in "xyz"):
                notes.append("positions stored as float32, the input's type")
        body = b"".join(c if isinstance(c, bytes) else "".join(c).encode("latin-1") for c in chunks)
        return self.header + body, notes


def _ascii_value(value, ptype):
    return float_text(value) if ptype in ("f4", "f8") else str(int(round(value)))


def _column(ply, element, name):
    if ply.fmt == "ascii":
        c = element.names().index(name)
        return np.array([float(t[c]) for t in ply.vertex_rows])
    return ply.vertex_rows[name].astype(np.float64)


def _find(elements, name):
    for k, e in enumerate(elements):
        if e.name == name:
            return k
    raise MeshFormatError(f"the header declares no '{name}' element")


HEADER_LIMIT = 256 << 10   # bytes: real headers are a few hundred; a longer one is not a header


def _header_lines(data, ends):
    """Yields (0-based line number, text) of each header line between 'ply' and 'end_header',
    one at a time, and sets ends[0] to the header's length in bytes through end_header's
    newline. Line by line: 'end_header' inside a comment does not end it."""
    pos, line_no = 0, 0
    while True:
        end = data.find(b"\n", pos, HEADER_LIMIT)
        if end < 0 and len(data) > HEADER_LIMIT:
            raise MeshFormatError(f"no 'end_header' line in the first {HEADER_LIMIT} bytes")
        stop = len(data) if end < 0 else end + 1
        text = data[pos:stop].decode("latin-1").rstrip("\r\n")
        if line_no == 0:
            if text.strip() != "ply":
                raise at_line(0, "not a PLY file (the first line is not 'ply')")
        elif text.split() == ["end_header"]:
            ends[0] = stop
            return
        else:
            yield line_no, text
        if end < 0:
            raise MeshFormatError("the header has no 'end_header' line")
        pos, line_no = stop, line_no + 1


def _parse_header(data):
    """(header bytes, format, elements, the body's first line number)."""
    fmt, elements, ends, line_no = None, [], [None], 0
    for line_no, raw in _header_lines(data, ends):
        t = raw.split()
        if not t or t[0] in ("comment", "obj_info"):
            continue
        if t[0] == "format" and fmt is not None:
            raise at_line(line_no, "a second 'format' line")
        if t[0] == "element" and len(t) == 3 and t[1] in (e.name for e in elements):
            raise at_line(line_no, f"element '{t[1]}' declared twice")
        if t[0] == "format" and len(t) == 3:
            fmt = t[1]
        elif t[0] == "element" and len(t) == 3:
            elements.append(Element(t[1], require_count(t[2], line_no, f"'{t[1]}' rows")))
        elif t[0] == "property" and not elements:
            raise at_line(line_no, "a property before any element")
        elif t[0] == "property" and t[-1] in elements[-1].names():
            raise at_line(line_no, f"property '{t[-1]}' declared twice in element '{elements[-1].name}'")
        elif t[0] == "property" and len(t) == 3 and t[1] in TYPES:
            elements[-1].properties.append((t[2], TYPES[t[1]]))
        elif t[0] == "property" and len(t) == 5 and t[1] == "list" and t[2] in TYPES and t[3] in TYPES:
            if TYPES[t[2]][0] == "f" or (t[4] in FACE_LISTS and TYPES[t[3]][0] == "f"):
                raise at_line(line_no, f"list '{t[4]}': its length and indices must be integer types")
            elements[-1].properties.append((t[4], (TYPES[t[2]], TYPES[t[3]])))
        else:
            raise at_line(line_no, f"header line '{raw.strip()}' is not understood")
    if fmt not in ("ascii", "binary_little_endian", "binary_big_endian"):
        raise MeshFormatError(f"unknown PLY format '{fmt}'" if fmt else "the header has no 'format' line")
    for e in elements:
        if not e.properties:  # rows of no bytes: a count that nothing in the file can check
            raise MeshFormatError(f"element '{e.name}' declares no properties")
    return data[:ends[0]], fmt, elements, line_no + 2


def _too_short(element, rows, need, left):
    return MeshFormatError(f"element '{element.name}' declares {rows} rows, which need at least {need} bytes; "
                           f"the file has {left} bytes left")


def _list_length(data, pos, element, name, row, count_type, item_type):
    """The length of one binary list, checked against the bytes that are left."""
    k = int(np.frombuffer(data, count_type, 1, pos)[0])
    if k < 0:
        raise MeshFormatError(f"{element.name} {row}: list '{name}' has a negative length ({k})")
    left = len(data) - pos - count_type.itemsize
    if k * item_type.itemsize > left:
        raise MeshFormatError(f"{element.name} {row}: list '{name}' declares {k} entries "
                              f"({k * item_type.itemsize} bytes); the file has {left} bytes left")
    return k


def _binary_element(data, offset, element, order):
    """(structured rows or raw bytes, the face lists (sizes, corners) if any, next offset)."""
    left = len(data) - offset
    if element.is_scalar():
        dtype = np.dtype([(n, order + t) for n, t in element.properties])
        if element.count * dtype.itemsize > left:
            raise _too_short(element, element.count, element.count * dtype.itemsize, left)
        return np.frombuffer(data, dtype, element.count, offset), None, offset + element.count * dtype.itemsize
    smallest_row = sum(np.dtype(t if isinstance(t, str) else t[0]).itemsize for _, t in element.properties)
    if element.count * smallest_row > left:
        raise _too_short(element, element.count, element.count * smallest_row, left)
    # Lists: one row at a time (fast path first: every list of the same length).
    fast = _uniform_lists(data, offset, element, order)
    if fast is not None:
        return fast
    sizes, corners = [], []
    pos = offset
    for row in range(element.count):
        for name, t in element.properties:
            if isinstance(t, str):
                pos += np.dtype(t).itemsize
                if pos > len(data):
                    raise _too_short(element, element.count, pos - offset, left)
                continue
            count_type, item_type = np.dtype(order + t[0]), np.dtype(order + t[1])
            if pos + count_type.itemsize > len(data):
                raise _too_short(element, element.count, pos + count_type.itemsize - offset, left)
            count = _list_length(data, pos, element, name, row, count_type, item_type)
            pos += count_type.itemsize
            items = np.frombuffer(data, item_type, count, pos)
            pos += count * item_type.itemsize
            if name in FACE_LISTS:
                sizes.append(count)
                corners.append(items.astype(np.int64))
    lists = (np.array(sizes, dtype=np.int64), np.concatenate(corners) if corners else np.zeros(0, np.int64))
    return data[offset:pos], lists, pos


def _uniform_lists(data, offset, element, order):
    """The element's rows and face lists when every list has the first row's length, else None."""
    first = offset
    fields = []
    for name, t in element.properties:
        if isinstance(t, str):
            fields.append((name, order + t))
            first += np.dtype(t).itemsize
        else:
            count_type, item_type = np.dtype(order + t[0]), np.dtype(order + t[1])
            if first + count_type.itemsize > len(data):
                return None
            k = _list_length(data, first, element, name, 0, count_type, item_type)
            # "NAME count": PLY names have no spaces, so no property can take this field's name
            fields += [(name + " count", count_type), (name, item_type, (k,))]
            first += count_type.itemsize + k * item_type.itemsize
    dtype = np.dtype(fields)
    end = offset + element.count * dtype.itemsize
    if end > len(data):
        return None
    rows = np.frombuffer(data, dtype, element.count, offset)
    for name, t in element.properties:
        if not isinstance(t, str) and np.any(rows[name + " count"] != dtype[name].shape[0]):
            return None
    lists = None
    for name in FACE_LISTS:
        if name in dtype.names:
            k = dtype[name].shape[0]
            lists = (np.full(element.count, k, dtype=np.int64), rows[name].astype(np.int64).reshape(-1))
    return data[offset:end], lists, end


def _ascii_face(tokens, element, line_no):
    """(corner count, corners) of one ASCII face line, every list length checked against the
    numbers on the line."""
    c, size, corners = 0, None, None
    for name, ptype in element.properties:
        if c >= len(tokens):
            raise at_line(line_no, f"the line ends before property '{name}'")
        if isinstance(ptype, str):
            c += 1
            continue
        k = parse_number(tokens[c], int, line_no, f"the length of list '{name}'")
        if k < 0:
            raise at_line(line_no, f"list '{name}' has a negative length ({k})")
        if k > len(tokens) - c - 1:
            raise at_line(line_no, f"list '{name}' declares {k} entries, the line has {len(tokens) - c - 1} "
                                   f"numbers after it")
        if name in FACE_LISTS:
            size = k
            corners = [parse_index(x, line_no) for x in tokens[c + 1:c + 1 + k]]
        c += 1 + k
    if c != len(tokens):
        raise at_line(line_no, f"{len(tokens)} numbers, the face's properties take {c}")
    if size < 3:
        raise at_line(line_no, f"a face needs at least 3 corners, this one has {size}")
    return size, corners


def _ascii_elements(body, elements, first_line):
    """Each element's lines, the vertex rows (token lists) and the face lists. `first_line`:
    the body's first line in the file (0-based), for the messages."""
    left = body.count(b"\n") + body.count(b"\r") + 1   # at most this many lines: checked before splitting
    for e in elements:
        if e.count > left:
            raise MeshFormatError(f"element '{e.name}' declares {e.count} rows, the file has at most {left} lines "
                                  f"left for it")
        left -= e.count
    lines = split_lines(body.decode("latin-1"))
    rows_at = [k for k, ln in enumerate(lines) if ln.strip()]
    chunks, vertex_rows, lists, pos = [], None, None, 0
    for e in elements:
        if pos + e.count > len(rows_at):
            raise MeshFormatError(f"element '{e.name}' declares {e.count} rows, the file has "
                                  f"{len(rows_at) - pos} lines left for it")
        at = rows_at[pos:pos + e.count]
        pos += e.count
        chunks.append([lines[k] for k in at])
        if e.name == "vertex":
            if not e.is_scalar():
                raise MeshFormatError("vertex elements with list properties are not supported")
            vertex_rows = [lines[k].split() for k in at]
            numeric = [e.names().index(n) for n in ("x", "y", "z") + NORMALS if n in e.names()]
            for k, t in zip(at, vertex_rows):
                if len(t) != len(e.properties):
                    raise at_line(first_line + k, f"a vertex line has {len(t)} values, the header declares "
                                                  f"{len(e.properties)}")
                for c in numeric:
                    parse_number(t[c], float, first_line + k, f"a number ({e.properties[c][0]})")
        elif e.name == "face":
            faces = [_ascii_face(lines[k].split(), e, first_line + k) for k in at]
            lists = (np.array([f[0] for f in faces], dtype=np.int64),
                     np.array([c for f in faces for c in f[1]], dtype=np.int64))
    return chunks, vertex_rows, lists


def read(data):
    """Parse PLY bytes. Every declared count (rows, list lengths) is checked against the
    bytes that are there before anything of its size is made; MeshFormatError otherwise."""
    header, fmt, elements, body_line = _parse_header(data)
    vertex = elements[_find(elements, "vertex")]
    if not all(n in vertex.names() for n in "xyz"):
        raise MeshFormatError("the vertex element has no x, y, z")
    if not vertex.is_scalar():
        raise MeshFormatError("vertex elements with list properties are not supported")
    face = _find(elements, "face")
    if not any(n in FACE_LISTS and not isinstance(t, str) for n, t in elements[face].properties):
        raise MeshFormatError("the face element has no vertex_indices list")
    body = data[len(header):]
    if fmt == "ascii":
        chunks, vertex_rows, lists = _ascii_elements(body, elements, body_line)
        columns = [vertex.names().index(n) for n in "xyz"]
        positions = np.array([[float(t[c]) for c in columns] for t in vertex_rows], dtype=np.float64)
    else:
        order = "<" if fmt == "binary_little_endian" else ">"
        chunks, pos, lists, vertex_rows = [], 0, None, None
        for e in elements:
            chunk, element_lists, pos = _binary_element(body, pos, e, order)
            if e.name == "vertex":
                vertex_rows = chunk
                chunk = chunk.tobytes()
            elif isinstance(chunk, np.ndarray):
                chunk = chunk.tobytes()
            if e.name == "face":
                lists = element_lists
            chunks.append(chunk)
        chunks.append(body[pos:])  # whatever follows the last element, kept
        positions = np.stack([vertex_rows[n].astype(np.float64) for n in "xyz"], axis=1)
        sizes = lists[0]
        if np.any(sizes < 3):
            row = int(np.argmax(sizes < 3))
            raise MeshFormatError(f"face {row} has {sizes[row]} corners, a face needs at least 3")
    sizes, corners = lists
    return PlyFile(header, fmt, elements, chunks, vertex_rows, sizes, corners), positions.reshape(-1, 3)


def write_plain(positions, sizes, corners):
    """Binary little-endian PLY with double positions and int32 face lists."""
    count = "uchar" if len(sizes) == 0 or int(np.max(sizes)) <= 255 else "int"
    header = ("ply\nformat binary_little_endian 1.0\ncomment written by edgedeform\n"
              f"element vertex {len(positions)}\nproperty double x\nproperty double y\nproperty double z\n"
              f"element face {len(sizes)}\nproperty list {count} int vertex_indices\nend_header\n")
    V = np.ascontiguousarray(positions, dtype="<f8").tobytes()
    cdt = "<u1" if count == "uchar" else "<i4"
    corners = np.asarray(corners, dtype="<i4")
    sizes = np.asarray(sizes, dtype=np.int64)
    if len(sizes) and np.all(sizes == sizes[0]):  # one record type: no per-face loop
        rows = np.zeros(len(sizes), dtype=[("n", cdt), ("i", "<i4", (int(sizes[0]),))])
        rows["n"] = sizes[0]
        rows["i"] = corners.reshape(len(sizes), -1)
        return header.encode("ascii") + V + rows.tobytes()
    ends = np.cumsum(sizes)
    F = b"".join(np.array([s], dtype=cdt).tobytes() + corners[e - s:e].tobytes() for s, e in zip(sizes, ends))
    return header.encode("ascii") + V + F
