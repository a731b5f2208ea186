//! Textures: values that vary over a surface, as Mitsuba 3 defines them — looked up by the
//! (u, v) texture coordinates (`bitmap`, `checkerboard`) or read from the hit mesh's own
//! per-vertex or per-face data (`mesh_attribute`, [`MeshAttributeTexture`]); a constant is a
//! plain number in the BSDF.
//!
//! A texture is bound to one parameter of a material ([`TextureBinding`], a [`ColourSlot`] of
//! [`crate::bsdf::Bsdf`]: a colour, or a roughness, which takes the texture's single value
//! [`Texture::eval_1`] as Mitsuba's `eval_1`); the scene resolves the material at a hit
//! ([`crate::scene::Scene::material_at`]), which evaluates the texture at the hit's UV — from
//! the triangle's vertex UVs at the barycentrics recomputed from the point, so a stored
//! sample (position and triangle) needs nothing more — and, for a mesh attribute, at the
//! triangle's attribute values blended by the same barycentrics. Materials without textures
//! are returned as they are, with no lookup.
//!
//! UV conventions (Mitsuba's): `to_uv` maps (u, v, 1) affinely before the lookup; texel (i, j)
//! of a `width` × `height` bitmap has its centre at ((i + ½)/width, (j + ½)/height), row 0 being
//! the image's first (top) row; bilinear filtering interpolates the four nearest centres,
//! nearest takes the texel containing the point; the wrap mode maps texel indices outside the
//! image back into it (repeat, mirror, clamp).

use crate::bsdf::{Bsdf, Plastic};
use crate::math::{Rgb, Vec2, Vec3};
use std::sync::Arc;

pub mod integral;
mod principled_weight;
pub use principled_weight::PrincipledWeight;

/// An affine map of texture coordinates: (u, v) ↦ (m00·u + m01·v + m02, m10·u + m11·v + m12)
/// (Mitsuba's `to_uv`, a 3×3 matrix whose last row is 0 0 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform(pub [[f32; 3]; 2]);

impl UvTransform {
    /// The identity.
    pub const IDENTITY: UvTransform = UvTransform([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);

    /// The image of `uv`.
    #[inline]
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        let [a, b] = self.0;
        Vec2::new(a[0] * uv.x + a[1] * uv.y + a[2], b[0] * uv.x + b[1] * uv.y + b[2])
    }
}

/// How texel indices outside the image are mapped back into it (Mitsuba's `wrap_mode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WrapMode {
    /// Tiles the image (the default).
    Repeat,
    /// Tiles it mirrored every other time.
    Mirror,
    /// Repeats the edge texels.
    Clamp,
}

impl WrapMode {
    /// Index `i` mapped into `0..n` (`n` > 0).
    #[inline]
    pub fn wrap(self, i: i64, n: i64) -> usize {
        let k = match self {
            WrapMode::Repeat => i.rem_euclid(n),
            WrapMode::Clamp => i.clamp(0, n - 1),
            WrapMode::Mirror => {
                let k = i.rem_euclid(2 * n);
                if k >= n { 2 * n - 1 - k } else { k }
            }
        };
        k as usize
    }
}

/// How a bitmap is sampled between texel centres (Mitsuba's `filter_type`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FilterType {
    /// Bilinear interpolation of the four nearest texel centres (the default).
    Bilinear,
    /// The texel containing the point.
    Nearest,
}

/// A grid of linear RGB texels (row 0 first, the image's top row).
#[derive(Clone, Debug, PartialEq)]
pub struct Bitmap {
    width: usize,
    height: usize,
    texels: Vec<Rgb>,
    /// Interpolation between texel centres.
    pub filter: FilterType,
    /// Indices outside the image.
    pub wrap: WrapMode,
    /// Applied to the surface's UV before the lookup.
    pub to_uv: UvTransform,
}

/// Why a texture cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TextureError {
    /// The texel grid does not match its size, or is empty.
    #[error("a {width}×{height} bitmap needs {} texels, got {got}", width * height)]
    Size {
        /// Columns.
        width: usize,
        /// Rows.
        height: usize,
        /// Texels given.
        got: usize,
    },
    /// A texel or colour is negative or not finite.
    #[error("texel {index} = {value} is negative or not finite")]
    BadTexel {
        /// Row-major texel index.
        index: usize,
        /// Its value.
        value: Rgb,
    },
    /// A `to_uv` entry is not finite.
    #[error("the to_uv transform has a non-finite entry")]
    BadTransform,
    /// A mesh attribute's name starts with neither `vertex_` nor `face_`.
    #[error("mesh attribute \"{0}\": the name must start with \"vertex_\" or \"face_\"")]
    AttributeName(String),
    /// A mesh attribute's scale is not finite.
    #[error("the scale {0} is not finite")]
    BadScale(f32),
}

