//! Factorise rarely: a system whose matrix differs little from the last one factorised (the
//! next Newton iteration of a static equilibrium, the next step of a continuum) is solved by
//! PCG with that factor as the preconditioner ([`super::pcg`]); only when PCG does not reach
//! its tolerance within its iteration budget is the matrix factorised again. A factor that
//! needed more than half the budget is renewed at the next solve to the full tolerance (one
//! needed only roughly is still made on it).
//!
//! The caller says whether a matrix may be near the last one (`nearby`): contact springs that
//! close, open or start sliding between two solves are stiff changes of high rank (measured on
//! the thesis slope: 2 300–2 700 of 3 800 points change state in a step's first open–close
//! iteration, and PCG did not converge in 200 iterations), and PCG's small residual moves the
//! gaps on which the open–close rules decide (the dominos took twice the iterations). So a
//! matrix with closed contact springs is factorised (`docs/theory/solver.md`) — unless it is
//! close to the factor's own matrix entry by entry (`closeness`): the same contact states and
//! penalties, a co-rotated tangent turned by round-off, as in a block system at rest. Such
//! solves are weighed against a new factorisation (the ski-rental rule, Karlin et al. 1988):
//! once the PCG iterations spent on them since the factor was made cost as much as making it
//! ([`LinearSolver::factorization_cost`]), the next one is factorised — the rule that pays at
//! most twice the best choice made in hindsight when renting (iterating) goes on until buying
//! (factorising).
//!
//! The result depends on which matrix the factor was made of, so that matrix is part of the
//! run's state ([`FactorSnapshot`]): a resumed run re-makes the same factor and continues bit
//! for bit.

use serde::{Deserialize, Serialize};

use super::pcg::pcg;
use super::{LinearSolver, SolverFailure};
use crate::assembly::SparsityPattern;

/// When and how an earlier factor is reused (`[analysis]` keys).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FactorReuse {
    /// Reuse at all (`factor_reuse`); false: every solve factorises.
    pub enabled: bool,
    /// Relative preconditioned residual at which PCG has converged [-] (`krylov_tolerance`).
    pub tolerance: f64,
    /// PCG iterations before the matrix is factorised instead (`krylov_max_iterations`).
    pub max_iterations: u32,
    /// Largest entrywise difference, relative to the factor's largest entry, at which any
    /// matrix is near the factor's (`factor_reuse_closeness`; 0: never by closeness).
    pub closeness: f64,
}

/// How one system was solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Solved {
    /// By a new factorisation.
    Factorized,
    /// By PCG on the last factor, in this many iterations.
    Krylov(u32),
    /// By the last factor, made of this very matrix (one solve, exact).
    OwnFactor,
}

/// The matrix the current factor was made of.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FactorSource {
    /// Its pattern (lower triangle).
    pub pattern: SparsityPattern,
    /// Its values on that pattern.
    #[serde(with = "crate::packed")]
    pub values: Vec<f64>,
    /// It was of the kind that the next matrices are near (no contact springs): any `nearby`
    /// matrix may be solved on it; otherwise only one close to it entry by entry.
    #[serde(default = "default_true")]
    pub nearby: bool,
}

/// `true` (serde default).
fn default_true() -> bool {
    true
}

/// A [`ReusingSolver`]'s state as data (checkpoints).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct FactorSnapshot {
    /// The matrix of the factor in use (`None`: no reusable factor).
    pub source: Option<FactorSource>,
    /// The pattern of the symbolic analysis in use, when not the source's (adopted patterns).
    #[serde(default)]
    pub analysed: Option<SparsityPattern>,
    /// The next solve factorises.
    pub renew: bool,
    /// The pattern changed since the last factorisation (checkpoints before it: assumed).
    #[serde(default = "default_true")]
    pub pattern_changed: bool,
    /// PCG iterations spent on matrices only close to the factor's since it was made.
    #[serde(default)]
    pub spent: u64,
    /// Counters so far.
    pub counts: SolveCounts,
    /// The node positions the source's preconditioner was built at, x, y, z per node (solvers
    /// built on the model's geometry, `linear_solver = "blocks"`; empty otherwise) [m].
    #[serde(default, with = "crate::packed")]
    pub geometry: Vec<f64>,
}

