//! A dataset applies only to its scene: the dataset-versus-scene checks. The geometry/material
//! fingerprint must be the one recorded (or, for a version-1 file, the older hash that also
//! covered emission: [`Scene::geometry_v1`]); each light is matched by name and must emit from
//! the same place in the same way (its shape hash), or its samples no longer apply.
//! Rendering checks lights one by one as it lights them ([`super::lighting`]); extending a
//! dataset needs every one of its lights ([`scene_lights`]). A refusal names the meshes and
//! materials that changed when the dataset recorded their hashes (format 4 on:
//! [`crate::scene::ObjectHash`]); they explain, the fingerprint decides.

use super::{DatasetHeader, LightTable};
use crate::scene::{Fingerprint, ObjectChanges, ObjectHash, Scene, object_changes};
use std::fmt;

/// The scene's geometry or materials are not those the dataset was traced in.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "traced from a different scene: {} (geometry/material fingerprint {} ≠ {})",
    ChangesText(changes.as_ref()),
    recorded.geometry_hex(),
    current.geometry_hex()
)]
pub struct SceneMismatch {
    /// The fingerprint the dataset recorded.
    pub recorded: Fingerprint,
    /// The scene's.
    pub current: Fingerprint,
    /// The meshes and materials that differ, `None` when the dataset records no object hashes
    /// (written before format 4).
    pub changes: Option<ObjectChanges>,
}

/// Checks that `scene` has the geometry and materials `header` was traced in (lights are
/// checked where they are used).
pub fn check_scene(header: &DatasetHeader, scene: &Scene) -> Result<(), SceneMismatch> {
    let recorded = header.fingerprint;
    if scene.fingerprint.geometry != recorded.geometry && scene.geometry_v1 != recorded.geometry {
        let changes = differing_objects(&header.objects, &scene.objects);
        return Err(SceneMismatch { recorded, current: scene.fingerprint, changes });
    }
    Ok(())
}

/// The objects that differ from `recorded` in `current`, `None` if either list is unknown
/// (empty: a dataset older than format 4).
pub fn differing_objects(recorded: &[ObjectHash], current: &[ObjectHash]) -> Option<ObjectChanges> {
    (!recorded.is_empty() && !current.is_empty()).then(|| object_changes(recorded, current))
}

/// What differs, for a message: the objects, or that the dataset cannot say.
pub struct ChangesText<'a>(pub Option<&'a ObjectChanges>);

impl fmt::Display for ChangesText<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Some(changes) => changes.fmt(f),
            None => f.write_str(
                "its geometry or materials differ (the dataset predates format 4, so it keeps one hash of the \
                 whole scene, not which mesh or material changed)",
            ),
        }
    }
}

/// A light of the dataset that the scene does not have as it was traced.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum LightMismatch {
    /// The light emits from another place or in another way (its shape hash differs).
    #[error("light '{0}' has moved or changed shape since the trace")]
    Moved(String),
    /// No light of the scene has the name.
    #[error("light '{0}' of the dataset is not in the scene any more")]
    Gone(String),
}

