#!/usr/bin/env python3
"""Writes meshes/*.obj and scene.xml for the ring showcase (a metal ring on a table).

Usage: python3 make_scene.py [segments, default 256]
Only the standard library is needed. Geometry (metres, +y up):
  * table: a 6 x 6 diffuse rectangle at y = 0 (in scene.xml), reflectance 0.7;
  * ring: an open cylinder of radius R = 0.5 and height H = 0.25 standing on the table around
    the y axis. Its inside wall (meshes/ring_inside.obj, normals pointing to the axis) is an
    ideal mirror (`conductor`); a thin outer wall at R + T (meshes/ring_outside.obj, normals
    outward) and the top rim between them (meshes/ring_rim.obj, normals up) are diffuse grey,
    so the ring is visible from outside (a light tracer cannot see mirrors through a pinhole);
  * light: a small 0.1 x 0.1 area light low on the left (-2.0, 0.7, 0), facing the ring.
Light entering the ring over its near rim reflects off the inside of the far wall and
focuses on the table into the cardioid (nephroid) "coffee cup" caustic, cusp at R/2.
"""
import math
import os
import sys

N = int(sys.argv[1]) if len(sys.argv) > 1 else 256
R, H, T = 0.5, 0.25, 0.01
HERE = os.path.dirname(os.path.abspath(__file__))


def ring_point(r, i, y):
    a = 2 * math.pi * i / N
    return (r * math.cos(a), y, r * math.sin(a))


def write_obj(name, comment, verts, faces):
    with open(os.path.join(HERE, 'meshes', name), 'w') as f:
        f.write(f'# {comment}; made by make_scene.py\n')
        for v in verts:
            f.write('v %.6f %.6f %.6f\n' % v)
        for a, b, c in faces:
            f.write(f'f {a + 1} {b + 1} {c + 1}\n')


def wall(r, inward):
    """N quads between y = 0 and y = H at radius r; normals inward or outward."""
    verts = [ring_point(r, i, y) for i in range(N) for y in (0.0, H)]
    faces = []
    for i in range(N):
        j = (i + 1) % N
        b0, t0, b1, t1 = 2 * i, 2 * i + 1, 2 * j, 2 * j + 1
        faces += [(b0, t0, b1), (b1, t0, t1)]
    # orient: the first face's normal decides (all faces are wound alike); flip all if needed
    (x0, y0, z0), (x1, y1, z1), (x2, y2, z2) = (verts[k] for k in faces[0])
    u, v = (x1 - x0, y1 - y0, z1 - z0), (x2 - x0, y2 - y0, z2 - z0)
    n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    outward = n[0] * (x0 + x2) + n[2] * (z0 + z2) > 0
    if outward == inward:
        faces = [(a, c, b) for a, b, c in faces]
    return verts, faces


def rim():
    verts = [ring_point(r, i, H) for i in range(N) for r in (R, R + T)]
    faces = []
    for i in range(N):
        j = (i + 1) % N
        faces += [(2 * i, 2 * i + 1, 2 * j), (2 * j, 2 * i + 1, 2 * j + 1)]
    (x0, y0, z0), (x1, y1, z1), (x2, y2, z2) = (verts[k] for k in faces[0])
    u, v = (x1 - x0, y1 - y0, z1 - z0), (x2 - x0, y2 - y0, z2 - z0)
    if u[2] * v[0] - u[0] * v[2] < 0:  # y component of the normal must be +
        faces = [(a, c, b) for a, b, c in faces]
    return verts, faces


os.makedirs(os.path.join(HERE, 'meshes'), exist_ok=True)
write_obj('ring_inside.obj', f'ring inside wall, R={R} H={H}, {N} segments, normals to the axis',
          *wall(R, inward=True))
write_obj('ring_outside.obj', f'ring outside wall, R={R + T} H={H}, {N} segments, normals outward',
          *wall(R + T, inward=False))
write_obj('ring_rim.obj', f'ring top rim, R={R}..{R + T} at y={H}, {N} segments, normals up', *rim())

SCENE = '''<?xml version="1.0" encoding="utf-8"?>
<!-- ring: a metal ring (open cylinder, mirror inside) on a diffuse table, lit from the side by a
     small bright area light low above the table: the cardioid "coffee cup" caustic.
     Written by make_scene.py (do not edit by hand). Mitsuba 3: `mitsuba scene.xml -Dspp=...`;
     the ptracer integrator computes what Opticks computes (mirrors seen through the pinhole
     are black for both). -->
<scene version="3.0.0">
    <default name="spp" value="256"/>

    <integrator type="ptracer">
        <integer name="max_depth" value="-1"/>
    </integrator>

    <sensor type="perspective">
        <string name="fov_axis" value="x"/>
        <float name="fov" value="40"/>
        <transform name="to_world">
            <lookat origin="0.35, 1.75, 1.2" target="0.1, 0, 0" up="0, 1, 0"/>
        </transform>
        <sampler type="independent">
            <integer name="sample_count" value="$spp"/>
        </sampler>
        <film type="hdrfilm">
            <integer name="width" value="320"/>
            <integer name="height" value="240"/>
            <string name="pixel_format" value="rgb"/>
            <rfilter type="box"/>
        </film>
    </sensor>

    <bsdf type="diffuse" id="table_paint">
        <rgb name="reflectance" value="0.7, 0.7, 0.7"/>
    </bsdf>

    <bsdf type="diffuse" id="ring_paint">
        <rgb name="reflectance" value="0.4, 0.4, 0.4"/>
    </bsdf>

    <!-- ideal mirror, one-sided (the inside wall's normals point to the axis) -->
    <bsdf type="conductor" id="mirror">
        <string name="material" value="none"/>
    </bsdf>

    <!-- 6 x 6 table at y = 0, facing up -->
    <shape type="rectangle" id="table">
        <transform name="to_world">
            <rotate x="1" angle="-90"/>
            <scale value="3"/>
        </transform>
        <ref id="table_paint"/>
    </shape>

    <shape type="obj" id="ring_inside">
        <string name="filename" value="meshes/ring_inside.obj"/>
        <boolean name="face_normals" value="true"/>
        <ref id="mirror"/>
    </shape>
    <shape type="obj" id="ring_outside">
        <string name="filename" value="meshes/ring_outside.obj"/>
        <boolean name="face_normals" value="true"/>
        <ref id="ring_paint"/>
    </shape>
    <shape type="obj" id="ring_rim">
        <string name="filename" value="meshes/ring_rim.obj"/>
        <boolean name="face_normals" value="true"/>
        <ref id="ring_paint"/>
    </shape>

    <!-- 0.1 x 0.1 area light low on the left, facing the ring: Phi = pi * 2000 * 0.01 = 62.8 W -->
    <shape type="rectangle" id="light">
        <transform name="to_world">
            <scale value="0.05"/>
            <lookat origin="-2.0, 0.7, 0" target="0, 0.1, 0" up="0, 1, 0"/>
        </transform>
        <emitter type="area">
            <rgb name="radiance" value="2000, 2000, 2000"/>
        </emitter>
        <bsdf type="diffuse"><rgb name="reflectance" value="0, 0, 0"/></bsdf>
    </shape>
</scene>
'''
with open(os.path.join(HERE, 'scene.xml'), 'w') as f:
    f.write(SCENE)
print(f'{N} segments: {2 * N} triangles per wall and rim')
