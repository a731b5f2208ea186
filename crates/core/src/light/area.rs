//! Area lights: one-sided emitters made of scene triangles, with the photometric frame their
//! profile is evaluated in.
//!
//! ## An area light's photometric frame
//! An area light evaluates and samples its profile in a frame per triangle: the vertical 0°
//! axis (local z) is the triangle's geometric normal, and the horizontal 0° reference (local x,
//! φ = 0; local y = z × x is φ = 90°) is the light's [`AreaLight::tangent`] projected onto the
//! triangle's plane. The tangent is world +x unless the scene sets one
//! ([`crate::scene::AreaEmission::tangent`]); where it is (within 0.6° of) parallel to a
//! triangle's normal, world +x and then world +z are projected instead
//! ([`AreaLight::frame`]). Only profiles that depend on φ (IES tables) need this frame; the
//! rotationally symmetric ones use the equivalent, cheaper `Frame::from_normal`. The tracer
//! (emission sampling) and the sensor (emitters seen directly, through
//! [`super::Light::emitted_fraction`]) both go through [`AreaLight::frame`], so they agree.
//!
//! ## A textured radiance
//! A light's radiance may be a texture over its triangles' texture coordinates ([`EmitterTexture`],
//! Mitsuba's `<texture name="radiance">` in an area emitter): L(y, ω) = L̄·(T(uv(y))/T̄)·f_e/cos θ
//! per channel, where T̄ is the texture's mean over the light's area and L̄ = c·T̄ the mean
//! radiance ([`AreaLight::radiance`]; c the colour the texture is multiplied by, or what a given
//! power makes it). T̄ is computed **exactly** when the light is built, triangle by triangle
//! ([`crate::texture::integral`]: the texture is piecewise polynomial on its cells; a mesh
//! attribute is linear over each triangle, its mean its corners'), so Φ =
//! L̄·A·∫s dω is the true power — what the light table stores, relighting replaces and the
//! plan's quotas follow. Start points stay uniform in area (density 1/A, the same position
//! density for the bidirectional estimator's MIS weights), and each path's weight carries the
//! relative radiance T(uv)/T̄ at its start: E[T/T̄] = 1 exactly, so the estimator is unbiased
//! and the emission vertex's stored sample (its weight field, 1 for an untextured light) says
//! how bright its point is — the stored sample does not grow. This keeps every untextured
//! light's paths bit for bit, at the price of wasting paths started where the texture is dark
//! (their weight is 0: they are dropped after their first sample). Camera paths that hit the
//! light and NEE evaluate the same T(uv)/T̄ at their point ([`AreaLight::scale_at`]).

use super::check::{check_power, unit_tangent};
use super::{BuiltProfile, Emission, EmissionProfile, LightError};
use crate::geometry::Triangle;
use crate::math::{Frame, Rgb, Vec2, Vec3};
use crate::sampling::warp;
use crate::texture::Texture;
use crate::texture::integral::{MAX_CELLS, MeanError, triangle_mean};
use std::sync::Arc;

/// The texture an area light's radiance follows (module docs), with what sampling and lookups
/// need: the texture coordinates of each of the light's triangles and the texture's mean.
#[derive(Clone, Debug, PartialEq)]
pub struct EmitterTexture {
    /// The texture (a bitmap, checkerboard, constant or the mesh's attribute).
    pub texture: Arc<Texture>,
    /// Per triangle of the light (in the order of [`AreaLight::triangles`]), the texture
    /// coordinates of its corners v0, v1, v2 (zero for a mesh attribute on a mesh without them).
    pub uvs: Vec<[Vec2; 3]>,
    /// For a `mesh_attribute` texture, per triangle of the light, the attribute at its corners
    /// (a face attribute's value three times); empty otherwise.
    pub corners: Vec<[Rgb; 3]>,
    /// T̄: the texture's exact mean over the light's area, per channel.
    pub mean: Rgb,
    /// 1/T̄ per channel, 0 where T̄ is 0 (that channel emits nothing anywhere).
    inv_mean: Rgb,
}

impl EmitterTexture {
    /// T(uv)/T̄ on the light's triangle `i` at barycentrics (b1, b2).
    #[inline]
    fn relative(&self, i: usize, (b1, b2): (f32, f32)) -> Rgb {
        let [a, b, c] = self.uvs[i];
        let attribute = match self.corners.get(i) {
            Some([x, y, z]) => (1.0 - b1 - b2) * *x + b1 * *y + b2 * *z,
            None => Rgb::ZERO,
        };
        self.texture.eval(a + b1 * (b - a) + b2 * (c - a), attribute) * self.inv_mean
    }
}

