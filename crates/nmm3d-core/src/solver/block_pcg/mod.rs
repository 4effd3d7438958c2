//! Conjugate gradients preconditioned by the blocks themselves, for rock masses of many blocks
//! (`linear_solver = "blocks"`): a two-level preconditioner whose subdomains are the blocks.
//! Each block's own equations (its covers, with the contact springs' diagonal parts) are solved
//! exactly by one sparse Cholesky factor of the block-diagonal part B of A; the coarse space is
//! the blocks' rigid motions, Φ (six columns per block: three translations and three rotations
//! about its centroid), with A_c = Φᵀ A Φ factorised too. Jointed blocks are stiff beside their
//! joints, so the system's softest modes are the blocks moving as rigid bodies against each
//! other: exactly what Φ spans. The two levels are combined symmetrically (the balancing form of
//! Mandel 1993, *Commun. Numer. Methods Eng.* 9; Toselli and Widlund 2005, §2.5.2):
//!
//!   M⁻¹ r = Q r + (I − Q A) B⁻¹ (I − A Q) r,   Q = Φ A_c⁻¹ Φᵀ,
//!
//! symmetric positive definite when A is. Unlike a direct factor of the whole web of blocks,
//! whose fill grows as N^(4/3) and its work as N² (the top separators of a three-dimensional
//! web are dense), B's factor holds each block alone and A_c has six equations per block.
//! "Factorising" makes both factors; a solve runs PCG to the tolerance and, should it not
//! converge, factorises the whole matrix instead — never a wrong answer.

mod layout;

use std::time::Instant;

use nmm3d_geom::Vec3;

use super::faer_cholesky::FaerCholesky;
use super::pcg::{pcg_with, PcgOutcome};
use super::{LinearSolver, SolverFailure};
use crate::assembly::SparsityPattern;
use crate::scenario::{FactorPrecision, Ordering};
use layout::{phi_row, Layout};

/// Settings of the block-preconditioned conjugate gradients.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlockParams {
    /// Relative preconditioned residual at which PCG has converged [-].
    pub tolerance: f64,
    /// PCG iterations before the whole matrix is factorised instead [-].
    pub max_iterations: u32,
}

impl Default for BlockParams {
    fn default() -> Self {
        Self { tolerance: 1e-10, max_iterations: 200 }
    }
}

/// The preconditioner: the blocks' factor and the coarse factor, with the coarse space.
struct TwoLevel {
    /// Block of each node (three equations) [-].
    node_block: Vec<u32>,
    /// Each node's position relative to its block's centroid, over the block's size [-].
    arms: Vec<Vec3>,
    /// Each equation's row of Φ ([`phi_row`]).
    phi: Vec<[f64; 6]>,
    /// The nodes' positions `arms` were made of, and those the factors were made at [m].
    positions: Vec<Vec3>,
    built_at: Vec<Vec3>,
    local: FaerCholesky,
    coarse: FaerCholesky,
}

/// Conjugate gradients preconditioned by the blocks and their rigid motions.
pub struct BlockPcg {
    params: BlockParams,
    pre: TwoLevel,
    layout: Option<Layout>,
    /// The matrix last "factorised" (its lower triangle on the layout's pattern).
    values: Vec<f64>,
    /// That matrix's own factor, where the coarse space failed it.
    whole: Option<FaerCholesky>,
    /// PCG iterations so far.
    pub iterations: u64,
    /// Solves that did not converge and were factorised instead.
    pub fallbacks: u64,
    setup_seconds: f64,
}

