#!/usr/bin/env python3
"""make_textures.py - the texture images and the OBJ of testdata/mitsuba/textures (crates/cli/tests/it/mitsuba_scenes.rs).

Writes, deterministically and with the standard library only (run from anywhere):
  * stripes.png: 16 x 8 8-bit sRGB RGB, a colour per column (hue ramp) darkened on the lower
    half: the sphere's bilinear, repeat-wrapped texture (sRGB decoded to linear as Mitsuba does);
  * tiles.png: 4 x 4 8-bit sRGB RGB, four saturated colours and greys: the cube's and the OBJ
    quad's texture, sampled nearest with mirror and clamp wrapping and a to_uv transform;
  * quad.obj: a unit quad with `vt` coordinates (Mitsuba flips v by default: flip_tex_coords).
Then render the reference from the repository root:
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
    /work/venv-mitsuba/bin/python tools/mitsuba/render_reference.py textures --passes 16 \
        --spp 4096 --competitor-spp 128 --threads 2
"""
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def png(path, width, height, rows):
    """Writes an 8-bit RGB PNG; rows[y][x] = (r, g, b) bytes, row 0 the top."""
    def chunk(tag, data):
        c = struct.pack('>I', len(data)) + tag + data
        return c + struct.pack('>I', zlib.crc32(tag + data) & 0xffffffff)
    raw = b''.join(b'\0' + bytes(v for px in row for v in px) for row in rows)
    data = (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', width, height, 8, 2, 0, 0, 0))
            + chunk(b'IDAT', zlib.compress(raw, 9)) + chunk(b'IEND', b''))
    with open(path, 'wb') as f:
        f.write(data)


def hue(t):
    """A saturated colour of hue t in [0, 1) as bytes."""
    k = [(5 + 6 * t) % 6, (3 + 6 * t) % 6, (1 + 6 * t) % 6]
    return tuple(int(round(255 * (1 - max(0, min(x, 4 - x, 1))))) for x in k)


def main():
    stripes = [[tuple(v if y < 4 else v // 3 for v in hue(x / 16)) for x in range(16)] for y in range(8)]
    png(os.path.join(HERE, 'stripes.png'), 16, 8, stripes)
    palette = [(230, 40, 30), (40, 200, 60), (30, 60, 230), (240, 220, 40), (200, 200, 200), (60, 60, 60)]
    tiles = [[palette[(x + 2 * y) % len(palette)] for x in range(4)] for y in range(4)]
    png(os.path.join(HERE, 'tiles.png'), 4, 4, tiles)
    with open(os.path.join(HERE, 'quad.obj'), 'w') as f:
        f.write('# a unit quad in the xy plane with texture coordinates (make_textures.py)\n')
        f.write('v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n')
        f.write('vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n')
        f.write('f 1/1 2/2 3/3 4/4\n')


if __name__ == '__main__':
    main()
