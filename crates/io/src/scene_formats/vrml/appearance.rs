//! VRML97 appearances → the core's materials and area emission: a Shape's `Appearance` and its
//! `Material` (VRML lighting: diffuse and specular colours, shininess, `emissiveColor`), or the
//! extension's `PhysicalMaterial` and `AreaLight` (Modified Phong parameters and radiance or
//! power as given), each material node converted once per sidedness. Kept apart from the walk
//! in [`super::convert`], which only asks for a Shape's material and emission.

use super::convert::{Converter, EMISSIVE_RADIANCE, Result, ptr, rgb};
use super::lexer::Pos;
use super::tree::{FieldValue, Node, ProtoInstance};
use crate::scene_formats::SceneFileError;
use opticks_core::bsdf::{Bsdf, Lambert, Material, ModifiedPhong};
use opticks_core::light::EmissionProfile;
use opticks_core::math::Rgb;

/// What a Shape's material emits: nothing, a radiance (W/(m²·sr)) or a power (W, turned into
/// radiance by the core over the Shape's area), with the AreaLight's emission profile.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Emission {
    /// The surface does not emit.
    None,
    /// Emitted radiance, W/(m²·sr).
    Radiance(Rgb, AreaProfile),
    /// Emitted power, W.
    Power(Rgb, AreaProfile),
}

/// An AreaLight's `emission` function as the core's profile; `None` is `"lambertian"` (the
/// core's default).
pub(super) type AreaProfile = Option<EmissionProfile>;

/// Parses an `emission` string: `"lambertian"`, `"uniform"` or `"cosine n"` (n as the core's
/// [`EmissionProfile::cosine_power`] allows); `None` if it is none of them.
fn parse_area_profile(s: &str) -> Option<AreaProfile> {
    let mut words = s.split_whitespace();
    let p = match (words.next()?, words.next()) {
        ("lambertian", None) => None,
        ("uniform", None) => Some(EmissionProfile::Uniform),
        ("cosine", Some(n)) => Some(EmissionProfile::cosine_power(n.parse().ok()?).ok()?),
        _ => return None,
    };
    words.next().is_none().then_some(p)
}

impl Converter {
    /// The material of a Shape's appearance (shared by every Shape using the same node).
    #[inline(never)] // keeps the recursive walk's stack frame small
    pub(super) fn material(&mut self, appearance: Option<&Node>, solid: bool) -> Result<(usize, Emission)> {
        let mat = match appearance {
            Some(a) if a.type_name == "Appearance" => {
                if a.node("texture").is_some() {
                    self.warn_once(a, "texture", "textures are not supported: ignored");
                }
                a.node("material").map(|m| &**m)
            }
            Some(a) => {
                self.warn_once(a, "appearance", "not an Appearance node: the default material is used");
                None
            }
            None => None,
        };
        // (kd, ks, exponent, two-sided, emission); `physical`: the extension's explicit Modified
        // Phong parameters, which must be possible as given (legacy colours are rescaled).
        let mut physical = false;
        let (kd, ks, exponent, two_sided, emission) = match mat {
            None => ([0.8; 3], [0.0; 3], 0.2 * 128.0, !solid, Emission::None),
            Some(m) => {
                if let Some(p) = self.extension(m, "PhysicalMaterial") {
                    physical = true;
                    let f = |k: &str| p.get(k).and_then(FieldValue::as_vec3).unwrap_or([0.0; 3]);
                    let e = p.get("exponent").and_then(FieldValue::as_float).unwrap_or(0.0);
                    let two = matches!(p.get("twoSided"), Some(FieldValue::Bool(true)));
                    (f("diffuse"), f("specular"), e, two, Emission::None)
                } else if let Some(p) = self.extension(m, "AreaLight") {
                    physical = true;
                    self.area_light(m, p)
                } else if m.type_name == "Material" {
                    if m.float("transparency", 0.0) > 0.0 {
                        self.warn_once(
                            m,
                            "transparency",
                            "transparency is not supported: the surface is opaque",
                        );
                    }
                    let e = m.vec3("emissiveColor", [0.0; 3]);
                    let emission = if e.iter().any(|&c| c != 0.0) {
                        Emission::Radiance(rgb(e) * EMISSIVE_RADIANCE, None)
                    } else {
                        Emission::None
                    };
                    let shininess = m.float("shininess", 0.2);
                    (
                        m.vec3("diffuseColor", [0.8; 3]),
                        m.vec3("specularColor", [0.0; 3]),
                        shininess * 128.0,
                        !solid,
                        emission,
                    )
                } else {
                    self.warn_once(m, "material", "not a Material node: the default material is used");
                    ([0.8; 3], [0.0; 3], 0.2 * 128.0, !solid, Emission::None)
                }
            }
        };
        let key = (mat.map(ptr).unwrap_or(0), two_sided);
        if let Some(found) = self.materials.get(&key) {
            return Ok(found.clone());
        }
        let name = match mat {
            Some(m) => {
                m.def_name.clone().unwrap_or_else(|| format!("{}_{}_{}", m.type_name, m.pos.line, m.pos.col))
            }
            None => "default".to_string(),
        };
        let bsdf = self.bsdf(mat, rgb(kd), rgb(ks), exponent, !physical)?;
        let index = self.out.materials.len();
        self.out.materials.push(Material { name, bsdf, two_sided });
        self.materials.insert(key, (index, emission.clone()));
        Ok((index, emission))
    }

