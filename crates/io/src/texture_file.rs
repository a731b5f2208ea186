//! Texture images: PNG, JPEG, Radiance HDR and OpenEXR files read into linear RGB texels for
//! `opticks_core::texture::Bitmap` (Mitsuba's `<texture type="bitmap">`).
//!
//! The size in the file's header is checked before any pixel is decoded, against a limit on
//! the texels ([`MAX_TEXELS`] by default; [`read_texture_within`] and
//! [`crate::scene_formats::LoadLimits::max_texels`] set another, the CLI's `--max-texels`), and
//! the `image` crate's allocation limit is set to the decoded image's size, so a small file
//! claiming a huge image is refused without allocating it. Like Mitsuba, 8- and 16-bit formats
//! (PNG, JPEG) are sRGB-encoded and decoded to linear unless `raw` is set; HDR and EXR hold
//! linear values. Alpha is dropped; grey images give three equal channels. Row 0 is the image's
//! top row.
//!
//! # Memory
//!
//! The texels take 12 bytes each (linear `f32` RGB). While a file is read, the decoder's own
//! copy of the image is held beside them; the peak, measured (maximum resident set of a process
//! reading one 8192 × 8192 image, which includes the file's buffers), is about:
//!
//! | file | bytes a texel at the peak |
//! |---|---|
//! | PNG, JPEG, 8 bits a channel | 15 |
//! | PNG, 16 bits a channel, RGBA | 18 |
//! | Radiance HDR | 24 (the decoded `f32` image and the texels) |
//! | OpenEXR, `half` RGBA | 20 |
//! | OpenEXR, `float` RGB | 24 |
//! | OpenEXR, `float` RGBA | 28 (every channel of the file is read, then the three used) |
//!
//! so an image of the default limit's 2²⁶ texels peaks at 1.0–1.9 GB while it is read and
//! keeps 805 MB.

use crate::image_file::read_exr_pixels;
use crate::input_file;
use opticks_core::math::Rgb;
use std::path::Path;

/// Why a texture image could not be read. Its message does not repeat the file's path: the
/// loader that asked for the texture names the file and the element.
#[derive(Debug, thiserror::Error)]
pub enum TextureError {
    /// The file could not be opened or read.
    #[error("cannot read: {0}")]
    Read(#[from] std::io::Error),
    /// The extension names no supported format.
    #[error("unsupported texture format \".{0}\" (supported: .png, .jpg, .jpeg, .bmp, .hdr, .exr)")]
    Unsupported(String),
    /// An image held in memory is neither PNG nor JPEG.
    #[error("not a PNG or JPEG image")]
    NotPngOrJpeg,
    /// The header gives a width or height of zero.
    #[error("the image is {width} × {height}: it has no texels")]
    Empty {
        /// Columns in the header.
        width: u64,
        /// Rows in the header.
        height: u64,
    },
    /// The header gives more texels than the limit ([`MAX_TEXELS`] by default).
    #[error(
        "the image is {width} × {height} = {} texels, more than the limit of {limit} \
         (--max-texels raises it)",
        .width.saturating_mul(*.height)
    )]
    TooLarge {
        /// Columns in the header.
        width: u64,
        /// Rows in the header.
        height: u64,
        /// The most texels the read allowed.
        limit: u64,
    },
    /// The header (PNG, JPEG, HDR) could not be read.
    #[error("cannot read the image header: {0}")]
    Header(image::ImageError),
    /// The pixels (PNG, JPEG, HDR) could not be decoded.
    #[error("cannot decode: {0}")]
    Decode(image::ImageError),
    /// The EXR header could not be read.
    #[error("cannot read the EXR header: {0}")]
    ExrHeader(exr::error::Error),
    /// The EXR pixels could not be read.
    #[error(transparent)]
    Exr(#[from] crate::image_file::ImageError),
}

/// The most texels a texture may have unless the caller says otherwise
/// ([`crate::scene_formats::LoadLimits::max_texels`]'s default): an 8192 × 8192 image, 805 MB as
/// linear f32 RGB, read at a peak of 15–28 bytes a texel (see the module docs).
pub const MAX_TEXELS: u64 = 1 << 26;

