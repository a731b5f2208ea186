#!/usr/bin/env python3
"""make_textures2.py - the image and PLY meshes of testdata/mitsuba/textures2 (crates/cli/tests/it/mitsuba_scenes.rs).

Writes, deterministically and with the standard library only (run from anywhere):
  * rough.png: 8 x 1 8-bit grey, read `raw`: the sphere's roughness (alpha = texel / 255, from
    0.1 to 0.55 along u, bilinear, repeat) - a bitmap's eval_1 is its luminance;
  * wall.ply: a 9 x 5 vertex grid (the back wall, ASCII) with a float per-vertex colour
    `color_0 color_1 color_2` (Mitsuba's `vertex_color`), blended across each triangle;
  * gem.ply: an octahedron (binary little-endian) with per-face float `red green blue`
    (Mitsuba's `face_color`) and `rough_0` (`face_rough`): a rough conductor whose
    specular_reflectance and alpha are both mesh attributes, constant per triangle.
Then render the reference from the repository root:
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
    /work/venv-mitsuba/bin/python tools/mitsuba/render_reference.py textures2 --passes 16 \
        --spp 1024 --competitor-spp 256 --threads 2
"""
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def grey_png(path, values):
    """Writes a one-row 8-bit greyscale PNG of the byte values."""
    def chunk(tag, data):
        c = struct.pack('>I', len(data)) + tag + data
        return c + struct.pack('>I', zlib.crc32(tag + data) & 0xffffffff)
    raw = b'\0' + bytes(values)
    data = (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', len(values), 1, 8, 0, 0, 0, 0))
            + chunk(b'IDAT', zlib.compress(raw, 9)) + chunk(b'IEND', b''))
    with open(path, 'wb') as f:
        f.write(data)


def hue(t):
    """A soft colour of hue t in [0, 1) (channels in [0.1, 0.8])."""
    return [0.1 + 0.7 * (0.5 + 0.5 * math.cos(2 * math.pi * (t - k / 3))) for k in range(3)]


def wall(path):
    nx, ny = 9, 5
    verts, faces = [], []
    for j in range(ny):
        for i in range(nx):
            u, v = i / (nx - 1), j / (ny - 1)
            c = [x * (0.6 + 0.4 * v) for x in hue(u)]
            verts.append((4 * u - 2, 2 * v, 0.0, *c))
    for j in range(ny - 1):
        for i in range(nx - 1):
            a = j * nx + i
            faces += [(a, a + 1, a + nx + 1), (a, a + nx + 1, a + nx)]
    with open(path, 'w') as f:
        f.write('ply\nformat ascii 1.0\ncomment make_textures2.py: the back wall, vertex colours\n')
        f.write(f'element vertex {len(verts)}\n')
        for p in ['x', 'y', 'z', 'color_0', 'color_1', 'color_2']:
            f.write(f'property float {p}\n')
        f.write(f'element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n')
        for v in verts:
            f.write(' '.join(f'{x:.6f}' for x in v) + '\n')
        for t in faces:
            f.write('3 %d %d %d\n' % t)


def gem(path):
    verts = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    faces = []
    for sx in (0, 1):
        for sy in (2, 3):
            for sz in (4, 5):
                t = (sx, sy, sz)
                # Counter-clockwise seen from outside.
                n = [verts[sx][0], verts[sy][1], verts[sz][2]]
                a, b, c = (verts[k] for k in t)
                cross = [(b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]),
                         (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]),
                         (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])]
                if sum(x * y for x, y in zip(cross, n)) < 0:
                    t = (sx, sz, sy)
                faces.append(t)
    with open(path, 'wb') as f:
        f.write(b'ply\nformat binary_little_endian 1.0\ncomment make_textures2.py: face attributes\n')
        f.write(b'element vertex 6\nproperty float x\nproperty float y\nproperty float z\n')
        f.write(b'element face 8\nproperty list uchar int vertex_indices\nproperty float red\n'
                b'property float green\nproperty float blue\nproperty float rough_0\nend_header\n')
        for v in verts:
            f.write(struct.pack('<3f', *v))
        for k, t in enumerate(faces):
            colour = hue(k / 8)
            rough = 0.12 + 0.42 * (k % 4) / 3
            f.write(struct.pack('<B3i4f', 3, *t, *colour, rough))


def main():
    grey_png(os.path.join(HERE, 'rough.png'), [30, 140, 45, 100, 60, 35, 120, 25])
    wall(os.path.join(HERE, 'wall.ply'))
    gem(os.path.join(HERE, 'gem.ply'))


if __name__ == '__main__':
    main()
