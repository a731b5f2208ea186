//! The ideal pinhole camera ([`Pinhole`], built from a scene's [`CameraDesc`]) and its
//! connection.
//!
//! Importance: the pinhole reads, for pixel j, the radiance at the eye averaged over the pixel's
//! square (area a) on the image plane at unit distance. A film area dA maps to the solid angle
//! dω = cos³θ_c·dA, so W_e = 1/(a·cos³θ_c) per unit solid angle, and a point x at distance d
//! subtends dω = |cos θ_x|·dA_x/d²: W = 1/(d²·a·cos³θ_c).

use super::raster::NO_PIXEL;
use super::{BLOCK, Connection, FilmHit, ProjectedBlock, Raster};
use crate::dataset::Sample;
use crate::math::Vec3;
use crate::scene::CameraDesc;

/// An ideal pinhole camera with its image plane at unit distance (see `scenes/README.md`):
/// film point (sx, sy) ∈ \[0,1\]², sy downward, looks along
/// `f + (2sx−1)·tan(fov_x/2)·right + (1−2sy)·tan(fov_y/2)·up`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pinhole {
    /// Centre of projection.
    pub eye: Vec3,
    /// Unit view direction.
    pub forward: Vec3,
    /// Unit image-right direction.
    pub right: Vec3,
    /// Unit image-up direction.
    pub up: Vec3,
    /// tan(fov_x / 2).
    pub tan_x: f32,
    /// tan(fov_y / 2) = tan_x · H / W.
    pub tan_y: f32,
    /// Width in pixels of the full film (the projection's; the image is the raster's window).
    pub width: u32,
    /// Height in pixels of the full film.
    pub height: u32,
    /// The pixels written and the reconstruction filter.
    pub raster: Raster,
}

/// Why a camera cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CameraError {
    /// Eye, target or up are NaN/infinite, or eye == target, or up ∥ view direction.
    #[error(
        "degenerate camera orientation (eye, target and up must be finite, eye ≠ target, up not parallel to the view)"
    )]
    Orientation,
    /// Field of view outside (0°, 180°).
    #[error("field of view {0}° is outside (0°, 180°)")]
    FieldOfView(f32),
    /// An image side of zero or beyond [`MAX_IMAGE_SIDE`].
    #[error("image size {0}x{1} must be between 1x1 and 32768x32768")]
    Size(u32, u32),
    /// An orthographic film whose width or height (metres) is not a finite number > 0.
    #[error("orthographic film of {0} × {1} m: each side must be a finite number > 0")]
    FilmExtent(f32, f32),
    /// A crop window that is empty or leaves the film.
    #[error(
        "crop window of {}x{} pixels at ({}, {}) must be at least 1x1 and lie within the {width}x{height} film",
        crop.width, crop.height, crop.x, crop.y
    )]
    Crop {
        /// The window.
        crop: super::Crop,
        /// The film's width.
        width: u32,
        /// The film's height.
        height: u32,
    },
    /// A reconstruction filter Opticks cannot use (or a camera that takes only the box).
    #[error("{0}")]
    Filter(String),
    /// A thin lens's aperture or focus distance.
    #[error(transparent)]
    Lens(#[from] super::LensError),
}

/// A full field-of-view angle (degrees) a perspective camera can have: in (0°, 180°). Public so
/// that scene readers apply this one rule to the angle as the file gives it (along any axis).
pub fn check_fov(degrees: f32) -> Result<(), CameraError> {
    if degrees > 0.0 && degrees < 180.0 { Ok(()) } else { Err(CameraError::FieldOfView(degrees)) }
}

/// The largest image side any camera may have (a 32768² film is 25.8 GB of f64 sums; whether
/// a size fits the machine's memory is checked before rendering, see
/// [`crate::film::accumulation_bytes`]).
pub const MAX_IMAGE_SIDE: u32 = 32768;

/// An image size a camera can have: each side from 1 to [`MAX_IMAGE_SIDE`]. Public so that
/// every reader of image sizes (scene files, camera paths, the command line) applies this one
/// rule before anything is allocated from them.
pub fn check_image_size(width: u32, height: u32) -> Result<(), CameraError> {
    let ok = |s: u32| (1..=MAX_IMAGE_SIDE).contains(&s);
    if ok(width) && ok(height) { Ok(()) } else { Err(CameraError::Size(width, height)) }
}

