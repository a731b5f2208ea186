#!/usr/bin/env python3
"""Writes the `room` scene (issue 25's "scene that resembles a furnished room"): scene.xml and
meshes/*.obj, standard library only, deterministic (the same files on every run).

A 6 x 2.8 x 6 m living room (x in [-3, 3], y in [0, 2.8] up, z in [-4, 2]) seen from a corner,
320 x 240, box filter:
  - white walls and ceiling, a blue-grey accent wall (z = -4), a wooden floor (`roughplastic`,
    alpha 0.12: glossy reflections of the window), a rug;
  - a window in the left wall (x = -3: z in [-3.2, -1.2], y in [0.9, 2.3]) that is an area light
    of bluish daylight facing into the room (the opening itself: no glass), and a warm 0.5 x 0.5
    m ceiling lamp;
  - a table with four legs and four chairs (wood, `roughplastic` alpha 0.3), a red sofa with
    arms and back, a bookshelf with 3 shelves of coloured books, a side cabinet, and a rough gold
    bowl (`roughconductor` sphere) on the table.
Everything is axis-aligned boxes written as OBJ triangles (flat shading, no normals in the
files, each box's faces pointing outward), so both renderers read the same triangles; only the
bowl is an analytic `sphere` (Opticks tessellates it). Furniture stands 1 mm above the floor and
boxes never share a face, so no coplanar faces fight.

Usage: python3 testdata/mitsuba/room/make_scene.py   (rewrites scene.xml and meshes/)
"""
import os

HERE = os.path.dirname(os.path.abspath(__file__))
X0, X1, Y1, Z0, Z1 = -3.0, 3.0, 2.8, -4.0, 2.0
WINDOW = (-3.2, -1.2, 0.9, 2.3)  # z0, z1, y0, y1 in the wall x = X0
LAMP = (0.0, -1.2, 0.25)         # centre x, centre z, half size; 1 cm below the ceiling
EPS = 0.001


class Mesh:
    def __init__(self):
        self.v, self.f = [], []

    def quad(self, a, b, c, d):
        """A quad a b c d, counter-clockwise seen from the side it faces."""
        i = len(self.v) + 1
        self.v += [a, b, c, d]
        self.f += [(i, i + 1, i + 2), (i, i + 2, i + 3)]

    def box(self, lo, hi):
        """An axis-aligned box, faces outward."""
        (x0, y0, z0), (x1, y1, z1) = lo, hi
        self.quad((x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1))  # +z
        self.quad((x1, y0, z0), (x0, y0, z0), (x0, y1, z0), (x1, y1, z0))  # -z
        self.quad((x1, y0, z1), (x1, y0, z0), (x1, y1, z0), (x1, y1, z1))  # +x
        self.quad((x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0))  # -x
        self.quad((x0, y1, z1), (x1, y1, z1), (x1, y1, z0), (x0, y1, z0))  # +y
        self.quad((x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1))  # -y

    def write(self, name):
        with open(os.path.join(HERE, 'meshes', name + '.obj'), 'w') as f:
            f.write(f'# {name}: written by make_scene.py\n')
            for v in self.v:
                f.write('v %.6g %.6g %.6g\n' % v)
            for t in self.f:
                f.write('f %d %d %d\n' % t)
        return len(self.f)


