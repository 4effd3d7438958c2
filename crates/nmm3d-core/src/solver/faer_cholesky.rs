//! Supernodal sparse Cholesky (faer) with a fill-reducing ordering (METIS nested dissection
//! for large systems, faer's AMD otherwise, or whichever of the two makes the smaller factor).
//! The symbolic factorisation is computed once and reused for every numeric factorisation while
//! the pattern holds; so is the pattern permuted into the factor's order (`permuted.rs`), into
//! which each factorisation gathers the values.
//! A pattern that changes only inside the factor's stored structure (contact pairs whose
//! entries are fill already) is adopted without a new analysis: fill is monotone and a filled
//! graph eliminates without fill (the path theorem, Rose, Tarjan and Lueker 1976), so such a
//! matrix fills nothing beyond the structure; only the gather map is remade.
//! Factorisations of much work are made on the run's threads, others on one
//! ([`super::factor_work::PARALLEL_FACTOR_FLOPS`]); the results do not depend on the thread count
//! (tested bit for bit). Where a factorisation
//! costs many triangular solves it is made in single precision and each solve refined to double
//! precision on it (`single.rs`; `analysis.factor_precision`).

use std::time::Instant;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltError;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::SymbolicSparseColMatRef;
use faer::{Conj, MatMut, Par, Side};

use super::factor_work::{column_flops, factor_par, supernode_flops};
use super::ordering::{amd, nested_dissection, Permutation};
use super::permuted::Permuted;
use super::single::{numeric_llt, SingleFactor};
use super::{LinearSolver, SolverFailure};
use crate::assembly::SparsityPattern;
use crate::scenario::{FactorPrecision, Ordering};

/// With `factor_precision = "auto"`, a factorisation is made in single precision from this
/// cost in PCG iterations on its factor ([`LinearSolver::factorization_cost`]) [-]: a refined
/// solve takes about 6 iterations where a double factor's takes one. Goodman's tunnel (cost
/// 21), alone: its factorisations and their solves 23.4 s → 14.8 s; the Yade-matched dominos
/// (cost 5.6) ran 30 % longer on single factors (under load; docs/factor-precision.md).
const SINGLE_FROM: f64 = 12.0;

/// The share of a factorisation's cost a single-precision one saves (Goodman's tunnel, alone:
/// 1.58× faster, 1 − 1/1.58; 1.44–1.59× since its kernels flush subnormals) [-]. With `"auto"`
/// the next factorisation is made in single precision only while the last factor's solves cost
/// fewer extra iterations than that: a run at rest solves many times on each factor (the thesis
/// tunnel at rest: 56 refinement iterations per factor, 13 % slower on single factors), a moving
/// rock mass once or twice.
const SINGLE_SAVES: f64 = 0.35;

/// Refinement iterations a solve on a single factor takes beyond the double factor's one, as
/// measured (Goodman's tunnel: 6.3 per factor) [-]: the estimate for a double factor's solves.
const EXTRA_PER_SOLVE: f64 = 5.0;

/// faer's sparse LLᵀ.
#[derive(Default)]
pub struct FaerCholesky {
    choice: Ordering,
    precision: FactorPrecision,
    /// The single-precision factor, when the last factorisation made one.
    single: SingleFactor,
    in_single: bool,
    /// Single precision failed on this analysis (a pivot, or refinement that did not
    /// converge): its factorisations are made in double precision.
    double_only: bool,
    /// Uses of the last factor (solves, and preconditioner applications on a double one), and
    /// the refinement iterations counted when it was made.
    solves_on_factor: u64,
    iterations_at_factor: u64,
    symbolic: Option<SymbolicCholesky<u32>>,
    /// The pattern in the factor's order, with the map from the source's entries.
    permuted: Option<Permuted>,
    /// The matrix's values in that order (kept between factorisations).
    gathered: Vec<f64>,
    /// A right-hand side in that order (kept between solves).
    permuted_rhs: Vec<f64>,
    /// The factor's values (double precision; empty while single-precision factors serve).
    values: Vec<f64>,
    /// Scratch of the numeric factorisation, kept: it is large for supernodal factors, and a
    /// fresh one per factorisation (every open–close iteration) costs its page clearing.
    scratch: Option<MemBuffer>,
    /// Scratch of the triangular solves, kept likewise.
    solve_scratch: Option<MemBuffer>,
    ordering: Option<&'static str>,
    /// The supernode of each column of the factor (factor order).
    supernode_of: Vec<u32>,
    /// The pattern the analysis was made of, kept once another pattern was adopted on it.
    analysed: Option<SparsityPattern>,
    /// A numeric factorisation on the analysis, in triangular-solve flops ([`factor_flops`]).
    factor_flops: f64,
    /// A numeric factorisation's work on the analysis ([`column_flops`]): whether it runs on
    /// the run's threads.
    work: f64,
    symbolic_seconds: f64,
    numeric_seconds: f64,
}

