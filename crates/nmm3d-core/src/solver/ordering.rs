//! Fill-reducing orderings. For 3-D stiffness matrices nested dissection (METIS) gives about
//! half the fill of approximate minimum degree and a 2–3× faster factorisation above ~20 000
//! DOFs (`research/ecosystem.md` §3.1); below `ND_MIN_BLOCKS` AMD is as good and cheaper.
//! The ordering is computed on the graph of 3 × 3 blocks (covers), three times smaller than the
//! DOF graph, and expanded so each cover's three equations stay together.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::SymbolicSparseColMatRef;

use crate::assembly::SparsityPattern;
use crate::scenario::Ordering;

/// Below this many covers faer's AMD is used.
pub const ND_MIN_BLOCKS: usize = 2000;

/// A permutation: `forward[new] = old`, `inverse[old] = new`.
#[derive(Debug, Clone, PartialEq)]
pub struct Permutation {
    /// New position → old index.
    pub forward: Vec<u32>,
    /// Old index → new position.
    pub inverse: Vec<u32>,
}

/// Nested-dissection ordering of the pattern's equations, when `choice` asks for it (`Auto`:
/// from `ND_MIN_BLOCKS` covers on; `Smallest`: always, to be compared with AMD); `None` means
/// AMD.
pub fn nested_dissection(p: &SparsityPattern, choice: Ordering) -> Option<Permutation> {
    let nb = p.n / 3;
    let wanted = match choice {
        Ordering::Auto => nb >= ND_MIN_BLOCKS,
        Ordering::Amd => false,
        Ordering::NestedDissection | Ordering::Smallest => nb > 0,
    };
    if !wanted || !p.n.is_multiple_of(3) {
        return None;
    }
    let (xadj, adjncy) = block_graph(p, nb);
    let block_perm = metis_node_nd(nb, xadj, adjncy)?;
    let forward: Vec<u32> = block_perm.iter().flat_map(|&b| (0..3).map(move |i| 3 * b + i)).collect();
    let mut inverse = vec![0u32; p.n];
    for (new, &old) in forward.iter().enumerate() {
        inverse[old as usize] = new as u32;
    }
    Some(Permutation { forward, inverse })
}

/// Approximate minimum degree ordering of the pattern's equations (faer's AMD, default
/// controls).
pub fn amd(p: &SparsityPattern) -> Result<Permutation, String> {
    let a = SymbolicSparseColMatRef::new_checked(p.n, p.n, &p.col_ptr, None, &p.row_idx);
    let (mut forward, mut inverse) = (vec![0u32; p.n], vec![0u32; p.n]);
    let mut mem = MemBuffer::new(amd::order_maybe_unsorted_scratch::<u32>(p.n, p.row_idx.len()));
    amd::order_maybe_unsorted(&mut forward, &mut inverse, a, Default::default(), MemStack::new(&mut mem))
        .map_err(|e| format!("{e:?}"))?;
    Ok(Permutation { forward, inverse })
}

/// Symmetric adjacency (CSR, no self loops) of the 3 × 3 blocks.
fn block_graph(p: &SparsityPattern, nb: usize) -> (Vec<i32>, Vec<i32>) {
    let mut nbr: Vec<Vec<i32>> = vec![Vec::new(); nb];
    for col in (0..p.n).step_by(3) {
        let bj = col / 3;
        for &r in &p.row_idx[p.col_ptr[col] as usize..p.col_ptr[col + 1] as usize] {
            let bi = r as usize / 3;
            if bi != bj {
                nbr[bi].push(bj as i32);
                nbr[bj].push(bi as i32);
            }
        }
    }
    let mut xadj = Vec::with_capacity(nb + 1);
    let mut adjncy = Vec::new();
    xadj.push(0);
    for mut list in nbr {
        list.sort_unstable();
        list.dedup();
        adjncy.extend(list);
        xadj.push(adjncy.len() as i32);
    }
    (xadj, adjncy)
}

