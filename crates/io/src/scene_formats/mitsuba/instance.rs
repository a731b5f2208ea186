//! Instancing: `<shape type="shapegroup" id="…">` holds shapes that are not in the scene
//! themselves, and each `<shape type="instance">` places a copy of them with its own
//! `to_world` (Mitsuba's semantics: the instance's transform applies after each member's own).
//!
//! Opticks bakes every instance into world-space meshes (the core has one triangle BVH, no
//! instancing): memory grows with the instance count, which is fine for the tens to thousands
//! of instances scene files hold. A group is built once, where it is first instanced, and copied
//! per instance: positions by the instance's matrix, shading normals by its inverse transpose,
//! and — as for an analytic shape under a mirroring `to_world` — an analytic member's winding
//! reversed under a mirroring instance, so that its outward normal stays outward (Mitsuba
//! intersects the untransformed shape in the instance's local space). Members are named
//! `INSTANCE/MEMBER` (an instance without an `id` is `instance_N`, N counting the scene's
//! shapes). As in Mitsuba, a group's members cannot emit (an error), groups do not nest, and an
//! instance needs exactly one `<ref>` to a group.

use super::Result;
use super::build::Builder;
use super::properties::Props;
use super::shape::{shape_and_kind, transform_mesh};
use super::xml::Element;
use glam::{DMat3, DMat4};
use opticks_core::scene::MeshDesc;

/// A built group: its members, each with whether it is analytic.
pub type Group = Vec<(MeshDesc, bool)>;

/// Builds the members of shapegroup `g` (in their own `to_world`).
fn build_group<'d>(b: &mut Builder<'d>, g: &'d Element) -> Result<Group> {
    let mut members = Group::new();
    for (k, c) in g.children.iter().enumerate() {
        match (c.tag.as_str(), c.raw("type")) {
            ("shape", Some("shapegroup" | "instance")) => {
                return Err(
                    c.err("a shapegroup cannot hold shapegroups or instances (Mitsuba does not nest them)")
                );
            }
            ("shape", _) => {
                let (mesh, analytic) = shape_and_kind(b, c, k)?;
                if mesh.emission.is_some() {
                    return Err(
                        c.err("a shape in a shapegroup cannot emit (Mitsuba does not instance emitters)")
                    );
                }
                members.push((mesh, analytic));
            }
            (other, _) => {
                return Err(
                    c.err(format!("unsupported element <{other}> inside a shapegroup (only <shape>s)"))
                );
            }
        }
    }
    if members.is_empty() {
        b.warn(g, "this shapegroup holds no shape");
    }
    Ok(members)
}

