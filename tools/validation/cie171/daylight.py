"""5.9–5.14: the sky component through a roof and a façade opening (open, glazed, obstructed)."""
import math
import statistics
import sys

from .closed_forms import (DAYLIGHT_FIXED, FACADE_OBST, FACADE_OPENING, FACADE_XY, GLASS_N,
                           RADIANCE_EFFICACY, ROOF_MASK, ROOF_OPENING, ROOF_XY, ROOM_H, ROOM_HALF, SCENES,
                           SKY_LZ, check_quadrature, e_facade_uniform, e_obstructed_sky, e_quadrature,
                           e_roof_uniform, sky_cie_overcast, sky_gensky_overcast, t_pane_opticks,
                           t_pane_radiance)
from .opticks import read_points
from .radiance import RADIANCE_SKY
from .report import pct, summary, table

DAYLIGHT_NOTES = (
    "The cases are CIE 171's 5.9–5.12 in principle (the sky component through a roof and a façade "
    "opening, open and glazed), 5.13 and 5.14 (the same openings with an external obstruction). The 2 % target is the issue's for "
    "daylight.\n\n"
    "**A bias of the surface meter found here, and fixed.** The `samples` estimator took as a "
    "meter's own every stored sample within its plane's tolerance (10⁻⁴ of its two edges' length) "
    "inside its rectangle — on its closed edges that included the samples on a perpendicular "
    "surface meeting it there, on either side. Measuring this room's whole 6 m × 6 m floor, the "
    "outside of the west and south walls (lit by the whole sky) within 1.2 mm of the floor's plane "
    "was counted in the cells along two edges: +11.0 ± 2.6 % in the corner cell; a closed black "
    "box under the sky read 2.3–7.0 lux at its edges where it must read 0. The meter now counts "
    "only the samples of surfaces parallel to it (the stored triangle's normal, core "
    "`IlluminanceMeter::splat_on`) and, on a `--surface`, within that surface's own deviation from "
    "its plane.")


# ---------------------------------------------------------------- time to accuracy (--time-to-accuracy)
#
# Issue 27: on each case, Opticks's time to the case's target against Radiance's time to the same
# target, Radiance's settings searched. A candidate setting reaches the target when every one of
# TTA_SEEDS independent runs reads every point within the target of the closed form: one run's
# max |diff| is a noisy stop criterion (a lucky run passes), and Opticks's SE is NaN at the smallest
# path counts (one chunk of paths), so the criterion is the runs' spread itself, the same for both


