#!/usr/bin/env python3
"""make_scene.py - writes normalmap.png, the tangent-space normal map of the `normalmap` test
scene (crates/cli/tests/it/mitsuba_scenes.rs), and grey.png, a one-channel image the loader must
refuse as a normal map (crates/io/tests/it/mitsuba_normalmap.rs).

normalmap.png: 64 x 64, 8-bit RGB, 4 x 4 cells over the texture's [0, 1]^2; cell (i, j) holds a
normal tilted 25 degrees from the shading normal toward azimuth 90 * ((i + 2 j) mod 4) degrees
(0: along dp/du), except the cells with i == j, which are flat, so that a wrong tangent frame
(axes swapped or mirrored), a wrong sRGB decoding or a map read upside down moves the lit and
shadowed cells. Encoded as Mitsuba expects: c = (n + 1) / 2, rounded to 8 bits. Pure Python
(zlib PNG writer), deterministic.
"""
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def png(path, width, height, rows, channels):
    colour = {1: 0, 3: 2}[channels]
    raw = b''.join(b'\x00' + bytes(r) for r in rows)

    def chunk(tag, data):
        return struct.pack('>I', len(data)) + tag + data + struct.pack('>I', zlib.crc32(tag + data) & 0xffffffff)

    with open(path, 'wb') as f:
        f.write(b'\x89PNG\r\n\x1a\n')
        f.write(chunk(b'IHDR', struct.pack('>IIBBBBB', width, height, 8, colour, 0, 0, 0)))
        f.write(chunk(b'IDAT', zlib.compress(raw, 9)))
        f.write(chunk(b'IEND', b''))


def main():
    n, cells = 64, 4
    tilt = math.radians(25.0)
    rows = []
    for y in range(n):
        row = []
        for x in range(n):
            i, j = x * cells // n, y * cells // n
            if i == j:
                v = (0.0, 0.0, 1.0)
            else:
                phi = math.radians(90.0 * ((i + 2 * j) % 4))
                v = (math.sin(tilt) * math.cos(phi), math.sin(tilt) * math.sin(phi), math.cos(tilt))
            row.extend(min(255, max(0, round((c + 1.0) / 2.0 * 255.0))) for c in v)
        rows.append(row)
    png(os.path.join(HERE, 'normalmap.png'), n, n, rows, 3)
    png(os.path.join(HERE, 'grey.png'), 4, 4, [[128] * 4 for _ in range(4)], 1)


if __name__ == '__main__':
    main()
