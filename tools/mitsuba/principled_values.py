"""Mitsuba 3's `principled` eval and pdf at fixed directions, pinned in
crates/core/src/bsdf/principled_tests.rs (test `matches_mitsuba_values`).

Run (from the repository root):
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so /work/venv-mitsuba/bin/python \
        tools/mitsuba/principled_values.py > crates/core/src/bsdf/principled_mitsuba.rs && cargo fmt
Prints the Rust table: per case, per direction pair, f = eval/cos(theta_o) (Mitsuba's eval
includes the cosine; Opticks's does not) per channel, and pdf. The cases' parameters are
repeated in principled_tests.rs (`mitsuba_cases`), in the same order.
"""
from bsdf_values import print_table


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


def main():
    print_table("principled", CASES, PAIRS)


if __name__ == "__main__":
    main()
