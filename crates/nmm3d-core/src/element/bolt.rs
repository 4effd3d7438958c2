//! A bolt spring between two material points: for an anchored bolt its head and its anchor,
//! for a grouted bolt the two faces of a joint it crosses (see `grout.rs`). The relative
//! displacement Δ = Σ w_c u_c (w the weight-function values of the first point's covers minus
//! those of the second's) splits along the bolt's unit axis t (second → first point, in the
//! reference configuration: small rotations) into the elongation δ = t·Δ and the shear
//! s = Δ − δ t. Tension F = P₀ + k_a (δ − δ_p), shear force V = k_s (s − s_p), each perfectly
//! plastic at its capacity. Its local matrix is (w wᵀ) ⊗ (k_a t tᵀ + k_s (I − t tᵀ)) over the
//! covers of both points (the form of a contact spring, thesis §3.4).

use nmm3d_geom::{Mat3, Vec3};

use crate::scenario::Bolt;

/// One point of a bolt: the covers of its ME and their weight-function values there.
pub type BoltPoint<'a> = (&'a [usize], Vec<f64>);

/// A bolt spring ready to assemble.
#[derive(Debug, Clone)]
pub struct BoltSpring {
    /// The scenario's bolt (index into `scenario.bolt`) it belongs to.
    pub bolt: usize,
    /// Covers of both points' MEs, each once.
    pub covers: Vec<usize>,
    /// Weight of each cover in Δ: w at the first point − w at the second.
    pub weights: Vec<f64>,
    /// Unit axis, second → first point.
    pub axis: Vec3,
    /// Its stiffness and strength.
    pub law: SpringLaw,
}

/// The stiffness and strength of a bolt spring: axial, shear, pretension, axial and shear
/// capacities, rupture elongation.
#[derive(Debug, Clone, Copy)]
pub struct SpringLaw {
    /// Axial stiffness [N/m].
    pub stiffness: f64,
    /// Shear stiffness across the axis [N/m] (0: none).
    pub shear_stiffness: f64,
    /// Tension at installation [N].
    pub pretension: f64,
    /// Axial capacity [N] (∞: elastic).
    pub yield_force: f64,
    /// Shear capacity [N] (∞: elastic).
    pub shear_capacity: f64,
    /// Elongation at rupture [m] (∞: never).
    pub rupture: f64,
}

impl SpringLaw {
    /// An anchored bolt's: axial only, its free length's stiffness.
    pub fn anchored(b: &Bolt) -> Self {
        Self {
            stiffness: b.stiffness.unwrap_or(0.0),
            shear_stiffness: 0.0,
            pretension: b.pretension,
            yield_force: b.yield_force.unwrap_or(f64::INFINITY),
            shear_capacity: f64::INFINITY,
            rupture: b.rupture_elongation.unwrap_or(f64::INFINITY),
        }
    }
}

impl BoltSpring {
    /// Between `first` and `second`, along `axis` (second → first), with `law`, for bolt `bolt`.
    pub fn new(bolt: usize, first: BoltPoint, second: BoltPoint, axis: Vec3, law: SpringLaw) -> Self {
        let mut covers: Vec<usize> = first.0.to_vec();
        let mut weights = first.1;
        for (&c, w) in second.0.iter().zip(second.1) {
            match covers.iter().position(|&x| x == c) {
                Some(i) => weights[i] -= w,
                None => {
                    covers.push(c);
                    weights.push(-w);
                }
            }
        }
        Self { bolt, covers, weights, axis: axis.normalize(), law }
    }

    /// Relative displacement Δ of the first point against the second for cover displacements
    /// `u` [m].
    pub fn relative(&self, u: &[Vec3]) -> Vec3 {
        self.covers.iter().zip(&self.weights).map(|(&c, w)| *w * u[c]).sum()
    }

    /// Elongation for cover displacements `u` [m].
    pub fn elongation(&self, u: &[Vec3]) -> f64 {
        self.axis.dot(&self.relative(u))
    }

    /// Shear displacement (across the axis) of a relative displacement `d` [m].
    pub fn shear_of(&self, d: &Vec3) -> Vec3 {
        d - self.axis * self.axis.dot(d)
    }

    /// Tension at elongation `delta` with plastic elongation `plastic` [N].
    pub fn tension(&self, delta: f64, plastic: f64) -> f64 {
        self.law.pretension + self.law.stiffness * (delta - plastic)
    }

    /// The local matrix (w wᵀ) ⊗ (k_a t tᵀ + k_s (I − t tᵀ)), row-major (3n)², with the axial
    /// or the shear part left out where it yields.
    pub fn local_matrix(&self, axial: bool, shear: bool) -> Vec<f64> {
        let n = self.covers.len();
        let tt = self.axis * self.axis.transpose();
        let ka = if axial { self.law.stiffness } else { 0.0 };
        let ks = if shear { self.law.shear_stiffness } else { 0.0 };
        let k3: Mat3 = tt * ka + (Mat3::identity() - tt) * ks;
        let mut m = vec![0.0; 9 * n * n];
        for a in 0..n {
            for b in 0..n {
                let s = self.weights[a] * self.weights[b];
                for i in 0..3 {
                    for j in 0..3 {
                        m[(3 * a + i) * 3 * n + 3 * b + j] = s * k3[(i, j)];
                    }
                }
            }
        }
        m
    }
}

