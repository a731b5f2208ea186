//! The Opticks extension of VRML97: six PROTOs a file declares itself (so it stays valid VRML97
//! for every other reader, which shows the standard node each body maps to) and whose physical
//! fields the converter reads when the declaration has exactly the interface below. See
//! `docs/scene-formats.md` for the meaning of each field.

use super::tree::{FieldType, ProtoDef};

/// The declarations, as a writer puts them at the top of a file (and as users copy them).
pub const DECLARATIONS: &str = r#"# Opticks physical extension (docs/scene-formats.md): standard VRML97 PROTOs.
PROTO PhysicalMaterial [
  field SFColor diffuse 0.8 0.8 0.8  # Modified Phong kd (albedo of the diffuse lobe)
  field SFColor specular 0 0 0       # Modified Phong ks
  field SFFloat exponent 0           # Phong exponent n (not VRML's shininess)
  field SFBool  twoSided FALSE       # TRUE: the back face scatters like the front
] { Material { diffuseColor IS diffuse specularColor IS specular } }
PROTO AreaLight [
  field SFColor  radiance 0 0 0          # emitted radiance, W/(m^2 sr), front face only
  field SFColor  power 0 0 0             # or: total power of the Shape, W (if radiance is 0)
  field SFString emission "lambertian"   # emission function: "lambertian", "uniform" or "cosine n"
  field SFColor  diffuse 0 0 0           # the emitter's own surface: Modified Phong kd,
  field SFColor  specular 0 0 0          #   ks,
  field SFFloat  exponent 0              #   n
  field SFBool   twoSided FALSE          #   and sidedness of its reflection
] { Material { diffuseColor IS diffuse specularColor IS specular emissiveColor IS radiance } }
PROTO PhysicalPointLight [
  field SFVec3f location 0 0 0
  field SFColor intensity 0 0 0   # radiant intensity, W/sr
  field SFColor power 0 0 0       # or: power, W (I = power / 4 pi; used if intensity is 0)
  field SFBool  on TRUE
  field SFFloat lumens 0          # or: power in lumens, keeping the intensity's colour
  field MFString iesUrl []        # optional: an IES LM-63 file (relative to this file); then
  field SFVec3f direction 0 -1 0  #   its vertical 0 degrees (nadir) axis, its horizontal
  field SFVec3f horizontal 1 0 0  #   0 degrees, and intensity scales its candela (0: white)
] { PointLight { location IS location on IS on } }
PROTO PhysicalSpotLight [
  field SFVec3f location 0 0 0
  field SFVec3f direction 0 0 -1
  field SFColor intensity 0 0 0       # radiant intensity on the axis, W/sr
  field SFColor power 0 0 0           # or: power, W (used if intensity is 0)
  field SFFloat beamWidth 1.570796    # radians: full intensity within this angle of the axis,
  field SFFloat cutOffAngle 0.785398  #   falling linearly in angle to 0 here (radians)
  field SFBool  on TRUE
] { SpotLight { location IS location direction IS direction beamWidth IS beamWidth cutOffAngle IS cutOffAngle on IS on } }
PROTO PhysicalDirectionalLight [
  field SFVec3f direction 0 0 -1      # the direction the light travels
  field SFColor irradiance 0 0 0      # W/m^2 on a plane perpendicular to it; lights the whole scene
  field SFBool  on TRUE
] { DirectionalLight { direction IS direction on IS on } }
PROTO PhysicalViewpoint [
  field SFVec3f    position 0 0 10
  field SFRotation orientation 0 0 1 0
  field SFFloat    fieldOfView 0.785398   # radians, along the smaller image side
  field SFString   description ""
  field SFInt32    width 512              # image size, pixels
  field SFInt32    height 512
] { Viewpoint { position IS position orientation IS orientation fieldOfView IS fieldOfView description IS description } }
"#;

/// Optional fields of an extension PROTO (added after files were written without them).
const OPTIONAL: &[(&str, &[(&str, FieldType)])] = {
    use FieldType::*;
    &[(
        "PhysicalPointLight",
        &[("iesUrl", MFString), ("direction", SFVec3f), ("horizontal", SFVec3f), ("lumens", SFFloat)],
    )]
};

