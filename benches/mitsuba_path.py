#!/usr/bin/env python3
"""mitsuba_path.py - benchmark the competitor's path tracer: Mitsuba 3's `path` on a reference scene.

What it measures
    Mitsuba 3 renders SCENE.xml with its `path` integrator (camera paths with next-event
    estimation and MIS; max_depth -1 = unbounded, Russian roulette from depth 5 by Mitsuba's
    default, rr_depth 5; the scene's own pixel filter, `box` in this repository's scenes) at
    SPP camera paths per pixel. Like mitsuba_ptracer.py, the render runs twice in one process;
    the first run absorbs JIT compilation and kernel-cache loading, the second run's wall time is
    reported (render + evaluation of the image, not scene loading). The second image is compared
    with the scene's reference (reference.exr next to scene.xml; for a variant scene-X.xml,
    reference-X.exr) with the project's metric, computed exactly like tools/imgcmp.py: relMSE =
    mean over pixels and channels of (t - r)^2 / (r^2 + 1e-2), and the per-channel mean ratio
    test / reference. Its efficiency is 1 / (relMSE x time_s), the figure issue 11 compares
    estimators with (higher is better; it does not depend on the spp for an unbiased estimator
    whose relMSE falls as 1/spp, apart from noise and the reference's own noise).

Output
    Human-readable lines on stderr; on stdout exactly one JSON line, e.g.
    {"scene": ".../cornell/scene.xml", "integrator": "path", "spp": 64, "camera_paths": 4194304,
     "time_s": 1.3, "first_run_s": 2.1, "cpu_s": 2.5, "load_avg_1min": 0.5, "relmse": 0.005,
     "mean_ratio": [..], "efficiency": 154.0, "efficiency_cpu": 160.0, ...}
    time_s is wall time; cpu_s the process CPU time of the same run (all threads).
    efficiency_cpu = 1 / (relMSE x cpu_s / threads) uses CPU time / threads, an estimate of the
    uncontended wall time on a shared machine (a lower bound on it: it assumes perfect use of
    every thread). load_avg_1min tells whether other jobs were running.

Install: see mitsuba_ptracer.py / benches/README.md (a venv with mitsuba and numpy, libLLVM).

Run (from the repo root)
    /work/venv-mitsuba/bin/python benches/mitsuba_path.py                          # cornell, 64 spp
    /work/venv-mitsuba/bin/python benches/mitsuba_path.py testdata/mitsuba/mirror-glass/scene.xml --spp 256
    ... --seed 3 --threads 2 --runs 2 --max-depth -1 --out /tmp/mitsuba_path.exr --reference R.exr
"""
import argparse
import json
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mitsuba_ptracer import DEFAULT_SCENE, log, read_rgb, relmse, start_mitsuba  # noqa: E402


