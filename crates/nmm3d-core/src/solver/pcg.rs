//! Preconditioned conjugate gradients (Hestenes–Stiefel; Saad, *Iterative Methods for Sparse
//! Linear Systems*, 2003, Alg. 9.1) on a symmetric matrix stored as its lower triangle.
//!
//! With the Cholesky factor of a nearby matrix K₀ as the preconditioner, K₀⁻¹K = I + K₀⁻¹ΔK:
//! a change ΔK of rank r (contact points that changed state) leaves all but r eigenvalues at 1,
//! so CG ends in about r + 1 iterations, each one triangular solve and one product.

use crate::assembly::SparsityPattern;

/// How a PCG solve ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PcgOutcome {
    /// Iterations made (products with the matrix).
    pub iterations: u32,
    /// The preconditioned residual fell below the tolerance.
    pub converged: bool,
}

/// Solve A x = b (A's lower triangle `values` on `pattern`) from x = 0, applying the
/// preconditioner M⁻¹ in place with `precondition`. Converged when the preconditioned residual
/// norm √(rᵀM⁻¹r) ≤ `tolerance` × √(bᵀM⁻¹b) — the error in the norm of M, relative. Stops
/// unconverged after `max_iterations`, or at once when A is not positive along a direction.
pub fn pcg(
    pattern: &SparsityPattern,
    values: &[f64],
    b: &[f64],
    x: &mut [f64],
    precondition: impl FnMut(&mut [f64]),
    tolerance: f64,
    max_iterations: u32,
) -> PcgOutcome {
    let times = |v: &[f64], out: &mut [f64]| pattern.symmetric_times(values, v, out);
    pcg_with(times, b, x, precondition, tolerance, max_iterations)
}

/// [`pcg`] with the matrix given as its product `times(v, out)`: out = A v.
pub fn pcg_with(
    mut times: impl FnMut(&[f64], &mut [f64]),
    b: &[f64],
    x: &mut [f64],
    mut precondition: impl FnMut(&mut [f64]),
    tolerance: f64,
    max_iterations: u32,
) -> PcgOutcome {
    let dot = |u: &[f64], v: &[f64]| -> f64 { u.iter().zip(v).map(|(a, b)| a * b).sum() };
    x.fill(0.0);
    let mut r = b.to_vec();
    let mut z = r.clone();
    precondition(&mut z);
    let mut rz = dot(&r, &z);
    let target = tolerance * tolerance * rz;
    let mut p = z.clone();
    let mut ap = vec![0.0; b.len()];
    if rz <= 0.0 {
        return PcgOutcome { iterations: 0, converged: rz == 0.0 };
    }
    for it in 1..=max_iterations {
        times(&p, &mut ap);
        let curvature = dot(&p, &ap);
        if curvature <= 0.0 || !curvature.is_finite() {
            return PcgOutcome { iterations: it, converged: false };
        }
        let alpha = rz / curvature;
        x.iter_mut().zip(&p).for_each(|(x, p)| *x += alpha * p);
        r.iter_mut().zip(&ap).for_each(|(r, ap)| *r -= alpha * ap);
        z.copy_from_slice(&r);
        precondition(&mut z);
        let rz_next = dot(&r, &z);
        if rz_next <= target {
            return PcgOutcome { iterations: it, converged: true };
        }
        let beta = rz_next / rz;
        p.iter_mut().zip(&z).for_each(|(p, z)| *p = z + beta * *p);
        rz = rz_next;
    }
    PcgOutcome { iterations: max_iterations, converged: false }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tridiagonal SPD matrix of order n with diagonal `d` and off-diagonal −1.
    fn tridiagonal(n: usize, d: impl Fn(usize) -> f64) -> (SparsityPattern, Vec<f64>) {
        let (mut col_ptr, mut row_idx, mut values) = (vec![0u32], Vec::new(), Vec::new());
        for j in 0..n {
            row_idx.push(j as u32);
            values.push(d(j));
            if j + 1 < n {
                row_idx.push(j as u32 + 1);
                values.push(-1.0);
            }
            col_ptr.push(row_idx.len() as u32);
        }
        (SparsityPattern { n, col_ptr, row_idx }, values)
    }

    fn residual(p: &SparsityPattern, v: &[f64], x: &[f64], b: &[f64]) -> f64 {
        let mut ax = vec![0.0; b.len()];
        p.symmetric_times(v, x, &mut ax);
        ax.iter().zip(b).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max)
    }

    #[test]
    fn plain_cg_solves_in_at_most_n_iterations() {
        let (p, v) = tridiagonal(30, |_| 3.0);
        let b: Vec<f64> = (0..30).map(|i| (i as f64).cos()).collect();
        let mut x = vec![0.0; 30];
        let out = pcg(&p, &v, &b, &mut x, |_| {}, 1e-12, 30);
        assert!(out.converged && out.iterations <= 30, "{out:?}");
        assert!(residual(&p, &v, &x, &b) < 1e-10);
    }

    #[test]
    fn an_exact_preconditioner_of_a_nearby_matrix_needs_about_rank_plus_one_iterations() {
        // K₀ diagonal-dominant; K = K₀ with two diagonal entries raised a thousandfold (two
        // contact springs closing): preconditioned by K₀'s exact inverse (here via a Jacobi-free
        // dense solve), CG needs about three iterations whatever n is.
        let n = 40;
        let (p0, v0) = tridiagonal(n, |_| 4.0);
        let (p, v) = tridiagonal(n, |j| if j == 7 || j == 23 { 4000.0 } else { 4.0 });
        let solve0 = |r: &mut [f64]| {
            // Thomas algorithm for K₀.
            let (mut c, mut d) = (vec![0.0; n], r.to_vec());
            c[0] = -1.0 / v0[0];
            d[0] /= v0[0];
            for i in 1..n {
                let m = v0[p0.col_ptr[i] as usize] + c[i - 1];
                c[i] = -1.0 / m;
                d[i] = (d[i] + d[i - 1]) / m;
            }
            r[n - 1] = d[n - 1];
            for i in (0..n - 1).rev() {
                r[i] = d[i] - c[i] * r[i + 1];
            }
        };
        let b: Vec<f64> = (0..n).map(|i| 1.0 + (i as f64 * 0.3).sin()).collect();
        let mut x = vec![0.0; n];
        let out = pcg(&p, &v, &b, &mut x, solve0, 1e-12, 50);
        assert!(out.converged && out.iterations <= 4, "{out:?}");
        assert!(residual(&p, &v, &x, &b) < 1e-9 * 4000.0);
    }

    #[test]
    fn an_indefinite_matrix_is_reported_unconverged() {
        let (p, v) = tridiagonal(5, |j| if j == 2 { -3.0 } else { 3.0 });
        let b = vec![0.0, 0.0, 1.0, 0.0, 0.0];
        let mut x = vec![0.0; 5];
        let out = pcg(&p, &v, &b, &mut x, |_| {}, 1e-12, 50);
        assert!(!out.converged, "{out:?}");
    }

    #[test]
    fn a_zero_right_hand_side_gives_zero_at_once() {
        let (p, v) = tridiagonal(4, |_| 3.0);
        let mut x = vec![1.0; 4];
        let out = pcg(&p, &v, &[0.0; 4], &mut x, |_| {}, 1e-12, 10);
        assert_eq!(out, PcgOutcome { iterations: 0, converged: true });
        assert_eq!(x, vec![0.0; 4]);
    }
}