impl BlockPcg {
    /// A solver for systems whose node i (equations 3i..3i + 3) belongs to block
    /// `node_block[i]` and sits at `positions[i]` [m].
    pub fn new(node_block: Vec<u32>, positions: &[Vec3], params: BlockParams) -> Self {
        // Blocks numbered by their nodes (a fixed block has none, and no columns in Φ).
        let mut number = std::collections::BTreeMap::new();
        for &b in &node_block {
            let next = number.len() as u32;
            number.entry(b).or_insert(next);
        }
        let node_block: Vec<u32> = node_block.iter().map(|b| number[b]).collect();
        let direct = || FaerCholesky::new(Ordering::Amd).with_precision(FactorPrecision::Double);
        let pre = TwoLevel {
            node_block,
            arms: Vec::new(),
            phi: Vec::new(),
            positions: Vec::new(),
            built_at: Vec::new(),
            local: direct(),
            coarse: direct(),
        };
        let mut s = Self {
            params,
            pre,
            layout: None,
            values: Vec::new(),
            whole: None,
            iterations: 0,
            fallbacks: 0,
            setup_seconds: 0.0,
        };
        s.pre.moved(positions);
        s
    }

    /// Make both factors of the matrix `values` on `p`.
    fn setup(&mut self, p: &SparsityPattern, values: &[f64]) -> Result<(), SolverFailure> {
        let pre = &mut self.pre;
        if pre.node_block.len() * 3 != p.n {
            let nodes = pre.node_block.len();
            return Err(SolverFailure::Analysis(format!("{} equations for {nodes} nodes of three", p.n)));
        }
        if self.layout.as_ref().is_none_or(|l| l.pattern != *p) {
            let layout = Layout::new(p, &pre.node_block);
            if self.layout.as_ref().is_none_or(|l| l.local != layout.local) {
                pre.local.new_pattern();
            }
            if self.layout.as_ref().is_none_or(|l| l.coarse != layout.coarse) {
                pre.coarse.new_pattern();
            }
            self.layout = Some(layout);
        }
        let layout = self.layout.as_mut().expect("made above");
        let mut local = vec![0.0; layout.local.nnz()];
        for (k, &l) in layout.local_of.iter().enumerate().filter(|(_, l)| **l != u32::MAX) {
            local[l as usize] = values[k];
        }
        pre.local.factorize(&layout.local, &local)?;
        layout.fill_a_phi(values, &pre.phi);
        pre.built_at.clone_from(&pre.positions);
        let coarse = layout.coarse_values(&pre.node_block, &pre.phi);
        self.values.clear();
        self.values.extend_from_slice(values);
        self.whole = None;
        if pre.coarse.factorize(&layout.coarse, &coarse).is_err() {
            // A block whose nodes do not span its rotations (collinear) makes A_c singular:
            // this matrix is solved by its own factor instead.
            self.fallbacks += 1;
            self.whole = Some(whole(p, values)?);
        }
        Ok(())
    }

    /// The same matrix factorised whole, for a solve PCG did not finish (a matrix that is not
    /// positive definite leaves NaN, which fails the step).
    fn fall_back(&mut self, rhs: &mut [f64]) {
        self.fallbacks += 1;
        let Some(layout) = self.layout.as_ref() else { return rhs.fill(f64::NAN) };
        match whole(&layout.pattern, &self.values) {
            Ok(mut direct) => direct.solve(rhs),
            Err(_) => rhs.fill(f64::NAN),
        }
    }
}

impl BlockPcg {
    /// PCG on the preconditioner of the last setup for the matrix `matrix` (`None`: that
    /// setup's own) to `tolerance`; `rhs` holds the solution if it converged. `None` before
    /// any setup.
    fn iterate(
        &mut self,
        matrix: Option<(&SparsityPattern, &[f64])>,
        rhs: &mut [f64],
        tolerance: f64,
    ) -> Option<PcgOutcome> {
        let layout = self.layout.as_ref()?;
        let (p, v) = matrix.unwrap_or((&layout.pattern, &self.values));
        let mut x = vec![0.0; rhs.len()];
        let tol = (tolerance, self.params.max_iterations);
        let out = self.pre.pcg((layout, |u: &[f64], out: &mut [f64]| p.symmetric_times(v, u, out)), rhs, &mut x, tol);
        self.iterations += u64::from(out.iterations);
        if out.converged {
            rhs.copy_from_slice(&x);
        }
        Some(out)
    }
}