def run_cases(run):
    """Append the daylight cases' sections (under one introduction) and verdicts to run."""
    opticks, radiance, sections, verdicts = run.opticks, run.radiance, run.sections, run.verdicts
    # 5.9–5.12 sky component
    closed_q, conv_q = check_quadrature()
    sky_prose = (
        f"A closed room x, y ∈ [−{ROOM_HALF:g}, {ROOM_HALF:g}] m, z ∈ [0, {ROOM_H:g}] m, every surface "
        "black (`plastic` of reflectance 0: only the sky component counts), under a sky dome "
        "without a ground (`source sky 0 0 4 0 0 1 180` alone: below the horizon is black). "
        f"The uniform sky is a constant `glow` of {SKY_LZ:g} cd/m² ({SKY_LZ:g}/179 W/(sr·m²)), not "
        "`gensky -u`, whose skybright.cal blends every sky toward the ground's brightness near the "
        "horizon; the overcast sky is `!gensky -ang 45 0 -c -b "
        f"{SKY_LZ / RADIANCE_EFFICACY:.5f}` (zenith luminance L_z = {SKY_LZ:g} cd/m²; `-b` gives "
        "the zenith radiance), whose luminance is the CIE overcast L_z (1 + 2 cos θ)/3 blended "
        "by gensky toward ρ·7/9·L_z (ρ = 0.2) with weights (cos θ + 1.01)^±10 — the closed "
        "forms below integrate that sky, which both programs read (the pure CIE formula differs "
        "from it by DIFF_CIE at these points). Points on the floor facing up. Closed forms: "
        "E = ∫ L T cos θ_p cos θ_w / r² dA over the opening by Gauss-Legendre quadrature "
        f"(order 48², against order 96² within {conv_q:.0e}); for the uniform sky through an open "
        "opening also the configuration factors — the parallel rectangle's "
        "(L/2) Σ [X/√(1+X²) atan(Y/√(1+X²)) + Y/√(1+Y²) atan(X/√(1+Y²))] for the roof, and "
        "for the wall the perpendicular rectangle's (L/2) [atan X − atan(X/√(1+Z²))/√(1+Z²)], "
        "X = x/c, Z = z/c, c the distance to the wall, the rectangle [0, x] × [0, z] having a "
        "corner at the foot of the perpendicular (Lambert's polygon formula over its edges), "
        "both by superposition over the four corners — which agree with the quadrature within "
        f"{closed_q:.0e}. The daylight factor's E_v,h of gensky's sky is EH_GENSKY lux "
        f"(7π L_z/9 = {7 * math.pi * SKY_LZ / 9:.1f} lux for the pure CIE sky), Opticks's "
        "EH_OPTICKS lux (its environment map's own).")
    sky_prose_points = (
        "**Opticks's sky at a point.** The meter's `connections` estimator gathers a sky's "
        "direct light at a point with a visibility-guided sampler (`sensor/meter/sky.rs`): a pilot "
        "(2 directions in each of 32 × 32 equal-area cells of the hemisphere above the point, "
        "then 2 in each of its 64 × 64 cells within those that saw the sky or lie within two of "
        "one), whose samples are discarded, learns where the sky is seen — here, through the "
        "opening; the fresh directions are drawn 85 % from that guide and 15 % from the sky's own "
        "sampling over the whole sphere, whose density is positive wherever the sky is, so the "
        "estimate stays unbiased wherever the guide is wrong; and as many are drawn as the pilot "
        "predicts for an SE of 0.5 % (256 to 2^20 a point). These cases therefore read with "
        "default settings (the trace is the default 4 M paths, unused at the points: the room is "
        "black). Before this sampler the default 256 directions came from the whole sky (∝ its "
        "luminance), of which only the few through the opening counted: a point's SE was 0–104 % "
        "and these cases needed `--direct-samples 1000000`. A fixed count still works: with "
        f"`--direct-samples {DAYLIGHT_FIXED}` (that many guided directions) a point's SE is "
        "SE_FIXED %. The texel size of the sky map (512 × 257, "
        "0.7°) does not matter for the uniform sky (constant) and little for the overcast sky "
        "(smooth; bilinear).\n\n"
        "**Radiance under a sky** sees the glow only through its ambient sampling (`-ab 1`), a "
        "random stratified hemisphere of `-ad` rays at each point (`-aa 0`: no cache), so its "
        "column changes from run to run; a small opening seen at a grazing angle is hit by few "
        "strata: in an earlier run of this script the façade's uniform-sky points (−2, −2) and "
        "(0, −2) read +13.2 % and −5.4 % (these tables are one run).")

    def daylight_points(title, stem, points_file, analytic, prose, radiance_note=None):
        print(f"{title} …", file=sys.stderr)
        t_trace = opticks.trace(SCENES / f"{stem}.rad", stem)
        extra = []
        overcast = "overcast" in stem
        if overcast:
            extra.append("--daylight-factor")
        meas, t_measure = opticks.measure_points(stem, SCENES / points_file, extra)
        default, _ = opticks.measure_points(stem, SCENES / points_file, ["--direct-samples", DAYLIGHT_FIXED])
        opticks.remove(stem)
        pts = read_points(SCENES / points_file)
        rows = [(f"({p[0]:g}, {p[1]:g})", analytic(p[0], p[1]), m["E_v_lux"], m["SE_v_lux"])
                for p, m in zip(pts, meas)]
        se_default = [100 * d["SE_v_lux"] / a for d, (_, a, _, _) in zip(default, rows)]
        diff_default = [pct(d["E_v_lux"], a) for d, (_, a, _, _) in zip(default, rows)]
        eh = statistics.fmean(m["E_v_lux"] / m["DF_percent"] * 100 for m in meas) if overcast else None
        rlux = rtext = None
        if radiance is not None:
            rlux, rsec, rcmd = radiance.irradiance(SCENES / f"{stem}.rad", pts, RADIANCE_SKY)
            rtext = f"Radiance `{rcmd}` on `testdata/cie171/{stem}.rad`: {rsec:.2f} s (oconv + rtrace)."
            if radiance_note:
                rtext += " " + radiance_note(pts, rows)
        verdicts.append((title, rows, rlux, 2))
        body = [f"## {title}", "", prose, "",
                f"Opticks: `opticks trace testdata/cie171/{stem}.rad` (default settings) and `opticks measure "
                f"--points testdata/cie171/{points_file}"
                f"{' --daylight-factor' if overcast else ''}` (default settings); trace {t_trace:.2f} s, "
                f"measure {t_measure:.2f} s. With `--direct-samples {DAYLIGHT_FIXED}` ({DAYLIGHT_FIXED} guided "
                f"directions): SE {min(se_default):.1f}–{max(se_default):.1f} %, "
                f"diff {min(diff_default):+.1f} to {max(diff_default):+.1f} %."]
        if overcast:
            body[-1] += (f" Daylight factor: Opticks's E_v,h {eh:.2f} lux, so DF = E / E_v,h; e.g. at "
                         f"{rows[0][0]} {100 * rows[0][2] / eh:.3f} % (closed form "
                         f"{100 * rows[0][1] / EH_GENSKY:.3f} %).")
        if rtext:
            body += ["", rtext]
        body += ["", table(rows, rlux), "", summary(rows, rlux, 2), ""]
        sections.append("\n".join(body))
        return se_default, eh

    # gensky -c's horizontal illuminance (midpoint rule on cos θ, 10⁶ steps)
    nmu = 1_000_000
    EH_GENSKY = 2 * math.pi * SKY_LZ * sum(sky_gensky_overcast((k + 0.5) / nmu) * (k + 0.5) / nmu
                                          for k in range(nmu)) / nmu
    diff_cie = [pct(e_quadrature(x, y, k, sky_cie_overcast), e_quadrature(x, y, k, sky_gensky_overcast))
                for k, pts in (("roof", ROOF_XY), ("facade", FACADE_XY)) for x, y in pts]
    rx0, rx1, ry0, ry1 = ROOF_OPENING
    fx0, fx1, fz0, fz1 = FACADE_OPENING
    roof_text = (f"The opening [{rx0:g}, {rx1:g}] × [{ry0:g}, {ry1:g}] m in the roof (z = {ROOM_H:g} m), "
                 "unglazed, zero-thickness.")
    facade_text = (f"The opening x ∈ [{fx0:g}, {fx1:g}] m, z ∈ [{fz0:g}, {fz1:g}] m in the north wall "
                   f"(y = {ROOM_HALF:g} m), unglazed, zero-thickness; the roof closed.")
    daylight_start = len(sections)
    ses, ehs = [], []
    for title, stem, pfile, fn, text in [
        ("5.9 Sky component: roof opening, uniform sky", "sky-roof-uniform", "sky-roof.csv",
         e_roof_uniform, roof_text + " Closed form: the parallel rectangle."),
        ("5.9 Sky component: roof opening, CIE overcast sky", "sky-roof-overcast", "sky-roof.csv",
         lambda x, y: e_quadrature(x, y, "roof", sky_gensky_overcast), roof_text + " Quadrature."),
        ("5.10 Sky component: façade opening, uniform sky", "sky-facade-uniform", "sky-facade.csv",
         e_facade_uniform, facade_text + " Closed form: the perpendicular rectangle."),
        ("5.10 Sky component: façade opening, CIE overcast sky", "sky-facade-overcast", "sky-facade.csv",
         lambda x, y: e_quadrature(x, y, "facade", sky_gensky_overcast), facade_text + " Quadrature."),
    ]:
        se_d, eh = daylight_points(title, stem, pfile, fn, text)
        ses += se_d
        if eh:
            ehs.append(eh)

    pane_text = (
        f"A pane (`glass` of transmissivity 1, index {GLASS_N:g}) fills the opening; the sky is gensky's "
        "CIE overcast sky. The meter's shadow rays pass thin panes (core `ThinDielectric`: Radiance's "
        "`glass`, Mitsuba's `thindielectric`) with the pane's straight-through transmittance "
        "(docs/estimator.md §5; up to 8 panes on a line of sight), so these points read as the open "
        "openings' do, with the same default settings (the pilot finds the light the pane lets through, "
        "so the directions and their number differ from the open case's). Opticks's pane transmits T(θ) = (1 − r)/(1 + r), r the unpolarised "
        f"Fresnel reflectance at n = {GLASS_N:g} (0.918 at normal incidence), which the quadrature "
        "integrates.")

    def radiance_pane_note(kind):
        def note(pts, rows):
            fn_rad = lambda x, y: e_quadrature(x, y, kind, sky_gensky_overcast, t_pane_radiance)  # noqa: E731
            worst = max(abs(pct(fn_rad(p[0], p[1]), a)) for p, (_, a, _, _) in zip(pts, rows))
            return ("Radiance's pane transmits per polarisation ((1 − r_s)/(1 + r_s) + (1 − r_p)/(1 + r_p))/2, "
                    "Opticks's with the unpolarised r: the closed form of Radiance's own pane differs from "
                    f"the column's by up to {worst:.2f} % at these points.")
        return note

    for title, stem, pfile, kind, text in [
        ("5.11 Sky component: glazed roof opening, CIE overcast sky", "sky-roof-glazed", "sky-roof.csv", "roof",
         roof_text.replace("unglazed, zero-thickness", "glazed")),
        ("5.12 Sky component: glazed façade opening, CIE overcast sky", "sky-facade-glazed", "sky-facade.csv",
         "facade", facade_text.replace("unglazed, zero-thickness", "glazed")),
    ]:
        fn = (lambda k: lambda x, y: e_quadrature(x, y, k, sky_gensky_overcast, t_pane_opticks))(kind)
        se_d, eh = daylight_points(title, stem, pfile, fn, text + " " + pane_text + " Quadrature.",
                                   radiance_pane_note(kind))
        ses += se_d
        if eh:
            ehs.append(eh)
    mx0, mx1, my0, my1, mz = ROOF_MASK
    bx0, bx1, by, bh = FACADE_OBST
    conv_o = max(abs(e_obstructed_sky(x, y, k) / e_obstructed_sky(x, y, k, order=96) - 1)
                 for k, pts in (("roof", ROOF_XY), ("facade", FACADE_XY)) for x, y in pts)
    obst_text = (
        "An opaque black obstruction outside the unglazed opening, parallel to it, hides part of the "
        "sky from the points: its central projection from a point onto the opening's plane is an "
        "axis-aligned rectangle, so E = the opening's sky component less that of the part of the "
        "opening the projection covers, both by the quadrature (order 48² against 96² within "
        f"{conv_o:.0e}); gensky's CIE overcast sky as above. A point whose hidden part is empty reads "
        "the open opening's value (a check that the obstruction hides nothing else).")
    for title, stem, pfile, kind, text in [
        ("5.13 Sky component: roof opening with an external obstruction, CIE overcast sky",
         "sky-roof-obstructed", "sky-roof.csv", "roof",
         roof_text + f" A black panel x ∈ [{mx0:g}, {mx1:g}] m, y ∈ [{my0:g}, {my1:g}] m at z = {mz:g} m "
         "(0.5 m above the roof) masks part of the opening."),
        ("5.14 Sky component: façade opening with an external obstruction, CIE overcast sky",
         "sky-facade-obstructed", "sky-facade.csv", "facade",
         facade_text + f" A black wall (a building across the street) x ∈ [{bx0:g}, {bx1:g}] m, "
         f"z ∈ [0, {bh:g}] m in the plane y = {by:g} m, 2 m in front of the façade."),
    ]:
        fn = (lambda k: lambda x, y: e_obstructed_sky(x, y, k))(kind)
        se_d, eh = daylight_points(title, stem, pfile, fn, text + " " + obst_text)
        ses += se_d
    intro = ["## 5.9–5.14 Daylight: the sky component", "",
             sky_prose.replace("DIFF_CIE", f"{min(diff_cie):+.2f} to {max(diff_cie):+.2f} %")
             .replace("EH_GENSKY", f"{EH_GENSKY:.2f}")
             .replace("EH_OPTICKS", f"{statistics.fmean(ehs):.2f}" if ehs else "not read"), "",
             sky_prose_points.replace("SE_FIXED", f"{min(ses):.0f}–{max(ses):.0f}"), "",
             DAYLIGHT_NOTES, ""]
    sections.insert(daylight_start, "\n".join(intro))