def room():
    walls, accent, floor, ceiling = Mesh(), Mesh(), Mesh(), Mesh()
    floor.quad((X0, 0, Z1), (X1, 0, Z1), (X1, 0, Z0), (X0, 0, Z0))           # faces +y
    ceiling.quad((X0, Y1, Z0), (X1, Y1, Z0), (X1, Y1, Z1), (X0, Y1, Z1))     # faces -y
    accent.quad((X0, 0, Z0), (X1, 0, Z0), (X1, Y1, Z0), (X0, Y1, Z0))        # back, faces +z
    walls.quad((X1, 0, Z1), (X0, 0, Z1), (X0, Y1, Z1), (X1, Y1, Z1))         # front, faces -z
    walls.quad((X1, 0, Z0), (X1, 0, Z1), (X1, Y1, Z1), (X1, Y1, Z0))         # right, faces -x
    # Left wall (faces +x) around the window: four quads.
    wz0, wz1, wy0, wy1 = WINDOW
    for (za, zb, ya, yb) in [(Z0, wz0, 0, Y1), (wz1, Z1, 0, Y1), (wz0, wz1, 0, wy0), (wz0, wz1, wy1, Y1)]:
        walls.quad((X0, ya, zb), (X0, ya, za), (X0, yb, za), (X0, yb, zb))
    # The window's reveal (the wall is 0.2 m thick), facing into the opening.
    t = X0 - 0.2
    walls.quad((t, wy0, wz0), (t, wy0, wz1), (X0, wy0, wz1), (X0, wy0, wz0))  # sill, faces +y
    walls.quad((t, wy1, wz1), (t, wy1, wz0), (X0, wy1, wz0), (X0, wy1, wz1))  # head, faces -y
    walls.quad((t, wy0, wz0), (X0, wy0, wz0), (X0, wy1, wz0), (t, wy1, wz0))  # faces +z
    walls.quad((X0, wy0, wz1), (t, wy0, wz1), (t, wy1, wz1), (X0, wy1, wz1))  # faces -z
    return walls, accent, floor, ceiling


def furniture():
    wood, fabric, rug, cabinet = Mesh(), Mesh(), Mesh(), Mesh()
    books = [Mesh() for _ in range(4)]
    e = EPS
    # Table: top 1.6 x 0.9 at 0.75 m, centred at (0, -1.2).
    tx, tz = 0.0, -1.2
    wood.box((tx - 0.8, 0.72, tz - 0.45), (tx + 0.8, 0.76, tz + 0.45))
    for sx in (-1, 1):
        for sz in (-1, 1):
            x, z = tx + sx * 0.7, tz + sz * 0.36
            wood.box((x - 0.03, e, z - 0.03), (x + 0.03, 0.72 - e, z + 0.03))
    # Four chairs: seat at 0.45 m, a back on the side away from the table.
    for (cx, cz, bx, bz) in [(-0.45, -2.0, 0, -1), (0.45, -2.0, 0, -1), (-0.45, -0.4, 0, 1), (0.45, -0.4, 0, 1)]:
        wood.box((cx - 0.22, 0.43, cz - 0.22), (cx + 0.22, 0.47, cz + 0.22))
        for sx in (-1, 1):
            for sz in (-1, 1):
                x, z = cx + sx * 0.19, cz + sz * 0.19
                wood.box((x - 0.02, e, z - 0.02), (x + 0.02, 0.43 - e, z + 0.02))
        z = cz + bz * 0.2
        wood.box((cx - 0.22, 0.47 + e, z - 0.02), (cx + 0.22, 0.95, z + 0.02))
    # Sofa against the right wall, facing -x.
    sx0, sx1, sz0, sz1 = 1.9, 2.85, -2.6, -0.2
    fabric.box((sx0, 0.1, sz0 + 0.2), (sx1 - 0.2, 0.45, sz1 - 0.2))           # seat
    fabric.box((sx1 - 0.2 + e, 0.1, sz0), (sx1, 0.95, sz1))                   # back
    fabric.box((sx0, 0.1, sz0), (sx1 - 0.2, 0.65, sz0 + 0.2 - e))              # arm
    fabric.box((sx0, 0.1, sz1 - 0.2 + e), (sx1 - 0.2, 0.65, sz1))              # arm
    for (x, z) in [(sx0 + 0.05, sz0 + 0.05), (sx0 + 0.05, sz1 - 0.05), (sx1 - 0.05, sz0 + 0.05), (sx1 - 0.05, sz1 - 0.05)]:
        wood.box((x - 0.03, e, z - 0.03), (x + 0.03, 0.1 - e, z + 0.03))
    # Rug under the table.
    rug.box((-1.6, e, -2.6), (1.4, 0.012, 0.2))
    # Bookshelf against the back wall: 1.8 m wide, 2 m tall, 0.35 m deep, 4 levels.
    bx0, bx1, bz0, bz1 = -2.6, -0.8, Z0 + 0.01, Z0 + 0.36
    wood.box((bx0, e, bz0), (bx0 + 0.03, 2.0, bz1))
    wood.box((bx1 - 0.03, e, bz0), (bx1, 2.0, bz1))
    levels = [0.05, 0.52, 0.99, 1.46, 1.93]
    for y in levels:
        wood.box((bx0 + 0.03 + e, y, bz0), (bx1 - 0.03 - e, y + 0.03, bz1))
    # Books: deterministic widths and heights from a small linear congruential sequence.
    state = 12345

    def rnd():
        nonlocal state
        state = (1103515245 * state + 12345) % 2 ** 31
        return state / 2 ** 31

    for y in levels[:-1]:
        x = bx0 + 0.04
        while True:
            w, h = 0.03 + 0.04 * rnd(), 0.25 + 0.15 * rnd()
            if x + w > bx1 - 0.04:
                break
            m = books[int(rnd() * len(books)) % len(books)]
            m.box((x, y + 0.03 + e, bz0 + 0.04), (x + w - e, y + 0.03 + h, bz1 - 0.02))
            x += w + 0.004
            if rnd() < 0.1:
                x += 0.1  # a gap
    # A low cabinet under the window's right, against the left wall.
    cabinet.box((X0 + 0.01, e, -0.9), (X0 + 0.46, 0.7, 0.6))
    return wood, fabric, rug, cabinet, books


