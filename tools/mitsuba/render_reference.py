#!/usr/bin/env python3
"""render_reference.py - Mitsuba 3 references (particle tracer or path tracer) for test scenes.

For each scene NAME (default: caustics ring) this script
  1. copies scenes/NAME/scene.xml and scenes/NAME/meshes/ to testdata/mitsuba/NAME/ (the test
     inputs live in testdata, so editing a showcase does not silently break the test); a scene
     with no scenes/NAME (e.g. `rough`, a test-only scene) is rendered from testdata in place;
  2. renders testdata/mitsuba/NAME/SCENE (--scene, default scene.xml) with Mitsuba's INTEGRATOR
     (--integrator: `ptracer`, the default, or `path`; --max-depth, default -1 = unbounded, with
     Mitsuba's default Russian roulette from depth 5; the scene's box filter) in PASSES passes of
     SPP samples (light paths per pixel for `ptracer`, camera paths for `path`) each, with seeds
     0..PASSES-1, in one process (the first, JIT-compiling pass is rendered once more to time the
     passes fairly: the time reported excludes it);
  3. writes the mean of all passes to reference.exr (linear RGB float32) and an exposure-scaled
     sRGB reference.png for eyes (for a scene file scene-X.xml: reference-X.exr, reference-X.png,
     reference-X_stats.json, so several variants of a scene can share a folder and its meshes);
  4. estimates the reference's own noise: relMSE(half A, half B) between the mean of the even
     and of the odd passes; each half has twice the variance of the full mean and the
     difference of two halves has the sum of their variances, so relMSE(reference) is about
     relMSE(halves) / 4 (the same estimate as testdata/scenes/*/reference_stats.json);
  5. renders the competitor figure: the same integrator at COMPETITOR_SPP (the path count the
     test gives Opticks) with seeds 1000001 and 1000002, and records its relMSE and per-channel
     mean ratio against the reference;
  6. writes reference_stats.json (reference-X_stats.json).
relMSE is imgcmp.py's: mean over pixels and channels of (t - r)^2 / (r^2 + 1e-2).

Run from the repository root (a few minutes per scene on 2 cores):
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
    /work/venv-mitsuba/bin/python tools/mitsuba/render_reference.py [NAME ...] \
        [--passes 16] [--spp 512] [--competitor-spp 64] [--threads 2] \
        [--integrator path] [--max-depth -1] [--scene scene-gold.xml] [--output-stem reference-path]
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
    ap.add_argument('--spp', type=int, default=512, help='samples (paths) per pixel per pass')
    ap.add_argument('--integrator', choices=['ptracer', 'path'], default='ptracer')
    ap.add_argument('--max-depth', type=int, default=-1)
    ap.add_argument('--scene', default='scene.xml',
                    help='scene file in each folder (scene-X.xml writes reference-X.*)')
    ap.add_argument('--output-stem', default=None,
                    help='name of the outputs (STEM.exr, STEM.png, STEM_stats.json; default '
                    'reference, or reference-X for scene-X.xml), e.g. reference-path for a path '
                    'tracer reference beside a particle tracer one')
    ap.add_argument('--competitor-spp', type=int, default=64)
    ap.add_argument('--threads', type=int, default=None)
    ap.add_argument('--exposure', type=float, default=1.0, help='for reference.png only')
    ap.add_argument('--halves-dir', default=None,
                    help='also write the two half means (NAME_REF.halfA.exr, .halfB.exr) here, '
                    'e.g. for sum_references.py (not committed: they are as big as the reference)')
    args = ap.parse_args()
    if not os.environ.get('DRJIT_LIBLLVM_PATH'):
        os.environ['DRJIT_LIBLLVM_PATH'] = '/usr/lib/x86_64-linux-gnu/libLLVM-19.so'
    import numpy as np
    import drjit as dr
    import mitsuba as mi
    mi.set_variant('llvm_ad_rgb')
    if args.threads:
        dr.set_thread_count(args.threads)
    integrator = mi.load_dict({'type': args.integrator, 'max_depth': args.max_depth})
    stem = os.path.splitext(args.scene)[0]
    ref_name = args.output_stem or ('reference' + (stem[len('scene'):] if stem.startswith('scene') else '-' + stem))

    for name in args.names:
        src, dst = os.path.join(REPO, 'scenes', name), os.path.join(REPO, 'testdata', 'mitsuba', name)
        if os.path.isdir(src):  # a showcase: test a copy; else a test-only scene, in place
            os.makedirs(dst, exist_ok=True)
            shutil.copy(os.path.join(src, 'scene.xml'), dst)
            shutil.rmtree(os.path.join(dst, 'meshes'), ignore_errors=True)
            shutil.copytree(os.path.join(src, 'meshes'), os.path.join(dst, 'meshes'))
        scene = mi.load_file(os.path.join(dst, args.scene))
        w, h = (int(v) for v in scene.sensors()[0].film().crop_size())

        def render(spp, seed):
            return np.array(mi.render(scene, integrator=integrator, spp=spp, seed=seed),
                            dtype=np.float64)[..., :3]

        render(args.spp, 999_999)  # JIT warm-up, not timed, not used
        passes, t0 = [], time.perf_counter()
        for p in range(args.passes):
            passes.append(render(args.spp, p))
            if not np.all(np.isfinite(passes[-1])):
                raise SystemExit(f'{name}: pass {p} has non-finite pixels')
            log(f'{name}: pass {p + 1}/{args.passes}, {time.perf_counter() - t0:.1f} s')
        elapsed = time.perf_counter() - t0
        ref = np.mean(passes, axis=0)
        half_a, half_b = np.mean(passes[0::2], axis=0), np.mean(passes[1::2], axis=0)
        halves = relmse(half_a, half_b)
        mi.Bitmap(np.ascontiguousarray(ref, dtype=np.float32),
                  pixel_format=mi.Bitmap.PixelFormat.RGB).write(os.path.join(dst, ref_name + '.exr'))
        if args.halves_dir:
            os.makedirs(args.halves_dir, exist_ok=True)
            for tag, img in (('halfA', half_a), ('halfB', half_b)):
                mi.Bitmap(np.ascontiguousarray(img, dtype=np.float32),
                          pixel_format=mi.Bitmap.PixelFormat.RGB).write(
                    os.path.join(args.halves_dir, f'{name}_{ref_name}.{tag}.exr'))
        mi.util.write_bitmap(os.path.join(dst, ref_name + '.png'),
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
        paths_key = 'light_paths' if args.integrator == 'ptracer' else 'camera_paths'
        stats = {
            'reference': dict(
                renderer=f'Mitsuba {mi.__version__} llvm_ad_rgb', integrator=args.integrator,
                max_depth=args.max_depth, scene=args.scene,
                spp=args.spp * args.passes, passes=args.passes, seeds=f'0..{args.passes - 1}',
                **{paths_key: args.spp * args.passes * w * h}, time_s=round(elapsed, 1),
                threads=args.threads or os.cpu_count(), load_avg_1min=round(os.getloadavg()[0], 2),
                relmse_halves=halves, relmse_reference_est=halves / 4,
                mean_rgb=[float(x) for x in ref.reshape(-1, 3).mean(0)], width=w, height=h),
            'competitor': dict(
                integrator=args.integrator, spp=args.competitor_spp,
                **{paths_key: args.competitor_spp * w * h}, runs=competitor,
                relmse=float(np.mean([c['relmse'] for c in competitor]))),
        }
        with open(os.path.join(dst, ref_name + '_stats.json'), 'w') as f:
            json.dump(stats, f, indent=2)
            f.write('\n')
        log(f'{name}: {args.spp * args.passes} spp in {elapsed:.1f} s, relMSE(halves) {halves:.3e} '
            f'-> reference ~{halves / 4:.3e}; competitor {stats["competitor"]["relmse"]:.4e}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
