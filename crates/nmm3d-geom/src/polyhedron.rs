//! Convex polyhedra held as outward-oriented face polygons (the V-representation per face),
//! built from boxes, half-spaces (H-representation) or vertex/face lists.

use crate::aabb::Aabb;
use crate::error::GeomError;
use crate::math::Vec3;
use crate::plane::Plane;
use crate::polygon;

/// An opaque label carried by a face through clipping: callers give it meaning
/// (a block face, a joint, a mesh-cell face).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct FaceTag(pub u32);

/// A planar convex face: vertices counter-clockwise seen from outside.
#[derive(Debug, Clone, PartialEq)]
pub struct Face {
    /// Vertices, counter-clockwise seen from outside.
    pub vertices: Vec<Vec3>,
    /// Caller-defined label.
    pub tag: FaceTag,
}

impl Face {
    /// Area vector (outward normal × area).
    pub fn area_vector(&self) -> Vec3 {
        polygon::area_vector(&self.vertices)
    }
    /// Face area.
    pub fn area(&self) -> f64 {
        self.area_vector().norm()
    }
}

/// A bounded convex polyhedron.
#[derive(Debug, Clone, PartialEq)]
pub struct ConvexPolyhedron {
    /// Outward-oriented faces.
    pub faces: Vec<Face>,
}

/// Relative tolerance of the clipping predicates: a vertex closer to a cutting plane than
/// `CLIP_TOLERANCE × diagonal` is taken to lie on it.
pub const CLIP_TOLERANCE: f64 = 1e-12;
/// A clipped piece whose volume is below `DEGENERATE_VOLUME_RATIO × diagonal³` is empty.
pub const DEGENERATE_VOLUME_RATIO: f64 = 1e-15;

impl ConvexPolyhedron {
    /// Axis-aligned box with faces tagged 0..6 in the order −x, +x, −y, +y, −z, +z.
    pub fn from_box(min: Vec3, max: Vec3) -> Self {
        let c = |i: usize| {
            Vec3::new(
                if i & 1 == 0 { min.x } else { max.x },
                if i & 2 == 0 { min.y } else { max.y },
                if i & 4 == 0 { min.z } else { max.z },
            )
        };
        let quads: [[usize; 4]; 6] =
            [[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1], [4, 5, 7, 6]];
        let faces = quads
            .iter()
            .enumerate()
            .map(|(k, q)| Face { vertices: q.iter().map(|&i| c(i)).collect(), tag: FaceTag(k as u32) })
            .collect();
        Self { faces }
    }

    /// Intersection of half-spaces; face `k` is tagged `k` (redundant planes leave no face).
    pub fn from_planes(planes: &[Plane]) -> Result<Self, GeomError> {
        let reach = planes.iter().map(|p| p.offset.abs()).fold(1.0, f64::max);
        let h = 1e3 * reach;
        let big = u32::MAX;
        let mut poly = Self::from_box(Vec3::repeat(-h), Vec3::repeat(h));
        for f in &mut poly.faces {
            f.tag = FaceTag(big);
        }
        for (k, p) in planes.iter().enumerate() {
            poly = poly.clip(p, FaceTag(k as u32)).ok_or(GeomError::Degenerate { volume: 0.0 })?;
        }
        if poly.faces.iter().any(|f| f.tag.0 == big) {
            return Err(GeomError::Unbounded);
        }
        Ok(poly)
    }

