#!/usr/bin/env python3
"""sum_references.py - a scene's reference as the sum of its single-light references.

Light transport is linear in the emitters: the image of a scene with lights A and B is the image
with only A plus the image with only B. For a folder testdata/mitsuba/NAME whose scene.xml has
the lights of scene-X.xml, scene-Y.xml, ... (each identical to scene.xml but for the other lights
removed), this script writes
    reference.exr / reference.png   the sum of reference-X.exr, reference-Y.exr, ...
    reference_stats.json            where it came from, its self-noise and a direct check:
  * self-noise: with --halves-dir (the folder render_reference.py --halves-dir wrote the half
    means to), relMSE(sum of halves A, sum of halves B) / 4, as for a rendered reference;
  * competitor: Mitsuba renders scene.xml itself (both lights at once) with the integrator of
    the parts at COMPETITOR_SPP, seeds 1000001 and 1000002, and records relMSE and per-channel
    mean ratio against the sum, as render_reference.py does; a mean ratio of 1 within noise
    checks that the parts add up to the whole scene.
So one converged render per light gives both the relighting references and the full scene's,
at the cost of one.

Run from the repository root:
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
    /work/venv-mitsuba/bin/python tools/mitsuba/sum_references.py bunny-box warm cool \
        --halves-dir /tmp/halves --competitor-spp 64 --threads 2
"""
import argparse
import json
import os
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EPS = 1e-2


def relmse(t, r):
    import numpy as np
    return float(np.mean((t - r) ** 2 / (r ** 2 + EPS)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('name')
    ap.add_argument('parts', nargs='+', help='X for each reference-X.exr to add')
    ap.add_argument('--halves-dir', default=None)
    ap.add_argument('--competitor-spp', type=int, default=64)
    ap.add_argument('--threads', type=int, default=None)
    args = ap.parse_args()
    if not os.environ.get('DRJIT_LIBLLVM_PATH'):
        os.environ['DRJIT_LIBLLVM_PATH'] = '/usr/lib/x86_64-linux-gnu/libLLVM-19.so'
    import numpy as np
    import drjit as dr
    import mitsuba as mi
    mi.set_variant('llvm_ad_rgb')
    folder = os.path.join(REPO, 'testdata', 'mitsuba', args.name)

    def read(path):
        return np.array(mi.Bitmap(path), dtype=np.float64)[..., :3]

    parts, stats_parts = [], {}
    for x in args.parts:
        parts.append(read(os.path.join(folder, f'reference-{x}.exr')))
        with open(os.path.join(folder, f'reference-{x}_stats.json')) as f:
            stats_parts[x] = json.load(f)['reference']
    ref = np.sum(parts, axis=0)
    mi.Bitmap(np.ascontiguousarray(ref, dtype=np.float32),
              pixel_format=mi.Bitmap.PixelFormat.RGB).write(os.path.join(folder, 'reference.exr'))
    mi.util.write_bitmap(os.path.join(folder, 'reference.png'), np.clip(ref, 0, 1).astype(np.float32))
    h, w = ref.shape[:2]
    integrators = {s['integrator'] for s in stats_parts.values()}
    assert len(integrators) == 1, integrators
    integrator_name = integrators.pop()

    halves = None
    if args.halves_dir:
        ha = np.sum([read(os.path.join(args.halves_dir, f'{args.name}_reference-{x}.halfA.exr'))
                     for x in args.parts], axis=0)
        hb = np.sum([read(os.path.join(args.halves_dir, f'{args.name}_reference-{x}.halfB.exr'))
                     for x in args.parts], axis=0)
        halves = relmse(ha, hb)
        print(f'{args.name}: sum of halves relMSE {halves:.3e} -> reference ~{halves / 4:.3e}',
              file=sys.stderr)

    if args.threads:  # after reading the EXRs (see benches/mitsuba_path.py)
        dr.set_thread_count(args.threads)
    scene = mi.load_file(os.path.join(folder, 'scene.xml'))
    integrator = mi.load_dict({'type': integrator_name, 'max_depth': -1})
    competitor = []
    mi.render(scene, integrator=integrator, spp=args.competitor_spp, seed=999_999)  # JIT warm-up
    for seed in (1_000_001, 1_000_002):
        t1 = time.perf_counter()
        img = np.array(mi.render(scene, integrator=integrator, spp=args.competitor_spp, seed=seed),
                       dtype=np.float64)[..., :3]
        dt = time.perf_counter() - t1
        ratio = img.reshape(-1, 3).mean(0) / ref.reshape(-1, 3).mean(0)
        competitor.append(dict(seed=seed, relmse=relmse(img, ref), time_s=round(dt, 3),
                               mean_ratio=[float(x) for x in ratio]))
        print(f'{args.name}: scene.xml at {args.competitor_spp} spp, seed {seed}: relMSE '
              f'{competitor[-1]["relmse"]:.4e}, mean ratio {ratio}', file=sys.stderr)
    paths_key = 'light_paths' if integrator_name == 'ptracer' else 'camera_paths'
    stats = {
        'reference': dict(
            renderer=f'Mitsuba {mi.__version__} llvm_ad_rgb', integrator=integrator_name,
            max_depth=-1, scene='scene.xml',
            made_as='sum of ' + ' + '.join(f'reference-{x}.exr' for x in args.parts)
                    + ' (light transport is linear in the emitters)',
            parts=stats_parts, spp=min(s['spp'] for s in stats_parts.values()),
            time_s=round(sum(s['time_s'] for s in stats_parts.values()), 1),
            relmse_halves=halves, relmse_reference_est=halves / 4 if halves is not None else None,
            mean_rgb=[float(x) for x in ref.reshape(-1, 3).mean(0)], width=w, height=h),
        'competitor': dict(
            integrator=integrator_name, scene='scene.xml', spp=args.competitor_spp,
            **{paths_key: args.competitor_spp * w * h}, runs=competitor,
            relmse=float(np.mean([c['relmse'] for c in competitor]))),
    }
    with open(os.path.join(folder, 'reference_stats.json'), 'w') as f:
        json.dump(stats, f, indent=2)
        f.write('\n')
    return 0


if __name__ == '__main__':
    sys.exit(main())