/// One METIS call at a time: it seeds and draws from a process-wide random generator, so two
/// threads ordering at once (the Rust tests, two runs in one Python process) got each other's
/// draws and a different order (a cube of covers, whose nested dissection is 21 % smaller than
/// AMD's, once got one larger than AMD's in the parallel Rust tests).
static METIS: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// METIS_NodeND with default options (deterministic: METIS seeds its generator itself).
#[allow(unsafe_code)] // the one FFI call; every pointer comes from a live Vec of the right length
fn metis_node_nd(n: usize, mut xadj: Vec<i32>, mut adjncy: Vec<i32>) -> Option<Vec<u32>> {
    let _one_at_a_time = METIS.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    let mut nv = n as i32;
    let mut perm = vec![0i32; n];
    let mut iperm = vec![0i32; n];
    // SAFETY: nv, xadj (n + 1 entries), adjncy (xadj[n] entries), perm and iperm (n entries) are
    // valid for the duration of the call; null vwgt and options select METIS's defaults.
    let status = unsafe {
        metis_sys::METIS_NodeND(
            &mut nv,
            xadj.as_mut_ptr(),
            adjncy.as_mut_ptr(),
            std::ptr::null_mut(),
            std::ptr::null_mut(),
            perm.as_mut_ptr(),
            iperm.as_mut_ptr(),
        )
    };
    (status == metis_sys::rstatus_et_METIS_OK).then(|| perm.into_iter().map(|x| x as u32).collect())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::assembly::DofMap;

    /// An nx × ny × nz grid graph of covers, 7-point stencil.
    pub(crate) fn grid(nx: usize, ny: usize, nz: usize) -> SparsityPattern {
        let id = |i: usize, j: usize, k: usize| i + nx * (j + ny * k);
        let n = nx * ny * nz;
        let dofs = DofMap::new(&vec![false; n], &vec![None; n]);
        let mut cliques = Vec::new();
        for (i, j, k) in (0..nz).flat_map(|k| (0..ny).flat_map(move |j| (0..nx).map(move |i| (i, j, k)))) {
            for (di, dj, dk) in [(1, 0, 0), (0, 1, 0), (0, 0, 1)] {
                if i + di < nx && j + dj < ny && k + dk < nz {
                    cliques.push(vec![id(i, j, k), id(i + di, j + dj, k + dk)]);
                }
            }
        }
        SparsityPattern::from_cliques(&dofs, cliques.iter().map(|c| c.as_slice()))
    }

    #[test]
    fn nested_dissection_is_a_permutation_keeping_blocks_together() {
        let (nx, ny, nz) = (15usize, 15usize, 10usize);
        let n = nx * ny * nz;
        let p = grid(nx, ny, nz);
        let perm = nested_dissection(&p, Ordering::Auto).expect("large enough for ND");
        let mut seen = perm.forward.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..3 * n as u32).collect::<Vec<_>>());
        for b in perm.forward.chunks(3) {
            assert!(b[0] % 3 == 0 && b[1] == b[0] + 1 && b[2] == b[0] + 2);
        }
        for (new, &old) in perm.forward.iter().enumerate() {
            assert_eq!(perm.inverse[old as usize] as usize, new);
        }
    }

    #[test]
    fn threads_ordering_at_once_get_the_order_one_thread_gets() {
        // METIS draws from one process-wide generator: without the lock, threads ordering at
        // the same time interleave its draws.
        let p = grid(12, 12, 12);
        let alone = nested_dissection(&p, Ordering::NestedDissection).expect("ND");
        std::thread::scope(|s| {
            let runs: Vec<_> = (0..4)
                .map(|_| {
                    s.spawn(|| (0..10).map(|_| nested_dissection(&p, Ordering::NestedDissection)).collect::<Vec<_>>())
                })
                .collect();
            for r in runs {
                for perm in r.join().expect("no panic") {
                    assert_eq!(perm.as_ref(), Some(&alone));
                }
            }
        });
    }
}
