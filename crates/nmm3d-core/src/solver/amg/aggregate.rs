//! Aggregation of a level's nodes (groups of `block` equations: a cover's three displacements
//! on the finest level, an aggregate's rigid-body modes below): the standard three-pass
//! algorithm of smoothed aggregation (Vaněk, Mandel & Brezina, *Computing* 56, 1996, §4;
//! pyamg's `standard_aggregation`) on the graph of strong couplings.

use super::bsr::Bsr;

/// The aggregate of every node, and how many aggregates there are.
#[derive(Debug, Clone, PartialEq)]
pub struct Aggregates {
    /// Aggregate of each node ([`ISOLATED`]: none).
    pub of: Vec<u32>,
    /// Number of aggregates.
    pub count: usize,
}

impl Aggregates {
    /// The nodes of each aggregate, in increasing order.
    pub fn members(&self) -> Vec<Vec<u32>> {
        let mut m = vec![Vec::new(); self.count];
        for (node, &a) in self.of.iter().enumerate().filter(|(_, &a)| a != ISOLATED) {
            m[a as usize].push(node as u32);
        }
        m
    }
}

/// The aggregate of a node coupled to no other: it is left out of the coarser levels, as in
/// smoothed aggregation (Vaněk, Mandel & Brezina 1996; pyamg): its equations are the smoother's
/// alone. Made its own aggregate, it would keep its k modes on every coarser level and stop the
/// coarsening — a pile of blocks at rest, whose columns touch with no force, stalled so
/// (`docs/theory/solver.md`).
pub const ISOLATED: u32 = u32::MAX - 1;

/// Strong neighbours of each node (a block row of `a`; itself excluded): node j is strongly
/// coupled to node i when ‖A_ij‖_F ≥ θ √(‖A_ii‖_F ‖A_jj‖_F) (the block form of the symmetric
/// strength measure).
pub fn strong_graph(a: &Bsr<f64>, theta: f64) -> Vec<Vec<u32>> {
    let size = a.br * a.bc;
    let norms: Vec<Vec<(u32, f64)>> = (0..a.rows / a.br)
        .map(|i| {
            let (idx, val) = a.block_row(i);
            idx.iter().zip(val.chunks_exact(size)).map(|(&j, b)| (j, b.iter().map(|v| v * v).sum())).collect()
        })
        .collect();
    let diag: Vec<f64> = norms
        .iter()
        .enumerate()
        .map(|(i, row)| row.iter().find(|(n, _)| *n as usize == i).map_or(0.0, |e| e.1.sqrt()))
        .collect();
    norms
        .iter()
        .enumerate()
        .map(|(i, row)| {
            row.iter()
                .filter(|&&(j, s)| {
                    j as usize != i && s > 0.0 && s.sqrt() >= theta * (diag[i] * diag[j as usize]).sqrt()
                })
                .map(|&(j, _)| j)
                .collect()
        })
        .collect()
}

/// Standard aggregation: (1) a node whose neighbours are all free founds an aggregate with
/// them; (2) a free node joins a neighbour's aggregate of the first pass; (3) the rest found
/// aggregates with their free neighbours.
pub fn aggregate(graph: &[Vec<u32>]) -> Aggregates {
    const FREE: u32 = u32::MAX;
    let mut of = vec![FREE; graph.len()];
    let mut count = 0u32;
    for i in 0..graph.len() {
        if graph[i].is_empty() {
            of[i] = ISOLATED;
        } else if of[i] == FREE && graph[i].iter().all(|&j| of[j as usize] == FREE) {
            of[i] = count;
            graph[i].iter().for_each(|&j| of[j as usize] = count);
            count += 1;
        }
    }
    let first = of.clone();
    for i in 0..graph.len() {
        if of[i] == FREE {
            if let Some(&j) = graph[i].iter().find(|&&j| first[j as usize] != FREE) {
                of[i] = first[j as usize];
            }
        }
    }
    for i in 0..graph.len() {
        if of[i] == FREE {
            of[i] = count;
            for &j in &graph[i] {
                if of[j as usize] == FREE {
                    of[j as usize] = count;
                }
            }
            count += 1;
        }
    }
    Aggregates { of, count: count as usize }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The path 0 – 1 – … – (n − 1).
    fn path(n: usize) -> Vec<Vec<u32>> {
        (0..n).map(|i| [i.wrapping_sub(1), i + 1].into_iter().filter(|&j| j < n).map(|j| j as u32).collect()).collect()
    }

    #[test]
    fn every_node_is_in_one_aggregate_of_its_neighbourhood() {
        for n in [2, 5, 10, 31] {
            let g = path(n);
            let agg = aggregate(&g);
            assert!(agg.of.iter().all(|&a| (a as usize) < agg.count), "n = {n}");
            for m in agg.members() {
                assert!(!m.is_empty());
                // An aggregate of a path is a connected run of at most three nodes.
                assert!(m.len() <= 3 && m.windows(2).all(|w| w[1] == w[0] + 1), "{m:?}");
            }
        }
        assert_eq!(aggregate(&path(9)).count, 3);
    }

    #[test]
    fn a_node_coupled_to_none_is_left_out() {
        // A path of five, then two nodes coupled to nothing.
        let mut g = path(5);
        g.extend([Vec::new(), Vec::new()]);
        let agg = aggregate(&g);
        assert_eq!(&agg.of[5..], &[ISOLATED, ISOLATED]);
        assert_eq!(agg.count, aggregate(&path(5)).count);
        assert_eq!(agg.members().concat(), vec![0, 1, 2, 3, 4]);
        assert_eq!(aggregate(&[Vec::new(), Vec::new()]).count, 0);
    }

    #[test]
    fn weak_couplings_do_not_join_nodes() {
        // Two 2 × 2 blocks (block = 2) coupled by an entry far below their diagonals.
        let a = super::super::csr::Csr {
            rows: 4,
            cols: 4,
            ptr: vec![0, 2, 4, 6, 8],
            idx: vec![0, 2, 1, 3, 0, 2, 1, 3],
            val: vec![1.0, 1e-3, 1.0, 0.0, 1e-3, 1.0, 0.0, 1.0],
        };
        let a = Bsr::from_csr(&a, 2, 2);
        assert_eq!(strong_graph(&a, 0.0), vec![vec![1], vec![0]]);
        assert_eq!(strong_graph(&a, 0.01), vec![Vec::<u32>::new(), vec![]]);
        // Coupled to nothing strongly, both are left to the smoother.
        assert_eq!(aggregate(&strong_graph(&a, 0.01)), Aggregates { of: vec![ISOLATED; 2], count: 0 });
    }
}
