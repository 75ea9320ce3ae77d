"""PLY (ASCII, binary little- and big-endian), read and written back with only the vertex
positions changed.

The header, every element (vertex properties such as colours or texture coordinates,
faces of any corner count with their own properties, edges, anything else) and the storage
format are kept byte for byte, except the vertex x, y, z, which get the new positions in
the file's own type (float32 files stay float32), and nx, ny, nz, when present, which are
recomputed from the deformed faces (area-weighted vertex normals).
"""

import numpy as np

from .number_text import float_text
from .polygons import vertex_normals

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
    raise ValueError(f"no '{name}' element")


def _parse_header(data):
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        raise ValueError("not a PLY file (no 'ply' ... 'end_header')")
    newline = data.find(b"\n", end)
    header = data[:newline + 1] if newline >= 0 else data + b"\n"
    fmt, elements = None, []
    for raw in header.decode("latin-1").splitlines()[1:]:
        t = raw.split()
        if not t or t[0] in ("comment", "obj_info", "end_header"):
            continue
        if t[0] == "format" and len(t) >= 2:
            fmt = t[1]
        elif t[0] == "element" and len(t) == 3:
            elements.append(Element(t[1], int(t[2])))
        elif t[0] == "property" and elements and len(t) == 3 and t[1] in TYPES:
            elements[-1].properties.append((t[2], TYPES[t[1]]))
        elif t[0] == "property" and elements and len(t) == 5 and t[1] == "list" \
                and t[2] in TYPES and t[3] in TYPES:
            elements[-1].properties.append((t[4], (TYPES[t[2]], TYPES[t[3]])))
        else:
            raise ValueError(f"header line '{raw.strip()}' is not understood")
    if fmt not in ("ascii", "binary_little_endian", "binary_big_endian"):
        raise ValueError(f"unknown PLY format '{fmt}'")
    return header, fmt, elements


def _binary_element(data, offset, element, order):
    """(structured rows or raw bytes, the face lists (sizes, corners) if any, next offset)."""
    if element.is_scalar():
        dtype = np.dtype([(n, order + t) for n, t in element.properties])
        end = offset + element.count * dtype.itemsize
        if end > len(data):
            raise ValueError(f"the file ends inside element '{element.name}'")
        return np.frombuffer(data, dtype, element.count, offset), None, end
    # Lists: one row at a time (fast path first: every list of the same length).
    fast = _uniform_lists(data, offset, element, order)
    if fast is not None:
        return fast
    sizes, corners = [], []
    pos = offset
    for _ in range(element.count):
        for name, t in element.properties:
            if isinstance(t, str):
                pos += np.dtype(t).itemsize
                continue
            count = int(np.frombuffer(data, order + t[0], 1, pos)[0])
            pos += np.dtype(t[0]).itemsize
            items = np.frombuffer(data, order + t[1], count, pos)
            pos += count * np.dtype(t[1]).itemsize
            if name in FACE_LISTS:
                sizes.append(count)
                corners.append(items.astype(np.int64))
    lists = (np.array(sizes, dtype=np.int64), np.concatenate(corners) if corners else np.zeros(0, np.int64))
    return data[offset:pos], lists, pos


def _uniform_lists(data, offset, element, order):
    first = offset
    fields = []
    for name, t in element.properties:
        if isinstance(t, str):
            fields.append((name, order + t))
            first += np.dtype(t).itemsize
        else:
            if first + np.dtype(t[0]).itemsize > len(data):
                return None
            k = int(np.frombuffer(data, order + t[0], 1, first)[0])
            fields += [(name + "#count", order + t[0]), (name, order + t[1], (k,))]
            first += np.dtype(t[0]).itemsize + k * np.dtype(t[1]).itemsize
    dtype = np.dtype(fields)
    end = offset + element.count * dtype.itemsize
    if end > len(data):
        return None
    rows = np.frombuffer(data, dtype, element.count, offset)
    for name, t in element.properties:
        if not isinstance(t, str) and np.any(rows[name + "#count"] != dtype[name].shape[0]):
            return None
    lists = None
    for name in FACE_LISTS:
        if name in dtype.names:
            k = dtype[name].shape[0]
            lists = (np.full(element.count, k, dtype=np.int64), rows[name].astype(np.int64).reshape(-1))
    return data[offset:end], lists, end


def _ascii_elements(body, elements):
    lines = body.decode("latin-1").splitlines(keepends=True)
    lines = [ln for ln in lines if ln.strip()]
    chunks, vertex_rows, lists, pos = [], None, None, 0
    for e in elements:
        rows = lines[pos:pos + e.count]
        if len(rows) < e.count:
            raise ValueError(f"the file ends inside element '{e.name}'")
        pos += e.count
        chunks.append(rows)
        if e.name == "vertex":
            if not e.is_scalar():
                raise ValueError("vertex elements with list properties are not supported")
            vertex_rows = [r.split() for r in rows]
            if any(len(t) != len(e.properties) for t in vertex_rows):
                raise ValueError("a vertex line has the wrong number of values")
        elif e.name == "face":
            sizes, corners = [], []
            for r in rows:
                t = r.split()
                c = 0
                for name, ptype in e.properties:
                    if isinstance(ptype, str):
                        c += 1
                        continue
                    k = int(t[c])
                    if name in FACE_LISTS:
                        sizes.append(k)
                        corners += [int(x) for x in t[c + 1:c + 1 + k]]
                    c += 1 + k
            lists = (np.array(sizes, dtype=np.int64), np.array(corners, dtype=np.int64))
    return chunks, vertex_rows, lists


def read(data):
    header, fmt, elements = _parse_header(data)
    vertex = elements[_find(elements, "vertex")]
    if not all(n in vertex.names() for n in "xyz"):
        raise ValueError("the vertex element has no x, y, z")
    face = _find(elements, "face")
    if not any(n in FACE_LISTS for n in elements[face].names()):
        raise ValueError("the face element has no vertex_indices list")
    body = data[len(header):]
    if fmt == "ascii":
        try:
            chunks, vertex_rows, lists = _ascii_elements(body, elements)
            positions = np.array([[float(t[vertex.names().index(n)]) for n in "xyz"] for t in vertex_rows])
        except (ValueError, IndexError) as exc:
            raise ValueError(f"cannot parse the ASCII body ({exc})") from None
    else:
        order = "<" if fmt == "binary_little_endian" else ">"
        chunks, pos, lists, vertex_rows = [], 0, None, None
        for e in elements:
            chunk, element_lists, pos = _binary_element(body, pos, e, order)
            if e.name == "vertex":
                if not e.is_scalar():
                    raise ValueError("vertex elements with list properties are not supported")
                vertex_rows = chunk
                chunk = chunk.tobytes()
            elif isinstance(chunk, np.ndarray):
                chunk = chunk.tobytes()
            if e.name == "face":
                lists = element_lists
            chunks.append(chunk)
        chunks.append(body[pos:])  # whatever follows the last element, kept
        positions = np.stack([vertex_rows[n].astype(np.float64) for n in "xyz"], axis=1)
    sizes, corners = lists
    if np.any(sizes < 3):
        raise ValueError("a face has fewer than 3 corners")
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