impl FaerCholesky {
    /// A solver using the given ordering choice.
    pub fn new(choice: Ordering) -> Self {
        Self { choice, ..Self::default() }
    }

    /// The same with the precision of its numeric factorisations.
    pub fn with_precision(self, precision: FactorPrecision) -> Self {
        Self { precision, ..self }
    }

    /// Whether the next factorisation is made in single precision.
    fn wants_single(&self) -> bool {
        !self.double_only
            && match self.precision {
                FactorPrecision::Double => false,
                FactorPrecision::Single => true,
                FactorPrecision::Auto => self
                    .factorization_cost()
                    .is_some_and(|c| c >= SINGLE_FROM && self.extra_iterations() <= SINGLE_SAVES * c),
            }
    }

    /// What the last factor's solves cost in iterations beyond one each: counted on a single
    /// factor, estimated on a double one (0 before the first).
    fn extra_iterations(&self) -> f64 {
        let solves = self.solves_on_factor as f64;
        match self.in_single {
            true => (self.single.iterations - self.iterations_at_factor) as f64 - solves,
            false => EXTRA_PER_SOLVE * solves,
        }
    }

    /// Solve in place on the single-precision factor, refined to double precision; false if the
    /// refinement did not converge — then the factor is made again in double precision (and
    /// stays so on this analysis), `rhs` untouched.
    fn solve_refined(&mut self, rhs: &mut [f64], tolerance: f64) -> bool {
        let (s, q) = self.symbolic.as_ref().zip(self.permuted.as_ref()).expect("factorize before solve");
        let x = &mut self.permuted_rhs;
        x.resize(rhs.len(), 0.0);
        q.permute_into(rhs, x);
        // Unconverged, the solve leaves x as it came: the right-hand side, for what follows.
        if self.single.solve(s, (&q.lower, &self.gathered), x, (tolerance, false)) {
            q.unpermute_into(x, rhs);
            return true;
        }
        self.double_only = true;
        if self.factorize_double().is_ok() {
            return false;
        }
        // Not positive definite in double precision where it was in single (round-off at the
        // edge): the refined iterate, the best there is.
        self.in_single = true;
        let (s, q) = self.symbolic.as_ref().zip(self.permuted.as_ref()).expect("analysed");
        let x = &mut self.permuted_rhs;
        self.single.solve(s, (&q.lower, &self.gathered), x, (tolerance, true));
        q.unpermute_into(x, rhs);
        true
    }

