//! Flat convex sets on a plane (a polygon, a segment or a point, given by 3-D points projected
//! on the plane through the origin normal to `n`): their hull, overlap and containment, and the
//! height of a support set over them. The contact detection's two-dimensional half.

use crate::math::Vec3;
use crate::polygon;

/// The lowest and highest levels of `points` along `n`.
pub(crate) fn support(points: &[Vec3], n: &Vec3) -> (f64, f64) {
    points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(n.dot(v)), hi.max(n.dot(v))))
}

/// Whether flat point `p` lies inside the counter-clockwise (about `n`) outline, within `eps`.
pub(crate) fn inside(outline: &[Vec3], p: &Vec3, n: &Vec3, eps: f64) -> bool {
    (0..outline.len()).all(|i| {
        let (q, r) = (outline[i], outline[(i + 1) % outline.len()]);
        (r - q).cross(&(p - q)).dot(n) >= -eps * (r - q).norm()
    })
}

/// 2-D convex hull (counter-clockwise about `n`) of points on a plane, by gift wrapping order.
pub(crate) fn hull(points: &[Vec3], n: &Vec3) -> Vec<Vec3> {
    let mut p: Vec<Vec3> = Vec::new();
    let scale = points.iter().map(|x| x.norm()).fold(1.0, f64::max);
    for x in points {
        if !p.iter().any(|y| (y - x).norm() <= 1e-12 * scale) {
            p.push(*x);
        }
    }
    if p.len() < 3 {
        return p;
    }
    polygon::sort_ccw(&mut p, n);
    // Drop points that are not corners (collinear or inside after angular sort around the centroid).
    let mut changed = true;
    while changed && p.len() > 3 {
        changed = false;
        for i in 0..p.len() {
            let (a, b, c) = (p[(i + p.len() - 1) % p.len()], p[i], p[(i + 1) % p.len()]);
            if (b - a).cross(&(c - b)).dot(n) <= 1e-12 * scale * scale {
                let _ = p.remove(i);
                changed = true;
                break;
            }
        }
    }
    p
}

/// Overlap of two flat convex sets (polygon, segment or point), as its corner points. A point
/// meets a point or a segment only within `near` of it; a point against a polygon is kept
/// as it is (a corner over a face: one past the face's edge is the caller's to judge).
pub(crate) fn overlap_2d(a: &[Vec3], b: &[Vec3], n: &Vec3, (eps, near): (f64, f64)) -> Vec<Vec3> {
    match (a.len(), b.len()) {
        (0, _) | (_, 0) => Vec::new(),
        (1, 1 | 2) => on_segment(a[0], b, near),
        (2, 1) => on_segment(b[0], a, near),
        (1, _) => vec![a[0]],
        (_, 1) => vec![b[0]],
        (2, 2) => segment_overlap(a[0], a[1], b[0], b[1], n, eps),
        (2, _) => clip_segment(a[0], a[1], b, n, eps),
        (_, 2) => clip_segment(b[0], b[1], a, n, eps),
        _ => polygon::intersect_convex(a, b, n, eps),
    }
}

/// `[p]` if flat point `p` lies within `near` of the segment (or point) `s`, else nothing.
fn on_segment(p: Vec3, s: &[Vec3], near: f64) -> Vec<Vec3> {
    let (q0, q1) = (s[0], s[s.len() - 1]);
    let e = q1 - q0;
    let t = if e.norm_squared() > 0.0 { ((p - q0).dot(&e) / e.norm_squared()).clamp(0.0, 1.0) } else { 0.0 };
    if (q0 + t * e - p).norm() <= near {
        vec![p]
    } else {
        Vec::new()
    }
}

/// Where two coplanar segments (as projected) meet: their crossing point, or for parallel
/// overlapping segments (parallel edges) the two ends of the overlap.
pub(crate) fn segment_overlap(p0: Vec3, p1: Vec3, q0: Vec3, q1: Vec3, n: &Vec3, eps: f64) -> Vec<Vec3> {
    let (d, e) = (p1 - p0, q1 - q0);
    let den = d.cross(&e).dot(n);
    if den.abs() <= eps * d.norm().max(e.norm()) {
        if d.cross(&(q0 - p0)).dot(n).abs() > eps * d.norm() {
            return Vec::new(); // parallel, apart
        }
        let t = |q: Vec3| (q - p0).dot(&d) / d.norm_squared();
        let (a, b) = (t(q0).min(t(q1)).max(0.0), t(q0).max(t(q1)).min(1.0));
        return if a <= b { vec![p0 + a * d, p0 + b * d] } else { Vec::new() };
    }
    let t = (q0 - p0).cross(&e).dot(n) / den;
    let s = (q0 - p0).cross(&d).dot(n) / den;
    if (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&s) {
        vec![p0 + t * d]
    } else {
        Vec::new()
    }
}

