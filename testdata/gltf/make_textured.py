#!/usr/bin/env python3
"""Writes textured.gltf + textured.bin + checker.png, and the same room as Mitsuba XML
(textured.xml + textured-floor.obj + textured-lamp.obj), for the glTF loader's texture,
transmission, scene and camera tests (crates/io/tests/it/gltf.rs, tests/gltf_textures.rs).

Python 3 standard library only. Run from anywhere:  python3 testdata/gltf/make_textured.py

What the glTF holds, as Blender's exporter writes it for a small textured interior:
* `checker.png`: a 4 x 4 sRGB checkerboard of two colours, an external image file, sampled
  NEAREST with REPEAT wrapping;
* `floor`: a 2 m x 2 m quad at y = 0 with TEXCOORD_0 (0,0)..(1,1), material `tiles`: the
  checker as baseColorTexture times baseColorFactor, KHR_texture_transform scale (2, 2) and
  offset (0.25, 0), KHR_materials_specular specularFactor 0 (a pure Lambertian), doubleSided;
* `lamp`: a 0.5 m x 0.5 m quad 1.5 m above, facing down, emissiveFactor x emissiveStrength =
  (8, 6, 4) W/(m^2 sr);
* `pane`: a vertical 1 m x 1 m quad, material `glass`: KHR_materials_transmission 1, ior 1.5,
  no KHR_materials_volume (thin-walled);
* two scenes: `Day` (default: floor, lamp, cameras `Overview` and `Detail`) and `Night`
  (floor, pane, a KHR_lights_punctual point light, camera `Detail`).

textured.xml is scene `Day` in Mitsuba's terms: the floor's OBJ `vt` is (u, 1 - v) because
Mitsuba's `obj` flips v (`flip_tex_coords`, default true), so both files give the same UVs, and
the texture transform is the bitmap's `to_uv`. A render of the two must agree.
"""

import json
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
COLOURS = ((230, 60, 40), (40, 120, 220))  # sRGB 8-bit
FACTOR = (1.0, 1.0, 1.0)  # baseColorFactor: 1, so that Mitsuba's bitmap alone is the same colour
RADIANCE_FACTOR = (1.0, 0.75, 0.5)
RADIANCE_STRENGTH = 8.0
SCALE = (2.0, 2.0)
OFFSET = (0.25, 0.0)


def png(width, height, rows):
    """An 8-bit RGB PNG of `rows` (lists of (r, g, b))."""
    raw = b"".join(b"\x00" + bytes(c for px in row for c in px) for row in rows)

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


# Quads: (positions, uvs, indices), counter-clockwise seen from the side they face.
FLOOR = ([(-1, 0, 1), (1, 0, 1), (1, 0, -1), (-1, 0, -1)], [(0, 0), (1, 0), (1, 1), (0, 1)], [0, 1, 2, 0, 2, 3])
LAMP = ([(-0.25, 1.5, -0.25), (0.25, 1.5, -0.25), (0.25, 1.5, 0.25), (-0.25, 1.5, 0.25)], None, [0, 1, 2, 0, 2, 3])
PANE = ([(-0.5, 0, -0.5), (0.5, 0, -0.5), (0.5, 1, -0.5), (-0.5, 1, -0.5)], None, [0, 1, 2, 0, 2, 3])


