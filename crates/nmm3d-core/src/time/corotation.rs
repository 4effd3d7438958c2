//! Co-rotational kinematics of a manifold element.
//!
//! The rotation $R_e$ of an ME is the polar factor of its mean deformation gradient
//! $\bar F = \sum_a \mathbf x_a \otimes \bar{\nabla} w_a$ (exact for linear covers). Strains are
//! measured in that frame, $\mathbf u^{loc}_a = R_e^\top \mathbf x_a - \mathbf X_a$, so a rigid
//! rotation of any size produces no strain and no spurious volume change. The internal force
//! and tangent are $\mathbf f_a = R_e(\sum_b K_{ab}\mathbf u^{loc}_b + \mathbf f^{0}_a)$ and
//! $R_e K_{ab} R_e^\top$ (Felippa & Haugen 2005, "A unified formulation of small-strain
//! corotational finite elements"; Solfec's body co-rotational FE).

use nmm3d_geom::{Mat3, Vec3};

use crate::element::kernel::{hooke, stress_matrix};
use crate::state::Motion;
use crate::system::System;

/// Convergence of the polar decomposition: the last rotation increment [rad].
const POLAR_EPS: f64 = 1e-13;
/// Iteration cap of nalgebra's search (Müller et al. 2016), the fallback.
const POLAR_MAX_ITER: usize = 100;
/// Newton steps of the polar decomposition before the fallback takes over (it converges
/// quadratically: 1.8–2.2 per call measured on the static block, the dominos and the slope, the
/// last of them only confirming, none falling back).
const POLAR_NEWTON_ITER: usize = 12;

/// Mean deformation gradient of ME `e`.
pub fn deformation_gradient(sys: &System, state: &Motion, e: usize) -> Mat3 {
    let k = sys.kernel(e);
    // Σ X_a ⊗ ḡ_a = I exactly (linear reproduction), so F = I + Σ u_a ⊗ ḡ_a.
    let du: Mat3 =
        sys.covers.elements[e].covers.iter().zip(&k.mean_gradient).map(|(&c, g)| state.u[c] * g.transpose()).sum();
    Mat3::identity() + du
}

/// Rotation of ME `e`, warm-started from `guess`: the R maximising tr(Rᵀ F̄), the polar factor.
///
/// Newton's method on R ← R exp([θ]×): with A = Rᵀ F̄ and S its symmetric part, the gradient of
/// tr(exp([θ]×)ᵀ A) at θ = 0 is g = (A₃₂ − A₂₃, A₁₃ − A₃₁, A₂₁ − A₁₂) and its Hessian −(tr S I − S),
/// so θ = (tr S I − S)⁻¹ g. Müller, Bender, Chentanez & Macklin (2016; nalgebra's `from_matrix_eps`)
/// step by g / tr S: near a rotation tr S I − S ≈ 2 I against tr S ≈ 3, so their error falls only
/// threefold per step — 9.6–11.2 steps per call measured on the static block and the dominos.
/// A converged R is the maximum when tr A > ‖F̄‖_F: at the stationary points R₀Q (Q the identity
/// or a half-turn about an eigenvector of U, F̄ = R₀U) the trace is u₁ + u₂ + u₃ or uᵢ − uⱼ − uₖ,
/// and at most one of them exceeds √(Σuᵢ²) — the maximum, which does for positive stretches.
/// Otherwise (an indefinite Hessian, a guess near a half-turn, a reflection) nalgebra's search
/// from `guess` decides. The dominos on the 0.1 m cover (3 001 MEs, 0.8 s): 4.26–4.51 s → 3.61–3.94 s.
pub fn rotation(f: &Mat3, guess: &Mat3) -> Mat3 {
    let mut r = *guess;
    for _ in 0..POLAR_NEWTON_ITER {
        let a = r.transpose() * f;
        let g = Vec3::new(a[(2, 1)] - a[(1, 2)], a[(0, 2)] - a[(2, 0)], a[(1, 0)] - a[(0, 1)]);
        let s = 0.5 * (a + a.transpose());
        let Some(h) = (Mat3::identity() * s.trace() - s).cholesky() else { break };
        let theta = h.solve(&g);
        if theta.norm() <= POLAR_EPS {
            if a.trace() > f.norm() {
                return r;
            }
            break;
        }
        r *= nalgebra::Rotation3::new(theta).into_inner();
    }
    let g = nalgebra::Rotation3::from_matrix_unchecked(*guess);
    nalgebra::Rotation3::from_matrix_eps(f, POLAR_EPS, POLAR_MAX_ITER, g).into_inner()
}