/// What the solver did so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct SolveCounts {
    /// Numeric factorisations.
    pub factorizations: u64,
    /// Systems solved by PCG on an earlier factor.
    pub krylov_solves: u64,
    /// PCG iterations, those of unconverged attempts included.
    pub krylov_iterations: u64,
    /// PCG attempts that did not converge (the matrix was factorised instead).
    pub krylov_failures: u64,
    /// Changed patterns factorised on the symbolic analysis of an earlier one.
    #[serde(default)]
    pub patterns_adopted: u64,
}

/// A direct solver whose factor is reused by PCG while it preconditions well.
pub struct ReusingSolver {
    direct: Box<dyn LinearSolver>,
    reuse: FactorReuse,
    source: Option<FactorSource>,
    /// The pattern changed since the factor was made (the next factorisation re-analyses).
    pattern_changed: bool,
    renew: bool,
    /// PCG iterations on matrices only close to the factor's since it was made: once they
    /// cost a factorisation, the next such matrix is factorised.
    spent: u64,
    /// The largest |value| of the source, once a closeness test needed it (a pass over the
    /// whole matrix per solve otherwise).
    scale: Option<f64>,
    /// What the solver did so far.
    pub counts: SolveCounts,
}

impl ReusingSolver {
    /// Reuse `direct`'s factors as `reuse` says.
    pub fn new(direct: Box<dyn LinearSolver>, reuse: FactorReuse) -> Self {
        let counts = SolveCounts::default();
        Self { direct, reuse, source: None, pattern_changed: false, renew: false, spent: 0, scale: None, counts }
    }

    /// The values of the matrix the current factor (or hierarchy) was made of, on its pattern.
    pub fn source_values(&self) -> Option<&[f64]> {
        self.source.as_ref().map(|s| s.values.as_slice())
    }

    /// Solve A x = `rhs` in place (A's lower triangle `values` on `pattern`); `nearby`: A may
    /// be solved by PCG on the last factor, if that factor's matrix was `nearby` too.
    pub fn solve(
        &mut self,
        pattern: &SparsityPattern,
        values: &[f64],
        rhs: &mut [f64],
        nearby: bool,
    ) -> Result<Solved, SolverFailure> {
        self.solve_to(pattern, values, rhs, nearby, self.reuse.tolerance)
    }

    /// [`Self::solve`], a PCG solve on the last factor ending at the relative `tolerance` (at
    /// least `krylov_tolerance`) instead: for a right-hand side needed only roughly.
    pub fn solve_to(
        &mut self,
        pattern: &SparsityPattern,
        values: &[f64],
        rhs: &mut [f64],
        nearby: bool,
        tolerance: f64,
    ) -> Result<Solved, SolverFailure> {
        if self.is_source(values) {
            // PCG would only confirm the factor's own solve (a step's equilibrium corrections
            // on the matrix its last trial factorised): one solve and a product fewer. A factor
            // in single precision refines it only to `tolerance`.
            self.direct.solve_to(rhs, tolerance);
            return Ok(Solved::OwnFactor);
        }
        let nearby_kind = self.source.as_ref().is_some_and(|s| nearby && s.nearby);
        let close = !nearby_kind && self.close_to_source(values);
        // A factor due for renewal still serves a solve needed only roughly (a step's
        // equilibrium correction, to 10⁻⁴): a few PCG iterations against a factorisation
        // (the sliding thesis tunnel: 44 of 204 factorisations in 0.3 s were made for these).
        // The renewal waits for the next solve to the full tolerance.
        let rough = tolerance > self.reuse.tolerance;
        if (nearby_kind || close) && (!self.renew || rough) {
            let tolerance = tolerance.max(self.reuse.tolerance);
            if let Some(iterations) = self.solve_on_factor(pattern, values, rhs, (tolerance, close)) {
                return Ok(Solved::Krylov(iterations));
            }
        }
        self.factorize(pattern, values, nearby)?;
        self.direct.solve(rhs);
        Ok(Solved::Factorized)
    }

