//! Warning (broad phase): which pairs of contact pieces may touch.
//!
//! Sort and sweep (Baraff 1992; Cohen et al. 1995) of the pieces' bounding boxes, each grown by
//! the detection margin plus a *skin*, along the axis over which the box centres spread most:
//! O(P log P + K) for P pieces and K candidate pairs. The list is kept as a Verlet list: a
//! pair farther apart than margin + skin when the list was built cannot come within the margin
//! before some vertex has moved more than skin / 2 (every point of a piece is a convex
//! combination of its vertices), so the list is rebuilt only when a vertex has moved that far.

use nmm3d_geom::{Aabb, ConvexPolyhedron, Vec3};

/// The candidate pairs and what they were built from.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Warning {
    /// Candidate pairs (i, j) of piece indices, i < j, sorted.
    pub pairs: Vec<(usize, usize)>,
    /// Vertex positions of every piece when the list was built.
    anchors: Vec<Vec<Vec3>>,
    /// Skin [m].
    skin: f64,
    /// Times the list was rebuilt.
    pub rebuilds: u64,
}

impl Warning {
    /// Candidate pairs for the current pieces; `keep(i, j)` filters pairs that can never touch
    /// (same block, both fixed). Rebuilt only when a vertex moved more than skin / 2.
    pub fn update(
        &mut self,
        current: &[ConvexPolyhedron],
        margin: f64,
        skin: f64,
        keep: impl Fn(usize, usize) -> bool,
    ) -> &[(usize, usize)] {
        if self.is_stale(current) || skin != self.skin {
            self.skin = skin;
            self.anchors =
                current.iter().map(|p| p.faces.iter().flat_map(|f| f.vertices.iter().copied()).collect()).collect();
            let boxes: Vec<Aabb> = current.iter().map(|c| c.aabb()).collect();
            self.pairs = sweep(&boxes, margin + skin).into_iter().filter(|&(i, j)| keep(i, j)).collect();
            self.rebuilds += 1;
        }
        &self.pairs
    }

    fn is_stale(&self, current: &[ConvexPolyhedron]) -> bool {
        if self.anchors.len() != current.len() {
            return true;
        }
        let limit = 0.5 * self.skin;
        current.iter().zip(&self.anchors).any(|(p, a)| {
            let mut k = 0;
            p.faces.iter().flat_map(|f| f.vertices.iter()).any(|v| {
                let moved = a.get(k).is_none_or(|w| (v - w).norm() > limit);
                k += 1;
                moved
            })
        })
    }
}

/// Pairs (i < j) of boxes within `gap` of each other, sorted.
pub fn sweep(boxes: &[Aabb], gap: f64) -> Vec<(usize, usize)> {
    if boxes.len() < 2 {
        return Vec::new();
    }
    let axis = spread_axis(boxes);
    let mut order: Vec<usize> = (0..boxes.len()).collect();
    order.sort_by(|&a, &b| boxes[a].min[axis].total_cmp(&boxes[b].min[axis]).then(a.cmp(&b)));
    let mut pairs = Vec::new();
    for (k, &i) in order.iter().enumerate() {
        let reach = boxes[i].max[axis] + gap;
        for &j in order[k + 1..].iter().take_while(|&&j| boxes[j].min[axis] <= reach) {
            if boxes[i].separation(&boxes[j]) <= gap {
                pairs.push((i.min(j), i.max(j)));
            }
        }
    }
    pairs.sort_unstable();
    pairs
}

/// The axis along which the box centres vary most.
fn spread_axis(boxes: &[Aabb]) -> usize {
    let n = boxes.len() as f64;
    let centres: Vec<Vec3> = boxes.iter().map(|b| 0.5 * (b.min + b.max)).collect();
    let mean: Vec3 = centres.iter().sum::<Vec3>() / n;
    let var = centres.iter().fold(Vec3::zeros(), |acc, c| acc + (c - mean).component_mul(&(c - mean)));
    (0..3).max_by(|&a, &b| var[a].total_cmp(&var[b])).unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box(x: f64, y: f64, z: f64) -> Aabb {
        Aabb { min: Vec3::new(x, y, z), max: Vec3::new(x + 1.0, y + 1.0, z + 1.0) }
    }

    #[test]
    fn sweep_finds_exactly_the_pairs_of_brute_force() {
        // Seeded scatter of boxes; every pair within the gap, and no other.
        let mut s = 12345u64;
        let mut r = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let boxes: Vec<Aabb> = (0..300).map(|_| unit_box(20.0 * r(), 20.0 * r(), 5.0 * r())).collect();
        let gap = 0.3;
        let mut brute = Vec::new();
        for i in 0..boxes.len() {
            for j in i + 1..boxes.len() {
                if boxes[i].separation(&boxes[j]) <= gap {
                    brute.push((i, j));
                }
            }
        }
        assert!(!brute.is_empty());
        assert_eq!(sweep(&boxes, gap), brute);
    }

    #[test]
    fn the_list_is_rebuilt_only_after_half_the_skin() {
        let cube = |x: f64| ConvexPolyhedron::from_box(Vec3::new(x, 0.0, 0.0), Vec3::new(x + 1.0, 1.0, 1.0));
        let mut w = Warning::default();
        let keep = |_: usize, _: usize| true;
        assert!(w.update(&[cube(0.0), cube(1.5)], 0.1, 0.2, keep).is_empty());
        // Moved 0.09 < skin / 2: the (empty) list stands.
        w.update(&[cube(0.0), cube(1.41)], 0.1, 0.2, keep);
        assert_eq!(w.rebuilds, 1);
        // Moved 0.25 > skin / 2: rebuilt, and now within margin + skin.
        assert_eq!(w.update(&[cube(0.0), cube(1.25)], 0.1, 0.2, keep), &[(0, 1)]);
        assert_eq!(w.rebuilds, 2);
    }
}