/// A one-sided emitter made of scene triangles.
#[derive(Clone, Debug, PartialEq)]
pub struct AreaLight {
    /// Name from the scene.
    pub name: String,
    /// Emitted radiance along the normal, W/(m²·sr) (for the default cosine profile, the
    /// radiance in every direction of the front hemisphere). Φ = radiance·A·∫s dω (module docs
    /// of [`super::profile`]).
    pub radiance: Rgb,
    /// The emission density over the front hemisphere, in each triangle's frame
    /// [`AreaLight::frame`].
    pub profile: BuiltProfile,
    /// Unit world direction whose projection onto each triangle's plane is the profile's
    /// horizontal 0° (module docs); world +x by default.
    pub tangent: Vec3,
    /// Scene triangle indices of the emitter.
    pub triangles: Vec<u32>,
    /// Cumulative areas (for picking a triangle ∝ area); last entry = total area.
    pub cumulative_area: Vec<f32>,
    /// The texture the radiance follows, if any (module docs); `radiance` is then its mean.
    pub texture: Option<EmitterTexture>,
}

impl AreaLight {
    /// The area light `name` over the scene triangles `triangles` (with their cumulative areas),
    /// emitting `radiance` along the normal with `profile` (`None`: Lambertian) oriented by
    /// `tangent` (`None`: world +x); a `power` Φ, if given, overrides the radiance (which
    /// becomes Φ/(A·∫s dω)). Checks the profile (one-sided: cut at 90°), the tangent and the
    /// power; the radiance is the caller's to check ([`super::check::check_emission`]). A
    /// `texture` (with the texture coordinates of each triangle) multiplies `radiance` point by
    /// point; the light's radiance becomes the mean, computed exactly (module docs).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        name: String,
        radiance: Rgb,
        profile: Option<&EmissionProfile>,
        tangent: Option<Vec3>,
        power: Option<Rgb>,
        triangles: Vec<u32>,
        cumulative_area: Vec<f32>,
        texture: Option<EmitterTextureDesc>,
    ) -> Result<AreaLight, LightError> {
        let profile = BuiltProfile::build(profile.unwrap_or(&EmissionProfile::Cosine), true)?;
        let tangent = tangent.map_or(Ok(Vec3::X), unit_tangent)?;
        let area = cumulative_area.last().copied().unwrap_or(0.0);
        let texture = match texture {
            None => None,
            Some(desc) => Some(emitter_texture(desc, &cumulative_area)?),
        };
        let radiance = match &texture {
            Some(t) => radiance * t.mean,
            None => radiance,
        };
        if let (Some(t), Some(phi)) = (&texture, power) {
            // A channel the texture leaves black everywhere cannot carry a given power.
            let unreachable = (0..3).any(|c| phi[c] > 0.0 && !(t.mean[c] > 0.0));
            if unreachable {
                return Err(LightError::PowerUnreachable(phi.to_array()));
            }
        }
        let radiance = match power {
            None => radiance,
            Some(phi) => {
                check_power(phi)?;
                if !(area > 0.0) && phi.max_element() > 0.0 {
                    return Err(LightError::PowerWithoutArea(phi.to_array()));
                }
                let per_radiance = profile.integral() * area;
                if !(per_radiance > 0.0) && phi.max_element() > 0.0 {
                    return Err(LightError::PowerUnreachable(phi.to_array()));
                }
                if per_radiance > 0.0 { phi / per_radiance } else { Rgb::ZERO }
            }
        };
        Ok(AreaLight { name, radiance, profile, tangent, triangles, cumulative_area, texture })
    }

    /// T(uv)/T̄ at the point `p` of the light's triangle `prim` (scene index): the radiance
    /// there relative to [`AreaLight::radiance`] (module docs); 1 for an untextured light.
    #[inline]
    pub fn scale_at(&self, triangles: &[Triangle], prim: u32, p: Vec3) -> Rgb {
        let Some(t) = &self.texture else { return Rgb::ONE };
        // The light's triangles are in scene order (its mesh's, flattened).
        match self.triangles.binary_search(&prim) {
            Ok(i) => t.relative(i, triangles[prim as usize].barycentrics(p)),
            Err(_) => Rgb::ZERO,
        }
    }

    /// Total emitting area A, m².
    pub fn area(&self) -> f32 {
        self.cumulative_area.last().copied().unwrap_or(0.0)
    }

    /// Power Φ per channel: L·A·∫s dω (π·L·A for a Lambertian emitter).
    #[inline]
    pub fn power(&self) -> Rgb {
        self.profile.integral() * self.radiance * self.area()
    }

    /// The profile's frame on a triangle of unit geometric normal `normal`: z = `normal`,
    /// x = the first of [`AreaLight::tangent`], world +x, world +z whose projection onto the
    /// triangle's plane is not (nearly) zero, normalised (module docs). For profiles that do not
    /// depend on the azimuth, `Frame::from_normal(normal)`.
    #[inline]
    pub fn frame(&self, normal: Vec3) -> Frame {
        if !self.profile.depends_on_azimuth() {
            return Frame::from_normal(normal);
        }
        tangent_frame(normal, self.tangent)
    }

    /// L_e(y0, ω)·A/Φ in the world direction `dir` from a point of normal `normal`:
    /// f_e(ω)/cos θ (1/π for a Lambertian emitter); 0 behind the surface.
    #[inline]
    pub fn emitted_fraction(&self, normal: Vec3, dir: Vec3) -> f32 {
        match self.profile {
            BuiltProfile::Cosine => std::f32::consts::FRAC_1_PI,
            ref p => p.emitted_fraction(self.frame(normal).to_local(dir)),
        }
    }

    /// The solid-angle density with which [`AreaLight::sample_emission`] draws the world
    /// direction `dir` from a point of normal `normal`: the profile's sampling pdf.
    #[inline]
    pub fn direction_pdf(&self, normal: Vec3, dir: Vec3) -> f32 {
        match self.profile {
            BuiltProfile::Cosine => dir.dot(normal).max(0.0) * std::f32::consts::FRAC_1_PI,
            ref p => p.sampling_pdf(self.frame(normal).to_local(dir)),
        }
    }

    /// A point uniform over the light's area (density 1/A), its triangle's geometric normal
    /// and the triangle: `u_pos.x` picks a triangle ∝ area and is reused, rescaled, with
    /// `u_pos.y` for a point uniform on it (so stratified inputs stay stratified). The position
    /// half of [`AreaLight::sample_emission`], which the meter's direct term also draws with.
    #[inline]
    pub fn sample_position(&self, triangles: &[Triangle], u_pos: Vec2) -> (Vec3, Vec3, u32) {
        let (_, _, point, normal, prim) = self.sample_point(triangles, u_pos);
        (point, normal, prim)
    }

    /// [`AreaLight::sample_position`] with the light's triangle index and the barycentrics.
    #[inline]
    fn sample_point(&self, triangles: &[Triangle], u_pos: Vec2) -> (usize, (f32, f32), Vec3, Vec3, u32) {
        let target = u_pos.x * self.area();
        let i = self.cumulative_area.partition_point(|&c| c <= target).min(self.triangles.len() - 1);
        let lo = if i == 0 { 0.0 } else { self.cumulative_area[i - 1] };
        let ux = ((target - lo) / (self.cumulative_area[i] - lo)).clamp(0.0, 1.0 - f32::EPSILON / 2.0);
        let prim = self.triangles[i];
        let tri = &triangles[prim as usize];
        let b = warp::square_to_uniform_triangle(Vec2::new(ux, u_pos.y));
        (i, (b.x, b.y), tri.point(b.x, b.y), tri.normal(), prim)
    }

    /// A path start: a point from [`AreaLight::sample_position`] (`u_pos`); `u_dir` a direction
    /// from the profile, in the triangle's frame. A textured light's weight and `emitted`
    /// carry T(uv)/T̄ at the point (module docs).
    #[inline]
    pub fn sample_emission(&self, triangles: &[Triangle], u_pos: Vec2, u_dir: Vec2) -> Emission {
        let (i, b, origin, normal, prim) = self.sample_point(triangles, u_pos);
        let (local, w) = self.profile.sample(u_dir);
        let dir = self.frame(normal).to_world(local);
        let (weight, emitted) = match &self.texture {
            None => (Rgb::splat(w), Rgb::ONE),
            Some(t) => {
                let scale = t.relative(i, b);
                (scale * w, scale)
            }
        };
        Emission { origin, surface: Some((normal, prim)), dir, weight, emitted }
    }
}