impl Bitmap {
    /// A `width` × `height` bitmap of `texels` (row-major, row 0 first). Refuses an empty grid,
    /// a grid of the wrong length, negative or non-finite texels and a non-finite transform.
    pub fn new(
        width: usize,
        height: usize,
        texels: Vec<Rgb>,
        filter: FilterType,
        wrap: WrapMode,
        to_uv: UvTransform,
    ) -> Result<Self, TextureError> {
        if width == 0 || height == 0 || width.checked_mul(height) != Some(texels.len()) {
            return Err(TextureError::Size { width, height, got: texels.len() });
        }
        if let Some((index, &value)) =
            texels.iter().enumerate().find(|(_, t)| !t.is_finite() || t.min_element() < 0.0)
        {
            return Err(TextureError::BadTexel { index, value });
        }
        check_transform(&to_uv)?;
        Ok(Bitmap { width, height, texels, filter, wrap, to_uv })
    }

    /// Columns and rows.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// The texels, row-major, row 0 first.
    pub fn texels(&self) -> &[Rgb] {
        &self.texels
    }

    /// The texel at column `i`, row `j`, wrapped.
    #[inline]
    fn texel(&self, i: i64, j: i64) -> Rgb {
        let (x, y) = (self.wrap.wrap(i, self.width as i64), self.wrap.wrap(j, self.height as i64));
        self.texels[y * self.width + x]
    }

    /// The colour at surface coordinates `uv`.
    #[inline]
    pub fn eval(&self, uv: Vec2) -> Rgb {
        let uv = self.to_uv.apply(uv);
        if !uv.is_finite() {
            return self.texels[0];
        }
        // Far outside [0, 1]² the indices saturate; the wrap keeps them in range.
        let p = Vec2::new(uv.x * self.width as f32, uv.y * self.height as f32);
        match self.filter {
            FilterType::Nearest => self.texel(p.x.floor() as i64, p.y.floor() as i64),
            FilterType::Bilinear => {
                let p = p - Vec2::splat(0.5);
                let (i, j) = (p.x.floor(), p.y.floor());
                let (w1x, w1y) = (p.x - i, p.y - j);
                let (i, j) = (i as i64, j as i64);
                let row = |j: i64| self.texel(i, j) * (1.0 - w1x) + self.texel(i + 1, j) * w1x;
                row(j) * (1.0 - w1y) + row(j + 1) * w1y
            }
        }
    }

    /// The largest value of each channel (a bound of [`Bitmap::eval`]: interpolation is convex).
    pub fn max_value(&self) -> Rgb {
        self.texels.iter().fold(Rgb::ZERO, |m, t| m.max(*t))
    }

    /// The gradient (∂/∂u, ∂/∂v) of the luminance of [`Bitmap::eval`] at surface coordinates
    /// `uv` (Mitsuba's `eval_1_grad`): the derivative of the bilinear interpolation of the four
    /// texels' luminances within their cell, in texels, times the resolution, carried back
    /// through `to_uv` by its transpose. Zero for nearest filtering (piecewise constant) and
    /// where `uv` is not finite.
    #[inline]
    pub fn gradient_1(&self, uv: Vec2) -> Vec2 {
        let q = self.to_uv.apply(uv);
        if self.filter == FilterType::Nearest || !q.is_finite() {
            return Vec2::ZERO;
        }
        let p = Vec2::new(q.x * self.width as f32, q.y * self.height as f32) - Vec2::splat(0.5);
        let (i, j) = (p.x.floor(), p.y.floor());
        let (w1x, w1y) = (p.x - i, p.y - j);
        let (i, j) = (i as i64, j as i64);
        let f = |di: i64, dj: i64| luminance(self.texel(i + di, j + dj));
        let (f00, f10, f01, f11) = (f(0, 0), f(1, 0), f(0, 1), f(1, 1));
        let dx = ((f10 - f00) * (1.0 - w1y) + (f11 - f01) * w1y) * self.width as f32;
        let dy = ((f01 - f00) * (1.0 - w1x) + (f11 - f10) * w1x) * self.height as f32;
        let [a, b] = self.to_uv.0;
        Vec2::new(a[0] * dx + b[0] * dy, a[1] * dx + b[1] * dy)
    }

    /// The smallest and largest luminance of a texel (bounds of [`Texture::eval_1`]: the
    /// luminance of a convex blend is the blend of the luminances).
    fn luminance_range(&self) -> (f32, f32) {
        self.texels
            .iter()
            .map(|t| luminance(*t))
            .fold((f32::INFINITY, 0.0), |(lo, hi), y| (lo.min(y), hi.max(y)))
    }
}

/// The luminance of a linear sRGB colour (Mitsuba's `luminance`: the Y row of sRGB → XYZ).
#[inline]
pub fn luminance(c: Rgb) -> f32 {
    c.dot(Vec3::new(0.212_671, 0.715_160, 0.072_169))
}