impl Pinhole {
    /// Validates a description into a pinhole camera.
    pub fn new(d: &CameraDesc) -> Result<Self, CameraError> {
        check_image_size(d.width, d.height)?;
        check_fov(d.fov_x_degrees)?;
        let forward = (d.target - d.eye).normalize_or_zero();
        let right = forward.cross(d.up).normalize_or_zero();
        if !d.eye.is_finite() || forward == Vec3::ZERO || right == Vec3::ZERO || !right.is_finite() {
            return Err(CameraError::Orientation);
        }
        let up = right.cross(forward);
        let tan_x = (d.fov_x_degrees.to_radians() * 0.5).tan();
        let tan_y = tan_x * d.height as f32 / d.width as f32;
        let raster = Raster::new(d.width, d.height, d.film)?;
        Ok(Pinhole { eye: d.eye, forward, right, up, tan_x, tan_y, width: d.width, height: d.height, raster })
    }

    /// Area of one pixel on the image plane at unit distance.
    #[inline]
    pub fn pixel_area(&self) -> f32 {
        (2.0 * self.tan_x / self.width as f32) * (2.0 * self.tan_y / self.height as f32)
    }

    /// Projects a world point. Returns the image pixel index (row-major in the raster's window,
    /// row 0 on top) and cos θ_c (between the camera axis and the direction to the point), or
    /// `None` when the point is behind the camera or outside the image.
    #[inline]
    pub fn project(&self, p: Vec3) -> Option<(usize, f32)> {
        let v = p - self.eye;
        let z = v.dot(self.forward);
        if z <= 0.0 {
            return None;
        }
        let (sx, sy) = self.film_xy(v, z);
        // cos θ_c only for points in the image (most splats' points are not).
        let pixel = self.raster.box_pixel(sx, sy)?;
        Some((pixel, z / v.length()))
    }

    /// Film coordinates of the offset `v` from the eye at depth `z` > 0 along the axis.
    #[inline]
    fn film_xy(&self, v: Vec3, z: f32) -> (f32, f32) {
        let x = v.dot(self.right) / (z * self.tan_x); // in [-1, 1] across the image
        let y = v.dot(self.up) / (z * self.tan_y);
        (0.5 * (x + 1.0), 0.5 * (1.0 - y))
    }

    /// The full film's coordinates (s_x, s_y) of a world point, within the film or beyond it,
    /// and cos θ_c; `None` behind the camera.
    #[inline]
    pub fn film_of(&self, p: Vec3) -> Option<(f32, f32, f32)> {
        let v = p - self.eye;
        let z = v.dot(self.forward);
        if z <= 0.0 {
            return None;
        }
        let (sx, sy) = self.film_xy(v, z);
        Some((sx, sy, z / v.length()))
    }

    /// The primary ray direction through film point (sx, sy) (for tests and path tracers).
    pub fn direction(&self, sx: f32, sy: f32) -> Vec3 {
        (self.forward + (2.0 * sx - 1.0) * self.tan_x * self.right + (1.0 - 2.0 * sy) * self.tan_y * self.up)
            .normalize()
    }
}

impl Pinhole {
    /// Connects `x` to the pinhole at the eye.
    #[inline]
    pub(super) fn connect(&self, x: Vec3) -> Option<Connection> {
        let (pixel, weight) = self.connection_of(x, self.pixel_area());
        (pixel != NO_PIXEL).then_some(Connection { pixel: pixel as usize, point: self.eye, weight })
    }

    /// [`Pinhole::connect`] of the positions of up to [`BLOCK`] samples at once (`pixel[l]` is
    /// [`NO_PIXEL`] where it gives `None`): the same arithmetic lane by lane
    /// ([`Pinhole::connection_of`]), but without a branch or an `Option` per sample, in arrays
    /// the compiler keeps in vector registers (the splat loop's projection was a fifth of its
    /// instructions).
    #[inline]
    pub(super) fn connect_block(&self, samples: &[Sample], block: &mut ProjectedBlock) {
        debug_assert!(samples.len() <= BLOCK);
        let (mut x, mut y, mut z) = ([0.0f32; BLOCK], [0.0f32; BLOCK], [0.0f32; BLOCK]);
        for (l, s) in samples.iter().enumerate() {
            [x[l], y[l], z[l]] = s.position;
        }
        let area = self.pixel_area();
        for l in 0..BLOCK {
            (block.pixel[l], block.weight[l]) = self.connection_of(Vec3::new(x[l], y[l], z[l]), area);
        }
        block.len = samples.len();
    }

    /// The pixel of `x` under the box filter ([`NO_PIXEL`] behind the eye or outside the image)
    /// and its connection's W = 1/(a·d²·cos³θ_c) (meaningless without a pixel), `area` being
    /// [`Pinhole::pixel_area`]; without a branch, so that a block of points vectorises.
    #[inline(always)]
    fn connection_of(&self, x: Vec3, area: f32) -> (u32, f32) {
        let v = x - self.eye;
        let depth = v.dot(self.forward);
        let (sx, sy) = self.film_xy(v, depth);
        let d2 = v.dot(v);
        let cos_c = depth / d2.sqrt();
        let pixel = if depth <= 0.0 { NO_PIXEL } else { self.raster.box_pixel_index(sx, sy) };
        (pixel, 1.0 / (area * d2 * cos_c * cos_c * cos_c))
    }

