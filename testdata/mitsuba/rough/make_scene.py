#!/usr/bin/env python3
"""Writes the two sphere meshes of the rough-materials scene (tests/rough_materials.rs):
meshes/gold_sphere.obj and meshes/glass_sphere.obj, latitude-longitude spheres with outward
faces (counter-clockwise seen from outside), radius 0.4, resting on the floor y = 0.

Usage: python3 make_scene.py [rings, default 32 -> 3968 triangles per sphere]
Only the standard library is needed; scene.xml is written by hand.
"""
import math
import os
import sys

RINGS = int(sys.argv[1]) if len(sys.argv) > 1 else 32
RADIUS = 0.4
SPHERES = {'gold_sphere': (-0.5, RADIUS, 0.0), 'glass_sphere': (0.5, RADIUS, 0.0)}


def sphere(centre, rings):
    segs = 2 * rings
    verts = [(0.0, 1.0, 0.0)]
    for i in range(1, rings):
        t = math.pi * i / rings
        for j in range(segs):
            p = 2 * math.pi * j / segs
            verts.append((math.sin(t) * math.cos(p), math.cos(t), -math.sin(t) * math.sin(p)))
    verts.append((0.0, -1.0, 0.0))
    ring = lambda i, j: 1 + (i - 1) * segs + j % segs  # 1-based ring i >= 1, 0-based index
    faces = []
    for j in range(segs):  # top cap: north pole is vertex 0
        faces.append((0, ring(1, j), ring(1, j + 1)))
    for i in range(1, rings - 1):
        for j in range(segs):
            a, b, c, d = ring(i, j), ring(i, j + 1), ring(i + 1, j), ring(i + 1, j + 1)
            faces += [(a, c, d), (a, d, b)]
    south = len(verts) - 1
    for j in range(segs):
        faces.append((ring(rings - 1, j), south, ring(rings - 1, j + 1)))
    out = [tuple(centre[k] + RADIUS * v[k] for k in range(3)) for v in verts]
    # Orient every face outward (geometric normal (v1-v0)x(v2-v0) away from the centre).
    fixed = []
    for f in faces:
        v0, v1, v2 = (out[k] for k in f)
        e1 = [v1[k] - v0[k] for k in range(3)]
        e2 = [v2[k] - v0[k] for k in range(3)]
        n = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0])
        outward = sum(n[k] * (v0[k] - centre[k]) for k in range(3)) > 0
        fixed.append(f if outward else (f[0], f[2], f[1]))
    return out, fixed


here = os.path.dirname(os.path.abspath(__file__))
os.makedirs(os.path.join(here, 'meshes'), exist_ok=True)
for name, centre in SPHERES.items():
    verts, faces = sphere(centre, RINGS)
    with open(os.path.join(here, 'meshes', name + '.obj'), 'w') as f:
        f.write(f'# {name}: radius {RADIUS} at {centre}, {len(faces)} triangles (make_scene.py)\n')
        f.writelines('v %.6f %.6f %.6f\n' % v for v in verts)
        f.writelines('f %d %d %d\n' % tuple(k + 1 for k in t) for t in faces)
    print(name, len(verts), 'vertices', len(faces), 'triangles')