/// What a textured area light is built from ([`AreaLight::new`]): the texture and, per
/// triangle of the light, its corners' texture coordinates and (a `mesh_attribute` texture
/// only, else empty) attribute values.
#[derive(Clone, Debug, PartialEq)]
pub struct EmitterTextureDesc {
    /// The texture.
    pub texture: Arc<Texture>,
    /// Per triangle, its corners' texture coordinates.
    pub uvs: Vec<[Vec2; 3]>,
    /// Per triangle, its corners' attribute values (a `mesh_attribute` texture), else empty.
    pub corners: Vec<[Rgb; 3]>,
}

/// The [`EmitterTexture`] of `desc` over triangles of cumulative areas `cumulative_area`:
/// T̄ = Σ A_i·mean_i / A, each triangle's mean exact (a mesh attribute's is its corners' mean,
/// the attribute being linear over the triangle; a negative or non-finite value is an error).
fn emitter_texture(desc: EmitterTextureDesc, cumulative_area: &[f32]) -> Result<EmitterTexture, LightError> {
    let EmitterTextureDesc { texture, uvs, corners } = desc;
    let (mut cells, mut sum, mut lo) = (0u64, glam::DVec3::ZERO, 0.0f32);
    for (i, (uv, &hi)) in uvs.iter().zip(cumulative_area).enumerate() {
        let mean = match (&*texture, corners.get(i)) {
            (Texture::MeshAttribute(m), Some(c)) => {
                let values = c.map(|x| x * m.scale);
                if let Some(v) = values.iter().find(|v| !v.is_finite() || v.min_element() < 0.0) {
                    return Err(LightError::Emission(v.to_array()));
                }
                (values[0] + values[1] + values[2]) / 3.0
            }
            _ => triangle_mean(&texture, *uv, &mut cells).map_err(|e| match e {
                MeanError::TooManyCells => LightError::TextureTooFine(MAX_CELLS),
                MeanError::MeshAttribute => LightError::TextureAttribute(String::new()),
            })?,
        };
        sum += mean.as_dvec3() * f64::from(hi - lo);
        lo = hi;
    }
    let area = f64::from(cumulative_area.last().copied().unwrap_or(0.0));
    let mean = if area > 0.0 { (sum / area).as_vec3() } else { Rgb::ZERO };
    let inv_mean = Rgb::select(mean.cmpgt(Rgb::ZERO), mean.recip(), Rgb::ZERO);
    Ok(EmitterTexture { texture, uvs, corners, mean, inv_mean })
}

