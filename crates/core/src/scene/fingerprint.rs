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
//!     over the sphere, the profile bytes and the frame's x then z axis (6 × f32);
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
mod tests {
    use super::{material_hash, material_v2};
    use crate::bsdf::{
        Blend, Bsdf, Lambert, Material, ModifiedPhong, Plastic, RoughConductor, RoughDielectric,
        RoughPlastic, SmoothConductor, SmoothDielectric, ThinDielectric,
    };
    use crate::light::EmissionProfile;
    use crate::math::{Frame, Rgb, Vec3};
    use crate::sampling::microfacet::{Distribution, Microfacet};
    use crate::scene::{PointLightDesc, Scene, demo::cornell_box};

    fn material(bsdf: Bsdf, two_sided: bool) -> Material {
        Material { name: "m".into(), bsdf, two_sided }
    }

    fn mf(distribution: Distribution, alpha_u: f32, alpha_v: f32) -> Microfacet {
        Microfacet { distribution, alpha_u, alpha_v }
    }

    fn phong() -> ModifiedPhong {
        ModifiedPhong { kd: Rgb::new(0.3, 0.2, 0.1), ks: Rgb::new(0.1, 0.2, 0.3), exponent: 20.0 }
    }

    fn mirror() -> SmoothConductor {
        let ior = Some((Rgb::new(0.2, 0.9, 1.1), Rgb::new(3.9, 2.4, 1.6e17)));
        SmoothConductor { specular_reflectance: Rgb::new(0.9, 0.8, 0.7), ior }
    }

    fn glass() -> SmoothDielectric {
        SmoothDielectric {
            eta: 1.0 / 1.5,
            specular_reflectance: Rgb::ONE,
            specular_transmittance: Rgb::new(1.0, 0.95, 0.9),
            absorption: Rgb::new(0.1, 2.5e-5, 0.0),
        }
    }

    fn rough_metal() -> RoughConductor {
        RoughConductor {
            microfacet: mf(Distribution::Beckmann, 0.1, 0.3),
            specular_reflectance: Rgb::ONE,
            ior: None,
        }
    }

    fn rough_glass() -> RoughDielectric {
        RoughDielectric {
            eta: 1.5,
            microfacet: mf(Distribution::Ggx, 0.25, 0.25),
            specular_reflectance: Rgb::new(1.0, 0.99, 0.98),
            specular_transmittance: Rgb::ONE,
            absorption: Rgb::new(0.0, 0.5, 12.0),
        }
    }

    fn rough_plastic(d: Rgb, s: Rgb, dist: Distribution, alpha: f32, visible: bool, nonlinear: bool) -> Bsdf {
        Bsdf::RoughPlastic(RoughPlastic::new(d, s, 1.49, 1.0, dist, alpha, visible, nonlinear).unwrap())
    }

    /// A blend of a diffuse of reflectance `rho` and a mirror.
    fn blend(weight: f32, rho: Rgb) -> Bsdf {
        let mirror = Bsdf::SmoothConductor(SmoothConductor::new(Rgb::ONE, None).unwrap());
        Bsdf::Blend(Blend::new(weight, Bsdf::Lambert(Lambert::new(rho).unwrap()), mirror).unwrap())
    }

    fn plastic(d: Rgb, s: Rgb, eta: f32, nonlinear: bool) -> Plastic {
        Plastic::new(d, s, eta, 1.0, nonlinear).unwrap()
    }

    fn thin() -> ThinDielectric {
        ThinDielectric {
            eta: 1.5,
            specular_reflectance: Rgb::new(1.0, 0.5, 0.25),
            specular_transmittance: Rgb::ONE,
        }
    }

    /// One material of every BSDF variant, with every option used.
    fn one_of_each() -> Vec<Material> {
        vec![
            material(Bsdf::Lambert(Lambert { reflectance: Rgb::new(0.885809, 1e-7, -0.0) }), true),
            material(Bsdf::ModifiedPhong(phong()), false),
            material(Bsdf::SmoothConductor(mirror()), true),
            material(Bsdf::SmoothDielectric(glass()), false),
            material(Bsdf::RoughConductor(rough_metal()), false),
            material(Bsdf::RoughDielectric(rough_glass()), true),
            material(Bsdf::Plastic(plastic(Rgb::new(0.5, 0.25, 0.0), Rgb::ONE, 1.49, true)), false),
            material(Bsdf::ThinDielectric(thin()), false),
        ]
    }

