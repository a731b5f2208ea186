#!/usr/bin/env python3
"""mitsuba_load.py - benchmark the competitor's scene loading: Mitsuba 3's `mi.load_file`.

What it measures
    The wall time of `mi.load_file(SCENE.xml)` (XML parsing, mesh files read, shapes and
    plugins instantiated, and the acceleration structure built: Mitsuba builds it in the
    Scene's constructor, Embree for the pip wheels' CPU variants), called RUNS times in one
    process. The first call in a fresh process (`first_load_s`) is the figure comparable to
    one `opticks trace` run, which loads the scene once; later calls (`load_s`, the last one,
    and `loads_s`, all of them) may profit from warm caches (the OS page cache serves both
    programs alike after the first run; Dr.Jit's kernel cache matters to the LLVM variants).
    `import_s` is `import mitsuba` + `set_variant` (not part of either figure); `process_s`
    the process's wall time up to the JSON line (start-up included; compare `/usr/bin/time`
    of an `opticks trace --paths 1`).

    Issue 25's target: a >= 1 M-triangle scene (benches/make_big_scene.py) loads, BVH
    included, no slower in Opticks than in Mitsuba's `load_file`.

Output
    Human-readable lines on stderr; on stdout exactly one JSON line, e.g.
    {"scene": ".../big-scene/scene.xml", "variant": "llvm_ad_rgb", "first_load_s": 2.1,
     "load_s": 1.9, "loads_s": [2.1, 1.9], "import_s": 0.4, "process_s": 4.6,
     "cpu_s": 3.9, "threads": 2, "load_avg_1min": 0.5, "shapes": 11, "triangles": 2500250}
    cpu_s is the process CPU time (all threads) of the first load.

Install: see benches/README.md (a venv with mitsuba; the llvm_* variants need a libLLVM, found
as mitsuba_ptracer.py finds it; --variant scalar_rgb needs none).

Run (from the repo root)
    python3 benches/make_big_scene.py --out /work/bench/big-scene
    /work/venv-mitsuba/bin/python benches/mitsuba_load.py /work/bench/big-scene/scene.xml
    ... --variant scalar_rgb --runs 3 --threads 2
"""
import argparse
import json
import os
import sys
import time

T0 = time.perf_counter()
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mitsuba_ptracer import log, start_mitsuba  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('scene', help='Mitsuba scene.xml (e.g. /work/bench/big-scene/scene.xml)')
    ap.add_argument('--variant', default='llvm_ad_rgb',
                    help='Mitsuba variant (default %(default)s; falls back to scalar_rgb)')
    ap.add_argument('--runs', type=int, default=2,
                    help='load_file calls in this process (default 2)')
    ap.add_argument('--threads', type=int, default=None,
                    help='worker threads (default: Dr.Jit default = all cores)')
    args = ap.parse_args()
    scene_path = os.path.abspath(args.scene)

    t = time.perf_counter()
    mi, dr, variant, llvm = start_mitsuba(args.variant)
    if args.threads:
        dr.set_thread_count(args.threads)
    import_s = time.perf_counter() - t
    log(f'mitsuba {mi.__version__}, variant {variant}'
        + (f' (DRJIT_LIBLLVM_PATH={llvm})' if llvm else '') + f', import {import_s:.2f} s')

    loads, cpu = [], None
    scene = None
    for k in range(args.runs):
        del scene
        scene = None
        c0, t0 = time.process_time(), time.perf_counter()
        scene = mi.load_file(scene_path)
        dt = time.perf_counter() - t0
        if cpu is None:
            cpu = time.process_time() - c0
        loads.append(dt)
        log(f'load_file #{k + 1}: {dt:.3f} s')
    shapes = scene.shapes()
    triangles = sum(int(s.face_count()) for s in shapes if hasattr(s, 'face_count'))
    print(json.dumps({
        'scene': scene_path, 'variant': variant, 'mitsuba': mi.__version__,
        'first_load_s': round(loads[0], 4), 'load_s': round(loads[-1], 4),
        'loads_s': [round(x, 4) for x in loads], 'import_s': round(import_s, 4),
        'process_s': round(time.perf_counter() - T0, 4), 'cpu_s': round(cpu, 4),
        'threads': args.threads or dr.thread_count(), 'load_avg_1min': os.getloadavg()[0],
        'shapes': len(shapes), 'triangles': triangles,
    }), flush=True)


if __name__ == '__main__':
    main()
