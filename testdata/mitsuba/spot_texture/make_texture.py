"""Writes slide.png, the 6 x 4 sRGB texture the spot_texture scene's first spot projects
(python3 make_texture.py; the standard library and ../emitter_texture/make_texture.py's PNG
writer). Its texels are distinct colours, one black and no two mirror images of each
other, so that a projection flipped, mirrored, rotated or shifted, or light sent through the
black texel, changes the image."""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "emitter_texture"))
from make_texture import write_png  # noqa: E402

WIDTH, HEIGHT = 6, 4


def texel(i, j):
    if (i, j) == (4, 1):
        return (0, 0, 0)  # a black texel: no light is projected through it
    r = 250 - 35 * i
    g = 50 + 65 * j
    b = 30 + 40 * ((i + 3 * j) % 6)
    return (r, g, b)


def main():
    write_png(os.path.join(os.path.dirname(os.path.abspath(__file__)), "slide.png"), WIDTH, HEIGHT, texel)

if __name__ == "__main__":
    main()
