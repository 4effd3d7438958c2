//! Clipping and splitting a convex polyhedron by a plane.
//!
//! Each face polygon is clipped (Sutherland–Hodgman); the points on the cutting plane form
//! the cap face, ordered counter-clockwise about the plane normal. Vertices within
//! [`CLIP_TOLERANCE`] × diagonal of the plane count as on it, so a plane through existing
//! vertices, edges or faces creates no slivers. An edge crossing is always computed from its
//! inside end, so the two faces sharing the edge produce the same point bit for bit.

use crate::math::Vec3;
use crate::plane::Plane;
use crate::polygon;
use crate::polyhedron::{ConvexPolyhedron, Face, FaceTag, CLIP_TOLERANCE, DEGENERATE_VOLUME_RATIO};

impl ConvexPolyhedron {
    /// The part on the inside of `plane` ($\mathbf n\cdot\mathbf x \le d$), with the new face
    /// tagged `tag`; `None` if that part has no volume.
    pub fn clip(&self, plane: &Plane, tag: FaceTag) -> Option<ConvexPolyhedron> {
        self.clip_within(plane, tag, CLIP_TOLERANCE * self.aabb().diagonal())
    }

    /// [`Self::clip`] with vertices within `eps` of the plane taken as on it (a caller that
    /// knows its scale snaps what lies closer: no sliver thinner than `eps` is cut off).
    pub fn clip_within(&self, plane: &Plane, tag: FaceTag, eps: f64) -> Option<ConvexPolyhedron> {
        let diag = self.aabb().diagonal();
        let dist = |v: &Vec3| plane.signed_distance(v);
        let all: Vec<f64> = self.faces.iter().flat_map(|f| f.vertices.iter().map(dist)).collect();
        if all.iter().all(|&s| s <= eps) {
            return Some(self.clone());
        }
        if all.iter().all(|&s| s >= -eps) {
            return None;
        }
        let mut faces = Vec::with_capacity(self.faces.len() + 1);
        let mut cap: Vec<Vec3> = Vec::new();
        for f in &self.faces {
            let clipped = clip_polygon(&f.vertices, plane, eps, &mut cap);
            if clipped.len() >= 3 && polygon::area_vector(&clipped).norm() > eps * eps {
                faces.push(Face { vertices: clipped, tag: f.tag });
            }
        }
        let mut unique: Vec<Vec3> = Vec::new();
        for p in cap {
            if !unique.iter().any(|q| (q - p).norm() <= eps) {
                unique.push(p);
            }
        }
        if unique.len() >= 3 {
            polygon::sort_ccw(&mut unique, &plane.normal);
            if polygon::area_vector(&unique).norm() > eps * eps {
                faces.push(Face { vertices: unique, tag });
            }
        }
        let out = ConvexPolyhedron { faces };
        (out.faces.len() >= 4 && out.volume() > DEGENERATE_VOLUME_RATIO * diag.powi(3)).then_some(out)
    }

    /// The two parts on either side of `plane`: (inside, outside). New faces are tagged
    /// `tag` on both parts.
    pub fn split(&self, plane: &Plane, tag: FaceTag) -> (Option<ConvexPolyhedron>, Option<ConvexPolyhedron>) {
        (self.clip(plane, tag), self.clip(&plane.flipped(), tag))
    }
}

/// Clip one polygon to the inside of `plane`; points on the plane are appended to `cap`.
fn clip_polygon(vs: &[Vec3], plane: &Plane, eps: f64, cap: &mut Vec<Vec3>) -> Vec<Vec3> {
    let n = vs.len();
    let s: Vec<f64> = vs.iter().map(|v| plane.signed_distance(v)).collect();
    let mut out = Vec::with_capacity(n + 2);
    for i in 0..n {
        let j = (i + 1) % n;
        let (a, b, sa, sb) = (vs[i], vs[j], s[i], s[j]);
        if sa <= eps {
            out.push(a);
            if sa >= -eps {
                cap.push(a);
            }
        }
        let crosses = (sa < -eps && sb > eps) || (sa > eps && sb < -eps);
        if crosses {
            let p = if sa < 0.0 { crossing(a, b, sa, sb) } else { crossing(b, a, sb, sa) };
            out.push(p);
            cap.push(p);
        }
    }
    polygon::dedup_cyclic(&mut out, eps);
    out
}