/// The matrix `values` on `p` factorised whole (double precision, the automatic ordering).
fn whole(p: &SparsityPattern, values: &[f64]) -> Result<FaerCholesky, SolverFailure> {
    let mut direct = FaerCholesky::new(Ordering::Auto).with_precision(FactorPrecision::Double);
    direct.factorize(p, values)?;
    Ok(direct)
}

impl TwoLevel {
    /// The nodes moved to `positions`: the rotations of the coarse space turn about the blocks'
    /// current centroids (from the next factorisation on).
    fn moved(&mut self, positions: &[Vec3]) {
        let blocks = self.node_block.iter().map(|&b| b as usize + 1).max().unwrap_or(0);
        let (mut sum, mut count) = (vec![Vec3::zeros(); blocks], vec![0.0; blocks]);
        for (&b, x) in self.node_block.iter().zip(positions) {
            sum[b as usize] += x;
            count[b as usize] += 1.0;
        }
        let centre: Vec<Vec3> = sum.iter().zip(&count).map(|(s, &c)| if c > 0.0 { s / c } else { *s }).collect();
        let mut size = vec![0.0f64; blocks];
        for (&b, x) in self.node_block.iter().zip(positions) {
            size[b as usize] = size[b as usize].max((x - centre[b as usize]).norm());
        }
        // Over the block's size, so that rotations and translations weigh alike in A_c.
        self.arms = (self.node_block.iter().zip(positions))
            .map(|(&b, x)| match size[b as usize] {
                s if s > 0.0 => (x - centre[b as usize]) / s,
                _ => Vec3::zeros(),
            })
            .collect();
        self.phi = (0..3 * self.arms.len()).map(|e| phi_row(&self.arms[e / 3], e % 3)).collect();
        self.positions = positions.to_vec();
    }

    /// Φᵀ v: per block, the force and the moment (over the block's size) of the nodes' `v`.
    fn restrict(&self, v: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for (i, (&b, arm)) in self.node_block.iter().zip(&self.arms).enumerate() {
            let f = Vec3::new(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
            let m = arm.cross(&f);
            let o = &mut out[6 * b as usize..6 * b as usize + 6];
            (0..3).for_each(|k| (o[k], o[k + 3]) = (o[k] + f[k], o[k + 3] + m[k]));
        }
    }

    /// v += Φ c: each node moved by its block's translation and rotation.
    fn prolong_add(&self, c: &[f64], v: &mut [f64]) {
        for (i, (&b, arm)) in self.node_block.iter().zip(&self.arms).enumerate() {
            let o = &c[6 * b as usize..6 * b as usize + 6];
            let u = Vec3::new(o[0], o[1], o[2]) + Vec3::new(o[3], o[4], o[5]).cross(arm);
            (0..3).for_each(|k| v[3 * i + k] += u[k]);
        }
    }

    /// Solve A x = b by PCG on this preconditioner (made with `layout`'s AΦ), A given by `times`.
    fn pcg(
        &mut self,
        (layout, times): (&Layout, impl Fn(&[f64], &mut [f64])),
        b: &[f64],
        x: &mut [f64],
        tol: (f64, u32),
    ) -> PcgOutcome {
        let (n, a_phi) = (b.len(), &layout.a_phi);
        let (mut c, mut w, mut t) = (vec![0.0; layout.coarse.n], vec![0.0; layout.coarse.n], vec![0.0; n]);
        // M⁻¹ r = Q r + (I − QA) B⁻¹ (I − AQ) r = y + Φ (c − A_c⁻¹ (AΦ)ᵀ y), with c = A_c⁻¹ Φᵀ r and
        // y = B⁻¹ (r − AΦ c): A enters only through AΦ, made with the factors.
        let precondition = |r: &mut [f64]| {
            self.restrict(r, &mut c);
            self.coarse.solve(&mut c);
            a_phi.times(&c, &mut t);
            t.iter_mut().zip(r.iter()).for_each(|(t, r)| *t = r - *t);
            self.local.solve(&mut t);
            a_phi.transpose_times(&t, &mut w);
            self.coarse.solve(&mut w);
            w.iter_mut().zip(&c).for_each(|(w, c)| *w = c - *w);
            r.copy_from_slice(&t);
            self.prolong_add(&w, r);
        };
        pcg_with(&times, b, x, precondition, tol.0, tol.1)
    }
}

impl LinearSolver for BlockPcg {
    fn factorize(&mut self, pattern: &SparsityPattern, values: &[f64]) -> Result<(), SolverFailure> {
        let t = Instant::now();
        let made = self.setup(pattern, values);
        self.setup_seconds += t.elapsed().as_secs_f64();
        made
    }

