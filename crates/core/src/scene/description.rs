//! The plain scene description: what every loader (Mitsuba XML, OBJ, VRML, glTF, the built-in
//! demo) produces. World-space triangles, materials, lights and an optional camera; no
//! acceleration structures. [`crate::scene::Scene::build`] validates it; the constructors
//! [`PointLightDesc::spot`] and [`DirectionalLightDesc::new`] check their light as they build
//! it, so a loader can report a bad value where the file gives it.

use crate::bsdf::Material;
use crate::light::check::{LightError, check_emission, unit_axis};
use crate::light::{EmissionProfile, axis_frame};
use crate::math::{Frame, Rgb, Vec2, Vec3};
use crate::scene::Photometry;
use crate::texture::{Texture, TextureBinding};
use glam::DVec3;

/// A camera as a scene file states it: where it is, how it is oriented, its image size and its
/// kind ([`CameraKind`]: perspective, thin lens or orthographic).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraDesc {
    /// Centre of projection.
    pub eye: Vec3,
    /// A point the camera looks at.
    pub target: Vec3,
    /// Up hint (need not be orthogonal to the view direction).
    pub up: Vec3,
    /// Full horizontal field of view, degrees (perspective and thin lens).
    pub fov_x_degrees: f32,
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// The kind of camera.
    pub kind: CameraKind,
    /// The film's crop window and reconstruction filter (default: the whole film, box).
    pub film: crate::sensor::FilmSpec,
}

/// How a scene file's camera forms its image ([`crate::sensor::Sensor::new`] builds the sensor).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum CameraKind {
    /// A pinhole at the eye (perspective projection).
    #[default]
    Perspective,
    /// A thin lens centred on the eye: depth of field.
    ThinLens {
        /// Radius of the aperture, metres (0: a pinhole).
        aperture_radius: f32,
        /// Distance from the lens to the plane in focus, along the view direction, metres.
        focus_distance: f32,
    },
    /// An orthographic projection: parallel rays along the view direction from a film
    /// rectangle centred on the eye (`fov_x_degrees` is not used).
    Orthographic {
        /// Half the film's width, metres.
        half_width: f32,
        /// Half the film's height, metres.
        half_height: f32,
    },
}

/// Where a scene element came from, for error messages ("scene.xml:42").
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Source {
    /// File path as given by the user (empty for built-in scenes).
    pub file: String,
    /// 1-based line, 0 if unknown.
    pub line: u32,
}

impl std::fmt::Display for Source {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.file.is_empty(), self.line) {
            (true, _) => write!(f, "<built-in>"),
            (false, 0) => write!(f, "{}", self.file),
            (false, l) => write!(f, "{}:{}", self.file, l),
        }
    }
}

/// A triangle mesh in world space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshDesc {
    /// Name (shape id) for messages.
    pub name: String,
    /// Where it was declared.
    pub source: Source,
    /// World-space vertex positions.
    pub positions: Vec<Vec3>,
    /// Counter-clockwise triangles (front face normal = (v1-v0)×(v2-v0)).
    pub triangles: Vec<[u32; 3]>,
    /// Optional per-vertex **shading** normals, one per position (any length, normalised when
    /// the scene is built), or empty for a faceted mesh. They are interpolated across each
    /// triangle by barycentrics and change only how the BSDF is oriented; the geometric normal
    /// still decides the sides, the emission and ray offsets (see [`crate::bsdf`]).
    pub normals: Vec<Vec3>,
    /// Optional per-vertex texture coordinates, one per position, or empty. A triangle's UV at
    /// a point is its vertices' interpolated by barycentrics; without them it is the
    /// barycentrics (b1, b2) themselves, as in Mitsuba. Only textured materials read them.
    pub uvs: Vec<Vec2>,
    /// Named per-vertex or per-face values that `mesh_attribute` textures read (only the ones a
    /// texture uses: a loader drops the others).
    pub attributes: Vec<MeshAttribute>,
    /// Index into [`SceneDescription::materials`].
    pub material: usize,
    /// If set, the mesh is a one-sided area light (front faces only).
    pub emission: Option<AreaEmission>,
}