/// Local (co-rotated) displacement of each cover of ME `e`.
pub fn local_displacements(sys: &System, state: &Motion, e: usize, r: &Mat3) -> Vec<Vec3> {
    // Rᵀ(X + u) − X = (Rᵀ − I) X + Rᵀ u, which keeps small strains exact far from the origin.
    let rt = r.transpose();
    let rt_minus_i = rt - Mat3::identity();
    sys.covers.elements[e]
        .covers
        .iter()
        .map(|&c| rt_minus_i * sys.covers.covers[c].position + rt * state.u[c])
        .collect()
}

/// Volume-mean Cauchy stress of ME `e` in global axes [Pa], compression negative.
pub fn element_stress(sys: &System, state: &Motion, e: usize) -> Mat3 {
    let r = state.rotations[e];
    let u = local_displacements(sys, state, e, &r);
    let corotational = r * local_stress(sys, e, &u) * r.transpose();
    match green_lagrange(sys, state, e, &u) {
        // Replace the linear mean stress by the Cauchy stress F S Fᵀ / J of St Venant–Kirchhoff.
        Some((f, svk, linear)) => corotational - r * linear * r.transpose() + f * svk * f.transpose() / f.determinant(),
        None => corotational,
    }
}

fn material(sys: &System, e: usize) -> &crate::model::Elastic {
    &sys.geometry.materials[sys.geometry.blocks[sys.covers.elements[e].block].material]
}

/// Young's modulus of ME `e`'s material [Pa].
pub fn young(sys: &System, e: usize) -> f64 {
    material(sys, e).young
}

/// Symmetric mean strain of ME `e` from its local displacements.
fn mean_strain(sys: &System, e: usize, u: &[Vec3]) -> Mat3 {
    let grad: Mat3 = u.iter().zip(&sys.kernel(e).mean_gradient).map(|(ua, g)| ua * g.transpose()).sum();
    0.5 * (grad + grad.transpose())
}

/// With `strain_measure = "green_lagrange"`: the ME's mean deformation gradient F̄, the second
/// Piola–Kirchhoff stress S(Ē) of its Green–Lagrange strain, and the linear (local) stress it
/// replaces.
fn green_lagrange(sys: &System, state: &Motion, e: usize, u: &[Vec3]) -> Option<(Mat3, Mat3, Mat3)> {
    if sys.scenario.analysis.strain_measure != crate::scenario::StrainMeasure::GreenLagrange {
        return None;
    }
    let mat = material(sys, e);
    let f = deformation_gradient(sys, state, e);
    let green = 0.5 * (f.transpose() * f - Mat3::identity());
    Some((f, hooke(mat, &green), hooke(mat, &mean_strain(sys, e, u))))
}

/// Co-rotated (local) volume-mean stress of ME `e` from its local displacements.
fn local_stress(sys: &System, e: usize, u: &[Vec3]) -> Mat3 {
    stress_matrix(&sys.initial_stress[e]) + hooke(material(sys, e), &mean_strain(sys, e, u))
}

/// Tensile part of a symmetric stress (negative principal stresses set to zero). No
/// eigen-solve when no principal stress changes sign (Sylvester's criterion: a symmetric
/// matrix is semidefinite iff all its principal minors are) — most MEs of a body under its
/// weight are compressed throughout.
fn tensile_part(s: &Mat3) -> Mat3 {
    if semidefinite(&-s) {
        return Mat3::zeros();
    }
    if semidefinite(s) {
        return *s;
    }
    let eig = nalgebra::SymmetricEigen::new(*s);
    let pos = eig.eigenvalues.map(|l| l.max(0.0));
    eig.eigenvectors * Mat3::from_diagonal(&pos) * eig.eigenvectors.transpose()
}