/// Mitsuba's `checkerboard`: `color0` where the fractional parts of u and v (after `to_uv`) are
/// both above ½ or both at most ½, `color1` elsewhere.
#[derive(Clone, Debug, PartialEq)]
pub struct Checkerboard {
    /// The colour of the squares containing (0.25, 0.25) (Mitsuba's default 0.4).
    pub color0: Rgb,
    /// The other squares' colour (Mitsuba's default 0.2).
    pub color1: Rgb,
    /// Applied to the surface's UV before the lookup.
    pub to_uv: UvTransform,
}

impl Checkerboard {
    /// A checkerboard; refuses negative or non-finite colours and a non-finite transform.
    pub fn new(color0: Rgb, color1: Rgb, to_uv: UvTransform) -> Result<Self, TextureError> {
        for (index, value) in [color0, color1].into_iter().enumerate() {
            if !value.is_finite() || value.min_element() < 0.0 {
                return Err(TextureError::BadTexel { index, value });
            }
        }
        check_transform(&to_uv)?;
        Ok(Checkerboard { color0, color1, to_uv })
    }

    /// The colour at surface coordinates `uv`.
    #[inline]
    pub fn eval(&self, uv: Vec2) -> Rgb {
        let uv = self.to_uv.apply(uv);
        let high = |x: f32| x - x.floor() > 0.5;
        if high(uv.x) == high(uv.y) { self.color0 } else { self.color1 }
    }

    /// The single value at `uv` (Mitsuba's `eval_1`): the mean of `color0`'s channels where the
    /// fractional parts of u and v are on *different* sides of ½, of `color1`'s elsewhere —
    /// the squares of [`Checkerboard::eval`] swapped, as Mitsuba 3's `eval_1` has them (a quirk
    /// of its code, followed so that a textured roughness renders as there).
    #[inline]
    pub fn eval_1(&self, uv: Vec2) -> f32 {
        let uv = self.to_uv.apply(uv);
        let high = |x: f32| x - x.floor() > 0.5;
        let c = if high(uv.x) != high(uv.y) { self.color0 } else { self.color1 };
        c.element_sum() / 3.0
    }
}

/// Mitsuba's `mesh_attribute`: the hit mesh's attribute `name` (`vertex_…`: one value per
/// vertex, blended by the barycentrics; `face_…`: one per triangle), times `scale`. The values
/// belong to the meshes ([`crate::scene::MeshDesc::attributes`]), not to the texture: one
/// texture reads each mesh it is on at that mesh's data.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshAttributeTexture {
    /// The attribute's name, starting with `vertex_` or `face_`.
    pub name: String,
    /// Multiplies the attribute (Mitsuba's `scale`, 1 by default).
    pub scale: f32,
}

impl MeshAttributeTexture {
    /// The texture of attribute `name` times `scale`; refuses a name starting with neither
    /// `vertex_` nor `face_` (Mitsuba's rule) and a non-finite scale.
    pub fn new(name: String, scale: f32) -> Result<Self, TextureError> {
        if !name.starts_with("vertex_") && !name.starts_with("face_") {
            return Err(TextureError::AttributeName(name));
        }
        if !scale.is_finite() {
            return Err(TextureError::BadScale(scale));
        }
        Ok(MeshAttributeTexture { name, scale })
    }

    /// Whether the attribute has one value per vertex (else one per face).
    pub fn per_vertex(&self) -> bool {
        self.name.starts_with("vertex_")
    }
}

fn check_transform(t: &UvTransform) -> Result<(), TextureError> {
    if t.0.iter().flatten().all(|x| x.is_finite()) { Ok(()) } else { Err(TextureError::BadTransform) }
}

/// The closed set of textures.
#[derive(Clone, Debug, PartialEq)]
pub enum Texture {
    /// One value everywhere (a constant `opacity`: every channel the same).
    Constant(f32),
    /// An image.
    Bitmap(Bitmap),
    /// Two colours in squares.
    Checkerboard(Checkerboard),
    /// A mesh's own per-vertex or per-face values.
    MeshAttribute(MeshAttributeTexture),
}

impl Texture {
    /// The colour at surface coordinates `uv`, where the mesh attribute the texture reads (if
    /// it is a [`Texture::MeshAttribute`]) is `attribute` (the scene's blend of the triangle's
    /// values; ignored by the other textures).
    #[inline]
    pub fn eval(&self, uv: Vec2, attribute: Rgb) -> Rgb {
        match self {
            Texture::Constant(v) => Rgb::splat(*v),
            Texture::Bitmap(b) => b.eval(uv),
            Texture::Checkerboard(c) => c.eval(uv),
            Texture::MeshAttribute(m) => attribute * m.scale,
        }
    }

