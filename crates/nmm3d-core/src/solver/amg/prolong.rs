//! The prolongator of smoothed aggregation (Vaněk, Mandel & Brezina 1996, §3): the tentative
//! prolongator T interpolates the near-null space (rigid-body modes on the finest level)
//! exactly on each aggregate — T Bc = B, T's columns orthonormal per aggregate — and one damped
//! Jacobi step smooths it: P = (I − ω D⁻¹ A) T with ω = 4 / (3 ρ(D⁻¹A)).

use super::aggregate::{Aggregates, ISOLATED};
use super::bsr::Bsr;
use super::csr::Csr;

/// Vectors a level's operator nearly annihilates, k per equation (rows of `values`, row-major).
#[derive(Debug, Clone, PartialEq)]
pub struct NearNull {
    /// Number of vectors.
    pub k: usize,
    /// Entry (equation i, vector c) at `values[i * k + c]`.
    pub values: Vec<f64>,
}

impl NearNull {
    /// Rigid-body modes of nodes with three displacements at `positions`: three translations
    /// and three rotations about the positions' centroid, scaled to their extent.
    pub fn rigid_body(positions: &[[f64; 3]]) -> Self {
        let n = positions.len().max(1) as f64;
        let c: [f64; 3] = std::array::from_fn(|d| positions.iter().map(|p| p[d]).sum::<f64>() / n);
        let extent =
            positions.iter().flat_map(|p| (0..3).map(move |d| (p[d] - c[d]).abs())).fold(0.0, f64::max).max(1e-300);
        let mut values = Vec::with_capacity(18 * positions.len());
        for p in positions {
            let [x, y, z] = [0, 1, 2].map(|d| (p[d] - c[d]) / extent);
            // ω × r for ω along x, y, z.
            values.extend([1.0, 0.0, 0.0, 0.0, -z, y]);
            values.extend([0.0, 1.0, 0.0, z, 0.0, -x]);
            values.extend([0.0, 0.0, 1.0, -y, x, 0.0]);
        }
        Self { k: 6, values }
    }
}