    /// The version-2 text is frozen (module docs): these are the bytes datasets' hashes cover.
    #[test]
    fn material_text_of_every_variant_is_pinned() {
        let texts: Vec<String> = one_of_each().iter().map(material_v2).collect();
        assert_eq!(
            texts,
            [
                "Lambert(Lambert { reflectance: Vec3(0.885809, 1e-7, -0.0) })|true",
                "ModifiedPhong(ModifiedPhong { kd: Vec3(0.3, 0.2, 0.1), ks: Vec3(0.1, 0.2, 0.3), exponent: 20.0 })|false",
                "SmoothConductor(SmoothConductor { specular_reflectance: Vec3(0.9, 0.8, 0.7), ior: Some((Vec3(0.2, 0.9, \
                 1.1), Vec3(3.9, 2.4, 1.6e17))) })|true",
                "SmoothDielectric(SmoothDielectric { eta: 0.6666667, specular_reflectance: Vec3(1.0, 1.0, 1.0), \
                 specular_transmittance: Vec3(1.0, 0.95, 0.9), absorption: Vec3(0.1, 2.5e-5, 0.0) })|false",
                "RoughConductor(RoughConductor { microfacet: Microfacet { distribution: Beckmann, alpha_u: 0.1, alpha_v: \
                 0.3 }, specular_reflectance: Vec3(1.0, 1.0, 1.0), ior: None })|false",
                "RoughDielectric(RoughDielectric { eta: 1.5, microfacet: Microfacet { distribution: Ggx, alpha_u: 0.25, \
                 alpha_v: 0.25 }, specular_reflectance: Vec3(1.0, 0.99, 0.98), specular_transmittance: Vec3(1.0, 1.0, \
                 1.0), absorption: Vec3(0.0, 0.5, 12.0) })|true",
                "Plastic(Plastic { diffuse_reflectance: Vec3(0.5, 0.25, 0.0), specular_reflectance: Vec3(1.0, 1.0, \
                 1.0), eta: 1.49, nonlinear: 1.0 })|false",
                "ThinDielectric(ThinDielectric { eta: 1.5, specular_reflectance: Vec3(1.0, 0.5, 0.25), \
                 specular_transmittance: Vec3(1.0, 1.0, 1.0) })|false",
            ]
        );
        let lambert = &one_of_each()[0];
        let digest = blake3::hash(format!("opticks material{}", texts[0]).as_bytes());
        assert_eq!(material_hash(lambert), digest.as_bytes()[..16], "BLAKE3(\"opticks material\" ‖ text)");
        assert_eq!(super::hex(&material_hash(lambert)), "2b5c37adb4b9dd7bdd34ecb807e063ee");
    }

