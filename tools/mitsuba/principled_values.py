"""Mitsuba 3's `principled` eval and pdf at fixed directions, pinned in
crates/core/src/bsdf/principled_tests.rs (test `matches_mitsuba_values`).

Run (from the repository root):
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so /work/venv-mitsuba/bin/python \
        tools/mitsuba/principled_values.py > crates/core/src/bsdf/principled_mitsuba.rs && cargo fmt
Prints the Rust tables: per case, per direction pair, f = eval/|cos(theta_o)| (Mitsuba's eval
includes the cosine; Opticks's does not) per channel, and pdf. The cases' parameters are
repeated in principled_tests.rs (`mitsuba_cases`, `mitsuba_trans_cases`), in the same order.

The second table (`MITSUBA_TRANS`, spec_trans > 0) has directions on both sides (theta > 90
is below the surface, inside the object) and Mitsuba's eval in both transport modes: in
`Importance` mode eval(wi, wo) is the physical f(wi -> wo) of light arriving from wi (Opticks's
eval(wi, wo)); in `Radiance` mode it is f(wo -> wi) (Opticks's eval(wo, wi)), which differs
for refraction by Mitsuba's 1/eta^2 radiance scaling.
"""
import mitsuba as mi

from bsdf_values import print_rows, print_table


def rgb(r, g, b):
    return {"type": "rgb", "value": [r, g, b]}


CASES = [
    # (name, dict): the first is every default.
    ("defaults", {"type": "principled"}),
    ("metal_anisotropic_tinted", {"type": "principled", "base_color": rgb(0.8, 0.4, 0.1), "metallic": 0.7,
                                  "roughness": 0.3, "anisotropic": 0.5, "spec_tint": 0.4, "specular": 0.6}),
    ("sheen_clearcoat_flat", {"type": "principled", "base_color": rgb(0.2, 0.5, 0.9), "roughness": 0.8,
                              "sheen": 0.8, "sheen_tint": 0.5, "clearcoat": 0.7, "clearcoat_gloss": 0.6,
                              "flatness": 0.4}),
    ("eta_metal", {"type": "principled", "base_color": rgb(0.9, 0.7, 0.3), "eta": 1.33, "metallic": 1.0,
                   "roughness": 0.1}),
    ("eta_below_one_rates", {"type": "principled", "base_color": rgb(0.6, 0.3, 0.3), "eta": 0.8,
                             "spec_tint": 1.0, "clearcoat": 1.0, "clearcoat_gloss": 0.2, "roughness": 0.4,
                             "metallic": 0.2, "diffuse_reflectance_sampling_rate": 0.5,
                             "main_specular_sampling_rate": 2.0, "clearcoat_sampling_rate": 3.0}),
    ("specular_zero", {"type": "principled", "specular": 0.0, "metallic": 0.5, "roughness": 0.2,
                       "sheen": 1.0}),
]


# (wi, wo) as (theta, phi) in degrees: near the mirror direction, off it, grazing, normal,
# and along both tangent axes (anisotropy).
PAIRS = [
    ((0, 0), (0, 0)),
    ((30, 0), (30, 180)),
    ((30, 0), (35, 170)),
    ((45, 20), (10, 90)),
    ((60, 0), (58, 183)),
    ((60, 90), (55, 275)),
    ((75, 40), (20, 250)),
    ((85, 0), (84, 180)),
    ((10, 0), (80, 45)),
    ((50, 0), (50, 0)),
]


# spec_trans > 0: the transmission lobe, two-sided.
TRANS_CASES = [
    ("trans_full_r02", {"type": "principled", "base_color": rgb(0.9, 0.8, 0.6), "spec_trans": 1.0,
                        "roughness": 0.2}),
    ("trans_03_r06", {"type": "principled", "base_color": rgb(0.2, 0.5, 0.9), "spec_trans": 0.3,
                      "roughness": 0.6, "metallic": 0.2, "sheen": 0.5, "clearcoat": 0.5}),
    ("trans_anisotropic", {"type": "principled", "base_color": rgb(0.7, 0.9, 0.5), "spec_trans": 1.0,
                           "roughness": 0.6, "anisotropic": 0.7, "eta": 1.33, "spec_tint": 0.5}),
    ("trans_03_r02_rates", {"type": "principled", "base_color": rgb(0.5, 0.5, 0.8), "spec_trans": 0.3,
                            "roughness": 0.2, "diffuse_reflectance_sampling_rate": 0.5,
                            "main_specular_sampling_rate": 2.0}),
    ("trans_eta_below_one", {"type": "principled", "spec_trans": 0.7, "roughness": 0.4, "eta": 0.8}),
    ("trans_specular_zero", {"type": "principled", "spec_trans": 1.0, "roughness": 0.2, "specular": 0.0}),
]

# theta > 90: below the surface. Front to back (refraction), back to front (refraction out and
# total internal reflection for eta 1.5 beyond 41.8 degrees), back to back (internal reflection),
# front to front.
TRANS_PAIRS = [
    ((0, 0), (180, 0)),
    ((30, 0), (160, 180)),
    ((45, 20), (150, 200)),
    ((60, 0), (145, 175)),
    ((80, 0), (110, 180)),
    ((150, 0), (45, 180)),
    ((160, 40), (25, 230)),
    ((135, 90), (20, 270)),
    ((140, 0), (140, 180)),
    ((170, 30), (150, 200)),
    ((30, 0), (30, 180)),
    ((50, 0), (130, 0)),
]


def print_trans_table(cases, pairs):
    imp = mi.BSDFContext(mi.TransportMode.Importance)
    rad = mi.BSDFContext(mi.TransportMode.Radiance)
    print("")
    print("/// spec_trans > 0: per pair, f_importance = eval/|cos θ_o| in Importance mode,")
    print("/// f_radiance the same in Radiance mode, per channel, and pdf.")
    print("#[allow(clippy::excessive_precision, clippy::type_complexity)]")
    print("pub(super) const MITSUBA_TRANS: &[(&str, &[((f32, f32), (f32, f32), [f32; 3], [f32; 3], f32)])] = &[")
    print_rows(cases, pairs, [imp, rad])
    print("];")

def main():
    print_table("principled", CASES, PAIRS)
    print_trans_table(TRANS_CASES, TRANS_PAIRS)


if __name__ == "__main__":
    main()
