//! Contact facets: the boundary faces of the manifold elements on a block's surface — the
//! lower levels of the contact hierarchy body → contact ME → contact facet → edge → vertex
//! (He 2011, Part 3).
//!
//! A face-to-face contact found between two pieces (one plane per pair) is resolved on the
//! facets: the facets of A and of B lying on the contact plane are overlaid, and every corner of
//! every overlap (facet of A ∩ facet of B) is a contact point — vertices of A's facets inside B's
//! (point-to-plane mode), vertices of B's facets inside A's, and crossings of facet edges
//! (crossing-lines mode). Each overlap's area is shared equally by its corners; coincident
//! corners of neighbouring overlaps are one point with the summed area. The pressure is thus
//! carried at the resolution of the covers instead of at the corners of the face only, which
//! would bend the faces and lock in spurious shear.

use rustc_hash::FxHashMap;

use nmm3d_geom::contact::Mode;
use nmm3d_geom::polygon;
use nmm3d_geom::Vec3;

use super::point::{barycentric, MaterialPoint};
use crate::model::tags;
use crate::system::System;

/// One boundary face of one ME.
#[derive(Debug, Clone)]
pub struct Facet {
    /// Its vertices as material points of the ME (counter-clockwise seen from outside).
    pub vertices: Vec<MaterialPoint>,
}

/// A contact point found on the facets (or, failing them, on the pieces).
#[derive(Debug, Clone)]
pub struct Candidate {
    /// Which features meet.
    pub mode: Mode,
    /// Material point on A.
    pub a: MaterialPoint,
    /// Material point on B.
    pub b: MaterialPoint,
    /// Current position on A [m].
    pub on_a: Vec3,
    /// Gap along the contact normal [m].
    pub gap: f64,
    /// Share of the contact area [m²].
    pub area: f64,
}

/// Boundary facets of every ME of `block` lying on the reference piece `piece` (its surface).
pub fn facets_of_piece(sys: &System, block: usize, piece: &nmm3d_geom::ConvexPolyhedron) -> Vec<Facet> {
    let tol = ON_PIECE * sys.covers.mesh.size;
    let covers = &sys.covers;
    let mut out = Vec::new();
    for (e, me) in covers.elements.iter().enumerate().filter(|(_, me)| me.block == block) {
        let corner = crate::cover::mesh::cell_corner(me.cell);
        for f in me.boundary_faces() {
            let x: Vec<Vec3> = f.vertices.iter().map(|xi| covers.mesh.to_global(&(corner + xi))).collect();
            if !x.iter().all(|p| piece.contains(p, tol)) || !tags::is_boundary(f.tag) {
                continue;
            }
            let vertices = x
                .into_iter()
                .map(|p| MaterialPoint {
                    element: e,
                    weights: crate::element::loads::weights_at(covers, me, &p),
                    reference: p,
                })
                .collect();
            out.push(Facet { vertices });
        }
    }
    out
}

/// Facets of a piece (with their current vertices `x`) facing along `outward` whose every
/// vertex lies within `tol` of the level `level` (n·x).
fn on_level<'a>(
    facets: &'a [Facet],
    x: &'a [Vec<Vec3>],
    n: &Vec3,
    level: f64,
    outward: f64,
    tol: f64,
) -> Vec<(&'a Facet, &'a [Vec3])> {
    facets
        .iter()
        .zip(x)
        .filter(|(_, x)| {
            x.iter().all(|p| (n.dot(p) - level).abs() <= tol) && outward * polygon::area_vector(x).dot(n) > 0.0
        })
        .map(|(f, x)| (f, x.as_slice()))
        .collect()
}

