//! PROTO instantiation (§4.8.3): a copy of the PROTO body's first node in which every
//! `field IS name` takes the instance's value of `name` (or the interface's default), and every
//! PROTO instance nested in the body is expanded in turn.
//!
//! `DEF`/`USE` sharing inside a body is kept within each copy. Expansion is bounded: at most
//! [`MAX_EXPANDED_NODES`] nodes and [`MAX_EXPANDED_BYTES`] bytes of copied field values (a
//! PROTO carrying a big point list would otherwise multiply it under the node limit) are
//! created in a whole file, and instances nest at most [`MAX_EXPANSION_DEPTH`] levels, so a
//! small hostile file cannot exhaust memory or the stack.

use super::lexer::Pos;
use super::tree::{Field, FieldValue, Node, NodeRef, ProtoDef, ProtoInstance};
use std::collections::HashMap;
use std::rc::Rc;

/// Most nodes all PROTO expansions of one file may create.
pub const MAX_EXPANDED_NODES: usize = 2_000_000;
/// Most bytes of field values (arrays, strings) all PROTO expansions of one file may copy.
pub const MAX_EXPANDED_BYTES: usize = 256 << 20;
/// Deepest node nesting an expansion may reach (counting the nodes around the instance).
pub const MAX_EXPANSION_DEPTH: usize = 400;

/// An expansion beyond the limits.
#[derive(Clone, Debug, PartialEq)]
pub struct ExpandError {
    /// The instance being expanded.
    pub pos: Pos,
    /// Which limit.
    pub message: String,
}

/// Expands PROTO instances, counting what it creates.
#[derive(Debug, Default)]
pub struct Expander {
    created: usize,
    bytes: usize,
}

type Memo = HashMap<*const Node, NodeRef>;

impl Expander {
    /// The node an instance of `proto` with the given field values is. `depth` is the nesting
    /// level of the instance.
    pub fn instantiate(
        &mut self,
        proto: &Rc<ProtoDef>,
        given: Vec<(String, FieldValue)>,
        pos: Pos,
        def_name: Option<String>,
        depth: usize,
    ) -> Result<NodeRef, ExpandError> {
        if depth > MAX_EXPANSION_DEPTH {
            return Err(ExpandError {
                pos,
                message: format!("PROTO instances nested more than {MAX_EXPANSION_DEPTH} levels deep"),
            });
        }
        let mut env: Vec<(String, FieldValue)> = Vec::new();
        for d in &proto.interface {
            if let Some(default) = &d.default {
                let v = given.iter().rev().find(|(n, _)| *n == d.name).map(|(_, v)| v.clone());
                env.push((d.name.clone(), v.unwrap_or_else(|| default.clone())));
            }
        }
        let Some(first) = proto.body.as_ref().and_then(|b| b.first()) else {
            return Err(ExpandError {
                pos,
                message: format!("PROTO `{}` has no body to expand", proto.name),
            });
        };
        let mut memo = Memo::new();
        let node = self.copy(first, &env, &mut memo, pos, depth + 1)?;
        let node = Rc::try_unwrap(node).unwrap_or_else(|shared| clone_shallow(&shared));
        Ok(Rc::new(Node {
            pos,
            def_name,
            proto: Some(Rc::new(ProtoInstance { proto: proto.clone(), fields: env })),
            ..node
        }))
    }

    fn copy(
        &mut self,
        n: &NodeRef,
        env: &[(String, FieldValue)],
        memo: &mut Memo,
        pos: Pos,
        depth: usize,
    ) -> Result<NodeRef, ExpandError> {
        if let Some(done) = memo.get(&Rc::as_ptr(n)) {
            return Ok(done.clone());
        }
        if depth > MAX_EXPANSION_DEPTH {
            return Err(ExpandError {
                pos,
                message: format!("PROTO expansion nests nodes more than {MAX_EXPANSION_DEPTH} levels deep"),
            });
        }
        self.created += 1;
        if self.created > MAX_EXPANDED_NODES {
            return Err(ExpandError {
                pos,
                message: format!("PROTO expansion would create more than {MAX_EXPANDED_NODES} nodes"),
            });
        }
        let out = if n.unexpanded {
            let Some(inst) = &n.proto else {
                return Err(ExpandError { pos, message: "internal: unexpanded node without PROTO".into() });
            };
            let mut given = Vec::with_capacity(inst.fields.len());
            for (name, v) in &inst.fields {
                if let Some(v) = self.value(v, env, memo, pos, depth)? {
                    given.push((name.clone(), v));
                }
            }
            self.instantiate(&inst.proto, given, n.pos, n.def_name.clone(), depth)?
        } else {
            let mut fields = Vec::with_capacity(n.fields.len());
            for f in &n.fields {
                if let Some(value) = self.value(&f.value, env, memo, pos, depth)? {
                    fields.push(Field { name: f.name.clone(), pos: f.pos, value });
                }
            }
            Rc::new(Node { fields, ..clone_shallow(n) })
        };
        memo.insert(Rc::as_ptr(n), out.clone());
        Ok(out)
    }

