//! Contact detection between two convex pieces: one contact plane per pair and the contact
//! points on it (the entrance modes of the 3-D NMM contact algorithm, He 2011 Part 3; the
//! least-penetrating support plane of the meta-contact search, Wang et al. 2022).
//!
//! 1. **Plane.** Candidate normals are the face normals of both pieces and the cross products
//!    of their edge directions (separating-axis theorem). For each, the separation is
//!    min over A of n·x − max over B of n·x (n pointing from B to A). The largest separation —
//!    the least penetration — picks the contact plane; beyond `margin` there is no contact.
//! 2. **Support polygons.** The vertices of A within `support_tolerance` of its lowest level along
//!    n, and those of B within it of its highest, projected on the plane, give two convex polygons
//!    (a face, an edge or a vertex of each piece).
//! 3. **Points.** Their overlap's corners are the contact points: a corner at a vertex of A is a
//!    vertex-to-face point (point-to-plane mode) against B, one at a vertex of B the reverse, and
//!    a corner where two edges cross is an edge-to-edge point (crossing-lines mode). Vertex-edge,
//!    vertex-vertex and parallel edges reduce to these. A face-to-face contact is the overlap
//!    polygon's corners — several points on one plane, no redundant interior points.
//! 4. **Gaps.** Each point's gap is measured along n between the two supports at that point
//!    (negative: penetration).
//! 5. **Thinning.** Points closer than `thin_distance` are one point (the deeper is kept): a thin
//!    overlap strip — parallel edges, or nearly touching corners — gives one point per end, not
//!    pairs of near-duplicates (Solfec's sparsification, `dom.c`).

use crate::math::Vec3;
use crate::polygon;
use crate::polyhedron::ConvexPolyhedron;

/// Which features meet at a contact point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// A vertex of A against a face of B.
    VertexOfA,
    /// A vertex of B against a face of A.
    VertexOfB,
    /// Crossing edges of A and B.
    EdgeEdge,
}

/// One contact point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPoint {
    /// Entrance mode.
    pub mode: Mode,
    /// Point on A's support surface [m].
    pub on_a: Vec3,
    /// Point on B's support surface [m].
    pub on_b: Vec3,
    /// Gap n·(on_a − on_b) [m]; negative is penetration.
    pub gap: f64,
}

/// The contact of a pair: one plane, its points.
#[derive(Debug, Clone, PartialEq)]
pub struct Contact {
    /// Unit normal from B to A.
    pub normal: Vec3,
    /// Separation along the normal (largest over the candidate axes) [m].
    pub separation: f64,
    /// Contact points on the plane.
    pub points: Vec<ContactPoint>,
    /// Area of the overlap of the two support polygons [m²] (0 for an edge or a point).
    pub area: f64,
}

/// Distinct vertices and edges of a convex polyhedron.
fn vertices_edges(p: &ConvexPolyhedron) -> (Vec<Vec3>, Vec<(usize, usize)>) {
    let verts = p.vertices();
    let tol = 1e-12 * p.aabb().diagonal();
    let id = |x: &Vec3| verts.iter().position(|w| (w - x).norm() <= tol).expect("a face vertex is a vertex");
    let mut edges = Vec::new();
    for f in &p.faces {
        for i in 0..f.vertices.len() {
            let (a, b) = (id(&f.vertices[i]), id(&f.vertices[(i + 1) % f.vertices.len()]));
            let e = (a.min(b), a.max(b));
            if a != b && !edges.contains(&e) {
                edges.push(e);
            }
        }
    }
    (verts, edges)
}

fn support(points: &[Vec3], n: &Vec3) -> (f64, f64) {
    points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(n.dot(v)), hi.max(n.dot(v))))
}

/// Separations within this fraction of the coordinates' scale count as equal when the plane
/// is chosen (face normals are tried first).
const FACE_PREFERENCE: f64 = 1e-9;

/// Tolerances of [`detect`] [m].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DetectParams {
    /// Pieces farther apart than this have no contact.
    pub margin: f64,
    /// Vertices this close to a piece's extreme level along the normal form its support polygon
    /// (how far from flat a face-to-face contact may be).
    pub support_tolerance: f64,
    /// Contact points closer than this are merged (the deeper kept).
    pub thin_distance: f64,
}