/// Contact points of a face-to-face contact with normal `n` (from B to A) on the facets of A
/// and of B (each with their current vertices), A's lowest and B's highest level along `n`;
/// empty when either side has no facet on the contact plane (a vertex or an edge meets a face:
/// the piece-level points stand).
pub fn overlay(
    sys: &System,
    (fa, xa): (&[Facet], &[Vec<Vec3>]),
    (fb, xb): (&[Facet], &[Vec<Vec3>]),
    n: &Vec3,
    (level_a, level_b): (f64, f64),
    tol: f64,
    merge: f64,
) -> Vec<Candidate> {
    let sa = on_level(fa, xa, n, level_a, -1.0, tol);
    let sb = on_level(fb, xb, n, level_b, 1.0, tol);
    if sa.is_empty() || sb.is_empty() {
        return Vec::new();
    }
    let flat = |p: &Vec3| p - n * n.dot(p);
    // A's facets are clockwise about n (they face −n): reverse them for the 2-D overlay.
    let pa: Vec<Vec<Vec3>> = sa.iter().map(|(_, x)| x.iter().rev().map(flat).collect()).collect();
    let pb: Vec<Vec<Vec3>> = sb.iter().map(|(_, x)| x.iter().map(flat).collect()).collect();
    let bounds = |p: &[Vec3]| {
        p.iter()
            .fold((Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY)), |(lo, hi), v| (lo.inf(v), hi.sup(v)))
    };
    let ba: Vec<_> = pa.iter().map(|p| bounds(p)).collect();
    let bb: Vec<_> = pb.iter().map(|p| bounds(p)).collect();
    let eps = 1e-6 * tol;
    let mut points: Vec<Candidate> = Vec::new();
    let mut index: FxHashMap<[i64; 3], Vec<usize>> = FxHashMap::default();
    for (i, (fa_, xa)) in sa.iter().enumerate() {
        for (j, (fb_, xb)) in sb.iter().enumerate() {
            let (lo, hi) = (ba[i].0.sup(&bb[j].0), ba[i].1.inf(&bb[j].1));
            if (0..3).any(|k| lo[k] > hi[k] + eps) {
                continue;
            }
            let cell = polygon::intersect_convex(&pa[i], &pb[j], n, eps);
            if cell.len() < 3 {
                continue;
            }
            let share = polygon::area_vector(&cell).norm() / cell.len() as f64;
            for p in &cell {
                let (on_a, ref_a) = lift(p, n, xa, fa_);
                let (on_b, ref_b) = lift(p, n, xb, fb_);
                if let Some(k) = find(&index, &points, &on_a, merge) {
                    points[k].area += share;
                    continue;
                }
                let mode = if xa.iter().any(|v| (flat(v) - p).norm() <= merge) {
                    Mode::VertexOfA
                } else if xb.iter().any(|v| (flat(v) - p).norm() <= merge) {
                    Mode::VertexOfB
                } else {
                    Mode::EdgeEdge
                };
                let a = MaterialPoint::on_element(sys, fa_.vertices[0].element, ref_a);
                let b = MaterialPoint::on_element(sys, fb_.vertices[0].element, ref_b);
                index.entry(key(&on_a, merge)).or_default().push(points.len());
                points.push(Candidate { mode, a, b, on_a, gap: n.dot(&(on_a - on_b)), area: share });
            }
        }
    }
    points
}

/// The point of the facet (current vertices `x`) above the flat point `p` along `n`, and its
/// reference position (the same affine combination of a fan triangle's reference vertices).
fn lift(p: &Vec3, n: &Vec3, x: &[Vec3], f: &Facet) -> (Vec3, Vec3) {
    let m = polygon::area_vector(x);
    let z = m.dot(&(x[0] - p)) / m.dot(n);
    let q = p + n * z;
    let mut best = (f64::INFINITY, x[0], f.vertices[0].reference);
    for i in 1..x.len() - 1 {
        let (l, d) = barycentric(&q, &x[0], &x[i], &x[i + 1]);
        if d < best.0 {
            let r = |k: usize| f.vertices[k].reference;
            best = (d, q, l[0] * r(0) + l[1] * r(i) + l[2] * r(i + 1));
        }
    }
    (best.1, best.2)
}

fn key(x: &Vec3, h: f64) -> [i64; 3] {
    [(x.x / h).floor() as i64, (x.y / h).floor() as i64, (x.z / h).floor() as i64]
}

/// A point already found within `h` of `x`.
fn find(index: &FxHashMap<[i64; 3], Vec<usize>>, points: &[Candidate], x: &Vec3, h: f64) -> Option<usize> {
    let k = key(x, h);
    for dz in -1..=1 {
        for dy in -1..=1 {
            for dx in -1..=1 {
                if let Some(ids) = index.get(&[k[0] + dx, k[1] + dy, k[2] + dz]) {
                    if let Some(&i) = ids.iter().find(|&&i| (points[i].on_a - x).norm() <= h) {
                        return Some(i);
                    }
                }
            }
        }
    }
    None
}

/// A facet lies on a piece when its vertices are within this fraction of the cover size of it.
const ON_PIECE: f64 = 1e-9;