/// The six extension PROTOs and their required interfaces (names and types, in any order).
const INTERFACES: &[(&str, &[(&str, FieldType)])] = {
    use FieldType::*;
    &[
        (
            "PhysicalMaterial",
            &[("diffuse", SFColor), ("specular", SFColor), ("exponent", SFFloat), ("twoSided", SFBool)],
        ),
        (
            "AreaLight",
            &[
                ("radiance", SFColor),
                ("power", SFColor),
                ("emission", SFString),
                ("diffuse", SFColor),
                ("specular", SFColor),
                ("exponent", SFFloat),
                ("twoSided", SFBool),
            ],
        ),
        (
            "PhysicalPointLight",
            &[("location", SFVec3f), ("intensity", SFColor), ("power", SFColor), ("on", SFBool)],
        ),
        (
            "PhysicalSpotLight",
            &[
                ("location", SFVec3f),
                ("direction", SFVec3f),
                ("intensity", SFColor),
                ("power", SFColor),
                ("beamWidth", SFFloat),
                ("cutOffAngle", SFFloat),
                ("on", SFBool),
            ],
        ),
        ("PhysicalDirectionalLight", &[("direction", SFVec3f), ("irradiance", SFColor), ("on", SFBool)]),
        (
            "PhysicalViewpoint",
            &[
                ("position", SFVec3f),
                ("orientation", SFRotation),
                ("fieldOfView", SFFloat),
                ("description", SFString),
                ("width", SFInt32),
                ("height", SFInt32),
            ],
        ),
    ]
};

/// Whether `name` is one of the extension's PROTO names.
pub fn is_extension_name(name: &str) -> bool {
    INTERFACES.iter().any(|(n, _)| *n == name)
}

/// Whether `p` is an extension PROTO declared with the documented interface (field or
/// exposedField, any order; no required field missing, nothing extra; optional fields may be
/// left out).
pub fn conforms(p: &ProtoDef) -> bool {
    let Some((_, want)) = INTERFACES.iter().find(|(n, _)| *n == p.name) else { return false };
    let optional = OPTIONAL.iter().find(|(n, _)| *n == p.name).map_or(&[][..], |(_, o)| o);
    let documented =
        |name: &str, ty: FieldType| want.iter().chain(optional).any(|&(n, t)| n == name && t == ty);
    p.body.is_some()
        && want.iter().all(|(name, _)| p.interface.iter().any(|d| d.name == *name))
        && p.interface.iter().enumerate().all(|(i, d)| {
            documented(&d.name, d.ty)
                && matches!(d.kind, "field" | "exposedField")
                && p.interface[..i].iter().all(|e| e.name != d.name)
        })
}

#[cfg(test)]
mod tests {
    use super::super::parser::parse;
    use super::*;

    #[test]
    fn the_declarations_have_the_documented_interfaces() {
        let src = format!(
            "#VRML V2.0 utf8\n{DECLARATIONS}\nPhysicalMaterial {{}} AreaLight {{}} PhysicalPointLight {{}} PhysicalSpotLight {{}} \
             PhysicalDirectionalLight {{}} PhysicalViewpoint {{}}"
        );
        let p = parse(&src).unwrap();
        assert_eq!(p.nodes.len(), 6);
        for (n, (name, _)) in p.nodes.iter().zip(INTERFACES) {
            let inst = n.proto.as_ref().unwrap();
            assert_eq!(inst.proto.name, *name);
            assert!(conforms(&inst.proto), "{name}");
        }
        assert!(p.warnings.is_empty(), "{:?}", p.warnings);
        let other = parse("#VRML V2.0 utf8\nPROTO PhysicalMaterial [ field SFColor diffuse 1 1 1 ] { Material {} } PhysicalMaterial {}")
            .unwrap();
        assert!(!conforms(&other.nodes[0].proto.as_ref().unwrap().proto));
        // The optional fields may be left out (files written before they existed), not retyped.
        let old = parse(
            "#VRML V2.0 utf8\nPROTO PhysicalPointLight [ field SFVec3f location 0 0 0 field SFColor intensity 0 0 0 \
             field SFColor power 0 0 0 field SFBool on TRUE ] { PointLight {} } PhysicalPointLight {}",
        )
        .unwrap();
        assert!(conforms(&old.nodes[0].proto.as_ref().unwrap().proto));
        let retyped = parse(
            "#VRML V2.0 utf8\nPROTO PhysicalPointLight [ field SFVec3f location 0 0 0 field SFColor intensity 0 0 0 \
             field SFColor power 0 0 0 field SFBool on TRUE field SFString iesUrl \"\" ] { PointLight {} } PhysicalPointLight {}",
        )
        .unwrap();
        assert!(!conforms(&retyped.nodes[0].proto.as_ref().unwrap().proto));
    }
}