    /// Solve in place on the double-precision factor.
    fn solve_double(&mut self, rhs: &mut [f64]) {
        let n = rhs.len();
        let (s, q) = self.symbolic.as_ref().zip(self.permuted.as_ref()).expect("factorize before solve");
        let need = s.solve_in_place_scratch::<f64>(1, Par::Seq);
        let mem = self.solve_scratch.get_or_insert_with(|| MemBuffer::new(need));
        let x = &mut self.permuted_rhs;
        x.resize(n, 0.0);
        q.permute_into(rhs, x);
        LltRef::<'_, u32, f64>::new(s, &self.values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(x, n, 1),
            Par::Seq,
            MemStack::new(mem),
        );
        q.unpermute_into(x, rhs);
    }

    /// The numeric factorisation of the gathered values in double precision.
    fn factorize_double(&mut self) -> Result<(), SolverFailure> {
        let (s, q) = self.symbolic.as_ref().zip(self.permuted.as_ref()).expect("analysed");
        self.in_single = false;
        self.values.resize(s.len_val(), 0.0);
        let mem = self.scratch.as_mut().expect("allocated with the symbolic factorisation");
        numeric_llt(s, &q.lower, &self.gathered, &mut self.values, (factor_par::<f64>(self.work), mem)).map_err(|e| {
            let LltError::NonPositivePivot { index } = e;
            // The index is in the fill-reducing order; report the original equation.
            SolverFailure::NotPositiveDefinite { equation: q.perm.forward[index] as usize }
        })
    }

    /// "nested dissection" or "amd" once the symbolic factorisation exists.
    pub fn ordering(&self) -> Option<&'static str> {
        self.ordering
    }

    fn analyse(&mut self, p: &SparsityPattern) -> Result<(), SolverFailure> {
        let t = Instant::now();
        let nd = nested_dissection(p, self.choice);
        let amd_too = nd.is_none() || self.choice == Ordering::Smallest;
        let mut best: Option<(&'static str, Permuted, SymbolicCholesky<u32>)> = None;
        if amd_too {
            let perm = amd(p).map_err(SolverFailure::Analysis)?;
            let (permuted, s) = symbolic(p, perm)?;
            best = Some(("amd", permuted, s));
        }
        if let Some(perm) = nd {
            let (permuted, s) = symbolic(p, perm)?;
            if best.as_ref().is_none_or(|b| s.len_val() < b.2.len_val()) {
                best = Some(("nested dissection", permuted, s));
            }
        }
        let (name, permuted, s) = best.expect("one ordering analysed");
        let work = column_flops(&s);
        self.ordering = Some(name);
        self.values = Vec::new();
        self.scratch =
            Some(MemBuffer::new(s.factorize_numeric_llt_scratch::<f64>(factor_par::<f64>(work), Default::default())));
        self.solve_scratch = None;
        self.single.reset();
        (self.in_single, self.double_only, self.solves_on_factor) = (false, false, 0);
        self.supernode_of = supernode_of(&s);
        self.factor_flops = factor_flops(&s);
        self.work = work;
        self.analysed = None;
        self.symbolic = Some(s);
        self.permuted = Some(permuted);
        self.symbolic_seconds += t.elapsed().as_secs_f64();
        Ok(())
    }

    /// Whether every entry of `p`, in the factor's order, lies in the factor's structure.
    fn holds(&self, p: &SparsityPattern) -> bool {
        let (Some(s), Some(q)) = (&self.symbolic, &self.permuted) else { return false };
        let SymbolicCholeskyRaw::Supernodal(sn) = s.raw() else { return false };
        let inv = &q.perm.inverse;
        p.n == q.lower.n
            && (0..p.n).all(|j| {
                p.row_idx[p.col_ptr[j] as usize..p.col_ptr[j + 1] as usize].iter().all(|&i| {
                    let (a, b) = (inv[i as usize], inv[j]);
                    let (row, col) = (a.max(b) as usize, a.min(b) as usize);
                    let node = self.supernode_of[col] as usize;
                    row < sn.supernode_end()[node] as usize
                        || sn.supernode(node).pattern().binary_search(&(row as u32)).is_ok()
                })
            })
    }
}

/// The time of a numeric LLᵀ in flops of a triangular solve: Σ c_j² over the factor's columns
/// (c_j: the entries of column j, as left-looking Cholesky counts them; George and Liu 1981,
/// §2.2), in a supernode of w columns above m rows column k from its end holding k + m; a
/// supernode's dense kernels do up to [`DENSE_SPEEDUP`] of them in the time a triangular
/// solve does one, and each supernode costs [`SUPERNODE_OVERHEAD`] besides (a simplicial
/// factor, which the analysis never makes: the flops alone).
fn factor_flops(s: &SymbolicCholesky<u32>) -> f64 {
    match s.raw() {
        SymbolicCholeskyRaw::Supernodal(sn) => (0..sn.n_supernodes())
            .map(|node| {
                let w = (sn.supernode_end()[node] - sn.supernode_begin()[node]) as f64;
                supernode_flops(w, sn.supernode(node).pattern().len() as f64) / w.min(DENSE_SPEEDUP)
                    + SUPERNODE_OVERHEAD
            })
            .sum(),
        SymbolicCholeskyRaw::Simplicial(_) => column_flops(s),
    }
}

/// How many flops a supernode of that many columns and more does in the time a triangular
/// solve does one (its kernels reuse what they load). Measured (faer 0.24, 2026-11-30):
/// factorisations of 20–22 PCG iterations on the tunnels (factors of 1.7–2.4 × 10⁶ entries),
/// 80–96 by the flops alone.
const DENSE_SPEEDUP: f64 = 4.0;

/// A supernode's fixed cost in solve flops (its kernels' set-up): measured, about 3 µs on
/// the dominos' 223 supernodes, whose factorisation takes 5.6 PCG iterations, 1.3 by flops.
const SUPERNODE_OVERHEAD: f64 = 16_000.0;

