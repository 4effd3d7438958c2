//! Oriented planes and the half-spaces they bound.

use crate::math::Vec3;

/// The half-space $\mathbf n\cdot\mathbf x \le d$ with unit outward normal $\mathbf n$.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    /// Unit outward normal.
    pub normal: Vec3,
    /// Offset: the plane is $\mathbf n\cdot\mathbf x = d$.
    pub offset: f64,
}

impl Plane {
    /// Plane through `point` with outward `normal` (normalised here; `None` if zero).
    pub fn from_point_normal(point: Vec3, normal: Vec3) -> Option<Self> {
        let len = normal.norm();
        if !(len > 0.0) || !len.is_finite() {
            return None;
        }
        let n = normal / len;
        Some(Self { normal: n, offset: n.dot(&point) })
    }

    /// Half-space $\mathbf n\cdot\mathbf x \le d$ from a possibly unnormalised `[nx, ny, nz, d]`.
    pub fn from_coefficients(c: [f64; 4]) -> Option<Self> {
        let n = Vec3::new(c[0], c[1], c[2]);
        let len = n.norm();
        if !(len > 0.0) || !len.is_finite() {
            return None;
        }
        Some(Self { normal: n / len, offset: c[3] / len })
    }

    /// Signed distance: negative inside the half-space, positive outside.
    #[inline]
    pub fn signed_distance(&self, x: &Vec3) -> f64 {
        self.normal.dot(x) - self.offset
    }

    /// The same plane bounding the opposite half-space.
    pub fn flipped(&self) -> Self {
        Self { normal: -self.normal, offset: -self.offset }
    }
}
