"""Mitsuba 3 reference for the illuminance meter in the air (crates/cli/tests/it/meter.rs).

The furnace room of testdata/scenes/furnace (closed unit cube, twosided grey diffuse of
albedo 0.5 everywhere, a 0.2 x 0.2 m area light of radiance 10 flush with the ceiling),
rendered with two meters in the air at y = 0.5, each 4 x 4 cells over x, z in [0.1, 0.9]:

* "up":   cells facing +y (toward the light: direct + indirect light),
          Opticks plane origin (0.1,0.5,0.1), u = (0,0,0.8), v = (0.8,0,0)  (u x v = +y);
* "down": cells facing -y (toward the floor: indirect light only),
          Opticks plane origin (0.1,0.5,0.1), u = (0.8,0,0), v = (0,0,0.8)  (u x v = -y).

Cell (i, j) is i along u and j along v, as `opticks measure` numbers them. Every cell is its
own Mitsuba `irradiancemeter` on a `rectangle` with a `null` BSDF, so the meters neither
block nor reflect light; `volpath` (max_depth -1) passes rays and shadow rays through null
surfaces. Each cell is rendered in PASSES independent passes (seeds 1000 + pass); the value is
their mean and the standard error their spread / sqrt(PASSES).

Run (from the repository root):
  DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so \
      /work/venv-mitsuba/bin/python testdata/mitsuba/meter-furnace/make_reference.py
writes testdata/mitsuba/meter-furnace/reference.json.
"""
import json
import os
import sys
import time

import mitsuba as mi

mi.set_variant("llvm_ad_rgb")

HERE = os.path.dirname(os.path.abspath(__file__))
MESHES = os.path.join(HERE, "..", "..", "scenes", "furnace", "meshes")
SPP = int(sys.argv[1]) if len(sys.argv) > 1 else 1 << 20
PASSES = int(sys.argv[2]) if len(sys.argv) > 2 else 8
N = 4

GRIDS = {
    # name: (origin, u, v); normal = u x v
    "up": ([0.1, 0.5, 0.1], [0.0, 0.0, 0.8], [0.8, 0.0, 0.0]),
    "down": ([0.1, 0.5, 0.1], [0.8, 0.0, 0.0], [0.0, 0.0, 0.8]),
}


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def cell_shape(origin, u, v, i, j):
    """A rectangle covering cell (i, j), normal u x v, with an irradiance meter."""
    c = [origin[k] + (i + 0.5) / N * u[k] + (j + 0.5) / N * v[k] for k in range(3)]
    hu = [x / (2 * N) for x in u]  # half edges: the rectangle spans [-1, 1]^2 locally
    hv = [x / (2 * N) for x in v]
    n = cross(u, v)
    ln = sum(x * x for x in n) ** 0.5
    n = [x / ln for x in n]
    m = [[hu[r], hv[r], n[r], c[r]] for r in range(3)] + [[0.0, 0.0, 0.0, 1.0]]
    return {
        "type": "rectangle",
        "to_world": mi.ScalarTransform4f(m),
        "bsdf": {"type": "null"},
        "sensor": {
            "type": "irradiancemeter",
            "film": {"type": "hdrfilm", "width": 1, "height": 1, "rfilter": {"type": "box"},
                     "pixel_format": "rgb"},
            "sampler": {"type": "independent", "sample_count": SPP},
        },
    }


def scene(cell):
    """The furnace room with one meter cell (each cell is its own scene: Mitsuba attaches a
    sensor to one shape only, and one null cell per scene keeps them independent anyway)."""
    grey = {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": 0.5}}}
    return mi.load_dict({
        "type": "scene",
        "integrator": {"type": "volpath", "max_depth": -1},
        "room": {"type": "obj", "filename": os.path.join(MESHES, "room.obj"), "face_normals": True,
                 "bsdf": grey},
        "light": {"type": "obj", "filename": os.path.join(MESHES, "light.obj"), "face_normals": True,
                  "bsdf": grey,
                  "emitter": {"type": "area", "radiance": {"type": "rgb", "value": 10.0}}},
        "meter": cell,
    })


def main():
    t0 = time.time()
    cells = []
    for name, (o, u, v) in GRIDS.items():
        for j in range(N):
            for i in range(N):
                sc = scene(cell_shape(o, u, v, i, j))
                runs = []
                for p in range(PASSES):
                    img = mi.render(sc, spp=SPP, seed=1000 + p)
                    runs.append(float(mi.TensorXf(img).numpy().reshape(-1)[0]))  # grey: R = G = B
                mean = sum(runs) / PASSES
                var = sum((r - mean) ** 2 for r in runs) / (PASSES - 1)
                cells.append({"grid": name, "i": i, "j": j, "E": mean, "se": (var / PASSES) ** 0.5})
                print(name, i, j, mean, (var / PASSES) ** 0.5, flush=True)
    out = {
        "what": "irradiance (W/m^2, R = G = B) per meter cell in the furnace room; see make_reference.py",
        "mitsuba": mi.__version__,
        "variant": "llvm_ad_rgb",
        "integrator": "volpath, max_depth -1",
        "spp_per_pass": SPP,
        "passes": PASSES,
        "seeds": [1000 + p for p in range(PASSES)],
        "seconds": round(time.time() - t0, 1),
        "grids": {k: {"origin": o, "u": u, "v": v, "cells": [N, N]} for k, (o, u, v) in GRIDS.items()},
        "cells": cells,
    }
    with open(os.path.join(HERE, "reference.json"), "w") as f:
        json.dump(out, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
