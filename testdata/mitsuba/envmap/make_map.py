"""Writes sky.exr, the 32 x 16 lat-long map of the `envmap` test scene (crates/cli/tests/it/environment.rs):
a dim blue sky brightening toward the horizon, a darker ground half and a bright 2 x 2 texel
"sun" at rows 3-4 (about 45 degrees above the horizon), columns 6-7.

    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so /work/venv-mitsuba/bin/python \
        testdata/mitsuba/envmap/make_map.py
"""
import os
import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")
W, H = 32, 16
img = np.zeros((H, W, 3), dtype=np.float32)
for j in range(H):
    t = j / (H - 1)  # 0 at the zenith, 1 at the nadir
    if t < 0.5:
        img[j, :] = (0.25 + 0.5 * t, 0.35 + 0.5 * t, 0.7 + 0.2 * t)
    else:
        img[j, :] = (0.15, 0.12, 0.1)
for i in range(W):
    img[:, i] *= 1.0 + 0.3 * np.cos(2 * np.pi * i / W)  # a little variation in azimuth
img[3:5, 6:8] = (60.0, 50.0, 40.0)
mi.Bitmap(img).write(os.path.join(os.path.dirname(os.path.abspath(__file__)), "sky.exr"))
