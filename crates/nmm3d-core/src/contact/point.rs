//! A material point of a block: the ME holding it and its weights, so it moves with the covers.

use nmm3d_geom::Vec3;

use crate::element::loads::weights_at;
use crate::state::Motion;
use crate::system::System;

/// A material point: the ME holding it and its weights (reference position kept).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MaterialPoint {
    /// ME index.
    pub element: usize,
    /// Weight-function values, aligned with the ME's covers.
    pub weights: Vec<f64>,
    /// Reference position [m].
    pub reference: Vec3,
}

impl MaterialPoint {
    /// Locate a reference point of a block.
    pub fn new(sys: &System, block: usize, x: Vec3) -> Option<Self> {
        let tol = 1e-7 * sys.covers.mesh().size;
        let e = sys.covers.locate(block, &x, tol)?;
        Some(Self { element: e, weights: weights_at(&sys.covers, &sys.covers.elements[e], &x), reference: x })
    }

    /// A reference point known to lie in ME `element`.
    pub fn on_element(sys: &System, element: usize, x: Vec3) -> Self {
        Self { element, weights: weights_at(&sys.covers, &sys.covers.elements[element], &x), reference: x }
    }

    /// A per-cover field (displacement, increment, velocity, …) interpolated at the point.
    pub fn of(&self, sys: &System, field: &[Vec3]) -> Vec3 {
        sys.covers.elements[self.element].covers.iter().zip(&self.weights).map(|(&c, w)| *w * field[c]).sum()
    }

    /// Current displacement [m].
    pub fn displacement(&self, sys: &System, state: &Motion) -> Vec3 {
        self.of(sys, &state.u)
    }

    /// Current position [m].
    pub fn position(&self, sys: &System, state: &Motion) -> Vec3 {
        self.reference + self.displacement(sys, state)
    }
}

/// Barycentric coordinates of the point of triangle (a, b, c) nearest `p` (clamped), and the
/// distance to it.
pub(crate) fn barycentric(p: &Vec3, a: &Vec3, b: &Vec3, c: &Vec3) -> ([f64; 3], f64) {
    let Some((v, w)) = in_plane(p, a, b, c) else { return ([1.0, 0.0, 0.0], (p - a).norm()) };
    let v = v.clamp(0.0, 1.0);
    let w = w.clamp(0.0, 1.0 - v);
    let q = a + v * (b - a) + w * (c - a);
    ([1.0 - v - w, v, w], (p - q).norm())
}

/// Coordinates (v, w) of the projection of `p` onto the plane of triangle (a, b, c), unclamped:
/// a + v (b − a) + w (c − a). `None` for a degenerate triangle.
pub(crate) fn in_plane(p: &Vec3, a: &Vec3, b: &Vec3, c: &Vec3) -> Option<(f64, f64)> {
    let (e1, e2, d) = (b - a, c - a, p - a);
    let (d11, d12, d22) = (e1.dot(&e1), e1.dot(&e2), e2.dot(&e2));
    let (d1, d2) = (d.dot(&e1), d.dot(&e2));
    let den = d11 * d22 - d12 * d12;
    (den > 0.0).then(|| ((d22 * d1 - d12 * d2) / den, (d11 * d2 - d12 * d1) / den))
}
