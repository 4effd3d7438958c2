//! An anchored bolt as an axial spring between two material points (its head and its anchor):
//! the elongation δ = t·(u_head − u_anchor) along the bolt's unit axis t (anchor → head, in the
//! reference configuration: small rotations), the tension F = P₀ + k (δ − δ_p) with δ_p the
//! plastic elongation. Its local matrix is k (w wᵀ) ⊗ (t tᵀ) over the covers of both points, w the
//! weight-function values, negative at the anchor (the same form as a contact spring, thesis §3.4).

use nmm3d_geom::Vec3;

use crate::scenario::Bolt;

/// A bolt ready to assemble.
#[derive(Debug, Clone)]
pub struct BoltSpring {
    /// Covers of the head's and the anchor's MEs, each once.
    pub covers: Vec<usize>,
    /// Weight of each cover in the elongation: w_head − w_anchor.
    pub weights: Vec<f64>,
    /// Unit axis, anchor → head.
    pub axis: Vec3,
    /// Axial stiffness [N/m].
    pub stiffness: f64,
    /// Tension at installation [N].
    pub pretension: f64,
    /// Yield force [N] (∞: elastic).
    pub yield_force: f64,
    /// Elongation at rupture [m] (∞: never).
    pub rupture: f64,
}

impl BoltSpring {
    /// From the scenario's bolt and the (covers, weights) of its head and anchor points.
    pub fn new(b: &Bolt, head: (&[usize], Vec<f64>), anchor: (&[usize], Vec<f64>)) -> Self {
        let mut covers: Vec<usize> = head.0.to_vec();
        let mut weights = head.1;
        for (&c, w) in anchor.0.iter().zip(anchor.1) {
            match covers.iter().position(|&x| x == c) {
                Some(i) => weights[i] -= w,
                None => {
                    covers.push(c);
                    weights.push(-w);
                }
            }
        }
        Self {
            covers,
            weights,
            axis: (Vec3::from(b.head) - Vec3::from(b.anchor)).normalize(),
            stiffness: b.stiffness,
            pretension: b.pretension,
            yield_force: b.yield_force.unwrap_or(f64::INFINITY),
            rupture: b.rupture_elongation.unwrap_or(f64::INFINITY),
        }
    }

    /// Elongation for cover displacements `u` [m].
    pub fn elongation(&self, u: &[Vec3]) -> f64 {
        self.covers.iter().zip(&self.weights).map(|(&c, w)| w * self.axis.dot(&u[c])).sum()
    }

    /// Tension at elongation `delta` with plastic elongation `plastic` [N].
    pub fn tension(&self, delta: f64, plastic: f64) -> f64 {
        self.pretension + self.stiffness * (delta - plastic)
    }

    /// The local matrix k (w wᵀ) ⊗ (t tᵀ), row-major (3n)².
    pub fn local_matrix(&self) -> Vec<f64> {
        let n = self.covers.len();
        let tt = self.axis * self.axis.transpose();
        let mut m = vec![0.0; 9 * n * n];
        for a in 0..n {
            for b in 0..n {
                let s = self.stiffness * self.weights[a] * self.weights[b];
                for i in 0..3 {
                    for j in 0..3 {
                        m[(3 * a + i) * 3 * n + 3 * b + j] = s * tt[(i, j)];
                    }
                }
            }
        }
        m
    }
}

/// What a bolt has been through (part of the run's state).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BoltState {
    /// Plastic elongation [m].
    pub plastic: f64,
    /// Broken: it carries nothing any more.
    pub broken: bool,
}

impl BoltState {
    /// After an accepted step at elongation `delta`: yield (the tension returns to ±F_y by
    /// plastic flow) and rupture.
    pub fn update(&mut self, b: &BoltSpring, delta: f64) {
        if self.broken {
            return;
        }
        if delta >= b.rupture {
            self.broken = true;
            return;
        }
        let f = b.tension(delta, self.plastic);
        if f.abs() > b.yield_force {
            self.plastic += (f - f.signum() * b.yield_force) / b.stiffness;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bolt() -> BoltSpring {
        let spec = Bolt {
            name: "b".into(),
            head: [0.0, 0.0, -1.0],
            anchor: [0.0, 0.0, 1.0],
            stiffness: 1e6,
            pretension: 1e3,
            yield_force: Some(5e3),
            rupture_elongation: Some(0.02),
        };
        BoltSpring::new(&spec, (&[0, 1], vec![0.25, 0.75]), (&[1, 2], vec![0.5, 0.5]))
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
        s.update(&b, 0.002); // 1e3 + 2e3 = 3e3 < 5e3: elastic
        assert_eq!(s.plastic, 0.0);
        s.update(&b, 0.01); // 1e3 + 1e4 = 1.1e4 > 5e3: yields back to 5e3
        assert!((b.tension(0.01, s.plastic) - 5e3).abs() < 1e-9);
        s.update(&b, 0.02);
        assert!(s.broken);
    }
}