/// The scene light of each light of the dataset's table, found by name; refuses lights that
/// are gone or emit from another place or in another way (their shape hash differs).
pub fn scene_lights(table: &LightTable, scene: &Scene) -> Result<Vec<usize>, LightMismatch> {
    table
        .lights
        .iter()
        .map(|record| match scene.light_index(&record.name) {
            Some(i) if scene.light_shapes[i] == record.shape => Ok(i),
            Some(_) => Err(LightMismatch::Moved(record.name.clone())),
            None => Err(LightMismatch::Gone(record.name.clone())),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::new_trace;
    use crate::dataset::testing::cornell_with_bulb;
    use crate::math::Vec3;
    use crate::scene::cornell_box;

    #[test]
    fn geometry_and_materials_must_be_the_traced_ones_and_the_version_1_hash_is_accepted() {
        let scene = Scene::build(&cornell_box()).unwrap();
        let (mut header, _) = new_trace(&scene, "box", Default::default());
        assert_eq!(check_scene(&header, &scene), Ok(()));
        // Lights do not enter the geometry hash: the box with a bulb is the same geometry.
        assert_eq!(check_scene(&header, &Scene::build(&cornell_with_bulb()).unwrap()), Ok(()));
        header.fingerprint.geometry = scene.geometry_v1;
        assert_eq!(check_scene(&header, &scene), Ok(()), "a version-1 file's hash");
        let mut repainted = cornell_box();
        repainted.materials[2] = repainted.materials[1].clone();
        let repainted = Scene::build(&repainted).unwrap();
        let e = check_scene(&header, &repainted).unwrap_err();
        assert_eq!((e.recorded, e.current), (header.fingerprint, repainted.fingerprint));
        assert!(e.to_string().contains(&repainted.fingerprint.geometry_hex()), "{e}");
    }

    /// A refusal names what changed: the repainted material and every mesh painted with it,
    /// a moved mesh, a new one; a dataset without object hashes says it cannot tell.
    #[test]
    fn a_refusal_names_the_meshes_and_materials_that_changed() {
        let desc = cornell_box();
        let scene = Scene::build(&desc).unwrap();
        let (header, _) = new_trace(&scene, "box", Default::default());
        let mut changed = desc.clone();
        let painted = changed.meshes[0].material;
        changed.materials[painted] = changed.materials[(painted + 1) % changed.materials.len()].clone();
        changed.materials[painted].name = desc.materials[painted].name.clone();
        let moved = changed.meshes.iter().position(|m| m.material != painted).unwrap();
        changed.meshes[moved].positions[0].y += 0.01;
        let mut extra = changed.meshes[moved].clone();
        extra.name = "a new box".into();
        changed.meshes.push(extra);
        let e = check_scene(&header, &Scene::build(&changed).unwrap()).unwrap_err();
        let text = e.to_string();
        for part in [
            format!("mesh '{}' changed", desc.meshes[0].name),
            format!("material '{}' changed", desc.materials[painted].name),
            format!("mesh '{}' changed", desc.meshes[moved].name),
            "mesh 'a new box' is new".to_string(),
        ] {
            assert!(text.contains(&part), "{part:?} not in {text}");
        }
        let untouched =
            desc.meshes.iter().find(|m| m.material != painted && m.name != desc.meshes[moved].name);
        if let Some(m) = untouched {
            assert!(!text.contains(&format!("mesh '{}'", m.name)), "{text}");
        }
        let old = DatasetHeader { objects: Vec::new(), ..header };
        let e = check_scene(&old, &Scene::build(&changed).unwrap()).unwrap_err();
        assert_eq!(e.changes, None);
        assert!(e.to_string().contains("predates format 4"), "{e}");
    }

    #[test]
    fn extending_needs_every_light_of_the_dataset_unmoved() {
        let scene = Scene::build(&cornell_with_bulb()).unwrap();
        let (header, _) = new_trace(&scene, "two", Default::default());
        assert_eq!(scene_lights(&header.table, &scene), Ok(vec![0, 1]));
        let mut brighter = cornell_with_bulb();
        brighter.point_lights[0].intensity *= 3.0;
        let brighter = Scene::build(&brighter).unwrap();
        assert_eq!(scene_lights(&header.table, &brighter), Ok(vec![0, 1]), "power is not shape");
        let mut moved = cornell_with_bulb();
        moved.point_lights[0].position += Vec3::X * 0.1;
        let moved = Scene::build(&moved).unwrap();
        assert_eq!(scene_lights(&header.table, &moved), Err(LightMismatch::Moved("bulb".into())));
        let gone = Scene::build(&cornell_box()).unwrap();
        assert_eq!(scene_lights(&header.table, &gone), Err(LightMismatch::Gone("bulb".into())));
    }
}
