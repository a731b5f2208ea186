//! Polygon triangulation for `IndexedFaceSet` faces: ear clipping in the polygon's own plane,
//! so concave faces come out right, with the polygon's winding kept (a face counter-clockwise
//! seen from its front gives triangles counter-clockwise seen from the same side).
//!
//! The plane is the one of the Newell normal (robust for non-planar and partly collinear
//! polygons); the polygon is projected on the coordinate plane most perpendicular to it, with
//! the axes ordered so that the projection keeps the polygon's orientation. Triangles are
//! passed through as they are; every bigger polygon, quads included, is ear-clipped (a quad
//! costs a few dozen operations, so it needs no separate path), except polygons with more than
//! [`EAR_CLIP_MAX`] corners, which are fanned (ear clipping is quadratic) and reported by the
//! caller.

use opticks_core::math::Vec3;

/// Largest polygon that is ear-clipped; bigger ones are fanned.
pub const EAR_CLIP_MAX: usize = 1000;

/// Appends the triangles of polygon `poly` (indices into `points`) to `out`. Returns false if
/// the polygon was too big to ear-clip and was fanned instead. Indices must be valid.
pub fn triangulate(points: &[Vec3], poly: &[u32], out: &mut Vec<[u32; 3]>) -> bool {
    let n = poly.len();
    if n < 3 {
        return true;
    }
    if n == 3 {
        out.push([poly[0], poly[1], poly[2]]);
        return true;
    }
    if n > EAR_CLIP_MAX {
        fan(poly, out);
        return false;
    }
    let p3 = |i: usize| {
        let p = points[poly[i] as usize];
        [f64::from(p.x), f64::from(p.y), f64::from(p.z)]
    };
    // Newell normal.
    let mut nrm = [0.0f64; 3];
    for i in 0..n {
        let (a, b) = (p3(i), p3((i + 1) % n));
        nrm[0] += (a[1] - b[1]) * (a[2] + b[2]);
        nrm[1] += (a[2] - b[2]) * (a[0] + b[0]);
        nrm[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    let abs = nrm.map(f64::abs);
    let axis = if abs[0] >= abs[1] && abs[0] >= abs[2] {
        0
    } else if abs[1] >= abs[2] {
        1
    } else {
        2
    };
    if abs[axis] == 0.0 || !abs[axis].is_finite() {
        fan(poly, out); // degenerate: no plane; the triangles have no area anyway
        return true;
    }
    // (u, v) such that u × v points along +normal.
    let (u, v) = match (axis, nrm[axis] > 0.0) {
        (0, true) => (1, 2),
        (0, false) => (2, 1),
        (1, true) => (2, 0),
        (1, false) => (0, 2),
        (_, true) => (0, 1),
        (_, false) => (1, 0),
    };
    let pts: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let p = p3(i);
            [p[u], p[v]]
        })
        .collect();
    ear_clip(&pts, poly, out);
    true
}

fn fan(poly: &[u32], out: &mut Vec<[u32; 3]>) {
    for i in 1..poly.len() - 1 {
        out.push([poly[0], poly[i], poly[i + 1]]);
    }
}

fn cross(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

fn inside(p: [f64; 2], a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> bool {
    cross(a, b, p) >= 0.0 && cross(b, c, p) >= 0.0 && cross(c, a, p) >= 0.0
}

/// Ear clipping of a counter-clockwise 2D polygon.
fn ear_clip(pts: &[[f64; 2]], poly: &[u32], out: &mut Vec<[u32; 3]>) {
    let mut rest: Vec<usize> = (0..pts.len()).collect();
    let mut i = 0usize;
    let mut misses = 0usize;
    while rest.len() > 3 {
        let m = rest.len();
        let (ip, ic, inx) = (rest[(i + m - 1) % m], rest[i % m], rest[(i + 1) % m]);
        let (a, b, c) = (pts[ip], pts[ic], pts[inx]);
        let convex = cross(a, b, c) > 0.0;
        let is_ear = convex
            && rest.iter().all(|&k| {
                k == ip || k == ic || k == inx || {
                    let p = pts[k];
                    // Coincident corners (a polygon touching itself) do not block an ear.
                    p == a || p == b || p == c || !inside(p, a, b, c)
                }
            });
        // After a full round without an ear the polygon is degenerate (collinear or
        // self-intersecting): clip anyway so the loop ends with n − 2 triangles.
        if is_ear || misses >= m {
            out.push([poly[ip], poly[ic], poly[inx]]);
            rest.remove(i % m);
            i %= rest.len();
            misses = 0;
        } else {
            i = (i + 1) % m;
            misses += 1;
        }
    }
    out.push([poly[rest[0]], poly[rest[1]], poly[rest[2]]]);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area_normal(p: &[Vec3], t: &[u32; 3]) -> Vec3 {
        let [a, b, c] = t.map(|i| p[i as usize]);
        0.5 * (b - a).cross(c - a)
    }

    #[test]
    fn l_shape_keeps_its_area_and_orientation_in_any_plane() {
        // L of area 3 in the xy-plane, counter-clockwise seen from +z.
        let l2 = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)];
        let frames = [
            (Vec3::X, Vec3::Y), // normal +z
            (Vec3::Y, Vec3::X), // normal -z
            (Vec3::Y, Vec3::Z), // normal +x
            (Vec3::new(0.6, 0.8, 0.0), Vec3::new(0.0, 0.0, 1.0)),
        ];
        for (ex, ey) in frames {
            let n = ex.cross(ey);
            for start in 0..6 {
                let pts: Vec<Vec3> = (0..6)
                    .map(|k| {
                        let (x, y) = l2[(k + start) % 6];
                        ex * x + ey * y + Vec3::splat(0.25)
                    })
                    .collect();
                let poly: Vec<u32> = (0..6).collect();
                let mut tris = Vec::new();
                assert!(triangulate(&pts, &poly, &mut tris));
                assert_eq!(tris.len(), 4);
                let mut total = 0.0;
                for t in &tris {
                    let an = area_normal(&pts, t);
                    assert!(an.dot(n) > 0.0, "triangle {t:?} is not ccw about {n:?}");
                    total += an.length();
                }
                assert!((total - 3.0).abs() < 1e-5, "area {total}");
            }
        }
    }

    #[test]
    fn degenerate_polygons_terminate_with_n_minus_2_triangles() {
        let pts = vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0, Vec3::X * 3.0, Vec3::X];
        let mut tris = Vec::new();
        triangulate(&pts, &[0, 1, 2, 3, 4], &mut tris);
        assert_eq!(tris.len(), 3);
        // A star (concave, 10 corners).
        let star: Vec<Vec3> = (0..10)
            .map(|k| {
                let a = k as f32 * std::f32::consts::PI / 5.0;
                let r = if k % 2 == 0 { 1.0 } else { 0.4 };
                Vec3::new(r * a.cos(), r * a.sin(), 0.0)
            })
            .collect();
        let mut tris = Vec::new();
        triangulate(&star, &(0..10).collect::<Vec<_>>(), &mut tris);
        assert_eq!(tris.len(), 8);
        assert!(tris.iter().all(|t| area_normal(&star, t).z > 0.0));
        let area: f32 = tris.iter().map(|t| area_normal(&star, t).z).sum();
        let expected = 10.0 * 0.5 * 1.0 * 0.4 * (std::f32::consts::PI / 5.0).sin();
        assert!((area - expected).abs() < 1e-5, "{area} vs {expected}");
    }
}
