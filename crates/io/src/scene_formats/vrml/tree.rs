//! The generic VRML node tree the parser produces: nodes with their type name, position and
//! typed field values. It knows nothing about rendering; [`super::convert`] gives it meaning.

use super::lexer::Pos;
use std::rc::Rc;

/// A shared node (`DEF`/`USE` share one node in several places).
pub type NodeRef = Rc<Node>;

/// The twenty VRML97 field types (§5).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FieldType {
    /// One boolean (`TRUE`, `FALSE`).
    SFBool,
    /// One RGB colour, three floats in [0, 1].
    SFColor,
    /// One single-precision float.
    SFFloat,
    /// One uncompressed image: width, height, components, then the pixels.
    SFImage,
    /// One 32-bit integer.
    SFInt32,
    /// One node, or `NULL`.
    SFNode,
    /// One rotation: an axis (three floats) and an angle in radians.
    SFRotation,
    /// One double-quoted UTF-8 string.
    SFString,
    /// One time, seconds as a double.
    SFTime,
    /// One 2D vector of floats.
    SFVec2f,
    /// One 3D vector of floats.
    SFVec3f,
    /// Zero or more RGB colours.
    MFColor,
    /// Zero or more floats.
    MFFloat,
    /// Zero or more 32-bit integers.
    MFInt32,
    /// Zero or more nodes.
    MFNode,
    /// Zero or more rotations.
    MFRotation,
    /// Zero or more strings.
    MFString,
    /// Zero or more times.
    MFTime,
    /// Zero or more 2D vectors.
    MFVec2f,
    /// Zero or more 3D vectors.
    MFVec3f,
}

impl FieldType {
    /// The type named `s` (`SFVec3f`…), if it is one.
    pub fn from_name(s: &str) -> Option<Self> {
        use FieldType::*;
        Some(match s {
            "SFBool" => SFBool,
            "SFColor" => SFColor,
            "SFFloat" => SFFloat,
            "SFImage" => SFImage,
            "SFInt32" => SFInt32,
            "SFNode" => SFNode,
            "SFRotation" => SFRotation,
            "SFString" => SFString,
            "SFTime" => SFTime,
            "SFVec2f" => SFVec2f,
            "SFVec3f" => SFVec3f,
            "MFColor" => MFColor,
            "MFFloat" => MFFloat,
            "MFInt32" => MFInt32,
            "MFNode" => MFNode,
            "MFRotation" => MFRotation,
            "MFString" => MFString,
            "MFTime" => MFTime,
            "MFVec2f" => MFVec2f,
            "MFVec3f" => MFVec3f,
            _ => return None,
        })
    }
}

/// A field's value. Colours share the `Vec3` variants with vectors.
#[derive(Clone, Debug, PartialEq)]
pub enum FieldValue {
    /// SFBool.
    Bool(bool),
    /// SFFloat.
    Float(f32),
    /// SFInt32.
    Int(i32),
    /// SFTime.
    Time(f64),
    /// SFString.
    Str(String),
    /// SFVec2f.
    Vec2([f32; 2]),
    /// SFVec3f, SFColor.
    Vec3([f32; 3]),
    /// SFRotation: axis x, y, z and angle in radians.
    Rotation([f32; 4]),
    /// SFImage: width, height, components, then the pixels.
    Image(Vec<i32>),
    /// SFNode (`None` is `NULL`).
    Node(Option<NodeRef>),
    /// MFFloat.
    Floats(Vec<f32>),
    /// MFInt32.
    Ints(Vec<i32>),
    /// MFTime.
    Times(Vec<f64>),
    /// MFString.
    Strs(Vec<String>),
    /// MFVec2f.
    Vec2s(Vec<[f32; 2]>),
    /// MFVec3f, MFColor.
    Vec3s(Vec<[f32; 3]>),
    /// MFRotation.
    Rotations(Vec<[f32; 4]>),
    /// MFNode.
    Nodes(Vec<NodeRef>),
    /// Inside a PROTO body: `IS name`, replaced when the PROTO is instantiated.
    Is(String),
}

/// A field as written in a node.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// Field name.
    pub name: String,
    /// Where the name is.
    pub pos: Pos,
    /// Its value.
    pub value: FieldValue,
}

/// A PROTO declaration (§4.8): its interface and its body.
#[derive(Debug, PartialEq)]
pub struct ProtoDef {
    /// The PROTO's name.
    pub name: String,
    /// Where it is declared.
    pub pos: Pos,
    /// Interface: `field`/`exposedField` declarations with their default values
    /// (`eventIn`/`eventOut` are kept with `None`).
    pub interface: Vec<InterfaceDecl>,
    /// The body's nodes; the first one is what an instance is. `None` for an EXTERNPROTO.
    pub body: Option<Vec<NodeRef>>,
    /// EXTERNPROTO URLs (empty for a PROTO).
    pub urls: Vec<String>,
}

