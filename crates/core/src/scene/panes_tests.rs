//! `Scene::shadow_transmittance` on stacks of horizontal squares: one pane's T at the crossing
//! angle (per channel, either face, unbounded rays), panes multiplying, and the segment blocked
//! by a mirror, an opaque surface or more than `MAX_PANES` panes.

use super::*;
use crate::bsdf::{Bsdf, Lambert, Material, SmoothConductor, ThinDielectric};
use crate::math::Vec3;
use crate::scene::{MeshDesc, PointLightDesc, SceneDescription};

/// A clear pane of index 1.52 in air, a tinted one, a mirror and a grey diffuser.
fn materials() -> Vec<Material> {
    let m = |name: &str, bsdf| Material { name: name.into(), bsdf, two_sided: true };
    vec![
        m("clear", Bsdf::ThinDielectric(ThinDielectric::new(1.52, 1.0, Rgb::ONE, Rgb::ONE).unwrap())),
        m(
            "tinted",
            Bsdf::ThinDielectric(ThinDielectric::new(1.52, 1.0, Rgb::ONE, Rgb::new(0.9, 0.6, 0.3)).unwrap()),
        ),
        m("mirror", Bsdf::SmoothConductor(SmoothConductor::new(Rgb::ONE, None).unwrap())),
        m("grey", Bsdf::Lambert(Lambert::new(Rgb::splat(0.5)).unwrap())),
    ]
}

/// Horizontal 10 m squares at the heights `sheets` give, of the materials they name (indices
/// into [`materials`]), and a point light high above (a scene needs a light).
fn sheets(sheets: &[(f32, usize)]) -> Scene {
    let meshes = sheets
        .iter()
        .enumerate()
        .map(|(i, &(y, material))| MeshDesc::square_at(format!("sheet{i}"), y, material))
        .collect();
    let desc = SceneDescription {
        materials: materials(),
        meshes,
        point_lights: vec![PointLightDesc {
            name: "bulb".into(),
            position: Vec3::new(0.0, 50.0, 0.0),
            intensity: Rgb::ONE,
            ..Default::default()
        }],
        ..Default::default()
    };
    Scene::build(&desc).unwrap()
}

/// The segment from (0.3, 0, −0.2) toward `dir` (normalised), `d` long (off the squares'
/// diagonals: a ray exactly through the edge two triangles share may miss both).
fn segment(dir: Vec3, d: f32) -> Ray {
    Ray { origin: Vec3::new(0.3, 0.0, -0.2), dir: dir.normalize(), t_max: d }
}

/// T of pane material `m` for a ray along unit `dir` crossing a horizontal sheet.
fn pane_t(m: usize, dir: Vec3) -> Rgb {
    let Bsdf::ThinDielectric(b) = &materials()[m].bsdf else { unreachable!() };
    b.transmittance(dir.normalize().y)
}

/// Without panes the answer is `occluded`'s; through one pane it is the pane's T at the
/// crossing angle, per channel, on either face and for unbounded rays; two panes multiply.
#[test]
fn panes_multiply_their_straight_through_transmittance() {
    let dir = Vec3::new(0.4, 1.0, 0.2);
    let opaque = sheets(&[(1.0, 3)]);
    assert!(!opaque.panes);
    assert_eq!(opaque.shadow_transmittance(&segment(dir, 0.5)), Some(Rgb::ONE));
    assert_eq!(opaque.shadow_transmittance(&segment(dir, 5.0)), None);
    assert_eq!(opaque.shadow_transmittance(&segment(-dir, 5.0)), Some(Rgb::ONE));

    let one = sheets(&[(1.0, 1)]);
    assert!(one.panes);
    let t = pane_t(1, dir);
    assert!(t.x < 0.9 && t.x > 0.5 && t.z < t.y && t.y < t.x, "{t:?}");
    assert_eq!(one.shadow_transmittance(&segment(dir, 0.5)), Some(Rgb::ONE), "short of the pane");
    assert_eq!(one.shadow_transmittance(&segment(dir, 5.0)), Some(t));
    assert_eq!(one.shadow_transmittance(&segment(dir, f32::INFINITY)), Some(t));
    let above = Ray { origin: Vec3::new(0.3, 2.0, -0.2), dir: -dir.normalize(), t_max: 5.0 };
    assert_eq!(one.shadow_transmittance(&above), Some(t), "from the back face");

    let steep = Vec3::new(0.0, 1.0, 0.05);
    let two = sheets(&[(1.0, 0), (2.0, 1)]);
    let both = two.shadow_transmittance(&segment(steep, 10.0)).unwrap();
    let product = pane_t(0, steep) * pane_t(1, steep);
    assert!((both - product).abs().max_element() < 1e-6, "{both:?} vs {product:?}");
    assert_eq!(two.shadow_transmittance(&segment(steep, 1.5)), Some(pane_t(0, steep)));
}

/// A mirror or an opaque surface behind (or before) a pane blocks the segment, as do more
/// than `MAX_PANES` panes; exactly `MAX_PANES` pass.
#[test]
fn other_surfaces_and_too_many_panes_block() {
    let up = Vec3::Y;
    for blocker in [2, 3] {
        let s = sheets(&[(1.0, 0), (2.0, blocker)]);
        assert_eq!(s.shadow_transmittance(&segment(up, 1.5)), Some(pane_t(0, up)));
        assert_eq!(s.shadow_transmittance(&segment(up, 3.0)), None, "material {blocker}");
        let s = sheets(&[(1.0, blocker), (2.0, 0)]);
        assert_eq!(s.shadow_transmittance(&segment(up, 3.0)), None, "material {blocker} first");
    }
    let stack = |n: usize| sheets(&(1..=n).map(|k| (k as f32 * 0.5, 0)).collect::<Vec<_>>());
    let at_most = stack(MAX_PANES).shadow_transmittance(&segment(up, 100.0)).unwrap();
    let expected = pane_t(0, up).x.powi(MAX_PANES as i32);
    assert!((at_most.x - expected).abs() < 1e-5, "{at_most:?} vs {expected}");
    assert_eq!(stack(MAX_PANES + 1).shadow_transmittance(&segment(up, 100.0)), None);
    assert!(stack(MAX_PANES + 1).shadow_transmittance(&segment(up, 0.5 * MAX_PANES as f32 + 0.25)).is_some());
}
