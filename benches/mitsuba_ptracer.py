#!/usr/bin/env python3
"""mitsuba_ptracer.py - benchmark the competitor: Mitsuba 3's light tracer on a reference scene.

What it measures
    Mitsuba 3 (the independent renderer Opticks is compared to) renders SCENE.xml with its
    `ptracer` integrator (light paths: every path vertex is connected to the camera and splatted
    into the pixel it projects to; max_depth -1 = unbounded, Russian roulette from depth 5 by
    Mitsuba's default; the pixel filter is the scene's own, `box` in testdata/scenes) using
    PATHS light paths in total (Mitsuba counts them as spp x width x height, so PATHS is rounded
    up to a multiple of width x height). The render runs twice in one process; the first run
    absorbs JIT compilation and kernel-cache loading, the second run's wall time is reported
    (render + evaluation of the image, not scene loading). The second image is compared with the
    scene's reference.exr (next to scene.xml) using the project's metric, computed exactly like
    tools/imgcmp.py: relMSE = mean over pixels and channels of (t - r)^2 / (r^2 + 1e-2), and the
    per-channel mean ratio test / reference.

Output
    Human-readable lines on stderr; on stdout exactly one JSON line, e.g.
    {"scene": ".../cornell/scene.xml", "variant": "llvm_ad_rgb", "integrator": "ptracer",
     "width": 256, "height": 256, "spp": 64, "light_paths": 4194304, "time_s": 2.2,
     "first_run_s": 2.9, "cpu_s": 4.3, "load_avg_1min": 0.5, "paths_per_s": 1.9e6, "relmse": 0.004, "mean_test": [..],
     "mean_ref": [..], "mean_ratio": [..], "threads": 2, "mitsuba": "3.9.1", ...}
    time_s is wall time; cpu_s the process CPU time of the same run (all threads): on a shared
    machine cpu_s / threads estimates the uncontended wall time, and load_avg_1min tells whether
    other jobs were running. The JSON goes to stdout,
    so that another script can run `... | tail -n 1 | python -c 'import json,sys; ...'`.

Install (a venv outside the repo; the llvm_* variants need a shared libLLVM)
    python3 -m venv /work/venv-mitsuba
    /work/venv-mitsuba/bin/pip install mitsuba numpy
    apt-get update && apt-get install -y libllvm19          # or whichever libllvmNN apt offers
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
(If DRJIT_LIBLLVM_PATH is unset, the script looks for a libLLVM in the usual Debian/Ubuntu places
and sets it. Without any libLLVM it falls back to the much slower `scalar_rgb`, with a warning.)

Run (from the repo root)
    /work/venv-mitsuba/bin/python benches/mitsuba_ptracer.py                       # cornell
    /work/venv-mitsuba/bin/python benches/mitsuba_ptracer.py testdata/scenes/furnace/scene.xml
    ... --paths 16777216 --seed 3 --threads 2 --out /tmp/mitsuba_cornell.exr
"""
import argparse
import glob
import json
import os
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_SCENE = os.path.join(REPO, 'testdata', 'scenes', 'cornell', 'scene.xml')
DEFAULT_PATHS = 64 * 256 * 256  # 4,194,304 = 64 spp on the 256 x 256 cornell film
EPS = 1e-2  # as in imgcmp.py


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def find_libllvm():
    """Sets DRJIT_LIBLLVM_PATH (before drjit is imported) if unset and a libLLVM is found."""
    if os.environ.get('DRJIT_LIBLLVM_PATH'):
        return os.environ['DRJIT_LIBLLVM_PATH']
    pats = ['/usr/lib/x86_64-linux-gnu/libLLVM-*.so', '/usr/lib/x86_64-linux-gnu/libLLVM.so*',
            '/usr/lib/aarch64-linux-gnu/libLLVM-*.so', '/usr/lib/llvm-*/lib/libLLVM*.so*',
            '/usr/lib64/libLLVM*.so*', '/opt/homebrew/opt/llvm/lib/libLLVM.dylib']
    found = sorted({p for pat in pats for p in glob.glob(pat)})

    def version(p):  # newest first: libLLVM-19.so > libLLVM-15.so
        digits = ''.join(ch if ch.isdigit() else ' ' for ch in os.path.basename(p)).split()
        return int(digits[0]) if digits else 0
    found.sort(key=version, reverse=True)
    if found:
        os.environ['DRJIT_LIBLLVM_PATH'] = found[0]
        return found[0]
    return None


def start_mitsuba(variant):
    """Imports Dr.Jit and Mitsuba and sets `variant`, initialising the LLVM backend now (so that
    its start-up is not timed later); falls back to `scalar_rgb` with a warning where the
    variant cannot start (no libLLVM). Returns (mi, dr, the variant set, the libLLVM path)."""
    llvm = find_libllvm() if variant.startswith('llvm') else None
    import drjit as dr
    import mitsuba as mi
    try:
        mi.set_variant(variant)
        if variant.startswith('llvm'):
            dr.zeros(mi.Float, 1).numpy()  # forces the LLVM backend to initialise now
    except Exception as e:  # no libLLVM, or the variant is not compiled in
        log(f'WARNING: variant {variant} unavailable ({e}); falling back to scalar_rgb '
            f'(much slower; install libLLVM and set DRJIT_LIBLLVM_PATH)')
        variant = 'scalar_rgb'
        mi.set_variant(variant)
    return mi, dr, variant, llvm


