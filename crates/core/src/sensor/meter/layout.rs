//! Where a connected meter reads: the cells of a grid ([`IlluminanceMeter`], anywhere — on a
//! surface or in the air) or a list of points, each with the normal of the side it measures
//! ([`MeterPoint`], like Radiance's `rtrace -I` input). The connected estimator draws uniform
//! points of the whole layout ([`MeterLayout::draw`]) and of one target
//! ([`MeterLayout::draw_in`]).

use super::{IlluminanceMeter, MAX_TARGETS, MeterError};
use crate::math::{Vec2, Vec3};

/// A point that measures the irradiance arriving from the side its normal faces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeterPoint {
    /// Where.
    pub position: Vec3,
    /// Unit normal of the measured side.
    pub normal: Vec3,
}

impl MeterPoint {
    /// A point meter at `position` facing `normal` (any non-zero length; normalised).
    pub fn new(position: Vec3, normal: Vec3) -> Result<Self, MeterError> {
        let len = normal.length();
        if !position.is_finite() || !normal.is_finite() || !(len > 1e-12) {
            return Err(MeterError::BadPoint);
        }
        let normal = if len.is_finite() {
            normal / len
        } else {
            // The length of a huge normal (≥ ~1.8e19) overflows to infinity, and dividing by
            // that gave a zero normal: divided by its largest component first.
            let n = normal / normal.abs().max_element();
            n / n.length()
        };
        Ok(MeterPoint { position, normal })
    }
}

/// The targets of a connected meter.
#[derive(Clone, Debug, PartialEq)]
pub enum MeterLayout {
    /// nx × ny cells of a parallelogram; target `j * nx + i`.
    Grid(IlluminanceMeter),
    /// Points, in their order.
    Points(Vec<MeterPoint>),
}

/// A point drawn on a layout: its target, where it is and the measured side's normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeterDraw {
    /// Target index (cell or point).
    pub target: usize,
    /// The point.
    pub position: Vec3,
    /// Unit normal of the measured side.
    pub normal: Vec3,
}

impl MeterLayout {
    /// A layout of points: at least one, at most [`MAX_TARGETS`].
    pub fn points(points: Vec<MeterPoint>) -> Result<Self, MeterError> {
        if points.is_empty() || points.len() > MAX_TARGETS {
            return Err(MeterError::PointCount(points.len()));
        }
        Ok(MeterLayout::Points(points))
    }

    /// Number of targets (cells or points).
    pub fn len(&self) -> usize {
        match self {
            MeterLayout::Grid(m) => m.nx as usize * m.ny as usize,
            MeterLayout::Points(p) => p.len(),
        }
    }

    /// Whether there is no target (never, for a layout built by its constructors).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// A point uniform over the whole layout (uniform on the grid's area, so uniform within its
    /// cell; a point picked uniformly from the list), from `u` ∈ [0,1)².
    #[inline]
    pub fn draw(&self, u: Vec2) -> MeterDraw {
        match self {
            MeterLayout::Grid(m) => {
                let i = ((u.x * m.nx as f32) as u32).min(m.nx - 1);
                let j = ((u.y * m.ny as f32) as u32).min(m.ny - 1);
                MeterDraw {
                    target: j as usize * m.nx as usize + i as usize,
                    position: m.origin + u.x * m.u + u.y * m.v,
                    normal: m.normal(),
                }
            }
            MeterLayout::Points(p) => {
                let t = ((u.x * p.len() as f32) as usize).min(p.len() - 1);
                MeterDraw { target: t, position: p[t].position, normal: p[t].normal }
            }
        }
    }

    /// A point uniform within target `t` (a cell's area; a point is itself), from `u`.
    #[inline]
    pub fn draw_in(&self, t: usize, u: Vec2) -> MeterDraw {
        match self {
            MeterLayout::Grid(m) => {
                let (i, j) = ((t % m.nx as usize) as f32, (t / m.nx as usize) as f32);
                let a = (i + u.x) / m.nx as f32;
                let b = (j + u.y) / m.ny as f32;
                MeterDraw { target: t, position: m.origin + a * m.u + b * m.v, normal: m.normal() }
            }
            MeterLayout::Points(p) => MeterDraw { target: t, position: p[t].position, normal: p[t].normal },
        }
    }

    /// Whether the targets are points (each drawn point of a target is the same: one
    /// direct-light sample is exact for delta lights).
    pub fn is_point(&self) -> bool {
        matches!(self, MeterLayout::Points(_))
    }

    /// How far from a target's plane a surface parallel to it still counts as lying in it.
    pub(crate) fn tolerance(&self, d: &MeterDraw) -> f32 {
        match self {
            MeterLayout::Grid(m) => m.tolerance,
            MeterLayout::Points(_) => 1e-5 * (1.0 + d.position.abs().max_element()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_are_uniform_and_land_in_their_cell() {
        let m = IlluminanceMeter::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 2.0), Vec3::new(4.0, 0.0, 0.0), 2, 4)
            .unwrap();
        let layout = MeterLayout::Grid(m);
        let mut counts = [0u32; 8];
        let mut rng = crate::sampling::RandomStream::new(1, &[]);
        for _ in 0..80_000 {
            let d = layout.draw(rng.next_2d());
            assert_eq!(m.locate(d.position), Some(d.target));
            counts[d.target] += 1;
            let e = layout.draw_in(5, rng.next_2d());
            assert_eq!(m.locate(e.position), Some(5));
        }
        assert!(counts.iter().all(|&c| (c as f64 / 10_000.0 - 1.0).abs() < 0.05), "{counts:?}");
        let pts = MeterLayout::points(vec![
            MeterPoint::new(Vec3::X, Vec3::Y * 3.0).unwrap(),
            MeterPoint::new(Vec3::Z, Vec3::NEG_Y).unwrap(),
        ])
        .unwrap();
        assert_eq!(pts.draw(Vec2::new(0.7, 0.1)).target, 1);
        assert_eq!(pts.draw_in(0, Vec2::new(0.7, 0.1)).normal, Vec3::Y);
        assert_eq!(MeterLayout::points(vec![]), Err(MeterError::PointCount(0)));
        assert_eq!(MeterPoint::new(Vec3::X, Vec3::ZERO), Err(MeterError::BadPoint));
        assert_eq!(MeterPoint::new(Vec3::splat(f32::NAN), Vec3::Y), Err(MeterError::BadPoint));
        let huge = MeterPoint::new(Vec3::X, Vec3::new(4e23, 0.7, 0.0)).unwrap();
        assert!(huge.normal.abs_diff_eq(Vec3::X, 1e-6), "a normal whose length overflows f32: {huge:?}");
    }
}