    /// Solve in place by iterations on the last factor: the solver's own (multigrid), else PCG
    /// preconditioned by the factor. Their iterations if they converged; `None` (counted a
    /// failure, `rhs` untouched) if not. `close`: the matrix is only close to the factor's
    /// (contact springs), and its iterations are weighed against a new factorisation.
    fn solve_on_factor(
        &mut self,
        pattern: &SparsityPattern,
        values: &[f64],
        rhs: &mut [f64],
        (tol, close): (f64, bool),
    ) -> Option<u32> {
        let converged = match self.direct.solve_nearby(pattern, values, rhs, tol) {
            Some(out) => out.converged.then_some(out.iterations),
            None => {
                let mut x = vec![0.0; rhs.len()];
                let direct = &mut self.direct;
                let max = self.reuse.max_iterations;
                let out = pcg(pattern, values, rhs, &mut x, |r| direct.precondition(r), tol, max);
                self.counts.krylov_iterations += u64::from(out.iterations);
                self.renew |= out.converged && 2 * out.iterations > max;
                if close {
                    self.spent += u64::from(out.iterations);
                    self.renew |= self.direct.factorization_cost().is_some_and(|c| self.spent as f64 >= c);
                }
                out.converged.then(|| {
                    rhs.copy_from_slice(&x);
                    out.iterations
                })
            }
        };
        match converged {
            Some(_) => self.counts.krylov_solves += 1,
            None => self.counts.krylov_failures += 1,
        }
        converged
    }

    /// Factorise and solve, and have the next solve factorise again (a matrix unlike the
    /// ones that follow, e.g. the mass matrix of the initial accelerations).
    pub fn solve_once(
        &mut self,
        pattern: &SparsityPattern,
        values: &[f64],
        rhs: &mut [f64],
    ) -> Result<(), SolverFailure> {
        self.factorize(pattern, values, false)?;
        self.direct.solve(rhs);
        Ok(())
    }

    /// Whether `values` are those the factor was made of (on its pattern), and the factor
    /// solves them exactly.
    fn is_source(&self, values: &[f64]) -> bool {
        self.direct.exact() && self.source.as_ref().is_some_and(|s| !self.pattern_changed && s.values == values)
    }

    /// Whether `values` (on the factor's pattern) are within the closeness of the factor's.
    fn close_to_source(&mut self, values: &[f64]) -> bool {
        let Some(s) = self.source.as_ref().filter(|s| !self.pattern_changed && s.values.len() == values.len()) else {
            return false;
        };
        if self.reuse.closeness <= 0.0 {
            return false;
        }
        let scale = *self.scale.get_or_insert_with(|| s.values.iter().fold(0.0f64, |m, v| m.max(v.abs())));
        let limit = self.reuse.closeness * scale;
        s.values.iter().zip(values).all(|(a, b)| (a - b).abs() <= limit)
    }

    /// Factorise; keep the matrix as the source of reused solves (marked whether it is of the
    /// `nearby` kind).
    fn factorize(&mut self, pattern: &SparsityPattern, values: &[f64], nearby: bool) -> Result<(), SolverFailure> {
        let same_pattern = !self.pattern_changed;
        if self.pattern_changed {
            if self.direct.adopt(pattern) {
                self.counts.patterns_adopted += 1;
            } else {
                self.direct.new_pattern();
            }
            self.pattern_changed = false;
        }
        // A failed factorisation leaves no usable factor.
        let old = self.source.take();
        self.scale = None;
        self.direct.factorize(pattern, values)?;
        self.counts.factorizations += 1;
        (self.renew, self.spent) = (false, 0);
        // Kept whatever its kind: a system on this very matrix is solved on the factor.
        if self.reuse.enabled {
            self.source = Some(match old {
                Some(mut s) if same_pattern && s.values.len() == values.len() => {
                    s.values.copy_from_slice(values);
                    s.nearby = nearby;
                    s
                }
                _ => FactorSource { pattern: pattern.clone(), values: values.to_vec(), nearby },
            });
        }
        Ok(())
    }

    /// The pattern changed: the next factorisation adopts it on the current analysis if the
    /// factor's structure holds it, else re-analyses it; until then the old factor still
    /// preconditions.
    pub fn new_pattern(&mut self) {
        self.pattern_changed = true;
    }

    /// The state to save.
    pub fn snapshot(&self) -> FactorSnapshot {
        // With a source, an analysis no pattern was adopted on since is the source's own.
        let analysed = (self.direct.analysed_pattern(self.source.is_none()))
            .filter(|a| self.source.as_ref().is_none_or(|s| s.pattern != *a));
        let (source, renew, pattern_changed, spent, counts) =
            (self.source.clone(), self.renew, self.pattern_changed, self.spent, self.counts);
        let geometry = self.direct.built_at().iter().flat_map(|x| [x.x, x.y, x.z]).collect();
        FactorSnapshot { source, analysed, renew, pattern_changed, spent, counts, geometry }
    }

