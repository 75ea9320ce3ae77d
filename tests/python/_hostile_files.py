"""Hostile mesh files: each a file a studio may hold (a lying count, a cut-off body, a BOM,
a malformed line) with the words its refusal must contain. Shared by the reader tests, the
memory-bound test and the fuzzers' seed corpus (tests/fuzz_readers)."""

import struct

TRIANGLE = "0 0 0\n1 0 0\n0 1 0\n"


def ply_ascii(vertices=3, faces=1, face_property="property list uchar int vertex_indices",
              body=TRIANGLE + "3 0 1 2\n", comment=""):
    return (f"ply\nformat ascii 1.0\n{comment}element vertex {vertices}\nproperty float x\n"
            f"property float y\nproperty float z\nelement face {faces}\n{face_property}\n"
            f"end_header\n{body}").encode()


def ply_binary(vertices=3, faces=1, count_type="uchar", face_bytes=None, comment=""):
    header = (f"ply\nformat binary_little_endian 1.0\n{comment}element vertex {vertices}\n"
              f"property float x\nproperty float y\nproperty float z\nelement face {faces}\n"
              f"property list {count_type} int vertex_indices\nend_header\n").encode()
    V = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    code = {"uchar": "B", "uint": "I", "int": "i"}[count_type]
    if face_bytes is None:
        face_bytes = struct.pack("<" + code + "3i", 3, 0, 1, 2)
    return header + V + face_bytes


def off(counts="3 1 0", body=TRIANGLE + "3 0 1 2\n"):
    return f"OFF\n{counts}\n{body}".encode()


# name: (extension, file bytes, words the MeshFormatError must contain)
HOSTILE = {
    # declared counts that the bytes do not hold
    "ply_list_count_1e8": (".ply", ply_ascii(body=TRIANGLE + "100000000 0 1 2\n"),
                           "PLY line 13: list 'vertex_indices' declares 100000000 entries, the line has 3"),
    "ply_list_count_2e9": (".ply", ply_ascii(body=TRIANGLE + "2000000000 0 1 2\n"),
                           "declares 2000000000 entries"),
    "ply_negative_vertex_count": (".ply", ply_ascii(vertices=-2),
                                  "PLY line 3: negative count of 'vertex' rows (-2)"),
    "ply_face_rows_1e12": (".ply", ply_ascii(faces=10**12),
                           "element 'face' declares 1000000000000 rows, the file has at most 2 lines left"),
    "ply_binary_vertex_rows_2e40": (".ply", ply_binary(vertices=2**40),
                                    "element 'vertex' declares 1099511627776 rows, which need at least"),
    "ply_binary_face_rows_over": (".ply", ply_binary(faces=5),
                                  "element 'face' declares 5 rows, which need at least 14 bytes; the file "
                                  "has 13 bytes left"),
    "ply_binary_list_count_4e9": (".ply", ply_binary(count_type="uint",
                                                     face_bytes=struct.pack("<I3i", 2**32 - 1, 0, 1, 2)),
                                  "face 0: list 'vertex_indices' declares 4294967295 entries"),
    "ply_binary_list_negative": (".ply", ply_binary(count_type="int",
                                                    face_bytes=struct.pack("<i3i", -1, 0, 1, 2)),
                                 "face 0: list 'vertex_indices' has a negative length (-1)"),
    "ply_binary_second_face_cut": (".ply", ply_binary(faces=2, face_bytes=struct.pack("<B3iB2i", 3, 0, 1, 2,
                                                                                      4, 0, 1)),
                                   "face 1: list 'vertex_indices' declares 4 entries (16 bytes); the file "
                                   "has 8 bytes left"),
    "off_negative_vertex_count": (".off", off("-2 7 0", TRIANGLE + "3 0 1 2\n3 0 2 1\n"),
                                  "OFF line 2: negative count of vertices (-2)"),
    "off_face_rows_1e12": (".off", off("3 1000000000000 0"),
                           "OFF line 2: 3 vertices and 1000000000000 faces declared, the file has at most 5 lines"),
    "off_face_corners_1e8": (".off", off(body=TRIANGLE + "100000000 0 1 2\n"),
                             "OFF line 6: the face declares 100000000 corners, the line has 3 numbers"),
    # malformed lines, named
    "ply_face_index_missing": (".ply", ply_ascii(body=TRIANGLE + "3 1 3\n"),
                               "PLY line 13: list 'vertex_indices' declares 3 entries, the line has 2"),
    "ply_two_corners": (".ply", ply_ascii(body=TRIANGLE + "2 0 1\n"),
                        "PLY line 13: a face needs at least 3 corners, this one has 2"),
    "ply_binary_two_corners": (".ply", ply_binary(face_bytes=struct.pack("<B2i", 2, 0, 1)),
                               "face 0 has 2 corners, a face needs at least 3"),
    "ply_float_list_length": (".ply", ply_ascii(face_property="property list float int vertex_indices"),
                              "PLY line 8: list 'vertex_indices': its length and indices must be integer types"),
    "ply_vertex_word": (".ply", ply_ascii(body="0 0 zero\n1 0 0\n0 1 0\n3 0 1 2\n"),
                        "PLY line 10: 'zero' is not a number (z)"),
    "ply_no_end_header": (".ply", b"ply\nformat ascii 1.0\nelement vertex 3\n", "no 'end_header' line"),
    "obj_normal_two_numbers": (".obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0\nf 1//1 2//1 3//1\n",
                               "OBJ line 4: a normal (vn) needs 3 numbers"),
    "obj_index_word": (".obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 three\n",
                       "OBJ line 4: 'three' is not a vertex index"),
    "obj_nan_vertex": (".obj", b"v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n",
                       "vertex 1 (0-based, in file order) has a coordinate that is not finite"),
    "off_face_word": (".off", off(body=TRIANGLE + "3 0 1 x\n"), "OFF line 6: 'x' is not a vertex index"),
}

# Large hostile files (about 30 MB each, made when needed): a lie or a bad line early in a
# long file, which a reader must refuse without parsing, or even splitting, the rest.
JUNK_LINES = 2_000_000
LARGE = {
    "large_off_bad_face_then_junk": (".off", lambda: off(body=TRIANGLE + "3 0 1 x\n" + "1 2 3 4 5 6 7 8\n" * JUNK_LINES)),
    "large_obj_bad_index_then_junk": (".obj", lambda: b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n" +
                                      b"x 1 2 3 4 5 6\n" * JUNK_LINES),
    "large_ply_ascii_face_rows_1e8": (".ply", lambda: ply_ascii(faces=10**8, body=TRIANGLE + "3 0 1 2\n" * JUNK_LINES)),
    "large_ply_binary_face_rows_1e8": (".ply", lambda: ply_binary(faces=10**8) + bytes(30_000_000)),
    "large_ply_header_of_blank_lines": (".ply", lambda: b"ply\nformat ascii 1.0\n" + b"\n" * 30_000_000),
}

# Valid files the readers once refused or misread: (extension, bytes, the same mesh without
# the oddity).
BOM = b"\xef\xbb\xbf"
OBJ_TRIANGLE = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
VALID = {
    "obj_with_bom": (".obj", BOM + OBJ_TRIANGLE, OBJ_TRIANGLE),
    "off_with_bom": (".off", BOM + off(), off()),
    "ply_with_bom": (".ply", BOM + ply_ascii(), ply_ascii()),
    "ply_comment_naming_end_header": (".ply", ply_ascii(comment="comment exported; see end_header below\n"),
                                      ply_ascii()),
    "ply_binary_comment_naming_end_header": (".ply", ply_binary(comment="comment end_header\n"), ply_binary()),
}