/// Floating-point operations of one PCG iteration preconditioned by a factor of `factor`
/// stored entries (faer keeps a supernode's diagonal block whole), on a matrix of `lower`
/// stored entries (lower triangle) and `n` equations: two triangular solves (2 per factor
/// entry each), the symmetric product (4 per stored entry) and the vector updates.
fn iteration_flops(factor: usize, lower: usize, n: usize) -> f64 {
    4.0 * factor as f64 + 4.0 * lower as f64 + 10.0 * n as f64
}

/// The supernode of each column.
fn supernode_of(s: &SymbolicCholesky<u32>) -> Vec<u32> {
    let SymbolicCholeskyRaw::Supernodal(sn) = s.raw() else { return Vec::new() };
    let mut of = vec![0u32; sn.nrows()];
    for (node, (&b, &e)) in sn.supernode_begin().iter().zip(sn.supernode_end()).enumerate() {
        of[b as usize..e as usize].fill(node as u32);
    }
    of
}

/// The pattern permuted by `perm` and the symbolic factorisation of that order.
fn symbolic(p: &SparsityPattern, perm: Permutation) -> Result<(Permuted, SymbolicCholesky<u32>), SolverFailure> {
    let permuted = Permuted::new(p, perm);
    // faer's analysis of an unpermuted matrix reads its upper triangle.
    let up = permuted.upper();
    let sym = SymbolicSparseColMatRef::new_checked(p.n, p.n, &up.col_ptr, None, &up.row_idx);
    // Always supernodal: the matrix is made of dense 3 × 3 blocks within dense element
    // cliques, so supernodes of three columns and more always exist. faer's flop-ratio rule
    // picks the simplicial kernel for fill-free contact systems, which measured 2–3× slower
    // (dominos: 11 s → 4 s of factorisation; pile of 3000 blocks: 9.5 s → 4.3 s).
    let params = CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
        ..Default::default()
    };
    let s = factorize_symbolic_cholesky(sym, Side::Upper, SymmetricOrdering::Identity, params)
        .map_err(|e| SolverFailure::Analysis(format!("{e:?}")))?;
    Ok((permuted, s))
}

impl LinearSolver for FaerCholesky {
    fn factorize(&mut self, p: &SparsityPattern, values: &[f64]) -> Result<(), SolverFailure> {
        if self.symbolic.is_none() {
            self.analyse(p)?;
        }
        let t = Instant::now();
        let (s, q) = (self.symbolic.as_ref(), self.permuted.as_ref());
        let (s, q) = s.zip(q).expect("analysed above");
        q.gather(values, &mut self.gathered);
        let single = self.wants_single();
        (self.solves_on_factor, self.iterations_at_factor) = (0, self.single.iterations);
        self.in_single = single && self.single.factorize(s, self.work, &q.lower, &self.gathered);
        // A pivot lost in single precision: this analysis stays in double.
        self.double_only |= single && !self.in_single;
        if !self.in_single {
            self.factorize_double()?;
        }
        self.numeric_seconds += t.elapsed().as_secs_f64();
        Ok(())
    }

    fn new_pattern(&mut self) {
        (self.symbolic, self.permuted, self.scratch, self.solve_scratch) = (None, None, None, None);
        self.analysed = None;
        self.single.reset();
        self.in_single = false;
    }

    fn adopt(&mut self, p: &SparsityPattern) -> bool {
        if !self.holds(p) {
            return false;
        }
        let q = self.permuted.take().expect("held by an analysis");
        if self.analysed.is_none() {
            self.analysed = Some(q.original());
        }
        self.permuted = Some(Permuted::new(p, q.perm));
        true
    }

    fn analysed_pattern(&self, always: bool) -> Option<SparsityPattern> {
        let last = || self.permuted.as_ref().filter(|_| always).map(Permuted::original);
        self.analysed.clone().or_else(last)
    }

    fn analyse_pattern(&mut self, p: &SparsityPattern) -> Result<(), SolverFailure> {
        self.new_pattern();
        self.analyse(p)
    }

    fn solve(&mut self, rhs: &mut [f64]) {
        self.solve_to(rhs, 0.0);
    }

    fn solve_to(&mut self, rhs: &mut [f64], tolerance: f64) {
        self.solves_on_factor += 1;
        if !(self.in_single && self.solve_refined(rhs, tolerance)) {
            self.solve_double(rhs);
        }
    }

