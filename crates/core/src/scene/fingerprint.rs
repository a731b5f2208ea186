//! Content fingerprints: a dataset is only valid for the scene it was traced in.
//!
//! Two hashes (BLAKE3, 128 bits each): `geometry` covers triangles and their materials (the
//! reflectance each triangle has, not the index of its material in the scene's list) — it must
//! match for a dataset to be rendered; `lights` covers the lights' names and shapes (where and
//! how they emit, not how much) — it may change (adding a light) without invalidating the stored
//! samples of the other lights, which are checked one by one with their own shape hashes.
//!
//! Which triangles emit is deliberately not part of `geometry`: a surface that becomes a light
//! changes nothing the stored paths saw (they were reflected by the same triangles with the same
//! BSDFs), so `add-light` accepts it. New or moved triangles, or a changed reflectance, are
//! refused: they would occlude or reflect the old lights' light, and the stored paths never saw
//! them. (Datasets of format version 1 recorded an older hash that also covered emission; the
//! scene keeps it as `Scene::geometry_v1` so they still match their scene.)
//!
//! # The encoding is a file-format contract
//!
//! Every dataset on disk records these hashes, so the bytes they are computed from are as frozen
//! as the dataset format itself: a change to any of them refuses every dataset ever traced. They
//! are therefore spelled out here, byte by byte, and depend on no `Debug` impl, no field or type
//! name of the Rust code and no library's formatting (renaming a field or upgrading glam changes
//! nothing). `crates/cli/tests/it/fingerprints.rs` pins the hashes of the reference scenes and renders datasets
//! written before this encoding was written out.
//!
//! ## Version 2 (the current one, [`Fingerprint::VERSION`])
//!
//! All numbers are little-endian; `f32` means the 4 bytes of the IEEE-754 value; a hash is the
//! first 16 bytes of the BLAKE3 digest of its input, which starts with an ASCII *domain* string
//! (the `v1`/`v2` in the domain strings are historical parts of the constants, not versions).
//!
//! * **Material text** (`material_v2`): ASCII text of the BSDF, `|`, then `true` or `false`
//!   (two-sided or not; written for dielectrics too, which ignore it). The material's name is not
//!   part of it. Numbers (`num`) are written as Rust's `{:?}` of `f32`: the shortest decimal that
//!   reads back to the same value, with at least one fractional digit (`1.0`, `0.885809`), in
//!   exponent form below 10⁻⁴ or from 10¹⁶ on (`1e-7`, `1.6e17`), `-0.0` for negative zero. A
//!   colour `rgb` is `Vec3(` num `, ` num `, ` num `)`. The BSDFs:
//!
//!   ```text
//!   Lambert(Lambert { reflectance: rgb })
//!   ModifiedPhong(ModifiedPhong { kd: rgb, ks: rgb, exponent: num })
//!   SmoothConductor(SmoothConductor { specular_reflectance: rgb, ior: IOR })
//!   SmoothDielectric(SmoothDielectric { eta: num, specular_reflectance: rgb, specular_transmittance: rgb, absorption: rgb })
//!   RoughConductor(RoughConductor { microfacet: MF, specular_reflectance: rgb, ior: IOR })
//!   RoughDielectric(RoughDielectric { eta: num, microfacet: MF, specular_reflectance: rgb, specular_transmittance: rgb, absorption: rgb })
//!   IOR = None | Some((rgb, rgb))            (η, then κ, of the conductor)
//!   MF  = Microfacet { distribution: Ggx, alpha_u: num, alpha_v: num }   (or Beckmann)
//!   ```
//!
//!   e.g. `Lambert(Lambert { reflectance: Vec3(0.5, 0.5, 0.5) })|true`. (This is the text
//!   `format!("{:?}|{}", bsdf, two_sided)` produced when fingerprints were introduced; it is now
//!   written field by field and no longer follows the Rust types.)
//! * **Material hash**: domain `opticks material`, then the material text.
//! * **Geometry hash**: domain `opticks geometry v2`, then for each triangle the scene keeps (in
//!   scene order: meshes in order, their triangles in order, zero-area ones dropped, each wound so
//!   that its front faces its vertex normals): its corners a, b, c (9 × f32), the 16-byte
//!   material hash of its material and, if it has shading normals (vertex normals not all within
//!   10⁻⁵ of its geometric normal), its three unit vertex normals (9 × f32); if its material is
//!   textured, its texture coordinates (6 × f32, if it has them) and the corner values of each
//!   mesh attribute a texture reads; if its material is anisotropic (`Bsdf::is_anisotropic`, or a
//!   texture on `alpha_u`, `alpha_v` or `anisotropic`) and it has texture coordinates, the 5
//!   bytes `dp/du` and its texture coordinates (6 × f32). That last part was added to version 2
//!   when such a BSDF's frame began to follow ∂p/∂u (Mitsuba's orientation): a dataset traced
//!   before was reflected in another frame on those triangles, and must be refused, not
//!   rendered (the version-1 geometry hash below takes the same bytes).
//! * **Light shape hash** (`light_shape`): domain `opticks light shape v1`, then
//!   * an area light: `lambertian area`; unless its profile is cosine (Lambertian), the profile
//!     bytes; if the profile is an IES table, the unit tangent of horizontal angle 0° (3 × f32);
//!     then for each of its triangles v0, v1 − v0, v2 − v0 (9 × f32);
//!   * a point light: `isotropic point`, its position (3 × f32); unless its profile is uniform
//!     over the sphere, the profile bytes and the frame's x then z axis (6 × f32); if it
//!     projects a texture, `projected texture` and the texture's bytes (as an area light's);
//!   * a directional light: `directional`, its unit direction, the centre of the disc it is
//!     emitted from (3 × f32 each) and the disc's radius (f32);
//!   * an environment: `environment`, its frame (the rotation's 3 columns, 9 × f32), the
//!     centre of the scene's bounding sphere (3 × f32) and its radius (f32), then `constant`,
//!     or `lat-long map`, the map's width and height after padding (u64 each), its scale (f32)
//!     and its texels (row-major from the top row, RGB, 3 × f32 each) — a changed map is a
//!     changed light even where only its colour changed;
//!
//!   where the profile bytes are `uniform sphere....` or `uniform hemisphere` (18 bytes each),
//!   `cosine`, `cosine power` + n (f32), `spot` + cutoff γ + beam β (radians, f32 each), or
//!   `table` + the refined grid's θ nodes (radians), φ nodes (radians) and candela values
//!   (θ-major), all f32. Power and colour are not part of a shape.
//! * **Lights hash**: domain `opticks lights v1`, then for each light in scene order (area lights
//!   in mesh order, point lights, directional lights, environments) its name (UTF-8) and its shape hash.
//! * **Version-1 geometry hash** (`Scene::geometry_v1`, what format-1 datasets recorded): domain
//!   `opticks geometry v1`, then per kept triangle its corners (9 × f32), its material index and
//!   its light index (u32 each, `u32::MAX` if it does not emit) and, if it has shading normals,
//!   those (9 × f32); then the material text of every material of the description, in order
//!   (used or not).
//!
//! ## Introducing a new version
//!
//! A version is never edited once datasets carry it. A new one (say a binary material encoding,
//! or a new BSDF field that old materials do not have) adds its encoders beside these under new
//! names (`material_v3`…) with new domain strings, bumps [`Fingerprint::VERSION`], and keeps
//! computing the version-2 hashes, exactly as the version-1 geometry hash is kept today: the
//! scene check accepts a dataset whose recorded hash equals the scene's hash in any version it
//! still computes, and `refine`/`add-light` record the current one. A new BSDF variant or light
//! kind can instead extend version 2, since no existing dataset contains it: give it its own
//! text or tag that no existing encoding can produce. Every struct below is destructured field by
//! field, so adding a field to a BSDF does not compile until its encoding is decided here.