def relmse(test, ref):
    """imgcmp.py's metric: mean over pixels and channels of (t - r)^2 / (r^2 + 1e-2)."""
    import numpy as np
    return float(np.mean((test - ref) ** 2 / (ref ** 2 + EPS)))


def read_rgb(mi, path):
    """An image file as an HxWx3 float64 array (first three channels, like imgcmp.py)."""
    import numpy as np
    bmp = mi.Bitmap(path)
    if bmp.pixel_format() not in (mi.Bitmap.PixelFormat.RGB, mi.Bitmap.PixelFormat.RGBA):
        bmp = bmp.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False)
    a = np.array(bmp, dtype=np.float64)
    if a.ndim == 2:
        a = a[..., None]
    a = a[..., :3]
    if a.shape[2] == 1:
        a = np.repeat(a, 3, axis=2)
    return a


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('scene', nargs='?', default=DEFAULT_SCENE, help='Mitsuba scene.xml '
                    '(default: testdata/scenes/cornell/scene.xml)')
    ap.add_argument('--paths', type=int, default=DEFAULT_PATHS,
                    help='total number of light paths (default %(default)d = 64 x 256^2)')
    ap.add_argument('--variant', default='llvm_ad_rgb',
                    help='Mitsuba variant (default %(default)s; falls back to scalar_rgb)')
    ap.add_argument('--reference', default=None,
                    help='reference image (default: reference.exr next to the scene)')
    ap.add_argument('--seed', type=int, default=0, help='seed of the measured (second) run')
    ap.add_argument('--threads', type=int, default=None,
                    help='worker threads (default: Dr.Jit default = all cores)')
    ap.add_argument('--runs', type=int, default=2,
                    help='renders in this process; the last one is reported (default 2)')
    ap.add_argument('--out', default=None, help='also write the measured image (.exr)')
    args = ap.parse_args()

    scene_path = os.path.abspath(args.scene)
    ref_path = args.reference or os.path.join(os.path.dirname(scene_path), 'reference.exr')

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
    log(f'mitsuba {mi.__version__}, drjit {dr.__version__}, variant {variant}'
        + (f', libLLVM {os.environ.get("DRJIT_LIBLLVM_PATH")}' if variant.startswith('llvm') else ''))

    scene = mi.load_file(scene_path)
    film = scene.sensors()[0].film()
    width, height = (int(v) for v in film.crop_size())
    spp = max(1, -(-args.paths // (width * height)))
    paths = spp * width * height
    if paths != args.paths:
        log(f'note: {args.paths} paths rounded up to {spp} x {width} x {height} = {paths}')
    integrator = mi.load_dict({'type': 'ptracer', 'max_depth': -1})

    times, cpu = [], []
    img = None
    for run in range(args.runs):
        seed = args.seed if run == args.runs - 1 else args.seed + 1000 + run
        t0, c0 = time.perf_counter(), time.process_time()
        img = mi.render(scene, integrator=integrator, spp=spp, seed=seed)
        img = np.array(img, dtype=np.float64)  # forces evaluation of the (lazy) JIT image
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
        log(f'run {run + 1}/{args.runs}: {times[-1]:.3f} s wall, {cpu[-1]:.3f} s CPU '
            f'({paths / times[-1] / 1e6:.3f} M paths/s)')
    img = img[..., :3]

    if args.out:
        mi.Bitmap(np.ascontiguousarray(img, dtype=np.float32),
                  pixel_format=mi.Bitmap.PixelFormat.RGB).write(args.out)
        log(f'wrote {args.out}')

    result = dict(scene=scene_path, variant=variant, integrator='ptracer', max_depth=-1,
                  width=width, height=height, spp=spp, light_paths=paths, seed=args.seed,
                  time_s=round(times[-1], 4), first_run_s=round(times[0], 4),
                  cpu_s=round(cpu[-1], 4), load_avg_1min=round(os.getloadavg()[0], 2),
                  paths_per_s=round(paths / times[-1], 1),
                  threads=args.threads or os.cpu_count(), mitsuba=mi.__version__,
                  libllvm=llvm if variant.startswith('llvm') else None)
    if ref is not None:
        if ref.shape != img.shape:
            log(f'WARNING: reference {ref_path} is {ref.shape[1]}x{ref.shape[0]}, '
                f'image is {width}x{height}: not compared')
        else:
            mt, mr = img.reshape(-1, 3).mean(0), ref.reshape(-1, 3).mean(0)
            with np.errstate(divide='ignore', invalid='ignore'):
                ratio = mt / mr
            result.update(reference=ref_path, relmse=relmse(img, ref),
                          mean_test=[float(x) for x in mt], mean_ref=[float(x) for x in mr],
                          mean_ratio=[float(x) for x in ratio],
                          nonfinite=int(np.count_nonzero(~np.isfinite(img))))
            log('relMSE vs reference = %.4g, mean ratio R,G,B = %.5f %.5f %.5f'
                % ((result['relmse'],) + tuple(ratio)))
    else:
        log(f'WARNING: no reference at {ref_path}: relMSE not computed')
    print(json.dumps(result), flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