    fn precondition(&mut self, r: &mut [f64]) {
        // On a double factor a use like a solve for the precision rule: on a single one the
        // caller's PCG would take more iterations (the thesis tunnel at rest, counted so: as
        // fast as double; not counted: 13 % slower, its factors alternating).
        if !self.in_single {
            self.solves_on_factor += 1;
            return self.solve_double(r);
        }
        let (s, q) = self.symbolic.as_ref().zip(self.permuted.as_ref()).expect("factorize before solve");
        let x = &mut self.permuted_rhs;
        x.resize(r.len(), 0.0);
        q.permute_into(r, x);
        self.single.precondition(s, x);
        q.unpermute_into(x, r);
    }

    fn factor_nonzeros(&self) -> usize {
        self.symbolic.as_ref().map_or(0, |s| s.len_val())
    }

    fn single_precision(&self) -> (u64, u64) {
        (self.single.factorizations, self.single.iterations)
    }

    fn factorization_cost(&self) -> Option<f64> {
        let (s, q) = self.symbolic.as_ref().zip(self.permuted.as_ref())?;
        Some(self.factor_flops / iteration_flops(s.len_val(), q.lower.row_idx.len(), q.lower.n))
    }

    fn timings(&self) -> (f64, f64) {
        (self.symbolic_seconds, self.numeric_seconds)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chain through the equations in a scrambled order (i → 5 i mod n), so the fill-reducing
    /// order is far from the identity and from its own inverse.
    fn chain(n: usize, diagonal: impl Fn(usize) -> f64) -> (SparsityPattern, Vec<f64>) {
        let order: Vec<usize> = (0..n).map(|i| 5 * i % n).collect();
        let mut lower: Vec<Vec<usize>> = (0..n).map(|j| vec![j]).collect();
        for w in order.windows(2) {
            lower[w[0].min(w[1])].push(w[0].max(w[1]));
        }
        let (mut col_ptr, mut row_idx, mut values) = (vec![0u32], Vec::new(), Vec::new());
        for (j, mut rows) in lower.into_iter().enumerate() {
            rows.sort_unstable();
            for i in rows {
                row_idx.push(i as u32);
                values.push(if i == j { diagonal(j) } else { 0.1 });
            }
            col_ptr.push(row_idx.len() as u32);
        }
        (SparsityPattern { n, col_ptr, row_idx }, values)
    }

    /// A grid of `nx × ny × nz` covers (7-point stencil, 3 × 3 blocks), diagonally dominant.
    fn grid(nx: usize, ny: usize, nz: usize) -> (SparsityPattern, Vec<f64>) {
        let p = crate::solver::ordering::tests::grid(nx, ny, nz);
        let values = dominant(&p);
        (p, values)
    }

    /// Values on `p`: 10 on the diagonal, −0.1 elsewhere (diagonally dominant for < 100
    /// entries per column).
    fn dominant(p: &SparsityPattern) -> Vec<f64> {
        (0..p.n)
            .flat_map(|j| (p.col_ptr[j]..p.col_ptr[j + 1]).map(move |e| (j, e as usize)))
            .map(|(j, e)| if p.row_idx[e] as usize == j { 10.0 } else { -0.1 })
            .collect()
    }

    #[test]
    fn a_large_factor_made_on_several_threads_has_the_bits_of_one_made_on_one() {
        let (p, v) = grid(18, 18, 18);
        let solve = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let mut f = FaerCholesky::new(Ordering::NestedDissection);
                f.factorize(&p, &v).unwrap();
                let mut x: Vec<f64> = (0..p.n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
                f.solve(&mut x);
                (x, column_flops(f.symbolic.as_ref().expect("analysed")))
            })
        };
        let (one, work) = solve(1);
        assert!(work >= super::super::factor_work::PARALLEL_FACTOR_FLOPS, "{work:e} flops: not made in parallel");
        for threads in [2, 3] {
            let (x, _) = solve(threads);
            assert!(x.iter().zip(&one).all(|(a, b)| a.to_bits() == b.to_bits()), "{threads} threads");
        }
    }

    #[test]
    fn a_dense_factorisation_costs_its_flops_at_the_dense_kernels_speed() {
        // One supernode of n columns: Σ_{k=1..n} k² flops (left-looking count), done
        // DENSE_SPEEDUP at a time, plus one supernode's overhead; an iteration makes two
        // triangular solves on the factor as stored (the supernode's n × n block whole) and a
        // product on the matrix's n(n + 1)/2 entries.
        let n = 60;
        let p = SparsityPattern {
            n,
            col_ptr: (0..=n).map(|j| (j * n - j * j.saturating_sub(1) / 2) as u32).collect(),
            row_idx: (0..n).flat_map(|j| (j..n).map(|i| i as u32)).collect(),
        };
        let values: Vec<f64> = (0..n).flat_map(|j| (j..n).map(move |i| if i == j { n as f64 } else { 0.5 })).collect();
        let mut f = FaerCholesky::new(Ordering::Amd);
        assert_eq!(f.factorization_cost(), None, "no analysis yet");
        f.factorize(&p, &values).unwrap();
        let (nf, entries) = (n as f64, (n * (n + 1) / 2) as f64);
        let flops = nf * (nf + 1.0) * (2.0 * nf + 1.0) / 6.0;
        let iteration = 4.0 * nf * nf + 4.0 * entries + 10.0 * nf;
        let expected = (flops / DENSE_SPEEDUP + SUPERNODE_OVERHEAD) / iteration;
        let got = f.factorization_cost().unwrap();
        assert!((got - expected).abs() <= 1e-12 * expected, "{got} against {expected}");
    }

    #[test]
    fn a_factorisation_costs_more_iterations_the_more_its_factor_fills() {
        // Grids of 3 × 3 blocks as the covers make them: the factor's columns grow with the
        // grid (nested dissection's separators), its flops faster than its entries.
        let cost = |m: usize| {
            let (p, v) = grid(m, m, m);
            let mut f = FaerCholesky::new(Ordering::Amd);
            f.factorize(&p, &v).unwrap();
            f.factorization_cost().unwrap()
        };
        let costs = [cost(4), cost(8), cost(12)];
        assert!(costs.windows(2).all(|c| c[1] > c[0]), "{costs:?}");
    }

    /// The filled graph of `p` eliminated in the order `forward` (the elimination game: each
    /// eliminated node's later neighbours become a clique), as a dense symmetric table in the
    /// original numbering.
    fn filled(p: &SparsityPattern, forward: &[u32]) -> Vec<Vec<bool>> {
        let n = p.n;
        let mut g = vec![vec![false; n]; n];
        for j in 0..n {
            for &i in &p.row_idx[p.col_ptr[j] as usize..p.col_ptr[j + 1] as usize] {
                (g[i as usize][j], g[j][i as usize]) = (true, true);
            }
        }
        for (k, &node) in forward.iter().enumerate() {
            let later: Vec<usize> =
                forward[k + 1..].iter().map(|&x| x as usize).filter(|&x| g[node as usize][x]).collect();
            for &a in &later {
                for &b in &later {
                    g[a][b] = true;
                }
            }
        }
        g
    }

    #[test]
    fn a_pattern_inside_the_factor_is_adopted_and_solves_as_a_new_analysis() {
        let (p, v) = grid(4, 4, 5);
        let mut s = FaerCholesky::new(Ordering::Amd);
        s.factorize(&p, &v).expect("positive definite");
        let g = filled(&p, &s.permuted.as_ref().expect("analysed").perm.forward);
        let dofs = crate::assembly::DofMap::new(&vec![false; p.n / 3], &vec![None; p.n / 3]);
        // Inside: every fill entry of the elimination (a lower bound: faer merges small
        // supernodes, storing zeros), and those stored zeros, which must solve as exactly.
        let (mut fill, mut stored, mut outside) = (Vec::new(), Vec::new(), Vec::new());
        for (a, b) in (0..p.n / 3).flat_map(|a| (0..a).map(move |b| (a, b))) {
            if p.block_offset(a, b).is_none() {
                let grown = p.with_cliques(&dofs, [&[a, b][..]].into_iter());
                let filled = (0..9).all(|k| g[3 * a + k / 3][3 * b + k % 3]);
                assert!(!filled || s.holds(&grown), "fill of blocks ({a}, {b}) outside the factor");
                match (filled, s.holds(&grown)) {
                    (true, _) => fill.push(grown),
                    (false, true) => stored.push(grown),
                    (false, false) => outside.push(grown),
                }
            }
        }
        let counts = (fill.len(), stored.len(), outside.len());
        assert!(counts.0 > 10 && counts.1 > 0 && counts.2 > 10, "fill, stored zeros, outside: {counts:?}");
        let rhs: Vec<f64> = (0..p.n).map(|i| (i as f64).sin()).collect();
        let picks = fill.iter().step_by(fill.len() / 4).chain(stored.iter().step_by(stored.len().div_ceil(4)));
        for grown in picks {
            let values = dominant(grown);
            assert!(s.adopt(grown));
            s.factorize(grown, &values).expect("positive definite");
            let mut fresh = FaerCholesky::new(Ordering::Amd);
            fresh.factorize(grown, &values).expect("positive definite");
            let (mut x, mut y) = (rhs.clone(), rhs.clone());
            s.solve(&mut x);
            fresh.solve(&mut y);
            assert!(x.iter().zip(&y).all(|(a, b)| (a - b).abs() < 1e-14), "as a new analysis solves");
            assert_eq!(s.analysed_pattern(false), Some(p.clone()), "the analysis stays that of the first");
        }
        let before = s.permuted.as_ref().map(|q| q.lower.clone());
        assert!(!s.adopt(&outside[0]), "fill outside the factor");
        assert_eq!(s.permuted.as_ref().map(|q| q.lower.clone()), before, "nothing changed");
    }

    #[test]
    fn smallest_keeps_the_smaller_factor_of_amd_and_nested_dissection() {
        // A cube of covers (nested dissection's factor is smaller) and a long thin bar (AMD's).
        let mut winners = Vec::new();
        for (p, v) in [grid(12, 12, 12), grid(3, 3, 60)] {
            let solved = |o: Ordering| {
                let mut s = FaerCholesky::new(o);
                s.factorize(&p, &v).expect("positive definite");
                let mut x = vec![1.0; p.n];
                s.solve(&mut x);
                (s.factor_nonzeros(), s.ordering(), x)
            };
            let (amd, nd) = (solved(Ordering::Amd), solved(Ordering::NestedDissection));
            let smallest = solved(Ordering::Smallest);
            let want = if nd.0 < amd.0 { &nd } else { &amd };
            assert_eq!((smallest.0, smallest.1), (want.0, want.1), "AMD {} entries, ND {}", amd.0, nd.0);
            assert_eq!(smallest.2, want.2, "the same order solves the same way");
            winners.push(want.1);
        }
        assert_eq!(winners, [Some("nested dissection"), Some("amd")], "each ordering wins once");
    }

    #[test]
    fn a_non_positive_pivot_is_reported_at_its_own_equation() {
        for ordering in [Ordering::Amd, Ordering::NestedDissection, Ordering::Auto, Ordering::Smallest] {
            for bad in [3, 7, 11] {
                let (p, v) = chain(12, |j| if j == bad { -1.0 } else { 10.0 });
                let mut s = FaerCholesky::new(ordering);
                assert_eq!(
                    s.factorize(&p, &v),
                    Err(SolverFailure::NotPositiveDefinite { equation: bad }),
                    "{ordering:?}"
                );
            }
            let (p, v) = chain(12, |_| 10.0);
            assert_eq!(FaerCholesky::new(ordering).factorize(&p, &v), Ok(()));
        }
    }
}

