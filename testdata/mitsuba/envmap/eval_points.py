"""Mitsuba 3's envmap emitter evaluated at a few directions, for the core's unit test
`light::environment::tests::lookup_matches_mitsuba` (which pins these numbers).

The map is 5 x 4 texels, texel (i, j) = (1 + i + 10 j, 2 + 3 i, 0.5 + j) (row j from the top), the
emitter rotated by to_world = rotate(axis (1, 2, 3)/√14, 40 degrees). Prints, per direction d (from the
scene toward the environment), d and Mitsuba's radiance L(d).

    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so /work/venv-mitsuba/bin/python \
        testdata/mitsuba/envmap/eval_points.py
"""
import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")
W, H = 5, 4
img = np.zeros((H, W, 3), dtype=np.float32)
for j in range(H):
    for i in range(W):
        img[j, i] = (1 + i + 10 * j, 2 + 3 * i, 0.5 + j)
emitter = mi.load_dict({
    "type": "envmap",
    "bitmap": mi.Bitmap(img),
    "to_world": mi.ScalarTransform4f().rotate(list(np.array([1, 2, 3]) / np.sqrt(14)), 40),
})
dirs = [(0, 1, 0), (0, -1, 0), (1, 0, 0), (0, 0, -1), (0.3, 0.5, -0.8), (-0.7, 0.1, 0.2),
        (0.05, -0.9, 0.4), (0.9, 0.3, 0.3), (-0.2, -0.2, -0.95)]
for d in dirs:
    d = np.array(d, dtype=np.float64)
    d /= np.linalg.norm(d)
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(-d)
    v = emitter.eval(si)
    print(f"([{d[0]:.9f}, {d[1]:.9f}, {d[2]:.9f}], [{v[0]:.6f}, {v[1]:.6f}, {v[2]:.6f}]),")
m = np.array(mi.ScalarTransform4f().rotate(list(np.array([1, 2, 3]) / np.sqrt(14)), 40).matrix)
print("to_world rows:", [[f"{x:.9f}" for x in r[:3]] for r in m[:3]])
