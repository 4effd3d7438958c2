//! Scalar and vector aliases: nmm3d is 3-D and double precision only.

/// A point or vector in 3-D space [m].
pub type Vec3 = nalgebra::Vector3<f64>;
/// A 3 × 3 matrix.
pub type Mat3 = nalgebra::Matrix3<f64>;

/// Rotation matrix for rotations about x, then y, then z (angles in degrees), i.e.
/// `R = Rz · Ry · Rx`, applied to column vectors.
pub fn rotation_xyz_deg(angles: [f64; 3]) -> Mat3 {
    let [ax, ay, az] = angles.map(f64::to_radians);
    let rx = nalgebra::Rotation3::from_axis_angle(&Vec3::x_axis(), ax);
    let ry = nalgebra::Rotation3::from_axis_angle(&Vec3::y_axis(), ay);
    let rz = nalgebra::Rotation3::from_axis_angle(&Vec3::z_axis(), az);
    (rz * ry * rx).into_inner()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_xyz_is_orthonormal_and_ordered() {
        let r = rotation_xyz_deg([90.0, 0.0, 90.0]);
        assert!((r * r.transpose() - Mat3::identity()).norm() < 1e-14);
        // x then z: the y axis goes to z by the x-rotation, z stays under the z-rotation.
        let y = r * Vec3::y();
        assert!((y - Vec3::z()).norm() < 1e-14);
    }
}