/// The least-penetrating contact plane and its points, or `None` beyond the margin.
pub fn detect(a: &ConvexPolyhedron, b: &ConvexPolyhedron, params: &DetectParams) -> Option<Contact> {
    let (margin, support_tolerance) = (params.margin, params.support_tolerance);
    let (va, ea) = vertices_edges(a);
    let (vb, eb) = vertices_edges(b);
    let ca: Vec3 = va.iter().sum::<Vec3>() / va.len() as f64;
    let cb: Vec3 = vb.iter().sum::<Vec3>() / vb.len() as f64;
    let mut axes: Vec<Vec3> = Vec::new();
    axes.extend(b.faces.iter().map(|f| f.area_vector().normalize()));
    axes.extend(a.faces.iter().map(|f| -f.area_vector().normalize()));
    for &(i, j) in &ea {
        for &(k, l) in &eb {
            let n = (va[j] - va[i]).cross(&(vb[l] - vb[k]));
            if n.norm() > 1e-9 * (va[j] - va[i]).norm() * (vb[l] - vb[k]).norm() {
                let n = n.normalize();
                axes.push(if n.dot(&(ca - cb)) >= 0.0 { n } else { -n });
            }
        }
    }
    let separation = |n: &Vec3| support(&va, n).0 - support(&vb, n).1;
    let seps: Vec<f64> = axes.iter().map(separation).collect();
    let top = seps.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    // Ties go to the first axis within round-off of the best, and face normals come first:
    // two blocks meeting on a face must not be given an edge–edge plane through that face.
    let tie = FACE_PREFERENCE * va.iter().chain(&vb).map(|x| x.norm()).fold(1.0, f64::max);
    let k = seps.iter().position(|&s| s >= top - tie).unwrap_or(0);
    let (best, sep) = (axes.get(k).copied().unwrap_or(Vec3::z()), seps.get(k).copied().unwrap_or(top));
    if sep > margin {
        return None;
    }
    let (points, area) = contact_points(&va, &vb, &best, support_tolerance);
    Some(Contact { normal: best, separation: sep, points: thin(points, params.thin_distance), area })
}

/// Merge points closer than `d`, keeping the deeper of each pair (order of first appearance).
fn thin(points: Vec<ContactPoint>, d: f64) -> Vec<ContactPoint> {
    let mut out: Vec<ContactPoint> = Vec::with_capacity(points.len());
    for p in points {
        match out.iter_mut().find(|q| (q.on_a - p.on_a).norm() < d) {
            Some(q) if p.gap < q.gap => *q = p,
            Some(_) => {}
            None => out.push(p),
        }
    }
    out
}

/// 2-D convex hull (counter-clockwise about `n`) of points on a plane, by gift wrapping order.
fn hull(points: &[Vec3], n: &Vec3) -> Vec<Vec3> {
    let mut p: Vec<Vec3> = Vec::new();
    let scale = points.iter().map(|x| x.norm()).fold(1.0, f64::max);
    for x in points {
        if !p.iter().any(|y| (y - x).norm() <= 1e-12 * scale) {
            p.push(*x);
        }
    }
    if p.len() < 3 {
        return p;
    }
    polygon::sort_ccw(&mut p, n);
    // Drop points that are not corners (collinear or inside after angular sort around the centroid).
    let mut changed = true;
    while changed && p.len() > 3 {
        changed = false;
        for i in 0..p.len() {
            let (a, b, c) = (p[(i + p.len() - 1) % p.len()], p[i], p[(i + 1) % p.len()]);
            if (b - a).cross(&(c - b)).dot(n) <= 1e-12 * scale * scale {
                let _ = p.remove(i);
                changed = true;
                break;
            }
        }
    }
    p
}

