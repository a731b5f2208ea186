//! Image files: writing a rendered RGB film to OpenEXR (linear radiance) or PNG (8-bit sRGB for
//! eyes), and reading the RGB channels of an OpenEXR file (our own output or Mitsuba's
//! references).
//!
//! Pixel buffers are interleaved RGB `f32`, row-major, row 0 at the top, `width * height * 3`
//! values (what [`opticks_core::film::Film::to_rgb_f32`] returns).
//!
//! Writes are atomic: the image is written to a temporary file in the destination directory and
//! renamed over the destination only once it is complete, so a reader never sees a half-written
//! image and a failed write leaves nothing behind. A run killed outright (SIGKILL, a power cut)
//! can still leave its temporary file `.NAME.tmp-PID-N`; the next write of `NAME` removes those
//! whose process no longer exists and returns them, for the command to report. A buffer holding a NaN or infinite value is
//! refused (the error names the first bad pixel) rather than written as a silently wrong image.

use std::fs::{self, File};
use std::io::{BufWriter, Seek, Write};
use std::path::{Path, PathBuf};

use exr::prelude::{
    Blocks, Encoding, FlatSamples, Image, Layer, LayerAttributes, LineOrder, SpecificChannels, Vec2,
    WritableImage,
};

/// The most samples (pixels × channels, over all its layers) [`read_exr_rgb`] reads from a file:
/// an RGBA image of [`MAX_TEXELS`](crate::texture_file::MAX_TEXELS) pixels (1 GiB as `f32`).
/// A texture read with a raised limit of N texels allows 4 N samples.
pub const MAX_EXR_SAMPLES: u64 = 4 * crate::texture_file::MAX_TEXELS;

/// Extensions [`write_image`] understands (lower case, without the dot).
pub const SUPPORTED_EXTENSIONS: &[&str] = &["exr", "png"];