    fn area_light(&mut self, m: &Node, p: &ProtoInstance) -> ([f32; 3], [f32; 3], f32, bool, Emission) {
        let f = |k: &str| p.get(k).and_then(FieldValue::as_vec3).unwrap_or([0.0; 3]);
        let (radiance, power) = (f("radiance"), f("power"));
        let profile = match p.get("emission") {
            Some(FieldValue::Str(e)) => parse_area_profile(e).unwrap_or_else(|| {
                self.warn_once(
                    m,
                    "emission",
                    format!(
                        "emission function \"{e}\" is not one of \"lambertian\", \"uniform\", \"cosine n\" (0 ≤ n ≤ 10⁶): lambertian used"
                    ),
                );
                None
            }),
            _ => None,
        };
        let nonzero = |c: [f32; 3]| c.iter().any(|&v| v != 0.0);
        let emission = if nonzero(radiance) {
            if nonzero(power) {
                self.warn_once(m, "power", "both radiance and power are given: radiance is used");
            }
            Emission::Radiance(rgb(radiance), profile)
        } else if nonzero(power) {
            Emission::Power(rgb(power), profile)
        } else {
            self.warn_once(m, "dark", "AreaLight with zero radiance and zero power: it does not emit");
            Emission::None
        };
        let e = p.get("exponent").and_then(FieldValue::as_float).unwrap_or(0.0);
        let two = matches!(p.get("twoSided"), Some(FieldValue::Bool(true)));
        (f("diffuse"), f("specular"), e, two, emission)
    }

    /// Lambert if there is no specular part, else Modified Phong. Legacy colours (`rescale`)
    /// with kd + ks > 1 are scaled down with a warning; the extension's physical parameters are
    /// taken as given, so an impossible value is an error.
    fn bsdf(&mut self, mat: Option<&Node>, kd: Rgb, ks: Rgb, exponent: f32, rescale: bool) -> Result<Bsdf> {
        let material_error = |s: &Self, source| match mat {
            Some(m) => SceneFileError::Material { at: s.loc(m.pos), element: m.type_name.clone(), source },
            None => SceneFileError::Material { at: s.loc(Pos::default()), element: "default".into(), source },
        };
        let sum = kd + ks;
        let (kd, ks) =
            if rescale && sum.max_element() > 1.0 && kd.min_element() >= 0.0 && ks.min_element() >= 0.0 {
                let scale = Rgb::ONE / sum.max(Rgb::ONE);
                if let Some(m) = mat {
                    let [r, g, b] = sum.to_array();
                    let note = format!(
                        "diffuse + specular = ({r}, {g}, {b}) exceeds 1: both scaled down to conserve energy"
                    );
                    self.warn_once(m, "energy", note);
                }
                (kd * scale, ks * scale)
            } else {
                (kd, ks)
            };
        if ks == Rgb::ZERO {
            Lambert::new(kd).map(Bsdf::Lambert).map_err(|e| material_error(self, e))
        } else {
            ModifiedPhong::new(kd, ks, exponent).map(Bsdf::ModifiedPhong).map_err(|e| material_error(self, e))
        }
    }
}