/// The contact points and the overlap area.
fn contact_points(va: &[Vec3], vb: &[Vec3], n: &Vec3, tol: f64) -> (Vec<ContactPoint>, f64) {
    let (lo_a, _) = support(va, n);
    let (_, hi_b) = support(vb, n);
    let sa: Vec<Vec3> = va.iter().filter(|v| n.dot(v) <= lo_a + tol).copied().collect();
    let sb: Vec<Vec3> = vb.iter().filter(|v| n.dot(v) >= hi_b - tol).copied().collect();
    // Work in the plane through the origin: flat copies, heights kept separately.
    let flat = |v: &Vec3| v - n * n.dot(v);
    let ha = hull(&sa.iter().map(flat).collect::<Vec<_>>(), n);
    let hb = hull(&sb.iter().map(flat).collect::<Vec<_>>(), n);
    let height_a = height_field(&sa, n);
    let height_b = height_field(&sb, n);
    let scale = va.iter().chain(vb).map(|x| x.norm()).fold(1.0, f64::max);
    let eps = 1e-9 * scale;
    let overlap = overlap_2d(&ha, &hb, n, eps);
    let near = |p: &Vec3, set: &[Vec3]| set.iter().any(|q| (q - p).norm() <= 1e-7 * scale);
    let area = if overlap.len() >= 3 { polygon::area_vector(&overlap).norm() } else { 0.0 };
    let points = overlap
        .into_iter()
        .map(|p| {
            let (za, zb) = (height_a(&p), height_b(&p));
            let mode = if near(&p, &ha) {
                Mode::VertexOfA
            } else if near(&p, &hb) {
                Mode::VertexOfB
            } else {
                Mode::EdgeEdge
            };
            ContactPoint { mode, on_a: p + n * za, on_b: p + n * zb, gap: za - zb }
        })
        .collect();
    (points, area)
}

/// Overlap of two flat convex sets (polygon, segment or point), as its corner points.
fn overlap_2d(a: &[Vec3], b: &[Vec3], n: &Vec3, eps: f64) -> Vec<Vec3> {
    match (a.len(), b.len()) {
        (0, _) | (_, 0) => Vec::new(),
        (1, _) => vec![a[0]],
        (_, 1) => vec![b[0]],
        (2, 2) => segment_overlap(a[0], a[1], b[0], b[1], n, eps),
        (2, _) => clip_segment(a[0], a[1], b, n, eps),
        (_, 2) => clip_segment(b[0], b[1], a, n, eps),
        _ => polygon::intersect_convex(a, b, n, eps),
    }
}

/// Where two coplanar segments (as projected) meet: their crossing point, or for parallel
/// overlapping segments (parallel edges) the two ends of the overlap.
fn segment_overlap(p0: Vec3, p1: Vec3, q0: Vec3, q1: Vec3, n: &Vec3, eps: f64) -> Vec<Vec3> {
    let (d, e) = (p1 - p0, q1 - q0);
    let den = d.cross(&e).dot(n);
    if den.abs() <= eps * d.norm().max(e.norm()) {
        if d.cross(&(q0 - p0)).dot(n).abs() > eps * d.norm() {
            return Vec::new(); // parallel, apart
        }
        let t = |q: Vec3| (q - p0).dot(&d) / d.norm_squared();
        let (a, b) = (t(q0).min(t(q1)).max(0.0), t(q0).max(t(q1)).min(1.0));
        return if a <= b { vec![p0 + a * d, p0 + b * d] } else { Vec::new() };
    }
    let t = (q0 - p0).cross(&e).dot(n) / den;
    let s = (q0 - p0).cross(&d).dot(n) / den;
    if (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&s) { vec![p0 + t * d] } else { Vec::new() }
}

/// The part of a segment inside a convex polygon (its two end points).
fn clip_segment(p0: Vec3, p1: Vec3, poly: &[Vec3], n: &Vec3, eps: f64) -> Vec<Vec3> {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    let k = poly.len();
    for i in 0..k {
        let (a, b) = (poly[i], poly[(i + 1) % k]);
        let out = (b - a).cross(n); // outward normal of edge a→b (polygon counter-clockwise about n)
        let (s0, s1) = (out.dot(&(p0 - a)), out.dot(&(p1 - a)));
        if s0 > eps && s1 > eps {
            return Vec::new();
        }
        if s0 > eps || s1 > eps {
            let t = s0 / (s0 - s1);
            if s0 > eps { t0 = t0.max(t) } else { t1 = t1.min(t) }
        }
    }
    if t0 > t1 {
        return Vec::new();
    }
    vec![p0 + t0 * (p1 - p0), p0 + t1 * (p1 - p0)]
}