#[cfg(test)]
impl MeshDesc {
    /// A horizontal 10 m square at height `y` (two triangles facing +y), of material `material`,
    /// centred on the y axis: the sheets of the panes' and the meter's tests.
    pub(crate) fn square_at(name: String, y: f32, material: usize) -> MeshDesc {
        MeshDesc {
            name,
            positions: vec![
                Vec3::new(-5.0, y, -5.0),
                Vec3::new(-5.0, y, 5.0),
                Vec3::new(5.0, y, 5.0),
                Vec3::new(5.0, y, -5.0),
            ],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            material,
            ..Default::default()
        }
    }
}

/// A mesh's named attribute (Mitsuba's mesh attributes): one value per vertex if the name starts
/// with `vertex_` (blended across a triangle by the barycentrics), one per triangle if it starts
/// with `face_`; one channel or three.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshAttribute {
    /// `vertex_…` or `face_…` (Mitsuba's names, e.g. `vertex_color`).
    pub name: String,
    /// 1 or 3.
    pub channels: u8,
    /// One per vertex or per triangle (a one-channel value in every component), finite.
    pub values: Vec<Rgb>,
}

impl MeshAttribute {
    /// Whether the attribute has one value per vertex (else one per triangle).
    pub fn per_vertex(&self) -> bool {
        self.name.starts_with("vertex_")
    }
}

/// How an emissive mesh emits: the one place an area light is described.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AreaEmission {
    /// Radiance along the normal, W/(m²·sr) (for the default Lambertian profile, in every
    /// front direction). Ignored for the power when `power` is given.
    pub radiance: Rgb,
    /// The directional distribution; `None` = [`EmissionProfile::Cosine`] (Lambertian).
    /// Evaluated in each triangle's photometric frame: z = the geometric normal, x (horizontal
    /// 0°) = `tangent` projected onto the triangle ([`crate::light::AreaLight::frame`]).
    pub profile: Option<EmissionProfile>,
    /// World direction of the profile's horizontal 0° (projected onto each triangle's plane;
    /// only IES profiles depend on it). `None` = world +x. Must be finite and non-zero.
    pub tangent: Option<Vec3>,
    /// If set, the area light's power Φ (W per channel), overriding `radiance` (which then
    /// follows: Φ/(A·∫s dω)).
    pub power: Option<Rgb>,
    /// A texture the radiance follows over the mesh's texture coordinates (which it must
    /// have): the radiance at a point is `radiance` times the texture's value there
    /// ([`crate::light::area`] module docs). `None`: uniform.
    pub texture: Option<std::sync::Arc<Texture>>,
}

impl AreaEmission {
    /// A Lambertian emitter of `radiance` W/(m²·sr).
    pub fn lambertian(radiance: Rgb) -> Self {
        AreaEmission { radiance, ..Default::default() }
    }
}

/// A point light.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointLightDesc {
    /// Name for messages and relighting.
    pub name: String,
    /// Where it was declared.
    pub source: Source,
    /// Position, world space.
    pub position: Vec3,
    /// Radiant intensity on the profile's axis, W/sr (isotropic: power Φ = 4π·I). For an IES
    /// profile, a per-channel scale of the file's candela/683.
    pub intensity: Rgb,
    /// The emission distribution; `None` = [`EmissionProfile::Uniform`] (isotropic).
    pub profile: Option<EmissionProfile>,
    /// The profile's frame in world space (z = the axis, e.g. a spot's direction or an IES
    /// file's 0° vertical angle; x = horizontal angle 0°). `None` = the identity (z = world +z).
    /// Use `Frame::from_normal(axis)` when only the axis matters.
    pub orientation: Option<Frame>,
    /// If set, the power Φ (W per channel), overriding `intensity` (which then follows from
    /// it: intensity = Φ/∫s dω).
    pub power: Option<Rgb>,
    /// The IES file an [`EmissionProfile::Ies`] profile was read from, if known (so a writer
    /// can refer to it rather than drop the table).
    pub ies_file: Option<std::path::PathBuf>,
    /// A texture a spot profile projects (Mitsuba's `spot` `texture`:
    /// [`crate::light::spot_texture`]); `None` for an untextured light.
    pub texture: Option<std::sync::Arc<crate::texture::Texture>>,
}

