"""CIE 171:2006 test cases (issue 27): scenes with closed-form illuminance, measured by Opticks
with its default settings and, when pyradiance is installed, by Radiance's `rtrace -I`; writes
docs/validation-cie171.md. The one command that regenerates the report:

    python3 tools/validation/cie171            # from the repository root: runs __main__.py

(any Python 3.9+, e.g. a venv's with pyradiance; without pyradiance the Radiance columns say "not
run"; `python3 -m cie171` from tools/validation/ runs the same). Options: --opticks
(default target/release/opticks), --work (datasets and CSVs, default target/cie171), --doc,
--no-radiance, --scenes-only (write testdata/cie171/ and stop), --time-to-accuracy (also search each
program's cheapest setting to every case's target and time it: the doc's "Time to accuracy against
Radiance" section, ~20 min on 2 cores; without the flag the section of the last such run is kept as
it is), --time-to-accuracy-only (that search alone, spliced into the existing doc).

The scenes and points files are written to testdata/cie171/ (committed: the Rust test
crates/cli/tests/it/cie171.rs reads the same files; rerunning this script rewrites them byte for
byte). Cases:

* 5.2 point source: an isotropic point source of I cd above a black horizontal floor;
  E = I cos³θ / h² at points of the floor.
* 5.3 area sources: a Lambertian rectangle and a Lambertian disc of luminance L parallel to a
  black floor; E = L × (π × the point-to-surface configuration factor), closed forms below.
* 5.7 internal obstructions: 5.3's rectangle with an opaque black rectangle parallel to it
  between the source and the floor; a floor point sees the source less the occluder's central
  projection onto the source's plane (an axis-aligned rectangle: parallel planes), so
  E = L × [π F(source) − π F(source ∩ projected occluder)], both by 5.3's superposition.
* 5.4 / 5.6 flux conservation and diffuse reflection: a closed cube with Lambertian walls of
  reflectance ρ and the point source at its centre; the mean irradiance of the walls is
  Φ / (A (1 − ρ)) (every wall alike, by symmetry).
* 5.8 internal reflected component: the same box; the walls' mean less the direct Φ / A is
  ρ Φ / (A (1 − ρ)), the integrating-sphere relation, exact for a closed enclosure (read from
  5.4 / 5.6's runs).
* 5.5 directional transmittance of clear glass: a parallel (directional) source of normal
  illuminance E_n at incidence θ on a horizontal pane (index 1.52) over a black floor;
  E = E_n cos θ T(θ) at points of the floor, T the pane's straight-through transmittance.
* 5.9–5.12 sky component (daylight): a closed black room with a rectangular opening in its roof
  or in a wall, under a uniform sky (a constant `glow` source) or gensky's CIE overcast sky
  (`!gensky -c`), the opening open or glazed (a `glass` pane); E at points of the floor. The
  uniform sky through an open opening has closed forms (the parallel and perpendicular
  rectangle's configuration factors, checked here against a quadrature); the overcast sky and
  the glazed pane's angular transmittance are integrated numerically over the opening
  (Gauss-Legendre, its convergence checked).
* 5.13 / 5.14 sky component with an external obstruction: the roof and façade openings (open,
  CIE overcast sky) with an opaque black panel over the roof opening / a black wall in front of
  the façade, parallel to the opening; E = the opening's quadrature less that of the part the
  obstruction's central projection covers.

Opticks reads the point-source scenes as Mitsuba XML (its `point` emitter is a true point
source, which a Radiance file cannot express) and the area-source scenes as the same `.rad` files
Radiance reads. Radiance's point source is a `light` sphere of radius RSPHERE whose intensity
L π r² is I.
"""