/// What a bolt spring has been through (part of the run's state).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BoltState {
    /// Plastic elongation [m].
    pub plastic: f64,
    /// Plastic shear displacement [m] (grouted bolts' dowel action).
    #[serde(default)]
    pub plastic_shear: Vec3,
    /// Broken: it carries nothing any more.
    pub broken: bool,
    /// Relative displacement of its points when it was installed [m] (a bolt installed by a
    /// later stage is unstressed in the rock as it has moved until then).
    #[serde(default)]
    pub installed: Vec3,
}

impl BoltState {
    /// Relative displacement Δ of spring `b` since its installation for cover displacements `u`
    /// [m].
    pub fn relative(&self, b: &BoltSpring, u: &[Vec3]) -> Vec3 {
        b.relative(u) - self.installed
    }

    /// Shear force at relative displacement `d` before the capacity is applied [N].
    pub fn trial_shear(&self, b: &BoltSpring, d: &Vec3) -> Vec3 {
        (b.shear_of(d) - self.plastic_shear) * b.law.shear_stiffness
    }

    /// After an accepted step at relative displacement `d`: yield (the forces return to their
    /// capacities by plastic flow) and rupture.
    pub fn update(&mut self, b: &BoltSpring, d: &Vec3) {
        if self.broken {
            return;
        }
        let delta = b.axis.dot(d);
        let law = &b.law;
        if delta >= law.rupture {
            self.broken = true;
            return;
        }
        let f = b.tension(delta, self.plastic);
        if f.abs() > law.yield_force {
            self.plastic += (f - f.signum() * law.yield_force) / law.stiffness;
        }
        let v = self.trial_shear(b, d);
        let m = v.norm();
        if m > law.shear_capacity {
            self.plastic_shear += v * ((m - law.shear_capacity) / (m * law.shear_stiffness));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law() -> SpringLaw {
        SpringLaw {
            stiffness: 1e6,
            shear_stiffness: 2e6,
            pretension: 1e3,
            yield_force: 5e3,
            shear_capacity: 4e3,
            rupture: 0.02,
        }
    }

    fn bolt() -> BoltSpring {
        let axis = Vec3::new(0.0, 0.0, -2.0);
        BoltSpring::new(0, (&[0, 1], vec![0.25, 0.75]), (&[1, 2], vec![0.5, 0.5]), axis, law())
    }

    #[test]
    fn shared_covers_are_merged_and_the_weights_sum_to_zero() {
        let b = bolt();
        assert_eq!(b.covers, vec![0, 1, 2]);
        assert_eq!(b.weights, vec![0.25, 0.25, -0.5]);
        // A rigid translation does not stretch it.
        let u = vec![Vec3::new(0.3, -0.2, 0.7); 3];
        assert!(b.elongation(&u).abs() < 1e-15);
        assert_eq!(b.axis, Vec3::new(0.0, 0.0, -1.0));
    }

    #[test]
    fn it_yields_then_breaks() {
        let b = bolt();
        let mut s = BoltState::default();
        let along = |d: f64| b.axis * d;
        s.update(&b, &along(0.002)); // 1e3 + 2e3 = 3e3 < 5e3: elastic
        assert_eq!(s.plastic, 0.0);
        s.update(&b, &along(0.01)); // 1e3 + 1e4 = 1.1e4 > 5e3: yields back to 5e3
        assert!((b.tension(0.01, s.plastic) - 5e3).abs() < 1e-9);
        s.update(&b, &along(0.02));
        assert!(s.broken);
    }

    #[test]
    fn the_dowel_yields_in_the_direction_of_shear() {
        let b = bolt();
        let mut s = BoltState::default();
        let d = Vec3::new(0.003, 0.004, 0.0); // |s| = 5 mm: 1e4 N > 4e3 N
        s.update(&b, &d);
        let v = s.trial_shear(&b, &d);
        assert!((v.norm() - 4e3).abs() < 1e-9);
        assert!((v.normalize() - d.normalize()).norm() < 1e-12);
        assert_eq!(s.plastic, 0.0, "shear alone does not stretch it");
    }

    #[test]
    fn the_local_matrix_splits_axial_and_shear_stiffness() {
        let b = bolt();
        let m = b.local_matrix(true, true);
        let n = 3 * b.covers.len();
        // Cover 0 against itself: w² (k_s, k_s, k_a) on the diagonal (axis along z).
        let w2 = 0.25 * 0.25;
        assert!((m[0] - w2 * 2e6).abs() < 1e-6);
        assert!((m[2 * n + 2] - w2 * 1e6).abs() < 1e-6);
        let m = b.local_matrix(false, true);
        assert!(m[2 * n + 2].abs() < 1e-9);
    }
}
