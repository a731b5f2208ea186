//! The lights as a bidirectional render sees them (`docs/bidirectional.md` §6): the lights that
//! are **on** — a relit power Φ'_k > 0 and paths N_k > 0 in the part of the dataset rendered —
//! with NEE's pick probability P_k = N_k/N (N = Σ N_k over the lights on, whatever their relit
//! powers), and the two things camera paths ask of a light: a point drawn with its own emission
//! position sampling, with what it emits toward a receiver (NEE, [`RenderLights::sample`]), and
//! what an area light emits at a point a camera ray found ([`RenderLights::hit`]) or an
//! environment in the direction a camera ray left the scene ([`RenderLights::escaped`]). All come with
//! the light's own [`Emitter`] densities for the MIS weights.
//!
//! Lights are matched to the dataset's light table by name, as `crate::dataset::lighting` does,
//! and every emitted quantity scales with Φ'_k: relighting, switching a light off, add-light'ed
//! and merged datasets and `--fraction` previews (whose N'_k are the rendered chunks' paths)
//! stay exact.

use crate::dataset::Emitter;
use crate::light::Light;
use crate::math::{Rgb, Vec2, Vec3};
use crate::scene::Scene;
use crate::trace::emitter_densities;
use std::f32::consts::PI;

/// One light that is on.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderLight {
    /// Its index in the scene.
    pub scene_index: usize,
    /// Its index in the dataset's light table.
    pub table_index: usize,
    /// Its relit power Φ'_k (W per channel).
    pub power: Rgb,
    /// Its paths N_k in the rendered part of the dataset.
    pub paths: u64,
    /// P_k = N_k/N.
    pub pick: f32,
}

/// The lights that are on, and the maps from scene and table indices to them.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderLights {
    lights: Vec<RenderLight>,
    /// Cumulative pick probabilities (last = 1).
    cumulative: Vec<f64>,
    by_scene: Vec<Option<u32>>,
    by_table: Vec<Option<u32>>,
    /// N = Σ N_k over the lights on.
    total_paths: u64,
    /// The environments among the lights on (indices into `lights`).
    environments: Vec<u32>,
}

/// A light point drawn for NEE, seen from a receiver.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightPoint {
    /// Unit direction from the receiver toward the light.
    pub dir: Vec3,
    /// Distance to the light point (∞ for a directional light).
    pub distance: f32,
    /// What arrives at the receiver per unit projected receiver area, before its cosine, divided
    /// by the pick probability: L_e·|cos θ₀|/(d²·p₀·P_k) (area), I/(d²·P_k) (point), E/P_k
    /// (directional), relit.
    pub radiance: Rgb,
    /// The light's own densities of the point and of the direction toward the receiver.
    pub emitter: Emitter,
    /// |cos θ₀| at the light point (area lights; 1 otherwise).
    pub cos_light: f32,
    /// P_k.
    pub pick: f32,
    /// The light's geometric normal (area lights), for the shadow ray's offset.
    /// (An environment's point is a direction: `distance` ∞, no normal.)
    pub normal: Option<Vec3>,
}

impl RenderLights {
    /// The lights of `scene` that are on, given the dataset table's light `names` and per table
    /// light the flux per path Φ'_k/N_k after relighting and `paths` N_k in the rendered chunks.
    pub fn new(scene: &Scene, names: &[&str], flux_per_path: &[Rgb], paths: &[u64]) -> Self {
        let mut lights = Vec::new();
        let mut by_scene = vec![None; scene.lights.len()];
        let mut by_table = vec![None; names.len()];
        for (k, name) in names.iter().enumerate() {
            let (flux, n) = (flux_per_path[k], paths[k]);
            let Some(scene_index) = scene.light_index(name) else { continue };
            if n == 0 || !(flux.max_element() > 0.0) {
                continue;
            }
            by_scene[scene_index] = Some(lights.len() as u32);
            by_table[k] = Some(lights.len() as u32);
            lights.push(RenderLight {
                scene_index,
                table_index: k,
                power: flux * n as f32,
                paths: n,
                pick: 0.0,
            });
        }
        let total_paths: u64 = lights.iter().map(|l| l.paths).sum();
        let mut cumulative = Vec::with_capacity(lights.len());
        let mut acc = 0u64;
        for l in &mut lights {
            acc += l.paths;
            l.pick = (l.paths as f64 / total_paths as f64) as f32;
            cumulative.push(acc as f64 / total_paths as f64);
        }
        let environments = (0..lights.len() as u32)
            .filter(|&i| matches!(scene.lights[lights[i as usize].scene_index], Light::Environment(_)))
            .collect();
        RenderLights { lights, cumulative, by_scene, by_table, total_paths, environments }
    }

