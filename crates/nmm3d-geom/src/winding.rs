//! Inside/outside tests against closed surfaces by the generalised winding number
//! (Jacobson, Kavan & Sorkine-Hornung 2013): the sum of the signed solid angles of the surface
//! triangles seen from the point, over 4π. It is 1 inside, 0 outside and robust to small gaps.

use crate::math::Vec3;

/// Signed solid angle of triangle (a, b, c) seen from the origin (Van Oosterom & Strackee 1983).
fn solid_angle(a: Vec3, b: Vec3, c: Vec3) -> f64 {
    let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
    let num = a.dot(&b.cross(&c));
    let den = la * lb * lc + a.dot(&b) * lc + b.dot(&c) * la + c.dot(&a) * lb;
    2.0 * num.atan2(den)
}

/// Winding number of `p` with respect to outward-oriented polygon faces.
pub fn winding_number<'a>(p: &Vec3, faces: impl IntoIterator<Item = &'a [Vec3]>) -> f64 {
    let mut total = 0.0;
    for f in faces {
        for i in 1..f.len().saturating_sub(1) {
            total += solid_angle(f[0] - p, f[i] - p, f[i + 1] - p);
        }
    }
    total / (4.0 * std::f64::consts::PI)
}

/// Whether `p` is inside the closed surface (winding number above ½).
pub fn inside<'a>(p: &Vec3, faces: impl IntoIterator<Item = &'a [Vec3]>) -> bool {
    winding_number(p, faces) > 0.5
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polyhedron::ConvexPolyhedron;

    #[test]
    fn cube_inside_and_outside() {
        let c = ConvexPolyhedron::from_box(Vec3::zeros(), Vec3::repeat(1.0));
        let faces: Vec<&[Vec3]> = c.faces.iter().map(|f| f.vertices.as_slice()).collect();
        assert!((winding_number(&Vec3::repeat(0.5), faces.iter().copied()) - 1.0).abs() < 1e-12);
        assert!(winding_number(&Vec3::new(1.5, 0.5, 0.5), faces.iter().copied()).abs() < 1e-12);
        assert!(inside(&Vec3::new(0.999, 0.001, 0.5), faces.iter().copied()));
    }
}