impl PointLightDesc {
    /// A spot light at `position` shining along `axis` (any length; x of its frame as close to
    /// world +x as possible) with `intensity` W/sr on the axis, Mitsuba's profile of cutoff angle
    /// `cutoff` and beam width `beam` (radians; [`EmissionProfile::spot`]). Checks the intensity,
    /// the angles and the axis, in that order.
    pub fn spot(
        name: String,
        source: Source,
        position: Vec3,
        axis: DVec3,
        intensity: Rgb,
        cutoff: f32,
        beam: f32,
    ) -> Result<Self, LightError> {
        Ok(PointLightDesc {
            intensity: check_emission(intensity)?,
            profile: Some(EmissionProfile::spot(cutoff, beam)?),
            orientation: Some(axis_frame(axis, DVec3::X)?),
            name,
            source,
            position,
            power: None,
            ies_file: None,
            texture: None,
        })
    }
}

/// A directional (sun) light covering the whole scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DirectionalLightDesc {
    /// Name for messages and relighting.
    pub name: String,
    /// Where it was declared.
    pub source: Source,
    /// Direction the light travels in (need not be unit length).
    pub direction: Vec3,
    /// Irradiance on a plane perpendicular to the direction, W/m².
    pub irradiance: Rgb,
}

impl DirectionalLightDesc {
    /// A sun travelling along `direction` (normalised in double precision) with `irradiance`
    /// W/m². Checks the irradiance, then the direction.
    pub fn new(name: String, source: Source, direction: DVec3, irradiance: Rgb) -> Result<Self, LightError> {
        let irradiance = check_emission(irradiance)?;
        Ok(DirectionalLightDesc { name, source, direction: unit_axis(direction)?.as_vec3(), irradiance })
    }
}

/// What an environment light emits, as a loader reads it (the core builds its sampling
/// distribution, [`crate::light::LatLong`]).
#[derive(Clone, Debug, PartialEq)]
pub enum EnvironmentRadiance {
    /// The same radiance from every direction, W/(m²·sr).
    Constant(Rgb),
    /// A latitude-longitude map in Mitsuba's convention (`crate::light::environment`).
    Map {
        /// Columns.
        width: usize,
        /// Rows.
        height: usize,
        /// `width × height` linear RGB texels, row-major from the top row.
        texels: Vec<Rgb>,
        /// Factor on every texel.
        scale: f32,
        /// The file the map was read from, if any (for messages and writers).
        file: Option<std::path::PathBuf>,
    },
}

/// An environment light at infinity (Mitsuba's `constant` and `envmap`).
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentLightDesc {
    /// Name for messages and relighting.
    pub name: String,
    /// Where it was declared.
    pub source: Source,
    /// What it emits.
    pub radiance: EnvironmentRadiance,
    /// The map's frame in the world: a rotation (world = R·map).
    pub to_world: glam::Mat3,
    /// The daylight sky it is, when a sky generator made it (Radiance's `!gensky`,
    /// `!gendaylit`): the daylight factor is defined under one model only.
    pub sky: Option<SkyModel>,
}

/// The sky model of an environment light a sky generator made; its zenith is the map's pole
/// (`to_world`·ŷ).
#[derive(Clone, Debug, PartialEq)]
pub enum SkyModel {
    /// The CIE standard overcast sky, luminance ∝ (1 + 2 cos θ)/3 above the horizon (Moon and
    /// Spencer's; `gensky -c`), with its ground below: the sky of the daylight factor.
    CieOvercast,
    /// Another model, in words for messages ("a CIE clear sky (gensky +s)").
    Other(String),
}

/// Everything a loader produces.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneDescription {
    /// Materials referenced by meshes.
    pub materials: Vec<Material>,
    /// Triangle meshes (area lights are meshes with an [`AreaEmission`]).
    pub meshes: Vec<MeshDesc>,
    /// Point lights.
    pub point_lights: Vec<PointLightDesc>,
    /// Directional lights.
    pub directional_lights: Vec<DirectionalLightDesc>,
    /// Environment lights.
    pub environment_lights: Vec<EnvironmentLightDesc>,
    /// The scene file's own camera, if it has one.
    pub camera: Option<CameraDesc>,
    /// Textures in place of materials' colour parameters (none: every colour is constant).
    pub textures: Vec<TextureBinding>,
    /// How its RGB values become lux: its format's rule ([`Photometry::RADIANCE`] for `.rad`,
    /// [`Photometry::REC709_683`] otherwise). Not part of any fingerprint: it changes no light
    /// path, only what a meter reports in lux.
    pub photometry: Photometry,
}