    /// Closed convex polyhedron from vertices and faces (counter-clockwise seen from outside);
    /// face `k` is tagged `k`.
    pub fn from_vertices_faces(vertices: &[Vec3], faces: &[Vec<usize>]) -> Result<Self, GeomError> {
        check_closed(vertices, faces)?;
        let mut out = Vec::with_capacity(faces.len());
        for (k, f) in faces.iter().enumerate() {
            let vs: Vec<Vec3> = f.iter().map(|&i| vertices[i]).collect();
            out.push(Face { vertices: vs, tag: FaceTag(k as u32) });
        }
        let poly = Self { faces: out };
        let vol = poly.volume();
        let diag = poly.aabb().diagonal();
        if !(vol > DEGENERATE_VOLUME_RATIO * diag.powi(3)) {
            return Err(GeomError::Degenerate { volume: vol });
        }
        for (k, f) in poly.faces.iter().enumerate() {
            let n = f.area_vector().normalize();
            let d = n.dot(&f.vertices[0]);
            if let Some(v) = vertices.iter().position(|v| n.dot(v) - d > 1e-9 * diag) {
                return Err(GeomError::NotConvex { face: k, vertex: v });
            }
        }
        Ok(poly)
    }

    /// Bounding box of all vertices.
    pub fn aabb(&self) -> Aabb {
        Aabb::from_points(self.faces.iter().flat_map(|f| f.vertices.iter()))
            .unwrap_or(Aabb { min: Vec3::zeros(), max: Vec3::zeros() })
    }

    /// Volume (divergence theorem over the faces).
    pub fn volume(&self) -> f64 {
        let r = self.reference_point();
        self.fan_tets(r).map(|t| signed_tet_volume(&t)).sum()
    }

    /// Volume centroid.
    pub fn centroid(&self) -> Vec3 {
        let r = self.reference_point();
        let (mut v, mut c) = (0.0, Vec3::zeros());
        for t in self.fan_tets(r) {
            let w = signed_tet_volume(&t);
            v += w;
            c += w * (t[0] + t[1] + t[2] + t[3]) / 4.0;
        }
        if v != 0.0 {
            c / v
        } else {
            r
        }
    }

    /// Distinct vertices (welded within `CLIP_TOLERANCE × diagonal`), in first-seen order.
    pub fn vertices(&self) -> Vec<Vec3> {
        let tol = CLIP_TOLERANCE * self.aabb().diagonal();
        let mut out: Vec<Vec3> = Vec::new();
        for v in self.faces.iter().flat_map(|f| f.vertices.iter()) {
            if !out.iter().any(|w| (w - v).norm() <= tol) {
                out.push(*v);
            }
        }
        out
    }

    /// Whether `p` is inside or on the boundary, within `tol` [m].
    pub fn contains(&self, p: &Vec3, tol: f64) -> bool {
        self.faces.iter().all(|f| {
            let n = f.area_vector().normalize();
            n.dot(&(p - f.vertices[0])) <= tol
        })
    }

    /// The supporting plane of every face (outward normals).
    pub fn face_planes(&self) -> Vec<Plane> {
        self.faces
            .iter()
            .filter_map(|f| Plane::from_point_normal(polygon::centroid(&f.vertices), f.area_vector()))
            .collect()
    }

    /// Image of the polyhedron under a map that preserves orientation (a rigid or affine map
    /// with positive determinant).
    pub fn map(&self, f: impl Fn(&Vec3) -> Vec3) -> Self {
        let faces = self
            .faces
            .iter()
            .map(|face| Face { vertices: face.vertices.iter().map(&f).collect(), tag: face.tag })
            .collect();
        Self { faces }
    }

    /// A point used as apex of the signed tetrahedral decomposition.
    pub fn reference_point(&self) -> Vec3 {
        let n: usize = self.faces.iter().map(|f| f.vertices.len()).sum();
        self.faces.iter().flat_map(|f| f.vertices.iter()).sum::<Vec3>() / n.max(1) as f64
    }

    /// Signed tetrahedral decomposition: apex `r` joined to a fan of every face.
    pub fn fan_tets(&self, r: Vec3) -> impl Iterator<Item = [Vec3; 4]> + '_ {
        self.faces.iter().flat_map(move |f| {
            let v = &f.vertices;
            (1..v.len().saturating_sub(1)).map(move |i| [r, v[0], v[i], v[i + 1]])
        })
    }
}

