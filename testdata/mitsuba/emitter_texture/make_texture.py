"""Writes screen.png, the 8 x 4 sRGB texture of the emitter_texture scene's textured panel
(python3 make_texture.py; the standard library only). Its texels are distinct colours and one
black column, so that a texture flipped, shifted or mirrored on the emitter, or paths started
where it is black, change the image."""

import struct
import zlib

WIDTH, HEIGHT = 8, 4


def texel(i, j):
    if i == 5:
        return (0, 0, 0)  # a black column: no light leaves there
    r = 255 - 28 * i
    g = 60 + 60 * j
    b = 40 + 25 * ((i + 2 * j) % 8)
    return (r, g, b)


def chunk(tag, data):
    return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)


def write_png(path, width, height, texel):
    """Writes an 8-bit RGB PNG of width x height whose texel (i, j) is texel(i, j)."""
    rows = b"".join(b"\x00" + bytes(c for i in range(width) for c in texel(i, j)) for j in range(height))
    png = b"\x89PNG\r\n\x1a\n"
    png += chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(rows, 9))
    png += chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def main():
    write_png("screen.png", WIDTH, HEIGHT, texel)


if __name__ == "__main__":
    main()