def main():
    rows = [[COLOURS[(i + j) % 2] for i in range(4)] for j in range(4)]
    with open(os.path.join(HERE, "checker.png"), "wb") as f:
        f.write(png(4, 4, rows))

    buf = bytearray()
    views, accessors = [], []

    def add(data, fmt, count, kind, ctype, target, minmax=None):
        while len(buf) % 4:
            buf.append(0)
        off = len(buf)
        for v in data:
            buf.extend(struct.pack(fmt, *v) if isinstance(v, tuple) else struct.pack(fmt, v))
        views.append({"buffer": 0, "byteOffset": off, "byteLength": len(buf) - off, "target": target})
        acc = {"bufferView": len(views) - 1, "componentType": ctype, "count": count, "type": kind}
        if minmax:
            acc["min"], acc["max"] = minmax
        accessors.append(acc)
        return len(accessors) - 1

    def mesh(name, quad, material):
        pos, uv, idx = quad
        lo = [min(p[k] for p in pos) for k in range(3)]
        hi = [max(p[k] for p in pos) for k in range(3)]
        attrs = {"POSITION": add([tuple(map(float, p)) for p in pos], "<3f", 4, "VEC3", 5126, 34962, (lo, hi))}
        if uv:
            attrs["TEXCOORD_0"] = add([tuple(map(float, t)) for t in uv], "<2f", 4, "VEC2", 5126, 34962)
        ind = add(idx, "<H", 6, "SCALAR", 5123, 34963)
        return {"name": name, "primitives": [{"attributes": attrs, "indices": ind, "material": material}]}

    meshes = [mesh("floor", FLOOR, 0), mesh("lamp", LAMP, 1), mesh("pane", PANE, 2)]
    gltf = {
        "asset": {"version": "2.0", "generator": "testdata/gltf/make_textured.py"},
        "extensionsUsed": [
            "KHR_texture_transform",
            "KHR_materials_specular",
            "KHR_materials_emissive_strength",
            "KHR_materials_transmission",
            "KHR_materials_ior",
            "KHR_lights_punctual",
        ],
        "scene": 0,
        "scenes": [{"name": "Day", "nodes": [0, 1, 3, 4]}, {"name": "Night", "nodes": [5, 2, 6, 7]}],
        "nodes": [
            {"name": "floor", "mesh": 0},
            {"name": "lamp", "mesh": 1},
            {"name": "pane", "mesh": 2},
            # Overview: at (0, 2, 2.5) looking at the origin (rotation about +x by -atan(2/2.5)).
            {"name": "Overview", "camera": 0, "translation": [0, 2, 2.5], "rotation": rot_x(-0.674740942)},
            {"name": "Detail", "camera": 1, "translation": [0, 0.6, 1.2], "rotation": rot_x(-0.463647609)},
            {"name": "floor.night", "mesh": 0},
            {"name": "Detail.night", "camera": 1, "translation": [0, 0.6, 1.2], "rotation": rot_x(-0.463647609)},
            {"name": "bulb", "translation": [0, 1.2, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
        ],
        "cameras": [
            {"name": "wide", "type": "perspective", "perspective": {"yfov": 0.7, "aspectRatio": 1.0, "znear": 0.01}},
            {"name": "close", "type": "perspective", "perspective": {"yfov": 0.5, "aspectRatio": 1.5, "znear": 0.01}},
        ],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "color": [1, 1, 1], "intensity": 683}]}},
        "materials": [
            {
                "name": "tiles",
                "doubleSided": True,
                "pbrMetallicRoughness": {
                    "baseColorFactor": list(FACTOR) + [1.0],
                    "baseColorTexture": {
                        "index": 0,
                        "extensions": {"KHR_texture_transform": {"scale": list(SCALE), "offset": list(OFFSET)}},
                    },
                    "metallicFactor": 0.0,
                    "roughnessFactor": 1.0,
                },
                "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}},
            },
            {
                "name": "lamp",
                "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0},
                "emissiveFactor": list(RADIANCE_FACTOR),
                "extensions": {
                    "KHR_materials_emissive_strength": {"emissiveStrength": RADIANCE_STRENGTH},
                    "KHR_materials_specular": {"specularFactor": 0.0},
                },
            },
            {
                "name": "glass",
                "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0.0, "roughnessFactor": 0.0},
                "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": 1.5}},
            },
        ],
        "textures": [{"sampler": 0, "source": 0}],
        "samplers": [{"magFilter": 9728, "minFilter": 9728, "wrapS": 10497, "wrapT": 10497}],
        "images": [{"name": "checker", "uri": "checker.png"}],
        "meshes": meshes,
        "buffers": [{"byteLength": len(buf), "uri": "textured.bin"}],
        "bufferViews": views,
        "accessors": accessors,
    }
    with open(os.path.join(HERE, "textured.bin"), "wb") as f:
        f.write(bytes(buf))
    with open(os.path.join(HERE, "textured.gltf"), "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")
    write_xml()


def rot_x(angle):
    """The unit quaternion (x, y, z, w) of a rotation by `angle` radians about +x."""
    import math

    return [math.sin(angle / 2), 0.0, 0.0, math.cos(angle / 2)]


def write_obj(name, quad, flip_v):
    pos, uv, idx = quad
    with open(os.path.join(HERE, name), "w") as f:
        f.write("# written by make_textured.py\n")
        for p in pos:
            f.write("v %g %g %g\n" % p)
        if uv:
            for u, v in uv:
                f.write("vt %g %g\n" % (u, 1 - v if flip_v else v))
        for t in range(0, len(idx), 3):
            c = [i + 1 for i in idx[t : t + 3]]
            f.write("f " + " ".join(f"{i}/{i}" if uv else f"{i}" for i in c) + "\n")


def write_xml():
    write_obj("textured-floor.obj", FLOOR, True)
    write_obj("textured-lamp.obj", LAMP, False)
    radiance = ", ".join(repr(c * RADIANCE_STRENGTH) for c in RADIANCE_FACTOR)
    xml = f"""<?xml version="1.0"?>
<!-- Written by make_textured.py: scene "Day" of textured.gltf as Mitsuba 3 XML. -->
<scene version="3.0.0">
    <sensor type="perspective" id="Overview">
        <float name="fov" value="40.1070456"/>
        <string name="fov_axis" value="y"/>
        <transform name="to_world"><lookat origin="0, 2, 2.5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="512"/><integer name="height" value="512"/>
            <rfilter type="box"/></film>
    </sensor>
    <shape type="obj" id="floor">
        <string name="filename" value="textured-floor.obj"/>
        <bsdf type="twosided">
            <bsdf type="diffuse">
                <texture type="bitmap" name="reflectance">
                    <string name="filename" value="checker.png"/>
                    <string name="filter_type" value="nearest"/>
                    <transform name="to_uv">
                        <scale x="{SCALE[0]}" y="{SCALE[1]}"/>
                        <translate x="{OFFSET[0]}" y="{OFFSET[1]}"/>
                    </transform>
                </texture>
            </bsdf>
        </bsdf>
    </shape>
    <shape type="obj" id="lamp">
        <string name="filename" value="textured-lamp.obj"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>
        <emitter type="area"><rgb name="radiance" value="{radiance}"/></emitter>
    </shape>
</scene>
"""
    with open(os.path.join(HERE, "textured.xml"), "w") as f:
        f.write(xml)


if __name__ == "__main__":
    main()
