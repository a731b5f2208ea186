//! Writes a [`SceneDescription`] as VRML97 with the Opticks extension ([`super::extension`]):
//! the PROTO declarations, a `PhysicalViewpoint`, `PhysicalPointLight`s (isotropic or IES),
//! `PhysicalSpotLight`s,
//! `PhysicalDirectionalLight`s, and one `Shape` with a world-space `IndexedFaceSet` per mesh, its
//! material a `PhysicalMaterial` (shared with `DEF`/`USE`) or, for an emitter, an `AreaLight`
//! carrying its radiance, emission function (Lambertian, uniform or cosⁿ) and reflectance.
//!
//! Numbers are written in Rust's shortest round-trip form, so reading the file back gives the
//! same positions, colours and exponents bit for bit. A `.gz` path is gzip-compressed. A point
//! light with an IES profile is written as a `PhysicalPointLight` whose `iesUrl` is the file it
//! was read from ([`PointLightDesc::ies_file`](opticks_core::scene::PointLightDesc), absolute as
//! the loaders keep it). Lights the extension cannot express (an IES table whose file is not
//! known, an IES or spot profile on an area light, a textured emitter or spot, an environment)
//! and cameras it has no node for (a thin lens, an orthographic camera) are an `InvalidInput`
//! error rather than silently dropped.

use super::extension::DECLARATIONS;
use super::parser::is_keyword;
use glam::{DMat3, DQuat, DVec3};
use opticks_core::bsdf::{Bsdf, Material};
use opticks_core::light::EmissionProfile;
use opticks_core::math::{Frame, Rgb, Vec3};
use opticks_core::scene::{CameraDesc, CameraKind, SceneDescription};
use std::collections::HashSet;
use std::io::{self, BufWriter, Write};
use std::path::Path;

/// Writes `desc` to `path` (gzip-compressed if the name ends in `.gz`), atomically enough for a
/// scene file: written in full, then flushed.
pub fn write_vrml_file(desc: &SceneDescription, path: &Path) -> io::Result<()> {
    let file = std::fs::File::create(path)?;
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("gz")) {
        let mut gz = flate2::write::GzEncoder::new(BufWriter::new(file), flate2::Compression::default());
        write_vrml(desc, &mut gz)?;
        gz.finish()?.flush()
    } else {
        let mut w = BufWriter::new(file);
        write_vrml(desc, &mut w)?;
        w.flush()
    }
}