use crate::bsdf::{
    Blend, Bsdf, Lambert, Material, ModifiedPhong, Plastic, Principled, PrincipledThin, RoughConductor,
    RoughDielectric, RoughPlastic, SmoothConductor, SmoothDielectric, ThinDielectric,
};
use crate::geometry::Triangle;
use crate::light::{BuiltProfile, EnvRadiance, Light};
use crate::math::Rgb;
use crate::sampling::microfacet::{Distribution, Microfacet};
use std::fmt::Write;

/// The scene's content hashes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Fingerprint {
    /// Hash of world-space triangles and their materials (not of which emit).
    pub geometry: [u8; 16],
    /// Hash of the lights' names and shapes (not their powers).
    pub lights: [u8; 16],
}

impl Fingerprint {
    /// The version of the encodings these hashes are computed from (see the module docs):
    /// datasets of format version 2 record hashes of this version.
    pub const VERSION: u32 = 2;

    /// Short hexadecimal form of the geometry hash, for messages.
    pub fn geometry_hex(&self) -> String {
        hex(&self.geometry)
    }

    /// Short hexadecimal form of the light hash, for messages.
    pub fn lights_hex(&self) -> String {
        hex(&self.lights)
    }
}

fn hex(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02x}")).collect()
}

/// Incremental hasher over little-endian numbers.
pub(crate) struct Hasher(pub(crate) blake3::Hasher);

