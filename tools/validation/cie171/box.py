"""5.4 / 5.6 (the closed box's wall mean) and 5.8 (its reflected component, from the same runs)."""
import math
import statistics
import sys

from .closed_forms import (BOX_I, BOX_PATHS, BOX_RHOS, BOX_SIDE, BOX_WALLS, GL_ORDER, RSPHERE_BOX, SCENES,
                           box_floor_points, e_box, e_reflected)
from .radiance import RADIANCE_BOX_REPEATS, radiance_box_options
from .report import pct, summary, table
from .scenes import rho_tag


def run_cases(run):
    """Append the box's two sections and verdicts to run."""
    opticks, radiance, sections, verdicts = run.opticks, run.radiance, run.sections, run.verdicts
    # 5.4 / 5.6 the box
    print("5.4 / 5.6 box …", file=sys.stderr)
    box_rows_all = []
    box_lines = []
    for rho in BOX_RHOS:
        tag = f"box-{rho_tag(rho)}"
        t_trace = opticks.trace(SCENES / f"{tag}.xml", tag, BOX_PATHS)
        ana = e_box(rho)
        rows, t_measure = opticks.measure_surfaces(tag, BOX_WALLS)
        walls = [r[0] for r in rows]
        opticks.remove(tag)
        mean = sum(r["E_v_lux"] for r in walls) / len(walls)
        se_bound = sum(r["SE_v_lux"] for r in walls) / len(walls)
        worst = max(walls, key=lambda r: abs(r["E_v_lux"] / ana - 1))
        rmean = rtext = None
        if radiance is not None:
            gl = box_floor_points()
            reps = 1 if rho == 0 else RADIANCE_BOX_REPEATS
            pts = [(x, y, 0, 0, 0, 1) for x, y, _ in gl for _ in range(reps)]
            opts = radiance_box_options(rho)
            rlux, rsec, rcmd = radiance.irradiance(SCENES / f"{tag}.rad", pts, opts)
            wsum = sum(w for _, _, w in gl)
            means = [sum(w * rlux[i * reps + k] for i, (_, _, w) in enumerate(gl)) / wsum for k in range(reps)]
            rmean = statistics.fmean(means)
            rse = statistics.stdev(means) / math.sqrt(reps) if reps > 1 else 0.0
            rtext = (rmean, rse, rsec, rcmd)
        box_rows_all.append((rho, ana, walls, mean, se_bound, worst, t_trace, t_measure, rtext))
        box_lines.append((f"ρ = {rho:g}", ana, mean, se_bound))
    radiance_box = [r[8][0] for r in box_rows_all] if radiance is not None else None
    verdicts.append(("5.4 / 5.6 Closed box", box_lines, radiance_box, 1))

    body = ["## 5.4 / 5.6 Flux conservation and diffuse reflection: a closed box", "",
            f"A closed cube of side {BOX_SIDE:g} m (x, y ∈ [−{BOX_SIDE / 2:g}, {BOX_SIDE / 2:g}] m, "
            f"z ∈ [0, {BOX_SIDE:g}] m) of Lambertian walls of reflectance ρ facing in, with an "
            f"isotropic point source of {BOX_I:g} cd (Φ = 4π·{BOX_I:g} lm) at its centre. The mean "
            "irradiance of the walls is E = Φ / (A (1 − ρ)), A = 6 s² (the integrating-sphere "
            "relation: every lumen emitted is received once directly and then ρ, ρ², … times "
            "again); with the source at the centre every wall has the same mean. Opticks reads "
            f"Mitsuba XML (`box-NN.xml`, a point emitter), traced with {BOX_PATHS} paths (a path "
            "in the ρ = 0.95 box has about 20 vertices, 4 M paths would be a 4 GB dataset; "
            "otherwise default settings), and measures the six walls' means in one run, "
            "`opticks measure --surface floor --surface ceiling … --cells 1x1` (one read of the "
            "dataset; default estimator for a surface: the samples that landed on it). The mean of the six walls' SEs bounds the SE of their "
            "mean (the walls share paths).",
            "",
            "**A small bias found here, and fixed.** At ρ = 0 every path's flux lands on exactly "
            "one wall, so the six walls' mean is Φ / A exactly, whatever the noise of each wall; "
            "it read +0.021 % (1 M paths) and +0.023 % (4 M): the surface meter took a sample as "
            "its own within 10⁻⁴ of the edges' length (0.6 mm here) of its plane, so a sample on "
            "an adjacent wall within 0.6 mm of the shared edge was counted by both walls (strips "
            "of 3 m × 0.6 mm along two edges per wall at about 0.56 × the mean irradiance: "
            "+2.2·10⁻⁴, the excess measured). A meter now counts only the samples of surfaces "
            "parallel to it (the stored triangle's normal) within its surface's own deviation "
            "from its plane (core `IlluminanceMeter::splat_on`, `on_mesh`).",
            ""]
    if radiance is not None:
        body += [f"Radiance reads `box-NN.rad` (the source a `light` sphere of radius {RSPHERE_BOX:g} m, "
                 "which absorbs the light that reaches it: 6·10⁻⁵ of each bounce), `rtrace -I` at "
                 f"{GL_ORDER} × {GL_ORDER} Gauss-Legendre points of the floor, their weighted mean "
                 "the floor's mean. Deep interreflection defeats Radiance's ambient cache (with "
                 "`-ad 512 -as 128 -aa 0.1 -ar 64`, ρ = 0.5 took 1.3 s at -ab 2, 5.6 s at -ab 3 and "
                 "about 4× more per further bounce, while -ab 3 still misses ρ⁴ = 6 % of the light), "
                 "so it runs as a path tracer: `-aa 0 -ad 1 -as 0` (one ambient ray per bounce), "
                 "-ab such that the truncated part ρ^(ab+1) is below 10⁻⁴, "
                 f"{RADIANCE_BOX_REPEATS} runs per point (the direct part is deterministic, "
                 "`-dj 0`); SE from the spread of the runs' floor means.", ""]
    head = "| ρ | analytic lux | Opticks mean of walls ± SE | diff % | worst wall diff % | trace s | measure s |"
    rule = "|---|---:|---:|---:|---:|---:|---:|"
    if radiance is not None:
        head += " Radiance floor mean ± SE | diff % | Radiance s | Radiance -ab |"
        rule += "---:|---:|---:|---:|"
    body += [head, rule]
    for rho, ana, walls, mean, se_bound, worst, t_trace, t_measure, rtext in box_rows_all:
        line = (f"| {rho:g} | {ana:.3f} | {mean:.3f} ± {se_bound:.3f} | {pct(mean, ana):+.3f} | "
                f"{pct(worst['E_v_lux'], ana):+.3f} | {t_trace:.2f} | {t_measure:.2f} |")
        if rtext is not None:
            rmean, rse, rsec, rcmd = rtext
            ab = rcmd.split("-ab ")[1].split()[0]
            line += f" {rmean:.3f} ± {rse:.3f} | {pct(rmean, ana):+.3f} | {rsec:.1f} | {ab} |"
        body.append(line)
    body.append("")
    body.append("Per wall (Opticks lux ± SE):")
    body.append("")
    body.append("| ρ | " + " | ".join(BOX_WALLS) + " |")
    body.append("|---|" + "---:|" * len(BOX_WALLS))
    for rho, ana, walls, *_ in box_rows_all:
        body.append(f"| {rho:g} | " + " | ".join(f"{w['E_v_lux']:.2f} ± {w['SE_v_lux']:.2f}" for w in walls) + " |")
    if radiance is not None:
        body += ["", "Radiance commands: " + "; ".join(f"ρ = {r[0]:g}: `{r[8][3]}`" for r in box_rows_all)]
    body += ["", summary(box_lines, radiance_box), ""]
    sections.append("\n".join(body))

    # 5.8 the internally reflected component, from the same box runs
    direct_mean = e_box(0.0)  # Φ / A: every lumen lands once directly, a sixth on each wall
    refl_rows = [(f"ρ = {rho:g}", e_reflected(rho), mean - direct_mean, se_bound)
                 for rho, ana, walls, mean, se_bound, *_ in box_rows_all if rho > 0]
    refl_radiance = ([r[8][0] - direct_mean for r in box_rows_all if r[0] > 0]
                     if radiance is not None else None)
    verdicts.append(("5.8 Internal reflected component", refl_rows, refl_radiance, 1))
    sections.append("\n".join([
        "## 5.8 Internal reflected component: the same closed box", "",
        "CIE 171's 5.8 checks the internally reflected component against the integrating-sphere "
        "relation. That relation is exact for the mean over an enclosure whose every surface has "
        "the same reflectance and no opening, whatever its shape — every reflected lumen lands on "
        "a surface again, so A Ē = Φ + ρ A Ē — and only an approximation for a room with an "
        "opening (the split-flux method is one too), whose reflected component has no closed form "
        "to hold a program to 1 %. So 5.4 / 5.6's closed box is 5.8's principle in exact form, and "
        "this table reads it from the same runs (no further scene): the reflected component's "
        "mean over the walls is Ē_r = Ē − Φ / A = ρ Φ / (A (1 − ρ)), Φ / A being the direct "
        "component's mean exactly (the source at the centre sends a sixth of Φ to each wall). "
        "Opticks's value is the six walls' mean less Φ / A; its SE is at most the walls' mean "
        "SE (the direct component's share of the noise cancels over the six walls, every "
        "path's first landing being on one of them). Radiance's is its floor mean less Φ / A "
        "(its 6 × 6-point quadrature of the direct part is exact within 0.01 %, its ρ = 0 row "
        "above). ρ = 0 has no reflected component (Opticks's walls read Φ / A exactly there, "
        "above).", "",
        table(refl_rows, refl_radiance, "ρ"), "", summary(refl_rows, refl_radiance), ""]))