    fn new_pattern(&mut self) {}

    fn solve(&mut self, rhs: &mut [f64]) {
        if let Some(whole) = self.whole.as_mut() {
            return whole.solve(rhs);
        }
        match self.iterate(None, rhs, self.params.tolerance) {
            Some(out) if out.converged => {}
            _ => self.fall_back(rhs),
        }
    }

    fn solve_nearby(
        &mut self,
        p: &SparsityPattern,
        values: &[f64],
        rhs: &mut [f64],
        tolerance: f64,
    ) -> Option<PcgOutcome> {
        if self.whole.is_some() || p.n != self.pre.node_block.len() * 3 {
            return None;
        }
        self.iterate(Some((p, values)), rhs, tolerance)
    }

    fn moved(&mut self, positions: &dyn Fn() -> Vec<Vec3>) {
        self.pre.moved(&positions());
    }

    fn built_at(&self) -> &[Vec3] {
        &self.pre.built_at
    }

    fn name(&self) -> &'static str {
        "blocks"
    }

    fn exact(&self) -> bool {
        false
    }

    fn iterations(&self) -> u64 {
        self.iterations
    }

    fn factor_nonzeros(&self) -> usize {
        self.pre.local.factor_nonzeros() + self.pre.coarse.factor_nonzeros()
    }

