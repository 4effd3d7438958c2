//! Contact surfaces: each convex piece of each block, with every distinct vertex tied to the ME
//! and weights that move it, so the current geometry follows the covers.

use nmm3d_geom::{ConvexPolyhedron, Face, FaceTag, Vec3};

use super::facets::{facets_of_piece, Facet};
use super::point::{barycentric, MaterialPoint};
use crate::state::State;
use crate::system::System;

/// One convex piece as a contact surface.
#[derive(Debug, Clone)]
pub struct ContactPiece {
    /// Block index.
    pub block: usize,
    /// The boundary facets of the block's MEs on this piece.
    pub facets: Vec<Facet>,
    /// Distinct vertices as material points.
    pub vertices: Vec<MaterialPoint>,
    /// Faces as vertex indices (outward, counter-clockwise), with their tags.
    pub faces: Vec<(Vec<usize>, FaceTag)>,
}

impl ContactPiece {
    /// From a reference piece of block `block` (`None` if a vertex cannot be located).
    pub fn new(sys: &System, block: usize, piece: &ConvexPolyhedron) -> Option<Self> {
        let refs = piece.vertices();
        let tol = 1e-12 * piece.aabb().diagonal();
        let vertices = refs.iter().map(|x| MaterialPoint::new(sys, block, *x)).collect::<Option<Vec<_>>>()?;
        let faces = piece
            .faces
            .iter()
            .map(|f| {
                (
                    f.vertices
                        .iter()
                        .map(|v| refs.iter().position(|w| (w - v).norm() <= tol).expect("vertex"))
                        .collect(),
                    f.tag,
                )
            })
            .collect();
        Some(Self { block, vertices, faces, facets: facets_of_piece(sys, block, piece) })
    }

    /// Current geometry.
    pub fn current(&self, sys: &System, state: &State) -> ConvexPolyhedron {
        let x: Vec<Vec3> = self.vertices.iter().map(|m| m.position(sys, state)).collect();
        ConvexPolyhedron {
            faces: self
                .faces
                .iter()
                .map(|(ids, tag)| Face { vertices: ids.iter().map(|&i| x[i]).collect(), tag: *tag })
                .collect(),
        }
    }

    /// Current vertices of every facet.
    pub fn facet_positions(&self, sys: &System, state: &State) -> Vec<Vec<Vec3>> {
        self.facets.iter().map(|f| f.vertices.iter().map(|m| m.position(sys, state)).collect()).collect()
    }

    /// Reference position of a point `p` lying on the current surface `cur` (the same affine
    /// combination of a face triangle's vertices, taken in the reference configuration).
    pub fn reference_of(&self, cur: &ConvexPolyhedron, p: &Vec3) -> Vec3 {
        let mut best = (f64::INFINITY, Vec3::zeros());
        for (k, (ids, _)) in self.faces.iter().enumerate() {
            let fv = &cur.faces[k].vertices;
            for i in 1..ids.len() - 1 {
                let (a, b, c) = (fv[0], fv[i], fv[i + 1]);
                let (l, d) = barycentric(p, &a, &b, &c);
                if d < best.0 {
                    let r = |j: usize| self.vertices[ids[j]].reference;
                    best = (d, l[0] * r(0) + l[1] * r(i) + l[2] * r(i + 1));
                }
            }
        }
        best.1
    }
}