    /// Continue from a snapshot: re-make its analysis and factor.
    pub fn restore(&mut self, s: FactorSnapshot) -> Result<(), SolverFailure> {
        self.direct.new_pattern();
        if !s.geometry.is_empty() {
            let at: Vec<_> = s.geometry.chunks(3).map(|x| nmm3d_geom::Vec3::new(x[0], x[1], x[2])).collect();
            self.direct.moved(&|| at.clone());
        }
        if let Some(a) = &s.analysed {
            self.direct.analyse_pattern(a)?;
        }
        if let Some(src) = &s.source {
            if s.analysed.is_some() && !self.direct.adopt(&src.pattern) {
                return Err(SolverFailure::Analysis("a checkpoint's factor outside its analysis".into()));
            }
            self.direct.factorize(&src.pattern, &src.values)?;
        }
        // Without a source the last factorised pattern is unknown: adopt the next one.
        self.pattern_changed = s.pattern_changed || (s.source.is_none() && s.analysed.is_some());
        (self.source, self.renew, self.spent, self.counts, self.scale) = (s.source, s.renew, s.spent, s.counts, None);
        Ok(())
    }

    /// Stored entries of the last factor.
    pub fn factor_nonzeros(&self) -> usize {
        self.direct.factor_nonzeros()
    }

    /// Seconds spent in symbolic analysis and in numeric factorisation so far.
    pub fn timings(&self) -> (f64, f64) {
        self.direct.timings()
    }

    /// The nodes are now at `positions()` [m] (see [`LinearSolver::moved`]).
    pub fn moved(&mut self, positions: &dyn Fn() -> Vec<nmm3d_geom::Vec3>) {
        self.direct.moved(positions);
    }