    /// The single value a float parameter (a roughness) takes, as Mitsuba's `eval_1`: a
    /// bitmap's luminance, the mean of a checkerboard square's colour ([`Checkerboard::eval_1`]:
    /// its squares swapped, as Mitsuba's), a one-channel mesh attribute's value (`attribute.x`;
    /// the scene admits only one-channel attributes here).
    #[inline]
    pub fn eval_1(&self, uv: Vec2, attribute: Rgb) -> f32 {
        match self {
            Texture::Constant(v) => *v,
            Texture::Bitmap(b) => luminance(b.eval(uv)),
            Texture::Checkerboard(c) => c.eval_1(uv),
            Texture::MeshAttribute(m) => attribute.x * m.scale,
        }
    }

    /// The largest value of each channel over the surface; for a mesh attribute, whose values
    /// the meshes hold, the scale (the scene bounds the values).
    pub fn max_value(&self) -> Rgb {
        match self {
            Texture::Constant(v) => Rgb::splat(*v),
            Texture::Bitmap(b) => b.max_value(),
            Texture::Checkerboard(c) => c.color0.max(c.color1),
            Texture::MeshAttribute(m) => Rgb::splat(m.scale),
        }
    }

    /// The smallest and largest value of [`Texture::eval_1`] over the surface (for a mesh
    /// attribute, whose values the meshes hold: the scale, twice).
    pub fn range_1(&self) -> (f32, f32) {
        match self {
            Texture::Constant(v) => (*v, *v),
            Texture::Bitmap(b) => b.luminance_range(),
            Texture::Checkerboard(c) => {
                let (a, b) = (c.color0.element_sum() / 3.0, c.color1.element_sum() / 3.0);
                (a.min(b), a.max(b))
            }
            Texture::MeshAttribute(m) => (m.scale, m.scale),
        }
    }

    /// Every number that decides the texture's values, in a fixed order (for the scene's
    /// fingerprint: a dataset traced with one texture does not render against another).
    pub fn fingerprint_words(&self) -> Vec<f32> {
        let mut words = Vec::new();
        self.fingerprint_with(&mut |w| words.extend_from_slice(w));
        words
    }

    /// [`Self::fingerprint_words`] handed to `sink` a block at a time: a bitmap's texels are
    /// not copied whole (the scene's fingerprint of an 8192² texture held an 805 MB copy).
    pub fn fingerprint_with(&self, sink: &mut dyn FnMut(&[f32])) {
        let t = |t: &UvTransform| t.0.concat();
        let w = match self {
            // A tag no other texture's first word is.
            Texture::Constant(v) => vec![3.0, *v],
            Texture::Bitmap(b) => {
                let mut w = vec![0.0, b.width as f32, b.height as f32];
                w.push(match b.filter {
                    FilterType::Bilinear => 0.0,
                    FilterType::Nearest => 1.0,
                });
                w.push(match b.wrap {
                    WrapMode::Repeat => 0.0,
                    WrapMode::Mirror => 1.0,
                    WrapMode::Clamp => 2.0,
                });
                w.extend(t(&b.to_uv));
                sink(&w);
                for block in b.texels.chunks(4096) {
                    let words: Vec<f32> = block.iter().flat_map(|x| x.to_array()).collect();
                    sink(&words);
                }
                return;
            }
            Texture::Checkerboard(c) => {
                let mut w = vec![1.0];
                w.extend(c.color0.to_array());
                w.extend(c.color1.to_array());
                w.extend(t(&c.to_uv));
                w
            }
            // The values are the meshes' (hashed with their triangles).
            Texture::MeshAttribute(m) => {
                let mut w = vec![2.0, m.scale, m.name.len() as f32];
                w.extend(m.name.bytes().map(f32::from));
                w
            }
        };
        sink(&w);
    }
}

/// A parameter of a BSDF that a texture can replace (Mitsuba's parameter names): a colour, or a
/// roughness ([`ColourSlot::is_colour`] tells which; the name is its first members').
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ColourSlot {
    /// `reflectance` of `diffuse`.
    Reflectance,
    /// `diffuse_reflectance` of `plastic`, `kd` of Phong.
    DiffuseReflectance,
    /// `specular_reflectance` of conductors, dielectrics and plastic; `ks` of Phong.
    SpecularReflectance,
    /// `specular_transmittance` of dielectrics.
    SpecularTransmittance,
    /// `alpha` of rough conductors and dielectrics: both roughnesses.
    Alpha,
    /// `alpha_u`: the roughness along the tangent.
    AlphaU,
    /// `alpha_v`: the roughness along the bitangent.
    AlphaV,
    /// `weight` of `blendbsdf`: the share of its second BSDF, a float (`eval_1`) in [0, 1].
    Weight,
    /// `opacity` of Mitsuba's `mask`: not a BSDF parameter but the probability that a ray meets
    /// the surface at all (`crate::scene`'s masked intersection); a float (`eval_1`) in [0, 1].
    Opacity,
    /// `normalmap` of Mitsuba's `normalmap`: not a BSDF parameter but the shading normal, an RGB
    /// texture whose colour c is the tangent-space normal 2c − 1 ([`crate::scene::Scene::normals_at`]).
    NormalMap,
    /// The height of Mitsuba's `bumpmap`: not a BSDF parameter but a field whose UV gradient
    /// ([`Bitmap::gradient_1`], of its luminance) tilts the shading normal
    /// ([`crate::scene::Scene::normals_at`]); a bitmap.
    BumpMap,
    /// The `scale` of Mitsuba's `bumpmap` (the gradient's multiplier, 1 if absent): a finite
    /// [`Texture::Constant`] beside the material's [`ColourSlot::BumpMap`].
    BumpScale,
    /// `base_color` of `principled` and `principledthin`: a colour.
    BaseColor,
    /// A weight of `principled` or `principledthin` in [0, 1] (`diff_trans` [0, 2]; its
    /// `eval_1`), set by [`set_principled`].
    Principled(PrincipledWeight),
}

