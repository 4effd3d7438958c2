//! Partial refactorisation: the contact equations ordered last, so an open–close iteration
//! refactorises only the factor's trailing block.
//!
//! Within a step, the open–close iterations change only the contact springs; the elastic
//! tangent and the mass stay. With the equations the springs touch (B) ordered after all
//! others (I), the factor of A = [A_II A_IB; A_BI A_BB] is [L_II 0; L_BI L_BB] where L_II and
//! L_BI depend on A_II and A_BI alone, and L_BB L_BBᵀ = A_BB − L_BI L_BIᵀ (the Schur complement,
//! George and Liu 1981, §2.3; the Delassus idea of nonsmooth contact dynamics with the elastic
//! factor kept, Jean 1999). A matrix A′ equal to the last fully factorised A₀ outside A_BB is
//! refactorised on its trailing block alone: M = A′_BB − U with U = L_BI L_BIᵀ = A₀_BB − L₀_BB
//! L₀_BBᵀ computed once per full factorisation, M = L′ L′ᵀ. A solve then runs the full factor's
//! forward substitution, swaps the trailing block (r = L₀_BB y_B, M z = r, y_B = L₀_BBᵀ z) and
//! runs its back substitution.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltError;
use faer::sparse::linalg::cholesky::supernodal::{SupernodalLltRef, SymbolicSupernodalCholesky};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use crate::assembly::SparsityPattern;

/// The trailing block of a factor whose last equations are the contact equations.
pub struct ContactBlock {
    /// Equations ordered before the block (the factor's order).
    n_interior: usize,
    /// Entries of the permuted matrix in the interior columns (a prefix of its values).
    prefix: usize,
    /// The block's pattern: the factor's trailing columns (lower, block-local numbering),
    /// closed under elimination, so M's factor has it too.
    pattern: SparsityPattern,
    /// For each entry of `pattern`, its index in the full factor's values.
    from_factor: Vec<u32>,
    /// `pattern` by rows.
    rows: Rows,
    /// For each matrix entry from `prefix` on, its position in `pattern`.
    from_matrix: Vec<u32>,
    symbolic: SymbolicCholesky<u32>,
    /// The interior columns of the last fully factorised matrix.
    interior: Vec<f64>,
    /// Its trailing block A₀_BB, and the factor's L₀_BB (on `pattern`).
    a0: Vec<f64>,
    l0: Vec<f64>,
    /// U = A₀_BB − L₀_BB L₀_BBᵀ, once a partial factorisation needed it.
    update: Option<Vec<f64>>,
    /// M and its factor.
    m: Vec<f64>,
    values: Vec<f64>,
    scratch: MemBuffer,
    solve_scratch: Option<MemBuffer>,
    /// The last factorisation was partial.
    active: bool,
    /// A full factorisation was made since the last [`ContactBlock::new_step`].
    ready: bool,
    /// Partial factorisations so far.
    pub partials: u64,
}

