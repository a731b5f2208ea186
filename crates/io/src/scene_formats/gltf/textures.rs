//! glTF textures: the images of a document (PNG or JPEG, in a buffer view, a `data:` URI or a
//! file beside the glTF), decoded once each, and a material's `textureInfo` — its sampler and its
//! `KHR_texture_transform` — as the bitmap parameters of `opticks_core::texture`.
//!
//! | glTF | Opticks |
//! |---|---|
//! | image `bufferView` / `uri` | decoded by [`crate::texture_file::decode_texture_within`] (header size checked first against [`crate::scene_formats::LoadLimits::max_texels`]), sRGB-decoded for colour textures, raw for data textures (metallic-roughness) |
//! | sampler `magFilter` | `NEAREST` → nearest texel; `LINEAR` or none → bilinear. Minification filters and mipmaps are not used (no texture is filtered over a pixel's footprint, as in Mitsuba's `bitmap`) |
//! | sampler `wrapS`, `wrapT` | `REPEAT`, `MIRRORED_REPEAT`, `CLAMP_TO_EDGE` → repeat, mirror, clamp; a sampler with two different modes uses `wrapS` (warning: an Opticks bitmap has one mode) |
//! | `texCoord` (and the transform's override) | which `TEXCOORD_n` set the mesh's UVs are read from |
//! | `KHR_texture_transform` | the affine UV map T·R·S of the extension: (u, v) ↦ (cos r·sₓ·u + sin r·s_y·v + oₓ, −sin r·sₓ·u + cos r·s_y·v + o_y) |
//!
//! The rotation is the one the implementations and Khronos's `TextureTransformTest` sample
//! agree on (Babylon.js, three.js, Blender's importer and exporter): counter-clockwise in glTF's
//! v-down UV space, i.e. rows (cos r, sin r), (−sin r, cos r). The extension's GLSL listing,
//! read column-major, gives the transpose; Khronos's issue KhronosGroup/glTF#1563 and pull
//! request #1624 settle it in favour of the implementations.
//!
//! glTF's UV origin is the image's top-left corner with v growing downwards, which is the
//! convention of the core's bitmaps (row 0 at v = 0): coordinates are used as they are.

use super::buffers::{self, BufferError, ReadError};
use crate::texture_file::{TextureError, TextureImage, decode_texture_within};
use ::gltf::texture::{MagFilter, WrappingMode};
use opticks_core::texture::{FilterType, UvTransform, WrapMode};
use std::collections::HashMap;
use std::path::Path;

/// An image of the document as messages name it: its index, and its name if it has one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ImageName {
    /// The image's index.
    pub index: usize,
    /// Its `name`, if any.
    pub name: Option<String>,
}

impl std::fmt::Display for ImageName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.name {
            Some(n) => write!(f, "image {} ({n:?})", self.index),
            None => write!(f, "image {}", self.index),
        }
    }
}

/// Why an image of the document cannot be had.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// The document has no image of that index.
    #[error("image {index} does not exist (the file has {count})")]
    Missing {
        /// The index asked for.
        index: usize,
        /// The document's image count.
        count: usize,
    },
    /// The image's `bufferView` does not exist.
    #[error("{image}: buffer view {view} does not exist")]
    MissingView {
        /// The image.
        image: ImageName,
        /// The buffer view it names.
        view: usize,
    },
    /// The image's buffer view cannot be read.
    #[error("{image}: {error}")]
    View {
        /// The image.
        image: ImageName,
        /// Why.
        error: ReadError,
    },
    /// The image's file cannot be read.
    #[error("{image}: cannot read image file {}: {error}", path.display())]
    File {
        /// The image.
        image: ImageName,
        /// The file as resolved.
        path: std::path::PathBuf,
        /// The operating system's reason.
        error: std::io::Error,
    },
    /// The image's `uri` cannot be resolved to data (a bad URI or `data:` payload).
    #[error("{image}: {error}")]
    Uri {
        /// The image.
        image: ImageName,
        /// What is wrong with the URI (never [`BufferError::File`], which is [`ImageError::File`]).
        error: BufferError,
    },
    /// The image has neither a `bufferView` nor a `uri`.
    #[error("{image} has neither a bufferView nor a uri")]
    NoData {
        /// The image.
        image: ImageName,
    },
    /// The image's bytes do not decode (or are too large).
    #[error("{image}: {error}")]
    Decode {
        /// The image.
        image: ImageName,
        /// Why.
        error: TextureError,
    },
}

/// The decoded images of a document, by (image index, raw).
pub struct Images<'a> {
    doc: &'a ::gltf::Document,
    buffers: &'a [Vec<u8>],
    folder: &'a Path,
    /// The most texels an image may have ([`crate::scene_formats::LoadLimits::max_texels`]).
    max_texels: u64,
    decoded: HashMap<(usize, bool), std::sync::Arc<TextureImage>>,
}

/// How a material samples one texture: the image, the UV set, the UV transform, the sampler.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureUse {
    /// Index of the image.
    pub image: usize,
    /// The `TEXCOORD_n` set.
    pub tex_coord: u32,
    /// `KHR_texture_transform`, or the identity.
    pub to_uv: UvTransform,
    /// The sampler's magnification filter.
    pub filter: FilterType,
    /// The sampler's wrap mode (`wrapS`).
    pub wrap: WrapMode,
}