impl Hasher {
    pub(crate) fn new(domain: &str) -> Self {
        let mut h = blake3::Hasher::new();
        h.update(domain.as_bytes());
        Hasher(h)
    }
    pub(crate) fn f32s(&mut self, v: &[f32]) {
        // One update for the slice: the same stream as one a value, without the per-call cost.
        let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
        self.0.update(&bytes);
    }
    pub(crate) fn finish(&self) -> [u8; 16] {
        let mut out = [0u8; 16];
        out.copy_from_slice(&self.0.finalize().as_bytes()[..16]);
        out
    }
}

/// The material text of encoding version 2 (module docs): the BSDF field by field, `|`, the
/// sidedness.
pub(crate) fn material_v2(material: &Material) -> String {
    let Material { name: _, bsdf, two_sided } = material;
    let mut t = Text(String::new());
    bsdf_v2(&mut t, bsdf);
    t.0.push('|');
    t.0.push_str(if *two_sided { "true" } else { "false" });
    t.0
}

/// The BSDF's record of [`material_v2`], closed (` })`); a blend's children are records within.
fn bsdf_v2(t: &mut Text, bsdf: &Bsdf) {
    match bsdf {
        Bsdf::Lambert(Lambert { reflectance }) => {
            t.variant("Lambert").rgb("reflectance", *reflectance);
        }
        Bsdf::ModifiedPhong(ModifiedPhong { kd, ks, exponent }) => {
            t.variant("ModifiedPhong").rgb("kd", *kd).rgb("ks", *ks).num("exponent", *exponent);
        }
        Bsdf::SmoothConductor(SmoothConductor { specular_reflectance, ior }) => {
            t.variant("SmoothConductor").rgb("specular_reflectance", *specular_reflectance).ior("ior", ior);
        }
        Bsdf::SmoothDielectric(SmoothDielectric {
            eta,
            specular_reflectance,
            specular_transmittance,
            absorption,
        }) => {
            t.variant("SmoothDielectric")
                .num("eta", *eta)
                .rgb("specular_reflectance", *specular_reflectance)
                .rgb("specular_transmittance", *specular_transmittance)
                .rgb("absorption", *absorption);
        }
        Bsdf::RoughConductor(RoughConductor { microfacet, specular_reflectance, ior }) => {
            t.variant("RoughConductor")
                .microfacet("microfacet", microfacet)
                .rgb("specular_reflectance", *specular_reflectance)
                .ior("ior", ior);
        }
        Bsdf::RoughDielectric(RoughDielectric {
            eta,
            microfacet,
            specular_reflectance,
            specular_transmittance,
            absorption,
        }) => {
            t.variant("RoughDielectric")
                .num("eta", *eta)
                .microfacet("microfacet", microfacet)
                .rgb("specular_reflectance", *specular_reflectance)
                .rgb("specular_transmittance", *specular_transmittance)
                .rgb("absorption", *absorption);
        }
        // The private fields are functions of these.
        Bsdf::Plastic(Plastic { diffuse_reflectance, specular_reflectance, eta, nonlinear, .. }) => {
            t.variant("Plastic")
                .rgb("diffuse_reflectance", *diffuse_reflectance)
                .rgb("specular_reflectance", *specular_reflectance)
                .num("eta", *eta)
                .num("nonlinear", if *nonlinear { 1.0 } else { 0.0 });
        }
        // The private fields are functions of these.
        Bsdf::RoughPlastic(RoughPlastic {
            diffuse_reflectance,
            specular_reflectance,
            eta,
            microfacet,
            sample_visible,
            nonlinear,
            ..
        }) => {
            t.variant("RoughPlastic")
                .rgb("diffuse_reflectance", *diffuse_reflectance)
                .rgb("specular_reflectance", *specular_reflectance)
                .num("eta", *eta)
                .microfacet("microfacet", microfacet)
                .num("sample_visible", if *sample_visible { 1.0 } else { 0.0 })
                .num("nonlinear", if *nonlinear { 1.0 } else { 0.0 });
        }
        Bsdf::Blend(Blend { weight, bsdfs }) => {
            t.variant("Blend").num("weight", *weight);
            for (field, child) in ["bsdf0", "bsdf1"].into_iter().zip(bsdfs.iter()) {
                t.key(field);
                bsdf_v2(t, child);
            }
        }
        Bsdf::Principled(Principled {
            base_color,
            roughness,
            anisotropic,
            metallic,
            spec_tint,
            eta,
            sheen,
            sheen_tint,
            clearcoat,
            clearcoat_gloss,
            flatness,
            diffuse_rate,
            specular_rate,
            clearcoat_rate,
            spec_trans,
            has_spec_trans,
        }) => {
            t.variant("Principled")
                .rgb("base_color", *base_color)
                .num("roughness", *roughness)
                .num("anisotropic", *anisotropic)
                .num("metallic", *metallic)
                .num("spec_tint", *spec_tint)
                .num("eta", *eta)
                .num("sheen", *sheen)
                .num("sheen_tint", *sheen_tint)
                .num("clearcoat", *clearcoat)
                .num("clearcoat_gloss", *clearcoat_gloss)
                .num("flatness", *flatness)
                .num("diffuse_rate", *diffuse_rate)
                .num("specular_rate", *specular_rate)
                .num("clearcoat_rate", *clearcoat_rate);
            // Only with the transmission lobe, so that reflective principled materials keep
            // the hashes they had before it existed.
            if *has_spec_trans {
                t.num("spec_trans", *spec_trans);
            }
        }
        Bsdf::PrincipledThin(PrincipledThin {
            base_color,
            roughness,
            anisotropic,
            spec_trans,
            eta,
            spec_tint,
            sheen,
            sheen_tint,
            flatness,
            diff_trans,
            spec_reflect_rate,
            spec_trans_rate,
            diffuse_reflect_rate,
            diffuse_trans_rate,
        }) => {
            t.variant("PrincipledThin")
                .rgb("base_color", *base_color)
                .num("roughness", *roughness)
                .num("anisotropic", *anisotropic)
                .num("spec_trans", *spec_trans)
                .num("eta", *eta)
                .num("spec_tint", *spec_tint)
                .num("sheen", *sheen)
                .num("sheen_tint", *sheen_tint)
                .num("flatness", *flatness)
                .num("diff_trans", *diff_trans)
                .num("spec_reflect_rate", *spec_reflect_rate)
                .num("spec_trans_rate", *spec_trans_rate)
                .num("diffuse_reflect_rate", *diffuse_reflect_rate)
                .num("diffuse_trans_rate", *diffuse_trans_rate);
        }
        Bsdf::ThinDielectric(ThinDielectric { eta, specular_reflectance, specular_transmittance }) => {
            t.variant("ThinDielectric")
                .num("eta", *eta)
                .rgb("specular_reflectance", *specular_reflectance)
                .rgb("specular_transmittance", *specular_transmittance);
        }
    }
    t.0.push_str(" })");
}