/// A texture image as read: its size and its texels, linear RGB, row-major from the top row.
#[derive(Debug)]
pub struct TextureImage {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width × height` linear RGB texels.
    pub texels: Vec<Rgb>,
}

/// Reads `path` (format by extension: `.png`, `.jpg`/`.jpeg`, `.bmp`, `.hdr`, `.exr`), of at
/// most [`MAX_TEXELS`] texels. With `raw`, 8- and 16-bit values are taken as they are (scaled
/// to [0, 1]) instead of sRGB-decoded (BMP, as Mitsuba reads it, is sRGB-encoded like PNG).
/// The error message does not repeat the path (the caller names it).
pub fn read_texture(path: &Path, raw: bool) -> Result<TextureImage, TextureError> {
    read_texture_within(path, raw, MAX_TEXELS)
}

/// [`read_texture`] with a limit of `max_texels` texels instead of [`MAX_TEXELS`]: a larger
/// image is refused ([`TextureError::TooLarge`]) from its header, before any pixel is decoded.
pub fn read_texture_within(path: &Path, raw: bool, max_texels: u64) -> Result<TextureImage, TextureError> {
    input_file::check_regular(path)?;
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    match ext.as_str() {
        "exr" => read_exr(path, max_texels),
        "png" | "jpg" | "jpeg" | "bmp" | "hdr" => read_with_image(path, raw, ext == "hdr", max_texels),
        _ => Err(TextureError::Unsupported(ext)),
    }
}

/// Whether `path` is a PNG or JPEG image of one grey channel (with or without alpha), read from
/// its header; false for every other file, and for one that cannot be read (its reader says why).
pub fn is_grey(path: &Path) -> bool {
    use image::ImageDecoder;
    let grey = || -> Option<bool> {
        let reader = image::ImageReader::open(path).ok()?.with_guessed_format().ok()?;
        let colour = reader.into_decoder().ok()?.color_type();
        Some(!colour.has_color())
    };
    grey().unwrap_or(false)
}

/// Checks a header's size against `limit` texels.
fn check_size(width: u64, height: u64, limit: u64) -> Result<(), TextureError> {
    if width == 0 || height == 0 {
        return Err(TextureError::Empty { width, height });
    }
    match width.checked_mul(height) {
        Some(n) if n <= limit => Ok(()),
        _ => Err(TextureError::TooLarge { width, height, limit }),
    }
}

fn read_with_image(
    path: &Path,
    raw: bool,
    linear: bool,
    max_texels: u64,
) -> Result<TextureImage, TextureError> {
    let open = || {
        let file = input_file::open(path)?.0;
        Ok(image::ImageReader::new(std::io::BufReader::new(file)).with_guessed_format()?)
    };
    decode_with_image(open, raw, linear, max_texels)
}

/// Decodes a PNG or JPEG image held in memory (a glTF buffer view or `data:` URI), the format
/// guessed from its first bytes, of at most [`MAX_TEXELS`] texels; `raw` as for
/// [`read_texture`]. The header's size is checked before the pixels are decoded, as for files.
pub fn decode_texture(bytes: &[u8], raw: bool) -> Result<TextureImage, TextureError> {
    decode_texture_within(bytes, raw, MAX_TEXELS)
}

/// [`decode_texture`] with a limit of `max_texels` texels instead of [`MAX_TEXELS`].
pub fn decode_texture_within(bytes: &[u8], raw: bool, max_texels: u64) -> Result<TextureImage, TextureError> {
    let open = || {
        let reader = image::ImageReader::new(std::io::Cursor::new(bytes)).with_guessed_format()?;
        match reader.format() {
            Some(image::ImageFormat::Png | image::ImageFormat::Jpeg) => Ok(reader),
            _ => Err(TextureError::NotPngOrJpeg),
        }
    };
    decode_with_image(open, raw, false, max_texels)
}

/// Decodes what `open` gives (called twice: once for the header, once for the pixels) with the
/// size checked in between against `max_texels`; `linear`: the format holds linear values (HDR).
fn decode_with_image<R: std::io::BufRead + std::io::Seek>(
    open: impl Fn() -> Result<image::ImageReader<R>, TextureError>,
    raw: bool,
    linear: bool,
    max_texels: u64,
) -> Result<TextureImage, TextureError> {
    let (w, h) = open()?.into_dimensions().map_err(TextureError::Header)?;
    check_size(w as u64, h as u64, max_texels)?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(w);
    limits.max_image_height = Some(h);
    // The decoded image in the widest form decoded here (f32 RGBA), and some slack.
    limits.max_alloc = Some((w as u64 * h as u64).saturating_mul(16).saturating_add(1 << 20));
    let mut reader = open()?;
    reader.limits(limits);
    let image = reader.decode().map_err(TextureError::Decode)?;
    let (width, height) = (image.width() as usize, image.height() as usize);
    let texels = linear_texels(image, !(raw || linear));
    Ok(TextureImage { width, height, texels })
}

/// The texels of a decoded image as linear RGB (sRGB-decoded if `decode`), converted from its
/// own sample type straight into the texel array: an 8-bit image through a 256-entry table, a
/// 16-bit one per sample, so no full-size f32 copy of the image exists beside the texels (the
/// peak is the decoded image, at most 8 bytes a texel for these, plus the 12-byte texels; it
/// was 12 more). Float images (HDR) are converted to RGB f32 first (a no-op for RGB ones).
fn linear_texels(image: image::DynamicImage, decode: bool) -> Vec<Rgb> {
    use image::DynamicImage as D;
    let to_linear = |v: f32| if decode { srgb_to_linear(v) } else { v };
    match image {
        D::ImageLuma8(_) | D::ImageLumaA8(_) | D::ImageRgb8(_) | D::ImageRgba8(_) => {
            let table: Vec<f32> = (0..=255u8).map(|v| to_linear(v as f32 / 255.0)).collect();
            let rgb = image.into_rgb8();
            rgb.pixels()
                .map(|p| Rgb::new(table[p[0] as usize], table[p[1] as usize], table[p[2] as usize]))
                .collect()
        }
        D::ImageLuma16(_) | D::ImageLumaA16(_) | D::ImageRgb16(_) | D::ImageRgba16(_) => {
            let rgb = image.into_rgb16();
            let f = |v: u16| to_linear(v as f32 / 65535.0);
            rgb.pixels().map(|p| Rgb::new(f(p[0]), f(p[1]), f(p[2]))).collect()
        }
        other => other.into_rgb32f().pixels().map(|p| Rgb::new(p[0], p[1], p[2]).map(to_linear)).collect(),
    }
}

fn read_exr(path: &Path, max_texels: u64) -> Result<TextureImage, TextureError> {
    let file = crate::image_file::open_input(path)?;
    let meta = exr::meta::MetaData::read_from_buffered(std::io::BufReader::new(file), false)
        .map_err(TextureError::ExrHeader)?;
    for header in &meta.headers {
        let s = header.layer_size;
        check_size(s.width() as u64, s.height() as u64, max_texels)?;
    }
    // Straight from the file's channels to the texels (no interleaved f32 copy between them).
    let (w, h, texels) = read_exr_pixels(path, max_texels, Rgb::new)?;
    Ok(TextureImage { width: w as usize, height: h as usize, texels })
}

/// The sRGB electro-optical transfer function: encoded value in [0, 1] → linear.
pub fn srgb_to_linear(v: f32) -> f32 {
    let v = v as f64;
    (if v <= 0.040_45 { v / 12.92 } else { ((v + 0.055) / 1.055).powf(2.4) }) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str, bytes: &[u8]) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("opticks-texture-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, bytes).unwrap();
        p
    }

    #[test]
    fn png_is_srgb_decoded_unless_raw_and_rows_start_at_the_top() {
        let mut img = image::RgbImage::new(2, 2);
        img.put_pixel(0, 0, image::Rgb([255, 0, 0]));
        img.put_pixel(1, 1, image::Rgb([128, 128, 128]));
        let mut bytes = Vec::new();
        img.write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png).unwrap();
        let p = temp("a.png", &bytes);
        let t = read_texture(&p, false).unwrap();
        assert_eq!((t.width, t.height), (2, 2));
        assert_eq!(t.texels[0], Rgb::new(1.0, 0.0, 0.0));
        assert!((t.texels[3].x - 0.2158605).abs() < 1e-5, "{}", t.texels[3]);
        let raw = read_texture(&p, true).unwrap();
        assert!((raw.texels[3].x - 128.0 / 255.0).abs() < 1e-6);
        // The same image as a BMP (Mitsuba's collection has them): the same texels.
        let mut bmp = Vec::new();
        img.write_to(&mut std::io::Cursor::new(&mut bmp), image::ImageFormat::Bmp).unwrap();
        let b = read_texture(&temp("a.bmp", &bmp), false).unwrap();
        assert_eq!((b.width, b.height, b.texels), (t.width, t.height, t.texels));
    }

    #[test]
    fn bad_and_huge_files_are_errors_before_any_allocation() {
        assert!(read_texture(&temp("b.png", b"not a png"), false).is_err());
        assert!(read_texture(&temp("c.tga", b""), false).unwrap_err().to_string().contains("unsupported"));
        // A PNG header claiming 100000 × 100000 pixels, with no data.
        let mut png = b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR".to_vec();
        png.extend(100_000u32.to_be_bytes());
        png.extend(100_000u32.to_be_bytes());
        png.extend([8, 2, 0, 0, 0]);
        let crc = crc32(&png[12..]);
        png.extend(crc.to_be_bytes());
        // The start of an (empty) image data chunk, where a decoder learns the header is done.
        png.extend(b"\0\0\0\0IDAT");
        png.extend(crc32(b"IDAT").to_be_bytes());
        let e = read_texture(&temp("d.png", &png), false).unwrap_err();
        assert!(e.to_string().contains("100000 × 100000"), "{e}");
        assert!(read_texture(Path::new("/nonexistent/e.png"), false).is_err());
    }

    /// CRC-32 (PNG's) of `data`.
    fn crc32(data: &[u8]) -> u32 {
        let mut c = 0xffff_ffffu32;
        for &b in data {
            c ^= b as u32;
            for _ in 0..8 {
                c = if c & 1 != 0 { 0xedb8_8320 ^ (c >> 1) } else { c >> 1 };
            }
        }
        !c
    }
}
