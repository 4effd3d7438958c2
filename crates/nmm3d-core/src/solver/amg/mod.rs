//! Smoothed-aggregation algebraic multigrid (Vaněk, Mandel & Brezina, *Computing* 56, 1996)
//! as the preconditioner of conjugate gradients: the iterative path for large continua, whose
//! Cholesky factor would outgrow memory (a 10⁶-ME block: 991 M entries, 8 GB).
//! The finest level's near-null space is the six rigid-body modes of the covers' nodes; each
//! level aggregates the strong couplings of its nodes, builds the tentative prolongator from
//! the modes and smooths it by one damped Jacobi step; A_c = Pᵀ A P. The coarsest level is
//! factorised. One V-cycle (a forward Gauss–Seidel sweep before the coarse correction, a
//! backward one after: symmetric) preconditions CG.
//!
//! "Factorising" builds the hierarchy; a solve runs PCG to the tolerance and, should it not
//! converge, falls back to a direct factorisation of the same matrix — never a wrong answer.

mod aggregate;
mod csr;
mod gauss_seidel;
mod prolong;

use std::time::Instant;

use super::faer_cholesky::FaerCholesky;
use super::pcg::{pcg_with, PcgOutcome};
use super::{LinearSolver, SolverFailure};
use crate::assembly::SparsityPattern;
use crate::scenario::Ordering;
use csr::Csr;
use prolong::NearNull;

/// Settings of the hierarchy and its conjugate gradients.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AmgParams {
    /// Strength threshold θ of a coupling between two nodes [-] (pyamg's default 0: all).
    pub strength: f64,
    /// A level with at most this many equations is factorised [-].
    pub coarse_size: usize,
    /// Most levels [-].
    pub max_levels: usize,
    /// ω ρ(D⁻¹A) of the prolongator's Jacobi smoothing [-] (4/3: Vaněk et al.).
    pub smoothing_weight: f64,
    /// Relative preconditioned residual at which PCG has converged [-].
    pub tolerance: f64,
    /// PCG iterations before the direct fallback [-].
    pub max_iterations: u32,
}

impl Default for AmgParams {
    fn default() -> Self {
        Self { strength: 0.0, coarse_size: 3000, max_levels: 10, smoothing_weight: 4.0 / 3.0, tolerance: 1e-8, max_iterations: 400 }
    }
}

/// One level: its operator, and the prolongator to it from the next coarser (with transpose).
struct Level {
    a: Csr,
    inv_diag: Vec<f64>,
    p: Csr,
    r: Csr,
}

/// A level's scratch for the V-cycle: its residual and the sweep's start, and the next
/// level's right-hand side and solution.
struct Work {
    residual: Vec<f64>,
    old: Vec<f64>,
    b: Vec<f64>,
    x: Vec<f64>,
}

/// Conjugate gradients preconditioned by smoothed-aggregation multigrid.
pub struct AmgSolver {
    params: AmgParams,
    /// Position of each node (three equations) of the finest level [m].
    positions: Vec<[f64; 3]>,
    levels: Vec<Level>,
    work: Vec<Work>,
    coarsest: Option<(Csr, FaerCholesky)>,
    /// PCG iterations of the solves so far, and solves that fell back to a factorisation.
    pub iterations: u64,
    /// Solves that did not converge and were factorised instead.
    pub fallbacks: u64,
    setup_seconds: f64,
    stored: usize,
}

impl AmgSolver {
    /// A solver for systems whose node i (equations 3i..3i + 3) sits at `positions[i]`.
    pub fn new(positions: Vec<[f64; 3]>, params: AmgParams) -> Self {
        Self { params, positions, levels: Vec::new(), work: Vec::new(), coarsest: None, iterations: 0, fallbacks: 0, setup_seconds: 0.0, stored: 0 }
    }

    /// Number of levels of the hierarchy (the factorised coarsest included).
    pub fn depth(&self) -> usize {
        self.levels.len() + usize::from(self.coarsest.is_some())
    }

    fn build(&mut self, mut a: Csr) -> Result<(), SolverFailure> {
        (self.levels, self.work) = (Vec::new(), Vec::new());
        let (mut block, mut b) = if self.positions.len() * 3 == a.rows {
            (3, NearNull::rigid_body(&self.positions))
        } else {
            (1, NearNull::constant(a.rows))
        };
        while a.rows > self.params.coarse_size && self.levels.len() + 1 < self.params.max_levels {
            let agg = aggregate::aggregate(&aggregate::strong_graph(&a, block, self.params.strength));
            if agg.count * b.k >= a.rows {
                break; // no coarsening left
            }
            let (t, coarse_b) = prolong::tentative(&agg, block, &b);
            let p = prolong::smooth(&a, &t, self.params.smoothing_weight);
            let r = p.transpose();
            let mut coarse = r.times_matrix(&a.times_matrix(&p));
            unit_diagonal_where_empty(&mut coarse);
            let inv_diag = inv_diagonal(&a)?;
            self.levels.push(Level { a, inv_diag, p, r });
            (a, block, b) = (coarse, coarse_b.k, coarse_b);
        }
        let (pattern, values) = a.to_lower();
        let mut direct = FaerCholesky::new(Ordering::Amd);
        direct.factorize(&pattern, &values)?;
        self.stored = self.levels.iter().map(|l| l.a.nnz() + 2 * l.p.nnz()).sum::<usize>() + direct.factor_nonzeros();
        self.coarsest = Some((a, direct));
        self.work = self
            .levels
            .iter()
            .map(|l| {
                let (n, c) = (l.a.rows, l.p.cols);
                Work { residual: vec![0.0; n], old: vec![0.0; n], b: vec![0.0; c], x: vec![0.0; c] }
            })
            .collect();
        Ok(())
    }
}

