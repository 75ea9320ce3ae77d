"""Minimal PNG writer and reader (NumPy + zlib), so sheets can be composed and checked
without Blender or PIL. The writer uses filter 0 on every row; the reader undoes filters
0-2 (None, Sub, Up), enough for our own files and for most others' first rows."""
import struct
import zlib

import numpy as np


def _chunk(tag, data):
    return (struct.pack(">I", len(data)) + tag + data +
            struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF))


def write_png(path, rgb):
    """rgb: (h,w,3) uint8, or float in [0,1] (clipped and rounded)."""
    a = np.asarray(rgb)
    if a.dtype != np.uint8:
        a = np.clip(np.round(a * 255.0), 0, 255).astype(np.uint8)
    h, w, _ = a.shape
    raw = np.concatenate([np.zeros((h, 1), np.uint8), a.reshape(h, w * 3)], axis=1)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(_chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)))
        f.write(_chunk(b"IDAT", zlib.compress(raw.tobytes(), 6)))
        f.write(_chunk(b"IEND", b""))


def read_png(path):
    """(h,w,c) uint8 of an 8-bit RGB/RGBA/grey PNG."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("%s: not a PNG" % path)
    pos, idat, hdr = 8, [], None
    while pos < len(data):
        n, = struct.unpack(">I", data[pos:pos + 4])
        tag, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        if tag == b"IHDR":
            hdr = struct.unpack(">IIBBBBB", body)
        elif tag == b"IDAT":
            idat.append(body)
        pos += 12 + n
    w, h, depth, ctype, _, _, interlace = hdr
    if depth != 8 or interlace:
        raise ValueError("%s: only 8-bit, non-interlaced PNGs" % path)
    c = {0: 1, 2: 3, 4: 2, 6: 4}[ctype]
    raw = np.frombuffer(zlib.decompress(b"".join(idat)), np.uint8).reshape(h, 1 + w * c)
    out = np.zeros((h, w * c), np.uint8)
    for y in range(h):      # rows depend on the row above: one short loop over rows
        ftype, row = raw[y, 0], raw[y, 1:].astype(np.int32)
        prev = out[y - 1].astype(np.int32) if y else np.zeros(w * c, np.int32)
        if ftype == 0:
            out[y] = row
        elif ftype == 2:
            out[y] = (row + prev) & 0xFF
        elif ftype == 1:
            r = row.reshape(w, c)
            out[y] = (np.cumsum(r, axis=0) & 0xFF).ravel()
        else:
            raise ValueError("%s: PNG filter %d not supported" % (path, ftype))
    return out.reshape(h, w, c)
