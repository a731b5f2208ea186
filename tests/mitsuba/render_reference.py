#!/usr/bin/env python3
"""render_reference.py - Mitsuba 3 particle-tracer references for the caustic showcase scenes.

For each scene NAME (default: caustics ring) this script
  1. copies scenes/NAME/scene.xml and scenes/NAME/meshes/ to testdata/mitsuba/NAME/ (the test
     inputs live in testdata, so editing a showcase does not silently break the test); a scene
     with no scenes/NAME (e.g. `rough`, a test-only scene) is rendered from testdata in place;
  2. renders testdata/mitsuba/NAME/scene.xml with Mitsuba's `ptracer` (max_depth -1, the scene's
     box filter) in PASSES passes of SPP samples (light paths per pixel) each, with seeds
     0..PASSES-1, in one process (the first, JIT-compiling pass is rendered once more to time the
     passes fairly: the time reported excludes it);
  3. writes the mean of all passes to reference.exr (linear RGB float32) and an exposure-scaled
     sRGB reference.png for eyes;
  4. estimates the reference's own noise: relMSE(half A, half B) between the mean of the even
     and of the odd passes; each half has twice the variance of the full mean and the
     difference of two halves has the sum of their variances, so relMSE(reference) is about
     relMSE(halves) / 4 (the same estimate as testdata/scenes/*/reference_stats.json);
  5. renders the competitor figure: Mitsuba's ptracer at COMPETITOR_SPP (the path count the
     test gives Opticks) with seeds 1000001 and 1000002, and records its relMSE and per-channel
     mean ratio against the reference;
  6. writes reference_stats.json.
relMSE is imgcmp.py's: mean over pixels and channels of (t - r)^2 / (r^2 + 1e-2).

Run from the repository root (a few minutes per scene on 2 cores):
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
    /work/venv-mitsuba/bin/python tests/mitsuba/render_reference.py [NAME ...] \
        [--passes 16] [--spp 512] [--competitor-spp 64] [--threads 2]
"""
import argparse
import json
import os
import shutil
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EPS = 1e-2


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def relmse(t, r):
    import numpy as np
    return float(np.mean((t - r) ** 2 / (r ** 2 + EPS)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('names', nargs='*', default=['caustics', 'ring'])
    ap.add_argument('--passes', type=int, default=16)
    ap.add_argument('--spp', type=int, default=512, help='light paths per pixel per pass')
    ap.add_argument('--competitor-spp', type=int, default=64)
    ap.add_argument('--threads', type=int, default=None)
    ap.add_argument('--exposure', type=float, default=1.0, help='for reference.png only')
    args = ap.parse_args()
    if not os.environ.get('DRJIT_LIBLLVM_PATH'):
        os.environ['DRJIT_LIBLLVM_PATH'] = '/usr/lib/x86_64-linux-gnu/libLLVM-19.so'
    import numpy as np
    import drjit as dr
    import mitsuba as mi
    mi.set_variant('llvm_ad_rgb')
    if args.threads:
        dr.set_thread_count(args.threads)
    integrator = mi.load_dict({'type': 'ptracer', 'max_depth': -1})

    for name in args.names:
        src, dst = os.path.join(REPO, 'scenes', name), os.path.join(REPO, 'testdata', 'mitsuba', name)
        if os.path.isdir(src):  # a showcase: test a copy; else a test-only scene, in place
            os.makedirs(dst, exist_ok=True)
            shutil.copy(os.path.join(src, 'scene.xml'), dst)
            shutil.rmtree(os.path.join(dst, 'meshes'), ignore_errors=True)
            shutil.copytree(os.path.join(src, 'meshes'), os.path.join(dst, 'meshes'))
        scene = mi.load_file(os.path.join(dst, 'scene.xml'))
        w, h = (int(v) for v in scene.sensors()[0].film().crop_size())

        def render(spp, seed):
            return np.array(mi.render(scene, integrator=integrator, spp=spp, seed=seed),
                            dtype=np.float64)[..., :3]

        render(args.spp, 999_999)  # JIT warm-up, not timed, not used
        passes, t0 = [], time.perf_counter()
        for p in range(args.passes):
            passes.append(render(args.spp, p))
            log(f'{name}: pass {p + 1}/{args.passes}, {time.perf_counter() - t0:.1f} s')
        elapsed = time.perf_counter() - t0
        ref = np.mean(passes, axis=0)
        half_a, half_b = np.mean(passes[0::2], axis=0), np.mean(passes[1::2], axis=0)
        halves = relmse(half_a, half_b)
        mi.Bitmap(np.ascontiguousarray(ref, dtype=np.float32),
                  pixel_format=mi.Bitmap.PixelFormat.RGB).write(os.path.join(dst, 'reference.exr'))
        mi.util.write_bitmap(os.path.join(dst, 'reference.png'),
                             np.clip(ref * args.exposure, 0, 1).astype(np.float32))

        competitor = []
        for seed in (1_000_001, 1_000_002):
            t1 = time.perf_counter()
            img = render(args.competitor_spp, seed)
            dt = time.perf_counter() - t1
            ratio = img.reshape(-1, 3).mean(0) / ref.reshape(-1, 3).mean(0)
            competitor.append(dict(seed=seed, relmse=relmse(img, ref), time_s=round(dt, 3),
                                   mean_ratio=[float(x) for x in ratio]))
            log(f'{name}: competitor seed {seed}: relMSE {competitor[-1]["relmse"]:.4e}, '
                f'mean ratio {ratio}')
        stats = {
            'reference': dict(
                renderer=f'Mitsuba {mi.__version__} llvm_ad_rgb', integrator='ptracer', max_depth=-1,
                spp=args.spp * args.passes, passes=args.passes, seeds=f'0..{args.passes - 1}',
                light_paths=args.spp * args.passes * w * h, time_s=round(elapsed, 1),
                threads=args.threads or os.cpu_count(), load_avg_1min=round(os.getloadavg()[0], 2),
                relmse_halves=halves, relmse_reference_est=halves / 4,
                mean_rgb=[float(x) for x in ref.reshape(-1, 3).mean(0)], width=w, height=h),
            'competitor': dict(
                integrator='ptracer', spp=args.competitor_spp,
                light_paths=args.competitor_spp * w * h, runs=competitor,
                relmse=float(np.mean([c['relmse'] for c in competitor]))),
        }
        with open(os.path.join(dst, 'reference_stats.json'), 'w') as f:
            json.dump(stats, f, indent=2)
            f.write('\n')
        log(f'{name}: {args.spp * args.passes} spp in {elapsed:.1f} s, relMSE(halves) {halves:.3e} '
            f'-> reference ~{halves / 4:.3e}; competitor {stats["competitor"]["relmse"]:.4e}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