impl ColourSlot {
    /// Mitsuba's name of the parameter.
    pub fn name(self) -> &'static str {
        match self {
            ColourSlot::Reflectance => "reflectance",
            ColourSlot::DiffuseReflectance => "diffuse_reflectance",
            ColourSlot::SpecularReflectance => "specular_reflectance",
            ColourSlot::SpecularTransmittance => "specular_transmittance",
            ColourSlot::Alpha => "alpha",
            ColourSlot::AlphaU => "alpha_u",
            ColourSlot::AlphaV => "alpha_v",
            ColourSlot::Weight => "weight",
            ColourSlot::Opacity => "opacity",
            ColourSlot::NormalMap => "normalmap",
            ColourSlot::BumpMap => "bumpmap",
            ColourSlot::BumpScale => "bumpmap scale",
            ColourSlot::BaseColor => "base_color",
            ColourSlot::Principled(w) => w.name(),
        }
    }

    /// Whether the parameter is a colour (else a roughness, set by [`set_roughness`], a blend's
    /// [`ColourSlot::Weight`], set by [`set_weight`], a weight of `principled`, set by
    /// [`set_principled`], the [`ColourSlot::Opacity`] of a masked
    /// surface or one of the [`ColourSlot::shapes_surface`] slots).
    pub fn is_colour(self) -> bool {
        !matches!(
            self,
            ColourSlot::Alpha
                | ColourSlot::AlphaU
                | ColourSlot::AlphaV
                | ColourSlot::Weight
                | ColourSlot::Principled(_)
        ) && self.is_bsdf_parameter()
    }

    /// Whether the slot is a parameter of the BSDF (else it says where the surface is met, an
    /// [`ColourSlot::Opacity`], or how it is oriented, [`ColourSlot::shapes_surface`]): what the
    /// scene sets when it resolves a material at a point.
    pub fn is_bsdf_parameter(self) -> bool {
        !matches!(self, ColourSlot::Opacity) && !self.shapes_surface()
    }

    /// Whether the slot perturbs the shading normal (a normal map, or a bump map's height or
    /// scale) rather than setting a parameter of the BSDF.
    pub fn shapes_surface(self) -> bool {
        matches!(self, ColourSlot::NormalMap | ColourSlot::BumpMap | ColourSlot::BumpScale)
    }
}

/// The least roughness a texture gives: Mitsuba clamps every α at 10⁻⁴ (`MicrofacetDistribution`),
/// so a black texel of a roughness texture is a near-mirror, not an error.
pub const MIN_TEXTURED_ALPHA: f32 = 1e-4;

/// Sets the roughness `slot` of `bsdf` to `alpha` (both α for [`ColourSlot::Alpha`]); false
/// (and `bsdf` unchanged) if the BSDF has no such roughness. The caller keeps α in range.
pub fn set_roughness(bsdf: &mut Bsdf, slot: ColourSlot, alpha: f32) -> bool {
    let m = match bsdf {
        Bsdf::RoughConductor(b) => &mut b.microfacet,
        Bsdf::RoughDielectric(b) => &mut b.microfacet,
        _ => return false,
    };
    match slot {
        ColourSlot::Alpha => (m.alpha_u, m.alpha_v) = (alpha, alpha),
        ColourSlot::AlphaU => m.alpha_u = alpha,
        ColourSlot::AlphaV => m.alpha_v = alpha,
        _ => return false,
    }
    true
}

/// Sets the weight of `bsdf`, a blend, to `w` (in [0, 1], the caller's to keep); false (and
/// `bsdf` unchanged) if it is not a blend.
pub fn set_weight(bsdf: &mut Bsdf, w: f32) -> bool {
    match bsdf {
        Bsdf::Blend(b) => {
            b.weight = w;
            true
        }
        _ => false,
    }
}