/// The material hash of encoding version 2: what the geometry hash records per triangle.
pub(crate) fn material_hash(material: &Material) -> [u8; 16] {
    let mut h = Hasher::new("opticks material");
    h.0.update(material_v2(material).as_bytes());
    h.finish()
}

/// Builder of the material text: `Name(Name {` then `, `-separated `field: value` pairs. The
/// caller closes the record.
struct Text(String);

impl Text {
    /// Opens the record of a BSDF variant: `Name(Name {`.
    fn variant(&mut self, name: &str) -> &mut Self {
        let _ = write!(self.0, "{name}({name} {{");
        self
    }
    /// `field: ` after the separator (none before the first field of a record).
    fn key(&mut self, field: &str) -> &mut Self {
        if !self.0.ends_with('{') {
            self.0.push(',');
        }
        let _ = write!(self.0, " {field}: ");
        self
    }
    /// A number: Rust's `{:?}` of an `f32` (shortest round-trip form; module docs).
    fn number(&mut self, x: f32) {
        let _ = write!(self.0, "{x:?}");
    }
    /// A colour: `Vec3(r, g, b)`.
    fn colour(&mut self, c: Rgb) {
        self.0.push_str("Vec3(");
        self.number(c.x);
        self.0.push_str(", ");
        self.number(c.y);
        self.0.push_str(", ");
        self.number(c.z);
        self.0.push(')');
    }
    fn num(&mut self, field: &str, x: f32) -> &mut Self {
        self.key(field).number(x);
        self
    }
    fn rgb(&mut self, field: &str, c: Rgb) -> &mut Self {
        self.key(field).colour(c);
        self
    }
    /// A conductor's complex index: `None` or `Some((η, κ))`.
    fn ior(&mut self, field: &str, ior: &Option<(Rgb, Rgb)>) -> &mut Self {
        self.key(field);
        match ior {
            None => self.0.push_str("None"),
            Some((eta, k)) => {
                self.0.push_str("Some((");
                self.colour(*eta);
                self.0.push_str(", ");
                self.colour(*k);
                self.0.push_str("))");
            }
        }
        self
    }
    /// `Microfacet { distribution: Ggx|Beckmann, alpha_u: num, alpha_v: num }`.
    fn microfacet(&mut self, field: &str, m: &Microfacet) -> &mut Self {
        let Microfacet { distribution, alpha_u, alpha_v } = m;
        let distribution = match distribution {
            Distribution::Ggx => "Ggx",
            Distribution::Beckmann => "Beckmann",
        };
        let _ = write!(self.key(field).0, "Microfacet {{ distribution: {distribution}");
        self.num("alpha_u", *alpha_u).num("alpha_v", *alpha_v);
        self.0.push_str(" }");
        self
    }
}