    /// "direct", "amg" or "blocks".
    pub fn name(&self) -> &'static str {
        self.direct.name()
    }

    /// Iterations the linear solver made inside its own solves (multigrid PCG) so far.
    pub fn inner_iterations(&self) -> u64 {
        self.direct.iterations()
    }

    /// Factorisations made in single precision and their refinement iterations so far.
    pub fn single_precision(&self) -> (u64, u64) {
        self.direct.single_precision()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::Ordering;
    use crate::solver::FaerCholesky;

    /// A 3-D Laplacian-like SPD matrix on an m × m × m grid (7-point stencil), diagonal `d`.
    fn grid(m: usize, d: impl Fn(usize) -> f64) -> (SparsityPattern, Vec<f64>) {
        let n = m * m * m;
        let (mut col_ptr, mut row_idx, mut values) = (vec![0u32], Vec::new(), Vec::new());
        for j in 0..n {
            row_idx.push(j as u32);
            values.push(d(j));
            for step in [1, m, m * m] {
                if j + step < n
                    && (step != 1 || !(j + 1).is_multiple_of(m))
                    && (step != m || !(j / m + 1).is_multiple_of(m))
                {
                    row_idx.push((j + step) as u32);
                    values.push(-1.0);
                }
            }
            col_ptr.push(row_idx.len() as u32);
        }
        (SparsityPattern { n, col_ptr, row_idx }, values)
    }

    /// `p` with entry (row, col), row > col, added.
    fn with_entry(p: &SparsityPattern, (row, col): (usize, usize)) -> SparsityPattern {
        let mut g = p.clone();
        let at = g.col_ptr[col] as usize
            + g.row_idx[p.col_ptr[col] as usize..p.col_ptr[col + 1] as usize].partition_point(|&r| (r as usize) < row);
        g.row_idx.insert(at, row as u32);
        g.col_ptr[col + 1..].iter_mut().for_each(|c| *c += 1);
        g
    }

    fn solver(max_iterations: u32) -> ReusingSolver {
        let reuse = FactorReuse { enabled: true, tolerance: 1e-12, max_iterations, closeness: 0.0 };
        ReusingSolver::new(Box::new(FaerCholesky::new(Ordering::Amd)), reuse)
    }

    fn rhs(n: usize) -> Vec<f64> {
        (0..n).map(|i| (i as f64 * 0.7).sin() + 0.1).collect()
    }

    fn max_difference(a: &[f64], b: &[f64]) -> f64 {
        a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
    }

    #[test]
    fn a_nearby_matrix_is_solved_on_the_last_factor_as_exactly_as_by_a_new_one() {
        let (p, v0) = grid(6, |_| 6.5);
        let (_, v1) = grid(6, |j| 6.5 * (1.0 + 0.02 * (j as f64 * 0.3).cos()));
        let mut s = solver(20);
        let mut x0 = rhs(p.n);
        assert_eq!(s.solve(&p, &v0, &mut x0, true), Ok(Solved::Factorized));
        let mut x1 = rhs(p.n);
        let got = s.solve(&p, &v1, &mut x1, true).unwrap();
        // κ(K₀⁻¹K₁) ≤ 1.02/0.98: CG's bound 2((√κ − 1)/(√κ + 1))ᵏ reaches 1e-12 by k = 8.
        assert!(matches!(got, Solved::Krylov(it) if it <= 8), "{got:?}");
        let mut exact = rhs(p.n);
        solver(20).solve(&p, &v1, &mut exact, true).unwrap();
        assert!(max_difference(&x1, &exact) <= 1e-10 * exact.iter().map(|x| x.abs()).fold(0.0, f64::max));
        assert_eq!(
            s.counts,
            SolveCounts { factorizations: 1, krylov_solves: 1, ..SolveCounts::default() }.with_iterations(&got)
        );
    }

    #[test]
    fn a_factor_due_for_renewal_still_serves_a_rough_solve() {
        let (p, v0) = grid(6, |_| 6.5);
        let (_, v1) = grid(6, |j| 6.5 * (1.0 + 0.04 * (j as f64 * 0.3).cos()));
        let mut s = solver(12);
        s.solve(&p, &v0, &mut rhs(p.n), true).unwrap();
        // More than half the budget: the factor is renewed at the next solve…
        let got = s.solve(&p, &v1, &mut rhs(p.n), true).unwrap();
        assert!(matches!(got, Solved::Krylov(it) if it > 6), "{got:?}");
        // …but not for a right-hand side needed only to 10⁻⁴ (a step's equilibrium correction).
        let mut rough = rhs(p.n);
        assert!(matches!(s.solve_to(&p, &v1, &mut rough, true, 1e-4), Ok(Solved::Krylov(_))));
        let mut exact = rhs(p.n);
        solver(12).solve(&p, &v1, &mut exact, true).unwrap();
        let scale = exact.iter().map(|x| x.abs()).fold(0.0, f64::max);
        assert!(max_difference(&rough, &exact) <= 1e-3 * scale);
        assert_eq!(s.solve(&p, &v1, &mut rhs(p.n), true), Ok(Solved::Factorized), "renewed at the full tolerance");
        assert_eq!(s.counts.factorizations, 2);
    }

    #[test]
    fn a_matrix_that_is_not_nearby_or_too_far_is_factorised() {
        let (p, v0) = grid(5, |_| 6.5);
        // Near enough for PCG (a percent stiffer), but not of the nearby kind.
        let (_, v1) = grid(5, |_| 6.5 * 1.01);
        // Far: a thousandfold stiffer along many equations (contact springs closing).
        let (_, far) = grid(5, |j| if j % 3 == 0 { 6500.0 } else { 6.5 });
        let mut s = solver(4);
        s.solve(&p, &v0, &mut rhs(p.n), true).unwrap();
        assert_eq!(s.solve(&p, &v1, &mut rhs(p.n), false), Ok(Solved::Factorized), "not nearby");
        // A factor made of a matrix that was not nearby is not reused either.
        assert_eq!(s.solve(&p, &v0, &mut rhs(p.n), true), Ok(Solved::Factorized), "source not nearby");
        let mut x = rhs(p.n);
        assert_eq!(s.solve(&p, &far, &mut x, true), Ok(Solved::Factorized), "PCG gave up");
        assert_eq!(s.counts.krylov_failures, 1);
        let mut exact = rhs(p.n);
        solver(4).solve(&p, &far, &mut exact, true).unwrap();
        assert_eq!(x, exact, "the fallback is the direct solve");
    }

    #[test]
    fn the_factors_own_matrix_is_solved_on_it_once_whatever_its_kind() {
        let (p, v0) = grid(5, |_| 6.5);
        let (_, v1) = grid(5, |_| 6.5 * 1.01);
        for nearby in [false, true] {
            let mut s = solver(20);
            let mut first = rhs(p.n);
            assert_eq!(s.solve(&p, &v0, &mut first, nearby), Ok(Solved::Factorized));
            // The same matrix again: the factor's own solve, bit for bit, no PCG, no factorisation.
            let mut again = rhs(p.n);
            assert_eq!(s.solve(&p, &v0, &mut again, nearby), Ok(Solved::OwnFactor));
            assert_eq!(again, first);
            assert_eq!(s.counts, SolveCounts { factorizations: 1, ..SolveCounts::default() });
            // Another matrix is not the factor's own.
            assert_ne!(s.solve(&p, &v1, &mut rhs(p.n), nearby), Ok(Solved::OwnFactor));
        }
    }

    #[test]
    fn a_matrix_close_to_the_factors_is_solved_on_it_whatever_its_kind() {
        // Contact springs (not nearby kind), the same states a step later: the tangent moved
        // by round-off. A spring that changed moves entries far beyond the closeness.
        let (p, v0) = grid(5, |_| 6.5);
        let (_, close) = grid(5, |j| 6.5 * (1.0 + 1e-8 * (j as f64).sin()));
        let (_, apart) = grid(5, |j| 6.5 * (1.0 + 1e-3 * (j as f64).sin()));
        let reuse = FactorReuse { enabled: true, tolerance: 1e-12, max_iterations: 20, closeness: 1e-6 };
        let mut s = ReusingSolver::new(Box::new(FaerCholesky::new(Ordering::Amd)), reuse);
        assert_eq!(s.solve(&p, &v0, &mut rhs(p.n), false), Ok(Solved::Factorized));
        let mut x = rhs(p.n);
        assert!(matches!(s.solve(&p, &close, &mut x, false), Ok(Solved::Krylov(_))), "close to the factor's");
        let mut exact = rhs(p.n);
        solver(20).solve(&p, &close, &mut exact, false).unwrap();
        assert!(max_difference(&x, &exact) <= 1e-10 * exact.iter().map(|x| x.abs()).fold(0.0, f64::max));
        assert_eq!(s.solve(&p, &apart, &mut rhs(p.n), false), Ok(Solved::Factorized), "a spring changed");
    }

    #[test]
    fn close_matrices_are_solved_on_the_factor_until_their_iterations_cost_a_factorisation() {
        // Ski rental: PCG on matrices only close to the factor's (contact springs at rest)
        // until the iterations spent cost as much as a factorisation, then a factorisation.
        let (p, v0) = grid(6, |_| 6.5);
        let close = |k: usize| grid(6, |j| 6.5 * (1.0 + 1e-7 * ((j + 7 * k) as f64).sin())).1;
        let reuse = FactorReuse { enabled: true, tolerance: 1e-14, max_iterations: 50, closeness: 1e-6 };
        let new = || ReusingSolver::new(Box::new(FaerCholesky::new(Ordering::Amd)), reuse);
        let mut s = new();
        s.solve(&p, &v0, &mut rhs(p.n), false).unwrap();
        let cost = s.direct.factorization_cost().expect("a direct factor knows its cost");
        assert!(cost > 1.0, "a factorisation costs more than an iteration: {cost}");
        let (mut spent, mut refactorised, mut copy) = (0u32, 0, None);
        for k in 1..60 {
            if k == 5 {
                let snap = serde_json::to_string(&s.snapshot()).unwrap();
                let mut b = new();
                b.restore(serde_json::from_str(&snap).unwrap()).unwrap();
                copy = Some(b);
            }
            let got = s.solve(&p, &close(k), &mut rhs(p.n), false).unwrap();
            if let Some(b) = copy.as_mut() {
                assert_eq!(b.solve(&p, &close(k), &mut rhs(p.n), false), Ok(got), "restored at {k}");
            }
            match got {
                Solved::Krylov(it) => {
                    assert!(f64::from(spent) < cost, "PCG at {k} after {spent} iterations");
                    spent += it;
                }
                Solved::Factorized => {
                    assert!(f64::from(spent) >= cost, "factorised at {k} after only {spent} iterations");
                    (spent, refactorised) = (0, refactorised + 1);
                }
                Solved::OwnFactor => unreachable!("every matrix differs"),
            }
        }
        assert!(refactorised >= 2, "{refactorised} factorisations in 59 close solves (cost {cost})");
        // Matrices of the nearby kind (no contact springs) are not weighed so: their factor
        // serves until PCG needs half its budget.
        let mut s = solver(50);
        s.solve(&p, &v0, &mut rhs(p.n), true).unwrap();
        for k in 1..60 {
            assert!(matches!(s.solve(&p, &close(k), &mut rhs(p.n), true), Ok(Solved::Krylov(_))), "{k}");
        }
    }

    #[test]
    fn a_restored_snapshot_continues_bit_for_bit() {
        let (p, v0) = grid(5, |_| 6.5);
        let (_, v1) = grid(5, |j| 6.5 + 0.1 * (j as f64).sin());
        let mut a = solver(20);
        a.solve(&p, &v0, &mut rhs(p.n), true).unwrap();
        let snap: FactorSnapshot = serde_json::from_str(&serde_json::to_string(&a.snapshot()).unwrap()).unwrap();
        assert_eq!(snap, a.snapshot());
        let mut b = solver(20);
        b.restore(snap).unwrap();
        let (mut xa, mut xb) = (rhs(p.n), rhs(p.n));
        assert!(matches!(a.solve(&p, &v1, &mut xa, true), Ok(Solved::Krylov(_))));
        assert!(matches!(b.solve(&p, &v1, &mut xb, true), Ok(Solved::Krylov(_))));
        assert_eq!(xa, xb);
        assert_eq!(a.counts, b.counts);
    }

    #[test]
    fn a_restored_snapshot_factorises_adopted_patterns_on_the_same_analysis() {
        // A pattern grown by one coupling inside the factor's fill: factorised on the first
        // analysis. The checkpoint carries that analysis's pattern, so a resumed run neither
        // orders the grown pattern afresh nor rejects the next adoption.
        let (p, v0) = grid(5, |_| 6.5);
        let reuse = FactorReuse { enabled: true, tolerance: 1e-12, max_iterations: 20, closeness: 1e-6 };
        let new = || ReusingSolver::new(Box::new(FaerCholesky::new(Ordering::Amd)), reuse);
        let mut a = new();
        a.solve(&p, &v0, &mut rhs(p.n), false).unwrap();
        let mut probe = FaerCholesky::new(Ordering::Amd);
        probe.factorize(&p, &v0).unwrap();
        let grown = (0..p.n)
            .flat_map(|x| (0..x).map(move |y| (x, y)))
            .filter(|&(x, y)| p.position(x, y).is_none())
            .map(|entry| with_entry(&p, entry))
            .find(|g| probe.adopt(g))
            .expect("an entry inside the fill");
        let values = |scale: f64| -> Vec<f64> {
            (0..grown.n)
                .flat_map(|j| (grown.col_ptr[j]..grown.col_ptr[j + 1]).map(move |e| (j, e as usize)))
                .map(|(j, e)| if grown.row_idx[e] as usize == j { 6.5 * scale } else { -0.5 })
                .collect()
        };
        a.new_pattern();
        a.solve(&grown, &values(1.0), &mut rhs(p.n), false).unwrap();
        assert_eq!(a.counts.patterns_adopted, 1);
        let snap: FactorSnapshot = serde_json::from_str(&serde_json::to_string(&a.snapshot()).unwrap()).unwrap();
        assert_eq!(snap.analysed, Some(p.clone()), "the analysis's own pattern travels");
        let mut b = new();
        b.restore(snap).unwrap();
        let (mut xa, mut xb) = (rhs(p.n), rhs(p.n));
        a.solve(&grown, &values(1.3), &mut xa, false).unwrap();
        b.solve(&grown, &values(1.3), &mut xb, false).unwrap();
        assert_eq!(xa, xb);
        assert_eq!(a.counts, b.counts);
        a.new_pattern();
        b.new_pattern();
        a.solve(&p, &v0, &mut xa, false).unwrap();
        b.solve(&p, &v0, &mut xb, false).unwrap();
        assert_eq!((xa, a.counts.patterns_adopted), (xb, 2), "back to the analysed pattern: adopted");
    }

    impl SolveCounts {
        fn with_iterations(mut self, s: &Solved) -> Self {
            if let Solved::Krylov(it) = s {
                self.krylov_iterations = u64::from(*it);
            }
            self
        }
    }
}