#[cfg(test)]
mod single_precision_tests {
    use super::*;
    use crate::solver::ordering::tests::grid as grid_pattern;

    /// A grid of `m³` covers with a stiffness-like matrix: each entry −1 off the diagonal, the
    /// diagonal the off-diagonal count plus `shift` (a shifted graph Laplacian: its condition
    /// number grows as the shift falls).
    fn laplacian(m: usize, shift: f64) -> (SparsityPattern, Vec<f64>) {
        let p = grid_pattern(m, m, m);
        let mut degree = vec![0.0; p.n];
        for j in 0..p.n {
            for &i in &p.row_idx[p.col_ptr[j] as usize..p.col_ptr[j + 1] as usize] {
                if i as usize != j {
                    (degree[i as usize], degree[j]) = (degree[i as usize] + 1.0, degree[j] + 1.0);
                }
            }
        }
        let values = (0..p.n)
            .flat_map(|j| (p.col_ptr[j]..p.col_ptr[j + 1]).map(move |e| (j, e as usize)))
            .map(|(j, e)| if p.row_idx[e] as usize == j { degree[j] + shift } else { -1.0 })
            .collect();
        (p, values)
    }

    fn solved(precision: FactorPrecision, (p, v): &(SparsityPattern, Vec<f64>)) -> (Vec<f64>, FaerCholesky) {
        let mut f = FaerCholesky::new(Ordering::Amd).with_precision(precision);
        f.factorize(p, v).unwrap();
        let mut x: Vec<f64> = (0..p.n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        f.solve(&mut x);
        (x, f)
    }

    fn relative(a: &[f64], b: &[f64]) -> f64 {
        let norm = |v: &mut dyn Iterator<Item = f64>| v.map(|x| x * x).sum::<f64>().sqrt();
        norm(&mut a.iter().zip(b).map(|(a, b)| a - b)) / norm(&mut b.iter().copied())
    }

    #[test]
    fn a_single_precision_factor_solves_to_double_precision() {
        let m = laplacian(8, 1e-3);
        let (double, _) = solved(FactorPrecision::Double, &m);
        let (single, f) = solved(FactorPrecision::Single, &m);
        assert_eq!(f.single_precision().0, 1, "factorised in single precision");
        assert!(f.single_precision().1 >= 2, "refined: {:?}", f.single_precision());
        assert!(relative(&single, &double) < 1e-11, "{}", relative(&single, &double));
        // Without the refinement the factor's own solve is a single-precision answer.
        let mut f = f;
        let mut raw: Vec<f64> = (0..m.0.n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        f.precondition(&mut raw);
        assert!(relative(&raw, &double) > 1e-8, "{}", relative(&raw, &double));
    }

    #[test]
    fn a_matrix_singular_in_single_precision_is_factorised_in_double() {
        // [[1, 1 − δ], [1 − δ, 1]]: positive definite (eigenvalues δ and 2 − δ), but 1 − δ
        // rounds to 1 in f32 — a zero pivot.
        let delta = 1e-9;
        let p = SparsityPattern { n: 2, col_ptr: vec![0, 2, 3], row_idx: vec![0, 1, 1] };
        let v = vec![1.0, 1.0 - delta, 1.0];
        let (x, f) = solved(FactorPrecision::Single, &(p, v));
        assert_eq!(f.single_precision().0, 0);
        // b = (−6, −4): x = A⁻¹ b by Cramer's rule.
        let det = 1.0 - (1.0 - delta) * (1.0 - delta);
        let exact = [(-6.0 + 4.0 * (1.0 - delta)) / det, (-4.0 + 6.0 * (1.0 - delta)) / det];
        assert!(relative(&x, &exact) < 1e-6, "{x:?} against {exact:?}");
    }

    #[test]
    fn a_matrix_beyond_single_precision_is_solved_in_double() {
        // Entries of 10³⁹ overflow f32 (largest 3.4 × 10³⁸): whether the single factorisation
        // stops at a pivot or its refinement stalls, the solve is the double factor's.
        let (p, v) = laplacian(6, 1e-3);
        let m = (p, v.iter().map(|x| 1e39 * x).collect::<Vec<f64>>());
        let (double, _) = solved(FactorPrecision::Double, &m);
        let (single, f) = solved(FactorPrecision::Single, &m);
        assert!(f.double_only, "single precision given up on this analysis");
        assert!(relative(&single, &double) < 1e-14, "{}", relative(&single, &double));
    }

    #[test]
    fn a_matrix_below_single_precision_is_solved_as_in_double() {
        // Entries of 10⁻⁴⁴ are f32 subnormals of a few bits: whatever the single factor makes of them, the
        // solve is the double factor's.
        let (p, v) = laplacian(6, 1e-3);
        let m = (p, v.iter().map(|x| 1e-44 * x).collect::<Vec<f64>>());
        let (double, _) = solved(FactorPrecision::Double, &m);
        let (single, _) = solved(FactorPrecision::Single, &m);
        assert!(relative(&single, &double) < 1e-9, "{}", relative(&single, &double));
    }

    #[test]
    fn auto_keeps_a_factor_that_serves_many_solves_in_double_precision() {
        let (p, v) = laplacian(16, 1.0);
        let mut f = FaerCholesky::new(Ordering::Amd).with_precision(FactorPrecision::Auto);
        let mut x = vec![1.0; p.n];
        f.factorize(&p, &v).unwrap();
        assert_eq!(f.single_precision().0, 1, "the first factor in single precision");
        // Many solves on it: their refinement costs more than a double factorisation would.
        for _ in 0..40 {
            f.solve(&mut x);
        }
        f.factorize(&p, &v).unwrap();
        assert_eq!(f.single_precision().0, 1, "the next in double");
        // One solve on the double factor: single precision pays again.
        f.solve(&mut x);
        f.factorize(&p, &v).unwrap();
        assert_eq!(f.single_precision().0, 2);
    }

    #[test]
    fn auto_factorises_in_single_precision_where_a_factorisation_costs_many_solves() {
        for (m, single) in [(4, false), (16, true)] {
            let g = laplacian(m, 1.0);
            let (_, f) = solved(FactorPrecision::Auto, &g);
            let cost = f.factorization_cost().unwrap();
            assert_eq!(cost >= SINGLE_FROM, single, "grid {m}: cost {cost}");
            assert_eq!(f.single_precision().0 == 1, single, "grid {m}: cost {cost}");
        }
    }
}
