//! Validation and assembly: [`SceneDescription`] → [`Scene`], in stages.
//!
//! Everything a file can get wrong is caught here and reported with the element's source:
//! non-finite coordinates, indices out of range, missing materials, impossible emission, a
//! scene with no light. [`Scene::build`] runs the stages in order:
//!
//! 1. **validate** each mesh ([`meshes::validate`](super::meshes)),
//! 2. **flatten** it into the scene's triangles with its shading normals (`Flat::push_mesh`;
//!    degenerate, zero-area triangles are dropped, since they can neither be hit nor emit, and
//!    counted in [`Scene::dropped_triangles`]), and build its area light if it emits,
//! 3. **lights**: the point, directional and environment lights, then the light table as a whole
//!    (`super::lights`),
//! 4. **textures**: each binding checked against its material (`super::textures`),
//! 5. **fingerprints** of the geometry and the lights (`super::hashes`),
//! 6. **BVH** over the triangles ([`Accel`]).
//!
//! A mesh is validated, flattened and made a light before the next mesh is looked at, so the
//! first error in file order is the one reported.

use super::attributes::AttributeTable;
use super::meshes::{self, Flat, NO_LIGHT, NO_SHADING, NO_UV};
use super::textures::{self, MaterialTextures, ShadingMap};
use super::{CameraDesc, Fingerprint, ObjectHash, Photometry, SceneDescription, SceneError, hashes, lights};
use crate::accel::Accel;
use crate::bsdf::{Bsdf, Material};
use crate::geometry::{Hit, Ray, SurfaceNormals, Triangle};
use crate::light::Light;
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::{mix, unit_from_hash};
use crate::texture::Texture;

/// A validated, ray-traceable scene.
#[derive(Debug)]
pub struct Scene {
    /// Triangles (scene order; sample records refer to these indices).
    pub triangles: Vec<Triangle>,
    normals: Vec<Vec3>,
    /// Per triangle: index into `shading_normals`, or [`NO_SHADING`].
    shading_of: Vec<u32>,
    /// Unit vertex normals of the triangles that have them.
    shading_normals: Vec<[Vec3; 3]>,
    material_of: Vec<u32>,
    light_of: Vec<u32>,
    /// Per triangle: index into `uvs`, or [`NO_UV`].
    uv_of: Vec<u32>,
    /// Vertex texture coordinates of the triangles that have them.
    uvs: Vec<[Vec2; 3]>,
    /// Per material: the textures in place of its parameters (empty: untextured).
    textures: MaterialTextures,
    /// Per material, its opacity texture's index in `textures` (a masked surface: Mitsuba's
    /// `mask`), if any.
    opacity_of: Vec<Option<u8>>,
    /// Whether any material is masked: only then do ray queries ask [`Scene::meets`].
    masked: bool,
    /// Per material, its normal or bump map (Mitsuba's `normalmap`, `bumpmap`), if any.
    shading_map_of: Vec<Option<ShadingMap>>,
    /// Per material, whether it is plain: no texture sets a parameter of its BSDF, no map
    /// shapes its normals and its frame need not follow ∂p/∂u. [`Scene::surface_at`] answers
    /// such a material's flat triangles without a call (the light tracer asks at every vertex).
    plain: Vec<bool>,
    /// Per material, whether its BSDF depends on the azimuth (`Bsdf::is_anisotropic`, or a
    /// texture on `alpha_u`, `alpha_v` or `anisotropic`): its shading frame then follows ∂p/∂u
    /// on triangles with texture coordinates ([`Scene::normals_at`]).
    anisotropic: Vec<bool>,
    /// Whether any triangle's material is a thin pane: only then does
    /// [`Scene::shadow_transmittance`] look past the first hit (`super::panes`).
    pub(super) panes: bool,
    /// The meshes' attributes that `mesh_attribute` textures read, one table per name.
    attributes: Vec<AttributeTable>,
    /// Materials.
    pub materials: Vec<Material>,
    /// Lights, in scene order.
    pub lights: Vec<Light>,
    /// Per light: hash of where and how it emits (geometry and emission distribution), not of
    /// its power. Samples stay valid for a light as long as this is unchanged; power and colour
    /// may change freely (relighting).
    pub light_shapes: Vec<[u8; 16]>,
    /// The scene file's camera, if any.
    pub camera: Option<CameraDesc>,
    /// How its RGB values become lux ([`SceneDescription::photometry`]; no fingerprint covers it).
    pub photometry: Photometry,
    /// Content hashes.
    pub fingerprint: Fingerprint,
    /// The geometry hash as format-version-1 datasets recorded it (which also covered which
    /// triangles emit): such a dataset matches this scene if its hash equals this one.
    pub geometry_v1: [u8; 16],
    /// One hash per mesh, then per material a mesh uses ([`ObjectHash`]): what lets a
    /// refused dataset name the objects that changed. The fingerprint alone decides.
    pub objects: Vec<ObjectHash>,
    /// Zero-area triangles that were dropped.
    pub dropped_triangles: usize,
    /// Finite triangles that were dropped because their area overflows `f32` (too large for
    /// single precision, not degenerate).
    pub oversized_triangles: usize,
    pub(super) accel: Accel,
}

