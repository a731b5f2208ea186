#!/usr/bin/env python3
"""render_masks.py - per-pixel masks of what the camera sees first, for region tests.

For a scene folder testdata/mitsuba/NAME and shape ids SHAPE... (the `id` of <shape> elements in
its scene.xml), casts SUB x SUB stratified primary rays per pixel (through the centres of a
SUB x SUB grid over the pixel's square, with the scene's own camera, in Mitsuba 3) and writes,
for each shape,
    mask-SHAPE.png   8-bit grey: 255 where EVERY one of the pixel's rays hits SHAPE first
                     (the pixel lies wholly inside the shape's image), else 0;
    mask-SHAPE.exr   the same as 0.0 / 1.0 in three float32 channels (like reference.exr),
and prints each mask's pixel count and the number of partly covered (edge) pixels, which are
excluded. What a mirror or a glass shows is not part of its mask's definition: the mask is the
shape's own silhouette, edges excluded.

Run from the repository root (seconds):
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
    /work/venv-mitsuba/bin/python tools/mitsuba/render_masks.py mirror-glass mirror_box glass_sphere
"""
import argparse
import os
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('name')
    ap.add_argument('shapes', nargs='+')
    ap.add_argument('--scene', default='scene.xml')
    ap.add_argument('--sub', type=int, default=8, help='rays per pixel along each axis')
    args = ap.parse_args()
    if not os.environ.get('DRJIT_LIBLLVM_PATH'):
        os.environ['DRJIT_LIBLLVM_PATH'] = '/usr/lib/x86_64-linux-gnu/libLLVM-19.so'
    import numpy as np
    import drjit as dr
    import mitsuba as mi
    mi.set_variant('llvm_ad_rgb')
    folder = os.path.join(REPO, 'testdata', 'mitsuba', args.name)
    scene = mi.load_file(os.path.join(folder, args.scene))
    sensor = scene.sensors()[0]
    w, h = (int(v) for v in sensor.film().crop_size())
    s = args.sub
    # ray k of pixel (x, y): film position ((x + (i + 0.5) / s) / w, (y + (j + 0.5) / s) / h)
    y, x, j, i = np.meshgrid(np.arange(h), np.arange(w), np.arange(s), np.arange(s), indexing='ij')
    u = ((x + (i + 0.5) / s) / w).ravel()
    v = ((y + (j + 0.5) / s) / h).ravel()
    n = u.size
    ray, _ = sensor.sample_ray(mi.Float(0.0), mi.Float(0.5), mi.Point2f(mi.Float(u), mi.Float(v)),
                               mi.Point2f(0.5, 0.5))
    si = scene.ray_intersect(ray)
    hit_id = np.array(dr.reinterpret_array(mi.UInt32, si.shape), dtype=np.int64)
    valid = np.array(si.is_valid(), dtype=bool)
    hit_id[~valid] = -1
    shapes = {sh.id(): sh for sh in scene.shapes()}
    for name in args.shapes:
        if name not in shapes:
            sys.exit(f'{name}: no shape with that id (have {sorted(shapes)})')
        sid = int(np.array(dr.reinterpret_array(mi.UInt32, mi.ShapePtr(shapes[name])))[0])
        frac = (hit_id == sid).reshape(h, w, s * s).mean(axis=2)
        inside = frac == 1.0
        edge = (frac > 0) & ~inside
        mi.util.write_bitmap(os.path.join(folder, f'mask-{name}.png'),
                             (inside * 255).astype(np.uint8)[..., None], write_async=False)
        rgb = np.repeat(inside.astype(np.float32)[..., None], 3, axis=2)
        mi.Bitmap(np.ascontiguousarray(rgb), pixel_format=mi.Bitmap.PixelFormat.RGB).write(
            os.path.join(folder, f'mask-{name}.exr'))
        print(f'{args.name}/{name}: {int(inside.sum())} pixels inside, {int(edge.sum())} edge '
              f'pixels excluded ({n} rays)')
    return 0


if __name__ == '__main__':
    sys.exit(main())