    /// The lights that are on.
    pub fn lights(&self) -> &[RenderLight] {
        &self.lights
    }

    /// N = Σ N_k over the lights on.
    pub fn total_paths(&self) -> u64 {
        self.total_paths
    }

    /// The light that is on of table index `k`, if it is on.
    #[inline]
    pub fn of_table(&self, k: usize) -> Option<&RenderLight> {
        self.by_table.get(k).copied().flatten().map(|i| &self.lights[i as usize])
    }

    /// The area light that is on whose emitter triangle `prim` is, if any.
    #[inline]
    pub fn of_triangle(&self, scene: &Scene, prim: u32) -> Option<&RenderLight> {
        let l = scene.light_of(prim)?;
        self.by_scene[l].map(|i| &self.lights[i as usize])
    }

    /// NEE from the receiver at `x`: picks a light with probability P_k (`u_pick`), draws its
    /// point with its own emission-position sampling (`u_pos`), and says what it sends toward x
    /// ([`RenderLights::toward`]). `None` if no light is on or the point cannot light x.
    #[inline]
    pub fn sample(&self, scene: &Scene, x: Vec3, u_pick: f32, u_pos: Vec2) -> Option<LightPoint> {
        let i =
            self.cumulative.partition_point(|&c| c <= u_pick as f64).min(self.lights.len().checked_sub(1)?);
        let (at, normal) = match &scene.lights[self.lights[i].scene_index] {
            Light::Area(a) => {
                // The point alone: `toward` evaluates what it sends (a textured light's radiance
                // there included), so no emission direction or start weight is needed here.
                let (at, normal, prim) = a.sample_position(&scene.triangles, u_pos);
                (at, Some((normal, prim)))
            }
            Light::Environment(env) => {
                let (omega, pdf) = env.sample_direction(u_pos);
                return self.from_environment(scene, i, omega, pdf);
            }
            _ => (Vec3::ZERO, None),
        };
        self.toward(scene, i, at, normal, x)
    }

    /// What the environment `i` (of [`RenderLights::lights`]) sends from the unit direction
    /// `omega` drawn with solid-angle density `pdf` (its own direction sampling), as NEE sees it:
    /// L'(ω)/(pdf·P_k), relit. `None` if `i` is no environment or `pdf` is 0.
    #[inline]
    pub fn from_environment(&self, scene: &Scene, i: usize, omega: Vec3, pdf: f32) -> Option<LightPoint> {
        let (radiance, pick) = self.environment_radiance(scene, i, omega, pdf)?;
        let light = &scene.lights[self.lights[i].scene_index];
        Some(LightPoint {
            dir: omega,
            distance: f32::INFINITY,
            radiance,
            emitter: emitter_densities(light, Vec3::ZERO, -omega),
            cos_light: 1.0,
            pick,
            normal: None,
        })
    }

    /// [`RenderLights::from_environment`]'s L'(ω)/(pdf·P_k) and P_k alone, without the
    /// emitter's densities an MIS weight needs (the meter's sky sampler weighs its own
    /// directions, and looking the direction up in the map's distribution again cost it a
    /// tenth of its instructions).
    #[inline]
    pub fn environment_radiance(&self, scene: &Scene, i: usize, omega: Vec3, pdf: f32) -> Option<(Rgb, f32)> {
        let rl = &self.lights[i];
        let Light::Environment(env) = &scene.lights[rl.scene_index] else { return None };
        if !(pdf > 0.0) {
            return None;
        }
        Some((relit_environment(env, rl.power, omega) / (pdf * rl.pick), rl.pick))
    }

