//! Aggregation of ill-posed covers (small cut cells).
//!
//! A physical cover whose every ME is a small piece of its sub-cell is nearly unconstrained:
//! its stiffness and mass scale with that tiny volume, the system becomes ill-conditioned and
//! the cover's displacement is dominated by round-off (and by free co-rotation of the sliver).
//! Following aggregated FEM (Badia, Verdugo & Martín 2018, "The aggregated unfitted finite
//! element method for elliptic problems", CMAME 336), an ME is *well posed* when its volume is
//! at least `threshold` × its sub-cell's (× the largest such fraction of its block, for blocks
//! smaller than a sub-cell); a cover with no well-posed ME is *tied*: its
//! displacement is the linear extrapolation, through the weight functions of the nearest
//! well-posed ME of the same block, of that ME's covers. Linear fields are still reproduced
//! exactly (patch test) and the condition number is bounded by the threshold.

use std::collections::HashMap;

use nmm3d_geom::Vec3;

use super::build::Covers;

/// How far (in cells) to look for a well-posed ME.
const SEARCH_RADIUS: i32 = 64;

/// Masters and weights of every tied cover (`None` for covers that keep their own DOFs).
pub fn tie_ill_posed(covers: &Covers, fixed_block: &[bool], threshold: f64) -> Vec<Option<Vec<(usize, f64)>>> {
    let mut tied = vec![None; covers.covers.len()];
    if threshold <= 0.0 {
        return tied;
    }
    let fraction: Vec<f64> = covers
        .elements
        .iter()
        .map(|e| e.volume / (covers.pattern.of_cell(e.cell)[e.subcell].shape.volume() * covers.mesh_of(e).size.powi(3)))
        .collect();
    // Measured against the block's fullest ME: a block smaller than a sub-cell (a sliver
    // between joints) has no ME above the threshold, and its pieces of 1e-11 of a cell would
    // otherwise keep their own DOFs (a cover of 2e-12 kg thrown metres in a 0.1 µs step).
    let mut fullest = vec![0.0_f64; fixed_block.len()];
    for (e, me) in covers.elements.iter().enumerate() {
        fullest[me.block] = fullest[me.block].max(fraction[e]);
    }
    let well_posed: Vec<bool> =
        covers.elements.iter().zip(&fraction).map(|(me, f)| *f >= threshold * fullest[me.block].min(1.0)).collect();
    let mut anchored = vec![false; covers.covers.len()];
    let mut roots: HashMap<(usize, [i32; 3]), Vec<usize>> = HashMap::new();
    for (e, me) in covers.elements.iter().enumerate().filter(|(e, _)| well_posed[*e]) {
        me.covers.iter().for_each(|&c| anchored[c] = true);
        roots.entry((me.block, me.cell)).or_default().push(e);
    }
    let mut reach: HashMap<usize, ([i32; 3], [i32; 3])> = HashMap::new();
    for &(block, cell) in roots.keys() {
        let (lo, hi) = reach.entry(block).or_insert((cell, cell));
        for k in 0..3 {
            (lo[k], hi[k]) = (lo[k].min(cell[k]), hi[k].max(cell[k]));
        }
    }
    for (c, cover) in covers.covers.iter().enumerate() {
        if anchored[c] || fixed_block[cover.block] {
            continue;
        }
        if let Some(root) = nearest_root(covers, &roots, &reach, cover.block, cover.node, &cover.position) {
            let me = &covers.elements[root];
            let xi = covers.cell_local(me, &cover.position);
            let w = covers.weights(me).iter().map(|p| p.eval(&xi));
            tied[c] = Some(me.covers.iter().copied().zip(w).collect());
        }
    }
    tied
}

fn nearest_root(
    covers: &Covers,
    roots: &HashMap<(usize, [i32; 3]), Vec<usize>>,
    reach: &HashMap<usize, ([i32; 3], [i32; 3])>,
    block: usize,
    node: [i32; 3],
    x: &Vec3,
) -> Option<usize> {
    let centre = [node[0].div_euclid(2), node[1].div_euclid(2), node[2].div_euclid(2)];
    // No ring beyond the block's farthest root cell can hold a root: a block without roots (a
    // sliver whose every ME is ill-posed) is answered at once instead of after 129³ cells.
    let (lo, hi) = reach.get(&block)?;
    let farthest = (0..3).map(|k| (centre[k] - lo[k]).abs().max((hi[k] - centre[k]).abs())).max().unwrap_or(0);
    let mut best: Option<(f64, usize)> = None;
    let mut found_at = None;
    for r in 0..=SEARCH_RADIUS.min(farthest) {
        for cell in ring(centre, r) {
            for &e in roots.get(&(block, cell)).into_iter().flatten() {
                let d = (covers.elements[e].centroid(covers.mesh_of(&covers.elements[e])) - x).norm();
                if best.is_none_or(|(bd, be)| d < bd || (d == bd && e < be)) {
                    best = Some((d, e));
                }
            }
        }
        // A root in ring r can be beaten by one in ring r + 1, never by a farther one.
        match found_at {
            Some(f) if r > f => break,
            None if best.is_some() => found_at = Some(r),
            _ => {}
        }
    }
    best.map(|(_, e)| e)
}

/// Cells at Chebyshev distance exactly `r` from `c`.
fn ring(c: [i32; 3], r: i32) -> impl Iterator<Item = [i32; 3]> {
    (-r..=r).flat_map(move |dk| {
        (-r..=r).flat_map(move |dj| {
            (-r..=r)
                .filter(move |di| di.abs().max(dj.abs()).max(dk.abs()) == r)
                .map(move |di| [c[0] + di, c[1] + dj, c[2] + dk])
        })
    })
}