impl ContactBlock {
    /// The block of the last `lower.n − n_interior` equations of a supernodal factor of the
    /// permuted lower triangle `lower`.
    pub fn new(full: &SymbolicSupernodalCholesky<u32>, lower: &SparsityPattern, n_interior: usize) -> Option<Self> {
        let (pattern, from_factor) = trailing_pattern(full, n_interior);
        let prefix = lower.col_ptr[n_interior] as usize;
        let from_matrix = (n_interior..lower.n)
            .flat_map(|j| (lower.col_ptr[j] as usize..lower.col_ptr[j + 1] as usize).map(move |e| (j, e)))
            .map(|(j, e)| position(&pattern, lower.row_idx[e] as usize - n_interior, j - n_interior))
            .collect::<Option<Vec<u32>>>()?;
        let up = transpose(&pattern);
        let sym = SymbolicSparseColMatRef::new_checked(up.n, up.n, &up.col_ptr, None, &up.row_idx);
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        };
        let symbolic = factorize_symbolic_cholesky(sym, Side::Upper, SymmetricOrdering::Identity, params).ok()?;
        let scratch = MemBuffer::new(symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()));
        let nnz = pattern.nnz();
        Some(Self {
            n_interior,
            prefix,
            values: vec![0.0; symbolic.len_val()],
            rows: Rows::of(&pattern),
            pattern,
            from_factor,
            from_matrix,
            symbolic,
            interior: Vec::new(),
            a0: vec![0.0; nnz],
            l0: vec![0.0; nnz],
            update: None,
            m: vec![0.0; nnz],
            scratch,
            solve_scratch: None,
            active: false,
            ready: false,
            partials: 0,
        })
    }

    /// Equations in the block.
    pub fn len(&self) -> usize {
        self.pattern.n
    }


    /// The next factorisation is full (a step's first: a resumed run re-makes it exactly).
    pub fn new_step(&mut self) {
        self.ready = false;
    }

    /// The full factor of `matrix` (permuted values) was just made: keep what a partial one needs.
    pub fn after_full(&mut self, matrix: &[f64], factor: &[f64]) {
        self.interior.clear();
        self.interior.extend_from_slice(&matrix[..self.prefix]);
        self.scatter(&matrix[self.prefix..]);
        std::mem::swap(&mut self.a0, &mut self.m);
        for (l, &at) in self.l0.iter_mut().zip(&self.from_factor) {
            *l = factor[at as usize];
        }
        (self.update, self.active, self.ready) = (None, false, true);
    }

    /// Refactorise the block of `matrix` (permuted values) if it equals the last full one
    /// outside the block: `None` if it does not; a non-positive pivot's equation (factor order).
    pub fn partial(&mut self, matrix: &[f64]) -> Option<Result<(), usize>> {
        if !self.ready || matrix[..self.prefix] != self.interior[..] {
            self.active = false;
            return None;
        }
        if self.update.is_none() {
            self.update = Some(self.schur_update());
        }
        self.scatter(&matrix[self.prefix..]);
        let update = self.update.as_ref().expect("made above");
        for (m, u) in self.m.iter_mut().zip(update) {
            *m -= u;
        }
        let p = &self.pattern;
        let sym = SymbolicSparseColMatRef::new_checked(p.n, p.n, &p.col_ptr, None, &p.row_idx);
        let result = self.symbolic.factorize_numeric_llt::<f64>(
            &mut self.values,
            SparseColMatRef::new(sym, &self.m),
            Side::Lower,
            Default::default(),
            Par::Seq,
            MemStack::new(&mut self.scratch),
            Default::default(),
        );
        self.active = result.is_ok();
        self.partials += u64::from(self.active);
        Some(result.map(|_| ()).map_err(|e| {
            let LltError::NonPositivePivot { index } = e;
            self.n_interior + index
        }))
    }

    /// Solve in place (`x` in the factor's order) with the full factor `factor` and, after a
    /// partial factorisation, the block's; false if the last factorisation was full (the
    /// caller solves on the full factor alone).
    pub fn solve(&mut self, full: &SymbolicSupernodalCholesky<u32>, factor: &[f64], x: &mut [f64]) -> bool {
        if !self.active {
            return false;
        }
        let n = x.len();
        let need = full.solve_in_place_scratch::<f64>(1, Par::Seq).or(self.symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        let mem = self.solve_scratch.get_or_insert_with(|| MemBuffer::new(need));
        let l = SupernodalLltRef::<'_, u32, f64>::new(full, factor);
        l.l_solve_with_conj(Conj::No, MatMut::from_column_major_slice_mut(x, n, 1), Par::Seq, MemStack::new(mem));
        let yb = &mut x[self.n_interior..];
        let mut r = lower_times(&self.pattern, &self.l0, yb);
        let nb = r.len();
        LltRef::<'_, u32, f64>::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut r, nb, 1),
            Par::Seq,
            MemStack::new(mem),
        );
        upper_times(&self.pattern, &self.l0, &r, yb);
        l.l_transpose_solve_with_conj(Conj::No, MatMut::from_column_major_slice_mut(x, n, 1), Par::Seq, MemStack::new(mem));
        true
    }

    /// `m` = the block entries (from `prefix` on) of a permuted matrix, on `pattern`.
    fn scatter(&mut self, block: &[f64]) {
        self.m.iter_mut().for_each(|m| *m = 0.0);
        for (&at, v) in self.from_matrix.iter().zip(block) {
            self.m[at as usize] += v;
        }
    }

    /// U = A₀_BB − L₀_BB L₀_BBᵀ on `pattern` (L Lᵀ's pattern lies in it: the factor's graph is
    /// chordal), column by column: column c gathers L[c.., k] L[c, k] over the columns k with
    /// an entry in row c (`rows`), each a suffix of column k, in a dense work vector.
    fn schur_update(&self) -> Vec<f64> {
        let (p, l) = (&self.pattern, &self.l0);
        let mut u = self.a0.clone();
        let mut work = vec![0.0; p.n];
        for c in 0..p.n {
            for &(k, at) in &self.rows.row_idx[self.rows.col_ptr[c] as usize..self.rows.col_ptr[c + 1] as usize] {
                let lck = l[at as usize];
                for e in at as usize..p.col_ptr[k as usize + 1] as usize {
                    work[p.row_idx[e] as usize] += l[e] * lck;
                }
            }
            for e in p.col_ptr[c] as usize..p.col_ptr[c + 1] as usize {
                let r = p.row_idx[e] as usize;
                u[e] -= work[r];
                work[r] = 0.0;
            }
        }
        u
    }
}

