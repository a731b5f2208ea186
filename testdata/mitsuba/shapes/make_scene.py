#!/usr/bin/env python3
"""Writes the mesh files of the `shapes` scene (crates/cli/tests/it/mitsuba_scenes.rs), by hand so that each
encoding is exercised exactly as specified:

  meshes/octa.ply          binary big-endian PLY: an octahedron of radius 0.3 with vertex
                           normals (nx ny nz, float) and texture coordinates (u v), uchar/int faces
  meshes/prism.ply         ASCII PLY: a triangular prism without normals (Mitsuba and Opticks
                           generate smooth vertex normals for it), uchar/uint `vertex_index`
  meshes/two.serialized    Mitsuba serialized format version 4 (zlib), two meshes: a tetrahedron
                           (index 0) and a box (index 1, used by the scene via shape_index)

Usage: python3 make_scene.py   (standard library only; scene.xml and parts/ are written by hand)
"""
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def octahedron():
    r = 0.3
    v = [(r, 0, 0), (-r, 0, 0), (0, r, 0), (0, -r, 0), (0, 0, r), (0, 0, -r)]
    f = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
    return v, f


def write_ply_binary_be(path, verts, faces):
    head = ('ply\nformat binary_big_endian 1.0\ncomment octahedron, make_scene.py\n'
            f'element vertex {len(verts)}\nproperty float x\nproperty float y\nproperty float z\n'
            'property float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\n'
            f'element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n')
    out = bytearray(head.encode())
    for x, y, z in verts:
        n = math.sqrt(x * x + y * y + z * z)
        out += struct.pack('>8f', x, y, z, x / n, y / n, z / n, 0.5 + x, 0.5 + y)
    for f in faces:
        out += struct.pack('>B3i', 3, *f)
    open(path, 'wb').write(out)


def write_ply_ascii_prism(path):
    h, r = 0.5, 0.25
    tri = [(r * math.cos(a), r * math.sin(a)) for a in (0, 2 * math.pi / 3, 4 * math.pi / 3)]
    verts = [(x, 0, z) for x, z in tri] + [(x, h, z) for x, z in tri]
    # Outward, counter-clockwise seen from outside; the side quads split in two (Mitsuba 3's
    # PLY reader takes triangles only).
    quads = [(0, 3, 4, 1), (1, 4, 5, 2), (2, 5, 3, 0)]
    faces = [(0, 1, 2), (3, 5, 4)] + [t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))]
    with open(path, 'w') as o:
        o.write(f'ply\nformat ascii 1.0\nelement vertex {len(verts)}\nproperty double x\n'
                'property double y\nproperty double z\n'
                f'element face {len(faces)}\nproperty list uchar uint vertex_index\nend_header\n')
        for v in verts:
            o.write('%.9g %.9g %.9g\n' % v)
        for f in faces:
            o.write(' '.join(str(k) for k in (len(f),) + f) + '\n')


def serialized_mesh(verts, faces):
    raw = struct.pack('<I', 0x1000) + b'mesh\0' + struct.pack('<QQ', len(verts), len(faces))
    raw += b''.join(struct.pack('<3f', *v) for v in verts)
    raw += b''.join(struct.pack('<3I', *f) for f in faces)
    return struct.pack('<HH', 0x041C, 4) + zlib.compress(raw)


def write_serialized(path):
    s = 0.2
    tet = [(s, s, s), (s, -s, -s), (-s, s, -s), (-s, -s, s)]
    tet_f = [(0, 1, 2), (0, 3, 1), (0, 2, 3), (1, 3, 2)]
    box = [(x, y, z) for x in (-s, s) for y in (-s, s) for z in (-s, s)]
    box_f = []
    for axis in range(3):
        for sign in (0, 1):
            quad = [i for i, p in enumerate(box) if (p[axis] > 0) == bool(sign)]
            # Order the 4 corners around the face's outward normal.
            n = [0, 0, 0]
            n[axis] = 1 if sign else -1
            c = [sum(box[i][k] for i in quad) / 4 for k in range(3)]
            u = [1 if k == (axis + 1) % 3 else 0 for k in range(3)]
            w = [n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]]
            quad.sort(key=lambda i: math.atan2(sum((box[i][k] - c[k]) * w[k] for k in range(3)),
                                               sum((box[i][k] - c[k]) * u[k] for k in range(3))))
            box_f += [(quad[0], quad[1], quad[2]), (quad[0], quad[2], quad[3])]
    data, offsets = b'', []
    for v, f in ((tet, tet_f), (box, box_f)):
        for t in f:  # every face outward
            a, b, c = (v[k] for k in t)
            e1 = [b[k] - a[k] for k in range(3)]
            e2 = [c[k] - a[k] for k in range(3)]
            nn = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0])
            assert sum(nn[k] * (a[k] + b[k] + c[k]) for k in range(3)) > 0, t
        offsets.append(len(data))
        data += serialized_mesh(v, f)
    data += b''.join(struct.pack('<Q', o) for o in offsets) + struct.pack('<I', len(offsets))
    open(path, 'wb').write(data)


def main():
    os.makedirs(os.path.join(HERE, 'meshes'), exist_ok=True)
    v, f = octahedron()
    write_ply_binary_be(os.path.join(HERE, 'meshes', 'octa.ply'), v, f)
    write_ply_ascii_prism(os.path.join(HERE, 'meshes', 'prism.ply'))
    write_serialized(os.path.join(HERE, 'meshes', 'two.serialized'))


if __name__ == '__main__':
    main()
