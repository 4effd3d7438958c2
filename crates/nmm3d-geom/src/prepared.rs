//! A convex piece prepared for contact detection: distinct vertices, faces, edges with their
//! two faces, centroid and face normals — computed once per piece, not once per pair it is in.

use crate::math::Vec3;
use crate::polyhedron::ConvexPolyhedron;

/// A piece prepared for detection: its distinct vertices, faces (vertex indices), edges,
/// centroid and outward unit face normals — computed once per piece, not once per pair it is in.
#[derive(Debug, Clone)]
pub struct Prepared {
    pub(crate) vertices: Vec<Vec3>,
    pub(crate) faces: Vec<Vec<usize>>,
    pub(crate) edges: Vec<Edge>,
    pub(crate) centroid: Vec3,
    pub(crate) normals: Vec<Vec3>,
}

/// An edge: its two vertices and the two faces meeting there.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Edge {
    pub(crate) ends: (usize, usize),
    pub(crate) faces: (usize, usize),
}

impl Prepared {
    /// Prepare a convex polyhedron.
    pub fn new(p: &ConvexPolyhedron) -> Self {
        let vertices = p.vertices();
        let tol = 1e-12 * p.aabb().diagonal();
        let id = |x: &Vec3| vertices.iter().position(|w| (w - x).norm() <= tol).expect("a face vertex is a vertex");
        let faces: Vec<Vec<usize>> = p.faces.iter().map(|f| f.vertices.iter().map(id).collect()).collect();
        let mut edges: Vec<Edge> = Vec::new();
        for (fi, f) in faces.iter().enumerate() {
            for i in 0..f.len() {
                let (a, b) = (f[i], f[(i + 1) % f.len()]);
                let ends = (a.min(b), a.max(b));
                if a == b {
                    continue;
                }
                match edges.iter_mut().find(|e| e.ends == ends) {
                    Some(e) => e.faces.1 = fi,
                    None => edges.push(Edge { ends, faces: (fi, fi) }),
                }
            }
        }
        let centroid = vertices.iter().sum::<Vec3>() / vertices.len() as f64;
        let normals = p.faces.iter().map(|f| f.area_vector().normalize()).collect();
        Self { vertices, faces, edges, centroid, normals }
    }

    /// Height along `m` where the line through flat point `p` enters the piece from below (`None`
    /// when it misses the piece).
    pub(crate) fn lower_surface(&self, p: &Vec3, m: &Vec3) -> Option<f64> {
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for (face, k) in self.faces.iter().zip(&self.normals) {
            // k·(p + t m − q) ≤ 0 on the inside of the face's plane.
            let (km, kd) = (k.dot(m), k.dot(&(self.vertices[face[0]] - p)));
            if km < 0.0 {
                lo = lo.max(kd / km);
            } else if km > 0.0 {
                hi = hi.min(kd / km);
            }
        }
        let tol = 1e-9 * (lo.abs() + hi.abs()).max(1.0);
        (lo.is_finite() && lo <= hi + tol).then_some(lo)
    }
}

/// Whether edge `ea` of A and edge `eb` of B build a face of the Minkowski difference A − B:
/// the arcs of their adjacent face normals cross on the Gauss map (normals of B negated).
/// Gregorius, "The Separating Axis Test between Convex Polyhedra", GDC 2013.
pub(crate) fn minkowski_face(a: &Prepared, ea: &Edge, b: &Prepared, eb: &Edge) -> bool {
    let (u1, u2) = (a.normals[ea.faces.0], a.normals[ea.faces.1]);
    let (v1, v2) = (-b.normals[eb.faces.0], -b.normals[eb.faces.1]);
    let (u_arc, v_arc) = (u2.cross(&u1), v2.cross(&v1));
    let (cba, dba) = (v1.dot(&u_arc), v2.dot(&u_arc));
    let (adc, bdc) = (u1.dot(&v_arc), u2.dot(&v_arc));
    cba * dba < 0.0 && adc * bdc < 0.0 && cba * bdc > 0.0
}