/// For each row of a lower pattern, its entries as (column, index), columns ascending.
struct Rows {
    col_ptr: Vec<u32>,
    row_idx: Vec<(u32, u32)>,
}

impl Rows {
    fn of(p: &SparsityPattern) -> Self {
        let mut col_ptr = vec![0u32; p.n + 1];
        for &r in &p.row_idx {
            col_ptr[r as usize + 1] += 1;
        }
        for c in 0..p.n {
            col_ptr[c + 1] += col_ptr[c];
        }
        let mut next = col_ptr[..p.n].to_vec();
        let mut row_idx = vec![(0u32, 0u32); p.row_idx.len()];
        for k in 0..p.n {
            for e in p.col_ptr[k] as usize..p.col_ptr[k + 1] as usize {
                let r = p.row_idx[e] as usize;
                row_idx[next[r] as usize] = (k as u32, e as u32);
                next[r] += 1;
            }
        }
        Self { col_ptr, row_idx }
    }
}

/// The trailing columns (from `n_interior`) of a supernodal factor: their lower pattern in
/// block-local numbering and where each entry sits in the factor's values.
fn trailing_pattern(full: &SymbolicSupernodalCholesky<u32>, n_interior: usize) -> (SparsityPattern, Vec<u32>) {
    let n = full.nrows();
    let (mut col_ptr, mut row_idx, mut from) = (vec![0u32], Vec::new(), Vec::new());
    let (begin, end) = (full.supernode_begin(), full.supernode_end());
    let offsets = full.col_ptr_for_val();
    for s in 0..full.n_supernodes() {
        let (start, stop) = (begin[s] as usize, end[s] as usize);
        if stop <= n_interior {
            continue;
        }
        let pattern = full.supernode(s).pattern();
        let rows = stop - start + pattern.len();
        for j in start.max(n_interior)..stop {
            let column = offsets[s] as usize + (j - start) * rows;
            for r in j..stop {
                row_idx.push((r - n_interior) as u32);
                from.push((column + r - start) as u32);
            }
            for (i, &r) in pattern.iter().enumerate() {
                row_idx.push(r - n_interior as u32);
                from.push((column + stop - start + i) as u32);
            }
            col_ptr.push(row_idx.len() as u32);
        }
    }
    (SparsityPattern { n: n - n_interior, col_ptr, row_idx }, from)
}

/// Index of entry (row, col) in a lower pattern.
fn position(p: &SparsityPattern, row: usize, col: usize) -> Option<u32> {
    let (lo, hi) = (p.col_ptr[col] as usize, p.col_ptr[col + 1] as usize);
    let at = p.row_idx[lo..hi].binary_search(&(row as u32)).ok()?;
    Some((lo + at) as u32)
}

/// The upper triangle of a lower pattern (its transpose).
fn transpose(p: &SparsityPattern) -> SparsityPattern {
    let mut col_ptr = vec![0u32; p.n + 1];
    for &r in &p.row_idx {
        col_ptr[r as usize + 1] += 1;
    }
    for c in 0..p.n {
        col_ptr[c + 1] += col_ptr[c];
    }
    let mut next = col_ptr[..p.n].to_vec();
    let mut row_idx = vec![0u32; p.row_idx.len()];
    for j in 0..p.n {
        for &r in &p.row_idx[p.col_ptr[j] as usize..p.col_ptr[j + 1] as usize] {
            row_idx[next[r as usize] as usize] = j as u32;
            next[r as usize] += 1;
        }
    }
    SparsityPattern { n: p.n, col_ptr, row_idx }
}

/// L y for a lower-triangular L on pattern `p`.
fn lower_times(p: &SparsityPattern, l: &[f64], y: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; p.n];
    for (j, &yj) in y.iter().enumerate() {
        for e in p.col_ptr[j] as usize..p.col_ptr[j + 1] as usize {
            out[p.row_idx[e] as usize] += l[e] * yj;
        }
    }
    out
}

/// `out` = Lᵀ z for a lower-triangular L on pattern `p`.
fn upper_times(p: &SparsityPattern, l: &[f64], z: &[f64], out: &mut [f64]) {
    for (j, o) in out.iter_mut().enumerate() {
        let range = p.col_ptr[j] as usize..p.col_ptr[j + 1] as usize;
        *o = range.map(|e| l[e] * z[p.row_idx[e] as usize]).sum();
    }
}
