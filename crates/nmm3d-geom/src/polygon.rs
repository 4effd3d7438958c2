//! Planar polygons in 3-D.

use crate::math::Vec3;
use crate::plane::Plane;

/// Area vector (Newell's method): its direction is the normal by the right-hand rule,
/// its length the area.
pub fn area_vector(vertices: &[Vec3]) -> Vec3 {
    let n = vertices.len();
    let mut a = Vec3::zeros();
    for i in 0..n {
        a += vertices[i].cross(&vertices[(i + 1) % n]);
    }
    0.5 * a
}

/// Area-weighted centroid of a planar polygon (fan triangulation from vertex 0).
pub fn centroid(vertices: &[Vec3]) -> Vec3 {
    let normal = area_vector(vertices);
    let mut total = 0.0;
    let mut c = Vec3::zeros();
    for i in 1..vertices.len().saturating_sub(1) {
        let (a, b, d) = (vertices[0], vertices[i], vertices[i + 1]);
        let w = (b - a).cross(&(d - a)).dot(&normal);
        total += w;
        c += w * (a + b + d) / 3.0;
    }
    if total.abs() > 0.0 {
        c / total
    } else {
        vertices.iter().sum::<Vec3>() / vertices.len().max(1) as f64
    }
}

/// Sort points lying on a plane with unit normal `n` counter-clockwise about `n`
/// (seen from the side `n` points to). Deterministic for equal inputs.
pub fn sort_ccw(points: &mut [Vec3], n: &Vec3) {
    if points.len() < 3 {
        return;
    }
    let c: Vec3 = points.iter().sum::<Vec3>() / points.len() as f64;
    let u = any_perpendicular(n);
    let v = n.cross(&u);
    points.sort_by(|a, b| {
        let (da, db) = (a - c, b - c);
        let ta = da.dot(&v).atan2(da.dot(&u));
        let tb = db.dot(&v).atan2(db.dot(&u));
        ta.total_cmp(&tb)
    });
}

/// A unit vector perpendicular to `n`.
pub fn any_perpendicular(n: &Vec3) -> Vec3 {
    let a = if n.x.abs() < 0.6 { Vec3::x() } else { Vec3::y() };
    n.cross(&a).normalize()
}

/// Remove consecutive points closer than `tol` (cyclically).
pub fn dedup_cyclic(points: &mut Vec<Vec3>, tol: f64) {
    points.dedup_by(|a, b| (*a - *b).norm() <= tol);
    while points.len() > 1 && (points[0] - points[points.len() - 1]).norm() <= tol {
        let _ = points.pop();
    }
}

/// Half-spaces bounding a convex polygon within its plane: for each edge, the plane through it
/// whose normal points out of the polygon (`normal` is the polygon's unit normal).
fn edge_planes(poly: &[Vec3], normal: &Vec3) -> Vec<Plane> {
    let n = poly.len();
    (0..n).filter_map(|i| Plane::from_point_normal(poly[i], (poly[(i + 1) % n] - poly[i]).cross(normal))).collect()
}

/// Intersection of two coplanar convex polygons (as a convex polygon, possibly empty).
/// `normal` is the unit normal `clip` is counter-clockwise about.
pub fn intersect_convex(subject: &[Vec3], clip: &[Vec3], normal: &Vec3, eps: f64) -> Vec<Vec3> {
    let mut out = subject.to_vec();
    for p in edge_planes(clip, normal) {
        out = clip_polygon_to(&out, &p, eps);
        if out.len() < 3 {
            return Vec::new();
        }
    }
    out
}

/// `subject` minus the coplanar convex `clip`, as convex polygons (one per clip edge that cuts).
pub fn difference_convex(subject: &[Vec3], clip: &[Vec3], normal: &Vec3, eps: f64) -> Vec<Vec<Vec3>> {
    let mut rest = subject.to_vec();
    let mut out = Vec::new();
    for p in edge_planes(clip, normal) {
        let outside = clip_polygon_to(&rest, &p.flipped(), eps);
        if outside.len() >= 3 && area_vector(&outside).norm() > eps * eps {
            out.push(outside);
        }
        rest = clip_polygon_to(&rest, &p, eps);
        if rest.len() < 3 {
            break;
        }
    }
    out
}

/// The part of a polygon strictly inside the half-space (within `eps`).
pub fn clip_polygon_to(poly: &[Vec3], plane: &Plane, eps: f64) -> Vec<Vec3> {
    let n = poly.len();
    let s: Vec<f64> = poly.iter().map(|v| plane.signed_distance(v)).collect();
    let mut out = Vec::with_capacity(n + 2);
    for i in 0..n {
        let j = (i + 1) % n;
        if s[i] <= eps {
            out.push(poly[i]);
        }
        if (s[i] < -eps && s[j] > eps) || (s[i] > eps && s[j] < -eps) {
            out.push(poly[i] + (s[i] / (s[i] - s[j])) * (poly[j] - poly[i]));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn convex_intersection_and_difference_partition_the_subject() {
        let sq = |x0: f64, y0: f64, s: f64| {
            vec![
                Vec3::new(x0, y0, 0.0),
                Vec3::new(x0 + s, y0, 0.0),
                Vec3::new(x0 + s, y0 + s, 0.0),
                Vec3::new(x0, y0 + s, 0.0),
            ]
        };
        let (a, b) = (sq(0.0, 0.0, 2.0), sq(1.0, 1.0, 2.0));
        let z = Vec3::z();
        let i = intersect_convex(&a, &b, &z, 1e-12);
        assert!((area_vector(&i).norm() - 1.0).abs() < 1e-12);
        let d: f64 = difference_convex(&a, &b, &z, 1e-12).iter().map(|p| area_vector(p).norm()).sum();
        assert!((d - 3.0).abs() < 1e-12);
        assert!(intersect_convex(&a, &sq(5.0, 5.0, 1.0), &z, 1e-12).is_empty());
    }
}
