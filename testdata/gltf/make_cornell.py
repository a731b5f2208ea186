#!/usr/bin/env python3
"""Writes cornell.gltf + cornell.bin: the Cornell box of ../scenes/cornell as glTF 2.0.

Python 3 standard library only. Run from anywhere:  python3 testdata/gltf/make_cornell.py

What it contains, and why (the loader is crates/io/src/scene_formats/gltf/):
* Geometry: the four meshes of ../scenes/cornell/meshes/*.obj (36 triangles). `white`, `red`
  and `light` are indexed (u16), `green` is non-indexed, to exercise both paths.
* The light's vertices are stored relative to its node, which is translated by LIGHT_OFFSET,
  and everything hangs below a root node `cornell`, so node transforms are exercised too.
* Materials: metallic 0, roughness 1, KHR_materials_specular specularFactor 0 (no specular
  layer: a pure Lambertian of albedo baseColor), doubleSided (Mitsuba's twosided).
* The light: base colour = white's albedo, emissiveFactor x KHR_materials_emissive_strength =
  radiance (18.387, 13.9873, 6.75357) W/(m^2 sr): strength 32 (a power of two), so the product
  computed in f32 is exactly f32(radiance) (checked below).
* Camera: perspective, yfov = 39.3077 deg (square image, so also the horizontal fov),
  aspectRatio 1, node at (0, 0, 3.9) looking down its -Z, i.e. at the origin, +Y up.
"""

import base64  # noqa: F401  (kept for users who want an embedded variant: see EMBED)
import json
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
MESHES = os.path.join(HERE, "..", "scenes", "cornell", "meshes")
EMBED = False  # True: put the buffer in a data: URI instead of cornell.bin

ALBEDO = {
    "white": (0.885809, 0.698859, 0.666422),
    "red": (0.570068, 0.0430135, 0.0443706),
    "green": (0.105421, 0.37798, 0.076425),
}
RADIANCE = ("18.387", "13.9873", "6.75357")
LIGHT_OFFSET = (0.0, 0.99, 0.01)
FOV_DEG = 39.3077


def f32(x):
    return struct.unpack("<f", struct.pack("<f", float(x)))[0]


def read_obj(path):
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == "v":
                verts.append(tuple(float(x) for x in t[1:4]))
            elif t[0] == "f":
                faces.append(tuple(int(x.split("/")[0]) - 1 for x in t[1:]))
    return verts, faces


def emissive_factor_and_strength():
    """(factor, strength) with f32(factor) x f32(strength) == f32(L) exactly in every channel.

    The strength is a power of two above every channel, so each factor f32(L)/strength is an
    exact f32 in [0, 1] and the product is exact too.
    """
    strength = 32.0
    assert strength >= max(float(x) for x in RADIANCE)
    factor = [f32(x) / strength for x in RADIANCE]
    for x, c in zip(RADIANCE, factor):
        assert f32(c) == c and f32(f32(c) * strength) == f32(x)
    return factor, strength


def main():
    bin_data = bytearray()
    accessors, views, meshes, nodes, materials = [], [], [], [], []

    def add_view(data, target):
        while len(bin_data) % 4:
            bin_data.append(0)
        views.append({"buffer": 0, "byteOffset": len(bin_data), "byteLength": len(data), "target": target})
        bin_data.extend(data)
        return len(views) - 1

    def add_positions(points):
        data = b"".join(struct.pack("<3f", *p) for p in points)
        v = add_view(data, 34962)
        lo = [min(f32(p[k]) for p in points) for k in range(3)]
        hi = [max(f32(p[k]) for p in points) for k in range(3)]
        accessors.append({"bufferView": v, "componentType": 5126, "count": len(points), "type": "VEC3",
                          "min": lo, "max": hi})
        return len(accessors) - 1

    def add_indices(tris):
        flat = [i for t in tris for i in t]
        v = add_view(struct.pack("<%dH" % len(flat), *flat), 34963)
        accessors.append({"bufferView": v, "componentType": 5123, "count": len(flat), "type": "SCALAR"})
        return len(accessors) - 1

    def add_material(name, albedo, emissive=None):
        m = {
            "name": name,
            "pbrMetallicRoughness": {"baseColorFactor": list(albedo) + [1.0], "metallicFactor": 0.0,
                                     "roughnessFactor": 1.0},
            "doubleSided": True,
            "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}},
        }
        if emissive:
            factor, strength = emissive
            m["emissiveFactor"] = factor
            m["extensions"]["KHR_materials_emissive_strength"] = {"emissiveStrength": strength}
        materials.append(m)
        return len(materials) - 1

    mat = {k: add_material(k, v) for k, v in ALBEDO.items()}
    mat["light"] = add_material("light", ALBEDO["white"], emissive_factor_and_strength())

    children = []
    for name in ["white", "red", "green", "light"]:
        verts, faces = read_obj(os.path.join(MESHES, name + ".obj"))
        tris = [(f[0], f[k], f[k + 1]) for f in faces for k in range(1, len(f) - 1)]
        node = {"name": name, "mesh": len(meshes)}
        if name == "light":
            verts = [tuple(p[k] - LIGHT_OFFSET[k] for k in range(3)) for p in verts]
            node["translation"] = list(LIGHT_OFFSET)
        if name == "green":  # non-indexed
            prim = {"attributes": {"POSITION": add_positions([verts[i] for t in tris for i in t])}}
        else:
            prim = {"attributes": {"POSITION": add_positions(verts)}, "indices": add_indices(tris)}
        prim["material"] = mat[name]
        meshes.append({"name": name, "primitives": [prim]})
        nodes.append(node)
        children.append(len(nodes) - 1)
    nodes.append({"name": "cornell", "children": children})
    nodes.append({"name": "camera", "camera": 0, "translation": [0.0, 0.0, 3.9]})

    uri = ("data:application/octet-stream;base64," + base64.b64encode(bytes(bin_data)).decode()) if EMBED \
        else "cornell.bin"
    doc = {
        "asset": {"version": "2.0", "generator": "testdata/gltf/make_cornell.py"},
        "extensionsUsed": ["KHR_materials_specular", "KHR_materials_emissive_strength"],
        "scene": 0,
        "scenes": [{"name": "cornell", "nodes": [len(nodes) - 2, len(nodes) - 1]}],
        "nodes": nodes,
        "cameras": [{"type": "perspective", "name": "camera", "perspective": {
            "yfov": math.radians(FOV_DEG), "aspectRatio": 1.0, "znear": 0.001, "zfar": 100.0}}],
        "meshes": meshes,
        "materials": materials,
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(bin_data), "uri": uri}],
    }
    with open(os.path.join(HERE, "cornell.gltf"), "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    if not EMBED:
        with open(os.path.join(HERE, "cornell.bin"), "wb") as f:
            f.write(bin_data)
    print("wrote cornell.gltf (%d triangles, %d buffer bytes)" % (
        sum(a["count"] for a in accessors if a["type"] == "SCALAR") // 3 + 2, len(bin_data)))


if __name__ == "__main__":
    main()