    /// Every parameter of every variant, and the sidedness, reaches the hash; equal materials
    /// (whatever their names) hash equal.
    #[test]
    fn material_hash_changes_with_every_parameter_and_only_with_them() {
        let base = one_of_each();
        for m in &base {
            let twin = Material { name: "another name".into(), ..m.clone() };
            assert_eq!(material_hash(&twin), material_hash(m), "{m:?}");
        }
        let rgb = Rgb::new;
        let (p, c, g, rc, rg) = (phong(), mirror(), glass(), rough_metal(), rough_glass());
        // Each variant with one parameter changed: every field, the presence of a conductor
        // index, the distribution, a roughness along each axis, a sign of zero.
        let changed = [
            Bsdf::Lambert(Lambert { reflectance: rgb(0.885809, 1e-7, 0.0) }),
            Bsdf::Lambert(Lambert { reflectance: rgb(0.885809, 2e-7, -0.0) }),
            Bsdf::ModifiedPhong(ModifiedPhong { kd: rgb(0.3, 0.2, 0.11), ..p.clone() }),
            Bsdf::ModifiedPhong(ModifiedPhong { ks: rgb(0.1, 0.21, 0.3), ..p.clone() }),
            Bsdf::ModifiedPhong(ModifiedPhong { exponent: 21.0, ..p }),
            Bsdf::SmoothConductor(SmoothConductor { specular_reflectance: rgb(0.91, 0.8, 0.7), ..c.clone() }),
            Bsdf::SmoothConductor(SmoothConductor { ior: None, ..c.clone() }),
            Bsdf::SmoothConductor(SmoothConductor {
                ior: Some((rgb(0.21, 0.9, 1.1), rgb(3.9, 2.4, 1.6e17))),
                ..c.clone()
            }),
            Bsdf::SmoothConductor(SmoothConductor {
                ior: Some((rgb(0.2, 0.9, 1.1), rgb(3.9, 2.4, 1.6e16))),
                ..c
            }),
            Bsdf::SmoothDielectric(SmoothDielectric { eta: 1.5, ..g.clone() }),
            Bsdf::SmoothDielectric(SmoothDielectric {
                specular_reflectance: rgb(1.0, 0.9, 1.0),
                ..g.clone()
            }),
            Bsdf::SmoothDielectric(SmoothDielectric {
                specular_transmittance: rgb(1.0, 0.95, 0.91),
                ..g.clone()
            }),
            Bsdf::SmoothDielectric(SmoothDielectric { absorption: rgb(0.2, 2.5e-5, 0.0), ..g }),
            Bsdf::RoughConductor(RoughConductor {
                microfacet: mf(Distribution::Beckmann, 0.11, 0.3),
                ..rc.clone()
            }),
            Bsdf::RoughConductor(RoughConductor {
                microfacet: mf(Distribution::Beckmann, 0.1, 0.1),
                ..rc.clone()
            }),
            Bsdf::RoughConductor(RoughConductor {
                microfacet: mf(Distribution::Ggx, 0.1, 0.3),
                ..rc.clone()
            }),
            Bsdf::RoughConductor(RoughConductor { specular_reflectance: rgb(1.0, 1.0, 0.5), ..rc.clone() }),
            Bsdf::RoughConductor(RoughConductor { ior: Some((Rgb::ONE, Rgb::ONE)), ..rc }),
            Bsdf::RoughDielectric(RoughDielectric { eta: 1.33, ..rg.clone() }),
            Bsdf::RoughDielectric(RoughDielectric {
                microfacet: mf(Distribution::Ggx, 0.3, 0.25),
                ..rg.clone()
            }),
            Bsdf::RoughDielectric(RoughDielectric {
                microfacet: mf(Distribution::Ggx, 0.25, 0.3),
                ..rg.clone()
            }),
            Bsdf::RoughDielectric(RoughDielectric {
                microfacet: mf(Distribution::Beckmann, 0.25, 0.25),
                ..rg.clone()
            }),
            Bsdf::RoughDielectric(RoughDielectric {
                specular_reflectance: rgb(1.0, 0.5, 0.98),
                ..rg.clone()
            }),
            Bsdf::RoughDielectric(RoughDielectric {
                specular_transmittance: rgb(0.5, 1.0, 1.0),
                ..rg.clone()
            }),
            Bsdf::RoughDielectric(RoughDielectric { absorption: rgb(0.0, 0.5, 0.0), ..rg }),
            Bsdf::Plastic(plastic(rgb(0.5, 0.25, 0.01), Rgb::ONE, 1.49, true)),
            Bsdf::Plastic(plastic(rgb(0.5, 0.25, 0.0), rgb(1.0, 0.5, 1.0), 1.49, true)),
            Bsdf::Plastic(plastic(rgb(0.5, 0.25, 0.0), Rgb::ONE, 1.5, true)),
            Bsdf::Plastic(plastic(rgb(0.5, 0.25, 0.0), Rgb::ONE, 1.49, false)),
            Bsdf::ThinDielectric(ThinDielectric { eta: 1.33, ..thin() }),
            Bsdf::ThinDielectric(ThinDielectric { specular_reflectance: Rgb::ONE, ..thin() }),
            Bsdf::ThinDielectric(ThinDielectric { specular_transmittance: rgb(1.0, 1.0, 0.9), ..thin() }),
            rough_plastic(Rgb::splat(0.5), Rgb::ONE, Distribution::Beckmann, 0.1, true, false),
            rough_plastic(Rgb::splat(0.4), Rgb::ONE, Distribution::Beckmann, 0.1, true, false),
            rough_plastic(Rgb::splat(0.5), Rgb::splat(0.9), Distribution::Beckmann, 0.1, true, false),
            rough_plastic(Rgb::splat(0.5), Rgb::ONE, Distribution::Ggx, 0.1, true, false),
            rough_plastic(Rgb::splat(0.5), Rgb::ONE, Distribution::Beckmann, 0.2, true, false),
            rough_plastic(Rgb::splat(0.5), Rgb::ONE, Distribution::Beckmann, 0.1, false, false),
            rough_plastic(Rgb::splat(0.5), Rgb::ONE, Distribution::Beckmann, 0.1, true, true),
            blend(0.5, Rgb::splat(0.5)),
            blend(0.25, Rgb::splat(0.5)),
            blend(0.5, Rgb::splat(0.6)),
        ];
        let mut all = base.clone();
        all.extend(base.iter().map(|m| Material { two_sided: !m.two_sided, ..m.clone() }));
        all.extend(changed.into_iter().map(|bsdf| material(bsdf, false)));
        all.extend(all.clone().into_iter().skip(2 * base.len()).map(|m| Material { two_sided: true, ..m }));
        // Every one hashes differently from every other.
        let hashes: Vec<[u8; 16]> = all.iter().map(material_hash).collect();
        for i in 0..all.len() {
            for j in 0..i {
                assert_ne!(hashes[i], hashes[j], "{:?}\nand\n{:?}", all[i], all[j]);
            }
        }
    }

