//! The `mesh` primitive (`mod mesh id  1+ meshfile [transform]  0  0`): the triangles of a
//! Wavefront `.obj` file, read by the one OBJ reader ([`crate::scene_formats::obj`], as
//! Mitsuba's `obj` shape reads it), moved by the primitive's own transform (read by
//! [`xform::parse_transform`], the `!xform` options' one reading) and then by the including
//! files' `!xform`s, every triangle taking the primitive's material.
//!
//! Why `.obj` and not Radiance's own mesh file: `obj2mesh` compiles an `.obj` into an `.rtm`, an
//! octree in a binary layout of Radiance's that is not documented as a format and holds nothing
//! the `.obj` does not; reading the `.obj` keeps one mesh reader. Why the material is the
//! modifier's alone: Radiance takes the `.obj`'s `usemtl` names as modifiers only under a `void`
//! mesh, and those modifiers live in the mesh file, which Opticks does not read; so a `void`
//! mesh is refused rather than left out, which would silently drop what Radiance shows.

use super::{Builder, Frame, MAX_FILES};
use crate::scene_formats::obj::read_obj;
use crate::scene_formats::radiance::err;
use crate::scene_formats::radiance::lexer::Primitive;
use crate::scene_formats::radiance::xform;
use crate::scene_formats::{FileLocation, SceneFileError};
use std::path::Path;

impl Builder {
    /// `mesh`: the `.obj` file named relative to the file `path` that names it; an `.rtm` (or
    /// any other file) is refused, a missing or malformed `.obj` is an error naming this line
    /// (the OBJ reader's, with the OBJ file's line and this primitive).
    pub(super) fn mesh(
        &mut self,
        path: &Path,
        p: &Primitive,
        here: &FileLocation,
        frame: &Frame,
    ) -> Result<(), SceneFileError> {
        let element = p.describe();
        let bad = |m: String| err(here, &element, m);
        let Some(file) = p.strings.first().filter(|_| p.ints.is_empty() && p.reals.is_empty()) else {
            return Err(bad(format!(
                "mesh takes 1 or more string arguments (the mesh file, then its transform), 0 integer and 0 real arguments, not {}, {} and {}",
                p.strings.len(),
                p.ints.len(),
                p.reals.len()
            )));
        };
        let extension = Path::new(&file.text).extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
        match extension.as_deref() {
            Some("obj") => {}
            Some("rtm") => {
                return Err(bad(format!(
                    "{} is obj2mesh's compiled mesh, which Opticks does not read: name the .obj file it was made from instead",
                    file.text
                )));
            }
            _ => {
                return Err(bad(format!(
                    "{}: a mesh is read from a Wavefront .obj file (give the .obj that obj2mesh compiles)",
                    file.text
                )));
            }
        }
        let words: Vec<String> = p.strings[1..].iter().map(|w| w.text.clone()).collect();
        let own = xform::parse_transform(&words).map_err(|e| bad(format!("its transform: {e}")))?;
        // The mesh's own transform first, then the including files' (as xform appends its
        // transform to a mesh's arguments).
        let t = frame.transform.then_after(&own);
        let modifier = frame.modifier.as_deref().unwrap_or(&p.modifier.text);
        if modifier == "void" {
            return Err(bad(
                "a void mesh takes the .obj's own materials (usemtl) in Radiance, which Opticks does not read: give the mesh a material".into(),
            ));
        }
        let resolved = self.lookup(modifier, here, &element)?;
        if self.files_read >= MAX_FILES {
            return Err(bad(format!("more than {MAX_FILES} files read")));
        }
        self.files_read += 1;
        let obj_path = path.parent().unwrap_or(Path::new("")).join(&file.text);
        let obj = read_obj(&obj_path, Some((element.clone(), here.clone())))?;
        let positions = obj.positions.iter().map(|v| t.point(v.as_dvec3()).as_vec3()).collect();
        let mut normals: Vec<_> = obj.normals.iter().map(|n| t.vector(n.as_dvec3()).as_vec3()).collect();
        let mut triangles = obj.triangles;
        // A mirror keeps each triangle's front where Radiance's transformed normal points (the
        // winding reversed, as xform reverses a polygon); -I turns the mesh inside out.
        if t.mirrors() != frame.invert {
            triangles.iter_mut().for_each(|tri| tri.swap(1, 2));
        }
        if frame.invert {
            normals.iter_mut().for_each(|n| *n = -*n);
        }
        self.add_surface(
            path,
            p,
            here,
            frame,
            modifier,
            resolved,
            (positions, triangles, normals, Vec::new()),
        )
    }
}