/// Sets the colour `slot` of `bsdf` to `c`; false (and `bsdf` unchanged) if the BSDF has no
/// such colour, or if `c` is one its constructor refuses (a plastic's).
pub fn set_colour(bsdf: &mut Bsdf, slot: ColourSlot, c: Rgb) -> bool {
    use ColourSlot::*;
    let field = match (bsdf, slot) {
        (Bsdf::Lambert(b), Reflectance) => &mut b.reflectance,
        (Bsdf::ModifiedPhong(b), DiffuseReflectance) => &mut b.kd,
        (Bsdf::ModifiedPhong(b), SpecularReflectance) => &mut b.ks,
        (Bsdf::SmoothConductor(b), SpecularReflectance) => &mut b.specular_reflectance,
        (Bsdf::RoughConductor(b), SpecularReflectance) => &mut b.specular_reflectance,
        (Bsdf::SmoothDielectric(b), SpecularReflectance) => &mut b.specular_reflectance,
        (Bsdf::SmoothDielectric(b), SpecularTransmittance) => &mut b.specular_transmittance,
        (Bsdf::RoughDielectric(b), SpecularReflectance) => &mut b.specular_reflectance,
        (Bsdf::RoughDielectric(b), SpecularTransmittance) => &mut b.specular_transmittance,
        (Bsdf::ThinDielectric(b), SpecularReflectance) => &mut b.specular_reflectance,
        (Bsdf::ThinDielectric(b), SpecularTransmittance) => &mut b.specular_transmittance,
        (Bsdf::Principled(b), BaseColor) => &mut b.base_color,
        (Bsdf::PrincipledThin(b), BaseColor) => &mut b.base_color,
        // Mitsuba's rough plastic keeps the sampling weight of the colours it was built with.
        (Bsdf::RoughPlastic(b), DiffuseReflectance) => &mut b.diffuse_reflectance,
        (Bsdf::RoughPlastic(b), SpecularReflectance) => &mut b.specular_reflectance,
        // The plastic's sampling weights follow from its colours: rebuilt.
        (Bsdf::Plastic(b), DiffuseReflectance | SpecularReflectance) => {
            let (d, s) = match slot {
                DiffuseReflectance => (c, b.specular_reflectance),
                _ => (b.diffuse_reflectance, c),
            };
            return match Plastic::new(d, s, b.eta, 1.0, b.nonlinear) {
                Ok(p) => {
                    *b = p;
                    true
                }
                Err(_) => false,
            };
        }
        _ => return false,
    };
    *field = c;
    true
}

/// Sets the weight `w` of `bsdf`, a principled or thin principled BSDF, to `x` (in
/// [0, [`PrincipledWeight::max`]], the caller's to keep); false (and `bsdf` unchanged) if the
/// BSDF has no such weight.
pub fn set_principled(bsdf: &mut Bsdf, w: PrincipledWeight, x: f32) -> bool {
    let field = match bsdf {
        Bsdf::Principled(p) => w.field(p),
        Bsdf::PrincipledThin(p) => w.thin_field(p),
        _ => None,
    };
    field.map(|f| *f = x).is_some()
}