def default_reference(scene_path):
    """reference.exr next to scene.xml; reference-X.exr next to a variant scene-X.xml."""
    folder, stem = os.path.split(os.path.splitext(scene_path)[0])
    suffix = stem[len('scene'):] if stem.startswith('scene') else '-' + stem
    return os.path.join(folder, 'reference' + suffix + '.exr')


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('scene', nargs='?', default=DEFAULT_SCENE, help='Mitsuba scene.xml '
                    '(default: testdata/scenes/cornell/scene.xml)')
    ap.add_argument('--spp', type=int, default=64, help='camera paths per pixel (default 64)')
    ap.add_argument('--max-depth', type=int, default=-1, help='default -1 (unbounded)')
    ap.add_argument('--variant', default='llvm_ad_rgb',
                    help='Mitsuba variant (default %(default)s; falls back to scalar_rgb)')
    ap.add_argument('--reference', default=None,
                    help='reference image (default: reference.exr, or reference-X.exr for '
                    'scene-X.xml, next to the scene)')
    ap.add_argument('--seed', type=int, default=0, help='seed of the measured (last) run')
    ap.add_argument('--threads', type=int, default=None,
                    help='worker threads (default: Dr.Jit default = all cores)')
    ap.add_argument('--runs', type=int, default=2,
                    help='renders in this process; the last one is reported (default 2)')
    ap.add_argument('--out', default=None, help='also write the measured image (.exr)')
    args = ap.parse_args()

    scene_path = os.path.abspath(args.scene)
    ref_path = args.reference or default_reference(scene_path)

    import numpy as np
    mi, dr, variant, llvm = start_mitsuba(args.variant)
    # Read the reference before changing Dr.Jit's thread count: with --threads 1, Mitsuba 3.9.1's
    # EXR reader (OpenEXR's thread pool) was seen to wait forever when called after it.
    ref = read_rgb(mi, ref_path) if os.path.exists(ref_path) else None
    if args.threads:
        try:
            dr.set_thread_count(args.threads)
        except AttributeError:
            log('WARNING: this Dr.Jit has no set_thread_count; using the default')
    threads = args.threads or os.cpu_count()
    log(f'mitsuba {mi.__version__}, drjit {dr.__version__}, variant {variant}'
        + (f', libLLVM {os.environ.get("DRJIT_LIBLLVM_PATH")}' if variant.startswith('llvm') else ''))

    scene = mi.load_file(scene_path)
    film = scene.sensors()[0].film()
    width, height = (int(v) for v in film.crop_size())
    paths = args.spp * width * height
    integrator = mi.load_dict({'type': 'path', 'max_depth': args.max_depth})

    times, cpu = [], []
    img = None
    for run in range(args.runs):
        seed = args.seed if run == args.runs - 1 else args.seed + 1000 + run
        t0, c0 = time.perf_counter(), time.process_time()
        img = mi.render(scene, integrator=integrator, spp=args.spp, seed=seed)
        img = np.array(img, dtype=np.float64)  # forces evaluation of the (lazy) JIT image
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
        log(f'run {run + 1}/{args.runs}: {times[-1]:.3f} s wall, {cpu[-1]:.3f} s CPU '
            f'({paths / times[-1] / 1e6:.3f} M camera paths/s)')
    img = img[..., :3]

    if args.out:
        mi.Bitmap(np.ascontiguousarray(img, dtype=np.float32),
                  pixel_format=mi.Bitmap.PixelFormat.RGB).write(args.out)
        log(f'wrote {args.out}')

    result = dict(scene=scene_path, variant=variant, integrator='path', max_depth=args.max_depth,
                  width=width, height=height, spp=args.spp, camera_paths=paths, seed=args.seed,
                  time_s=round(times[-1], 4), first_run_s=round(times[0], 4),
                  cpu_s=round(cpu[-1], 4), load_avg_1min=round(os.getloadavg()[0], 2),
                  paths_per_s=round(paths / times[-1], 1), threads=threads,
                  mitsuba=mi.__version__, libllvm=llvm if variant.startswith('llvm') else None)
    if ref is not None:
        if ref.shape != img.shape:
            log(f'WARNING: reference {ref_path} is {ref.shape[1]}x{ref.shape[0]}, '
                f'image is {width}x{height}: not compared')
        else:
            mt, mr = img.reshape(-1, 3).mean(0), ref.reshape(-1, 3).mean(0)
            with np.errstate(divide='ignore', invalid='ignore'):
                ratio = mt / mr
            e = relmse(img, ref)
            result.update(reference=ref_path, relmse=e,
                          mean_test=[float(x) for x in mt], mean_ref=[float(x) for x in mr],
                          mean_ratio=[float(x) for x in ratio],
                          efficiency=1.0 / (e * times[-1]) if e > 0 else None,
                          efficiency_cpu=1.0 / (e * cpu[-1] / threads) if e > 0 and cpu[-1] > 0 else None,
                          nonfinite=int(np.count_nonzero(~np.isfinite(img))))
            log('relMSE vs reference = %.4g, mean ratio R,G,B = %.5f %.5f %.5f, efficiency %.4g /s'
                % ((e,) + tuple(ratio) + (result['efficiency'] or 0,)))
    else:
        log(f'WARNING: no reference at {ref_path}: relMSE not computed')
    print(json.dumps(result), flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