/// Writes `desc` as VRML97 text.
pub fn write_vrml(desc: &SceneDescription, w: &mut impl Write) -> io::Result<()> {
    // Refuse rather than silently drop a light's distribution the extension cannot express.
    let unsupported = desc
        .point_lights
        .iter()
        .find_map(|l| match (&l.profile, &l.ies_file) {
            (None | Some(EmissionProfile::Uniform | EmissionProfile::Spot { .. }), _) => None,
            (Some(EmissionProfile::Ies(_)), Some(f)) if f.to_str().is_some() => None,
            (Some(EmissionProfile::Ies(_)), Some(f)) => {
                Some(format!("point light {}'s IES file {} is not a UTF-8 path", l.name, f.display()))
            }
            (Some(EmissionProfile::Ies(_)), None) => Some(format!(
                "point light {} has an IES profile but not the file it came from (the extension refers to IES files by URL)",
                l.name
            )),
            (Some(_), _) => {
                Some(format!("point light {} has an emission profile other than isotropic, spot or IES", l.name))
            }
        })
        .or_else(|| {
            desc.meshes
                .iter()
                .find(|m| m.emission.as_ref().is_some_and(|e| area_emission(e.profile.as_ref()).is_none()))
                .map(|m| format!("area light {} has a tabulated (IES) emission profile", m.name))
        })
        .or_else(|| {
            let textured = desc.point_lights.iter().find(|l| l.texture.is_some());
            textured.map(|l| format!("spot light {} projects a texture", l.name))
        })
        .or_else(|| {
            desc.meshes
                .iter()
                .find(|m| m.emission.as_ref().is_some_and(|e| e.texture.is_some()))
                .map(|m| format!("area light {} has a textured radiance", m.name))
        })
        .or_else(|| {
            desc.environment_lights.first().map(|l| format!("environment light {} (at infinity)", l.name))
        })
        .or_else(|| match desc.camera.map(|c| c.kind) {
            Some(CameraKind::ThinLens { .. }) => Some("the camera is a thin lens".to_string()),
            Some(CameraKind::Orthographic { .. }) => Some("the camera is orthographic".to_string()),
            Some(CameraKind::Perspective) | None => None,
        });
    if let Some(what) = unsupported {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{what}: the Opticks VRML extension cannot express it (write Mitsuba XML instead)"),
        ));
    }
    writeln!(w, "#VRML V2.0 utf8")?;
    writeln!(w, "# Written by Opticks. Units: metres, W/(m^2 sr), W/sr. World-space meshes.")?;
    w.write_all(DECLARATIONS.as_bytes())?;
    let mut names = Names::default();
    // Materials keep their names (shapes and lights get a suffix if they collide).
    let mut material_defs: Vec<Option<String>> = vec![None; desc.materials.len()];
    for m in desc.meshes.iter().filter(|m| m.emission.is_none()) {
        if let (Some(slot @ None), Some(mat)) =
            (material_defs.get_mut(m.material), desc.materials.get(m.material))
        {
            *slot = Some(names.fresh(&mat.name));
        }
    }
    let mut defined = vec![false; desc.materials.len()];
    if let Some(c) = &desc.camera {
        camera(w, c)?;
    }
    for l in &desc.point_lights {
        if let Some(EmissionProfile::Spot { cutoff_angle, beam_width }) = l.profile {
            writeln!(w, "DEF {} PhysicalSpotLight {{", names.fresh(&l.name))?;
            let axis = l.orientation.map_or(opticks_core::math::Vec3::Z, |f| f.n);
            writeln!(w, "  location {}\n  direction {}", v3(l.position), v3(axis))?;
            match l.power {
                Some(p) => writeln!(w, "  power {}", v3(p))?,
                None => writeln!(w, "  intensity {}", v3(l.intensity))?,
            }
            writeln!(w, "  beamWidth {beam_width}\n  cutOffAngle {cutoff_angle}\n}}")?;
        } else if let (Some(EmissionProfile::Ies(_)), Some(file)) = (&l.profile, &l.ies_file) {
            writeln!(w, "DEF {} PhysicalPointLight {{", names.fresh(&l.name))?;
            let frame = l.orientation.unwrap_or(Frame { s: Vec3::X, t: Vec3::Y, n: Vec3::Z });
            writeln!(w, "  location {}\n  iesUrl {}", v3(l.position), vrml_string(&file.to_string_lossy()))?;
            writeln!(w, "  direction {}\n  horizontal {}", v3(frame.n), v3(frame.s))?;
            writeln!(w, "  intensity {}", v3(l.intensity))?;
            if let Some(p) = l.power {
                writeln!(w, "  power {}", v3(p))?;
            }
            writeln!(w, "}}")?;
        } else {
            writeln!(w, "DEF {} PhysicalPointLight {{", names.fresh(&l.name))?;
            let intensity = l.power.map_or(l.intensity, |p| p / (4.0 * std::f32::consts::PI));
            writeln!(w, "  location {}\n  intensity {}\n}}", v3(l.position), v3(intensity))?;
        }
    }
    for d in &desc.directional_lights {
        writeln!(w, "DEF {} PhysicalDirectionalLight {{", names.fresh(&d.name))?;
        writeln!(w, "  direction {}\n  irradiance {}\n}}", v3(d.direction), v3(d.irradiance))?;
    }
    for m in &desc.meshes {
        writeln!(w, "DEF {} Shape {{", names.fresh(&m.name))?;
        let Some(mat) = desc.materials.get(m.material) else {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("mesh {} has no material", m.name),
            ));
        };
        write!(w, "  appearance Appearance {{ material ")?;
        match &m.emission {
            Some(e) => {
                let emission = area_emission(e.profile.as_ref()).unwrap_or_default();
                // A power overrides the radiance (AreaEmission::power): write it as such.
                match e.power {
                    Some(phi) => write!(w, "AreaLight {{ power {} emission \"{emission}\" ", v3(phi))?,
                    None => write!(w, "AreaLight {{ radiance {} emission \"{emission}\" ", v3(e.radiance))?,
                }
                phong_fields(w, mat)?;
                writeln!(w, "}} }}")?;
            }
            None => {
                let def = material_defs[m.material].as_deref().unwrap_or("_");
                if defined[m.material] {
                    writeln!(w, "USE {def} }}")?;
                } else {
                    write!(w, "DEF {def} PhysicalMaterial {{ ")?;
                    phong_fields(w, mat)?;
                    writeln!(w, "}} }}")?;
                    defined[m.material] = true;
                }
            }
        }
        writeln!(w, "  geometry IndexedFaceSet {{")?;
        writeln!(w, "    solid {}", if mat.two_sided { "FALSE" } else { "TRUE" })?;
        writeln!(w, "    coord Coordinate {{ point [")?;
        for p in &m.positions {
            writeln!(w, "      {},", v3(*p))?;
        }
        writeln!(w, "    ] }}\n    coordIndex [")?;
        for t in &m.triangles {
            writeln!(w, "      {} {} {} -1,", t[0], t[1], t[2])?;
        }
        writeln!(w, "    ]\n  }}\n}}")?;
    }
    Ok(())
}