/// A texture in place of one colour parameter of one material of a scene description.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureBinding {
    /// Index into [`crate::scene::SceneDescription::materials`].
    pub material: usize,
    /// Which colour it replaces.
    pub slot: ColourSlot,
    /// The texture (shared: one image may colour many materials).
    pub texture: Arc<Texture>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(w: usize, h: usize) -> Vec<Rgb> {
        (0..w * h).map(|k| Rgb::new((k % w) as f32, (k / w) as f32, 1.0)).collect()
    }

    #[test]
    fn wrap_modes_fold_indices_as_mitsuba() {
        let r: Vec<usize> = (-4..8).map(|i| WrapMode::Repeat.wrap(i, 3)).collect();
        assert_eq!(r, [2, 0, 1, 2, 0, 1, 2, 0, 1, 2, 0, 1]);
        let m: Vec<usize> = (-4..8).map(|i| WrapMode::Mirror.wrap(i, 3)).collect();
        assert_eq!(m, [2, 2, 1, 0, 0, 1, 2, 2, 1, 0, 0, 1]);
        let c: Vec<usize> = (-4..8).map(|i| WrapMode::Clamp.wrap(i, 3)).collect();
        assert_eq!(c, [0, 0, 0, 0, 0, 1, 2, 2, 2, 2, 2, 2]);
    }

    #[test]
    fn bilinear_interpolates_between_texel_centres_and_nearest_picks_the_texel() {
        let b = |filter, wrap| Bitmap::new(4, 2, grid(4, 2), filter, wrap, UvTransform::IDENTITY).unwrap();
        let lin = b(FilterType::Bilinear, WrapMode::Clamp);
        // Texel centres return the texel exactly.
        assert_eq!(lin.eval(Vec2::new(0.125, 0.25)), Rgb::new(0.0, 0.0, 1.0));
        assert_eq!(lin.eval(Vec2::new(0.625, 0.75)), Rgb::new(2.0, 1.0, 1.0));
        // Halfway between centres: the mean; u is linear in between.
        let m = lin.eval(Vec2::new(0.25, 0.5));
        assert!((m - Rgb::new(0.5, 0.5, 1.0)).abs().max_element() < 1e-6, "{m}");
        let q = lin.eval(Vec2::new(0.125 + 0.25 * 0.3, 0.25));
        assert!((q.x - 0.3).abs() < 1e-5, "{q}");
        // Clamp: beyond the last centre stays at the edge; repeat blends with the other side.
        assert_eq!(lin.eval(Vec2::new(0.99, 0.25)).x, 3.0);
        let rep = b(FilterType::Bilinear, WrapMode::Repeat);
        assert!((rep.eval(Vec2::new(1.0, 0.25)).x - 1.5).abs() < 1e-5);
        assert!((rep.eval(Vec2::new(2.0, 0.25)) - rep.eval(Vec2::new(0.0, 0.25))).length() < 1e-5);
        let near = b(FilterType::Nearest, WrapMode::Repeat);
        assert_eq!(near.eval(Vec2::new(0.26, 0.9)), Rgb::new(1.0, 1.0, 1.0));
        assert_eq!(near.eval(Vec2::new(-0.01, 0.1)), Rgb::new(3.0, 0.0, 1.0));
        let mirror = b(FilterType::Nearest, WrapMode::Mirror);
        assert_eq!(mirror.eval(Vec2::new(-0.01, 0.1)), Rgb::new(0.0, 0.0, 1.0));
        assert_eq!(mirror.eval(Vec2::new(1.3, 0.1)), Rgb::new(2.0, 0.0, 1.0));
        assert_eq!(lin.max_value(), Rgb::new(3.0, 1.0, 1.0));
    }

    #[test]
    fn gradient_1_is_the_derivative_of_the_bilinear_luminance_through_to_uv() {
        // A grey ramp in x and an RGB ramp in y (luminance weights), repeated, scaled by to_uv.
        let texels: Vec<Rgb> =
            (0..16).map(|k| Rgb::new(0.1 * (k % 4) as f32, 0.05 * (k / 4) as f32, 0.2)).collect();
        let to_uv = UvTransform([[2.0, 0.5, 0.1], [-0.3, 1.5, 0.0]]);
        let b = Bitmap::new(4, 4, texels, FilterType::Bilinear, WrapMode::Repeat, to_uv).unwrap();
        let f = |uv: Vec2| luminance(b.eval(uv));
        for uv in [Vec2::new(0.2, 0.3), Vec2::new(0.41, 0.07), Vec2::new(0.05, 0.15)] {
            let h = 1e-3;
            let fd = Vec2::new(
                (f(uv + Vec2::new(h, 0.0)) - f(uv - Vec2::new(h, 0.0))) / (2.0 * h),
                (f(uv + Vec2::new(0.0, h)) - f(uv - Vec2::new(0.0, h))) / (2.0 * h),
            );
            let g = b.gradient_1(uv);
            assert!((g - fd).length() < 2e-3 * fd.length().max(1.0), "{uv}: {g} against {fd}");
        }
        let near = Bitmap::new(
            2,
            1,
            vec![Rgb::ZERO, Rgb::ONE],
            FilterType::Nearest,
            WrapMode::Clamp,
            UvTransform::IDENTITY,
        );
        assert_eq!(near.unwrap().gradient_1(Vec2::new(0.5, 0.5)), Vec2::ZERO);
    }

    #[test]
    fn to_uv_transforms_before_the_lookup_and_checkerboard_alternates() {
        let t = UvTransform([[2.0, 0.0, 0.5], [0.0, 2.0, 0.0]]);
        assert_eq!(t.apply(Vec2::new(0.25, 0.5)), Vec2::new(1.0, 1.0));
        let (a, b) = (Rgb::splat(0.4), Rgb::splat(0.2));
        let c = Checkerboard::new(a, b, UvTransform::IDENTITY).unwrap();
        assert_eq!(c.eval(Vec2::new(0.25, 0.25)), a);
        assert_eq!(c.eval(Vec2::new(0.75, 0.75)), a);
        assert_eq!(c.eval(Vec2::new(0.75, 0.25)), b);
        assert_eq!(c.eval(Vec2::new(-0.25, 0.25)), b);
        let scaled = Checkerboard::new(a, b, UvTransform([[4.0, 0.0, 0.0], [0.0, 4.0, 0.0]])).unwrap();
        assert_eq!(scaled.eval(Vec2::new(0.2, 0.05)), b);
    }

    #[test]
    fn bad_bitmaps_are_refused() {
        let ok = |t| Bitmap::new(2, 1, t, FilterType::Nearest, WrapMode::Repeat, UvTransform::IDENTITY);
        assert!(matches!(ok(vec![Rgb::ONE]), Err(TextureError::Size { got: 1, .. })));
        assert!(matches!(ok(vec![Rgb::ONE, -Rgb::ONE]), Err(TextureError::BadTexel { index: 1, .. })));
        assert!(matches!(ok(vec![Rgb::ONE, Rgb::splat(f32::NAN)]), Err(TextureError::BadTexel { .. })));
        let nan = UvTransform([[f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        assert_eq!(Checkerboard::new(Rgb::ONE, Rgb::ONE, nan), Err(TextureError::BadTransform));
        assert!(
            Bitmap::new(0, 0, vec![], FilterType::Nearest, WrapMode::Clamp, UvTransform::IDENTITY).is_err()
        );
    }

    #[test]
    fn eval_1_is_mitsubas_single_value_and_range_1_bounds_it() {
        let texels = vec![Rgb::new(1.0, 0.0, 0.0), Rgb::new(0.0, 1.0, 0.0), Rgb::splat(0.25), Rgb::ZERO];
        let b = Texture::Bitmap(
            Bitmap::new(4, 1, texels, FilterType::Nearest, WrapMode::Repeat, UvTransform::IDENTITY).unwrap(),
        );
        // Luminance: Y of linear sRGB; a grey is its own value.
        assert_eq!(b.eval_1(Vec2::new(0.1, 0.5), Rgb::ZERO), 0.212_671);
        assert_eq!(b.eval_1(Vec2::new(0.3, 0.5), Rgb::ZERO), 0.715_16);
        assert!((b.eval_1(Vec2::new(0.6, 0.5), Rgb::ZERO) - 0.25).abs() < 1e-7);
        assert_eq!(b.range_1(), (0.0, 0.715_16));
        // Checkerboard: the mean of the colour, color0 where eval gives color1 (Mitsuba's eval_1).
        let c = Texture::Checkerboard(
            Checkerboard::new(Rgb::new(0.1, 0.2, 0.6), Rgb::splat(0.5), UvTransform::IDENTITY).unwrap(),
        );
        assert_eq!(c.eval(Vec2::splat(0.25), Rgb::ZERO), Rgb::new(0.1, 0.2, 0.6));
        assert_eq!(c.eval_1(Vec2::splat(0.25), Rgb::ZERO), 0.5);
        assert!((c.eval_1(Vec2::new(0.75, 0.25), Rgb::ZERO) - 0.3).abs() < 1e-7);
        assert_eq!(c.range_1().1, 0.5);
        // A mesh attribute: the scene's blend times the scale.
        let m = Texture::MeshAttribute(MeshAttributeTexture::new("face_w".into(), 2.0).unwrap());
        assert_eq!(m.eval(Vec2::ZERO, Rgb::new(0.1, 0.2, 0.3)), Rgb::new(0.2, 0.4, 0.6));
        assert_eq!(m.eval_1(Vec2::ZERO, Rgb::splat(0.2)), 0.4);
        assert!(!MeshAttributeTexture::new("face_w".into(), 1.0).unwrap().per_vertex());
        assert_eq!(MeshAttributeTexture::new("w".into(), 1.0), Err(TextureError::AttributeName("w".into())));
        assert!(MeshAttributeTexture::new("vertex_w".into(), f32::NAN).is_err());
        assert_ne!(
            m.fingerprint_words(),
            Texture::MeshAttribute(MeshAttributeTexture::new("face_v".into(), 2.0).unwrap())
                .fingerprint_words()
        );
    }

    #[test]
    fn set_roughness_sets_the_rough_bsdfs_alphas_only() {
        use crate::bsdf::{Lambert, RoughConductor};
        let mut b = Bsdf::RoughConductor(RoughConductor::new(0.3, Rgb::ONE, None).unwrap());
        assert!(set_roughness(&mut b, ColourSlot::AlphaV, 0.1));
        let Bsdf::RoughConductor(c) = &b else { panic!() };
        assert_eq!((c.microfacet.alpha_u, c.microfacet.alpha_v), (0.3, 0.1));
        assert!(set_roughness(&mut b, ColourSlot::Alpha, 0.2));
        let Bsdf::RoughConductor(c) = &b else { panic!() };
        assert_eq!((c.microfacet.alpha_u, c.microfacet.alpha_v), (0.2, 0.2));
        assert!(!set_roughness(&mut b, ColourSlot::Reflectance, 0.2));
        let mut l = Bsdf::Lambert(Lambert::new(Rgb::ONE).unwrap());
        assert!(!set_roughness(&mut l, ColourSlot::Alpha, 0.2));
        assert!(ColourSlot::Reflectance.is_colour() && !ColourSlot::AlphaU.is_colour());
        assert!(!set_colour(&mut b, ColourSlot::Alpha, Rgb::ONE));
    }
}