/// The shape hash of a light, encoding version 2 (module docs): where and how it emits, not how
/// much. `triangles` are the scene's (an area light refers to them by index).
pub(crate) fn light_shape(light: &Light, triangles: &[Triangle]) -> [u8; 16] {
    let mut h = Hasher::new("opticks light shape v1");
    match light {
        Light::Area(a) => {
            h.0.update(b"lambertian area");
            if !matches!(a.profile, BuiltProfile::Cosine) {
                profile(&mut h, &a.profile);
            }
            if matches!(a.profile, BuiltProfile::Table(_)) {
                h.f32s(&a.tangent.to_array());
            }
            for &t in &a.triangles {
                let Triangle { v0, e1, e2 } = &triangles[t as usize];
                h.f32s(&[v0.x, v0.y, v0.z, e1.x, e1.y, e1.z, e2.x, e2.y, e2.z]);
            }
            // A texture decides where the light emits (an untextured light's bytes are unchanged).
            if let Some(t) = &a.texture {
                h.0.update(b"radiance texture");
                t.texture.fingerprint_with(&mut |w| h.f32s(w));
                for uv in &t.uvs {
                    h.f32s(&[uv[0].x, uv[0].y, uv[1].x, uv[1].y, uv[2].x, uv[2].y]);
                }
            }
        }
        Light::Point(p) => {
            h.0.update(b"isotropic point");
            h.f32s(&p.position.to_array());
            if !matches!(p.profile, BuiltProfile::Uniform { hemisphere: false }) {
                profile(&mut h, &p.profile);
                let (s, n) = (p.frame.s, p.frame.n);
                h.f32s(&[s.x, s.y, s.z, n.x, n.y, n.z]);
            }
            // A projected texture decides where the spot emits (untextured bytes unchanged).
            if let Some(t) = &p.texture {
                h.0.update(b"projected texture");
                t.texture.fingerprint_with(&mut |w| h.f32s(w));
            }
        }
        Light::Directional(d) => {
            h.0.update(b"directional");
            h.f32s(&d.direction.to_array());
            h.f32s(&d.centre.to_array());
            h.f32s(&[d.radius]);
        }
        Light::Environment(e) => {
            h.0.update(b"environment");
            h.f32s(&e.to_world.to_cols_array());
            h.f32s(&e.centre.to_array());
            h.f32s(&[e.radius]);
            match &e.radiance {
                EnvRadiance::Constant(_) => {
                    h.0.update(b"constant");
                }
                EnvRadiance::Map(m) => {
                    h.0.update(b"lat-long map");
                    let (w, ht) = m.size();
                    h.0.update(&(w as u64).to_le_bytes());
                    h.0.update(&(ht as u64).to_le_bytes());
                    let (texels, scale) = m.texels();
                    h.f32s(&[scale]);
                    // A block at a time, in place in one buffer (the same stream as the whole map
                    // at once): a copy of an 8192² map's texels took 805 MB.
                    let mut bytes = vec![0u8; 4096 * 12];
                    for block in texels.chunks(4096) {
                        let bytes = &mut bytes[..block.len() * 12];
                        for (out, t) in bytes.chunks_exact_mut(12).zip(block) {
                            for (o, x) in out.chunks_exact_mut(4).zip(t.to_array()) {
                                o.copy_from_slice(&x.to_le_bytes());
                            }
                        }
                        h.0.update(bytes);
                    }
                }
            };
        }
    }
    h.finish()
}

/// The profile bytes of a light shape: what defines the distribution, not its scale.
fn profile(h: &mut Hasher, profile: &BuiltProfile) {
    match profile {
        BuiltProfile::Uniform { hemisphere: true } => {
            h.0.update(b"uniform hemisphere");
        }
        BuiltProfile::Uniform { hemisphere: false } => {
            h.0.update(b"uniform sphere....");
        }
        BuiltProfile::Cosine => {
            h.0.update(b"cosine");
        }
        BuiltProfile::CosinePower { exponent } => {
            h.0.update(b"cosine power");
            h.f32s(&[*exponent]);
        }
        BuiltProfile::Spot { cutoff, beam, cos_cutoff: _, cos_beam: _, integral: _ } => {
            h.0.update(b"spot");
            h.f32s(&[*cutoff, *beam]);
        }
        BuiltProfile::Table(t) => {
            h.0.update(b"table");
            let (thetas, phis, values) = t.grid();
            h.f32s(thetas);
            h.f32s(phis);
            h.f32s(values);
        }
    }
}

#[cfg(test)]
#[path = "fingerprint_tests.rs"]
mod tests;