    /// Connects `x` to the pinhole for a filtered splat: its film coordinates, unclipped.
    #[inline]
    pub(super) fn film_hit(&self, x: Vec3) -> Option<FilmHit> {
        let (sx, sy, cos_c) = self.film_of(x)?;
        let d2 = (self.eye - x).length_squared();
        let weight = 1.0 / (self.pixel_area() * d2 * cos_c * cos_c * cos_c);
        Some(FilmHit { film: (sx, sy), point: self.eye, weight })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::CameraKind;
    use crate::sensor::FilmSpec;

    /// The splat loop's block projection is `connect` lane by lane, to the bit: the same
    /// pixel (or none: behind the eye, off the film, outside a crop window) and the same W, on
    /// points all around the eye and at the film's edges, in blocks of every length.
    #[test]
    fn a_block_projects_as_each_point_connects() {
        use crate::sampling::{RandomStream, warp};
        use crate::sensor::Crop;
        let mut rng = RandomStream::new(17, &[]);
        let crop = Crop { x: 40, y: 10, width: 150, height: 100 };
        for film in [Default::default(), FilmSpec { crop: Some(crop), ..Default::default() }] {
            let p = Pinhole::new(&CameraDesc { film, ..cam_desc() }).unwrap();
            let (mut inside, mut outside) = (0, 0);
            for len in (1..=BLOCK).cycle().take(4000) {
                let samples: Vec<Sample> = (0..len)
                    .map(|_| {
                        // Around the view's axis, a fifth of them behind the eye.
                        let d = p.forward + 0.8 * warp::square_to_uniform_sphere(rng.next_2d());
                        let x = p.eye + d * (0.01 + 10.0 * rng.next_f32());
                        Sample::scattered(x, Vec3::Z, 0, crate::math::Rgb::ONE)
                    })
                    .collect();
                let mut block = ProjectedBlock::default();
                p.connect_block(&samples, &mut block);
                assert_eq!(block.len, len);
                for (l, s) in samples.iter().enumerate() {
                    match p.connect(s.position()) {
                        Some(c) => {
                            inside += 1;
                            assert_eq!(block.pixel[l] as usize, c.pixel);
                            assert_eq!(block.weight[l].to_bits(), c.weight.to_bits());
                        }
                        None => {
                            outside += 1;
                            assert_eq!(block.pixel[l], NO_PIXEL);
                        }
                    }
                }
            }
            assert!(inside > 1000 && outside > 1000, "{inside} inside, {outside} outside");
        }
    }

    fn cam_desc() -> CameraDesc {
        CameraDesc {
            eye: Vec3::new(0.0, 0.0, 3.9),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_x_degrees: 39.3077,
            width: 256,
            height: 128,
            kind: CameraKind::Perspective,
            film: Default::default(),
        }
    }

    fn cam() -> Pinhole {
        Pinhole::new(&cam_desc()).unwrap()
    }

    #[test]
    fn projection_inverts_the_film_mapping() {
        let c = cam();
        for (sx, sy) in [(0.5f32, 0.5f32), (0.01, 0.02), (0.99, 0.7), (0.3, 0.999)] {
            let p = c.eye + 2.5 * c.direction(sx, sy);
            let (pix, cos_c) = c.project(p).unwrap();
            assert_eq!(pix % 256, (sx * 256.0) as usize);
            assert_eq!(pix / 256, (sy * 128.0) as usize);
            assert!((cos_c - c.direction(sx, sy).dot(c.forward)).abs() < 1e-5);
        }
        assert!(c.project(c.eye - c.forward).is_none());
        // Image right is +x, up is +y for a camera looking down -z.
        assert!((c.right - Vec3::X).length() < 1e-6 && (c.up - Vec3::Y).length() < 1e-6);
    }

    #[test]
    fn degenerate_cameras_are_refused() {
        let good = CameraDesc {
            eye: Vec3::ZERO,
            target: Vec3::Z,
            up: Vec3::Y,
            fov_x_degrees: 45.0,
            width: 4,
            height: 4,
            kind: CameraKind::Perspective,
            film: Default::default(),
        };
        assert!(Pinhole::new(&good).is_ok());
        assert!(Pinhole::new(&CameraDesc { up: Vec3::Z, ..good }).is_err());
        assert!(Pinhole::new(&CameraDesc { target: Vec3::ZERO, ..good }).is_err());
        assert!(Pinhole::new(&CameraDesc { fov_x_degrees: f32::NAN, ..good }).is_err());
        assert!(Pinhole::new(&CameraDesc { width: 0, ..good }).is_err());
        assert!(Pinhole::new(&CameraDesc { eye: Vec3::splat(f32::NAN), ..good }).is_err());
    }
}
