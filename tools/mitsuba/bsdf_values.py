"""What the `*_values.py` scripts share: Mitsuba 3's eval and pdf of a list of BSDFs at fixed
direction pairs, printed as the Rust table a BSDF's tests pin (per case, per pair, f =
eval/cos(theta_o) per channel -- Mitsuba's eval includes the cosine, Opticks's does not -- and
pdf). Imported by tools/mitsuba/principled_values.py and roughplastic_values.py.
"""
import math

import mitsuba as mi

mi.set_variant("scalar_rgb")


def direction(theta_deg, phi_deg):
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return [math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)]


def print_table(kind, cases, pairs):
    """The table `crates/core/src/bsdf/<kind>_mitsuba.rs` of Mitsuba's `kind` BSDF: each of
    `cases` (name, dict) at each of `pairs` ((theta, phi) of wi, of wo, in degrees)."""
    ctx = mi.BSDFContext()
    print("//! Mitsuba 3's own `%s` values, pinned by `super::%s`'s tests: generated" % (kind, kind))
    print("//! by tools/mitsuba/%s_values.py (Mitsuba %s). Per case, (wi θ, φ), (wo θ, φ) in" % (kind, mi.__version__))
    print("//! degrees, f = eval/cos θ_o per channel, pdf.")
    print("")
    print("#[allow(clippy::excessive_precision, clippy::type_complexity)]")
    print("pub(super) const MITSUBA: &[(&str, &[((f32, f32), (f32, f32), [f32; 3], f32)])] = &[")
    print_rows(cases, pairs, [ctx])
    print("];")


def print_rows(cases, pairs, contexts):
    """The rows of each of `cases` (name, dict) at each of `pairs`: (wi theta, phi), (wo theta,
    phi), then f = eval/|cos theta_o| per channel in each of `contexts` (transport modes), then
    the pdf in the first context."""
    for name, d in cases:
        bsdf = mi.load_dict(d)
        print('    ("%s", &[' % name)
        for (ti, pi), (to, po) in pairs:
            si = mi.SurfaceInteraction3f()
            si.wi = mi.Vector3f(direction(ti, pi))
            wo = mi.Vector3f(direction(to, po))
            cos_o = abs(wo[2])
            fs = []
            for ctx in contexts:
                value = bsdf.eval(ctx, si, wo)
                fs.append("[%.8e, %.8e, %.8e]" % tuple(value[c] / cos_o for c in range(3)))
            pdf = bsdf.pdf(contexts[0], si, wo)
            print("        ((%r, %r), (%r, %r), %s, %.8e)," % (
                float(ti), float(pi), float(to), float(po), ", ".join(fs), float(pdf)))
        print("    ]),")