    /// A field value with IS references resolved (`None`: an IS to an event, dropped).
    fn value(
        &mut self,
        v: &FieldValue,
        env: &[(String, FieldValue)],
        memo: &mut Memo,
        pos: Pos,
        depth: usize,
    ) -> Result<Option<FieldValue>, ExpandError> {
        let mut count = |v: &FieldValue| {
            self.bytes += value_bytes(v);
            if self.bytes > MAX_EXPANDED_BYTES {
                Err(ExpandError {
                    pos,
                    message: format!(
                        "PROTO expansion would copy more than {} MB of field values",
                        MAX_EXPANDED_BYTES >> 20
                    ),
                })
            } else {
                Ok(v.clone())
            }
        };
        Ok(Some(match v {
            FieldValue::Is(name) => match env.iter().find(|(n, _)| n == name) {
                Some((_, v)) => count(v)?,
                None => return Ok(None),
            },
            FieldValue::Node(Some(c)) => FieldValue::Node(Some(self.copy(c, env, memo, pos, depth + 1)?)),
            FieldValue::Nodes(v) => {
                let mut out = Vec::with_capacity(v.len());
                for c in v {
                    out.push(self.copy(c, env, memo, pos, depth + 1)?);
                }
                FieldValue::Nodes(out)
            }
            other => count(other)?,
        }))
    }
}

/// The heap bytes a field value's copy takes (nodes are counted as nodes, not here).
fn value_bytes(v: &FieldValue) -> usize {
    use std::mem::size_of_val;
    match v {
        FieldValue::Str(s) | FieldValue::Is(s) => s.len(),
        FieldValue::Image(v) | FieldValue::Ints(v) => size_of_val(&v[..]),
        FieldValue::Floats(v) => size_of_val(&v[..]),
        FieldValue::Times(v) => size_of_val(&v[..]),
        FieldValue::Strs(v) => v.iter().map(|s| s.len() + size_of::<String>()).sum(),
        FieldValue::Vec2s(v) => size_of_val(&v[..]),
        FieldValue::Vec3s(v) => size_of_val(&v[..]),
        FieldValue::Rotations(v) => size_of_val(&v[..]),
        _ => 0,
    }
}

fn clone_shallow(n: &Node) -> Node {
    Node {
        type_name: n.type_name.clone(),
        pos: n.pos,
        def_name: n.def_name.clone(),
        fields: n.fields.clone(),
        proto: n.proto.clone(),
        unexpanded: false,
        unknown: n.unknown,
    }
}

#[cfg(test)]
mod tests {
    use super::super::parser::parse;
    use super::*;

    fn parse_ok(body: &str) -> super::super::parser::Parsed {
        parse(&format!("#VRML V2.0 utf8\n{body}")).unwrap()
    }

    #[test]
    fn is_fields_take_instance_values_or_defaults() {
        let p = parse_ok(
            "PROTO Col [ field SFColor c 1 0 0 field SFFloat s 0.5 exposedField MFNode kids [] ] \
               { Group { children [ Shape { appearance Appearance { material Material { diffuseColor IS c shininess IS s } } } ] } }\n\
             Col { c 0 1 0 }\nCol { }",
        );
        assert_eq!(p.nodes.len(), 2);
        let colour = |n: &NodeRef| -> FieldValue {
            let FieldValue::Nodes(k) = n.get("children").unwrap() else { panic!() };
            let FieldValue::Node(Some(a)) = k[0].get("appearance").unwrap() else { panic!() };
            let FieldValue::Node(Some(m)) = a.get("material").unwrap() else { panic!() };
            m.get("diffuseColor").unwrap().clone()
        };
        assert_eq!(colour(&p.nodes[0]), FieldValue::Vec3([0.0, 1.0, 0.0]));
        assert_eq!(colour(&p.nodes[1]), FieldValue::Vec3([1.0, 0.0, 0.0]));
        assert_eq!(p.nodes[0].type_name, "Group");
        let inst = p.nodes[0].proto.as_ref().unwrap();
        assert_eq!(inst.proto.name, "Col");
        assert_eq!(inst.get("s"), Some(&FieldValue::Float(0.5)));
    }

    #[test]
    fn nested_protos_pass_values_through() {
        let p = parse_ok(
            "PROTO A [ field SFVec3f size 1 1 1 ] { Box { size IS size } }\n\
             PROTO B [ field SFVec3f sz 2 2 2 ] { Shape { geometry A { size IS sz } } }\n\
             B { sz 3 3 3 } B {}",
        );
        let size = |n: &NodeRef| {
            let FieldValue::Node(Some(g)) = n.get("geometry").unwrap() else { panic!() };
            assert_eq!(g.type_name, "Box");
            g.get("size").unwrap().clone()
        };
        assert_eq!(size(&p.nodes[0]), FieldValue::Vec3([3.0; 3]));
        assert_eq!(size(&p.nodes[1]), FieldValue::Vec3([2.0; 3]));
    }

    #[test]
    fn is_errors_and_externprotos() {
        let e = parse("#VRML V2.0 utf8\nPROTO A [ field SFFloat r 1 ] { Box { size IS r } }").unwrap_err();
        assert!(e.message.contains("SFVec3f"), "{}", e.message);
        let e = parse("#VRML V2.0 utf8\nPROTO A [ ] { Box { size IS q } }").unwrap_err();
        assert!(e.message.contains("declares no `q`"), "{}", e.message);
        let p = parse_ok("EXTERNPROTO E [ field SFFloat x ] [\"e.wrl#E\"]\nE { x 1 }");
        assert!(p.nodes[0].unknown);
        assert!(p.warnings[0].1.contains("EXTERNPROTO"), "{:?}", p.warnings);
    }

    #[test]
    fn exponential_expansion_is_bounded() {
        let mut s = String::from("PROTO P0 [ ] { Group { } }\n");
        for i in 1..40 {
            let p = i - 1;
            s += &format!("PROTO P{i} [ ] {{ Group {{ children [ P{p} {{}} P{p} {{}} ] }} }}\n");
        }
        s += "P39 {}";
        let e = parse(&format!("#VRML V2.0 utf8\n{s}")).unwrap_err();
        assert!(e.message.contains("more than"), "{}", e.message);
    }
}
