"""The time-to-accuracy search (--time-to-accuracy): each program's cheapest setting that reads
every point of a case within its target, over several seeds."""
import math
import pathlib
import resource
import statistics
import subprocess
import tempfile
import time

from .closed_forms import (BOX_RHOS, BOX_WALLS, PANE_ANGLES, RADIANCE_EFFICACY, SCENES, box_floor_points, e_box,
                           e_disc, e_facade_uniform, e_obstructed, e_obstructed_sky, e_pane, e_point,
                           e_quadrature, e_rect, e_reflected, e_roof_uniform, sky_gensky_overcast,
                           t_pane_opticks)
from .opticks import read_measure, read_meters, read_points
from .radiance import radiance_box_options
from .report import pct
from .scenes import pane_tag, rho_tag


# ---------------------------------------------------------------- time to accuracy (--time-to-accuracy)
#
# Issue 27: on each case, Opticks's time to the case's target against Radiance's time to the same
# target, Radiance's settings searched. A candidate setting reaches the target when every one of
# TTA_SEEDS independent runs reads every point within the target of the closed form: one run's
# max |diff| is a noisy stop criterion (a lucky run passes), and Opticks's SE is NaN at the smallest
# path counts (one chunk of paths), so the criterion is the runs' spread itself, the same for both
# programs. Times are CPU seconds (user + system of the child processes) of one run, wall beside.

TTA_HEADING = "## Time to accuracy against Radiance"
TTA_SEEDS = (1, 2, 3)
TTA_PATHS = [2 ** k for k in range(12, 22)] + ["4M"]  # 4096 … 2^21 doubling, then the default 4M
TTA_BOX_PATHS = [2 ** k for k in range(12, 21)]  # to 1M: 4M paths of the ρ = 0.95 box is a 4 GB dataset
TTA_SKY_DS = ["auto", "1024", "2048", "4096", "8192", "16384", "32768", "65536"]  # measure --direct-samples (auto: the default)
TTA_AREA_DS = ["auto", "512", "1024", "2048", "4096", "8192", "16384"]  # the same for the area-light cases
TTA_AREA_KEYS = ("rect", "disc", "obstruct")  # their direct light is the meter's, sampled on the source
TTA_SKY_RAYS = 2 ** 17  # Radiance's sky grid: at most -ad × runs averaged ambient rays a point


def run_timed(cmd, **kw):
    """Run one child process to completion: (CPU seconds — user + system of it and the children it
    waited for —, wall seconds, the CompletedProcess). Children run one at a time, so the
    RUSAGE_CHILDREN delta is this one's."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    out = subprocess.run(cmd, check=True, **kw)
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), wall, out


class SubCase:
    """One scene of a case (a case may have several: the box's ρ, the pane's angles): what both
    programs read, the closed form, and how a run's raw lux become the compared values."""

    def __init__(self, key, label, scene, rad_scene, kind, points=None, analytic=None, rho=None, reflected=False):
        self.key, self.label, self.scene, self.rad_scene, self.kind = key, label, scene, rad_scene, kind
        self.points_file = points
        self.rho, self.reflected = rho, reflected
        if kind == "box":
            gl = box_floor_points()
            self.rad_points = [(x, y, 0, 0, 0, 1) for x, y, _ in gl]
            self.gl_w = [w for _, _, w in gl]
            self.analytic = [e_reflected(rho) if reflected else e_box(rho)]
        else:
            self.rad_points = read_points(points)
            self.analytic = [analytic(p[0], p[1]) for p in self.rad_points]

    def values(self, raw, program):
        """Raw lux of a run → the values compared with self.analytic."""
        if self.kind != "box":
            return raw
        if program == "opticks":  # the six walls' mean
            mean = statistics.fmean(raw)
        else:  # Radiance: the floor's Gauss-Legendre mean
            mean = sum(w * e for w, e in zip(self.gl_w, raw)) / sum(self.gl_w)
        return [mean - e_box(0.0) if self.reflected else mean]

    def worst(self, raw, program):
        return max(abs(pct(v, a)) for v, a in zip(self.values(raw, program), self.analytic))


