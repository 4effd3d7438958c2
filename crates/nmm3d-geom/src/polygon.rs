//! Planar polygons in 3-D.

use crate::math::Vec3;

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
