//! The lights stage of [`super::Scene::build`]: each light description becomes a core
//! [`Light`] through its kind's constructor ([`AreaLight::new`], [`PointLight::new`],
//! [`DirectionalLight::new`], which hold the checks), whose [`crate::light::LightError`] is
//! located here at the light's declaration. Then the scene's light table as a whole: at least
//! one light, unique names.

use super::meshes::Emitter;
use super::{AreaEmission, DirectionalLightDesc, MeshDesc, PointLightDesc, SceneError, Source};
use crate::light::{AreaLight, DirectionalLight, Light, LightError, PointLight};
use crate::math::Vec3;

/// `source` of a light's constructor, located at the light `name` declared at `at`.
fn located(at: &Source, name: &str) -> impl FnOnce(LightError) -> SceneError {
    let (at, light) = (at.clone(), name.to_string());
    move |source| SceneError::Light { at, light, source }
}

/// The area light of the emissive `mesh` (emitting `emission`) over its flattened triangles.
pub(super) fn area_light(
    mesh: &MeshDesc,
    emission: &AreaEmission,
    emitter: Emitter,
) -> Result<Light, SceneError> {
    if emitter.triangles.is_empty() {
        return Err(SceneError::EmptyAreaLight { at: mesh.source.clone(), light: mesh.name.clone() });
    }
    AreaLight::new(
        mesh.name.clone(),
        emission.radiance,
        emission.profile.as_ref(),
        emission.tangent,
        emission.power,
        emitter.triangles,
        emitter.cumulative_area,
    )
    .map(Light::Area)
    .map_err(located(&mesh.source, &mesh.name))
}

/// The point light of `p`.
pub(super) fn point_light(p: &PointLightDesc) -> Result<Light, SceneError> {
    PointLight::new(p.name.clone(), p.position, p.intensity, p.profile.as_ref(), p.orientation, p.power)
        .map(Light::Point)
        .map_err(located(&p.source, &p.name))
}

/// The directional lights `lights` over a scene of triangle corners `vertices` (not empty):
/// each covers the scene's bounding sphere (centre of the bounding box, half its diagonal).
pub(super) fn directional_lights(
    lights: &[DirectionalLightDesc],
    vertices: &[[Vec3; 3]],
) -> Result<Vec<Light>, SceneError> {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for v in vertices.iter().flatten() {
        lo = lo.min(*v);
        hi = hi.max(*v);
    }
    let bounds = (0.5 * (lo + hi), 0.5 * (hi - lo).length());
    lights
        .iter()
        .map(|d| {
            DirectionalLight::new(d.name.clone(), d.direction, d.irradiance, bounds)
                .map(Light::Directional)
                .map_err(located(&d.source, &d.name))
        })
        .collect()
}

/// The scene's lights as a whole: at least one, and no two with the same name (lights are
/// matched by name when relighting).
pub(super) fn check_light_table(lights: &[Light]) -> Result<(), SceneError> {
    if lights.is_empty() {
        return Err(SceneError::NoLight);
    }
    let mut names = std::collections::HashSet::new();
    match lights.iter().map(Light::name).find(|n| !names.insert(*n)) {
        Some(dup) => Err(SceneError::DuplicateLightName(dup.to_string())),
        None => Ok(()),
    }
}
