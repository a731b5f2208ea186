//! Per-object hashes: which mesh or material of a scene changed since a dataset was traced.
//!
//! The geometry fingerprint ([`super::Fingerprint`]) decides whether a dataset applies to a
//! scene; it is one hash of everything, so on its own it can only say "different scene". Next
//! to it, a scene keeps one hash per mesh and one per material it uses ([`ObjectHash`]), and a
//! dataset (format version 4 on) records them, so a refusal can name what changed: `mesh
//! 'floor' changed; material 'red' is new` ([`object_changes`]). They decide nothing: the
//! fingerprint alone is the law, and a dataset without them (written before format 4) is
//! checked exactly as before.
//!
//! # The encoding is a file-format contract
//!
//! * **Mesh hash**: domain `opticks mesh v1`, then for each triangle of the mesh the scene keeps
//!   exactly the bytes the geometry hash (version 2) records for it: corners, material hash,
//!   shading normals if any. So a mesh's hash changes exactly when its share of the geometry
//!   hash does: moved, re-triangulated, re-smoothed or repainted. Its name is not hashed: it is
//!   the key objects are matched by.
//! * **Material hash**: the version-2 material hash ([`super::fingerprint`]), for each material
//!   some mesh uses, in the scene's material order (an unused material cannot change a result).
//!
//! Objects are matched by kind and name; a name that occurs several times (two meshes both
//! called `group`) is matched occurrence by occurrence, in scene order.

use std::collections::{HashMap, HashSet};
use std::fmt;

/// What an [`ObjectHash`] covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ObjectKind {
    /// A mesh (a shape of the scene file): its triangles, their materials and normals.
    Mesh,
    /// A material some mesh uses.
    Material,
}

impl ObjectKind {
    /// The word for messages: `mesh`, `material`.
    pub fn word(self) -> &'static str {
        match self {
            ObjectKind::Mesh => "mesh",
            ObjectKind::Material => "material",
        }
    }
}

/// The content hash of one named object of a scene.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ObjectHash {
    /// Mesh or material.
    pub kind: ObjectKind,
    /// Its name in the scene (a shape's id, a material's name).
    pub name: String,
    /// BLAKE3 (first 16 bytes) of its content, as the module docs spell out.
    pub hash: [u8; 16],
}

/// How one object differs between a recorded and a current scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Change {
    /// In both, with another hash.
    Changed,
    /// Only in the current scene.
    New,
    /// Only in the recorded one.
    Gone,
}

/// The objects that differ between two scenes, in scene order (recorded objects first, then
/// those only in the current scene).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ObjectChanges {
    /// Each differing object: its kind, name and how it differs.
    pub changes: Vec<(ObjectKind, String, Change)>,
}

impl ObjectChanges {
    /// Most objects a message names; the rest are counted.
    pub const NAMED: usize = 6;

    /// Whether no object differs (the scenes may still differ: objects reordered).
    pub fn is_empty(&self) -> bool {
        self.changes.is_empty()
    }
}

impl fmt::Display for ObjectChanges {
    /// `mesh 'floor' changed, material 'red' is new, … and 3 more`; for no difference, that
    /// the same objects are in another order.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.changes.is_empty() {
            return f.write_str("every mesh and material is unchanged, but their order differs");
        }
        for (i, (kind, name, change)) in self.changes.iter().take(Self::NAMED).enumerate() {
            let how = match change {
                Change::Changed => "changed",
                Change::New => "is new",
                Change::Gone => "is gone",
            };
            let sep = if i == 0 { "" } else { ", " };
            write!(f, "{sep}{} '{name}' {how}", kind.word())?;
        }
        if self.changes.len() > Self::NAMED {
            write!(f, " and {} more", self.changes.len() - Self::NAMED)?;
        }
        Ok(())
    }
}

/// An object's key: kind, name and which occurrence of that kind and name it is (the k-th
/// object of a kind and name in each list is the same object), with its hash.
type Keyed<'a> = ((ObjectKind, &'a str, usize), [u8; 16]);

/// The keys of `list`, counted through a map, so that a scene of many thousand meshes is
/// compared in linear time.
fn keyed(list: &[ObjectHash]) -> Vec<Keyed<'_>> {
    let mut seen: HashMap<(ObjectKind, &str), usize> = HashMap::new();
    list.iter()
        .map(|o| {
            let nth = seen.entry((o.kind, o.name.as_str())).or_default();
            *nth += 1;
            ((o.kind, o.name.as_str(), *nth - 1), o.hash)
        })
        .collect()
}

/// The objects of `current` that differ from those `recorded` (module docs: matched by kind,
/// name and occurrence).
pub fn object_changes(recorded: &[ObjectHash], current: &[ObjectHash]) -> ObjectChanges {
    let (recorded, current) = (keyed(recorded), keyed(current));
    let current_hashes: HashMap<_, _> = current.iter().copied().collect();
    let recorded_keys: HashSet<_> = recorded.iter().map(|r| r.0).collect();
    let mut changes = Vec::new();
    for &((kind, name, nth), hash) in &recorded {
        let change = match current_hashes.get(&(kind, name, nth)) {
            Some(&h) if h == hash => continue,
            Some(_) => Change::Changed,
            None => Change::Gone,
        };
        changes.push((kind, name.to_string(), change));
    }
    for &(k, _) in current.iter().filter(|c| !recorded_keys.contains(&c.0)) {
        changes.push((k.0, k.1.to_string(), Change::New));
    }
    ObjectChanges { changes }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn object(kind: ObjectKind, name: &str, hash: u8) -> ObjectHash {
        ObjectHash { kind, name: name.into(), hash: [hash; 16] }
    }

    #[test]
    fn changes_are_matched_by_kind_name_and_occurrence() {
        use ObjectKind::{Material, Mesh};
        let recorded = [
            object(Mesh, "floor", 1),
            object(Mesh, "group", 2),
            object(Mesh, "group", 3),
            object(Material, "floor", 4),
            object(Mesh, "lamp", 5),
        ];
        assert!(object_changes(&recorded, &recorded).is_empty());
        let current = [
            object(Mesh, "floor", 1),
            object(Mesh, "group", 2),
            object(Mesh, "group", 9),
            object(Material, "floor", 8),
            object(Mesh, "vase", 6),
        ];
        let c = object_changes(&recorded, &current);
        assert_eq!(
            c.changes,
            [
                (Mesh, "group".to_string(), Change::Changed),
                (Material, "floor".to_string(), Change::Changed),
                (Mesh, "lamp".to_string(), Change::Gone),
                (Mesh, "vase".to_string(), Change::New),
            ]
        );
        assert_eq!(
            c.to_string(),
            "mesh 'group' changed, material 'floor' changed, mesh 'lamp' is gone, mesh 'vase' is new"
        );
    }

    #[test]
    fn long_lists_are_cut_and_a_reordering_is_named() {
        let recorded: Vec<_> = (0..10).map(|i| object(ObjectKind::Mesh, &format!("m{i}"), 0)).collect();
        let current: Vec<_> = (0..10).map(|i| object(ObjectKind::Mesh, &format!("m{i}"), 1)).collect();
        let text = object_changes(&recorded, &current).to_string();
        assert!(text.ends_with("mesh 'm5' changed and 4 more"), "{text}");
        let mut reordered = recorded.clone();
        reordered.reverse();
        let c = object_changes(&recorded, &reordered);
        assert!(c.is_empty());
        assert!(c.to_string().contains("order"), "{c}");
    }
}