class Candidate:
    def __init__(self, settings, runs, sub, program):
        """runs: per seed (raw, cpu, wall, trace cpu)."""
        self.settings = settings
        self.worst = max(sub.worst(r[0], program) for r in runs)
        self.cpu = statistics.fmean(r[1] for r in runs)
        self.wall = statistics.fmean(r[2] for r in runs)
        self.trace_cpu = statistics.fmean(r[3] for r in runs)


class TimeToAccuracy:
    def __init__(self, exe, work, radiance):
        self.exe, self.work, self.radiance = str(exe), work, radiance
        self.cache = {}
        self.tried = {"opticks": 0, "radiance": 0}

    # -- Opticks

    def opticks_runs(self, sub, paths, ds_list, seed):
        """Trace once at (paths, seed) and measure for every --direct-samples of ds_list not yet run."""
        need = [ds for ds in ds_list if (sub.key, paths, ds, seed) not in self.cache]
        if not need:
            return
        tag = f"tta-{sub.key}"
        # stderr too: the smallest counts warn that their SE is unknown (one chunk of paths)
        quiet = dict(cwd=self.work, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        tc, tw, _ = run_timed([self.exe, "trace", str(sub.scene), "-o", f"{tag}.opds", "--overwrite", "--quiet",
                               "--paths", str(paths), "--seed", str(seed)], **quiet)
        for ds in need:
            mc = mw = 0.0
            if sub.kind == "box":
                # the six walls in one run (one read of the dataset)
                meters = [a for wall_name in BOX_WALLS for a in ("--surface", wall_name)]
                mc, mw, _ = run_timed([self.exe, "measure", f"{tag}.opds", *meters, "--cells", "1x1",
                                       "-o", f"{tag}.csv", "--quiet"], **quiet)
                walls = read_meters(self.work / f"{tag}.csv")
                raw = [walls[wall_name][0]["E_v_lux"] for wall_name in BOX_WALLS]
            else:
                extra = [] if ds == "auto" else ["--direct-samples", ds]
                mc, mw, _ = run_timed([self.exe, "measure", f"{tag}.opds", "--points", str(sub.points_file),
                                       "--seed", str(seed), "-o", f"{tag}.csv", "--quiet", *extra], **quiet)
                raw = [m["E_v_lux"] for m in read_measure(self.work / f"{tag}.csv")]
            self.cache[(sub.key, paths, ds, seed)] = (raw, tc + mc, tw + mw, tc)
            self.tried["opticks"] += 1
        (self.work / f"{tag}.opds").unlink(missing_ok=True)

    def opticks_candidate(self, sub, paths, ds):
        for s in TTA_SEEDS:
            self.opticks_runs(sub, paths, [ds], s)
        settings = f"--paths {paths}" + ("" if ds == "auto" else f" --direct-samples {ds}")
        return Candidate(settings, [self.cache[(sub.key, paths, ds, s)] for s in TTA_SEEDS], sub, "opticks")

    def opticks_search(self, sub, target):
        """The cheapest (paths, direct samples) whose every seed is within target: the path count
        doubling upward (stopping at the first that passes, or when two doublings did not improve
        the accuracy), every --direct-samples at each count for the sky and area-light cases."""
        grid = TTA_BOX_PATHS if sub.kind == "box" else TTA_PATHS
        ds_grid = TTA_SKY_DS if sub.kind == "sky" else TTA_AREA_DS if sub.key in TTA_AREA_KEYS else ["auto"]
        best, trail = None, []
        for paths in grid:
            for s in TTA_SEEDS:
                self.opticks_runs(sub, paths, ds_grid, s)
            row = [self.opticks_candidate(sub, paths, ds) for ds in ds_grid]
            for c in row:
                if c.worst <= target and (best is None or c.cpu < best.cpu):
                    best = c
            trail.append(min(c.worst for c in row))
            if best is not None or (len(trail) >= 3 and min(trail[-2:]) >= 0.9 * trail[-3]):
                break
        closest = best or min((self.opticks_candidate(sub, p, ds) for p in grid for ds in ds_grid
                               if (sub.key, p, ds, TTA_SEEDS[0]) in self.cache), key=lambda c: c.worst)
        default = self.opticks_candidate(sub, "1M" if sub.kind == "box" else "4M", "auto")
        return best, closest, default

    # -- Radiance

    def radiance_candidate(self, sub, options, runs):
        """oconv + one rtrace of len(TTA_SEEDS) × runs repetitions of the points (each repetition
        draws fresh samples: rtrace's sample index advances per ray); seed k is the mean of the k-th
        block of `runs`. One seed's time: oconv's + rtrace's / len(TTA_SEEDS) (rtrace's start-up
        shared by the blocks)."""
        key = (sub.key, tuple(options), runs)
        if key not in self.cache:
            r, n = len(TTA_SEEDS), len(sub.rad_points)
            with tempfile.TemporaryDirectory() as tmp:
                octree = pathlib.Path(tmp) / "scene.oct"
                with open(octree, "wb") as f:
                    oc, ow, _ = run_timed(["oconv", "-f", sub.rad_scene.name], cwd=sub.rad_scene.parent,
                                          env=self.radiance.env, stdout=f)
                rays = "".join(" ".join(map(str, p)) + "\n" for p in sub.rad_points) * (r * runs)
                rc, rw, out = run_timed(["rtrace", "-h", "-I", "-ov", *options, str(octree)], input=rays,
                                        capture_output=True, text=True, env=self.radiance.env)
            rgb = [[float(v) for v in line.split()] for line in out.stdout.splitlines() if line.strip()]
            lux = [RADIANCE_EFFICACY * (0.2651058 * a + 0.6701058 * b + 0.0647884 * c) for a, b, c in rgb]
            seeds = []
            for k in range(r):
                block = lux[k * runs * n:(k + 1) * runs * n]
                raw = [statistics.fmean(block[j * n + i] for j in range(runs)) for i in range(n)]
                seeds.append((raw, oc + rc / r, ow + rw / r, 0.0))
            self.cache[key] = seeds
            self.tried["radiance"] += 1
        settings = " ".join(options) + (f", mean of {runs} runs" if runs > 1 else "")
        return Candidate(settings, self.cache[key], sub, "radiance")

    def radiance_rows(self, sub):
        """Rows of (options, runs) in increasing cost; each row is searched until it passes or its
        accuracy stops improving."""
        if sub.kind == "direct":
            base = ["-ab", "0", "-dt", "0", "-dc", "1", "-lw", "1e-6"]
            rows = [[(base + ["-dj", "0", "-ds", ds], 1)
                     for ds in ("0.2", "0.1", "0.05", "0.02", "0.01", "0.005", "0.002", "0.001")]]
            rows += [[(base + ["-dj", dj, "-ds", ds], n) for n in (1, 4, 16, 64, 256, 1024)]
                     for dj in ("0.7", "1") for ds in ("0.2", "0.05", "0.01")]
            return rows
        if sub.kind == "sky":
            rows = []
            for n in (1, 4, 16):
                rows.append([(["-ab", "1", "-aa", "0", "-ad", str(ad), "-as", str(ad // 2),
                               "-lw", f"{min(1e-5, 0.1 / ad):.0e}"], n)
                             for ad in (256, 1024, 4096, 16384, 65536) if ad * n <= TTA_SKY_RAYS])
            return rows
        # the box: a path tracer (one ambient ray a bounce, no cache), -ab such that the truncated
        # ρ^(ab+1) is below 0.25 % (then 0.01 %), runs averaged
        if sub.rho == 0:
            return [[(radiance_box_options(0.0), 1)]]
        rows = []
        for tol in (2.5e-3, 1e-4):
            ab = math.ceil(math.log(tol) / math.log(sub.rho)) - 1
            opts = radiance_box_options(sub.rho)
            opts[opts.index("-ab") + 1] = str(ab)
            rows.append([(opts, n) for n in (4, 16, 64, 256, 1024)])
        return rows

    def radiance_search(self, sub, target):
        best, closest = None, None
        for row in self.radiance_rows(sub):
            trail = []
            for options, runs in row:
                c = self.radiance_candidate(sub, options, runs)
                if closest is None or c.worst < closest.worst:
                    closest = c
                if c.worst <= target:
                    if best is None or c.cpu < best.cpu:
                        best = c
                    break
                if best is not None and c.cpu > best.cpu:
                    break
                trail.append(c.worst)
                if len(trail) >= 3 and min(trail[-2:]) >= 0.9 * trail[-3]:
                    break
        return best, closest


def tta_cases():
    """The summary table's cases as (title, target %, sub-cases)."""
    s = SCENES
    cases = [
        ("5.2 Point source", 1, [SubCase("point", "", s / "point.xml", s / "point.rad", "direct", s / "point.csv", e_point)]),
        ("5.3 Area source: rectangle", 1, [SubCase("rect", "", s / "rect.rad", s / "rect.rad", "direct", s / "rect.csv", e_rect)]),
        ("5.3 Area source: disc", 1, [SubCase("disc", "", s / "disc.rad", s / "disc.rad", "direct", s / "disc.csv", e_disc)]),
        ("5.7 Internal obstruction", 1, [SubCase("obstruct", "", s / "obstruct.rad", s / "obstruct.rad", "direct",
                                                 s / "obstruct.csv", e_obstructed)]),
        ("5.4 / 5.6 Closed box", 1, [SubCase(f"box-{rho_tag(r)}", f"ρ {r:g}", s / f"box-{rho_tag(r)}.xml",
                                             s / f"box-{rho_tag(r)}.rad", "box", rho=r) for r in BOX_RHOS]),
        ("5.8 Internal reflected component", 1, [SubCase(f"box-{rho_tag(r)}", f"ρ {r:g}", s / f"box-{rho_tag(r)}.xml",
                                                         s / f"box-{rho_tag(r)}.rad", "box", rho=r, reflected=True)
                                                 for r in BOX_RHOS if r > 0]),
        ("5.5 Directional transmittance of clear glass", 1,
         [SubCase(pane_tag(t), f"{t}°", s / f"{pane_tag(t)}.xml", s / f"{pane_tag(t)}.rad", "direct", s / "pane.csv",
                  (lambda t: lambda x, y: e_pane(t))(t)) for t in PANE_ANGLES]),
    ]
    sky_titles = {
        "sky-roof-uniform": ("5.9 Sky component: roof opening, uniform sky", e_roof_uniform),
        "sky-roof-overcast": ("5.9 Sky component: roof opening, CIE overcast sky",
                              lambda x, y: e_quadrature(x, y, "roof", sky_gensky_overcast)),
        "sky-facade-uniform": ("5.10 Sky component: façade opening, uniform sky", e_facade_uniform),
        "sky-facade-overcast": ("5.10 Sky component: façade opening, CIE overcast sky",
                                lambda x, y: e_quadrature(x, y, "facade", sky_gensky_overcast)),
        "sky-roof-glazed": ("5.11 Sky component: glazed roof opening, CIE overcast sky",
                            lambda x, y: e_quadrature(x, y, "roof", sky_gensky_overcast, t_pane_opticks)),
        "sky-facade-glazed": ("5.12 Sky component: glazed façade opening, CIE overcast sky",
                              lambda x, y: e_quadrature(x, y, "facade", sky_gensky_overcast, t_pane_opticks)),
        "sky-roof-obstructed": ("5.13 Sky component: roof opening with an external obstruction, CIE overcast sky",
                                lambda x, y: e_obstructed_sky(x, y, "roof")),
        "sky-facade-obstructed": ("5.14 Sky component: façade opening with an external obstruction, CIE overcast sky",
                                  lambda x, y: e_obstructed_sky(x, y, "facade")),
    }
    for stem, (title, fn) in sky_titles.items():
        pts = s / ("sky-roof.csv" if "roof" in stem else "sky-facade.csv")
        cases.append((title, 2, [SubCase(stem, "", s / f"{stem}.rad", s / f"{stem}.rad", "sky", pts, fn)]))
    return cases


def per_sub(subs, picks, fmt_one):
    """Settings of a case's sub-cases: once if they agree, else per sub-case."""
    texts = [fmt_one(c) for c in picks]
    if len(set(texts)) == 1:
        return texts[0] + (f" (each of {len(subs)})" if len(subs) > 1 else "")
    return "; ".join(f"{s.label}: {t}" for s, t in zip(subs, texts))