/// Signed volume of the tetrahedron (a, b, c, d): positive when (b−a, c−a, d−a) is right-handed.
pub fn signed_tet_volume(t: &[Vec3; 4]) -> f64 {
    (t[1] - t[0]).dot(&(t[2] - t[0]).cross(&(t[3] - t[0]))) / 6.0
}

/// Every directed edge must appear exactly once and its reverse exactly once.
pub fn check_closed(vertices: &[Vec3], faces: &[Vec<usize>]) -> Result<(), GeomError> {
    use std::collections::HashMap;
    let mut edges: HashMap<(usize, usize), usize> = HashMap::new();
    for (k, f) in faces.iter().enumerate() {
        if f.len() < 3 {
            return Err(GeomError::NotClosed { reason: format!("face {k} has fewer than 3 vertices") });
        }
        for (i, &a) in f.iter().enumerate() {
            if a >= vertices.len() {
                return Err(GeomError::BadIndex { face: k, vertex: a, count: vertices.len() });
            }
            let b = f[(i + 1) % f.len()];
            if edges.insert((a, b), k).is_some() {
                return Err(GeomError::NotClosed {
                    reason: format!("edge {a}->{b} is used twice in the same direction (face {k}): faces are not consistently oriented"),
                });
            }
        }
    }
    let mut open: Vec<_> = edges.keys().filter(|(a, b)| !edges.contains_key(&(*b, *a))).collect();
    open.sort();
    if let Some((a, b)) = open.first() {
        return Err(GeomError::NotClosed {
            reason: format!("edge {a}->{b} of face {} has no matching reverse edge", edges[&(*a, *b)]),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_volume_and_centroid() {
        let b = ConvexPolyhedron::from_box(Vec3::new(1.0, 2.0, 3.0), Vec3::new(2.0, 4.0, 6.0));
        assert!((b.volume() - 6.0).abs() < 1e-14);
        assert!((b.centroid() - Vec3::new(1.5, 3.0, 4.5)).norm() < 1e-14);
        assert_eq!(b.vertices().len(), 8);
    }

    #[test]
    fn planes_make_a_tetrahedron() {
        let planes = [
            Plane::from_coefficients([-1.0, 0.0, 0.0, 0.0]).unwrap(),
            Plane::from_coefficients([0.0, -1.0, 0.0, 0.0]).unwrap(),
            Plane::from_coefficients([0.0, 0.0, -1.0, 0.0]).unwrap(),
            Plane::from_coefficients([1.0, 1.0, 1.0, 1.0]).unwrap(),
        ];
        let t = ConvexPolyhedron::from_planes(&planes).unwrap();
        assert!((t.volume() - 1.0 / 6.0).abs() < 1e-12);
        assert_eq!(t.faces.len(), 4);
    }

    #[test]
    fn unbounded_planes_are_rejected() {
        let planes = [Plane::from_coefficients([0.0, 0.0, 1.0, 0.0]).unwrap()];
        assert_eq!(ConvexPolyhedron::from_planes(&planes), Err(GeomError::Unbounded));
    }

    #[test]
    fn open_or_misoriented_polyhedra_are_rejected() {
        let v = vec![Vec3::zeros(), Vec3::x(), Vec3::y(), Vec3::z()];
        let good = vec![vec![0, 2, 1], vec![0, 1, 3], vec![0, 3, 2], vec![1, 2, 3]];
        assert!(ConvexPolyhedron::from_vertices_faces(&v, &good).is_ok());
        let flipped = vec![vec![0, 1, 2], vec![0, 1, 3], vec![0, 3, 2], vec![1, 2, 3]];
        assert!(matches!(ConvexPolyhedron::from_vertices_faces(&v, &flipped), Err(GeomError::NotClosed { .. })));
        let open = vec![vec![0, 2, 1], vec![0, 1, 3], vec![0, 3, 2]];
        assert!(ConvexPolyhedron::from_vertices_faces(&v, &open).is_err());
    }
}
