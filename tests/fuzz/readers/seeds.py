"""The fuzzers' starting corpus for one format, written as files:

    python3 seeds.py EXT FOLDER

Small valid files that use what each reader handles (quads and n-gons, texture coordinates,
normals, colours, comments, every PLY storage format and list layout) and the hostile files
of tests/python/_hostile_files.py."""

import struct
import sys
from pathlib import Path

from _hostile_files import HOSTILE, VALID

QUAD = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5 1\n"

OBJ = {
    "quads_uvs_normals": "# quads\nmtllib a.mtl\no box\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1 0.2 0.3 0.4\n"
                         "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\nvn 0 1 0\ng side\nusemtl red\ns 1\n"
                         "f 1/1/1 2/2/1 3/3/1 4/1/1\nf 1//2 2//2 5//2\nf -5/-3 -4/-2 -1/-1\n",
    "crlf_relative": "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf -3 -2 -1\r\nv 1 1 0\r\nf 2 -1 3\r\n",
    "pentagon": "v 0 0 0\nv 1 0 0\nv 1.5 1 0\nv 0.5 1.5 0\nv -0.5 1 0\nf 1 2 3 4 5\n",
}

OFF = {
    "off_quads": "OFF\n# a pyramid\n5 5 0\n" + QUAD + "4 0 1 2 3\n3 0 1 4\n3 1 2 4\n3 2 3 4\n3 3 0 4\n",
    "coff": "COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 0 1 2 1 0 0\n",
    "noff_counts_on_header": "NOFF 3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n",
    "stoff": "STOFF\n3 1 3\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n",
    "crlf": "OFF\r\n3 1 0\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n",
}


def ply_header(fmt, vertex_props, face_props, vertices, faces, extra=""):
    return (f"ply\nformat {fmt} 1.0\ncomment seed\nelement vertex {vertices}\n" +
            "".join(f"property {p}\n" for p in vertex_props) + f"element face {faces}\n" +
            "".join(f"property {p}\n" for p in face_props) + extra + "end_header\n").encode()


def ply_seeds():
    out = {}
    out["ascii_normals_colours"] = ply_header(
        "ascii", ["float x", "float y", "float z", "float nx", "float ny", "float nz", "uchar red"],
        ["list uchar int vertex_indices", "uchar flags"], 4, 2,
        "element edge 1\nproperty int vertex1\nproperty int vertex2\n") + \
        b"0 0 0 0 0 1 9\n1 0 0 0 0 1 9\n1 1 0 0 0 1 9\n0 1 0 0 0 1 9\n4 0 1 2 3 7\n3 0 1 2 1\n0 1\n"
    out["ascii_crlf"] = out["ascii_normals_colours"].replace(b"\n", b"\r\n")
    V = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
    for fmt, order in (("binary_little_endian", "<"), ("binary_big_endian", ">")):
        for coord, code in (("float", "f"), ("double", "d")):
            header = ply_header(fmt, [f"{coord} x", f"{coord} y", f"{coord} z"],
                                ["list uchar uint vertex_indices"], 4, 2)
            body = b"".join(struct.pack(order + 3 * code, *v) for v in V)
            uniform = struct.pack(order + "B3I", 3, 0, 1, 2) + struct.pack(order + "B3I", 3, 0, 2, 3)
            mixed = struct.pack(order + "B4I", 4, 0, 1, 2, 3) + struct.pack(order + "B3I", 3, 0, 1, 2)
            out[f"{fmt}_{coord}_triangles"] = header + body + uniform
            out[f"{fmt}_{coord}_mixed"] = header + body + mixed
    return out


def seeds(ext):
    files = {name: data for name, (e, data, *_) in {**HOSTILE, **VALID}.items() if e == ext}
    if ext == ".obj":
        files.update({k: v.encode() for k, v in OBJ.items()})
    elif ext == ".off":
        files.update({k: v.encode() for k, v in OFF.items()})
    else:
        files.update(ply_seeds())
    return files


def main():
    ext, folder = sys.argv[1], Path(sys.argv[2])
    folder.mkdir(parents=True, exist_ok=True)
    for name, data in seeds(ext).items():
        (folder / (name + ext)).write_bytes(data)


if __name__ == "__main__":
    main()