impl Scene {
    /// Validates `desc` and builds the BVH, light table and fingerprint (the stages of the
    /// module docs).
    pub fn build(desc: &SceneDescription) -> Result<Scene, SceneError> {
        let mut flat = Flat::default();
        let mut lights = Vec::new();
        let mut ranges = Vec::with_capacity(desc.meshes.len());
        for mesh in &desc.meshes {
            let normals = meshes::validate(mesh, desc.materials.len())?;
            let light = if mesh.emission.is_some() { lights.len() as u32 } else { NO_LIGHT };
            let first = flat.vertices.len();
            let emitter = flat.push_mesh(mesh, &normals, light);
            ranges.push((mesh.name.as_str(), first..flat.vertices.len()));
            if let Some(emission) = &mesh.emission {
                lights.push(lights::area_light(mesh, emission, emitter, &flat)?);
            }
        }
        for p in &desc.point_lights {
            lights.push(lights::point_light(p)?);
        }
        if !desc.directional_lights.is_empty() && !flat.vertices.is_empty() {
            lights.extend(lights::directional_lights(&desc.directional_lights, &flat.vertices)?);
        }
        if !desc.environment_lights.is_empty() && !flat.vertices.is_empty() {
            lights.extend(lights::environment_lights(&desc.environment_lights, &flat.vertices)?);
        }
        if flat.triangles.is_empty() {
            return Err(SceneError::NoGeometry);
        }
        lights::check_light_table(&lights)?;
        let textures = textures::bind(desc, &flat.attributes)?;
        let anisotropic = textures::anisotropic(&desc.materials, &textures);
        let hashes = hashes::fingerprints(&desc.materials, &textures, &anisotropic, &flat, &lights, &ranges);
        let accel = Accel::build(&flat.vertices);
        let opacity_of = textures::opacities(&textures);
        let shading_map_of = textures::shading_maps(&textures);
        let plain = (shading_map_of.iter().zip(&textures).zip(&anisotropic))
            .map(|((map, t), &a)| map.is_none() && !a && t.iter().all(|b| !b.slot.is_bsdf_parameter()))
            .collect();
        Ok(Scene {
            masked: opacity_of.iter().any(Option::is_some),
            panes: flat.material_of.iter().any(|&m| desc.materials[m as usize].bsdf.is_pane()),
            opacity_of,
            shading_map_of,
            plain,
            anisotropic,
            normals: flat.triangles.iter().map(Triangle::normal).collect(),
            triangles: flat.triangles,
            shading_of: flat.shading_of,
            shading_normals: flat.shading_normals,
            material_of: flat.material_of,
            light_of: flat.light_of,
            uv_of: flat.uv_of,
            uvs: flat.uvs,
            textures,
            attributes: flat.attributes,
            materials: desc.materials.clone(),
            lights,
            light_shapes: hashes.light_shapes,
            camera: desc.camera,
            photometry: desc.photometry,
            fingerprint: hashes.fingerprint,
            geometry_v1: hashes.geometry_v1,
            objects: hashes.objects,
            dropped_triangles: flat.dropped,
            oversized_triangles: flat.oversized,
            accel,
        })
    }