/// Height (along n) of a support set at a flat point: the plane through it for ≥ 3 points,
/// interpolation along an edge for 2, the vertex's height for 1.
fn height_field(s: &[Vec3], n: &Vec3) -> impl Fn(&Vec3) -> f64 {
    let pts: Vec<Vec3> = s.to_vec();
    let n = *n;
    move |p: &Vec3| {
        let flat = |v: &Vec3| v - n * n.dot(v);
        match pts.len() {
            0 => 0.0,
            1 => n.dot(&pts[0]),
            2 => {
                let (a, b) = (flat(&pts[0]), flat(&pts[1]));
                let t = if (b - a).norm() > 0.0 { ((p - a).dot(&(b - a)) / (b - a).norm_squared()).clamp(0.0, 1.0) } else { 0.0 };
                n.dot(&pts[0]) * (1.0 - t) + n.dot(&pts[1]) * t
            }
            _ => {
                // Least-squares plane h = h0 + g·(p − c) through the support points.
                let c: Vec3 = pts.iter().map(flat).sum::<Vec3>() / pts.len() as f64;
                let h0: f64 = pts.iter().map(|v| n.dot(v)).sum::<f64>() / pts.len() as f64;
                let u = polygon::any_perpendicular(&n);
                let w = n.cross(&u);
                let (mut suu, mut suw, mut sww, mut su, mut sw) = (0.0, 0.0, 0.0, 0.0, 0.0);
                for v in &pts {
                    let (x, y, h) = ((flat(v) - c).dot(&u), (flat(v) - c).dot(&w), n.dot(v) - h0);
                    suu += x * x;
                    suw += x * y;
                    sww += y * y;
                    su += x * h;
                    sw += y * h;
                }
                let det = suu * sww - suw * suw;
                let (gu, gw) = if det.abs() > 1e-300 { ((su * sww - sw * suw) / det, (sw * suu - su * suw) / det) } else { (0.0, 0.0) };
                h0 + gu * (p - c).dot(&u) + gw * (p - c).dot(&w)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::rotation_xyz_deg;

    fn cube(c: Vec3, s: f64) -> ConvexPolyhedron {
        ConvexPolyhedron::from_box(c - Vec3::repeat(s / 2.0), c + Vec3::repeat(s / 2.0))
    }

    fn rotated(p: &ConvexPolyhedron, deg: [f64; 3]) -> ConvexPolyhedron {
        let r = rotation_xyz_deg(deg);
        let c = p.centroid();
        p.map(|x| c + r * (x - c))
    }

    const P: DetectParams = DetectParams { margin: 0.01, support_tolerance: 1e-3, thin_distance: 1e-2 };

    fn count(c: &Contact, m: Mode) -> usize {
        c.points.iter().filter(|p| p.mode == m).count()
    }

    #[test]
    fn cube_resting_on_a_slab_is_four_vertex_points_on_one_plane() {
        let base = ConvexPolyhedron::from_box(Vec3::new(-5.0, -5.0, -1.0), Vec3::new(5.0, 5.0, 0.0));
        let c = detect(&cube(Vec3::new(0.3, 0.2, 0.499), 1.0), &base, &P).unwrap();
        assert!((c.normal - Vec3::z()).norm() < 1e-12);
        assert_eq!(c.points.len(), 4);
        assert_eq!(count(&c, Mode::VertexOfA), 4);
        assert!(c.points.iter().all(|p| (p.gap + 0.001).abs() < 1e-12));
        assert!((c.area - 1.0).abs() < 1e-12, "the whole face is in contact");
        // Turned about z it still sits on its face: four points.
        let c = detect(&rotated(&cube(Vec3::new(0.0, 0.0, 0.499), 1.0), [0.0, 0.0, 30.0]), &base, &P).unwrap();
        assert_eq!(count(&c, Mode::VertexOfA), 4);
    }

    #[test]
    fn tetrahedron_point_down_is_one_vertex_point() {
        let base = ConvexPolyhedron::from_box(Vec3::new(-5.0, -5.0, -1.0), Vec3::new(5.0, 5.0, 0.0));
        let v = [Vec3::new(0.0, 0.0, -0.002), Vec3::new(1.0, 0.0, 1.0), Vec3::new(-0.5, 0.9, 1.0), Vec3::new(-0.5, -0.9, 1.0)];
        let faces = vec![vec![0, 2, 1], vec![0, 1, 3], vec![0, 3, 2], vec![1, 2, 3]];
        let tet = ConvexPolyhedron::from_vertices_faces(&v, &faces).unwrap();
        let c = detect(&tet, &base, &DetectParams { margin: 0.01, support_tolerance: 1e-3, thin_distance: 1e-2 }).unwrap();
        assert_eq!(c.points.len(), 1);
        assert_eq!(c.points[0].mode, Mode::VertexOfA);
        assert!((c.points[0].gap + 0.002).abs() < 1e-12);
        assert_eq!(c.area, 0.0);
    }

    #[test]
    fn cube_on_its_edge_is_two_points() {
        let base = ConvexPolyhedron::from_box(Vec3::new(-5.0, -5.0, -1.0), Vec3::new(5.0, 5.0, 0.0));
        let h = 0.5 * 2f64.sqrt();
        let c = detect(&rotated(&cube(Vec3::new(0.0, 0.0, h - 0.001), 1.0), [45.0, 0.0, 0.0]), &base, &DetectParams { margin: 0.01, support_tolerance: 1e-4, thin_distance: 1e-2 }).unwrap();
        assert_eq!(c.points.len(), 2, "{:?}", c.points);
        assert!(c.points.iter().all(|p| (p.gap + 0.001).abs() < 1e-9));
    }

    #[test]
    fn crossing_beams_touch_at_four_edge_crossings() {
        // Two beams crossing at right angles (a dougong layer): the overlap is a square whose
        // corners are where the beams' edges cross.
        let lower = ConvexPolyhedron::from_box(Vec3::new(-3.0, -0.5, -1.0), Vec3::new(3.0, 0.5, 0.0));
        let upper = ConvexPolyhedron::from_box(Vec3::new(-0.4, -3.0, -0.001), Vec3::new(0.4, 3.0, 1.0));
        let c = detect(&upper, &lower, &DetectParams { margin: 0.01, support_tolerance: 1e-4, thin_distance: 1e-2 }).unwrap();
        assert!((c.normal - Vec3::z()).norm() < 1e-12);
        assert_eq!(c.points.len(), 4);
        assert_eq!(count(&c, Mode::EdgeEdge), 4, "{:?}", c.points);
        assert!((c.area - 0.8).abs() < 1e-12, "the crossing square 0.8 × 1");
    }

    #[test]
    fn crossing_edges_are_one_edge_edge_point() {
        let lower = rotated(&cube(Vec3::new(0.0, 0.0, 0.0), 1.0), [45.0, 0.0, 0.0]);
        let h = 2f64.sqrt();
        let upper = rotated(&cube(Vec3::new(0.0, 0.0, h - 0.001), 1.0), [0.0, 45.0, 0.0]);
        let c = detect(&upper, &lower, &DetectParams { margin: 0.01, support_tolerance: 1e-4, thin_distance: 1e-2 }).unwrap();
        assert_eq!(c.points.len(), 1, "{:?}", c.points);
        assert_eq!(c.points[0].mode, Mode::EdgeEdge);
        assert!((c.points[0].gap + 0.001).abs() < 1e-9);
        assert!((c.normal - Vec3::z()).norm() < 1e-9);
    }

    #[test]
    fn parallel_edges_touch_along_their_overlap() {
        // Two cubes on their edges, edges parallel (both along x), offset along x.
        let lower = rotated(&cube(Vec3::zeros(), 1.0), [45.0, 0.0, 0.0]);
        let h = 2f64.sqrt();
        let upper = rotated(&cube(Vec3::new(0.4, 0.0, h - 0.001), 1.0), [45.0, 0.0, 0.0]);
        let c = detect(&upper, &lower, &DetectParams { margin: 0.01, support_tolerance: 1e-4, thin_distance: 1e-2 }).unwrap();
        assert_eq!(c.points.len(), 2, "{:?}", c.points);
        let xs: Vec<f64> = c.points.iter().map(|p| p.on_a.x).collect();
        assert!((xs[0].min(xs[1]) + 0.1).abs() < 1e-9 && (xs[0].max(xs[1]) - 0.5).abs() < 1e-9, "{xs:?}");
    }

    #[test]
    fn pieces_beyond_the_margin_do_not_touch() {
        let a = cube(Vec3::new(0.0, 0.0, 2.0), 1.0);
        let b = cube(Vec3::zeros(), 1.0);
        assert!(detect(&a, &b, &DetectParams { margin: 0.5, support_tolerance: 1e-3, thin_distance: 1e-2 }).is_none());
        let c = detect(&a, &b, &DetectParams { margin: 1.5, support_tolerance: 1e-3, thin_distance: 1e-2 }).unwrap();
        assert!((c.separation - 1.0).abs() < 1e-12 && c.points.iter().all(|p| (p.gap - 1.0).abs() < 1e-12));
    }
}
