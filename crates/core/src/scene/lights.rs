//! The lights stage of [`super::Scene::build`]: each light description becomes a core
//! [`Light`] through its kind's constructor ([`AreaLight::new`], [`PointLight::new`],
//! [`DirectionalLight::new`], which hold the checks), whose [`crate::light::LightError`] is
//! located here at the light's declaration, as is a light whose power is not finite. Then the
//! scene's light table as a whole: at least one light, unique names, a finite total power.

use super::meshes::{Emitter, Flat, NO_UV};
use super::{
    AreaEmission, DirectionalLightDesc, EnvironmentLightDesc, EnvironmentRadiance, MeshDesc, PointLightDesc,
    SceneError, Source,
};
use crate::light::EmitterTextureDesc;
use crate::light::{
    AreaLight, DirectionalLight, EnvRadiance, EnvironmentLight, LatLong, Light, LightError, PointLight,
};
use crate::math::{Vec2, Vec3};
use crate::texture::Texture;
use std::sync::Arc;

/// `source` of a light's constructor, located at the light `name` declared at `at`.
fn located(at: &Source, name: &str) -> impl FnOnce(LightError) -> SceneError {
    let (at, light) = (at.clone(), name.to_string());
    move |source| SceneError::Light { at, light, source }
}

/// A constructed light whose power is finite, channel by channel and summed (the weight its
/// path quota is computed from): radiance 1e38 on a unit square, or a sun over a scene of huge
/// coordinates, has finite parameters but infinite power, and its samples would carry ∞.
fn finite_power(light: Light) -> Result<Light, LightError> {
    let p = light.power();
    if p.is_finite() && (p.x + p.y + p.z).is_finite() {
        Ok(light)
    } else {
        Err(LightError::PowerNotFinite(p.to_array()))
    }
}

/// The area light of the emissive `mesh` (emitting `emission`) over its flattened triangles
/// (in `flat`, which holds their texture coordinates, which a textured emission needs).
pub(super) fn area_light(
    mesh: &MeshDesc,
    emission: &AreaEmission,
    emitter: Emitter,
    flat: &Flat,
) -> Result<Light, SceneError> {
    if emitter.triangles.is_empty() {
        return Err(SceneError::EmptyAreaLight { at: mesh.source.clone(), light: mesh.name.clone() });
    }
    let texture = match &emission.texture {
        None => None,
        Some(t) => Some(texture_desc(t, &emitter, flat).map_err(located(&mesh.source, &mesh.name))?),
    };
    AreaLight::new(
        mesh.name.clone(),
        emission.radiance,
        emission.profile.as_ref(),
        emission.tangent,
        emission.power,
        emitter.triangles,
        emitter.cumulative_area,
        texture,
    )
    .map(Light::Area)
    .and_then(finite_power)
    .map_err(located(&mesh.source, &mesh.name))
}

/// What the textured light over `emitter` needs of `flat`: per triangle, its texture
/// coordinates (required, unless the texture is a mesh attribute: then zero where missing) and,
/// for a mesh attribute, its corners' values (required).
fn texture_desc(
    texture: &Arc<Texture>,
    emitter: &Emitter,
    flat: &Flat,
) -> Result<EmitterTextureDesc, LightError> {
    let attribute = match &**texture {
        Texture::MeshAttribute(m) => Some(m),
        _ => None,
    };
    let uv = |prim: u32| match flat.uv_of[prim as usize] {
        NO_UV => attribute.map(|_| [Vec2::ZERO; 3]),
        k => Some(flat.uvs[k as usize]),
    };
    let uvs = emitter.triangles.iter().map(|&prim| uv(prim)).collect::<Option<Vec<_>>>();
    let uvs = uvs.ok_or(LightError::TextureWithoutUvs)?;
    let corners = match attribute {
        None => Vec::new(),
        Some(m) => {
            let missing = || LightError::TextureAttribute(m.name.clone());
            let table = flat.attributes.iter().find(|t| t.name == m.name).ok_or_else(missing)?;
            let corners = emitter.triangles.iter().map(|&prim| table.corners(prim).copied());
            corners.collect::<Option<Vec<_>>>().ok_or_else(missing)?
        }
    };
    Ok(EmitterTextureDesc { texture: texture.clone(), uvs, corners })
}