/// One interface declaration of a PROTO.
#[derive(Clone, Debug, PartialEq)]
pub struct InterfaceDecl {
    /// `field`, `exposedField`, `eventIn` or `eventOut`.
    pub kind: &'static str,
    /// The field type.
    pub ty: FieldType,
    /// The name.
    pub name: String,
    /// Default value (fields and exposedFields of a PROTO).
    pub default: Option<FieldValue>,
}

/// What a node expanded from a PROTO instance remembers of it: the PROTO and the instance's
/// field values (defaults filled in). [`super::convert`] uses it to recognise the extension.
#[derive(Debug, PartialEq)]
pub struct ProtoInstance {
    /// The PROTO.
    pub proto: Rc<ProtoDef>,
    /// Every field of the interface with the instance's value.
    pub fields: Vec<(String, FieldValue)>,
}

impl ProtoInstance {
    /// The instance's value of `name`.
    pub fn get(&self, name: &str) -> Option<&FieldValue> {
        self.fields.iter().find(|(n, _)| n == name).map(|(_, v)| v)
    }
}

/// A node.
#[derive(Debug, PartialEq)]
pub struct Node {
    /// Node type: a standard node (`Transform`), or a PROTO name for an unexpanded instance
    /// inside a PROTO body, or an unknown name (the node was skipped and has no fields).
    pub type_name: String,
    /// Where the node type name is.
    pub pos: Pos,
    /// The `DEF` name, if any.
    pub def_name: Option<String>,
    /// The fields given in the file (not the defaults).
    pub fields: Vec<Field>,
    /// Set for an instance of a PROTO: before expansion (inside a PROTO body) the PROTO to
    /// expand; after expansion the node is the PROTO's first body node and this remembers the
    /// instance.
    pub proto: Option<Rc<ProtoInstance>>,
    /// True for an instance not expanded yet (only inside PROTO bodies).
    pub unexpanded: bool,
    /// True if the node type was unknown (the parser warned and skipped its body).
    pub unknown: bool,
}

impl Node {
    /// The value of field `name`, if it was given.
    pub fn get(&self, name: &str) -> Option<&FieldValue> {
        self.fields.iter().rev().find(|f| f.name == name).map(|f| &f.value)
    }

    /// SFFloat `name`, or `default`.
    pub fn float(&self, name: &str, default: f32) -> f32 {
        match self.get(name) {
            Some(FieldValue::Float(v)) => *v,
            _ => default,
        }
    }

    /// SFInt32 `name`, or `default`.
    pub fn int(&self, name: &str, default: i32) -> i32 {
        match self.get(name) {
            Some(FieldValue::Int(v)) => *v,
            _ => default,
        }
    }

    /// SFBool `name`, or `default`.
    pub fn bool(&self, name: &str, default: bool) -> bool {
        match self.get(name) {
            Some(FieldValue::Bool(v)) => *v,
            _ => default,
        }
    }

    /// SFVec3f/SFColor `name`, or `default`.
    pub fn vec3(&self, name: &str, default: [f32; 3]) -> [f32; 3] {
        match self.get(name) {
            Some(FieldValue::Vec3(v)) => *v,
            _ => default,
        }
    }

    /// SFRotation `name`, or `default`.
    pub fn rotation(&self, name: &str, default: [f32; 4]) -> [f32; 4] {
        match self.get(name) {
            Some(FieldValue::Rotation(v)) => *v,
            _ => default,
        }
    }

    /// SFNode `name` (`None` if absent or NULL).
    pub fn node(&self, name: &str) -> Option<&NodeRef> {
        match self.get(name) {
            Some(FieldValue::Node(Some(n))) => Some(n),
            _ => None,
        }
    }

    /// MFNode `name` (empty if absent).
    pub fn nodes(&self, name: &str) -> &[NodeRef] {
        match self.get(name) {
            Some(FieldValue::Nodes(v)) => v,
            _ => &[],
        }
    }
}

impl FieldValue {
    /// The colour/vector, if this is one.
    pub fn as_vec3(&self) -> Option<[f32; 3]> {
        match self {
            FieldValue::Vec3(v) => Some(*v),
            _ => None,
        }
    }

    /// The float, if this is one.
    pub fn as_float(&self) -> Option<f32> {
        match self {
            FieldValue::Float(v) => Some(*v),
            _ => None,
        }
    }
}
