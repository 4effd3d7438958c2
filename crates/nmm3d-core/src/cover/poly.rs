//! Polynomials in the cell-local coordinates ξ = (ξ, η, ζ) with every exponent ≤ 2
//! ("box degree 2"): enough for linear tetrahedral and trilinear hexahedral weight
//! functions, their products and the products of their gradients.

use nmm3d_geom::integrate::Exponent;
use nmm3d_geom::Vec3;

/// Number of monomials ξ^a η^b ζ^c with a, b, c ∈ {0, 1, 2}.
pub const TERMS: usize = 27;

/// Exponent of coefficient `k` (k = a + 3b + 9c).
pub const fn exponent(k: usize) -> Exponent {
    [(k % 3) as u8, ((k / 3) % 3) as u8, (k / 9) as u8]
}

/// All 27 exponents in coefficient order.
pub fn all_exponents() -> Vec<Exponent> {
    (0..TERMS).map(exponent).collect()
}

/// Exponents of total degree ≤ 2 (what linear weight functions need), as a mask.
pub fn degree_two_mask() -> [bool; TERMS] {
    let mut m = [false; TERMS];
    for (k, slot) in m.iter_mut().enumerate() {
        let e = exponent(k);
        *slot = e[0] + e[1] + e[2] <= 2;
    }
    m
}

/// A polynomial: coefficient of ξ^a η^b ζ^c at a + 3b + 9c.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Poly(pub [f64; TERMS]);

impl Poly {
    /// The zero polynomial.
    pub const ZERO: Poly = Poly([0.0; TERMS]);

    /// c0 + c·ξ.
    pub fn affine(c0: f64, c: Vec3) -> Self {
        let mut p = Self::ZERO;
        p.0[0] = c0;
        p.0[1] = c.x;
        p.0[3] = c.y;
        p.0[9] = c.z;
        p
    }

    /// Product; both factors must keep every exponent ≤ 2.
    pub fn mul(&self, o: &Poly) -> Poly {
        let mut r = Poly::ZERO;
        for (i, &a) in self.0.iter().enumerate().filter(|(_, a)| **a != 0.0) {
            let ei = exponent(i);
            for (j, &b) in o.0.iter().enumerate().filter(|(_, b)| **b != 0.0) {
                let ej = exponent(j);
                let (x, y, z) = (ei[0] + ej[0], ei[1] + ej[1], ei[2] + ej[2]);
                assert!(x <= 2 && y <= 2 && z <= 2, "product leaves the box-degree-2 space");
                r.0[x as usize + 3 * y as usize + 9 * z as usize] += a * b;
            }
        }
        r
    }

    /// ∂/∂ξ_axis.
    pub fn derivative(&self, axis: usize) -> Poly {
        let mut r = Poly::ZERO;
        for (k, &c) in self.0.iter().enumerate().filter(|(_, c)| **c != 0.0) {
            let e = exponent(k);
            if e[axis] > 0 {
                let mut f = e;
                f[axis] -= 1;
                r.0[f[0] as usize + 3 * f[1] as usize + 9 * f[2] as usize] += c * e[axis] as f64;
            }
        }
        r
    }

    /// Value at ξ.
    pub fn eval(&self, xi: &Vec3) -> f64 {
        let px = [1.0, xi.x, xi.x * xi.x];
        let py = [1.0, xi.y, xi.y * xi.y];
        let pz = [1.0, xi.z, xi.z * xi.z];
        self.0
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let e = exponent(k);
                c * px[e[0] as usize] * py[e[1] as usize] * pz[e[2] as usize]
            })
            .sum()
    }

    /// ∫ p dξ given the moments ∫ ξ^a η^b ζ^c dξ (entries not computed must be NaN, so that
    /// a missing moment shows up instead of being silently taken as zero).
    pub fn integrate(&self, moments: &[f64; TERMS]) -> f64 {
        self.0.iter().zip(moments).filter(|(c, _)| **c != 0.0).map(|(c, m)| c * m).sum()
    }

    /// Linear combination `self + s·o`.
    pub fn add_scaled(&self, s: f64, o: &Poly) -> Poly {
        let mut r = *self;
        for (a, b) in r.0.iter_mut().zip(o.0.iter()) {
            *a += s * b;
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn product_derivative_and_eval_agree() {
        let p = Poly::affine(1.0, Vec3::new(2.0, -1.0, 0.5));
        let q = Poly::affine(-0.5, Vec3::new(0.0, 3.0, 1.0));
        let pq = p.mul(&q);
        let x = Vec3::new(0.3, 0.7, 0.2);
        assert!((pq.eval(&x) - p.eval(&x) * q.eval(&x)).abs() < 1e-14);
        // d(pq)/dη = p' q + p q'
        let d = pq.derivative(1);
        let expect = -q.eval(&x) + p.eval(&x) * 3.0;
        assert!((d.eval(&x) - expect).abs() < 1e-14);
    }
}
