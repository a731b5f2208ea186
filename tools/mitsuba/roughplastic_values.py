"""Mitsuba 3's `roughplastic` eval and pdf at fixed directions, pinned in
crates/core/src/bsdf/roughplastic.rs (test `matches_mitsuba_values`).

Run (from the repository root):
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so /work/venv-mitsuba/bin/python \
        tools/mitsuba/roughplastic_values.py > crates/core/src/bsdf/roughplastic_mitsuba.rs && cargo fmt
Prints the Rust table: per case, per direction pair, f = eval/cos(theta_o) (Mitsuba's eval
includes the cosine; Opticks's does not) per channel, and pdf.
"""
from bsdf_values import print_table

CASES = [
    # (name, dict): the first is every default.
    ("defaults", {"type": "roughplastic"}),
    ("ggx_nonlinear", {"type": "roughplastic", "distribution": "ggx", "alpha": 0.3, "nonlinear": True,
                       "diffuse_reflectance": {"type": "rgb", "value": [0.8, 0.4, 0.1]}}),
    ("beckmann_rough_not_visible", {"type": "roughplastic", "alpha": 0.5, "sample_visible": False,
                                    "int_ior": 1.7, "ext_ior": 1.1,
                                    "diffuse_reflectance": {"type": "rgb", "value": [0.2, 0.5, 0.9]}}),
    ("ggx_specular", {"type": "roughplastic", "distribution": "ggx", "alpha": 0.08, "int_ior": 1.9,
                      "specular_reflectance": {"type": "rgb", "value": [0.7, 0.6, 0.5]},
                      "diffuse_reflectance": {"type": "rgb", "value": [0.3, 0.3, 0.3]}}),
]


# (wi, wo) as (theta, phi) in degrees: near the mirror direction, off it, grazing, normal.
PAIRS = [
    ((0, 0), (0, 0)),
    ((30, 0), (30, 180)),
    ((30, 0), (35, 170)),
    ((45, 20), (10, 90)),
    ((60, 0), (58, 183)),
    ((75, 40), (20, 250)),
    ((85, 0), (84, 180)),
    ((10, 0), (80, 45)),
    ((50, 0), (50, 0)),
]


def main():
    print_table("roughplastic", CASES, PAIRS)


if __name__ == "__main__":
    main()