impl TextureUse {
    /// The use of `info`'s texture; a note when the sampler's two wrap modes differ.
    pub fn of(info: &::gltf::texture::Info<'_>, notes: &mut Vec<String>, what: &str) -> TextureUse {
        let texture = info.texture();
        let sampler = texture.sampler();
        let filter = match sampler.mag_filter() {
            Some(MagFilter::Nearest) => FilterType::Nearest,
            Some(MagFilter::Linear) | None => FilterType::Bilinear,
        };
        let wrap_of = |m: WrappingMode| match m {
            WrappingMode::Repeat => WrapMode::Repeat,
            WrappingMode::MirroredRepeat => WrapMode::Mirror,
            WrappingMode::ClampToEdge => WrapMode::Clamp,
        };
        if sampler.wrap_s() != sampler.wrap_t() {
            notes.push(format!(
                "{what}: wrapS {:?} and wrapT {:?} differ; {:?} is used for both",
                sampler.wrap_s(),
                sampler.wrap_t(),
                sampler.wrap_s()
            ));
        }
        let (to_uv, tex_coord) = match info.texture_transform() {
            Some(t) => {
                (uv_transform(t.offset(), t.rotation(), t.scale()), t.tex_coord().unwrap_or(info.tex_coord()))
            }
            None => (UvTransform::IDENTITY, info.tex_coord()),
        };
        TextureUse {
            image: texture.source().index(),
            tex_coord,
            to_uv,
            filter,
            wrap: wrap_of(sampler.wrap_s()),
        }
    }
}

/// `KHR_texture_transform`'s matrix T(offset)·R(rotation)·S(scale) as a UV map.
pub fn uv_transform(offset: [f32; 2], rotation: f32, scale: [f32; 2]) -> UvTransform {
    let (s, c) = rotation.sin_cos();
    UvTransform([[c * scale[0], s * scale[1], offset[0]], [-s * scale[0], c * scale[1], offset[1]]])
}

impl<'a> Images<'a> {
    /// The images of `doc`, whose buffers are `buffers` and whose files are in `folder`, each
    /// of at most `max_texels` texels.
    pub fn new(doc: &'a ::gltf::Document, buffers: &'a [Vec<u8>], folder: &'a Path, max_texels: u64) -> Self {
        Images { doc, buffers, folder, max_texels, decoded: HashMap::new() }
    }

    /// Image `index`, decoded (sRGB to linear unless `raw`); the error names the image and,
    /// for a file, its path.
    pub fn get(&mut self, index: usize, raw: bool) -> Result<std::sync::Arc<TextureImage>, ImageError> {
        if let Some(t) = self.decoded.get(&(index, raw)) {
            return Ok(t.clone());
        }
        let json = self
            .doc
            .as_json()
            .images
            .get(index)
            .ok_or_else(|| ImageError::Missing { index, count: self.doc.images().len() })?;
        let name = || ImageName { index, name: json.name.clone() };
        let bytes: std::borrow::Cow<'_, [u8]> = match (&json.buffer_view, &json.uri) {
            (Some(view), _) => {
                let view = self
                    .doc
                    .views()
                    .nth(view.value())
                    .ok_or_else(|| ImageError::MissingView { image: name(), view: view.value() })?;
                buffers::view_bytes(&view, self.buffers)
                    .map_err(|error| ImageError::View { image: name(), error })?
                    .into()
            }
            (None, Some(uri)) => buffers::read_uri(uri, self.folder)
                .map_err(|e| match e {
                    BufferError::File { path, source } => {
                        ImageError::File { image: name(), path, error: source }
                    }
                    error => ImageError::Uri { image: name(), error },
                })?
                .into(),
            (None, None) => return Err(ImageError::NoData { image: name() }),
        };
        let image = decode_texture_within(&bytes, raw, self.max_texels)
            .map_err(|error| ImageError::Decode { image: name(), error })?;
        let image = std::sync::Arc::new(image);
        self.decoded.insert((index, raw), image.clone());
        Ok(image)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use opticks_core::math::Vec2;

    #[test]
    fn texture_transform_is_translation_rotation_scale() {
        // The extension's example: offset (0, 1), rotation π/2, scale (0.5, 0.5).
        let t = uv_transform([0.0, 1.0], std::f32::consts::FRAC_PI_2, [0.5, 0.5]);
        // S: (1, 0) → (0.5, 0); R (rows (cos, sin), (−sin, cos)): → (0, −0.5); T: → (0, 0.5).
        let p = t.apply(Vec2::new(1.0, 0.0));
        assert!((p - Vec2::new(0.0, 0.5)).length() < 1e-6, "{p}");
        let q = t.apply(Vec2::new(0.0, 1.0));
        assert!((q - Vec2::new(0.5, 1.0)).length() < 1e-6, "{q}");
        assert_eq!(uv_transform([0.0, 0.0], 0.0, [1.0, 1.0]), UvTransform::IDENTITY);
    }
}