/// T and the coarse level's near-null vectors (T Bc = B): per aggregate a QR factorisation of
/// B's rows there (modified Gram–Schmidt, twice). A vector dependent on the others on an
/// aggregate (a rotation about the line of a two-node aggregate) gets a zero column.
pub fn tentative(agg: &Aggregates, block: usize, b: &NearNull) -> (Bsr<f64>, NearNull) {
    let k = b.k;
    let rows = agg.of.len() * block;
    let mut q_rows = vec![[0.0f64; 8]; rows];
    let mut coarse = vec![0.0; agg.count * k * k];
    for (a, nodes) in agg.members().iter().enumerate() {
        let eqs: Vec<usize> = nodes.iter().flat_map(|&n| (0..block).map(move |d| n as usize * block + d)).collect();
        let mut q: Vec<Vec<f64>> = (0..k).map(|c| eqs.iter().map(|&e| b.values[e * k + c]).collect()).collect();
        let r = &mut coarse[a * k * k..(a + 1) * k * k];
        for c in 0..k {
            let original = norm(&q[c]);
            for _ in 0..2 {
                for prev in 0..c {
                    let h: f64 = q[prev].iter().zip(&q[c]).map(|(u, v)| u * v).sum();
                    r[prev * k + c] += h;
                    let (done, rest) = q.split_at_mut(c);
                    rest[0].iter_mut().zip(&done[prev]).for_each(|(v, u)| *v -= h * u);
                }
            }
            let left = norm(&q[c]);
            if left > 1e-10 * original && left > 0.0 {
                r[c * k + c] = left;
                q[c].iter_mut().for_each(|v| *v /= left);
            } else {
                q[c].iter_mut().for_each(|v| *v = 0.0);
            }
        }
        for (i, &e) in eqs.iter().enumerate() {
            (0..k).for_each(|c| q_rows[e][c] = q[c][i]);
        }
    }
    let mut t = Csr { rows, cols: agg.count * k, ptr: Vec::with_capacity(rows + 1), idx: Vec::new(), val: Vec::new() };
    t.ptr.push(0);
    for (e, q) in q_rows.iter().enumerate() {
        // A node in no aggregate has no coarse modes: an empty row.
        let a = agg.of[e / block] as usize;
        if a != ISOLATED as usize {
            t.idx.extend((0..k).map(|c| (a * k + c) as u32));
            t.val.extend_from_slice(&q[..k]);
        }
        t.ptr.push(t.idx.len());
    }
    (Bsr::from_csr(&t, block, k), NearNull { k, values: coarse })
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// P = (I − ω D⁻¹ A) T, ω = `weight` / ρ(D⁻¹ A) (`inv_diag`: D⁻¹; ρ from `cycle`, the
/// V-cycle's copy of A: half the memory to stream, and an estimate needs no more digits).
pub fn smooth(a: &Bsr<f64>, cycle: &Bsr<f32>, inv_diag: &[f64], t: &Bsr<f64>, weight: f64) -> Bsr<f64> {
    let omega = weight / spectral_radius(cycle, inv_diag);
    let mut p = a.times_matrix(t);
    p.scale_rows(|r| -omega * inv_diag[r]);
    // T's pattern lies within A T's: A's diagonal blocks are stored.
    p.add_within(t);
    p
}

/// ρ(D⁻¹ A) by power iterations (D⁻¹A is similar to the symmetric D^-½ A D^-½): 20 from a
/// fixed start, 5 % added for what they miss.
fn spectral_radius(a: &Bsr<f32>, inv_diag: &[f64]) -> f64 {
    let mut x: Vec<f64> = (0..a.rows).map(|i| 1.0 + 0.5 * ((i as f64) * 0.618).sin()).collect();
    let mut y = vec![0.0; a.rows];
    let mut rho = 1.0;
    for _ in 0..20 {
        a.times(&x, &mut y);
        y.iter_mut().zip(inv_diag).for_each(|(v, d)| *v *= d);
        let n = norm(&y);
        if n == 0.0 {
            break;
        }
        rho = n / norm(&x);
        x.iter_mut().zip(&y).for_each(|(x, y)| *x = y / n);
    }
    1.05 * rho
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tentative_prolongator_reproduces_the_rigid_body_modes() {
        let positions: Vec<[f64; 3]> = (0..8).map(|i| [(i % 2) as f64, ((i / 2) % 2) as f64, (i / 4) as f64]).collect();
        let b = NearNull::rigid_body(&positions);
        // Two aggregates of four nodes (the cube's two faces z = 0 and z = 1).
        let agg = Aggregates { of: (0..8).map(|i| i / 4).collect(), count: 2 };
        let (t, bc) = tentative(&agg, 3, &b);
        assert_eq!((t.rows, t.cols, bc.k), (24, 12, 6));
        for c in 0..6 {
            let col: Vec<f64> = (0..12).map(|i| bc.values[i * 6 + c]).collect();
            let mut tb = vec![0.0; 24];
            t.times(&col, &mut tb);
            for e in 0..24 {
                assert!((tb[e] - b.values[e * 6 + c]).abs() < 1e-12, "mode {c}, equation {e}");
            }
        }
        // Orthonormal columns.
        let tt = t.transpose().times_matrix(&t).to_csr();
        for r in 0..12 {
            let (i, v) = tt.row(r);
            i.iter().zip(v).for_each(|(&j, &x)| assert!((x - if j as usize == r { 1.0 } else { 0.0 }).abs() < 1e-12));
        }
    }

    #[test]
    fn a_dependent_mode_gets_a_zero_column() {
        // Two nodes on the x axis: the rotation about x moves neither.
        let b = NearNull::rigid_body(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]);
        let (t, _) = tentative(&Aggregates { of: vec![0, 0], count: 1 }, 3, &b);
        let t = t.to_csr();
        let zero_columns = (0..6).filter(|&c| (0..6).all(|r| t.row(r).1[c] == 0.0)).count();
        assert_eq!(zero_columns, 1);
    }
}
