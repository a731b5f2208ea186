#!/usr/bin/env python3
"""Writes crates/io/src/scene_formats/mitsuba/conductors.rs: the RGB complex index of refraction
(eta, k) of each of Mitsuba's named conductors (`<string name="material" value="Au"/>`), exactly
as Mitsuba 3's RGB variants derive them (`ior_from_file` in include/mitsuba/render/ior.h): the
tabulated spectrum of data/ior/NAME.eta.spd and NAME.k.spd (the published tables Mitsuba ships,
from the mitsuba-data repository: luxpop.com and Palik's handbook) is integrated against the CIE
1931 2-degree colour matching functions (no illuminant: d65 = false, 1000 steps over 360-830 nm,
linear interpolation, zero outside the table), scaled so that the constant spectrum 1 has Y = 1,
converted XYZ -> linear sRGB, and negative channels clamped to 0 (unbounded above). This script
calls Mitsuba's own `spectrum_list_to_srgb` on the same files, and checks each value against a
`conductor` plugin Mitsuba instantiates with that material.

Usage (the .spd files: the `ior/` folder of a mitsuba-data checkout):
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so \
        /work/venv-mitsuba/bin/python tools/mitsuba/conductor_presets.py IOR_DIR
"""
import os
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(REPO, 'crates/io/src/scene_formats/mitsuba/conductors.rs')


def main():
    ior_dir = sys.argv[1]
    import mitsuba as mi
    mi.set_variant('scalar_rgb')
    names = sorted({f[:-len('.eta.spd')] for f in os.listdir(ior_dir) if f.endswith('.eta.spd')})
    rows = []
    for name in names:
        rgb = []
        for part in ('eta', 'k'):
            w, v = mi.spectrum_from_file(os.path.join(ior_dir, f'{name}.{part}.spd'))
            rgb.append([float(x) for x in mi.spectrum_list_to_srgb(w, v, False, False)])
        params = mi.traverse(mi.load_dict({'type': 'conductor', 'material': name}))
        for part, ours in zip(('eta', 'k'), rgb):
            theirs = [float(x) for x in params[f'{part}.value']]
            assert all(abs(a - b) <= 1e-4 * max(1.0, abs(b)) for a, b in zip(ours, theirs)), (name, part, ours, theirs)
        rows.append((name, rgb[0], rgb[1]))
    fmt = lambda c: 'Rgb::new({:.6}, {:.6}, {:.6})'.format(*c)
    with open(OUT, 'w') as o:
        o.write('//! Mitsuba\'s named conductors (`<string name="material" value="Au"/>` in a `conductor` or\n'
                '//! `roughconductor`) as RGB complex indices of refraction η + iκ, derived from Mitsuba\'s\n'
                '//! spectral tables exactly as its RGB variants derive them (the rule is in\n'
                '//! `tools/mitsuba/conductor_presets.py`, which wrote this file; do not edit by hand).\n\n'
                'use opticks_core::math::Rgb;\n\n'
                '/// (name, η, κ), sorted by name.\n'
                'pub const CONDUCTORS: &[(&str, Rgb, Rgb)] = &[\n')
        for name, eta, k in rows:
            o.write(f'    ("{name}", {fmt(eta)}, {fmt(k)}),\n')
        o.write('];\n\n/// The η and κ of the named conductor `name`.\npub fn named(name: &str) -> Option<(Rgb, Rgb)> {\n'
                '    CONDUCTORS.iter().find(|(n, _, _)| *n == name).map(|&(_, eta, k)| (eta, k))\n}\n')
    print(f'wrote {len(rows)} conductors to {OUT}')


if __name__ == '__main__':
    main()
