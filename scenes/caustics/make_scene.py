#!/usr/bin/env python3
"""Writes meshes/glass_sphere.obj (an icosphere, outward normals) for the caustics showcase.

Usage: python3 make_scene.py [subdivision levels, default 4 -> 5120 triangles]
Only the standard library is needed; scene.xml is written by hand.
"""
import math
import sys

LEVELS = int(sys.argv[1]) if len(sys.argv) > 1 else 4
CENTRE = (0.0, 0.5, 0.0)
RADIUS = 0.5

p = (1 + math.sqrt(5)) / 2
verts = [(-1, p, 0), (1, p, 0), (-1, -p, 0), (1, -p, 0), (0, -1, p), (0, 1, p),
         (0, -1, -p), (0, 1, -p), (p, 0, -1), (p, 0, 1), (-p, 0, -1), (-p, 0, 1)]


def norm(v):
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v)


verts = [norm(v) for v in verts]
tris = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
        (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
        (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
for _ in range(LEVELS):
    cache = {}

    def mid(a, b):
        key = (min(a, b), max(a, b))
        if key not in cache:
            verts.append(norm(tuple((x + y) / 2 for x, y in zip(verts[a], verts[b]))))
            cache[key] = len(verts) - 1
        return cache[key]

    nxt = []
    for a, b, c in tris:
        ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
        nxt += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    tris = nxt


def sub(u, v):
    return tuple(x - y for x, y in zip(u, v))


def cross(u, v):
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


with open("meshes/glass_sphere.obj", "w") as f:
    f.write(f"# icosphere, {LEVELS} subdivisions, centre {CENTRE}, radius {RADIUS}; made by make_scene.py\n")
    for v in verts:
        f.write("v %.6f %.6f %.6f\n" % tuple(CENTRE[i] + RADIUS * v[i] for i in range(3)))
    for a, b, c in tris:
        n = cross(sub(verts[b], verts[a]), sub(verts[c], verts[a]))
        s = sum(n[i] * (verts[a][i] + verts[b][i] + verts[c][i]) for i in range(3))
        if s < 0:  # wind counter-clockwise seen from outside
            b, c = c, b
        f.write(f"f {a + 1} {b + 1} {c + 1}\n")
print(f"{len(verts)} vertices, {len(tris)} triangles")