    /// Closest surface hit along `ray` (a masked surface only where `Scene::meets` says
    /// the ray meets it).
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let (t, prim) = match self.masked {
            false => self.accel.intersect(ray)?,
            true => self.intersect_masked(ray)?,
        };
        let position = self.triangles[prim as usize].snap(ray.origin + t * ray.dir);
        Some(Hit { t, prim, position, normal: self.normals[prim as usize] })
    }

    /// The hit of `ray` on triangle `prim`, which the caller knows to be its closest (a
    /// [`crate::sensor::VisibilityBuffer`]'s front triangle): the same hit as
    /// [`Scene::intersect`]'s, for one triangle test instead of a traversal (the traversal if
    /// the ray misses `prim` after all).
    #[inline]
    pub fn intersect_front(&self, ray: &Ray, prim: u32) -> Option<Hit> {
        let Some(t) = self.accel.intersect_one(ray, prim) else { return self.intersect(ray) };
        let position = self.triangles[prim as usize].snap(ray.origin + t * ray.dir);
        Some(Hit { t, prim, position, normal: self.normals[prim as usize] })
    }

    /// Whether the segment from `ray.origin` of length `ray.t_max` is blocked (by a masked
    /// surface only where `Scene::meets` says the ray meets it).
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        match self.masked {
            false => self.accel.occluded(ray),
            true => self.occluded_masked(ray),
        }
    }

    /// The masked scene's closest hit (out of line: unmasked scenes' queries stay small).
    #[inline(never)]
    fn intersect_masked(&self, ray: &Ray) -> Option<(f32, u32)> {
        self.accel.intersect_where(ray, |prim, t| self.meets(ray, prim, t))
    }

    /// The masked scene's occlusion (out of line, as [`Scene::intersect_masked`]).
    #[inline(never)]
    fn occluded_masked(&self, ray: &Ray) -> bool {
        self.accel.occluded_where(ray, |prim, t| self.meets(ray, prim, t))
    }

    /// Whether `ray` meets triangle `prim`, which it crosses at distance `t`: always, unless
    /// the triangle's material is masked (Mitsuba's `mask`, opacity α at the crossing): then
    /// with probability α, decided by a hash of the ray and the triangle — stochastic
    /// transparency. Every estimator then sees the surface with probability α and what lies
    /// behind it with 1 − α, the expectation of Mitsuba's α·f + (1 − α)·(straight through); and
    /// since shadow rays and connections pass too, the light estimator sees through the mask
    /// (Mitsuba's null lobe is a delta its light tracer cannot connect through). The hash makes
    /// the answer a function of the query alone, as the traversal needs (it may ask twice).
    #[inline]
    pub(super) fn meets(&self, ray: &Ray, prim: u32, t: f32) -> bool {
        let m = self.material_of[prim as usize] as usize;
        let Some(k) = self.opacity_of[m] else { return true };
        let b = self.triangles[prim as usize].barycentrics(ray.origin + t * ray.dir);
        let uv = self.uv_of_barycentrics(prim, b);
        let alpha = textures::opacity_at(&self.textures[m][k as usize], &self.attributes, prim, b, uv);
        if alpha >= 1.0 {
            return true;
        }
        let (o, d) = (ray.origin.to_array().map(f32::to_bits), ray.dir.to_array().map(f32::to_bits));
        let a = o[0] as u64 | (o[1] as u64) << 32;
        let c = o[2] as u64 | (d[0] as u64) << 32;
        let e = d[1] as u64 | (d[2] as u64) << 32;
        let h = mix(mix(mix(a ^ 0x6d61_736b) ^ c) ^ e ^ prim as u64);
        unit_from_hash(h) < alpha
    }

    /// Whether triangle `prim`'s material is masked (rays may pass it: [`Scene::occluded`]).
    #[inline]
    pub fn is_masked(&self, prim: u32) -> bool {
        self.masked && self.opacity_of[self.material_of[prim as usize] as usize].is_some()
    }

    /// f_r = ρ/π and two-sidedness of triangle `prim` when its BSDF is an untextured Lambert
    /// reflector on a triangle without shading normals: what [`crate::bsdf::ShadingPoint::eval`]
    /// reduces to there (ρ/π on the lit side, 0 elsewhere), so a connection needs neither the
    /// material resolved at the point, nor its normals, nor a shading frame (the diffuse walls
    /// that hold most of an interior's stored samples). `None` for every other surface.
    #[inline]
    pub(crate) fn flat_lambert(&self, prim: u32) -> Option<(Rgb, bool)> {
        if self.shading_of[prim as usize] != NO_SHADING {
            return None;
        }
        let m = self.material_of[prim as usize] as usize;
        let material = &self.materials[m];
        let Bsdf::Lambert(l) = &material.bsdf else { return None };
        // The plain material with the geometric normal: what `material_at` and `normals_at`
        // give where no texture sets a parameter of the BSDF and none shapes the surface.
        if !self.plain[m] {
            return None;
        }
        Some((l.eval_lit(), material.two_sided))
    }

    /// Unit geometric normal of triangle `prim`.
    #[inline]
    pub fn normal(&self, prim: u32) -> Vec3 {
        self.normals[prim as usize]
    }

    /// [`Scene::material_at`] and [`Scene::normals_at`] of the point `p` on triangle `prim` in
    /// one query: inline for a flat triangle of a plain material (its material as is, its
    /// geometric normal: what both give there), by those two calls otherwise.
    #[inline]
    pub fn surface_at<'s>(
        &'s self,
        prim: u32,
        p: Vec3,
        resolved: &'s mut Option<Material>,
    ) -> (&'s Material, SurfaceNormals) {
        let i = prim as usize;
        let m = self.material_of[i] as usize;
        if self.plain[m] && self.shading_of[i] == NO_SHADING {
            return (&self.materials[m], SurfaceNormals::flat(self.normals[i]));
        }
        let n = self.normals_at(prim, p);
        (self.material_at(prim, p, resolved), n)
    }

    /// The normals of triangle `prim` at the point `p` on it: the geometric normal and the
    /// vertex normals interpolated at p's barycentrics (recomputed from p, so a stored sample
    /// needs no more than its position and triangle), perturbed by the material's normal or bump
    /// map if it has one (`Scene::normal_mapped`, `Scene::bump_mapped`). Every estimator shades
    /// with these, so a mapped normal is a shading normal like any other: the adjoint rule and
    /// the leak guard of [`crate::bsdf::shading`] apply to it.
    #[inline]
    pub fn normals_at(&self, prim: u32, p: Vec3) -> SurfaceNormals {
        let n = self.interpolated_normals(prim, p);
        let m = self.material_of[prim as usize] as usize;
        let n = match self.shading_map_of[m] {
            None => n,
            Some(ShadingMap::Normal(k)) => self.normal_mapped(prim, p, n, k),
            Some(ShadingMap::Bump(k, scale)) => self.bump_mapped(prim, p, n, k, scale),
        };
        if self.anisotropic[m] && self.uv_of[prim as usize] != NO_UV {
            return SurfaceNormals { tangent: self.uv_tangent(prim, n.shading), ..n };
        }
        n
    }

    /// Mitsuba's shading tangent (`initialize_sh_frame`): ∂p/∂u of triangle `prim` made
    /// orthogonal to the shading normal `ns` and unit; `None` (the frame of `ns` alone) where the
    /// triangle's texture coordinates are degenerate or ∂p/∂u is along `ns`, where Mitsuba
    /// falls back to `coordinate_system` too.
    #[inline]
    fn uv_tangent(&self, prim: u32, ns: Vec3) -> Option<Vec3> {
        let (dpdu, _) = self.dp_duv(prim);
        (dpdu - ns * ns.dot(dpdu)).try_normalize()
    }

    /// The geometric normal and the interpolated vertex normals at `p` on triangle `prim`.
    #[inline]
    fn interpolated_normals(&self, prim: u32, p: Vec3) -> SurfaceNormals {
        let ng = self.normals[prim as usize];
        let k = self.shading_of[prim as usize];
        if k == NO_SHADING {
            return SurfaceNormals::flat(ng);
        }
        let [n0, n1, n2] = self.shading_normals[k as usize];
        let (b1, b2) = self.triangles[prim as usize].barycentrics(p);
        let ns = ((1.0 - b1 - b2) * n0 + b1 * n1 + b2 * n2).normalize_or_zero();
        // Interpolated normals can cancel (opposite vertex normals) or, at a crease, lean
        // through the surface: keep the shading normal on the geometric side.
        if ns.dot(ng) > 0.0 {
            SurfaceNormals { geometric: ng, shading: ns, tangent: None }
        } else {
            SurfaceNormals::flat(ng)
        }
    }

    /// Mitsuba 3's `normalmap`: the normal map's colour c at p (texture `k` of the triangle's
    /// material) is the normal 2c − 1 in the shading frame (s, t, n) of `n`, where s is dp/du
    /// made orthogonal to the shading normal n ([`Scene::dp_du`]; Mitsuba's
    /// `initialize_sh_frame`) and t = n × s. A map value of (0, 0, 1) leaves `n` as it is
    /// (bit for bit), as does a value that would leave the geometric side of the surface or
    /// has no direction (the shading normal stays on the geometric side, as interpolated ones
    /// do).
    #[inline(never)]
    fn normal_mapped(&self, prim: u32, p: Vec3, n: SurfaceNormals, k: u8) -> SurfaceNormals {
        let m = self.material_of[prim as usize] as usize;
        let uv = self.uv_at(prim, p);
        let local = self.textures[m][k as usize].texture.eval(uv, Rgb::ZERO) * 2.0 - 1.0;
        if local.x == 0.0 && local.y == 0.0 && local.z > 0.0 {
            return n;
        }
        let ns = n.shading;
        let (dpdu, _) = self.dp_duv(prim);
        let s = (dpdu - ns * ns.dot(dpdu)).normalize_or_zero();
        let s = if s == Vec3::ZERO { crate::math::Frame::from_normal(ns).s } else { s };
        let t = ns.cross(s);
        let mapped = (s * local.x + t * local.y + ns * local.z).normalize_or_zero();
        if mapped.dot(n.geometric) > 0.0 { SurfaceNormals { shading: mapped, ..n } } else { n }
    }

    /// Mitsuba 3's `bumpmap`: the height's UV gradient g (texture `k`'s [`crate::texture::Bitmap::gradient_1`]
    /// at p, times `scale`) lifts the surface's tangents out of the shading plane of n:
    /// dp/du' = dp/du − n (n·dp/du) + n g_u, likewise for v, and the new normal is
    /// normalize(dp/du' × dp/dv'), turned to the geometric normal's side (Mitsuba's flip;
    /// [`Scene::dp_duv`] for the tangents). A zero gradient (a flat height, a scale of 0) leaves
    /// `n` as it is, bit for bit, as does a result with no direction or in the surface's plane.
    #[inline(never)]
    fn bump_mapped(&self, prim: u32, p: Vec3, n: SurfaceNormals, k: u8, scale: f32) -> SurfaceNormals {
        let m = self.material_of[prim as usize] as usize;
        let Texture::Bitmap(height) = &*self.textures[m][k as usize].texture else { return n };
        let g = height.gradient_1(self.uv_at(prim, p)) * scale;
        if g == Vec2::ZERO || !g.is_finite() {
            return n;
        }
        let ns = n.shading;
        let (dpdu, dpdv) = self.dp_duv(prim);
        let du = dpdu + ns * (g.x - ns.dot(dpdu));
        let dv = dpdv + ns * (g.y - ns.dot(dpdv));
        let bumped = du.cross(dv).normalize_or_zero();
        let d = bumped.dot(n.geometric);
        if d == 0.0 || !d.is_finite() {
            return n;
        }
        SurfaceNormals { shading: if d > 0.0 { bumped } else { -bumped }, ..n }
    }

    /// (∂p/∂u, ∂p/∂v) of triangle `prim` (Mitsuba's mesh): from its vertex UVs, or, without UVs,
    /// the edges v1 − v0 and v2 − v0 (the barycentric parameterisation); zero where the UVs
    /// are degenerate.
    #[inline]
    fn dp_duv(&self, prim: u32) -> (Vec3, Vec3) {
        let tri = &self.triangles[prim as usize];
        let k = self.uv_of[prim as usize];
        if k == NO_UV {
            return (tri.e1, tri.e2);
        }
        let [a, b, c] = self.uvs[k as usize];
        let (d0, d1) = (b - a, c - a);
        let det = d0.x * d1.y - d0.y * d1.x;
        if det == 0.0 {
            return (Vec3::ZERO, Vec3::ZERO);
        }
        ((tri.e1 * d1.y - tri.e2 * d0.y) / det, (tri.e2 * d0.x - tri.e1 * d1.x) / det)
    }

    /// Whether any triangle has shading normals.
    pub fn has_shading_normals(&self) -> bool {
        !self.shading_normals.is_empty()
    }

    /// Material of triangle `prim`, with its colours as the scene file gives them: what decides
    /// the kind of scattering (delta, transmitting, absorbing). Everything that evaluates or
    /// samples the BSDF at a point uses [`Scene::material_at`].
    #[inline]
    pub fn material(&self, prim: u32) -> &Material {
        &self.materials[self.material_of[prim as usize] as usize]
    }

    /// The material of triangle `prim` at the point `p` on it: its textured parameters evaluated
    /// at p's texture coordinates ([`Scene::uv_at`]) and, for mesh attributes, the triangle's
    /// values at p's barycentrics. An untextured material (or one whose only textures are a normal or bump map or an
    /// opacity, not the BSDF's) is the scene's own (no lookup, no copy); a textured one is a copy without a name, kept in `resolved` (the
    /// caller's slot, `&mut None`: a plain reference out, so the hot loops pay nothing for
    /// textures they do not have).
    #[inline]
    pub fn material_at<'s>(&'s self, prim: u32, p: Vec3, resolved: &'s mut Option<Material>) -> &'s Material {
        let m = self.material_of[prim as usize] as usize;
        let textures = &self.textures[m];
        // A normal or bump map and an opacity are not parameters of the BSDF.
        if textures.iter().all(|b| !b.slot.is_bsdf_parameter()) {
            return &self.materials[m];
        }
        let b = self.triangles[prim as usize].barycentrics(p);
        let uv = self.uv_of_barycentrics(prim, b);
        resolved.insert(textures::resolve(&self.materials[m], textures, &self.attributes, prim, b, uv))
    }

    /// The texture coordinates of triangle `prim` at the point `p` on it: its vertex UVs at p's
    /// barycentrics (recomputed from p, as [`Scene::normals_at`] does), or those barycentrics
    /// (b1, b2) for a mesh without UVs (Mitsuba's parameterisation).
    #[inline]
    pub fn uv_at(&self, prim: u32, p: Vec3) -> Vec2 {
        self.uv_of_barycentrics(prim, self.triangles[prim as usize].barycentrics(p))
    }

    /// The texture coordinates of triangle `prim` at barycentrics (b1, b2).
    #[inline]
    fn uv_of_barycentrics(&self, prim: u32, (b1, b2): (f32, f32)) -> Vec2 {
        let k = self.uv_of[prim as usize];
        if k == NO_UV {
            return Vec2::new(b1, b2);
        }
        let [a, b, c] = self.uvs[k as usize];
        a + b1 * (b - a) + b2 * (c - a)
    }

    /// Whether any material is textured.
    pub fn has_textures(&self) -> bool {
        self.textures.iter().any(|t| !t.is_empty())
    }

    /// The light whose emitter triangle `prim` is, if any.
    #[inline]
    pub fn light_of(&self, prim: u32) -> Option<usize> {
        let l = self.light_of[prim as usize];
        (l != NO_LIGHT).then_some(l as usize)
    }

    /// Index of the light named `name`.
    pub fn light_index(&self, name: &str) -> Option<usize> {
        self.lights.iter().position(|l| l.name() == name)
    }

    /// Powers Φ_k of all lights, in scene order.
    pub fn light_powers(&self) -> Vec<Rgb> {
        self.lights.iter().map(Light::power).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::offset_ray_origin;
    use crate::sampling::RandomStream;
    use crate::sampling::warp::square_to_cosine_hemisphere;
    use crate::scene::cornell_box;

    /// The Cornell box in millimetres, placed as Mitsuba's `cbox.xml` is: floor at y = 0, one
    /// wall at x = 0, the camera 800 mm in front. Rays from the camera hit the floor and the wall;
    /// a ray leaving the hit point into the box must not hit the same surface again. With the hit
    /// point taken as `origin + t·dir` (off the plane by ~1e-4 mm) 5–20% of them did (Mitsuba's
    /// own Cornell box rendered 18% dark on its green wall and floor).
    #[test]
    fn rays_leaving_walls_at_the_coordinate_origin_do_not_hit_them_again() {
        let mut desc = cornell_box();
        for m in &mut desc.meshes {
            for p in &mut m.positions {
                *p = (*p + Vec3::ONE) * 278.0; // [-1, 1]³ → [0, 556]³
            }
        }
        let scene = Scene::build(&desc).unwrap();
        let eye = Vec3::new(278.0, 273.0, 1356.0);
        let mut rng = RandomStream::new(3, &[]);
        let (mut hits, mut again) = (0, 0);
        for _ in 0..20_000 {
            let target = Vec3::new(rng.next_f32() * 556.0, rng.next_f32() * 556.0, rng.next_f32() * 556.0);
            let Some(hit) =
                scene.intersect(&Ray { origin: eye, dir: (target - eye).normalize(), t_max: f32::INFINITY })
            else {
                continue;
            };
            let on_zero_plane = hit.position.x.abs() < 1.0 || hit.position.y.abs() < 1.0;
            if !on_zero_plane {
                continue;
            }
            let n = if hit.normal.dot(eye - hit.position) > 0.0 { hit.normal } else { -hit.normal };
            let local = square_to_cosine_hemisphere(rng.next_2d());
            let (t, b) = n.any_orthonormal_pair();
            let dir = (t * local.x + b * local.y + n * local.z).normalize();
            let ray =
                Ray { origin: offset_ray_origin(hit.position, hit.normal, dir), dir, t_max: f32::INFINITY };
            hits += 1;
            if scene.intersect(&ray).is_some_and(|h| h.prim == hit.prim) {
                again += 1;
            }
        }
        assert!(hits > 2000, "{hits} hits on the floor or the x = 0 wall");
        assert_eq!(again, 0, "{again} of {hits} rays leaving a wall at 0 hit it again");
    }

    /// Issue 26: a finite triangle whose area overflows `f32` was counted as "degenerate
    /// (zero-area)"; it is counted as too large, and a zero-area one is still degenerate.
    #[test]
    fn triangles_too_large_for_f32_are_not_called_degenerate() {
        let mut desc = cornell_box();
        let m = desc.meshes.iter_mut().find(|m| m.emission.is_none() && m.normals.is_empty()).unwrap();
        m.uvs.clear();
        m.attributes.clear();
        let n = m.positions.len() as u32;
        m.positions.extend([
            Vec3::ZERO,
            Vec3::new(1e20, 0.0, 0.0),
            Vec3::new(0.0, 1e20, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(3e38, 0.0, 0.0),
            Vec3::new(-3e38, 1.0, 0.0),
        ]);
        // Area 5·10³⁹; a zero-area one; edges that overflow f32 themselves.
        m.triangles.extend([[n, n + 1, n + 2], [n, n + 3, n + 3], [n + 4, n + 5, n]]);
        let scene = Scene::build(&desc).unwrap();
        assert_eq!((scene.dropped_triangles, scene.oversized_triangles), (1, 2));
        assert_eq!(Scene::build(&cornell_box()).unwrap().oversized_triangles, 0);
    }
}

#[cfg(test)]
#[path = "anisotropy_tests.rs"]
mod anisotropy_tests;
