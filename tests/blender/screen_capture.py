"""Window screenshots under Xvfb that are real pictures, or a clear failure.

Blender 4.3.2 with Mesa 25 llvmpipe (Debian 13) draws the window correctly (a framebuffer
read inside a draw handler and an `xwd` of the X screen both show it), but
`bpy.ops.screen.screenshot` reads the GL front buffer, which that driver returns all
black (measured: LIBGL_ALWAYS_SOFTWARE, +extension GLX, MESA_GL_VERSION_OVERRIDE,
LIBGL_DRI3_DISABLE do not change it). So: take Blender's screenshot; if it is all black,
capture the X screen with `xwd -root` (x11-apps) instead; if that is black too, or there is
no xwd, raise, so that no test saves a black picture and passes.
"""

import os
import struct
import subprocess
import zlib


class BlackScreenshot(RuntimeError):
    pass


def _png_is_black(path):
    import bpy
    import numpy as np
    img = bpy.data.images.load(path, check_existing=False)
    try:
        px = np.empty(img.size[0] * img.size[1] * img.channels, np.float32)
        img.pixels.foreach_get(px)
        return img.size[0] == 0 or float(px.reshape(-1, img.channels)[:, :3].max()) == 0.0
    finally:
        bpy.data.images.remove(img)


def _write_png(path, width, height, rows):
    """rows: `height` byte strings of RGB (8 bits each), top row first."""
    raw = b"".join(b"\0" + row for row in rows)

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def _xwd_rows(data):
    """(width, height, RGB rows) of an `xwd` dump: ZPixmap, 24-bit colour in 32-bit pixels."""
    h = struct.unpack(">25I", data[:100])
    header_size, pixmap_format, depth, width, height = h[0], h[2], h[3], h[4], h[5]
    byte_order, bits_per_pixel, bytes_per_line, ncolors = h[7], h[11], h[12], h[19]
    masks = h[14:17]
    if pixmap_format != 2 or bits_per_pixel != 32 or depth != 24 or \
            masks != (0xFF0000, 0xFF00, 0xFF):
        raise BlackScreenshot("xwd: unexpected pixel format %s" % (h,))
    start = header_size + 12 * ncolors
    r, g, b = (2, 1, 0) if byte_order == 0 else (1, 2, 3)   # LSB first: B G R x
    rows = []
    for y in range(height):
        line = data[start + y * bytes_per_line:start + y * bytes_per_line + 4 * width]
        rgb = bytearray(3 * width)
        rgb[0::3], rgb[1::3], rgb[2::3] = line[r::4], line[g::4], line[b::4]
        rows.append(bytes(rgb))
    return width, height, rows


def _capture_x_screen(path):
    try:
        dump = subprocess.run(["xwd", "-root", "-silent"], capture_output=True,
                              check=True, timeout=60).stdout
    except (OSError, subprocess.CalledProcessError) as exc:
        raise BlackScreenshot("Blender's screenshot is all black, and the X screen cannot be "
                              "captured instead (xwd, package x11-apps: %s)" % exc) from None
    width, height, rows = _xwd_rows(dump)
    if not any(any(row) for row in rows):
        raise BlackScreenshot("the screenshot is all black, from Blender and from the X screen")
    _write_png(path, width, height, rows)


def save(path, take):
    """`take()` writes Blender's screenshot to `path`. Returns how the picture was made."""
    take()
    if os.path.isfile(path) and not _png_is_black(path):
        return "bpy.ops.screen.screenshot"
    _capture_x_screen(path)
    return "xwd -root (Blender's own screenshot was all black)"