    #[test]
    fn a_light_shape_covers_where_and_how_it_emits_not_how_much() {
        let mut d = cornell_box();
        let axis = Frame::from_normal(Vec3::new(0.0, -1.0, 0.0));
        let spot = EmissionProfile::Spot { cutoff_angle: 0.6, beam_width: 0.4 };
        d.point_lights.push(PointLightDesc {
            name: "spot".into(),
            position: Vec3::new(0.0, 1.5, 0.0),
            intensity: Rgb::ONE,
            profile: Some(spot),
            orientation: Some(axis),
            ..Default::default()
        });
        let shape = |d: &crate::scene::SceneDescription| Scene::build(d).unwrap().light_shapes[1];
        let original = shape(&d);
        let mut brighter = d.clone();
        brighter.point_lights[0].intensity = Rgb::new(2.0, 1.0, 3.0);
        assert_eq!(shape(&brighter), original, "power and colour are not shape");
        let mut wider = d.clone();
        wider.point_lights[0].profile = Some(EmissionProfile::Spot { cutoff_angle: 0.7, beam_width: 0.4 });
        assert_ne!(shape(&wider), original, "the cone is");
        let mut tilted = d.clone();
        tilted.point_lights[0].orientation = Some(Frame::from_normal(Vec3::new(0.1, -1.0, 0.0).normalize()));
        assert_ne!(shape(&tilted), original, "the axis is");
        let mut moved = d.clone();
        moved.point_lights[0].position.x += 1e-3;
        assert_ne!(shape(&moved), original, "the position is");
        let mut uniform = d;
        uniform.point_lights[0].profile = Some(EmissionProfile::Uniform);
        assert_ne!(shape(&uniform), original, "the profile is");
    }

    #[test]
    fn emission_is_not_geometry_but_reflectance_and_triangles_are() {
        let base = cornell_box();
        let fp = |d: &crate::scene::SceneDescription| Scene::build(d).unwrap().fingerprint;
        let original = fp(&base);
        let non_emitting = base.meshes.iter().position(|m| m.emission.is_none()).unwrap();

        let mut glowing = base.clone();
        glowing.meshes[non_emitting].emission = Some(crate::scene::AreaEmission::lambertian(Rgb::splat(0.5)));
        assert_eq!(fp(&glowing).geometry, original.geometry, "a surface turned light is the same geometry");
        assert_ne!(fp(&glowing).lights, original.lights, "but the lights changed");

        let mut extra_material = base.clone();
        extra_material.materials.push(extra_material.materials[0].clone());
        assert_eq!(fp(&extra_material).geometry, original.geometry, "an unused material changes nothing");

        let mut repainted = base.clone();
        let m = repainted.meshes[non_emitting].material;
        repainted.materials[m].bsdf = Bsdf::Lambert(Lambert { reflectance: Rgb::splat(0.123) });
        assert_ne!(fp(&repainted).geometry, original.geometry, "another reflectance is another scene");

        let mut moved = base.clone();
        moved.meshes[non_emitting].positions[0].x += 1e-3;
        assert_ne!(fp(&moved).geometry, original.geometry, "moved triangles are another scene");
    }
}
