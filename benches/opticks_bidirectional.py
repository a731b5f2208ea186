#!/usr/bin/env python3
"""opticks_bidirectional.py - efficiency of Opticks's estimators on a reference scene.

What it measures
    For SCENE.xml: `opticks trace` of PATHS light paths (wall time t_trace), then from that
    dataset `opticks render --estimator light` and `--estimator bidirectional --spp S
    --connections C` for each S, C asked for (wall time t_render each, as the command reports
    it: dataset opened and scene loaded before the clock starts). Each image is compared with the
    scene's reference exactly as mitsuba_path.py does (relMSE = mean of (t - r)^2 / (r^2 + 1e-2),
    per-channel mean ratio), optionally only inside a mask (--mask M.exr: pixels where the mask
    is 1; relMSE then over those pixels). Efficiencies, 1 / (relMSE x seconds):
      frame:  t_render only (a frame from an existing dataset),
      image:  t_trace + t_render (one image including its trace).
    The reference's own noise (relmse_reference_est in its stats JSON) is reported, not
    subtracted.

Output
    One JSON line per render on stdout; a human-readable table on stderr.

Run (from the repo root, after `cargo build --release`)
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so /work/venv-mitsuba/bin/python \\
        benches/opticks_bidirectional.py testdata/scenes/cornell/scene.xml --paths 1000000 --spp 4,16 --connections 1,4
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mitsuba_path import default_reference  # noqa: E402
from mitsuba_ptracer import REPO, find_libllvm, log, read_rgb, relmse  # noqa: E402


def run(cmd):
    t0 = time.time()
    before = os.times()
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    after = os.times()
    cpu = (after.children_user - before.children_user) + (after.children_system - before.children_system)
    return out, time.time() - t0, cpu


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('scene')
    ap.add_argument('--paths', type=int, default=1_000_000)
    ap.add_argument('--spp', default='16', help='comma-separated camera paths per pixel')
    ap.add_argument('--connections', default='1', help='comma-separated n_c')
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--reference')
    ap.add_argument('--mask')
    ap.add_argument('--light', action='append', default=[], help='passed to render (relighting)')
    ap.add_argument('--opticks', default=os.path.join(REPO, 'target', 'release', 'opticks'))
    ap.add_argument('--mitsuba-spp', type=int, default=0,
                    help='also run mitsuba_path.py at this spp in the same run (its 2nd run timed), '
                         'its image measured like ours (mask included)')
    a = ap.parse_args()
    os.environ.setdefault('DRJIT_LIBLLVM_PATH', find_libllvm() or '')
    import mitsuba as mi
    import numpy as np
    mi.set_variant('scalar_rgb')
    ref_path = a.reference or default_reference(a.scene)
    ref = read_rgb(mi, ref_path)
    mask = read_rgb(mi, a.mask)[..., 0] > 0.5 if a.mask else None
    tmp = tempfile.mkdtemp()
    data = os.path.join(tmp, 'd.opds')
    out, t_trace, c_trace = run([a.opticks, 'trace', a.scene, '--paths', str(a.paths), '--seed', str(a.seed), '-o', data])
    m = re.search(r'in ([0-9.]+) s', out)
    t_trace = float(m.group(1)) if m else t_trace
    log(f'trace: {a.paths} paths in {t_trace:.2f} s (CPU {c_trace:.2f} s)')
    lights = sum((['--light', l] for l in a.light), [])
    def measure(img):
        test = read_rgb(mi, img)
        if mask is not None:
            e = float(np.mean(((test - ref) ** 2 / (ref ** 2 + 1e-2))[mask]))
            return e, [float(test[..., c][mask].mean() / ref[..., c][mask].mean()) for c in range(3)]
        return relmse(test, ref), [float(test[..., c].mean() / ref[..., c].mean()) for c in range(3)]

    if a.mitsuba_spp:
        img = os.path.join(tmp, 'mitsuba.exr')
        out, _, _ = run([sys.executable, os.path.join(REPO, 'benches', 'mitsuba_path.py'), a.scene,
                         '--spp', str(a.mitsuba_spp), '--threads', '2', '--out', img, '--reference', ref_path])
        mj = json.loads(out.strip().splitlines()[-1])
        e, ratio = measure(img)
        rec = dict(scene=a.scene, estimator='mitsuba-path', spp=a.mitsuba_spp, render_s=mj['time_s'],
                   render_cpu_s=mj.get('cpu_s'), relmse=e, mean_ratio=ratio, efficiency_frame=1 / (e * mj['time_s']),
                   efficiency_image=1 / (e * mj['time_s']), load_avg_1min=os.getloadavg()[0], mask=a.mask)
        print(json.dumps(rec), flush=True)
        log(f'Mitsuba path spp {a.mitsuba_spp}: {mj["time_s"]:.2f} s (CPU {mj.get("cpu_s", 0):.2f}), relMSE {e:.4g}, '
            f'mean {ratio[0]:.4f} {ratio[1]:.4f} {ratio[2]:.4f}, eff {1 / (e * mj["time_s"]):.3g}')
    runs = [('light', None, None)] + [('bidirectional', int(s), int(c)) for s in a.spp.split(',') for c in a.connections.split(',')]
    for est, spp, nc in runs:
        img = os.path.join(tmp, f'{est}-{spp}-{nc}.exr')
        cmd = [a.opticks, 'render', data, '-o', img, '--estimator', est] + lights
        if spp:
            cmd += ['--spp', str(spp), '--connections', str(nc)]
        out, wall, cpu = run(cmd)
        m = re.search(r'in ([0-9.]+) s', out)
        t = float(m.group(1)) if m else wall
        e, ratio = measure(img)
        rec = dict(scene=a.scene, estimator=est, spp=spp, connections=nc, paths=a.paths, trace_s=t_trace,
                   render_s=t, render_cpu_s=cpu, trace_cpu_s=c_trace, relmse=e, mean_ratio=ratio,
                   efficiency_frame=1 / (e * t), efficiency_image=1 / (e * (t + t_trace)),
                   load_avg_1min=os.getloadavg()[0], mask=a.mask)
        print(json.dumps(rec), flush=True)
        log(f'{est:>13} spp {spp} n_c {nc}: render {t:.2f} s (CPU {cpu:.2f}), relMSE {e:.4g}, '
            f'mean {ratio[0]:.4f} {ratio[1]:.4f} {ratio[2]:.4f}, eff frame {1 / (e * t):.3g}, '
            f'image {1 / (e * (t + t_trace)):.3g}')


if __name__ == '__main__':
    main()