/// Point where the edge from `inside` (distance `si` < 0) to `outside` meets the plane.
#[inline]
fn crossing(inside: Vec3, outside: Vec3, si: f64, so: f64) -> Vec3 {
    inside + (si / (si - so)) * (outside - inside)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_cube() -> ConvexPolyhedron {
        ConvexPolyhedron::from_box(Vec3::zeros(), Vec3::repeat(1.0))
    }

    #[test]
    fn split_conserves_volume() {
        let p = Plane::from_point_normal(Vec3::new(0.3, 0.4, 0.5), Vec3::new(1.0, 2.0, 3.0)).unwrap();
        let (a, b) = unit_cube().split(&p, FaceTag(99));
        let (a, b) = (a.unwrap(), b.unwrap());
        assert!((a.volume() + b.volume() - 1.0).abs() < 1e-14);
        assert!(a.faces.iter().any(|f| f.tag == FaceTag(99)));
    }

    #[test]
    fn plane_through_a_face_or_edge_leaves_no_sliver() {
        let face = Plane::from_point_normal(Vec3::new(1.0, 0.0, 0.0), Vec3::x()).unwrap();
        assert_eq!(unit_cube().clip(&face, FaceTag(9)).unwrap().volume(), 1.0);
        assert!(unit_cube().clip(&face.flipped(), FaceTag(9)).is_none());
        let diagonal = Plane::from_point_normal(Vec3::zeros(), Vec3::new(1.0, -1.0, 0.0)).unwrap();
        let (a, b) = unit_cube().split(&diagonal, FaceTag(9));
        let (a, b) = (a.unwrap(), b.unwrap());
        assert!((a.volume() - 0.5).abs() < 1e-15 && (b.volume() - 0.5).abs() < 1e-15);
        assert_eq!(a.faces.len(), 5);
        assert_eq!(a.vertices().len(), 6);
    }

    #[test]
    fn seeded_random_cuts_conserve_volume_and_close() {
        let mut seed = 0xC0FFEEu64;
        let mut rnd = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..200 {
            let n = Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5);
            let p = Plane::from_point_normal(Vec3::new(rnd(), rnd(), rnd()), n).unwrap();
            let (a, b) = unit_cube().split(&p, FaceTag(7));
            let va = a.as_ref().map_or(0.0, |x| x.volume());
            let vb = b.as_ref().map_or(0.0, |x| x.volume());
            assert!((va + vb - 1.0).abs() < 1e-13);
            for piece in [a, b].into_iter().flatten() {
                // A closed surface has zero total area vector.
                let s: Vec3 = piece.faces.iter().map(|f| f.area_vector()).sum();
                assert!(s.norm() < 1e-13);
                let (v, e, f) = euler_counts(&piece);
                assert_eq!(v + f - e, 2, "Euler characteristic");
            }
        }
    }

    fn euler_counts(p: &ConvexPolyhedron) -> (usize, usize, usize) {
        let verts = p.vertices();
        let id = |x: &Vec3| verts.iter().position(|w| (w - x).norm() < 1e-12).unwrap();
        let mut edges = std::collections::BTreeSet::new();
        for f in &p.faces {
            for i in 0..f.vertices.len() {
                let (a, b) = (id(&f.vertices[i]), id(&f.vertices[(i + 1) % f.vertices.len()]));
                let _ = edges.insert((a.min(b), a.max(b)));
            }
        }
        (verts.len(), edges.len(), p.faces.len())
    }
}
