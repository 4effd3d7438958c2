//! Geological orientation of planes: dip and dip direction.
//!
//! Convention (x = East, y = North, z = Up): dip $\delta \in [0, 90]$°, dip direction
//! $\alpha \in [0, 360)$° clockwise from North. The upward unit normal is
//! $\mathbf n = (\sin\delta\sin\alpha,\ \sin\delta\cos\alpha,\ \cos\delta)$ and the dip vector
//! (steepest descent) is $\mathbf d = (\cos\delta\sin\alpha,\ \cos\delta\cos\alpha,\ -\sin\delta)$.

use crate::math::Vec3;

/// Upward unit normal of a plane with the given dip and dip direction (degrees).
pub fn normal_from_dip(dip_deg: f64, dip_direction_deg: f64) -> Vec3 {
    let (d, a) = (dip_deg.to_radians(), dip_direction_deg.to_radians());
    Vec3::new(d.sin() * a.sin(), d.sin() * a.cos(), d.cos())
}

/// Unit dip vector (direction of steepest descent in the plane).
pub fn dip_vector(dip_deg: f64, dip_direction_deg: f64) -> Vec3 {
    let (d, a) = (dip_deg.to_radians(), dip_direction_deg.to_radians());
    Vec3::new(d.cos() * a.sin(), d.cos() * a.cos(), -d.sin())
}

/// Dip and dip direction (degrees) of the plane with normal `n` (either sense).
pub fn dip_from_normal(n: &Vec3) -> (f64, f64) {
    let n = if n.z < 0.0 { -n.normalize() } else { n.normalize() };
    let dip = n.z.clamp(-1.0, 1.0).acos().to_degrees();
    let mut dd = n.x.atan2(n.y).to_degrees();
    if dd < 0.0 {
        dd += 360.0;
    }
    (dip, dd)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_and_dip_vector_are_orthogonal_and_round_trip() {
        let mut seed = 12345u64;
        for _ in 0..500 {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let dip = (seed >> 11) as f64 / (1u64 << 53) as f64 * 89.0 + 0.5;
            let dd = ((seed >> 7) % 3600) as f64 / 10.0;
            let n = normal_from_dip(dip, dd);
            let d = dip_vector(dip, dd);
            assert!(n.dot(&d).abs() < 1e-14);
            assert!(d.z <= 0.0 && n.z >= 0.0);
            let (dip2, dd2) = dip_from_normal(&n);
            assert!((dip2 - dip).abs() < 1e-9);
            assert!(((dd2 - dd + 540.0) % 360.0 - 180.0).abs() < 1e-9);
        }
    }

    #[test]
    fn east_dipping_plane() {
        let n = normal_from_dip(30.0, 90.0);
        assert!((n - Vec3::new(0.5, 0.0, 3f64.sqrt() / 2.0)).norm() < 1e-15);
    }
}
