#!/usr/bin/env python3
"""Writes meshes/ of the mirror-glass scene (issue 11's "complete" test): the shared Cornell box
(testdata/scenes/cornell) with its large box split off as a perfect mirror and a smooth glass
sphere resting on the small box.

  meshes/white.obj   the Cornell box's white.obj without the large box (floor, ceiling, back
                     wall, small box), copied object by object
  meshes/mirror.obj  the Cornell box's large box (12 triangles, faces outward), unchanged
  meshes/red.obj, green.obj, light.obj   copied unchanged
  meshes/sphere.obj  a latitude-longitude sphere, RINGS rings x 2 RINGS segments (RINGS = 64:
                     16,128 triangles, 8,066 vertices), radius 0.27, with exact (analytic)
                     vertex normals `vn` and faces outward (counter-clockwise seen from outside);
                     its south pole rests 1e-4 above the small box's top (y = -0.4) at the
                     centre of that top, (0.335, 0.38) in x, z

Usage: python3 make_scene.py   (standard library only; scene.xml is written by hand)
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
CORNELL = os.path.join(HERE, '..', '..', 'scenes', 'cornell', 'meshes')
RINGS, RADIUS = 64, 0.27
TOP_Y = -0.4            # the small box's top face
GAP = 1e-4              # the sphere's pole sits this far above it (no coincident surfaces)


def read_objects(path):
    """An OBJ written by testdata/scenes/cornell/make_scene.py as {name: (verts, faces)} with
    faces indexing the object's own vertices from 0 (the file numbers vertices globally)."""
    objs, order, base, cur = {}, [], 0, None
    with open(path) as f:
        for line in f:
            tok = line.split()
            if not tok or tok[0] == '#':
                continue
            if tok[0] == 'o':
                if cur is not None:
                    base += len(objs[cur][0])
                cur = tok[1]
                objs[cur] = ([], [])
                order.append(cur)
            elif tok[0] == 'v':
                objs[cur][0].append(tuple(float(x) for x in tok[1:4]))
            elif tok[0] == 'f':
                objs[cur][1].append(tuple(int(x) - 1 - base for x in tok[1:4]))
    return order, objs


def write_objects(path, header, order, objs):
    with open(path, 'w') as out:
        out.write(header)
        base = 0
        for name in order:
            verts, faces = objs[name]
            out.write(f'o {name}\n')
            out.writelines('v %.6f %.6f %.6f\n' % v for v in verts)
            out.writelines('f %d %d %d\n' % tuple(base + k + 1 for k in f) for f in faces)
            base += len(verts)


def small_box_top_centre(objs):
    verts = [v for v in objs['small-box'][0] if abs(v[1] - TOP_Y) < 1e-9]
    assert len(verts) >= 4, 'small box top not found'
    xs = sorted({round(v[0], 6) for v in verts})
    zs = sorted({round(v[2], 6) for v in verts})
    return sum(xs) / len(xs), sum(zs) / len(zs)


def sphere(centre, rings, radius):
    segs = 2 * rings
    unit = [(0.0, 1.0, 0.0)]
    for i in range(1, rings):
        t = math.pi * i / rings
        for j in range(segs):
            p = 2 * math.pi * j / segs
            unit.append((math.sin(t) * math.cos(p), math.cos(t), -math.sin(t) * math.sin(p)))
    unit.append((0.0, -1.0, 0.0))
    ring = lambda i, j: 1 + (i - 1) * segs + j % segs  # 0-based index of ring i >= 1
    faces = [(0, ring(1, j), ring(1, j + 1)) for j in range(segs)]
    for i in range(1, rings - 1):
        for j in range(segs):
            a, b, c, d = ring(i, j), ring(i, j + 1), ring(i + 1, j), ring(i + 1, j + 1)
            faces += [(a, c, d), (a, d, b)]
    south = len(unit) - 1
    faces += [(ring(rings - 1, j), south, ring(rings - 1, j + 1)) for j in range(segs)]
    for f in faces:  # every face outward: ((v1 - v0) x (v2 - v0)) . v0 > 0 on the unit sphere
        v0, v1, v2 = (unit[k] for k in f)
        e1 = [v1[k] - v0[k] for k in range(3)]
        e2 = [v2[k] - v0[k] for k in range(3)]
        n = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0])
        assert sum(n[k] * (v0[k] + v1[k] + v2[k]) for k in range(3)) > 0, f
    verts = [tuple(centre[k] + radius * u[k] for k in range(3)) for u in unit]
    return verts, unit, faces


def main():
    os.makedirs(os.path.join(HERE, 'meshes'), exist_ok=True)
    header = ('# mirror-glass scene: written by make_scene.py from testdata/scenes/cornell/meshes.\n'
              '# Units: meters, world space, right-handed, +y up.\n'
              '# Triangles are counter-clockwise; geometric normal = normalize((v1-v0) x (v2-v0)).\n')
    order, objs = read_objects(os.path.join(CORNELL, 'white.obj'))
    assert order == ['floor', 'ceiling', 'back', 'small-box', 'large-box'], order
    write_objects(os.path.join(HERE, 'meshes', 'white.obj'),
                  header + '# Walls face the inside of the box, the small box faces outward.\n',
                  order[:4], objs)
    write_objects(os.path.join(HERE, 'meshes', 'mirror.obj'),
                  header + '# The Cornell box\'s large box, faces outward.\n',
                  ['large-box'], objs)
    for name in ('red', 'green', 'light'):
        o, ob = read_objects(os.path.join(CORNELL, name + '.obj'))
        write_objects(os.path.join(HERE, 'meshes', name + '.obj'), header, o, ob)
    cx, cz = small_box_top_centre(objs)
    centre = (cx, TOP_Y + GAP + RADIUS, cz)
    verts, normals, faces = sphere(centre, RINGS, RADIUS)
    with open(os.path.join(HERE, 'meshes', 'sphere.obj'), 'w') as out:
        out.write(f'# glass sphere: radius {RADIUS} at ({centre[0]:.6f}, {centre[1]:.6f}, '
                  f'{centre[2]:.6f}), {RINGS} x {2 * RINGS} latitude-longitude, {len(faces)} '
                  'triangles, analytic vertex normals; written by make_scene.py\n')
        out.writelines('v %.7f %.7f %.7f\n' % v for v in verts)
        out.writelines('vn %.7f %.7f %.7f\n' % n for n in normals)
        out.writelines('f %d//%d %d//%d %d//%d\n' % (a + 1, a + 1, b + 1, b + 1, c + 1, c + 1)
                       for a, b, c in faces)
    print(f'sphere: centre {centre}, {len(verts)} vertices, {len(faces)} triangles')


if __name__ == '__main__':
    main()