/// Errors of image reading and writing. Every variant names the file concerned.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// The extension selects no supported format.
    #[error("{}: unsupported image format {ext:?} (supported extensions: .exr, .png)", .path.display())]
    UnsupportedFormat {
        /// The file.
        path: PathBuf,
        /// Its extension (empty if none).
        ext: String,
    },
    /// The pixel buffer does not hold `width * height * 3` values, or the size is zero.
    #[error(
        "{}: pixel buffer has {len} values, expected {width} x {height} x 3 = {expected}",
        .path.display()
    )]
    BadSize {
        /// The file.
        path: PathBuf,
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
        /// Length of the buffer passed.
        len: usize,
        /// `width * height * 3`.
        expected: usize,
    },
    /// A pixel value is NaN or infinite; nothing was written.
    #[error(
        "{}: non-finite value {value} at pixel (x {x}, y {y}) channel {channel} (0 = R, 1 = G, 2 = B); \
         image not written",
        .path.display()
    )]
    NonFinite {
        /// The file.
        path: PathBuf,
        /// Column of the first bad pixel.
        x: u32,
        /// Row of the first bad pixel (0 = top).
        y: u32,
        /// Channel index, 0 = R, 1 = G, 2 = B.
        channel: usize,
        /// The offending value.
        value: f32,
    },
    /// The exposure passed to a PNG write is not finite.
    #[error("{}: exposure {exposure_stops} stops is not finite", .path.display())]
    BadExposure {
        /// The file.
        path: PathBuf,
        /// The exposure passed.
        exposure_stops: f32,
    },
    /// Creating, writing, renaming or reading the file failed.
    #[error("{}: {source}", .path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The OpenEXR encoder or decoder failed (including a file that is not a valid EXR).
    #[error("{}: OpenEXR: {source}", .path.display())]
    Exr {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: exr::error::Error,
    },
    /// The PNG encoder failed.
    #[error("{}: PNG: {source}", .path.display())]
    Png {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: image::ImageError,
    },
    /// The file would replace one the run reads (a texture, an environment map, ...).
    #[error(transparent)]
    ReplacesInput(#[from] crate::output_paths::OutputError),
    /// The EXR file is readable but holds nothing usable as an RGB image.
    #[error("{}: {message}", .path.display())]
    Content {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

/// Writes an RGB image, choosing the format by the (case-insensitive) extension of `path`:
///
/// * `.exr`: OpenEXR, linear float32 `R`, `G`, `B` channels, RLE compression, scanlines,
///   encoded on the calling thread. Not ZIP: a rendered float image hardly compresses (its low
///   mantissa bits are noise), so ZIP (16 lines) saved 4–10 % of the file (a 512 × 512 render:
///   2.83 MB against RLE's 2.90 MB and 3.15 MB raw; converged references 4–6 %) for 10–25 × the
///   time (80 ms of two threads against 7 ms, about a quarter of a 512 × 512 light-estimator
///   frame; the `exr` crate's parallel writer also started a thread pool of its own, ignoring
///   `--threads`). RLE still shrinks black backgrounds and masks; every OpenEXR reader reads it. The values are written as they are, bit for bit: **`exposure_stops` is ignored**
///   (an EXR holds radiance).
/// * `.png`: 8-bit sRGB: each value is multiplied by `2^exposure_stops`, clamped to [0, 1],
///   encoded with the sRGB transfer function (OETF) and rounded to the nearest of 0..=255.
///
/// `rgb` holds `width * height` interleaved RGB triples, row 0 at the top. Any other extension,
/// a wrong buffer size, or a NaN/infinite value anywhere (the error names the first such pixel)
/// is an error, and then nothing is written. The write is atomic: a temporary file in the same
/// directory is written, then renamed to `path` (replacing an existing file); the temporary file
/// is removed if anything fails.
///
/// Returns the stale temporary files of killed runs it removed (see [`write_files_atomically`]).
pub fn write_image(
    path: &Path,
    width: u32,
    height: u32,
    rgb: &[f32],
    exposure_stops: f32,
) -> Result<Vec<(PathBuf, u64)>, ImageError> {
    let bytes = encode_image(path, width, height, rgb, exposure_stops)?;
    write_files_atomically(&[(path, &bytes)])
}

/// The bytes [`write_image`] would write to `path` (same format, exposure and checks), for a
/// command that writes several files all or none ([`write_files_atomically`]).
pub fn encode_image(
    path: &Path,
    width: u32,
    height: u32,
    rgb: &[f32],
    exposure_stops: f32,
) -> Result<Vec<u8>, ImageError> {
    let format = output_format(path)?;
    check_pixels(path, width, height, rgb)?;
    let mut out = std::io::Cursor::new(Vec::new());
    match format {
        Format::Exr => write_exr_to(&mut out, path, width, height, rgb)?,
        Format::Png => {
            if !exposure_stops.is_finite() {
                return Err(ImageError::BadExposure { path: path.to_path_buf(), exposure_stops });
            }
            let bytes = srgb8_from_linear(rgb, exposure_stops);
            write_png_to(&mut out, path, width, height, &bytes)?;
        }
    }
    Ok(out.into_inner())
}

/// The format [`write_image`] would write to `path`, chosen by its extension; an error for an
/// unsupported one. Commands call it before long work, so a typo in `-o` costs nothing.
pub fn check_output_path(path: &Path) -> Result<(), ImageError> {
    output_format(path).map(|_| ())
}

fn output_format(path: &Path) -> Result<Format, ImageError> {
    let ext = path.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
    match ext.as_str() {
        "exr" => Ok(Format::Exr),
        "png" => Ok(Format::Png),
        _ => Err(ImageError::UnsupportedFormat { path: path.to_path_buf(), ext }),
    }
}

/// Reads the RGB channels of an OpenEXR file: returns `(width, height, rgb)` with `rgb` holding
/// `width * height` interleaved RGB triples (row 0 at the top), as `f32`.
///
/// Channels are chosen like the project's `imgcmp.py`: `R`, `G`, `B` (case-insensitive, any
/// layer prefix such as `diffuse.R` ignored) if present, else a single luminance `Y` channel
/// copied to all three, else a single channel of any name copied to all three. Alpha and other
/// extra channels are dropped. Half, float and uint samples and every compression the `exr`
/// crate supports (incl. the ZIP float32 files Mitsuba writes) are read; for a multi-layer file
/// the first layer with usable channels is taken, at its largest resolution level.
///
/// The sizes in the header are checked before any pixel is read (the `exr` crate allocates
/// every channel of every layer at the size its header gives): a layer of more than
/// [`MAX_TEXELS`](crate::texture_file::MAX_TEXELS) pixels, or more than [`MAX_EXR_SAMPLES`]
/// samples in all, is an error, so a small file claiming a huge image allocates nothing.
pub fn read_exr_rgb(path: &Path) -> Result<(u32, u32, Vec<f32>), ImageError> {
    let (w, h, rgb) = read_exr_pixels(path, crate::texture_file::MAX_TEXELS, |r, g, b| [r, g, b])?;
    Ok((w, h, rgb.into_flattened()))
}

/// [`read_exr_rgb`] with layers of at most `max_pixels` pixels (and `4 * max_pixels` samples in
/// all), each pixel made by `pixel` from its R, G, B values: the pixels are built straight from
/// the file's channels, with no copy between them.
pub(crate) fn read_exr_pixels<T>(
    path: &Path,
    max_pixels: u64,
    pixel: impl Fn(f32, f32, f32) -> T,
) -> Result<(u32, u32, Vec<T>), ImageError> {
    use exr::prelude::{ReadChannels, ReadLayers};
    let max_samples = max_pixels.saturating_mul(4);
    let content_err = |message: String| ImageError::Content { path: path.to_path_buf(), message };
    let meta = exr::meta::MetaData::read_from_buffered(std::io::BufReader::new(open_input(path)?), false)
        .map_err(|source| exr_error(path, source))?;
    let mut samples = 0u64;
    for header in &meta.headers {
        let (w, h) = (header.layer_size.width() as u64, header.layer_size.height() as u64);
        let pixels = w.saturating_mul(h);
        if pixels > max_pixels {
            return Err(content_err(format!(
                "EXR layer of {w} x {h} pixels: more than the {max_pixels} an image read may have"
            )));
        }
        samples = samples.saturating_add(pixels.saturating_mul(header.channels.list.len() as u64));
        if samples > max_samples {
            return Err(content_err(format!(
                "EXR layers of more than {max_samples} samples (pixels x channels) in all: \
                 more than an image read may hold"
            )));
        }
    }
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_buffered(std::io::BufReader::new(open_input(path)?))
        .map_err(|source| exr_error(path, source))?;

    for layer in &image.layer_data {
        let channels = &layer.channel_data.list;
        let find = |name: &str| {
            channels.iter().find(|c| {
                let full = c.name.to_string();
                full.rsplit('.').next().unwrap_or("").eq_ignore_ascii_case(name)
            })
        };
        let picked: [&FlatSamples; 3] = match (find("R"), find("G"), find("B"), find("Y")) {
            (Some(r), Some(g), Some(b), _) => [&r.sample_data, &g.sample_data, &b.sample_data],
            (_, _, _, Some(y)) => [&y.sample_data; 3],
            _ if channels.len() == 1 => [&channels[0].sample_data; 3],
            _ => continue,
        };
        let (w, h) = (layer.size.width(), layer.size.height());
        let n = w * h;
        if n == 0 {
            return Err(content_err("EXR layer has no pixels".into()));
        }
        if picked.iter().any(|s| s.len() != n) {
            return Err(content_err(format!(
                "EXR channels hold fewer samples than {w} x {h} (subsampled channels are not supported)"
            )));
        }
        let width = u32::try_from(w).map_err(|_| content_err(format!("EXR width {w} too large")))?;
        let height = u32::try_from(h).map_err(|_| content_err(format!("EXR height {h} too large")))?;
        let [r, g, b] = picked;
        let value = |s: &FlatSamples, i: usize| s.value_by_flat_index(i).to_f32();
        let pixels = (0..n).map(|i| pixel(value(r, i), value(g, i), value(b, i))).collect();
        return Ok((width, height, pixels));
    }
    let names: Vec<String> = image
        .layer_data
        .iter()
        .flat_map(|l| l.channel_data.list.iter().map(|c| c.name.to_string()))
        .collect();
    Err(content_err(format!("EXR has no R, G, B or Y channels (channels: {})", names.join(", "))))
}

/// The sRGB transfer function (OETF): linear value in [0, 1] -> encoded value in [0, 1].
/// Values outside [0, 1] are clamped first.
pub fn srgb_oetf(linear: f32) -> f32 {
    let x = linear.clamp(0.0, 1.0) as f64;
    let v = if x <= 0.003_130_8 { 12.92 * x } else { 1.055 * x.powf(1.0 / 2.4) - 0.055 };
    v as f32
}

enum Format {
    Exr,
    Png,
}

/// Opens an image to read through [`crate::input_file`] (regular files only, and remembered as
/// an input of the run).
pub(crate) fn open_input(path: &Path) -> Result<File, ImageError> {
    crate::input_file::open(path)
        .map(|(file, _)| file)
        .map_err(|source| ImageError::Io { path: path.to_path_buf(), source })
}

fn exr_error(path: &Path, source: exr::error::Error) -> ImageError {
    match source {
        exr::error::Error::Io(source) => ImageError::Io { path: path.to_path_buf(), source },
        source => ImageError::Exr { path: path.to_path_buf(), source },
    }
}

/// Checks the buffer size and that every value is finite.
fn check_pixels(path: &Path, width: u32, height: u32, rgb: &[f32]) -> Result<(), ImageError> {
    let expected = width as usize * height as usize * 3;
    if rgb.len() != expected || expected == 0 {
        return Err(ImageError::BadSize {
            path: path.to_path_buf(),
            width,
            height,
            len: rgb.len(),
            expected,
        });
    }
    if let Some(i) = rgb.iter().position(|v| !v.is_finite()) {
        let pixel = i / 3;
        return Err(ImageError::NonFinite {
            path: path.to_path_buf(),
            x: (pixel % width as usize) as u32,
            y: (pixel / width as usize) as u32,
            channel: i % 3,
            value: rgb[i],
        });
    }
    Ok(())
}

/// Linear RGB -> 8-bit sRGB bytes, after scaling by `2^exposure_stops`.
fn srgb8_from_linear(rgb: &[f32], exposure_stops: f32) -> Vec<u8> {
    let scale = 2f64.powf(exposure_stops as f64) as f32;
    rgb.iter().map(|&v| (srgb_oetf(v * scale) * 255.0).round() as u8).collect()
}

fn write_exr_to(
    file: &mut (impl Write + Seek),
    path: &Path,
    width: u32,
    height: u32,
    rgb: &[f32],
) -> Result<(), ImageError> {
    let w = width as usize;
    let channels = SpecificChannels::rgb(|pos: Vec2<usize>| {
        let i = (pos.y() * w + pos.x()) * 3;
        (rgb[i], rgb[i + 1], rgb[i + 2])
    });
    let encoding = Encoding {
        compression: exr::compression::Compression::RLE,
        blocks: Blocks::ScanLines,
        line_order: LineOrder::Increasing,
    };
    let layer = Layer::new((w, height as usize), LayerAttributes::default(), encoding, channels);
    Image::from_layer(layer)
        .write()
        .non_parallel()
        .to_buffered(file)
        .map_err(|source| exr_error(path, source))
}

fn write_png_to(
    file: &mut impl Write,
    path: &Path,
    width: u32,
    height: u32,
    bytes: &[u8],
) -> Result<(), ImageError> {
    use image::ImageEncoder;
    image::codecs::png::PngEncoder::new(file)
        .write_image(bytes, width, height, image::ExtendedColorType::Rgb8)
        .map_err(|source| ImageError::Png { path: path.to_path_buf(), source })
}

/// Writes several files all or none: each into its temporary file first, and only when every
/// one is complete are they renamed into place (so `measure -o x.csv --png y.png` never leaves
/// one written and the other not because of a write error). None may be a file the run has read
/// ([`crate::output_paths::spares_what_was_read`]): then nothing is written.
///
/// Before writing, the temporary files `.NAME.tmp-PID-N` that killed runs left beside each
/// destination `NAME` are removed, and returned with their sizes: only those whose process no
/// longer exists (so a concurrent writer's file is never touched; on systems without `/proc`
/// none are).
pub fn write_files_atomically(files: &[(&Path, &[u8])]) -> Result<Vec<(PathBuf, u64)>, ImageError> {
    for &(path, _) in files {
        crate::output_paths::spares_what_was_read(path)?;
    }
    let mut removed = Vec::new();
    for &(path, _) in files {
        removed.extend(remove_stale_temporaries(path));
    }
    let mut done: Vec<(PathBuf, &Path)> = Vec::new();
    for &(path, bytes) in files {
        let written = write_temporary(path, |file| {
            file.write_all(bytes).map_err(|source| ImageError::Io { path: path.to_path_buf(), source })
        });
        match written {
            Ok(tmp) => done.push((tmp, path)),
            Err(e) => {
                done.iter().for_each(|(tmp, _)| drop(fs::remove_file(tmp)));
                return Err(e);
            }
        }
    }
    for (i, (tmp, path)) in done.iter().enumerate() {
        if let Err(source) = fs::rename(tmp, path) {
            done[i..].iter().for_each(|(tmp, _)| drop(fs::remove_file(tmp)));
            return Err(ImageError::Io { path: path.to_path_buf(), source });
        }
    }
    Ok(removed)
}

/// Removes `dir/.NAME.tmp-PID-N` beside `path` = `dir/NAME` whose process `PID` is not running
/// (it was killed before it could clean up), returning each removed file with its size.
fn remove_stale_temporaries(path: &Path) -> Vec<(PathBuf, u64)> {
    let proc_fs = Path::new("/proc/self").exists();
    let (Some(name), true) = (path.file_name(), proc_fs) else { return Vec::new() };
    let prefix = format!(".{}.tmp-", name.to_string_lossy());
    let Ok(entries) = fs::read_dir(crate::output_paths::folder_of(path)) else { return Vec::new() };
    let mut removed = Vec::new();
    for entry in entries.flatten() {
        let file_name = entry.file_name().to_string_lossy().into_owned();
        let Some(rest) = file_name.strip_prefix(&prefix) else { continue };
        let Some((pid, n)) = rest.split_once('-') else { continue };
        let (Ok(pid), true) = (pid.parse::<u32>(), n.bytes().all(|b| b.is_ascii_digit())) else { continue };
        if pid == std::process::id() || Path::new(&format!("/proc/{pid}")).exists() {
            continue; // a live writer's (or ours)
        }
        let bytes = entry.metadata().map(|m| m.len()).unwrap_or(0);
        if fs::remove_file(entry.path()).is_ok() {
            removed.push((entry.path(), bytes));
        }
    }
    removed
}

/// A complete, synced temporary file next to `path` holding what `write` wrote, not yet renamed
/// (the first half of [`write_files_atomically`]).
fn write_temporary(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<(), ImageError>,
) -> Result<PathBuf, ImageError> {
    let io_err = |p: &Path, source| ImageError::Io { path: p.to_path_buf(), source };
    let (tmp, file) = crate::output_paths::create_temporary(path).map_err(|e| io_err(path, e))?;

    let result = (|| {
        let mut writer = BufWriter::new(file);
        write(&mut writer)?;
        writer.flush().map_err(|e| io_err(path, e))?;
        let file = writer.into_inner().map_err(|e| io_err(path, e.into_error()))?;
        file.sync_all().map_err(|e| io_err(path, e))
    })();
    match result {
        Ok(()) => Ok(tmp),
        Err(e) => {
            let _ = fs::remove_file(&tmp);
            Err(e)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_oetf_known_values() {
        assert_eq!(srgb_oetf(0.0), 0.0);
        assert_eq!(srgb_oetf(1.0), 1.0);
        assert_eq!(srgb_oetf(-3.0), 0.0);
        assert_eq!(srgb_oetf(7.0), 1.0);
        assert!((srgb_oetf(0.5) - 0.735_356_7).abs() < 1e-6);
        assert!((srgb_oetf(0.002) - 0.02584).abs() < 1e-6);
        assert_eq!(srgb8_from_linear(&[0.0, 1.0, 0.5, 0.25], 0.0), vec![0, 255, 188, 137]);
        assert_eq!(srgb8_from_linear(&[0.25], 1.0), vec![188]);
    }

    #[test]
    fn a_killed_writers_temporary_file_is_removed_by_the_next_write() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        // A process that has exited: its pid names no live process (until reused, when the
        // file is merely left alone).
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let dead = child.id();
        child.wait().unwrap();
        let stale = d.join(format!(".x.png.tmp-{dead}-0"));
        let live = d.join(format!(".x.png.tmp-{}-7", std::process::id()));
        let other = d.join(format!(".y.png.tmp-{dead}-0"));
        for f in [&stale, &live, &other] {
            std::fs::write(f, b"half an image").unwrap();
        }
        let removed = write_files_atomically(&[(&d.join("x.png"), b"png")]).unwrap();
        assert_eq!(removed, vec![(stale.clone(), 13)]);
        assert!(!stale.exists() && live.exists() && other.exists());
        assert_eq!(std::fs::read(d.join("x.png")).unwrap(), b"png");
    }

    #[test]
    fn several_files_are_written_all_or_none() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::write(d.join("a.csv"), b"old").unwrap();
        let e = write_files_atomically(&[(&d.join("a.csv"), b"new"), (&d.join("nodir/b.png"), b"png")]);
        assert!(e.is_err());
        assert_eq!(std::fs::read(d.join("a.csv")).unwrap(), b"old", "the first is not replaced either");
        assert_eq!(std::fs::read_dir(d).unwrap().count(), 1, "no temporary file is left");
        write_files_atomically(&[(&d.join("a.csv"), b"new"), (&d.join("b.png"), b"png")]).unwrap();
        assert_eq!(
            (std::fs::read(d.join("a.csv")).unwrap(), std::fs::read(d.join("b.png")).unwrap()),
            (b"new".to_vec(), b"png".to_vec())
        );
    }
}
