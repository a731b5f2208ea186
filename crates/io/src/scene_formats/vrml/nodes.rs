//! The 54 standard VRML97 node types and the types of their fields and exposedFields (§6), which
//! the parser needs to read a field's value (VRML values are not self-describing: `1 2 3` is an
//! SFVec3f, an SFColor or three MFFloat values depending on the field). Default values live in
//! the converter, where they are used.

use super::tree::FieldType;
use std::collections::HashMap;
use std::sync::OnceLock;

const BBOX: &str = "SFVec3f bboxCenter; SFVec3f bboxSize";

/// (node, "Type name; Type name; …"): fields and exposedFields of each standard node.
const SPECS: &[(&str, &str)] = &[
    ("Anchor", "MFNode children; SFString description; MFString parameter; MFString url; BBOX"),
    ("Appearance", "SFNode material; SFNode texture; SFNode textureTransform"),
    (
        "AudioClip",
        "SFString description; SFBool loop; SFFloat pitch; SFTime startTime; SFTime stopTime; MFString url",
    ),
    (
        "Background",
        "MFFloat groundAngle; MFColor groundColor; MFString backUrl; MFString bottomUrl; MFString frontUrl; \
         MFString leftUrl; MFString rightUrl; MFString topUrl; MFFloat skyAngle; MFColor skyColor",
    ),
    ("Billboard", "SFVec3f axisOfRotation; MFNode children; BBOX"),
    ("Box", "SFVec3f size"),
    ("Collision", "MFNode children; SFBool collide; BBOX; SFNode proxy"),
    ("Color", "MFColor color"),
    ("ColorInterpolator", "MFFloat key; MFColor keyValue"),
    ("Cone", "SFFloat bottomRadius; SFFloat height; SFBool side; SFBool bottom"),
    ("Coordinate", "MFVec3f point"),
    ("CoordinateInterpolator", "MFFloat key; MFVec3f keyValue"),
    ("Cylinder", "SFBool bottom; SFFloat height; SFFloat radius; SFBool side; SFBool top"),
    (
        "CylinderSensor",
        "SFBool autoOffset; SFFloat diskAngle; SFBool enabled; SFFloat maxAngle; SFFloat minAngle; SFFloat offset",
    ),
    (
        "DirectionalLight",
        "SFFloat ambientIntensity; SFColor color; SFVec3f direction; SFFloat intensity; SFBool on",
    ),
    (
        "ElevationGrid",
        "SFNode color; SFNode normal; SFNode texCoord; MFFloat height; SFBool ccw; SFBool colorPerVertex; \
         SFFloat creaseAngle; SFBool normalPerVertex; SFBool solid; SFInt32 xDimension; SFFloat xSpacing; \
         SFInt32 zDimension; SFFloat zSpacing",
    ),
    (
        "Extrusion",
        "SFBool beginCap; SFBool ccw; SFBool convex; SFFloat creaseAngle; MFVec2f crossSection; SFBool endCap; \
         MFRotation orientation; MFVec2f scale; SFBool solid; MFVec3f spine",
    ),
    ("Fog", "SFColor color; SFString fogType; SFFloat visibilityRange"),
    (
        "FontStyle",
        "MFString family; SFBool horizontal; MFString justify; SFString language; SFBool leftToRight; \
         SFFloat size; SFFloat spacing; SFString style; SFBool topToBottom",
    ),
    ("Group", "MFNode children; BBOX"),
    ("ImageTexture", "MFString url; SFBool repeatS; SFBool repeatT"),
    (
        "IndexedFaceSet",
        "SFNode color; SFNode coord; SFNode normal; SFNode texCoord; SFBool ccw; MFInt32 colorIndex; \
         SFBool colorPerVertex; SFBool convex; MFInt32 coordIndex; SFFloat creaseAngle; MFInt32 normalIndex; \
         SFBool normalPerVertex; SFBool solid; MFInt32 texCoordIndex",
    ),
    (
        "IndexedLineSet",
        "SFNode color; SFNode coord; MFInt32 colorIndex; SFBool colorPerVertex; MFInt32 coordIndex",
    ),
    ("Inline", "MFString url; BBOX"),
    ("LOD", "MFNode level; SFVec3f center; MFFloat range"),
    (
        "Material",
        "SFFloat ambientIntensity; SFColor diffuseColor; SFColor emissiveColor; SFFloat shininess; \
         SFColor specularColor; SFFloat transparency",
    ),
    (
        "MovieTexture",
        "SFBool loop; SFFloat speed; SFTime startTime; SFTime stopTime; MFString url; SFBool repeatS; SFBool repeatT",
    ),
    (
        "NavigationInfo",
        "MFFloat avatarSize; SFBool headlight; SFFloat speed; MFString type; SFFloat visibilityLimit",
    ),
    ("Normal", "MFVec3f vector"),
    ("NormalInterpolator", "MFFloat key; MFVec3f keyValue"),
    ("OrientationInterpolator", "MFFloat key; MFRotation keyValue"),
    ("PixelTexture", "SFImage image; SFBool repeatS; SFBool repeatT"),
    (
        "PlaneSensor",
        "SFBool autoOffset; SFBool enabled; SFVec2f maxPosition; SFVec2f minPosition; SFVec3f offset",
    ),
    (
        "PointLight",
        "SFFloat ambientIntensity; SFVec3f attenuation; SFColor color; SFFloat intensity; SFVec3f location; \
         SFBool on; SFFloat radius",
    ),
    ("PointSet", "SFNode color; SFNode coord"),
    ("PositionInterpolator", "MFFloat key; MFVec3f keyValue"),
    ("ProximitySensor", "SFVec3f center; SFVec3f size; SFBool enabled"),
    ("ScalarInterpolator", "MFFloat key; MFFloat keyValue"),
    ("Script", "MFString url; SFBool directOutput; SFBool mustEvaluate"),
    ("Shape", "SFNode appearance; SFNode geometry"),
    (
        "Sound",
        "SFVec3f direction; SFFloat intensity; SFVec3f location; SFFloat maxBack; SFFloat maxFront; \
         SFFloat minBack; SFFloat minFront; SFFloat priority; SFNode source; SFBool spatialize",
    ),
    ("Sphere", "SFFloat radius"),
    ("SphereSensor", "SFBool autoOffset; SFBool enabled; SFRotation offset"),
    (
        "SpotLight",
        "SFFloat ambientIntensity; SFVec3f attenuation; SFFloat beamWidth; SFColor color; SFFloat cutOffAngle; \
         SFVec3f direction; SFFloat intensity; SFVec3f location; SFBool on; SFFloat radius",
    ),
    ("Switch", "MFNode choice; SFInt32 whichChoice"),
    ("Text", "MFString string; SFNode fontStyle; MFFloat length; SFFloat maxExtent"),
    ("TextureCoordinate", "MFVec2f point"),
    ("TextureTransform", "SFVec2f center; SFFloat rotation; SFVec2f scale; SFVec2f translation"),
    ("TimeSensor", "SFTime cycleInterval; SFBool enabled; SFBool loop; SFTime startTime; SFTime stopTime"),
    ("TouchSensor", "SFBool enabled"),
    (
        "Transform",
        "SFVec3f center; MFNode children; SFRotation rotation; SFVec3f scale; SFRotation scaleOrientation; \
         SFVec3f translation; BBOX",
    ),
    (
        "Viewpoint",
        "SFFloat fieldOfView; SFBool jump; SFRotation orientation; SFVec3f position; SFString description",
    ),
    ("VisibilitySensor", "SFVec3f center; SFBool enabled; SFVec3f size"),
    ("WorldInfo", "MFString info; SFString title"),
];