/// Rows with nothing stored get a unit diagonal: the coarse equations of zero prolongator
/// columns (dependent modes), which the correction never uses.
fn unit_diagonal_where_empty(a: &mut Csr) {
    for r in 0..a.rows {
        let (lo, hi) = (a.ptr[r], a.ptr[r + 1]);
        if a.val[lo..hi].iter().all(|&v| v == 0.0) {
            if let Ok(k) = a.idx[lo..hi].binary_search(&(r as u32)) {
                a.val[lo + k] = 1.0;
            }
        }
    }
}

fn inv_diagonal(a: &Csr) -> Result<Vec<f64>, SolverFailure> {
    a.diagonal()
        .iter()
        .enumerate()
        .map(|(r, &d)| if d > 0.0 { Ok(1.0 / d) } else { Err(SolverFailure::NotPositiveDefinite { equation: r }) })
        .collect()
}

/// PCG on the matrix `times` applies, preconditioned by one V-cycle, from x = 0.
fn pcg(
    (levels, work, coarse): (&[Level], &mut [Work], &mut FaerCholesky),
    params: &AmgParams,
    times: impl FnMut(&[f64], &mut [f64]),
    b: &[f64],
    x: &mut [f64],
) -> PcgOutcome {
    let mut z = vec![0.0; b.len()];
    let precondition = |r: &mut [f64]| {
        vcycle(levels, work, coarse, r, &mut z);
        r.copy_from_slice(&z);
    };
    pcg_with(times, b, x, precondition, params.tolerance, params.max_iterations)
}

/// x ≈ A⁻¹ b on the first of `levels` by one V-cycle from x = 0 (`coarse`: the factor below).
fn vcycle(levels: &[Level], work: &mut [Work], coarse: &mut FaerCholesky, b: &[f64], x: &mut [f64]) {
    let (Some((level, below)), Some((w, rest))) = (levels.split_first(), work.split_first_mut()) else {
        x.copy_from_slice(b);
        coarse.solve(x);
        return;
    };
    x.fill(0.0);
    gauss_seidel::sweep(&level.a, &level.inv_diag, b, x, &mut w.old, false);
    level.a.times(x, &mut w.residual);
    w.residual.iter_mut().zip(b).for_each(|(r, b)| *r = b - *r);
    level.r.times(&w.residual, &mut w.b);
    vcycle(below, rest, coarse, &w.b, &mut w.x);
    level.p.add_times(&w.x, x);
    gauss_seidel::sweep(&level.a, &level.inv_diag, b, x, &mut w.old, true);
}

impl LinearSolver for AmgSolver {
    fn factorize(&mut self, pattern: &SparsityPattern, values: &[f64]) -> Result<(), SolverFailure> {
        let t = Instant::now();
        self.build(Csr::from_lower(pattern, values))?;
        self.setup_seconds += t.elapsed().as_secs_f64();
        Ok(())
    }

    fn new_pattern(&mut self) {}

    fn solve(&mut self, rhs: &mut [f64]) {
        let (levels, coarse) = (&self.levels, &mut self.coarsest.as_mut().expect("factorize before solve").1);
        let Some(finest) = levels.first().map(|l| &l.a) else {
            coarse.solve(rhs);
            return;
        };
        let mut x = vec![0.0; rhs.len()];
        let hierarchy = (levels.as_slice(), self.work.as_mut_slice(), coarse);
        let out = pcg(hierarchy, &self.params, |v, out| finest.times(v, out), rhs, &mut x);
        self.iterations += u64::from(out.iterations);
        if out.converged {
            rhs.copy_from_slice(&x);
            return;
        }
        // Not converged: the same matrix factorised (a solver must not return a wrong answer);
        // one that is not positive definite leaves NaN, which fails the step.
        self.fallbacks += 1;
        let (p, v) = finest.to_lower();
        let mut direct = FaerCholesky::new(Ordering::Auto);
        match direct.factorize(&p, &v) {
            Ok(()) => direct.solve(rhs),
            Err(_) => rhs.fill(f64::NAN),
        }
    }

    fn solve_nearby(&mut self, p: &SparsityPattern, values: &[f64], rhs: &mut [f64]) -> Option<PcgOutcome> {
        let (levels, coarse) = (&self.levels, &mut self.coarsest.as_mut()?.1);
        if levels.is_empty() {
            return None;
        }
        let mut x = vec![0.0; rhs.len()];
        let hierarchy = (levels.as_slice(), self.work.as_mut_slice(), coarse);
        let out = pcg(hierarchy, &self.params, |v, out| p.symmetric_times(values, v, out), rhs, &mut x);
        self.iterations += u64::from(out.iterations);
        if out.converged {
            rhs.copy_from_slice(&x);
        }
        Some(out)
    }

    fn name(&self) -> &'static str {
        "amg"
    }

    fn iterations(&self) -> u64 {
        self.iterations
    }

    fn factor_nonzeros(&self) -> usize {
        self.stored
    }

    fn timings(&self) -> (f64, f64) {
        (0.0, self.setup_seconds)
    }
}
