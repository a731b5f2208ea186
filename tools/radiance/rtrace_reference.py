#!/usr/bin/env python3
"""Reference illuminances for the photometry cross-check (issue 27): `rtrace -I` at the points
of testdata/points/photometry.csv in testdata/radiance/photometry.rad, converted to lux as
Radiance converts them, E_v = 179 * (CIE_rf R + CIE_gf G + CIE_bf B) (Radiance's
src/common/color.h: WHTEFFICACY and bright(), whose weights its macros compute from the default
primaries R (0.640, 0.330), G (0.290, 0.600), B (0.150, 0.060) and white (1/3, 1/3), as
weights() does here: 0.2651058, 0.6701058, 0.0647884; color.h's comment quotes older values,
.265074126, .670114631, .064811243, those of a white at (0.3333, 0.3333)). The numbers are recorded in crates/cli/tests/it/photometry.rs; CI does not run
this script (it needs Radiance: pyradiance's binaries).

Settings: -I (irradiance at the point, facing the given direction), -ab 1 (the floor is black,
so one bounce is the sky and nothing more), -aa 0 (no irradiance caching: every value is its
own Monte Carlo estimate), three settings (-ad, -ds) = (4096, 0.02), (8192, 0.01), (16384,
0.005) with -as ad/4, -lw 1e-6, and the direct calculation of the panel with -dj 0 (a
deterministic subdivision, finer as -ds falls), -dt 0 -dc 1.
Each point is traced REPEATS times in every run (with -aa 0 the repeats draw fresh ambient
samples): the reference is the mean of all values, its spread the largest deviation of one
setting's mean from it and the repeats' standard deviation, both printed (rtrace's ambient
samples differ from run to run, so a rerun moves the means by about that spread).

Run from anywhere:  /tmp/prvenv/bin/python tools/radiance/rtrace_reference.py
(pyradiance installed in /tmp/prvenv; its bin/ goes on PATH and its lib/ is RAYPATH).
"""
import pathlib
import statistics
import subprocess
import tempfile
import os

import pyradiance

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENE = ROOT / "testdata/radiance/photometry.rad"
POINTS = ROOT / "testdata/points/photometry.csv"


def weights(xr=0.640, yr=0.330, xg=0.290, yg=0.600, xb=0.150, yb=0.060, xw=1 / 3, yw=1 / 3):
    """color.h's CIE_rf, CIE_gf, CIE_bf: the luminance (Y) of each primary, white = (1, 1, 1)."""
    d = xr * (yg - yb) + xg * (yb - yr) + xb * (yr - yg)
    cr = (xw * (yg - yb) - yw * (xg - xb) + xg * yb - xb * yg) / yw
    cg = (xw * (yb - yr) - yw * (xb - xr) - xr * yb + xb * yr) / yw
    cb = (xw * (yr - yg) - yw * (xr - xg) + xr * yg - xg * yr) / yw
    return yr * cr / d, yg * cg / d, yb * cb / d


RF, GF, BF = weights()
EFFICACY = 179.0  # color.h WHTEFFICACY
SETTINGS = [(4096, 0.02), (8192, 0.01), (16384, 0.005)]  # (-ad, -ds)
REPEATS = 5

pkg = pathlib.Path(pyradiance.__file__).parent
env = dict(os.environ, PATH=f"{pkg / 'bin'}:{os.environ['PATH']}", RAYPATH=f".:{pkg / 'lib'}")


def points():
    out = []
    for line in POINTS.read_text().splitlines():
        line = line.split("#")[0].strip()
        if not line or line.startswith("x"):
            continue
        out.append([float(v) for v in line.replace(",", " ").split()])
    return out


def main():
    print("weights", RF, GF, BF)
    pts = points()
    with tempfile.TemporaryDirectory() as tmp:
        octree = pathlib.Path(tmp) / "scene.oct"
        with open(octree, "wb") as f:
            subprocess.run(["oconv", "-f", SCENE.name], cwd=SCENE.parent, env=env, stdout=f, check=True)
        rays = "".join(" ".join(map(str, p)) + "\n" for p in pts for _ in range(REPEATS))
        per_setting = {}
        for ad, ds in SETTINGS:
            cmd = ["rtrace", "-h", "-I", "-ov", "-ab", "1", "-aa", "0", "-ad", str(ad),
                   "-as", str(ad // 4), "-lw", "1e-6", "-dj", "0", "-ds", str(ds), "-dt", "0",
                   "-dc", "1", str(octree)]
            out = subprocess.run(cmd, input=rays, capture_output=True, text=True, env=env, check=True)
            rgb = [[float(v) for v in line.split()] for line in out.stdout.splitlines() if line.strip()]
            per_setting[(ad, ds)] = [rgb[k * REPEATS:(k + 1) * REPEATS] for k in range(len(pts))]
            print("ran", " ".join(cmd))
    print()
    print("point | E_R E_G E_B (W/m²) | E_v lux (Radiance) | repeats' sd | largest setting deviation")
    for k, p in enumerate(pts):
        values = [v for s in SETTINGS for v in per_setting[s][k]]
        mean = [statistics.fmean(v[c] for v in values) for c in range(3)]
        lux = [EFFICACY * (RF * v[0] + GF * v[1] + BF * v[2]) for v in values]
        lux_mean = statistics.fmean(lux)
        sd = statistics.stdev(lux)
        setting_means = [statistics.fmean(lux[i * REPEATS:(i + 1) * REPEATS]) for i in range(len(SETTINGS))]
        dev = max(abs(m - lux_mean) for m in setting_means)
        print(f"{p} | {mean[0]:.4f} {mean[1]:.4f} {mean[2]:.4f} | {lux_mean:.2f} | {sd:.2f} | {dev:.2f}"
              f" (per (-ad, -ds) {SETTINGS}: {', '.join(f'{m:.2f}' for m in setting_means)})")


if __name__ == "__main__":
    main()