/// The frame of z = `normal` (unit) whose x axis is `tangent` (unit) projected onto the plane ⊥ `normal`,
/// falling back to world +x, then +z, when that projection is shorter than 10⁻² (the tangent
/// within 0.6° of the normal).
fn tangent_frame(normal: Vec3, tangent: Vec3) -> Frame {
    let project = |t: Vec3| t - normal * t.dot(normal);
    let mut s = project(tangent);
    for fallback in [Vec3::X, Vec3::Z] {
        if s.length_squared() >= 1e-4 {
            break;
        }
        s = project(fallback);
    }
    let s = s.normalize();
    Frame { s, t: normal.cross(s), n: normal }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::{Bitmap, Checkerboard, FilterType, UvTransform, WrapMode};

    /// The quad [0, 2] × [0, 1] (z = 0, facing +z) as two triangles of area 1, with UVs
    /// spanning [0, 1]², and a Lambertian light of radiance 1 over it following `texture`.
    fn textured_quad(texture: Texture) -> (AreaLight, Vec<Triangle>) {
        let p = [Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(2.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
        let tri = |a: Vec3, b: Vec3, c: Vec3| Triangle { v0: a, e1: b - a, e2: c - a };
        let triangles = vec![tri(p[0], p[1], p[2]), tri(p[0], p[2], p[3])];
        let uv = |q: Vec3| Vec2::new(q.x / 2.0, q.y);
        let uvs = vec![[uv(p[0]), uv(p[1]), uv(p[2])], [uv(p[0]), uv(p[2]), uv(p[3])]];
        let light = AreaLight::new(
            "l".into(),
            Rgb::ONE,
            None,
            None,
            None,
            vec![0, 1],
            vec![1.0, 2.0],
            Some(EmitterTextureDesc { texture: Arc::new(texture), uvs, corners: Vec::new() }),
        )
        .unwrap();
        (light, triangles)
    }

    #[test]
    fn a_textured_light_power_is_the_analytic_integral_of_its_radiance() {
        let pi = std::f32::consts::PI;
        // A 2×2 bitmap, nearest: Φ = π·A·(mean texel) = π·2·(1 + 2 + 3 + 6)/4 per grey level.
        let texels = [1.0, 2.0, 3.0, 6.0].map(|g| Rgb::new(g, 2.0 * g, 0.0)).to_vec();
        let bm =
            Bitmap::new(2, 2, texels, FilterType::Nearest, WrapMode::Repeat, UvTransform::IDENTITY).unwrap();
        let (light, _) = textured_quad(Texture::Bitmap(bm));
        let want = Rgb::new(3.0, 6.0, 0.0) * (pi * 2.0);
        assert!((light.power() - want).abs().max_element() < 1e-5 * want.max_element(), "{}", light.power());
        // A checkerboard of 1.5 periods per side (cells of side 1/3 in uv): 5 of its 9 cells
        // are color0: Φ = π·A·(5·c0 + 4·c1)/9.
        let (c0, c1) = (Rgb::new(9.0, 0.0, 1.0), Rgb::new(0.0, 4.5, 1.0));
        let to_uv = UvTransform([[1.5, 0.0, 0.0], [0.0, 1.5, 0.0]]);
        let (light, _) = textured_quad(Texture::Checkerboard(Checkerboard::new(c0, c1, to_uv).unwrap()));
        let want = (c0 * 5.0 + c1 * 4.0) / 9.0 * (pi * 2.0);
        assert!((light.power() - want).abs().max_element() < 1e-5 * want.max_element(), "{}", light.power());
    }

    #[test]
    fn textured_start_weights_average_to_one_and_match_the_lookup() {
        let to_uv = UvTransform([[1.5, 0.0, 0.0], [0.0, 1.5, 0.0]]);
        let c = Checkerboard::new(Rgb::new(9.0, 0.0, 1.0), Rgb::new(0.0, 4.5, 1.0), to_uv).unwrap();
        let (light, triangles) = textured_quad(Texture::Checkerboard(c));
        let n = 300;
        let mut sum = Rgb::ZERO;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let e = light.sample_emission(&triangles, u, Vec2::new(0.3, 0.7));
                let (_, prim) = e.surface.unwrap();
                assert_eq!(e.weight, e.emitted); // a Lambertian profile's weight is 1
                assert!((light.scale_at(&triangles, prim, e.origin) - e.emitted).abs().max_element() < 1e-6);
                sum += e.emitted;
            }
        }
        let mean = sum / (n * n) as f32;
        // E[T/T̄] = 1 per channel (the channel-y texture is 0 on 5/9 of the area); the grid
        // is stratified, its error the cells cut by the checker's edges.
        assert!((mean - Rgb::ONE).abs().max_element() < 1e-2, "{mean}");
    }

    #[test]
    fn tangent_frame_follows_the_projected_tangent_and_falls_back() {
        let n = Vec3::new(0.0, -1.0, 1.0).normalize();
        for (tangent, want_s) in [
            (Vec3::X, Vec3::X),
            (Vec3::Y, Vec3::new(0.0, 1.0, 1.0).normalize()),
            (-Vec3::Y, Vec3::new(0.0, -1.0, -1.0).normalize()),
            (n, Vec3::X),                                       // parallel to the normal: world +x
            (Vec3::new(0.0, -1.0, 1.001).normalize(), Vec3::X), // within 0.6°: still the fallback
        ] {
            let f = tangent_frame(n, tangent);
            assert!((f.s - want_s).length() < 1e-5, "{tangent}: s = {}", f.s);
            assert!(f.s.dot(f.n).abs() < 1e-6 && (f.t - n.cross(f.s)).length() < 1e-6 && f.n == n);
        }
        // Normal along +x with tangent +x: +x projects to zero, +z is used.
        assert!((tangent_frame(Vec3::X, Vec3::X).s - Vec3::Z).length() < 1e-6);
        assert!((tangent_frame(-Vec3::Y, Vec3::X).s - Vec3::X).length() < 1e-6);
    }
}
