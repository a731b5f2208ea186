#!/usr/bin/env python3
"""Writes meshes/ of the bunny-box scene (issue 11: a Lambertian bunny in a box with coloured walls
and two coloured area lights, 320 x 240).

  meshes/bunny.obj    the Stanford bunny (bun_zipper: 35,947 vertices, 69,451 triangles, not
                      decimated), scaled by SCALE, its lowest point put on the floor (y = 0) and
                      its bounding box centred on (x, z) = BUNNY_XZ; with vertex normals `vn`
                      computed as Mitsuba 3 does for a mesh without normals
                      (Mesh::recompute_vertex_normals: the sum of the unit face normals weighted by
                      each triangle's angle at the vertex), so both renderers shade it with the
                      same smooth normals whatever they would generate themselves
  meshes/white.obj    floor (y = 0), ceiling (y = H), back wall (z = -D), facing into the box
  meshes/red.obj      left wall (x = -W), facing +x
  meshes/green.obj    right wall (x = +W), facing -x
  meshes/light_warm.obj, light_cool.obj   the two ceiling lights, 1 cm below the ceiling,
                      facing down (-y)
The box's front (z = +D) is open, as in the Cornell box. Triangles are counter-clockwise seen
from the side they face; geometric normal = normalize((v1 - v0) x (v2 - v0)).

The bunny comes from the Stanford 3D Scanning Repository (Greg Turk and Marc Levoy, 1994; see
README.md for the terms); the PLY read here is the copy in Mitsuba's test data repository
(mitsuba-renderer/mitsuba-data, common/meshes/bunny.ply, binary little-endian, 1,334,429 bytes,
sha256 b9b363c443640e9e0ad202188457037241d6eb671fd575e188821fea4bd2042d), which is byte for
byte the repository's bun_zipper.ply geometry (same vertex and face counts and bounds).

scene.xml is written by hand; make_scene.py derives its variants from it, so that they differ
from it only where they must: scene-warm.xml and scene-cool.xml switch the other light off by
removing the <emitter> from its <shape> (the block after its "COOL LIGHT" / "WARM LIGHT"
comment): its black panel stays, absorbing and shadowing exactly as in scene.xml, so that
scene.xml's image is the sum of theirs and a dataset of scene.xml with that light's power set
to zero must match them; scene-gold.xml gives the bunny the
BSDF GOLD (GGX roughconductor, alpha 0.25, the rough scene's gold; one-sided, the bunny's
faces point outward) in place of the block after the "BUNNY MATERIAL" comment.

Usage: python3 make_scene.py PATH/TO/bunny.ply   (standard library only)
       python3 make_scene.py --variants-only     (rewrites only the scene-*.xml variants)
"""
import hashlib
import math
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
PLY_SHA256 = 'b9b363c443640e9e0ad202188457037241d6eb671fd575e188821fea4bd2042d'
W, H, D = 1.6, 2.4, 1.5           # box: x in [-W, W], y in [0, H], z in [-D, D]
SCALE = 8.0                       # bunny: 0.154 m tall in the PLY -> 1.23 m
BUNNY_XZ = (0.0, -0.3)
LIGHT_Y = H - 0.01
# (name, centre x, centre z, half size x, half size z)
LIGHTS = [('light_warm', -0.75, -0.2, 0.35, 0.35), ('light_cool', 0.85, 0.45, 0.2, 0.2)]


def read_ply(path):
    data = open(path, 'rb').read()
    if hashlib.sha256(data).hexdigest() != PLY_SHA256:
        print('warning: this is not the PLY the committed OBJ was made from', file=sys.stderr)
    end = data.index(b'end_header\n') + len(b'end_header\n')
    header = data[:end].decode('ascii').split('\n')
    assert header[0] == 'ply' and 'format binary_little_endian 1.0' in header, header[:3]
    nv = next(int(l.split()[2]) for l in header if l.startswith('element vertex'))
    nf = next(int(l.split()[2]) for l in header if l.startswith('element face'))
    props = [l.split()[2] for l in header if l.startswith('property float')]
    assert props == ['x', 'y', 'z'], props  # bun_zipper as stored: positions only
    flat = struct.unpack_from('<%df' % (3 * nv), data, end)
    verts = [flat[3 * i:3 * i + 3] for i in range(nv)]
    faces, o = [], end + 12 * nv
    for _ in range(nf):
        assert data[o] == 3, 'not a triangle'
        faces.append(struct.unpack_from('<3i', data, o + 1))
        o += 13
    assert o == len(data)
    return verts, faces


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def norm(a):
    return math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])


