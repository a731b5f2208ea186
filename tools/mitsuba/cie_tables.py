#!/usr/bin/env python3
"""Writes crates/io/src/scene_formats/mitsuba/cie.rs: the tables Mitsuba 3 converts spectra to
RGB with (include/mitsuba/core/spectrum.h): the CIE 1931 2-degree colour matching functions and
the CIE D65 illuminant (normalised to luminance 1) at Mitsuba's 95 nodes, 360-830 nm every 5 nm,
read from Mitsuba itself (`cie1931_xyz`, `cie_d65` at the nodes), and checks the Rust
conversion's rule on a few spectra against Mitsuba's `spectrum_list_to_srgb` (the expected
values it prints are pinned in the unit tests of spectrum.rs).

Usage:
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so \
        /work/venv-mitsuba/bin/python tools/mitsuba/cie_tables.py
"""
import os

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(REPO, 'crates/io/src/scene_formats/mitsuba/cie.rs')


def main():
    import mitsuba as mi
    mi.set_variant('scalar_rgb')
    rows = []
    for i in range(95):
        w = 360.0 + 5.0 * i
        x, y, z = (float(v) for v in mi.cie1931_xyz(w))
        rows.append((w, x, y, z, float(mi.cie_d65(w))))
    with open(OUT, 'w') as o:
        o.write('//! The CIE tables of Mitsuba 3\'s spectrum-to-RGB conversion, at its 95 nodes (360–830 nm,\n'
                '//! every 5 nm): the CIE 1931 2° colour matching functions x̄, ȳ, z̄ and the D65 illuminant\n'
                '//! normalised to luminance 1. Written by `tools/mitsuba/cie_tables.py` from Mitsuba itself; do\n'
                '//! not edit by hand. Used by [`super::spectrum`].\n\n'
                '/// (x̄, ȳ, z̄, D65) at 360 + 5·i nm.\n'
                'pub const NODES: [[f32; 4]; 95] = [\n')
        import numpy as np
        f = lambda v: str(np.float32(v))  # the shortest decimal that is this f32
        for w, x, y, z, d in rows:
            o.write(f'    [{f(x)}, {f(y)}, {f(z)}, {f(d)}], // {int(w)} nm\n')
        o.write('];\n')
    for w, v, bounded, d65 in [([400, 500, 600, 700], [0.1, 0.9, 0.3, 0.5], True, True),
                               ([400, 500, 600, 700], [0.1, 0.9, 0.3, 0.5], False, False),
                               ([300, 900], [1.0, 1.0], False, False)]:
        print(w, v, bounded, d65, [float(c) for c in mi.spectrum_list_to_srgb(w, v, bounded, d65)])


if __name__ == '__main__':
    main()
