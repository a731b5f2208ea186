"""5.2, 5.3 and 5.7: a source over a black floor, each program at the points of the floor."""
import statistics
import sys

from .closed_forms import (AREA_H, AREA_L, DISC_R, FLOOR_HALF, OBST_H, OBST_RECT, POINT_H, POINT_I, RECT,
                           RSPHERE, SCENES, e_disc, e_obstructed, e_point, e_rect)
from .opticks import read_points
from .radiance import RADIANCE_DIRECT
from .report import pct, summary, table


def run_cases(run):
    """Append 5.2's, 5.3's and 5.7's sections and verdicts to run."""
    opticks, radiance, sections, verdicts = run.opticks, run.radiance, run.sections, run.verdicts
    def direct_case(title, tag, scene, rad_scene, points_file, analytic, prose, rel=""):
        print(f"{title} …", file=sys.stderr)
        t_trace = opticks.trace(SCENES / scene, tag)
        meas, t_measure = opticks.measure_points(tag, SCENES / points_file)
        opticks.remove(tag)
        pts = read_points(SCENES / points_file)
        rows = [(f"({p[0]:g}, {p[1]:g})", analytic(p[0], p[1]), m["E_v_lux"], m["SE_v_lux"])
                for p, m in zip(pts, meas)]
        rlux = rtext = None
        if radiance is not None:
            rlux, rsec, rcmd = radiance.irradiance(SCENES / rad_scene, pts, RADIANCE_DIRECT)
            rtext = f"Radiance `{rcmd}` on `testdata/cie171/{rad_scene}`: {rsec:.2f} s (oconv + rtrace)."
        verdicts.append((title, rows, rlux, 1))
        body = [f"## {title}", "", prose, "",
                f"Opticks: `opticks trace testdata/cie171/{scene}` (default settings: 4 M paths) and "
                f"`opticks measure --points testdata/cie171/{points_file}` (default settings: the "
                f"connections estimator); trace {t_trace:.2f} s, measure {t_measure:.2f} s.{rel}"]
        if rtext:
            body.append("")
            body.append(rtext)
        body += ["", table(rows, rlux), "", summary(rows, rlux), ""]
        sections.append("\n".join(body))

    x0, x1, y0, y1 = RECT
    direct_case(
        "5.2 Point source", "point", "point.xml", "point.rad", "point.csv", e_point,
        f"An isotropic point source of I = {POINT_I:g} cd, h = {POINT_H:g} m above the centre of a "
        f"{2 * FLOOR_HALF:g} m × {2 * FLOOR_HALF:g} m black floor (z up, the floor's centre at the "
        "origin); points on the floor facing up. Closed form E = I cos³θ / h² (θ from the nadir). "
        f"Opticks reads Mitsuba XML (`<emitter type=\"point\">`, {POINT_I:g}/683 W/sr of white "
        "light, so that its 683 lm/W lux are the candela's); Radiance has no point source and "
        f"reads a `light` sphere of radius {RSPHERE:g} m and radiance I / (179 π r²) "
        "(`point.rad`). The point light's direct light at a point is exact in Opticks (a shadow "
        "ray, no sampling): its SE is 0.",
        " The dataset is not needed for the direct light of a point source (the floor is black).")
    direct_case(
        "5.3 Area source: rectangle", "rect", "rect.rad", "rect.rad", "rect.csv", e_rect,
        f"A Lambertian rectangle [{x0:g}, {x1:g}] × [{y0:g}, {y1:g}] m of luminance L = {AREA_L:g} "
        f"cd/m², facing down, h = {AREA_H:g} m above a black 4 m × 4 m floor; points on the "
        "floor facing up, under the centre, a corner and the edges of the source and off its "
        "side. Closed form, for a point under a corner of a parallel rectangle of sides a, b: "
        "E = (L/2) [X/√(1+X²) atan(Y/√(1+X²)) + Y/√(1+Y²) atan(X/√(1+Y²))], X = a/h, Y = b/h, "
        "combined over the four corners by superposition (signed sides). Both programs read the "
        "same `.rad` file (Radiance's photometry: L = 1000/179 W/(sr·m²)).")
    direct_case(
        "5.3 Area source: disc", "disc", "disc.rad", "disc.rad", "disc.csv", e_disc,
        f"A Lambertian disc of radius R = {DISC_R:g} m and luminance L = {AREA_L:g} cd/m² "
        f"(a Radiance `ring`), facing down, centred h = {AREA_H:g} m above the floor's centre; "
        "points at offsets a from the axis. Closed form E = π L · ½ [1 − (h² + a² − R²) / "
        "√((h² + a² + R²)² − 4a²R²)] (π L R² / (h² + R²) on the axis). Opticks tessellates the "
        "ring into a 128-gon of the disc's exact area; Radiance's ring is exact.")

    ox0, ox1, oy0, oy1 = OBST_RECT
    direct_case(
        "5.7 Internal obstruction", "obstruct", "obstruct.rad", "obstruct.rad", "obstruct.csv", e_obstructed,
        f"5.3's source (the Lambertian rectangle [{x0:g}, {x1:g}] × [{y0:g}, {y1:g}] m of "
        f"{AREA_L:g} cd/m², facing down, h = {AREA_H:g} m above the black floor) with an opaque "
        f"black rectangle [{ox0:g}, {ox1:g}] × [{oy0:g}, {oy1:g}] m parallel to it at "
        f"h_o = {OBST_H:g} m, between the source and the floor; points on the floor facing up, in "
        "its penumbra (part of the source hidden, along one edge of it or at a corner) and one out "
        "of it. Closed form: the planes being parallel, what the occluder hides from a floor "
        "point P is its central projection from P onto the source's plane — the occluder scaled "
        "by h / h_o about P, an axis-aligned rectangle — intersected with the source; E is "
        "additive over the source's area, so E = E_rect(source) − E_rect(hidden part), each by "
        "5.3's corner superposition (signed sides). The occluder is a black `plastic` polygon "
        "(reflectance 0, so the reflected component is 0); both programs read the same `.rad` "
        "file.")
    if radiance is not None:
        # Radiance's penumbra: a finer -ds, and jittered shadow rays averaged over runs.
        pts = read_points(SCENES / "obstruct.csv")
        fine = [o if o != "0.01" else "0.001" for o in RADIANCE_DIRECT]
        rfine, _, _ = radiance.irradiance(SCENES / "obstruct.rad", pts, fine)
        reps = 200
        jitter = [o if k == 0 or RADIANCE_DIRECT[k - 1] != "-dj" else "1" for k, o in enumerate(RADIANCE_DIRECT)]
        rj, rjsec, rjcmd = radiance.irradiance(SCENES / "obstruct.rad", [p for p in pts for _ in range(reps)], jitter)
        rjmean = [statistics.fmean(rj[k * reps:(k + 1) * reps]) for k in range(len(pts))]
        ana = [e_obstructed(p[0], p[1]) for p in pts]
        worst_fine = max(abs(pct(r, a)) for r, a in zip(rfine, ana))
        worst_j = max(abs(pct(r, a)) for r, a in zip(rjmean, ana))
        sections[-1] = sections[-1].rstrip("\n") + "\n\n" + (
            "**Radiance in the penumbra.** Its column's settings cast one shadow ray to the centre of "
            "each piece of the subdivided source (`-dj 0`), so a piece is lit or shadowed whole; the "
            "subdivision is capped, and `-ds 0.001` instead of 0.01 still reads up to "
            f"{worst_fine:.2f} % off. With jittered shadow rays (`{rjcmd}`) averaged over {reps} runs "
            f"per point ({rjsec:.2f} s in all) it reads within {worst_j:.2f} %.\n")