def vertex_normals(verts, faces):
    """Mitsuba 3's Mesh::recompute_vertex_normals: for each triangle of non-zero area, its unit
    normal times the angle at each corner is added to that corner's vertex; then normalised
    (a vertex with no such triangle gets +x, Mitsuba's placeholder)."""
    acc = [[0.0, 0.0, 0.0] for _ in verts]
    for f in faces:
        p = [verts[k] for k in f]
        n = cross(sub(p[1], p[0]), sub(p[2], p[0]))
        ln = norm(n)
        if not ln > 0:
            continue
        n = (n[0] / ln, n[1] / ln, n[2] / ln)
        for i in range(3):
            d0, d1 = sub(p[(i + 1) % 3], p[i]), sub(p[(i + 2) % 3], p[i])
            l0, l1 = norm(d0), norm(d1)
            if not (l0 > 0 and l1 > 0):
                continue
            c = max(-1.0, min(1.0, (d0[0] * d1[0] + d0[1] * d1[1] + d0[2] * d1[2]) / (l0 * l1)))
            a = math.acos(c)
            for k in range(3):
                acc[f[i]][k] += n[k] * a
    out = []
    for a in acc:
        ln = norm(a)
        out.append((a[0] / ln, a[1] / ln, a[2] / ln) if ln > 0 else (1.0, 0.0, 0.0))
    return out


def quad(a, b, c, d):
    """Two counter-clockwise triangles a b c, a c d."""
    return [a, b, c, d], [(0, 1, 2), (0, 2, 3)]


def write_obj(path, header, objects):
    with open(path, 'w') as out:
        out.write(header)
        base = 0
        for name, (verts, faces) in objects:
            out.write(f'o {name}\n')
            out.writelines('v %.6f %.6f %.6f\n' % v for v in verts)
            out.writelines('f %d %d %d\n' % tuple(base + k + 1 for k in f) for f in faces)
            base += len(verts)


def switch_off(xml, marker):
    """xml with the <emitter> removed from the <shape> after the comment `<!-- MARKER`, and a
    note in that comment: the light's (black) geometry stays."""
    start = xml.index('    <!-- ' + marker)
    end = xml.index('</shape>\n', start)
    e0 = xml.index('        <emitter', start)
    e1 = xml.index('</emitter>\n', e0) + len('</emitter>\n')
    assert e1 <= end
    note = f'    <!-- {marker} SWITCHED OFF (its <emitter> removed by make_scene.py; the panel stays)'
    head = xml.index(marker, start) + len(marker)
    return xml[:start] + note + xml[head:e0] + xml[e1:]


GOLD = '''    <!-- BUNNY MATERIAL: GGX gold, the rough scene's (one-sided; the bunny faces outward) -->
    <bsdf type="roughconductor" id="bunny_material">
        <string name="distribution" value="ggx"/>
        <float name="alpha" value="0.25"/>
        <rgb name="eta" value="0.143, 0.374, 1.442"/>
        <rgb name="k" value="3.983, 2.385, 1.603"/>
    </bsdf>
'''


def replace_bsdf(xml, marker, new):
    """xml with the comment starting with `<!-- MARKER` and the <bsdf> after it replaced by new."""
    start = xml.index('    <!-- ' + marker)
    end = xml.index('\n    </bsdf>\n', start) + len('\n    </bsdf>\n')
    return xml[:start] + new + xml[end:]


