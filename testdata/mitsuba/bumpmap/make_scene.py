#!/usr/bin/env python3
"""make_scene.py - writes height.png, the height field of the `bumpmap` test scene
(crates/cli/tests/it/mitsuba_scenes.rs, bidirectional_references.rs).

height.png: 64 x 64, 8-bit grey, h(u, v) = 0.5 + 0.2 sin(2 pi 2u) + 0.2 sin(2 pi (u + 2v)) at the
texel centres (u = (x + 1/2) / 64, v = (y + 1/2) / 64, row 0 the top row), rounded to 8 bits. It
tiles seamlessly (wrap_mode repeat) and has no mirror symmetry in u or v, so that a gradient of
the wrong sign (a map read upside down or mirrored), axes swapped, a wrong dp/du or dp/dv or a
lost `scale` moves the lit and shadowed slopes. Written with normalmap's PNG writer
(../normalmap/make_scene.py). Pure Python, deterministic.
"""
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, '..', 'normalmap'))
from make_scene import png  # noqa: E402


def main():
    n = 64
    rows = []
    for y in range(n):
        row = []
        for x in range(n):
            u, v = (x + 0.5) / n, (y + 0.5) / n
            h = 0.5 + 0.2 * math.sin(2 * math.pi * 2 * u) + 0.2 * math.sin(2 * math.pi * (u + 2 * v))
            row.append(min(255, max(0, round(h * 255.0))))
        rows.append(row)
    png(os.path.join(HERE, 'height.png'), n, n, rows, 1)


if __name__ == '__main__':
    main()
