#!/usr/bin/env python3
"""make_big_scene.py - writes issue 14's >= 1 M-triangle benchmark scene (NOT committed: generated).

The scene: GRID x GRID instances of the Stanford bunny of testdata/mitsuba/bunny-box (69,451
triangles), each subdivided SUBDIV times (every triangle split into four at its edge midpoints,
so 4^SUBDIV x 69,451 triangles; the shape stays the same, the new vertices' normals are the
normalised means of the edge's two vertex normals), standing on the floor of a closed 8 x 3 x 8 m
room (white Lambertian walls, floor and ceiling) lit by one 1 x 1 m ceiling light, seen by a
256 x 256 pinhole camera (box filter) from inside the room. Every bunny is the same OBJ file,
placed by its <shape>'s to_world (centred, scaled by 0.8, rotated about +y and translated), so
the OBJ is written once; both Mitsuba 3 and Opticks load each <shape> as its own world-space
triangles (no instancing), so the renderers see GRID^2 x 4^SUBDIV x 69,451 triangles. Defaults: SUBDIV 1, GRID 3 -> 9 x 277,804 =
2,500,236 bunny triangles (+ 14 for the room and light).

Writes OUT/scene.xml and OUT/meshes/{bunny_subN.obj, room.obj, light.obj}, by default into
target/big-scene/ (ignored by git: the scene is large and reproducible, do not commit it).

Usage (from the repository root; standard library only, ~1 min):
    python3 benches/make_big_scene.py [--out target/big-scene] [--subdiv 1] [--grid 3]
    # Mitsuba's light tracer on it (issue 14's competitor figure):
    /work/venv-mitsuba/bin/python benches/mitsuba_ptracer.py target/big-scene/scene.xml --threads 2
    # Opticks:
    opticks trace target/big-scene/scene.xml --paths 4194304 -o /tmp/big.opds
    opticks render /tmp/big.opds -o /tmp/big.exr
(No reference.exr is written: the figures of interest are times, not errors.)
"""
import argparse
import math
import os

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BUNNY = os.path.join(REPO, 'testdata', 'mitsuba', 'bunny-box', 'meshes', 'bunny.obj')
HALF, HEIGHT = 4.0, 3.0        # room: x, z in [-HALF, HALF], y in [0, HEIGHT]
SCALE = 0.8                    # each bunny: 1.23 m -> 0.99 m tall
BUNNY_XZ = (0.0, -0.3)         # where bunny-box/make_scene.py centred the bunny's bounding box


def read_obj(path):
    verts, normals, faces = [], [], []
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == 'v':
                verts.append(tuple(float(x) for x in t[1:4]))
            elif t[0] == 'vn':
                normals.append(tuple(float(x) for x in t[1:4]))
            elif t[0] == 'f':
                faces.append(tuple(int(c.split('/')[0]) - 1 for c in t[1:4]))
    assert len(normals) == len(verts), 'bunny.obj: one vn per v expected (v//vn corners)'
    return verts, normals, faces


def subdivide(verts, normals, faces):
    verts, normals = list(verts), list(normals)
    mid = {}

    def midpoint(a, b):
        key = (a, b) if a < b else (b, a)
        if key not in mid:
            p = tuple((verts[a][k] + verts[b][k]) / 2 for k in range(3))
            n = tuple(normals[a][k] + normals[b][k] for k in range(3))
            ln = math.sqrt(sum(c * c for c in n)) or 1.0
            verts.append(p)
            normals.append(tuple(c / ln for c in n) if ln > 1e-12 else normals[a])
            mid[key] = len(verts) - 1
        return mid[key]
    out = []
    for a, b, c in faces:
        ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
        out += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    return verts, normals, out