def lights():
    window, lamp = Mesh(), Mesh()
    wz0, wz1, wy0, wy1 = WINDOW
    x = X0 - 0.2 - 0.01  # just outside the reveal, facing +x into the room
    window.quad((x, wy0, wz1), (x, wy0, wz0), (x, wy1, wz0), (x, wy1, wz1))
    cx, cz, h = LAMP
    y = Y1 - 0.01  # facing -y
    lamp.quad((cx - h, y, cz - h), (cx + h, y, cz - h), (cx + h, y, cz + h), (cx - h, y, cz + h))
    # The lamp's housing: a thin box above it, against the ceiling.
    housing = Mesh()
    housing.box((cx - h - 0.03, Y1 - 0.01 + EPS, cz - h - 0.03), (cx + h + 0.03, Y1 - EPS, cz + h + 0.03))
    return window, lamp, housing


SCENE = """<?xml version="1.0" encoding="utf-8"?>
<!-- room: a furnished living room (issue 25's scene resembling a furnished room), written by
     make_scene.py (do not edit by hand: edit the script and rerun it). {triangles} triangles
     in OBJ boxes, a gold sphere, a daylight window and a ceiling lamp; 320 x 240, box filter.
     reference*.exr are Mitsuba's `path` (tools/mitsuba/render_reference.py room, integrator path). -->
<scene version="3.0.0">
    <default name="spp" value="64"/>
    <default name="max_depth" value="-1"/>

    <integrator type="path">
        <integer name="max_depth" value="$max_depth"/>
    </integrator>

    <sensor type="perspective">
        <string name="fov_axis" value="x"/>
        <float name="fov" value="72"/>
        <transform name="to_world">
            <lookat origin="2.5, 1.6, 1.7" target="-1.2, 0.8, -2.4" up="0, 1, 0"/>
        </transform>
        <sampler type="independent">
            <integer name="sample_count" value="$spp"/>
        </sampler>
        <film type="hdrfilm">
            <integer name="width" value="320"/>
            <integer name="height" value="240"/>
            <string name="pixel_format" value="rgb"/>
            <string name="component_format" value="float32"/>
            <rfilter type="box"/>
        </film>
    </sensor>

    <bsdf type="twosided" id="white">
        <bsdf type="diffuse"><rgb name="reflectance" value="0.78, 0.77, 0.74"/></bsdf>
    </bsdf>
    <bsdf type="twosided" id="accent">
        <bsdf type="diffuse"><rgb name="reflectance" value="0.25, 0.34, 0.46"/></bsdf>
    </bsdf>
    <bsdf type="roughplastic" id="floor">
        <string name="distribution" value="ggx"/>
        <float name="alpha" value="0.12"/>
        <rgb name="diffuse_reflectance" value="0.42, 0.26, 0.13"/>
    </bsdf>
    <bsdf type="roughplastic" id="wood">
        <string name="distribution" value="ggx"/>
        <float name="alpha" value="0.3"/>
        <rgb name="diffuse_reflectance" value="0.30, 0.17, 0.08"/>
    </bsdf>
    <bsdf type="twosided" id="fabric">
        <bsdf type="diffuse"><rgb name="reflectance" value="0.55, 0.10, 0.08"/></bsdf>
    </bsdf>
    <bsdf type="twosided" id="rug">
        <bsdf type="diffuse"><rgb name="reflectance" value="0.62, 0.56, 0.42"/></bsdf>
    </bsdf>
    <bsdf type="twosided" id="cabinet">
        <bsdf type="diffuse"><rgb name="reflectance" value="0.85, 0.85, 0.82"/></bsdf>
    </bsdf>
    <bsdf type="twosided" id="book0"><bsdf type="diffuse"><rgb name="reflectance" value="0.60, 0.15, 0.10"/></bsdf></bsdf>
    <bsdf type="twosided" id="book1"><bsdf type="diffuse"><rgb name="reflectance" value="0.12, 0.30, 0.15"/></bsdf></bsdf>
    <bsdf type="twosided" id="book2"><bsdf type="diffuse"><rgb name="reflectance" value="0.10, 0.15, 0.45"/></bsdf></bsdf>
    <bsdf type="twosided" id="book3"><bsdf type="diffuse"><rgb name="reflectance" value="0.70, 0.60, 0.35"/></bsdf></bsdf>
    <bsdf type="roughconductor" id="gold">
        <string name="material" value="Au"/>
        <string name="distribution" value="ggx"/>
        <float name="alpha" value="0.2"/>
    </bsdf>
    <bsdf type="diffuse" id="black"><rgb name="reflectance" value="0, 0, 0"/></bsdf>

{shapes}
    <shape type="sphere">
        <point name="center" x="0.25" y="0.93" z="-1.1"/>
        <float name="radius" value="0.17"/>
        <ref id="gold"/>
    </shape>

    <!-- daylight: the window opening, bluish, facing into the room -->
    <shape type="obj">
        <string name="filename" value="meshes/window.obj"/>
        <ref id="black"/>
        <emitter type="area"><rgb name="radiance" value="5.0, 5.6, 6.4"/></emitter>
    </shape>
    <!-- the warm ceiling lamp, facing down -->
    <shape type="obj">
        <string name="filename" value="meshes/lamp.obj"/>
        <ref id="black"/>
        <emitter type="area"><rgb name="radiance" value="30, 24, 16"/></emitter>
    </shape>
</scene>
"""