/// Whether the symmetric `a` is positive semidefinite: its diagonal, 2 × 2 principal minors
/// and determinant are ≥ 0.
fn semidefinite(a: &Mat3) -> bool {
    let minor = |i: usize, j: usize| a[(i, i)] * a[(j, j)] - a[(i, j)] * a[(j, i)];
    (0..3).all(|i| a[(i, i)] >= 0.0)
        && minor(0, 1) >= 0.0
        && minor(0, 2) >= 0.0
        && minor(1, 2) >= 0.0
        && a.determinant() >= 0.0
}

/// Internal force of ME `e` per cover, f_a = R_e(Σ_b K_ab u_b^loc + f⁰_a) (plus the
/// Green–Lagrange correction).
pub fn internal_force(sys: &System, state: &Motion, e: usize, r: &Mat3) -> Vec<Vec3> {
    force(sys, state, e, r, &local_displacements(sys, state, e, r))
}

/// [`internal_force`] and the tensile part σ⁺ of the ME's co-rotated stress, which the
/// geometric part of its tangent takes ([`tangent`]).
pub fn internal_force_and_tension(sys: &System, state: &Motion, e: usize, r: &Mat3) -> (Vec<Vec3>, Mat3) {
    let u = local_displacements(sys, state, e, r);
    (force(sys, state, e, r, &u), tensile_part(&local_stress(sys, e, &u)))
}

/// The tensile part σ⁺ of ME `e`'s co-rotated stress at rotation `r` (as
/// [`internal_force_and_tension`] gives it).
pub fn tension(sys: &System, state: &Motion, e: usize, r: &Mat3) -> Mat3 {
    tensile_part(&local_stress(sys, e, &local_displacements(sys, state, e, r)))
}

fn force(sys: &System, state: &Motion, e: usize, r: &Mat3, u: &[Vec3]) -> Vec<Vec3> {
    let k = sys.kernel(e);
    let n = k.n;
    let large = large_strain_correction(sys, state, e, r, u);
    let mut f = vec![Vec3::zeros(); n];
    for a in 0..n {
        let mut fa = if sys.initial_forces[e].is_empty() { Vec3::zeros() } else { sys.initial_forces[e][a] };
        for b in 0..n {
            fa += block(&k.stiffness, n, a, b) * u[b];
        }
        f[a] = r * fa + large.as_ref().map_or(Vec3::zeros(), |c| c * k.mean_gradient[a]);
    }
    f
}

/// Tangent of ME `e` (row-major (3n)²) at rotation `r` with tensile stress `tension`: the
/// rotated elastic stiffness plus the geometric (stress) stiffness of the tensile part,
/// k_ab = V (mean ∇w_a) · σ⁺ (mean ∇w_b) I. Tension stiffens membranes and bent plates (large
/// deflections converge); compression is left out so the matrix stays positive definite. The
/// tangent only steers the iteration: the force is exact either way.
pub fn tangent(sys: &System, e: usize, r: &Mat3, tension: &Mat3) -> Vec<f64> {
    let k = sys.kernel(e);
    let n = k.n;
    let mut t = vec![0.0; 9 * n * n];
    for a in 0..n {
        let ga = tension * k.mean_gradient[a];
        for b in 0..n {
            let geometric = k.volume * ga.dot(&k.mean_gradient[b]);
            let rot = r * block(&k.stiffness, n, a, b) * r.transpose() + geometric * Mat3::identity();
            for i in 0..3 {
                for j in 0..3 {
                    t[(3 * a + i) * 3 * n + 3 * b + j] = rot[(i, j)];
                }
            }
        }
    }
    t
}

/// Green–Lagrange correction V (F̄ S(Ē) − R σ_lin) (per unit mean gradient) of ME `e`: the
/// mean (constant-strain) part of the element taken to St Venant–Kirchhoff; zero at small
/// strain, exact SVK for linear covers, bending of hex8 left co-rotational.
fn large_strain_correction(sys: &System, state: &Motion, e: usize, r: &Mat3, u: &[Vec3]) -> Option<Mat3> {
    green_lagrange(sys, state, e, u).map(|(f, svk, linear)| sys.kernel(e).volume * (f * svk - r * linear))
}

/// 3 × 3 block (a, b) of a row-major (3n)² matrix.
#[inline]
pub fn block(m: &[f64], n: usize, a: usize, b: usize) -> Mat3 {
    let row = |i: usize| &m[(3 * a + i) * 3 * n + 3 * b..(3 * a + i) * 3 * n + 3 * b + 3];
    let (r0, r1, r2) = (row(0), row(1), row(2));
    Mat3::new(r0[0], r0[1], r0[2], r1[0], r1[1], r1[2], r2[0], r2[1], r2[2])
}