/// The part of a segment inside a convex polygon (its two end points).
pub(crate) fn clip_segment(p0: Vec3, p1: Vec3, poly: &[Vec3], n: &Vec3, eps: f64) -> Vec<Vec3> {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    let k = poly.len();
    for i in 0..k {
        let (a, b) = (poly[i], poly[(i + 1) % k]);
        let out = (b - a).cross(n); // outward normal of edge a→b (polygon counter-clockwise about n)
        let (s0, s1) = (out.dot(&(p0 - a)), out.dot(&(p1 - a)));
        if s0 > eps && s1 > eps {
            return Vec::new();
        }
        if s0 > eps || s1 > eps {
            let t = s0 / (s0 - s1);
            if s0 > eps {
                t0 = t0.max(t)
            } else {
                t1 = t1.min(t)
            }
        }
    }
    if t0 > t1 {
        return Vec::new();
    }
    vec![p0 + t0 * (p1 - p0), p0 + t1 * (p1 - p0)]
}

/// Height (along n) of a support set at a flat point: the plane through it for ≥ 3 points,
/// interpolation along an edge for 2, the vertex's height for 1.
pub(crate) fn height_field(s: &[Vec3], n: &Vec3) -> impl Fn(&Vec3) -> f64 {
    let pts: Vec<Vec3> = s.to_vec();
    let n = *n;
    move |p: &Vec3| {
        let flat = |v: &Vec3| v - n * n.dot(v);
        match pts.len() {
            0 => 0.0,
            1 => n.dot(&pts[0]),
            2 => {
                let (a, b) = (flat(&pts[0]), flat(&pts[1]));
                let t = if (b - a).norm() > 0.0 {
                    ((p - a).dot(&(b - a)) / (b - a).norm_squared()).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                n.dot(&pts[0]) * (1.0 - t) + n.dot(&pts[1]) * t
            }
            _ => {
                // Least-squares plane h = h0 + g·(p − c) through the support points.
                let c: Vec3 = pts.iter().map(flat).sum::<Vec3>() / pts.len() as f64;
                let h0: f64 = pts.iter().map(|v| n.dot(v)).sum::<f64>() / pts.len() as f64;
                let u = polygon::any_perpendicular(&n);
                let w = n.cross(&u);
                let (mut suu, mut suw, mut sww, mut su, mut sw) = (0.0, 0.0, 0.0, 0.0, 0.0);
                for v in &pts {
                    let (x, y, h) = ((flat(v) - c).dot(&u), (flat(v) - c).dot(&w), n.dot(v) - h0);
                    suu += x * x;
                    suw += x * y;
                    sww += y * y;
                    su += x * h;
                    sw += y * h;
                }
                let det = suu * sww - suw * suw;
                let (gu, gw) = if det.abs() > 1e-300 {
                    ((su * sww - sw * suw) / det, (sw * suu - su * suw) / det)
                } else {
                    (0.0, 0.0)
                };
                h0 + gu * (p - c).dot(&u) + gw * (p - c).dot(&w)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_meets_a_point_or_a_segment_only_on_it() {
        let (n, lim) = (Vec3::z(), (1e-12, 1e-3));
        let segment = [Vec3::zeros(), Vec3::x()];
        let on = Vec3::new(0.5, 0.5e-3, 0.0);
        assert_eq!(overlap_2d(&[on], &segment, &n, lim), vec![on]);
        assert_eq!(overlap_2d(&segment, &[on], &n, lim), vec![on]);
        assert!(overlap_2d(&[Vec3::new(0.5, 1.3, 0.0)], &segment, &n, lim).is_empty(), "beside it");
        assert!(overlap_2d(&segment, &[Vec3::new(1.01, 0.0, 0.0)], &n, lim).is_empty(), "beyond its end");
        assert_eq!(overlap_2d(&[on], &[Vec3::new(0.5, 0.0, 0.0)], &n, lim), vec![on]);
        assert!(overlap_2d(&[on], &[Vec3::x()], &n, lim).is_empty());
        // A corner against a polygon is the caller's to judge (a corner past a face's edge).
        let square = [Vec3::zeros(), Vec3::x(), Vec3::new(1.0, 1.0, 0.0), Vec3::y()];
        assert_eq!(overlap_2d(&[Vec3::new(3.0, 0.0, 0.0)], &square, &n, lim).len(), 1);
    }
}