/// The point light of `p`.
pub(super) fn point_light(p: &PointLightDesc) -> Result<Light, SceneError> {
    let (profile, texture) = (p.profile.as_ref(), p.texture.clone());
    PointLight::new(p.name.clone(), p.position, p.intensity, profile, p.orientation, p.power, texture)
        .map(Light::Point)
        .and_then(finite_power)
        .map_err(located(&p.source, &p.name))
}

/// The scene's bounding sphere from its triangle corners `vertices` (not empty): the centre
/// of the bounding box and half its diagonal.
fn bounding_sphere(vertices: &[[Vec3; 3]]) -> (Vec3, f32) {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for v in vertices.iter().flatten() {
        lo = lo.min(*v);
        hi = hi.max(*v);
    }
    (0.5 * (lo + hi), 0.5 * (hi - lo).length())
}

/// The directional lights `lights` over a scene of triangle corners `vertices` (not empty):
/// each covers the scene's bounding sphere.
pub(super) fn directional_lights(
    lights: &[DirectionalLightDesc],
    vertices: &[[Vec3; 3]],
) -> Result<Vec<Light>, SceneError> {
    let bounds = bounding_sphere(vertices);
    lights
        .iter()
        .map(|d| {
            DirectionalLight::new(d.name.clone(), d.direction, d.irradiance, bounds)
                .map(Light::Directional)
                .and_then(finite_power)
                .map_err(located(&d.source, &d.name))
        })
        .collect()
}

/// The environment lights `lights` around a scene of triangle corners `vertices` (not empty):
/// each emits from disks of the scene's bounding radius, and a map's sampling distribution is
/// built here.
pub(super) fn environment_lights(
    lights: &[EnvironmentLightDesc],
    vertices: &[[Vec3; 3]],
) -> Result<Vec<Light>, SceneError> {
    let bounds = bounding_sphere(vertices);
    lights
        .iter()
        .map(|d| {
            let radiance = match &d.radiance {
                EnvironmentRadiance::Constant(c) => Ok(EnvRadiance::Constant(*c)),
                EnvironmentRadiance::Map { width, height, texels, scale, .. } => {
                    LatLong::new(*width, *height, texels, *scale).map(EnvRadiance::Map)
                }
            };
            radiance
                .and_then(|r| EnvironmentLight::new(d.name.clone(), r, d.to_world, bounds))
                .map(Light::Environment)
                .and_then(finite_power)
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
    let total: f32 = lights.iter().map(|l| crate::dataset::quota_weight(l.power())).sum();
    if !total.is_finite() {
        return Err(SceneError::TotalPowerNotFinite);
    }
    let mut names = std::collections::HashSet::new();
    match lights.iter().map(Light::name).find(|n| !names.insert(*n)) {
        Some(dup) => Err(SceneError::DuplicateLightName(dup.to_string())),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use crate::math::Rgb;
    use crate::scene::{AreaEmission, Scene, SceneError, cornell_box};

    /// Issue 10, item 20: a light of radiance 1e38 passed `Scene::build` with infinite power, and
    /// `bench` then printed `"mean_rgb":[inf,inf,inf]`. A light whose power (or the sum of its
    /// channels, or of all lights') is not finite is refused, located at its declaration.
    #[test]
    fn lights_of_infinite_power_are_refused() {
        // The box's light, ten times larger (area 17.48 m²): radiance L gives Φ = π·A·L.
        let box_with = |radiance: Rgb| {
            let mut desc = cornell_box();
            let light = &mut desc.meshes[3];
            light.positions.iter_mut().for_each(|p| *p *= 10.0);
            light.emission = Some(AreaEmission::lambertian(radiance));
            desc
        };
        let per_watt = 1.0 / (std::f32::consts::PI * 17.48);
        let e = Scene::build(&box_with(Rgb::new(1e38, 1.0, 1.0))).unwrap_err();
        assert!(matches!(e, SceneError::Light { .. }), "{e}");
        assert!(e.to_string().contains("light 'light': its power [inf, "), "{e}");
        // Each channel finite, their sum not.
        let e = Scene::build(&box_with(Rgb::splat(1.5e38 * per_watt))).unwrap_err();
        assert!(e.to_string().contains("is not a finite number"), "{e}");
        // Each light finite, all of them together not.
        let mut desc = box_with(Rgb::new(3e38 * per_watt, 0.0, 0.0));
        assert!(Scene::build(&desc).is_ok(), "one such light alone is finite");
        let mut second = desc.meshes[3].clone();
        second.name = "light2".into();
        desc.meshes.push(second);
        assert!(matches!(Scene::build(&desc), Err(SceneError::TotalPowerNotFinite)));
    }
}
