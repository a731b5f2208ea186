#!/usr/bin/env python3
"""Writes meshes/sphere.obj for the smooth-normals scene (crates/cli/tests/it/caustics.rs): a low-poly
latitude-longitude sphere (8 rings x 16 segments = 224 triangles, one vertex per pole), radius
0.5 about the origin, faces outward (counter-clockwise seen from outside), with no `vn` and no
`vt`, so Mitsuba 3 (and Opticks) generate angle-weighted smooth vertex normals for it.

Usage: python3 make_scene.py   (standard library only; scene.xml is written by hand)
"""
import math
import os

RINGS, SEGS, RADIUS = 8, 16, 0.5


def main():
    verts = [(0.0, RADIUS, 0.0)]
    for i in range(1, RINGS):
        t = math.pi * i / RINGS
        for j in range(SEGS):
            p = 2 * math.pi * j / SEGS
            verts.append((RADIUS * math.sin(t) * math.cos(p), RADIUS * math.cos(t),
                          -RADIUS * math.sin(t) * math.sin(p)))
    verts.append((0.0, -RADIUS, 0.0))
    ring = lambda i, j: 1 + (i - 1) * SEGS + j % SEGS  # 0-based index of ring i >= 1
    faces = [(0, ring(1, j), ring(1, j + 1)) for j in range(SEGS)]
    for i in range(1, RINGS - 1):
        for j in range(SEGS):
            a, b, c, d = ring(i, j), ring(i, j + 1), ring(i + 1, j), ring(i + 1, j + 1)
            faces += [(a, c, d), (a, d, b)]
    south = len(verts) - 1
    faces += [(ring(RINGS - 1, j), south, ring(RINGS - 1, j + 1)) for j in range(SEGS)]
    for f in faces:  # every face outward: (v1 - v0) x (v2 - v0) . v0 > 0
        v0, v1, v2 = (verts[k] for k in f)
        e1 = [v1[k] - v0[k] for k in range(3)]
        e2 = [v2[k] - v0[k] for k in range(3)]
        n = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0])
        assert sum(n[k] * v0[k] for k in range(3)) > 0, f
    here = os.path.dirname(os.path.abspath(__file__))
    os.makedirs(os.path.join(here, 'meshes'), exist_ok=True)
    with open(os.path.join(here, 'meshes', 'sphere.obj'), 'w') as out:
        out.write(f'# {RINGS} x {SEGS} latitude-longitude sphere, radius {RADIUS}, no vn: '
                  'written by make_scene.py\n')
        for v in verts:
            out.write('v %.9g %.9g %.9g\n' % v)
        for f in faces:
            out.write('f %d %d %d\n' % tuple(k + 1 for k in f))


if __name__ == '__main__':
    main()