    /// A camera ray leaving the scene along the unit direction `dir`: per environment that is
    /// on, its relit radiance L'(dir), its densities of that direction, and P_k.
    #[inline]
    pub fn escaped<'a>(
        &'a self,
        scene: &'a Scene,
        dir: Vec3,
    ) -> impl Iterator<Item = (Rgb, Emitter, f32)> + 'a {
        self.environments.iter().filter_map(move |&i| {
            let rl = &self.lights[i as usize];
            let light = &scene.lights[rl.scene_index];
            let Light::Environment(env) = light else { return None };
            Some((relit_environment(env, rl.power, dir), emitter_densities(light, Vec3::ZERO, -dir), rl.pick))
        })
    }

    /// Whether an environment is on.
    #[inline]
    pub fn has_environment(&self) -> bool {
        !self.environments.is_empty()
    }

    /// What light `i` (of [`RenderLights::lights`]) sends from its point `at` (on the
    /// triangle `surface` = (normal, scene index); area lights only, ignored for the others)
    /// toward `x`, as NEE sees it (a textured light's radiance at `at`). `None` behind a
    /// one-sided emitter or at x itself.
    #[inline]
    pub fn toward(
        &self,
        scene: &Scene,
        i: usize,
        at: Vec3,
        surface: Option<(Vec3, u32)>,
        x: Vec3,
    ) -> Option<LightPoint> {
        let rl = &self.lights[i];
        let finite = |p: Vec3| {
            let v = p - x;
            let d2 = v.length_squared();
            (d2 > 0.0).then(|| (v / d2.sqrt(), d2.sqrt(), d2))
        };
        let light = &scene.lights[rl.scene_index];
        match light {
            Light::Area(a) => {
                let (normal, prim) = surface?;
                let (dir, d, d2) = finite(at)?;
                let cos_light = -normal.dot(dir);
                if !(cos_light > 0.0) {
                    return None;
                }
                let fraction = a.emitted_fraction(normal, -dir);
                // L_e·cos θ₀/(d²·p₀·P) with L_e = fraction·Φ/A and p₀ = 1/A.
                // An untextured light's scale is exactly 1.
                let radiance = rl.power
                    * (fraction * cos_light / (d2 * rl.pick))
                    * a.scale_at(&scene.triangles, prim, at);
                let emitter = emitter_densities(light, normal, -dir);
                Some(LightPoint {
                    dir,
                    distance: d,
                    radiance,
                    emitter,
                    cos_light,
                    pick: rl.pick,
                    normal: Some(normal),
                })
            }
            Light::Point(p) => {
                let (dir, d, d2) = finite(p.position)?;
                let radiance = rl.power * (p.emission_density(-dir) / (d2 * rl.pick));
                let emitter = emitter_densities(light, Vec3::ZERO, -dir);
                Some(LightPoint {
                    dir,
                    distance: d,
                    radiance,
                    emitter,
                    cos_light: 1.0,
                    pick: rl.pick,
                    normal: None,
                })
            }
            // An environment's point is a direction: [`RenderLights::from_environment`].
            Light::Environment(_) => None,
            Light::Directional(s) => {
                let disk = PI * s.radius * s.radius;
                let radiance = rl.power / (disk * rl.pick);
                let dir = -s.direction;
                let emitter = emitter_densities(light, Vec3::ZERO, -dir);
                Some(LightPoint {
                    dir,
                    distance: f32::INFINITY,
                    radiance,
                    emitter,
                    cos_light: 1.0,
                    pick: rl.pick,
                    normal: None,
                })
            }
        }
    }

    /// A camera ray arriving at the point `at` of `prim` (an emitter triangle of normal
    /// `normal`) from the direction `to_camera`: the relit radiance L_e toward the camera (a
    /// textured light's at `at`), the light's densities
    /// of the point and of that direction, and P_k. `None` if `prim` emits for no light that is
    /// on, or the ray arrives from behind.
    #[inline]
    pub fn hit(
        &self,
        scene: &Scene,
        prim: u32,
        at: Vec3,
        normal: Vec3,
        to_camera: Vec3,
    ) -> Option<(Rgb, Emitter, f32)> {
        let rl = self.of_triangle(scene, prim)?;
        let Light::Area(a) = &scene.lights[rl.scene_index] else { return None };
        if !(normal.dot(to_camera) > 0.0) {
            return None;
        }
        let radiance = rl.power
            * (a.emitted_fraction(normal, to_camera) / a.area())
            * a.scale_at(&scene.triangles, prim, at);
        let emitter = emitter_densities(&scene.lights[rl.scene_index], normal, to_camera);
        Some((radiance, emitter, rl.pick))
    }
}