/// `<shape type="instance">`: the world-space meshes of one copy of its group.
pub fn instance<'d>(b: &mut Builder<'d>, e: &'d Element, index: usize) -> Result<Vec<MeshDesc>> {
    let name = e.attr("id")?.map_or_else(|| format!("instance_{index}"), str::to_string);
    let mut p = Props::of(e)?;
    let refs: Vec<&Element> = p.objects().to_vec();
    let [r] = refs.as_slice() else {
        return Err(e.err(format!(
            "an instance needs exactly one <ref id=\"…\"/> to a shapegroup (it has {})",
            refs.len()
        )));
    };
    let group = match r.target.map(|i| b.doc.top(i)) {
        Some(g) if r.tag == "ref" && g.tag == "shape" && g.raw("type") == Some("shapegroup") => g,
        _ => return Err(r.err("an instance's <ref> must name a top-level <shape type=\"shapegroup\">")),
    };
    let id = group.required("id")?.to_string();
    b.used.insert(id.clone());
    let m = match p.transform("to_world")? {
        Some((t, _)) => t.matrix,
        None => DMat4::IDENTITY,
    };
    b.finish(&p);
    if !b.groups.contains_key(&id) {
        let built = build_group(b, group)?;
        b.groups.insert(id.clone(), built);
    }
    let mirrored = DMat3::from_mat4(m).determinant() < 0.0;
    let mut out = Vec::new();
    for (member, analytic) in &b.groups[&id] {
        let mut mesh = member.clone();
        mesh.name = format!("{name}/{}", member.name);
        mesh.source = Builder::source(e);
        if let Some(i) = transform_mesh(&m, &mut mesh.positions, &mut mesh.normals) {
            return Err(e.err(format!(
                "to_world maps vertex {} of {} to a non-finite point",
                i + 1,
                member.name
            )));
        }
        if *analytic && mirrored {
            mesh.triangles.iter_mut().for_each(|t| t.swap(1, 2));
        }
        out.push(mesh);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use crate::scene_formats::mitsuba::parse;
    use crate::scene_formats::{LoadOptions, SceneFileError};
    use opticks_core::math::Vec3;
    use std::path::Path;

    fn load(body: &str) -> Result<crate::scene_formats::LoadedScene, SceneFileError> {
        let text = format!("<scene version=\"3.0.0\">{body}</scene>");
        parse(&text, Path::new("inst.xml"), &LoadOptions::default())
    }

    const GROUP: &str = r#"<shape type="shapegroup" id="g">
        <shape type="rectangle" id="r"><transform name="to_world"><translate z="1"/></transform></shape>
        <shape type="sphere" id="s"><float name="radius" value="0.5"/></shape></shape>"#;

    #[test]
    fn instances_compose_their_transform_after_each_members() {
        let s = load(&format!(
            r#"{GROUP}<shape type="instance" id="a"><ref id="g"/><transform name="to_world"><translate x="10"/></transform></shape>
            <shape type="instance"><ref id="g"/><transform name="to_world"><scale x="-1"/></transform></shape>"#
        ))
        .unwrap();
        let d = &s.description;
        let names: Vec<&str> = d.meshes.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["a/r", "a/s", "instance_2/r", "instance_2/s"]);
        // The rectangle's own translation first, then the instance's.
        assert!(
            d.meshes[0]
                .positions
                .iter()
                .all(|p| (p.z - 1.0).abs() < 1e-6 && (p.x - 10.0).abs() <= 1.0 + 1e-6)
        );
        // The mirrored sphere still faces outwards: each triangle's normal points away from its centre.
        let sphere = &d.meshes[3];
        for t in &sphere.triangles {
            let [a, b, c] = t.map(|i| sphere.positions[i as usize]);
            let n = (b - a).cross(c - a);
            assert!(n.dot(a + b + c) > 0.0, "inward triangle {t:?}");
        }
        // The rectangle is analytic too: mirrored in x, its normal (the transformed +z) stays +z.
        let (r0, r1) = (&d.meshes[0], &d.meshes[2]);
        let normal = |m: &MeshDesc| {
            let [a, b, c] = m.triangles[0].map(|i| m.positions[i as usize]);
            (b - a).cross(c - a).normalize()
        };
        assert!((normal(r0) - Vec3::Z).length() < 1e-5 && (normal(r1) - Vec3::Z).length() < 1e-5);
        assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    }

    use opticks_core::scene::MeshDesc;

    #[test]
    fn bad_groups_and_instances_are_errors_at_the_element() {
        let cases = [
            (r#"<shape type="instance"/>"#, "exactly one <ref"),
            (
                r#"<bsdf type="diffuse" id="d"/><shape type="instance"><ref id="d"/></shape>"#,
                "must name a top-level <shape type=\"shapegroup\">",
            ),
            (
                r#"<shape type="shapegroup" id="g"><shape type="rectangle"><emitter type="area"/></shape></shape><shape type="instance"><ref id="g"/></shape>"#,
                "cannot emit",
            ),
            (
                r#"<shape type="shapegroup" id="g"><shape type="instance"/></shape><shape type="instance"><ref id="g"/></shape>"#,
                "cannot hold shapegroups",
            ),
        ];
        for (body, needle) in cases {
            let e = load(body).unwrap_err().to_string();
            assert!(e.contains(needle) && e.starts_with("inst.xml:1:"), "{body}: {e}");
        }
        // A group no instance uses: a warning, and nothing in the scene.
        let s = load(&format!(r#"{GROUP}<shape type="rectangle"/>"#)).unwrap();
        assert_eq!(s.description.meshes.len(), 1);
        assert!(s.warnings.iter().any(|w| w.contains("never used")), "{:?}", s.warnings);
    }
}