    fn timings(&self) -> (f64, f64) {
        (0.0, self.setup_seconds)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::pcg::pcg;
    use std::collections::BTreeMap;

    /// A row of `blocks` cubes of 2 × 2 × 2 nodes (unit spacing, 1.5 apart along x): inside each
    /// cube every pair of nodes is joined by an axial spring of stiffness 1 (a truss: stiff in
    /// every deformation, free in rigid motion); neighbouring cubes by axial springs of
    /// stiffness `joint` across the gap between facing nodes; each node held by a spring
    /// `mass` in every direction (the inertia of a dynamic step). The lower triangle, the
    /// nodes' blocks and positions.
    fn row_of_cubes(blocks: usize, joint: f64, mass: f64) -> (SparsityPattern, Vec<f64>, Vec<u32>, Vec<Vec3>) {
        let corner =
            |b: usize, c: usize| Vec3::new(2.5 * b as f64 + (c & 1) as f64, ((c >> 1) & 1) as f64, (c >> 2) as f64);
        let (mut at, mut block) = (Vec::new(), Vec::new());
        for b in 0..blocks {
            for c in 0..8 {
                at.push(corner(b, c));
                block.push(b as u32);
            }
        }
        let mut dense = BTreeMap::<(usize, usize), f64>::new();
        let mut spring = |a: usize, b: usize, k: f64| {
            let d = (at[b] - at[a]).normalize();
            for i in 0..3 {
                for j in 0..3 {
                    let v = k * d[i] * d[j];
                    for (r, c, s) in [
                        (3 * a + i, 3 * a + j, v),
                        (3 * b + i, 3 * b + j, v),
                        (3 * a + i, 3 * b + j, -v),
                        (3 * b + i, 3 * a + j, -v),
                    ] {
                        if r >= c {
                            *dense.entry((c, r)).or_insert(0.0) += s;
                        }
                    }
                }
            }
        };
        for b in 0..blocks {
            for p in 0..8 {
                for q in p + 1..8 {
                    spring(8 * b + p, 8 * b + q, 1.0);
                }
                if b + 1 < blocks && p & 1 == 1 {
                    spring(8 * b + p, 8 * (b + 1) + (p - 1), joint);
                }
            }
        }
        for e in 0..3 * at.len() {
            *dense.entry((e, e)).or_insert(0.0) += mass;
        }
        let n = 3 * at.len();
        let (mut col_ptr, mut row_idx, mut values) = (vec![0u32], Vec::new(), Vec::new());
        for j in 0..n {
            for (&(_, r), &v) in dense.range((j, j)..(j, n)) {
                row_idx.push(r as u32);
                values.push(v);
            }
            col_ptr.push(row_idx.len() as u32);
        }
        (SparsityPattern { n, col_ptr, row_idx }, values, block, at)
    }

    /// A block solver of `params` set up on `v` and its solution of A x = `b`.
    fn solved(
        params: BlockParams,
        (p, v, block, at): (&SparsityPattern, &[f64], Vec<u32>, &[Vec3]),
        b: &[f64],
    ) -> (BlockPcg, Vec<f64>) {
        let mut s = BlockPcg::new(block, at, params);
        s.factorize(p, v).unwrap();
        let mut x = b.to_vec();
        s.solve(&mut x);
        (s, x)
    }

    fn rhs(n: usize) -> Vec<f64> {
        (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0 + 0.1 * i as f64).collect()
    }

    fn direct(p: &SparsityPattern, v: &[f64], b: &[f64]) -> Vec<f64> {
        let mut f = FaerCholesky::new(Ordering::Amd);
        f.factorize(p, v).unwrap();
        let mut x = b.to_vec();
        f.solve(&mut x);
        x
    }

    fn relative(a: &[f64], b: &[f64]) -> f64 {
        let d: f64 = a.iter().zip(b).map(|(a, b)| (a - b).powi(2)).sum();
        (d / b.iter().map(|b| b * b).sum::<f64>()).sqrt()
    }

    #[test]
    fn the_coarse_matrix_is_phi_transpose_a_phi() {
        let (p, v, block, at) = row_of_cubes(3, 0.3, 0.01);
        let mut s = BlockPcg::new(block, &at, BlockParams::default());
        s.factorize(&p, &v).unwrap();
        let (layout, pre) = (s.layout.as_ref().unwrap(), &s.pre);
        // Φ column by column (Φ e_k), A Φ by products, Φᵀ A Φ by restriction.
        let (n, m) = (p.n, layout.coarse.n);
        let mut want = vec![vec![0.0; m]; m];
        for k in 0..m {
            let (mut e, mut col, mut a_col, mut out) = (vec![0.0; m], vec![0.0; n], vec![0.0; n], vec![0.0; m]);
            e[k] = 1.0;
            pre.prolong_add(&e, &mut col);
            p.symmetric_times(&v, &col, &mut a_col);
            pre.restrict(&a_col, &mut out);
            want[k] = out;
        }
        let got = layout.coarse_values(&pre.node_block, &pre.phi);
        let c = &layout.coarse;
        for j in 0..m {
            for k in c.col_ptr[j] as usize..c.col_ptr[j + 1] as usize {
                let i = c.row_idx[k] as usize;
                assert!((got[k] - want[i][j]).abs() <= 1e-12 * (1.0 + want[i][j].abs()), "({i}, {j})");
            }
        }
        // Every nonzero of Φᵀ A Φ in the lower triangle is stored.
        let stored: usize = (0..m).map(|i| (0..=i).filter(|&j| want[i][j].abs() > 1e-14).count()).sum();
        assert!(c.nnz() >= stored);
    }

    #[test]
    fn the_block_preconditioned_solve_equals_the_direct_one() {
        let (p, v, block, at) = row_of_cubes(6, 1e-3, 1e-4);
        let b = rhs(p.n);
        let (s, x) = solved(BlockParams::default(), (&p, &v, block, &at), &b);
        assert!(relative(&x, &direct(&p, &v, &b)) < 1e-8);
        assert_eq!(s.fallbacks, 0);
        assert!(s.iterations <= 10, "{} iterations", s.iterations);
    }

    #[test]
    fn the_blocks_rigid_motions_are_what_block_jacobi_alone_misses() {
        // Thirty stiff cubes on soft joints: block Jacobi (each cube's own equations solved
        // exactly) leaves the row's slow rigid motions to CG; the coarse space solves them.
        let (p, v, block, at) = row_of_cubes(30, 1e-3, 1e-5);
        let b = rhs(p.n);
        let (mut s, x) = solved(BlockParams::default(), (&p, &v, block, &at), &b);
        let two_level = s.iterations;
        let mut y = vec![0.0; p.n];
        let local = &mut s.pre.local;
        let jacobi = pcg(&p, &v, &b, &mut y, |r| local.solve(r), 1e-10, 2000);
        assert!(jacobi.converged && relative(&y, &x) < 1e-7);
        assert!(two_level <= 12 && jacobi.iterations >= 4 * two_level as u32, "{two_level} against {jacobi:?}");
    }

    #[test]
    fn a_block_of_one_node_has_no_rotations_and_still_preconditions() {
        // The last cube's last node taken as a block of its own: its rotations move nothing.
        let (p, v, mut block, at) = row_of_cubes(3, 1e-2, 1e-4);
        *block.last_mut().unwrap() = 3;
        let b = rhs(p.n);
        let (s, x) = solved(BlockParams::default(), (&p, &v, block, &at), &b);
        assert!(s.whole.is_none() && s.fallbacks == 0);
        assert!(relative(&x, &direct(&p, &v, &b)) < 1e-8);
    }

    #[test]
    fn a_solve_that_does_not_converge_is_factorised_instead() {
        let (p, v, block, at) = row_of_cubes(4, 1e-3, 1e-4);
        let b = rhs(p.n);
        let (s, x) = solved(BlockParams { max_iterations: 1, ..BlockParams::default() }, (&p, &v, block, &at), &b);
        assert_eq!(s.fallbacks, 1);
        assert!(relative(&x, &direct(&p, &v, &b)) < 1e-12);
    }

    #[test]
    fn rotated_blocks_keep_their_rigid_motions_in_the_coarse_space() {
        // The same row turned by a quarter turn about z and moved: built at the new positions,
        // the coarse space holds each cube's rotations about its own centroid again.
        let (p, v, block, at) = row_of_cubes(2, 0.1, 1e-3);
        let turn = nalgebra::Rotation3::new(Vec3::new(0.0, 0.0, std::f64::consts::FRAC_PI_2));
        let moved: Vec<Vec3> = at.iter().map(|x| turn * x + Vec3::new(3.0, -1.0, 2.0)).collect();
        let mut s = BlockPcg::new(block, &at, BlockParams::default());
        s.moved(&|| moved.clone());
        let rigid: Vec<f64> = moved
            .iter()
            .flat_map(|x| {
                let u = Vec3::new(0.0, 0.0, 1.0).cross(&(x - moved[..8].iter().sum::<Vec3>() / 8.0));
                [u.x, u.y, u.z]
            })
            .collect();
        // A rotation of the first cube about its centroid (and nothing of the second) is Φ c.
        let mut c = vec![0.0; 12];
        let size = moved[..8].iter().map(|x| (x - moved[..8].iter().sum::<Vec3>() / 8.0).norm()).fold(0.0, f64::max);
        c[5] = size;
        let mut u = vec![0.0; p.n];
        s.pre.prolong_add(&c, &mut u);
        assert!(relative(&u[..24], &rigid[..24]) < 1e-12 && u[24..].iter().all(|x| *x == 0.0));
        assert_eq!(s.built_at(), &[] as &[Vec3], "nothing factorised yet");
        s.factorize(&p, &v).unwrap();
        assert_eq!(s.built_at(), moved.as_slice());
    }
}
