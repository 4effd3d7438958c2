//! Manifold patterns: how a cubic cell is divided into the sub-cells that carry the weight
//! functions. Cell-local coordinates ξ ∈ [0, 1]³; corner `c` is (c&1, c>>1&1, c>>2&1).
//!
//! * `tet5`: a central tetrahedron and four corner ones; cells whose i+j+k is odd use the
//!   mirrored plan so that face diagonals match across cells (conforming).
//! * `tet6`: six tetrahedra around the main diagonal 0–7 (Kuhn / Freudenthal); translation
//!   invariant, hence conforming.
//! * `tet24`: each face split into 4 triangles towards its centre, each joined to the body
//!   centre: 24 tetrahedra, extra nodes at face and body centres.
//! * `hex8`: the cube itself with trilinear weight functions.
//!
//! In every pattern the weight functions of a sub-cell form a partition of unity and
//! reproduce linear fields.

use nmm3d_geom::{ConvexPolyhedron, Face, FaceTag, Mat3, Plane, Vec3};

use super::poly::Poly;
use crate::scenario::PatternKind;

pub use crate::model::tags::CELL_TAG;

/// One sub-cell of the pattern.
#[derive(Debug, Clone)]
pub struct SubCell {
    /// Node offsets from the cell's corner, in half-cell units.
    pub nodes: Vec<[i32; 3]>,
    /// Weight function of each node, in cell-local ξ.
    pub weights: Vec<Poly>,
    /// Outward bounding planes in cell-local ξ.
    pub planes: Vec<Plane>,
    /// For each plane, the indices (into `nodes`) of the nodes on it.
    pub plane_nodes: Vec<Vec<usize>>,
    /// The sub-cell as a polyhedron in ξ; face `k` is tagged `CELL_TAG + k` (plane `k`).
    pub shape: ConvexPolyhedron,
}

/// The sub-cells of a pattern, for even and odd cells.
#[derive(Debug, Clone)]
pub struct PatternTable {
    /// Which pattern.
    pub kind: PatternKind,
    /// `[even, odd]` sub-cell lists (identical except for tet5).
    pub subcells: [Vec<SubCell>; 2],
}

fn corner(c: usize) -> [i32; 3] {
    [2 * (c & 1) as i32, 2 * ((c >> 1) & 1) as i32, 2 * ((c >> 2) & 1) as i32]
}

fn half(k: [i32; 3]) -> Vec3 {
    Vec3::new(k[0] as f64, k[1] as f64, k[2] as f64) * 0.5
}

impl PatternTable {
    /// Build the table of a pattern.
    pub fn new(kind: PatternKind) -> Self {
        let even = subcells(kind, false);
        let odd = subcells(kind, true);
        Self { kind, subcells: [even, odd] }
    }

    /// Sub-cells of cell (i, j, k).
    pub fn of_cell(&self, cell: [i32; 3]) -> &[SubCell] {
        &self.subcells[parity(cell)]
    }

    /// Whether the weight functions are linear (tetrahedral patterns).
    pub fn is_linear(&self) -> bool {
        self.kind != PatternKind::Hex8
    }
}

/// 0 for even i+j+k, 1 for odd.
pub fn parity(cell: [i32; 3]) -> usize {
    (cell[0] + cell[1] + cell[2]).rem_euclid(2) as usize
}

fn subcells(kind: PatternKind, odd: bool) -> Vec<SubCell> {
    match kind {
        PatternKind::Tet6 => {
            let perms = [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]];
            perms
                .iter()
                .map(|p| {
                    let (a, b) = (1usize << p[0], (1usize << p[0]) | (1usize << p[1]));
                    tet([corner(0), corner(a), corner(b), corner(7)])
                })
                .collect()
        }
        PatternKind::Tet5 => {
            let plan: [[usize; 4]; 5] = if !odd {
                [[0, 3, 5, 6], [1, 0, 3, 5], [2, 0, 3, 6], [4, 0, 5, 6], [7, 3, 5, 6]]
            } else {
                [[1, 2, 4, 7], [0, 1, 2, 4], [3, 1, 2, 7], [5, 1, 4, 7], [6, 2, 4, 7]]
            };
            plan.iter().map(|t| tet(t.map(corner))).collect()
        }
        PatternKind::Tet24 => {
            let body = [1, 1, 1];
            let cube = ConvexPolyhedron::from_box(Vec3::zeros(), Vec3::repeat(1.0));
            let mut out = Vec::new();
            for f in &cube.faces {
                let keys: Vec<[i32; 3]> =
                    f.vertices.iter().map(|v| [2 * v.x as i32, 2 * v.y as i32, 2 * v.z as i32]).collect();
                let c = [
                    keys.iter().map(|k| k[0]).sum::<i32>() / 4,
                    keys.iter().map(|k| k[1]).sum::<i32>() / 4,
                    keys.iter().map(|k| k[2]).sum::<i32>() / 4,
                ];
                for i in 0..4 {
                    out.push(tet([keys[i], keys[(i + 1) % 4], c, body]));
                }
            }
            out
        }
        PatternKind::Hex8 => vec![hex8()],
    }
}

