//! Element matrices of one manifold element, integrated exactly from its moments.
//!
//! With cell-local coordinates ξ, x = o + s R (c + ξ), so ∇ = (1/s) R ∇_ξ and dV = s³ dξ.
//! Writing $H_{ab} = \int \nabla_\xi w_a \otimes \nabla_\xi w_b\,d\xi$ and
//! $G_{ab} = \int \nabla w_a \otimes \nabla w_b\,dV = s\,R H_{ab} R^\top$, the isotropic
//! elastic stiffness block is (thesis §3.3; any FE text, e.g. Zienkiewicz & Taylor Vol. 1 §6)
//!
//! $$K_{ab} = \lambda\,G_{ab} + \mu\,G_{ab}^\top + \mu\,\mathrm{tr}(G_{ab})\,I,$$
//!
//! the consistent mass is $M_{ab} = \rho\int w_a w_b\,dV\;I$, and the body force
//! $f_a = \rho\,\mathbf g \int w_a\,dV$.

use nmm3d_geom::{Mat3, Vec3};

use crate::cover::poly::{Poly, TERMS};
use crate::cover::MathMesh;
use crate::model::Elastic;

/// Reference-configuration matrices of one ME (shared by identical full sub-cells).
#[derive(Debug, Clone)]
pub struct ElementKernel {
    /// Number of covers n.
    pub n: usize,
    /// Stiffness, (3n) × (3n), row-major.
    pub stiffness: Vec<f64>,
    /// Scalar consistent mass ρ∫w_a w_b dV, n × n, row-major.
    pub mass: Vec<f64>,
    /// ∫ w_a dV [m³].
    pub integral_w: Vec<f64>,
    /// (1/V) ∫ ∇w_a dV [1/m].
    pub mean_gradient: Vec<Vec3>,
    /// Volume [m³].
    pub volume: f64,
}

/// Build the kernel from moments ∫ξ^α dξ, weight functions and material.
pub fn element_kernel(moments: &[f64; TERMS], weights: &[Poly], mesh: &MathMesh, mat: &Elastic) -> ElementKernel {
    let n = weights.len();
    let (s, r) = (mesh.size, mesh.rotation);
    let s3 = s * s * s;
    let volume = moments[0] * s3;
    let grads: Vec<[Poly; 3]> = weights.iter().map(|w| [w.derivative(0), w.derivative(1), w.derivative(2)]).collect();
    let integral_w: Vec<f64> = weights.iter().map(|w| w.integrate(moments) * s3).collect();
    let mean_gradient: Vec<Vec3> = grads
        .iter()
        .map(|g| {
            let h = Vec3::new(g[0].integrate(moments), g[1].integrate(moments), g[2].integrate(moments));
            s * s * (r * h) / volume
        })
        .collect();
    let mut mass = vec![0.0; n * n];
    let mut stiffness = vec![0.0; 9 * n * n];
    for a in 0..n {
        for b in a..n {
            let m = mat.density * weights[a].mul(&weights[b]).integrate(moments) * s3;
            mass[a * n + b] = m;
            mass[b * n + a] = m;
            let mut h = Mat3::zeros();
            for k in 0..3 {
                for l in 0..3 {
                    h[(k, l)] = grads[a][k].mul(&grads[b][l]).integrate(moments);
                }
            }
            let g = s * (r * h * r.transpose());
            let kab = mat.lambda * g + mat.mu * g.transpose() + mat.mu * g.trace() * Mat3::identity();
            for i in 0..3 {
                for j in 0..3 {
                    stiffness[(3 * a + i) * 3 * n + 3 * b + j] = kab[(i, j)];
                    stiffness[(3 * b + j) * 3 * n + 3 * a + i] = kab[(i, j)];
                }
            }
        }
    }
    ElementKernel { n, stiffness, mass, integral_w, mean_gradient, volume }
}

/// Symmetric 3 × 3 stress from [xx, yy, zz, xy, yz, zx].
pub fn stress_matrix(s: &[f64; 6]) -> Mat3 {
    Mat3::new(s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2])
}

/// [xx, yy, zz, xy, yz, zx] of a symmetric 3 × 3 matrix.
pub fn stress_components(m: &Mat3) -> [f64; 6] {
    [
        m[(0, 0)],
        m[(1, 1)],
        m[(2, 2)],
        0.5 * (m[(0, 1)] + m[(1, 0)]),
        0.5 * (m[(1, 2)] + m[(2, 1)]),
        0.5 * (m[(2, 0)] + m[(0, 2)]),
    ]
}

/// Isotropic Hooke's law σ = λ tr(ε) I + 2μ ε.
pub fn hooke(mat: &Elastic, strain: &Mat3) -> Mat3 {
    mat.lambda * strain.trace() * Mat3::identity() + 2.0 * mat.mu * strain
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cover::{build::moments, PatternTable};
    use crate::scenario::PatternKind;

    fn rock() -> Elastic {
        Elastic::new(&crate::scenario::Material { name: "r".into(), density: 2000.0, young: 1e9, poisson: 0.3 })
    }

    #[test]
    fn stiffness_has_six_rigid_modes_and_mass_sums_to_total() {
        for kind in [PatternKind::Tet6, PatternKind::Hex8, PatternKind::Tet24] {
            let table = PatternTable::new(kind);
            let mesh = MathMesh::new(0.5, Vec3::zeros(), [10.0, 20.0, 30.0]);
            let sub = &table.subcells[0][0];
            let m = moments(&sub.shape, &table);
            let k = element_kernel(&m, &sub.weights, &mesh, &rock());
            let n = k.n;
            let total: f64 = k.mass.iter().sum();
            assert!((total - 2000.0 * k.volume).abs() < 1e-9 * total);
            // Rigid translation and infinitesimal rotation give zero force.
            let pos: Vec<Vec3> = sub
                .nodes
                .iter()
                .map(|q| mesh.to_global(&(Vec3::new(q[0] as f64, q[1] as f64, q[2] as f64) * 0.5)))
                .collect();
            for mode in 0..6 {
                let u: Vec<f64> = pos
                    .iter()
                    .flat_map(|p| {
                        let v = if mode < 3 {
                            let mut t = Vec3::zeros();
                            t[mode] = 1.0;
                            t
                        } else {
                            let mut w = Vec3::zeros();
                            w[mode - 3] = 1.0;
                            w.cross(p)
                        };
                        [v.x, v.y, v.z]
                    })
                    .collect();
                let kmax = k.stiffness.iter().fold(0.0f64, |a, b| a.max(b.abs()));
                for row in 0..3 * n {
                    let f: f64 = (0..3 * n).map(|c| k.stiffness[row * 3 * n + c] * u[c]).sum();
                    assert!(f.abs() < 1e-9 * kmax, "{kind:?} mode {mode}: {f}");
                }
            }
        }
    }
}