def main():
    os.makedirs(os.path.join(HERE, 'meshes'), exist_ok=True)
    walls, accent, floor, ceiling = room()
    wood, fabric, rug, cabinet, books = furniture()
    window, lamp, housing = lights()
    parts = [('walls', walls, 'white'), ('ceiling', ceiling, 'white'), ('accent', accent, 'accent'),
             ('floor', floor, 'floor'), ('wood', wood, 'wood'), ('fabric', fabric, 'fabric'),
             ('rug', rug, 'rug'), ('cabinet', cabinet, 'cabinet'), ('housing', housing, 'white')]
    parts += [(f'books{i}', m, f'book{i}') for i, m in enumerate(books)]
    shapes, total = [], 0
    for name, mesh, bsdf in parts:
        total += mesh.write(name)
        shapes.append(f'    <shape type="obj">\n        <string name="filename" value="meshes/{name}.obj"/>\n'
                      f'        <ref id="{bsdf}"/>\n    </shape>')
    total += window.write('window') + lamp.write('lamp')
    with open(os.path.join(HERE, 'scene.xml'), 'w') as f:
        f.write(SCENE.format(triangles=total, shapes='\n'.join(shapes)))
    print(f'wrote scene.xml and meshes/: {total} triangles in OBJ files')


if __name__ == '__main__':
    main()