/// A tetrahedral sub-cell with linear (barycentric) weight functions.
fn tet(mut nodes: [[i32; 3]; 4]) -> SubCell {
    let mut p = nodes.map(half);
    let vol = (p[1] - p[0]).dot(&(p[2] - p[0]).cross(&(p[3] - p[0])));
    if vol < 0.0 {
        nodes.swap(2, 3);
        p.swap(2, 3);
    }
    let t = Mat3::from_columns(&[p[1] - p[0], p[2] - p[0], p[3] - p[0]]);
    let inv = t.try_inverse().expect("a pattern tetrahedron is not flat");
    // λ_{1..3}(ξ) = rows of T⁻¹ applied to (ξ − p0); λ0 = 1 − Σ.
    let mut weights = Vec::with_capacity(4);
    let mut rest = Poly::affine(1.0, Vec3::zeros());
    for r in 0..3 {
        let g = inv.row(r).transpose();
        let w = Poly::affine(-g.dot(&p[0]), g);
        rest = rest.add_scaled(-1.0, &w);
        weights.push(w);
    }
    weights.insert(0, rest);
    // Face k is opposite node k.
    let mut planes = Vec::new();
    let mut plane_nodes = Vec::new();
    let mut faces = Vec::new();
    for k in 0..4 {
        let others: Vec<usize> = (0..4).filter(|&i| i != k).collect();
        let (a, b, c) = (p[others[0]], p[others[1]], p[others[2]]);
        let mut n = (b - a).cross(&(c - a));
        let mut verts = vec![a, b, c];
        if n.dot(&(p[k] - a)) > 0.0 {
            n = -n;
            verts.swap(1, 2);
        }
        planes.push(Plane::from_point_normal(a, n).expect("non-degenerate face"));
        plane_nodes.push(others);
        faces.push(Face { vertices: verts, tag: FaceTag(CELL_TAG + k as u32) });
    }
    SubCell { nodes: nodes.to_vec(), weights, planes, plane_nodes, shape: ConvexPolyhedron { faces } }
}

/// The trilinear hexahedron.
fn hex8() -> SubCell {
    let nodes: Vec<[i32; 3]> = (0..8).map(corner).collect();
    let weights = (0..8)
        .map(|c| {
            let f = |bit: usize, axis: usize| {
                let mut e = Vec3::zeros();
                e[axis] = 1.0;
                if (c >> bit) & 1 == 1 {
                    Poly::affine(0.0, e)
                } else {
                    Poly::affine(1.0, -e)
                }
            };
            f(0, 0).mul(&f(1, 1)).mul(&f(2, 2))
        })
        .collect();
    let mut shape = ConvexPolyhedron::from_box(Vec3::zeros(), Vec3::repeat(1.0));
    let mut planes = Vec::new();
    let mut plane_nodes = Vec::new();
    for (k, f) in shape.faces.iter_mut().enumerate() {
        f.tag = FaceTag(CELL_TAG + k as u32);
        planes.push(Plane::from_point_normal(f.vertices[0], f.area_vector()).expect("cube face"));
        let on: Vec<usize> = (0..8).filter(|&c| f.vertices.iter().any(|v| half(corner(c)) == *v)).collect();
        plane_nodes.push(on);
    }
    SubCell { nodes, weights, planes, plane_nodes, shape }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all() -> [PatternKind; 4] {
        [PatternKind::Tet5, PatternKind::Tet6, PatternKind::Tet24, PatternKind::Hex8]
    }

    #[test]
    fn subcells_fill_the_cube() {
        for kind in all() {
            let t = PatternTable::new(kind);
            for side in &t.subcells {
                let v: f64 = side.iter().map(|s| s.shape.volume()).sum();
                assert!((v - 1.0).abs() < 1e-14, "{kind:?}");
            }
        }
    }

    #[test]
    fn weights_are_a_partition_of_unity_reproducing_linear_fields() {
        for kind in all() {
            let t = PatternTable::new(kind);
            for s in t.subcells.iter().flatten() {
                let c = s.shape.centroid();
                let x = c + 0.1 * (s.shape.faces[0].vertices[0] - c);
                let sum: f64 = s.weights.iter().map(|w| w.eval(&x)).sum();
                let lin: Vec3 = s.weights.iter().zip(&s.nodes).map(|(w, k)| w.eval(&x) * half(*k)).sum();
                assert!((sum - 1.0).abs() < 1e-14, "{kind:?}");
                assert!((lin - x).norm() < 1e-14, "{kind:?}");
                for (i, k) in s.nodes.iter().enumerate() {
                    assert!((s.weights[i].eval(&half(*k)) - 1.0).abs() < 1e-14);
                }
            }
        }
    }

    #[test]
    fn tet5_face_diagonals_match_across_cells() {
        // Face x=1 of an even cell meets face x=0 of the odd cell to its right.
        let t = PatternTable::new(PatternKind::Tet5);
        let edges_on = |side: &[SubCell], x: i32, shift: i32| {
            let mut e = std::collections::BTreeSet::new();
            for s in side {
                for (pi, nodes) in s.plane_nodes.iter().enumerate() {
                    if nodes.iter().all(|&n| s.nodes[n][0] == x) && s.planes[pi].normal.x.abs() > 0.99 {
                        for a in nodes {
                            for b in nodes {
                                let (ka, kb) = (s.nodes[*a], s.nodes[*b]);
                                if ka < kb {
                                    let _ = e.insert(([ka[0] + shift, ka[1], ka[2]], [kb[0] + shift, kb[1], kb[2]]));
                                }
                            }
                        }
                    }
                }
            }
            e
        };
        assert_eq!(edges_on(&t.subcells[0], 2, 0), edges_on(&t.subcells[1], 0, 2));
    }
}