/// The AreaLight `emission` string of an area light's profile (`None`: not expressible).
fn area_emission(p: Option<&EmissionProfile>) -> Option<String> {
    match p {
        None | Some(EmissionProfile::Cosine) => Some("lambertian".into()),
        Some(EmissionProfile::Uniform) => Some("uniform".into()),
        Some(EmissionProfile::CosinePower { exponent }) => Some(format!("cosine {exponent}")),
        Some(EmissionProfile::Spot { .. } | EmissionProfile::Ies(_)) => None,
    }
}

/// `text` as a VRML SFString: quoted, with `"` and `\` escaped.
fn vrml_string(text: &str) -> String {
    format!("\"{}\"", text.replace('\\', "\\\\").replace('"', "\\\""))
}

fn v3(v: Rgb) -> String {
    format!("{} {} {}", v.x, v.y, v.z)
}

fn phong_fields(w: &mut impl Write, m: &Material) -> io::Result<()> {
    let (kd, ks, n) = match &m.bsdf {
        Bsdf::Lambert(l) => (l.reflectance, Rgb::ZERO, 0.0),
        Bsdf::ModifiedPhong(p) => (p.kd, p.ks, p.exponent),
        other => {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!(
                    "material '{}' ({}) has no VRML form yet: the extension writes Lambert and Modified Phong",
                    m.name,
                    bsdf_kind(other)
                ),
            ));
        }
    };
    write!(w, "diffuse {} specular {} exponent {} twoSided {} ", v3(kd), v3(ks), n, bool_str(m.two_sided))
}

fn bsdf_kind(b: &Bsdf) -> &'static str {
    match b {
        Bsdf::Lambert(_) => "Lambert",
        Bsdf::ModifiedPhong(_) => "Modified Phong",
        Bsdf::SmoothConductor(_) => "mirror",
        Bsdf::SmoothDielectric(_) => "glass",
        Bsdf::RoughConductor(_) => "rough conductor",
        Bsdf::RoughDielectric(_) => "rough dielectric",
        Bsdf::Plastic(_) => "plastic",
        Bsdf::RoughPlastic(_) => "rough plastic",
        Bsdf::Blend(_) => "blend",
        Bsdf::ThinDielectric(_) => "thin dielectric",
        Bsdf::Principled(_) => "principled",
        Bsdf::PrincipledThin(_) => "thin principled",
    }
}

fn bool_str(b: bool) -> &'static str {
    if b { "TRUE" } else { "FALSE" }
}

fn camera(w: &mut impl Write, c: &CameraDesc) -> io::Result<()> {
    let eye = c.eye.as_dvec3();
    let f = (c.target.as_dvec3() - eye).normalize_or_zero();
    let r = f.cross(c.up.as_dvec3()).normalize_or_zero();
    let u = r.cross(f);
    // The rotation taking VRML's default view (-z, up +y) to this one.
    let (axis, angle) = if r == DVec3::ZERO {
        (DVec3::Z, 0.0)
    } else {
        DQuat::from_mat3(&DMat3::from_cols(r, u, -f)).normalize().to_axis_angle()
    };
    let (wd, ht) = (f64::from(c.width.max(1)), f64::from(c.height.max(1)));
    let fov_x = f64::from(c.fov_x_degrees).to_radians();
    let fov = if wd <= ht { fov_x } else { 2.0 * ((fov_x / 2.0).tan() * ht / wd).atan() };
    writeln!(w, "PhysicalViewpoint {{")?;
    writeln!(w, "  position {}", v3(c.eye))?;
    writeln!(w, "  orientation {} {} {} {}", axis.x, axis.y, axis.z, angle)?;
    writeln!(w, "  fieldOfView {fov}  # radians, along the smaller image side")?;
    writeln!(w, "  width {}\n  height {}\n}}", c.width, c.height)
}

/// Unique VRML identifiers made from scene names.
#[derive(Default)]
struct Names(HashSet<String>);

impl Names {
    fn fresh(&mut self, name: &str) -> String {
        let mut id: String = name
            .chars()
            .map(|ch| if ch.is_ascii_alphanumeric() || ch == '_' || !ch.is_ascii() { ch } else { '_' })
            .collect();
        if id.is_empty() || id.starts_with(|ch: char| ch.is_ascii_digit()) || is_keyword(&id) {
            id.insert(0, '_');
        }
        let mut candidate = id.clone();
        let mut k = 1;
        while !self.0.insert(candidate.clone()) {
            k += 1;
            candidate = format!("{id}_{k}");
        }
        candidate
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_valid_and_unique() {
        let mut n = Names::default();
        assert_eq!(n.fresh("white"), "white");
        assert_eq!(n.fresh("white"), "white_2");
        assert_eq!(n.fresh("3 boxes"), "_3_boxes");
        assert_eq!(n.fresh("TRUE"), "_TRUE");
        assert_eq!(n.fresh(""), "_");
    }
}
