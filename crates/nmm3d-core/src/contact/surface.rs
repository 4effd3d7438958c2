//! Contact surfaces: each convex piece of each block, with every distinct vertex tied to the ME
//! and weights that move it, so the current geometry follows the covers.

use nmm3d_geom::{ConvexPolyhedron, Face, FaceTag, Vec3};

use super::facets::{facets_of_piece, Facet};
use super::point::{barycentric, in_plane, MaterialPoint};
use crate::state::Motion;
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
    pub fn current(&self, sys: &System, state: &Motion) -> ConvexPolyhedron {
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
    pub fn facet_positions(&self, sys: &System, state: &Motion) -> Vec<Vec<Vec3>> {
        self.facets.iter().map(|f| f.vertices.iter().map(|m| m.position(sys, state)).collect()).collect()
    }

    /// The material point of this piece at `p`, a point of its current geometry `cur` given by
    /// the detection: on a face, or — the projection of the other piece's corner onto the
    /// contact plane beyond the edge of the face giving it — on a face's plane beyond its edge.
    /// There the nearest surface point lies elsewhere and its material point would measure the
    /// overlap wrongly, so when the nearest one misses `p` by more than `tol` [m] and `p` lies
    /// on a face's plane, the point is taken on that plane, its weights extrapolated from the
    /// ME of the nearest surface point (exact for that ME's affine motion). `None` if no ME of
    /// the block holds the nearest surface point.
    pub fn material_point(
        &self,
        sys: &System,
        state: &Motion,
        cur: &ConvexPolyhedron,
        p: &Vec3,
        tol: f64,
    ) -> Option<MaterialPoint> {
        let m = MaterialPoint::new(sys, self.block, self.reference_of(cur, p))?;
        let miss = (m.position(sys, state) - p).norm();
        if miss <= tol {
            return Some(m);
        }
        let Some(on_plane) = self.reference_on_plane(cur, p, tol) else { return Some(m) };
        let beyond = MaterialPoint::on_element(sys, m.element, on_plane);
        Some(if (beyond.position(sys, state) - p).norm() < miss { beyond } else { m })
    }

    /// Reference position of a point `p` on the plane of a face of `cur` (within `tol`; the
    /// nearest such plane): the face's affine map from current to reference, extended beyond
    /// its edges. `None` if `p` is on no face's plane.
    fn reference_on_plane(&self, cur: &ConvexPolyhedron, p: &Vec3, tol: f64) -> Option<Vec3> {
        let mut best = (tol, None);
        for (k, (ids, _)) in self.faces.iter().enumerate() {
            let fv = &cur.faces[k].vertices;
            // The fan triangle of largest area: the best conditioned map.
            let Some(i) = (1..ids.len() - 1).max_by(|&i, &j| {
                let area = |i: usize| (fv[i] - fv[0]).cross(&(fv[i + 1] - fv[0])).norm();
                area(i).total_cmp(&area(j))
            }) else {
                continue;
            };
            let normal = (fv[i] - fv[0]).cross(&(fv[i + 1] - fv[0]));
            let Some((v, w)) = in_plane(p, &fv[0], &fv[i], &fv[i + 1]) else { continue };
            let off_plane = normal.normalize().dot(&(p - fv[0])).abs();
            if off_plane > best.0 {
                continue;
            }
            let r = |j: usize| self.vertices[ids[j]].reference;
            best = (off_plane, Some(r(0) + v * (r(i) - r(0)) + w * (r(i + 1) - r(0))));
        }
        best.1
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A frustum, 2 m square at its base and 1 m at its top (1 m high), moved by `t`.
    fn frustum(t: Vec3) -> (System, Motion) {
        let text = r#"
[analysis]
duration = 0.001
dt = 0.001
[cover]
size = 0.5
[[material]]
name = "rock"
density = 2500.0
young = 1e9
poisson = 0.25
[[body]]
name = "frustum"
material = "rock"
shape = { convex = { planes = [
  [0.0, 0.0, -1.0, 0.0], [0.0, 0.0, 1.0, 1.0],
  [1.0, 0.0, 0.5, 1.0], [-1.0, 0.0, 0.5, 1.0], [0.0, 1.0, 0.5, 1.0], [0.0, -1.0, 0.5, 1.0]
] } }
"#;
        let sys = System::build(crate::input::from_toml_str(text, "<test>", &[]).unwrap(), "<test>").unwrap();
        let mut state = Motion::initial(&sys);
        state.u.iter_mut().for_each(|u| *u = t);
        (sys, state)
    }

    #[test]
    fn a_point_on_a_faces_plane_past_its_edge_is_taken_on_that_plane() {
        let t = Vec3::new(0.3, -0.2, 0.1);
        let (sys, state) = frustum(t);
        let piece = &sys.geometry.blocks[0].pieces[0];
        let cp = ContactPiece::new(&sys, 0, piece).unwrap();
        let cur = cp.current(&sys, &state);
        // On the top face's plane (z = 1), 0.3 m past its edge x = 0.5, above the slanted side.
        let p = (Vec3::new(0.8, 0.0, 1.0) - sys.geometry.origin) + t;
        let nearest = MaterialPoint::new(&sys, 0, cp.reference_of(&cur, &p)).unwrap();
        let tol = 1e-4;
        assert!((nearest.position(&sys, &state) - p).norm() > 0.1, "the nearest surface point is elsewhere");
        let m = cp.material_point(&sys, &state, &cur, &p, tol).unwrap();
        assert!((m.position(&sys, &state) - p).norm() < 1e-9, "{:?} vs {p:?}", m.position(&sys, &state));
        // A point on the surface keeps its nearest material point.
        let on = (Vec3::new(0.25, 0.1, 1.0) - sys.geometry.origin) + t;
        assert!((cp.material_point(&sys, &state, &cur, &on, tol).unwrap().position(&sys, &state) - on).norm() < 1e-9);
    }
}