def write_variants():
    with open(os.path.join(HERE, 'scene.xml')) as f:
        xml = f.read()
    variants = {
        'scene-warm.xml': ('only the warm light emits (the cool one switched off)',
                           switch_off(xml, 'COOL LIGHT')),
        'scene-cool.xml': ('only the cool light emits (the warm one switched off)',
                           switch_off(xml, 'WARM LIGHT')),
        'scene-gold.xml': ('the bunny is GGX gold (roughconductor, alpha 0.25), both lights',
                           replace_bsdf(xml, 'BUNNY MATERIAL', GOLD)),
    }
    for name, (what, text) in variants.items():
        head = text.index('<scene ')
        text = (text[:head] + f'<!-- {name}: written by make_scene.py from scene.xml; {what}. -->\n'
                + text[head:])
        with open(os.path.join(HERE, name), 'w') as f:
            f.write(text)


def main():
    if sys.argv[1:] == ['--variants-only']:
        write_variants()
        return
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    write_variants()
    verts, faces = read_ply(sys.argv[1])
    lo = [min(v[k] for v in verts) for k in range(3)]
    hi = [max(v[k] for v in verts) for k in range(3)]
    shift = (BUNNY_XZ[0] - SCALE * (lo[0] + hi[0]) / 2, -SCALE * lo[1],
             BUNNY_XZ[1] - SCALE * (lo[2] + hi[2]) / 2)
    world = [tuple(SCALE * v[k] + shift[k] for k in range(3)) for v in verts]
    normals = vertex_normals(world, faces)
    os.makedirs(os.path.join(HERE, 'meshes'), exist_ok=True)
    with open(os.path.join(HERE, 'meshes', 'bunny.obj'), 'w') as out:
        out.write('# Stanford bunny (Stanford 3D Scanning Repository, Turk & Levoy 1994; see '
                  '../README.md), %d vertices, %d triangles,\n# scaled by %g and placed on the floor '
                  'by make_scene.py; vn = Mitsuba 3\'s angle-weighted vertex normals.\n'
                  % (len(world), len(faces), SCALE))
        out.writelines('v %.5f %.5f %.5f\n' % v for v in world)
        out.writelines('vn %.4f %.4f %.4f\n' % n for n in normals)
        out.writelines('f %d//%d %d//%d %d//%d\n' % (a + 1, a + 1, b + 1, b + 1, c + 1, c + 1)
                       for a, b, c in faces)
    header = ('# bunny-box: written by make_scene.py. Units: meters, world space, right-handed, '
              '+y up.\n# Triangles are counter-clockwise; geometric normal = '
              'normalize((v1-v0) x (v2-v0)).\n')
    walls = [
        ('floor', quad((-W, 0, D), (W, 0, D), (W, 0, -D), (-W, 0, -D))),
        ('ceiling', quad((-W, H, -D), (W, H, -D), (W, H, D), (-W, H, D))),
        ('back', quad((-W, 0, -D), (W, 0, -D), (W, H, -D), (-W, H, -D))),
    ]
    write_obj(os.path.join(HERE, 'meshes', 'white.obj'), header + '# Walls face into the box.\n', walls)
    write_obj(os.path.join(HERE, 'meshes', 'red.obj'), header,
              [('left', quad((-W, 0, D), (-W, 0, -D), (-W, H, -D), (-W, H, D)))])
    write_obj(os.path.join(HERE, 'meshes', 'green.obj'), header,
              [('right', quad((W, 0, -D), (W, 0, D), (W, H, D), (W, H, -D)))])
    for name, cx, cz, hx, hz in LIGHTS:
        y = LIGHT_Y
        write_obj(os.path.join(HERE, 'meshes', name + '.obj'),
                  header + f'# {2 * hx:g} x {2 * hz:g} m ceiling light, area {4 * hx * hz:g} m^2, '
                  'facing down (-y).\n',
                  [(name, quad((cx - hx, y, cz - hz), (cx + hx, y, cz - hz),
                               (cx + hx, y, cz + hz), (cx - hx, y, cz + hz)))])
    print(f'bunny: {len(world)} vertices, {len(faces)} triangles, bounds '
          f'{[round(min(v[k] for v in world), 4) for k in range(3)]} .. '
          f'{[round(max(v[k] for v in world), 4) for k in range(3)]}')


if __name__ == '__main__':
    main()