/// The environment `env`'s radiance L(ω) scaled to the relit power `power`: L·Φ'/Φ per
/// channel (0 in a channel that emits nothing).
#[inline]
fn relit_environment(env: &crate::light::EnvironmentLight, power: Rgb, omega: Vec3) -> Rgb {
    let (l, own) = (env.radiance(omega), env.power());
    let per = |l: f32, relit: f32, own: f32| if own > 0.0 { l * (relit / own) } else { 0.0 };
    Rgb::new(per(l.x, power.x, own.x), per(l.y, power.y, own.y), per(l.z, power.z, own.z))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{PointLightDesc, cornell_box};

    fn cornell_with_bulb() -> crate::scene::SceneDescription {
        let mut d = cornell_box();
        let position = Vec3::new(0.3, -0.2, 0.6);
        d.point_lights.push(PointLightDesc {
            name: "bulb".into(),
            position,
            intensity: Rgb::ONE,
            ..Default::default()
        });
        d
    }

    /// Lights are matched by name; a light is on with paths and a relit power > 0; P_k = N_k/N
    /// over the lights on only; what NEE and emitter hits return scales with the relit power.
    #[test]
    fn lights_on_their_picks_and_their_relit_emission() {
        let scene = Scene::build(&cornell_with_bulb()).unwrap(); // "light" (area), "bulb" (point)
        let flux = [Rgb::splat(2.0), Rgb::splat(0.5)];
        // The table lists them the other way round, plus a light gone from the scene.
        let both = RenderLights::new(
            &scene,
            &["bulb", "light", "gone"],
            &[flux[1], flux[0], Rgb::ONE],
            &[300, 100, 50],
        );
        assert_eq!(both.total_paths(), 400);
        assert_eq!(both.lights().len(), 2);
        let (bulb, area) = (both.of_table(0).unwrap(), both.of_table(1).unwrap());
        assert!(both.of_table(2).is_none());
        assert_eq!((bulb.scene_index, area.scene_index), (1, 0));
        assert_eq!((bulb.pick, area.pick), (0.75, 0.25));
        assert_eq!(area.power, Rgb::splat(200.0)); // Φ' = flux per path × N_k
        // The bulb off: the area light alone, picked with probability 1.
        let one = RenderLights::new(&scene, &["bulb", "light"], &[Rgb::ZERO, flux[0]], &[300, 100]);
        assert!(one.of_table(0).is_none());
        assert_eq!((one.total_paths(), one.of_table(1).unwrap().pick), (100, 1.0));
        // NEE from a point of the floor toward the ceiling light: twice the power, twice the light.
        let x = Vec3::new(0.1, -0.99, 0.2);
        let a = one.sample(&scene, x, 0.3, Vec2::new(0.4, 0.6)).unwrap();
        let doubled = RenderLights::new(&scene, &["bulb", "light"], &[Rgb::ZERO, 2.0 * flux[0]], &[300, 100]);
        let b = doubled.sample(&scene, x, 0.3, Vec2::new(0.4, 0.6)).unwrap();
        assert_eq!((a.dir, a.pick), (b.dir, b.pick));
        assert!((b.radiance - 2.0 * a.radiance).abs().max_element() <= 1e-6 * b.radiance.max_element());
        // An emitter hit on the ceiling light from below, and none from above.
        let prim = (0..scene.triangles.len() as u32).find(|&p| scene.light_of(p) == Some(0)).unwrap();
        let (n, at) = (scene.normal(prim), scene.triangles[prim as usize].point(0.25, 0.25));
        assert!(one.hit(&scene, prim, at, n, n).is_some() && one.hit(&scene, prim, at, n, -n).is_none());
        assert!(
            RenderLights::new(&scene, &["light"], &[Rgb::ZERO], &[100]).hit(&scene, prim, at, n, n).is_none()
        );
    }
}