def write_quads(path, quads):
    with open(path, 'w') as f:
        f.write('# make_big_scene.py; counter-clockwise seen from the side each quad faces\n')
        for i, q in enumerate(quads):
            f.writelines('v %.6f %.6f %.6f\n' % v for v in q)
            f.write('f %d %d %d\nf %d %d %d\n' % (4 * i + 1, 4 * i + 2, 4 * i + 3, 4 * i + 1, 4 * i + 3, 4 * i + 4))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--out', default=os.path.join(REPO, 'target', 'big-scene'))
    ap.add_argument('--subdiv', type=int, default=1)
    ap.add_argument('--grid', type=int, default=3)
    args = ap.parse_args()
    os.makedirs(os.path.join(args.out, 'meshes'), exist_ok=True)
    verts, normals, faces = read_obj(BUNNY)
    for _ in range(args.subdiv):
        verts, normals, faces = subdivide(verts, normals, faces)
    name = f'bunny_sub{args.subdiv}.obj'
    with open(os.path.join(args.out, 'meshes', name), 'w') as f:
        f.write(f'# bunny-box bunny subdivided {args.subdiv}x by make_big_scene.py: '
                f'{len(faces)} triangles\n')
        f.writelines('v %.6f %.6f %.6f\n' % v for v in verts)
        f.writelines('vn %.5f %.5f %.5f\n' % n for n in normals)
        f.writelines('f %d//%d %d//%d %d//%d\n' % (a + 1, a + 1, b + 1, b + 1, c + 1, c + 1)
                     for a, b, c in faces)
    H, Y = HALF, HEIGHT
    write_quads(os.path.join(args.out, 'meshes', 'room.obj'), [
        ((-H, 0, H), (H, 0, H), (H, 0, -H), (-H, 0, -H)),       # floor, up
        ((-H, Y, -H), (H, Y, -H), (H, Y, H), (-H, Y, H)),       # ceiling, down
        ((-H, 0, -H), (H, 0, -H), (H, Y, -H), (-H, Y, -H)),     # back, +z
        ((H, 0, H), (-H, 0, H), (-H, Y, H), (H, Y, H)),         # front, -z
        ((-H, 0, H), (-H, 0, -H), (-H, Y, -H), (-H, Y, H)),     # left, +x
        ((H, 0, -H), (H, 0, H), (H, Y, H), (H, Y, -H)),         # right, -x
    ])
    ly = Y - 0.01
    write_quads(os.path.join(args.out, 'meshes', 'light.obj'),
                [((-0.5, ly, -0.5), (0.5, ly, -0.5), (0.5, ly, 0.5), (-0.5, ly, 0.5))])
    shapes = []
    g, spacing = args.grid, 2 * HALF * 0.55 / max(args.grid, 1)
    for i in range(g):
        for j in range(g):
            x = (i - (g - 1) / 2) * spacing
            z = (j - (g - 1) / 2) * spacing
            angle = (37 * (i * g + j)) % 360
            shapes.append(f'''    <shape type="obj" id="bunny_{i}_{j}">
        <string name="filename" value="meshes/{name}"/>
        <transform name="to_world">
            <translate z="{-BUNNY_XZ[1]}"/>
            <scale value="{SCALE}"/>
            <rotate y="1" angle="{angle}"/>
            <translate x="{x:.4f}" y="0" z="{z:.4f}"/>
        </transform>
        <ref id="bunny"/>
    </shape>
''')
    xml = f'''<?xml version="1.0" encoding="utf-8"?>
<!-- big scene (issue 14): {g * g} bunnies x {len(faces)} triangles = {g * g * len(faces)} triangles
     in a closed room; written by benches/make_big_scene.py (do not edit, do not commit). -->
<scene version="3.0.0">
    <integrator type="ptracer">
        <integer name="max_depth" value="-1"/>
    </integrator>
    <sensor type="perspective">
        <string name="fov_axis" value="x"/>
        <float name="fov" value="70"/>
        <transform name="to_world">
            <lookat origin="0, 2.2, {HALF - 0.2}" target="0, 0.3, 0" up="0, 1, 0"/>
        </transform>
        <sampler type="independent"><integer name="sample_count" value="64"/></sampler>
        <film type="hdrfilm">
            <integer name="width" value="256"/>
            <integer name="height" value="256"/>
            <string name="pixel_format" value="rgb"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <bsdf type="twosided" id="white">
        <bsdf type="diffuse"><rgb name="reflectance" value="0.7, 0.7, 0.7"/></bsdf>
    </bsdf>
    <bsdf type="twosided" id="bunny">
        <bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.76, 0.7"/></bsdf>
    </bsdf>
    <shape type="obj" id="room">
        <string name="filename" value="meshes/room.obj"/>
        <boolean name="face_normals" value="true"/>
        <ref id="white"/>
    </shape>
    <shape type="obj" id="light">
        <string name="filename" value="meshes/light.obj"/>
        <boolean name="face_normals" value="true"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="0, 0, 0"/></bsdf>
        <emitter type="area"><rgb name="radiance" value="20, 20, 20"/></emitter>
    </shape>
{''.join(shapes)}</scene>
'''
    with open(os.path.join(args.out, 'scene.xml'), 'w') as f:
        f.write(xml)
    print(f'{args.out}/scene.xml: {g * g} bunnies x {len(faces)} triangles = '
          f'{g * g * len(faces)} triangles (+ 14)')


if __name__ == '__main__':
    main()