/// Rotation vector (axis × angle) of a rotation matrix [rad].
pub fn rotation_vector(r: &Mat3) -> Vec3 {
    nalgebra::Rotation3::from_matrix_unchecked(*r).scaled_axis()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tensile_part_skips_the_eigen_solve_only_where_no_principal_stress_changes_sign() {
        let by_eigen = |s: &Mat3| {
            let eig = nalgebra::SymmetricEigen::new(*s);
            eig.eigenvectors * Mat3::from_diagonal(&eig.eigenvalues.map(|l| l.max(0.0))) * eig.eigenvectors.transpose()
        };
        let q = turn(0.3, -0.7, 1.1);
        for d in [
            [-1.0, -2.0, -3.0],
            [1.0, 2.0, 3.0],
            [1.0, -2.0, 3.0],
            [0.0, -1.0, -1.0],
            [2.0, 0.0, 0.0],
            [-1e-9, 5.0, 5.0],
        ] {
            let s = q * Mat3::from_diagonal(&Vec3::from(d)) * q.transpose();
            let (got, want) = (tensile_part(&s), by_eigen(&s));
            assert!((got - want).norm() <= 1e-12 * s.norm(), "{d:?}: {got} vs {want}");
        }
        assert!(semidefinite(&Mat3::from_diagonal(&Vec3::new(1.0, 0.0, 2.0))));
        assert!(!semidefinite(&(q * Mat3::from_diagonal(&Vec3::new(1.0, -1e-6, 2.0)) * q.transpose())));
    }

    fn turn(x: f64, y: f64, z: f64) -> Mat3 {
        nalgebra::Rotation3::new(Vec3::new(x, y, z)).into_inner()
    }

    /// A symmetric positive stretch with principal values `u` in axes turned by `axes`.
    fn stretch(u: [f64; 3], axes: &Mat3) -> Mat3 {
        axes * Mat3::from_diagonal(&Vec3::from(u)) * axes.transpose()
    }

    #[test]
    fn the_newton_rotation_is_the_polar_factor_from_near_and_far_guesses() {
        for (k, u) in [[1.0, 1.0, 1.0], [1.001, 0.999, 1.0002], [1.3, 0.8, 1.05], [2.0, 0.5, 0.9]].iter().enumerate() {
            let r0 = turn(0.3 + k as f64, -1.1, 0.7);
            let f = r0 * stretch(*u, &turn(0.2, 0.5, -0.4 * k as f64));
            // From the last step's rotation nearby, from the identity, and from a half-turn away
            // (a saddle of tr(Rᵀ F): the fallback must still find the maximum).
            for guess in [r0 * turn(1e-3, -2e-3, 5e-4), Mat3::identity(), r0 * turn(0.0, 0.0, std::f64::consts::PI)] {
                let r = rotation(&f, &guess);
                assert!((r - r0).norm() < 1e-11, "stretch {u:?}: {}", (r - r0).norm());
                assert!((r.transpose() * r - Mat3::identity()).norm() < 1e-13);
            }
        }
    }

    #[test]
    fn an_inverted_element_gets_the_maximum_or_nalgebras_search() {
        let nalgebra_polar = |f: &Mat3| {
            let g = nalgebra::Rotation3::from_matrix_unchecked(Mat3::identity());
            nalgebra::Rotation3::from_matrix_eps(f, POLAR_EPS, POLAR_MAX_ITER, g).into_inner()
        };
        let r0 = turn(0.4, 0.1, -0.2);
        // One stretch negative, the maximum still unique (trace 1.8 > ‖F‖ = 1.43): found.
        let f = r0 * Mat3::from_diagonal(&Vec3::new(-0.2, 1.0, 1.0));
        assert!((rotation(&f, &Mat3::identity()) - nalgebra_polar(&f)).norm() < 1e-12);
        // A reflection: no stationary point passes the test, nalgebra's search decides.
        let f = r0 * Mat3::from_diagonal(&Vec3::new(-1.0, 1.0, 1.0));
        assert_eq!(rotation(&f, &Mat3::identity()), nalgebra_polar(&f));
    }
}