type Table = HashMap<&'static str, Vec<(&'static str, FieldType)>>;

fn table() -> &'static Table {
    static TABLE: OnceLock<Table> = OnceLock::new();
    TABLE.get_or_init(|| {
        SPECS
            .iter()
            .map(|&(node, spec)| {
                let fields = spec
                    .split(';')
                    .flat_map(|f| if f.trim() == "BBOX" { BBOX.split(';').collect() } else { vec![f] })
                    .filter_map(|f| {
                        let mut w = f.split_whitespace();
                        Some((FieldType::from_name(w.next()?)?, w.next()?))
                    })
                    .map(|(t, n)| (n, t))
                    .collect();
                (node, fields)
            })
            .collect()
    })
}

/// Whether `node` is a standard VRML97 node type.
pub fn is_standard(node: &str) -> bool {
    table().contains_key(node)
}

/// The type of field (or exposedField) `field` of the standard node `node`.
pub fn field_type(node: &str, field: &str) -> Option<FieldType> {
    table().get(node)?.iter().find(|(n, _)| *n == field).map(|(_, t)| *t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn all_54_nodes_are_known_with_their_field_types() {
        assert_eq!(table().len(), 54);
        assert!(table().values().all(|f| !f.is_empty()));
        assert_eq!(field_type("Transform", "bboxSize"), Some(FieldType::SFVec3f));
        assert_eq!(field_type("IndexedFaceSet", "coordIndex"), Some(FieldType::MFInt32));
        assert_eq!(field_type("Transform", "nope"), None);
        let written: usize =
            SPECS.iter().map(|(_, s)| s.split(';').count() + s.matches("BBOX").count()).sum();
        let total: usize = table().values().map(|f| f.len()).sum();
        assert_eq!(total, written, "a field type name was misspelt in SPECS");
    }
}
