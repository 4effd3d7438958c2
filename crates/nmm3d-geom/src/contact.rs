//! Contact detection between two convex pieces: one contact plane per pair and the contact
//! points on it (the entrance modes of the 3-D NMM contact algorithm, He 2011 Part 3; the
//! least-penetrating support plane of the meta-contact search, Wang et al. 2022).
//!
//! 1. **Plane.** Candidate normals are the face normals of both pieces and the cross products
//!    of those pairs of edges that build a face of the Minkowski difference (separating-axis
//!    theorem with the Gauss-map test, Gregorius 2013). For each, the separation is
//!    min over A of n·x − max over B of n·x (n pointing from B to A). The largest separation —
//!    the least penetration — picks the contact plane, face normals winning ties within the
//!    support tolerance; beyond `margin` there is no contact. Pieces overlapping by more than the
//!    support tolerance whose supports miss each other on that plane (deformed pieces are only
//!    nearly convex) try the next planes, at most ten support tolerances deeper.
//! 2. **Support polygons.** The vertices of A within `support_tolerance` of its lowest level along
//!    n, and those of B within it of its highest, projected on the plane, give two convex polygons
//!    (a face, an edge or a vertex of each piece); the piece whose face gives the plane takes that
//!    whole face, however warped.
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

use crate::flat::{height_field, hull, inside, overlap_2d, segment_overlap, support};
use crate::math::Vec3;
use crate::polygon;
use crate::polyhedron::ConvexPolyhedron;
use crate::prepared::minkowski_face;
pub use crate::prepared::Prepared;

/// Which features meet at a contact point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
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
    /// Vertices of one piece within the margin of the other's face that gives the plane,
    /// projecting inside it, but not on the support (beyond the support tolerance): corners
    /// that can reach the face within a step — a tipping edge's far end, a block turning onto
    /// a face. Without a point they would pass into the face unresisted and be found at the
    /// next detection already deep, to be pushed out with energy from nowhere (DDA detects
    /// every vertex within its step's reach for the same reason: Shi 1988, ch. 4).
    pub approaching: Vec<ContactPoint>,
}

/// Separations within this fraction of the coordinates' scale (at least within the support
/// tolerance) count as equal when the plane is chosen (face normals are tried first).
const FACE_PREFERENCE: f64 = 1e-9;

/// How much deeper than the least-penetrating plane, in support tolerances, a plane may be
/// and still be tried when the supports on the better planes do not overlap.
const FALLBACK_DEPTH: f64 = 10.0;

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
    detect_prepared(&Prepared::new(a), &Prepared::new(b), params)
}

/// [`detect`] on prepared pieces.
pub fn detect_prepared(a: &Prepared, b: &Prepared, params: &DetectParams) -> Option<Contact> {
    let (margin, support_tolerance) = (params.margin, params.support_tolerance);
    let (va, vb) = (&a.vertices, &b.vertices);
    let mut axes: Vec<Vec3> = Vec::with_capacity(a.normals.len() + b.normals.len() + a.edges.len() * b.edges.len());
    axes.extend(b.normals.iter().copied());
    axes.extend(a.normals.iter().map(|n| -n));
    for ea in &a.edges {
        for eb in &b.edges {
            // Only edge pairs forming a face of the Minkowski difference give an axis: the others
            // point where neither edge meets the other piece, and would pick a plane on which
            // the two supports do not overlap (no contact point at all).
            if !minkowski_face(a, ea, b, eb) {
                continue;
            }
            let ((i, j), (k, l)) = (ea.ends, eb.ends);
            let n = (va[j] - va[i]).cross(&(vb[l] - vb[k]));
            if n.norm() > 1e-9 * (va[j] - va[i]).norm() * (vb[l] - vb[k]).norm() {
                let n = n.normalize();
                axes.push(if n.dot(&(a.centroid - b.centroid)) >= 0.0 { n } else { -n });
            }
        }
    }
    let separation = |n: &Vec3| support(va, n).0 - support(vb, n).1;
    let mut seps: Vec<f64> = Vec::with_capacity(axes.len());
    for n in &axes {
        let s = separation(n);
        if s > margin {
            return None; // the largest separation is beyond the margin too
        }
        seps.push(s);
    }
    let top = seps.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    // Ties go to the first face normal within the support tolerance of the best: two blocks
    // meeting on a face must not be given an edge–edge plane through that face (an edge of A
    // lying on a face of B gives an edge–edge axis within round-off, or within the slight
    // misalignment of deformed pieces, of B's face normal). Without such a face the best axis
    // itself: another edge pair within the tolerance can be two edges far apart (two long
    // blocks of the thesis slope crossing at an edge: a corner 1.3 m from the other's edge was
    // taken for a point, whose material point lay 11 cm inside the block — the pair then read
    // as open while the blocks passed 7 cm into each other).
    let tie = (FACE_PREFERENCE * va.iter().chain(vb).map(|x| x.norm()).fold(1.0, f64::max)).max(support_tolerance);
    let faces = b.normals.len() + a.normals.len();
    let best = (0..seps.len()).fold(0, |k, m| if seps[m] > seps[k] { m } else { k });
    let k = seps[..faces.min(seps.len())].iter().position(|&s| s >= top - tie).unwrap_or(best);
    if axes.is_empty() || seps[k] > margin {
        return None;
    }
    // Deformed pieces are convex only nearly: the supports on the least-penetrating plane may
    // miss each other by a fraction of a millimetre (a corner just short of an edge) while the
    // pieces overlap. Then the next planes, at most `FALLBACK_DEPTH` support tolerances deeper,
    // are tried in order: overlapping pieces must not be left without points. Pieces apart or
    // just touching (diagonal neighbours, blocks meeting at an edge of a joint) are left alone:
    // a deeper plane would give them an overlap they do not have.
    // An edge–edge plane whose supports miss each other while the pieces overlap at all is the
    // same failure on warped faces (a corner pressed into a face that is out of plane by more
    // than the support tolerance: the best axis crosses two edges that do not meet).
    let edge_plane = k >= b.normals.len() + a.normals.len();
    let overlapping = top < -support_tolerance || (edge_plane && top < 0.0);
    let mut order: Vec<usize> = (0..axes.len())
        .filter(|&m| overlapping && m != k && seps[m] >= top - FALLBACK_DEPTH * support_tolerance)
        .collect();
    order.sort_by(|&p, &q| seps[q].total_cmp(&seps[p]));
    let mut first = None;
    for m in std::iter::once(k).chain(order) {
        let c = contact_on_axis(a, b, m, axes[m], seps[m], params);
        if !c.points.is_empty() {
            return Some(c);
        }
        first.get_or_insert(c);
    }
    first
}

/// The contact on candidate axis `m` (an index into B's face normals, then A's, then edge pairs).
fn contact_on_axis(
    a: &Prepared,
    b: &Prepared,
    m: usize,
    normal: Vec3,
    separation: f64,
    params: &DetectParams,
) -> Contact {
    // A plane given by a face: that whole face is its piece's support, however far from flat
    // the deformed face is (its vertices need not all lie within the support tolerance).
    let (nb, na) = (b.normals.len(), a.normals.len());
    let face_b = (m < nb).then(|| b.faces[m].as_slice());
    let face_a = (nb <= m && m < nb + na).then(|| a.faces[m - nb].as_slice());
    let (mut points, mut area) =
        contact_points((&a.vertices, face_a), (&b.vertices, face_b), &normal, params.support_tolerance);
    if let [corner] = points.as_slice() {
        if let Some(crossing) =
            past_the_face((a, face_a), (b, face_b), &normal, corner, (params.support_tolerance, params.thin_distance))
        {
            (points, area) = (crossing, 0.0);
        }
    }
    let points = thin(points, params.thin_distance);
    let approaching = approaching((a, face_a), (b, face_b), &normal, params)
        .into_iter()
        .filter(|p| points.iter().all(|q| (q.on_a - p.on_a).norm() >= params.thin_distance))
        .collect();
    Contact { normal, separation, points, area, approaching }
}

/// A single corner that is the support of one piece but lies past the edge of the other's face
/// that gives the plane (as projected) is no contact point: what overlaps there are the edges
/// running from it, crossing that face's edges. The points are then where the gap can be
/// least — the corners of the overlap of the face with the footprint of the piece's part beyond
/// the face's plane, the piece's corners over the face and its edges crossing the face's edges —
/// each at the piece's surface above it, kept where within the support tolerance (`None` when
/// the corner projects inside the face). Measured on the thesis slope: such a corner 13 cm past
/// an edge gave a point whose spring never held the blocks, which then crossed by 3.5 cm and
/// were pushed apart with energy from nowhere.
fn past_the_face(
    (a, face_a): (&Prepared, Option<&[usize]>),
    (b, face_b): (&Prepared, Option<&[usize]>),
    n: &Vec3,
    corner: &ContactPoint,
    (tol, near): (f64, f64),
) -> Option<Vec<ContactPoint>> {
    // The face's piece `f` (its outward normal `m` towards the other), the corner's piece `o`.
    let (f, face, o, m, x) = match (face_a, face_b) {
        (_, Some(face)) => (b, face, a, *n, corner.on_a),
        (Some(face), None) => (a, face, b, -n, corner.on_b),
        (None, None) => return None,
    };
    let flat = |v: &Vec3| v - m * m.dot(v);
    let on_face: Vec<Vec3> = face.iter().map(|&i| f.vertices[i]).collect();
    let outline = hull(&on_face.iter().map(flat).collect::<Vec<_>>(), &m);
    let scale = f.vertices.iter().chain(&o.vertices).map(|x| x.norm()).fold(1.0, f64::max);
    let eps = 1e-9 * scale;
    // A corner past the edge by less than the thinning distance is the point: the crossings
    // would lie within that distance of it, and swapping them for it as the corner passes the
    // edge gave the dominos a step of energy.
    if outline.len() < 3 || inside(&outline, &flat(&x), &m, near) {
        return None;
    }
    // The part of `o` beyond the face's plane (below its top along m): vertices and edge crossings.
    let level = on_face.iter().map(|v| m.dot(v)).fold(f64::NEG_INFINITY, f64::max);
    let beyond: Vec<Vec3> = o.vertices.iter().filter(|v| m.dot(v) <= level).map(flat).collect();
    let mut part = beyond.clone();
    for e in &o.edges {
        let (p, q) = (o.vertices[e.ends.0], o.vertices[e.ends.1]);
        let (hp, hq) = (m.dot(&p) - level, m.dot(&q) - level);
        if hp * hq < 0.0 {
            part.push(flat(&(p + (q - p) * (hp / (hp - hq)))));
        }
    }
    // Where the gap can be least: the corners of that overlap, the piece's corners over the
    // face and its edges crossing the face's edges (its lower surface is convex, the face flat).
    let mut at = overlap_2d(&hull(&part, &m), &outline, &m, (eps, eps));
    at.extend(beyond.into_iter().filter(|p| inside(&outline, p, &m, eps)));
    for e in o.edges.iter().filter(|e| m.dot(&o.vertices[e.ends.0]).min(m.dot(&o.vertices[e.ends.1])) <= level) {
        let (p, q) = (flat(&o.vertices[e.ends.0]), flat(&o.vertices[e.ends.1]));
        for i in 0..outline.len() {
            at.extend(segment_overlap(p, q, outline[i], outline[(i + 1) % outline.len()], &m, eps));
        }
    }
    let height = height_field(&on_face, &m);
    let o_is_a = face_b.is_some();
    let (vertex_of_o, vertex_of_f) =
        if o_is_a { (Mode::VertexOfA, Mode::VertexOfB) } else { (Mode::VertexOfB, Mode::VertexOfA) };
    let points = at
        .into_iter()
        .filter_map(|p| {
            let (zo, zf) = (o.lower_surface(&p, &m)?, height(&p));
            let near = |v: &[Vec3]| v.iter().any(|w| (flat(w) - p).norm() <= 1e-7 * scale);
            let (of_o, of_f) = (near(&o.vertices), near(&on_face));
            let (on_o, on_f) = (p + m * zo, p + m * zf);
            let mode = match (of_o, of_f) {
                (true, _) => vertex_of_o,
                (_, true) => vertex_of_f,
                _ => Mode::EdgeEdge,
            };
            let (on_a, on_b) = if o_is_a { (on_o, on_f) } else { (on_f, on_o) };
            let gap = zo - zf;
            (gap <= tol).then_some(ContactPoint { mode, on_a, on_b, gap })
        })
        .collect();
    Some(points)
}

/// The vertices of one piece approaching the other's face that gives the plane (see
/// [`Contact::approaching`]): within `margin` of the face's plane, beyond the support
/// tolerance from the support level, projecting inside the face.
fn approaching(
    (a, face_a): (&Prepared, Option<&[usize]>),
    (b, face_b): (&Prepared, Option<&[usize]>),
    n: &Vec3,
    params: &DetectParams,
) -> Vec<ContactPoint> {
    // The face's side is `face`, the vertices' side `others`; `s` = +1 when the face is A's.
    let (face, face_vertices, others, s, mode) = match (face_a, face_b) {
        (Some(f), _) => (f, &a.vertices, &b.vertices, 1.0, Mode::VertexOfB),
        (None, Some(f)) => (f, &b.vertices, &a.vertices, -1.0, Mode::VertexOfA),
        (None, None) => return Vec::new(),
    };
    let on_face: Vec<Vec3> = face.iter().map(|&i| face_vertices[i]).collect();
    let flat = |v: &Vec3| v - n * n.dot(v);
    let outline = hull(&on_face.iter().map(flat).collect::<Vec<_>>(), n);
    if outline.len() < 3 {
        return Vec::new();
    }
    let height = height_field(&on_face, n);
    let scale = face_vertices.iter().chain(others).map(|x| x.norm()).fold(1.0, f64::max);
    let eps = 1e-9 * scale;
    // The support level of the vertices' side (its extreme towards the face).
    let level = others.iter().map(|v| s * n.dot(v)).fold(f64::NEG_INFINITY, f64::max);
    others
        .iter()
        .filter(|v| s * n.dot(v) < level - params.support_tolerance)
        .filter_map(|v| {
            let p = flat(v);
            let gap = s * (height(&p) - n.dot(v));
            (gap <= params.margin && inside(&outline, &p, n, eps)).then(|| {
                let on_face = p + n * height(&p);
                let (on_a, on_b) = if s > 0.0 { (on_face, *v) } else { (*v, on_face) };
                ContactPoint { mode, on_a, on_b, gap }
            })
        })
        .collect()
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

/// The contact points and the overlap area. Each side's support is its face giving the plane,
/// if any, else its vertices within `tol` of its extreme level along n.
fn contact_points(
    (va, face_a): (&[Vec3], Option<&[usize]>),
    (vb, face_b): (&[Vec3], Option<&[usize]>),
    n: &Vec3,
    tol: f64,
) -> (Vec<ContactPoint>, f64) {
    let (lo_a, _) = support(va, n);
    let (_, hi_b) = support(vb, n);
    let sa: Vec<Vec3> = match face_a {
        Some(f) => f.iter().map(|&i| va[i]).collect(),
        None => va.iter().filter(|v| n.dot(v) <= lo_a + tol).copied().collect(),
    };
    let sb: Vec<Vec3> = match face_b {
        Some(f) => f.iter().map(|&i| vb[i]).collect(),
        None => vb.iter().filter(|v| n.dot(v) >= hi_b - tol).copied().collect(),
    };
    // Work in the plane through the origin: flat copies, heights kept separately.
    let flat = |v: &Vec3| v - n * n.dot(v);
    let ha = hull(&sa.iter().map(flat).collect::<Vec<_>>(), n);
    let hb = hull(&sb.iter().map(flat).collect::<Vec<_>>(), n);
    let height_a = height_field(&sa, n);
    let height_b = height_field(&sb, n);
    let scale = va.iter().chain(vb).map(|x| x.norm()).fold(1.0, f64::max);
    let eps = 1e-9 * scale;
    let overlap = overlap_2d(&ha, &hb, n, (eps, tol));
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::rotation_xyz_deg;
    use crate::polyhedron::{Face, FaceTag};

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
        let v = [
            Vec3::new(0.0, 0.0, -0.002),
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::new(-0.5, 0.9, 1.0),
            Vec3::new(-0.5, -0.9, 1.0),
        ];
        let faces = vec![vec![0, 2, 1], vec![0, 1, 3], vec![0, 3, 2], vec![1, 2, 3]];
        let tet = ConvexPolyhedron::from_vertices_faces(&v, &faces).unwrap();
        let c =
            detect(&tet, &base, &DetectParams { margin: 0.01, support_tolerance: 1e-3, thin_distance: 1e-2 }).unwrap();
        assert_eq!(c.points.len(), 1);
        assert_eq!(c.points[0].mode, Mode::VertexOfA);
        assert!((c.points[0].gap + 0.002).abs() < 1e-12);
        assert_eq!(c.area, 0.0);
    }

    #[test]
    fn cube_on_its_edge_is_two_points() {
        let base = ConvexPolyhedron::from_box(Vec3::new(-5.0, -5.0, -1.0), Vec3::new(5.0, 5.0, 0.0));
        let h = 0.5 * 2f64.sqrt();
        let c = detect(
            &rotated(&cube(Vec3::new(0.0, 0.0, h - 0.001), 1.0), [45.0, 0.0, 0.0]),
            &base,
            &DetectParams { margin: 0.01, support_tolerance: 1e-4, thin_distance: 1e-2 },
        )
        .unwrap();
        assert_eq!(c.points.len(), 2, "{:?}", c.points);
        assert!(c.points.iter().all(|p| (p.gap + 0.001).abs() < 1e-9));
    }

    #[test]
    fn crossing_beams_touch_at_four_edge_crossings() {
        // Two beams crossing at right angles (a dougong layer): the overlap is a square whose
        // corners are where the beams' edges cross.
        let lower = ConvexPolyhedron::from_box(Vec3::new(-3.0, -0.5, -1.0), Vec3::new(3.0, 0.5, 0.0));
        let upper = ConvexPolyhedron::from_box(Vec3::new(-0.4, -3.0, -0.001), Vec3::new(0.4, 3.0, 1.0));
        let c = detect(&upper, &lower, &DetectParams { margin: 0.01, support_tolerance: 1e-4, thin_distance: 1e-2 })
            .unwrap();
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
        let c = detect(&upper, &lower, &DetectParams { margin: 0.01, support_tolerance: 1e-4, thin_distance: 1e-2 })
            .unwrap();
        assert_eq!(c.points.len(), 1, "{:?}", c.points);
        assert_eq!(c.points[0].mode, Mode::EdgeEdge);
        assert!((c.points[0].gap + 0.001).abs() < 1e-9);
        assert!((c.normal - Vec3::z()).norm() < 1e-9);
    }

    /// A reference box with its vertices moved to `current` (in the order of `vertices()`).
    fn deformed(reference: ConvexPolyhedron, current: &[[f64; 3]]) -> ConvexPolyhedron {
        let refs = reference.vertices();
        reference.map(|x| {
            let k = refs.iter().position(|r| (r - x).norm() < 1e-12).expect("a vertex");
            Vec3::from(current[k])
        })
    }

    /// Overlapping dominos (as in a run: margin 10.1 mm, support tolerance 0.1 mm): the contact
    /// has points, the deepest within `within` [m] of the separation.
    fn overlap_has_points(a: &ConvexPolyhedron, b: &ConvexPolyhedron, within: f64) {
        let c = detect(a, b, &DetectParams { margin: 0.0101, support_tolerance: 1e-4, thin_distance: 1e-3 })
            .expect("within the margin");
        assert!(c.separation < 0.0, "they overlap: {}", c.separation);
        assert!(!c.points.is_empty(), "no contact points on plane {:?}", c.normal);
        let deepest = c.points.iter().map(|p| p.gap).fold(f64::INFINITY, f64::min);
        assert!((deepest - c.separation).abs() < within, "deepest point {deepest} vs separation {}", c.separation);
    }

    #[test]
    fn a_warped_face_still_meets_the_edge_pressing_on_it() {
        // Two tipped dominos (0.1 × 0.4 × 1 m) from a two-end run, as deformed boxes: B's top
        // edge presses on A's face, which is out of plane by more than the support tolerance,
        // so A's vertices at its lowest level along the normal lie away from B's edge. The
        // contact must still have points, or the pieces pass through each other.
        let a = deformed(
            ConvexPolyhedron::from_box(Vec3::new(3.0, 0.0, 0.0), Vec3::new(3.1, 0.4, 1.0)),
            &[
                [3.0000483225466272, 0.00015626848217371663, 3.726996282332984e-5],
                [2.236751442043936, -0.000871569394798676, 0.6460979852232005],
                [2.236272285098666, 0.39912736482870986, 0.6461836319360568],
                [2.9995205877118742, 0.4001546106574536, 5.4281103885819825e-5],
                [3.064652219307988, 0.00023696373680563286, 0.0763683288787361],
                [3.064127516848026, 0.4002369305975589, 0.07638270452648994],
                [2.3008869423219664, 0.3991903035393516, 0.7225036051162467],
                [2.3013612379169945, -0.0008105724270106356, 0.7224242737257767],
            ],
        );
        let b = deformed(
            ConvexPolyhedron::from_box(Vec3::new(2.5, 0.0, 0.0), Vec3::new(2.6, 0.4, 1.0)),
            &[
                [2.4936978227739868, 1.528007071367554e-5, -1.0192670490805508e-7],
                [1.993878633989234, 6.583029577021847e-5, 0.8661282660218974],
                [1.993908708625231, 0.40006871837137137, 0.8661210158940632],
                [2.493739698441877, 0.40001724132653077, -1.134497036642743e-7],
                [2.580315124813464, 6.334598892150908e-6, 0.0499756898791135],
                [2.5803561998959155, 0.40000811502430766, 0.04997642317960749],
                [2.080523424279209, 0.40006011181494266, 0.916100531653525],
                [2.0804931428777698, 6.332253763041004e-5, 0.9161081355131595],
            ],
        );
        overlap_has_points(&a, &b, 2e-4);
    }

    #[test]
    fn a_cube_on_a_twisted_face_touches_over_its_whole_base() {
        // A slab whose top face is twisted by ±0.5 mm at its corners (far beyond the support
        // tolerance): its highest vertices are two opposite corners, away from the cube. The
        // face giving the plane is the support as a whole, so the cube's base meets it.
        let w = 5e-4;
        let slab = ConvexPolyhedron::from_box(Vec3::new(-1.0, -1.0, -0.5), Vec3::new(1.0, 1.0, 0.0)).map(|x| {
            if x.z == 0.0 {
                Vec3::new(x.x, x.y, w * x.x.signum() * x.y.signum())
            } else {
                *x
            }
        });
        let c = detect(
            &cube(Vec3::new(0.7, -0.7, 0.1 - 2e-4), 0.2),
            &slab,
            &DetectParams { margin: 0.01, support_tolerance: 1e-4, thin_distance: 1e-3 },
        )
        .expect("touching");
        assert!((c.normal - Vec3::z()).norm() < 1e-3, "{:?}", c.normal);
        assert_eq!(count(&c, Mode::VertexOfA), 4, "{:?}", c.points);
        assert!(c.points.iter().all(|p| p.gap < 0.0 && p.gap > -2e-4 - w), "{:?}", c.points);
    }

    #[test]
    fn a_corner_driven_into_a_face_gives_a_point() {
        // Two dominos from a two-end run meeting top to top: a top corner of A is driven into
        // the upper part of B's face (deformed boxes as in the run).
        let a = deformed(
            ConvexPolyhedron::from_box(Vec3::new(2.5, 0.0, 0.0), Vec3::new(2.6, 0.4, 1.0)),
            &[
                [2.4940698596833406, 2.9445177722291965e-5, -7.486392809888382e-7],
                [1.9315367807334616, -0.0007353289563163735, 0.8270908580481733],
                [1.9295922696927623, 0.39940484726885733, 0.825908352206083],
                [2.4937172082426042, 0.40003479720961943, -1.122401968596495e-6],
                [2.576544017583669, 0.00011238034317430725, 0.05651986598520236],
                [2.5762041045998356, 0.4001107378022789, 0.05650305547618939],
                [2.01232011625685, 0.3998051784166048, 0.8820878395833291],
                [2.014307874052098, -0.00010732297372067199, 0.8829253040677545],
            ],
        );
        let b = deformed(
            ConvexPolyhedron::from_box(Vec3::new(2.0, 0.0, 0.0), Vec3::new(2.1, 0.4, 1.0)),
            &[
                [1.991193350013307, -7.823790365147525e-5, -2.456494274036676e-7],
                [1.7998594720417431, 0.00015292116064123998, 0.9814931159827066],
                [1.801166811009167, 0.4000855601971445, 0.981736761386054],
                [1.991104834763085, 0.39994949624551995, -2.952799262323028e-7],
                [2.0893638650240827, -4.291417027039606e-5, 0.019008633799941506],
                [2.089280704934643, 0.3999487843517086, 0.01897388601517551],
                [1.899332936006871, 0.3998165862671024, 1.0008047408843046],
                [1.8980288431393872, -0.00024698527256018375, 1.0005667486004202],
            ],
        );
        // The face is out of plane by a few tenths of a millimetre: the point's gap (from the
        // face's mean plane) is the overlap to within that.
        overlap_has_points(&a, &b, 5e-4);
    }

    #[test]
    fn a_corner_pressed_into_a_warped_face_past_an_edge_plane_gives_a_point() {
        // A tipped domino's top corner (B) pressed into the face of an upright one (A) whose
        // top corner is pushed 0.4 mm out of plane (four times the support tolerance), from a
        // two-end run: the best axis crosses two edges whose supports miss each other. The
        // pair overlaps, so the face planes behind it are tried; a point must come out.
        let a = deformed(
            ConvexPolyhedron::from_box(Vec3::new(1.5, 0.0, 0.0), Vec3::new(1.6, 0.4, 1.0)),
            &[
                [1.4999911938149832, -5.831333092718583e-07, -5.98629548824506e-07],
                [1.499953730924162, 7.047127921992474e-05, 1.0000038403435698],
                [1.5004022878536074, 0.40012077327016266, 0.9999266267056216],
                [1.5000018393826104, 0.4000030103851861, 2.639167290390927e-06],
                [1.5999900753299483, -8.094726703155245e-06, 1.908461156047019e-06],
                [1.6000018162756622, 0.3999998987628896, -4.896098728265363e-07],
                [1.6003871572509505, 0.3999787258337194, 0.9999148905107962],
                [1.5999542476432547, -1.6156652436606388e-05, 0.9999903254163255],
            ],
        );
        let b = deformed(
            ConvexPolyhedron::from_box(Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.1, 0.4, 1.0)),
            &[
                [0.9971844326507497, 0.00249167189087431, 0.04085714114494149],
                [1.405668770063083, -0.0037146730313439664, 0.9535645222149491],
                [1.4090792255635334, 0.3962414006114385, 0.9546745329448862],
                [1.001257202668959, 0.402470939405209, 0.04171400993821307],
                [1.0884491732208101, 0.0016498535620931936, -4.615856863973829e-07],
                [1.0925279091459854, 0.40163407379869737, 0.0008607194976963132],
                [1.5003915190866954, 0.3955736324630418, 0.9139805407157683],
                [1.4969610324158529, -0.004435456850451808, 0.9127587254942888],
            ],
        );
        let c = detect(&a, &b, &DetectParams { margin: 0.0101, support_tolerance: 1e-4, thin_distance: 1e-3 })
            .expect("within the margin");
        assert!(!c.points.is_empty(), "no contact points on plane {:?} ({})", c.normal, c.separation);
        let corner = Vec3::new(1.5003915190866954, 0.3955736324630418, 0.9139805407157683);
        assert!(c.points.iter().any(|p| (p.on_b - corner).norm() < 1e-3), "{:?}", c.points);
    }

    #[test]
    fn a_corner_past_the_edge_of_the_face_gives_the_edges_crossing_it() {
        // Two deformed blocks of the thesis slope (case A, t = 1.55 s): A's lowest corner is
        // 3.6 cm below B's top face plane but 13 cm past its edge; the pieces cross by 3.5 cm
        // where A's edges pass over that edge. Every point must lie on both pieces and the
        // crossing must be there.
        let piece = |v: &[[f64; 3]], f: &[[usize; 4]]| {
            let v: Vec<Vec3> = v.iter().map(|x| Vec3::new(x[0], x[1], x[2])).collect();
            // Deformed faces are planar only nearly: built as they are, not checked.
            let faces = f.iter().map(|f| Face { vertices: f.iter().map(|&i| v[i]).collect(), tag: FaceTag(0) });
            ConvexPolyhedron { faces: faces.collect() }
        };
        let a = piece(
            &[
                [15.457535075887264, 6.080725117115364, -9.163805753588832],
                [15.437496713071212, 7.047814876969904, -9.19169532480454],
                [15.35431091287133, 7.067064074270376, -8.4644540278994],
                [15.374878738300932, 6.074420198653891, -8.43582766608965],
                [12.607871425094682, 7.029868582964288, -7.781006349157121],
                [12.946389547195174, 7.054871776045165, -7.157222620942074],
                [12.968093777088512, 6.007382924929311, -7.12701461199671],
                [12.629154984212033, 6.002681266067915, -7.751383941185907],
            ],
            &[[0, 1, 2, 3], [2, 1, 4, 5], [3, 2, 5, 6], [1, 0, 7, 4], [0, 3, 6, 7], [5, 4, 7, 6]],
        );
        let b = piece(
            &[
                [15.454998130514326, 6.137869284369886, -10.000014599225615],
                [15.441680016499726, 7.0741746613231555, -9.988546385367785],
                [15.333971104422975, 7.061769927135985, -9.10087029088706],
                [15.347733402086291, 6.094241337963161, -9.11272104308922],
                [12.14117765447914, 7.007443284652363, -8.373486534506043],
                [12.494405708073613, 7.004357365847104, -7.711363156454576],
                [12.155490738765469, 6.001253373253354, -8.38581190989441],
                [12.509024135570082, 5.97670405230599, -7.723951518463921],
            ],
            &[[0, 1, 2, 3], [2, 1, 4, 5], [1, 0, 6, 4], [3, 2, 5, 7], [6, 0, 3, 7], [5, 4, 6, 7]],
        );
        let c = detect(&a, &b, &DetectParams { margin: 0.301, support_tolerance: 1e-3, thin_distance: 1e-2 })
            .expect("within the margin");
        assert!(!c.points.is_empty(), "no points on plane {:?} ({})", c.normal, c.separation);
        for p in &c.points {
            assert!(a.contains(&p.on_a, 1e-6) && b.contains(&p.on_b, 1e-6), "a point off the pieces: {p:?}");
        }
        let deepest = c.points.iter().map(|p| p.gap).fold(f64::INFINITY, f64::min);
        assert!(deepest < -0.03, "the 3.5 cm crossing is not represented: {:?}", c.points);
    }

    #[test]
    fn the_far_corners_of_a_tipping_face_are_approaching_points() {
        // A cube tipped 1° about y rests on the edge of its base: two support points. The other
        // two corners of the base are 17.5 mm above the slab: points to be, within a 20 mm
        // margin (a step's reach), none within 10 mm.
        let base = ConvexPolyhedron::from_box(Vec3::new(-5.0, -5.0, -1.0), Vec3::new(5.0, 5.0, 0.0));
        let tip = 1f64.to_radians();
        let h = 0.5 * (tip.cos() + tip.sin());
        let cube = rotated(&cube(Vec3::new(0.0, 0.0, h - 0.001), 1.0), [0.0, 1.0, 0.0]);
        let params = |margin| DetectParams { margin, support_tolerance: 1e-4, thin_distance: 1e-2 };
        let c = detect(&cube, &base, &params(0.02)).unwrap();
        assert_eq!(c.points.len(), 2, "{:?}", c.points);
        assert_eq!(c.approaching.len(), 2, "{:?}", c.approaching);
        let rise = tip.sin() - 0.001;
        for p in &c.approaching {
            assert_eq!(p.mode, Mode::VertexOfA);
            assert!((p.gap - rise).abs() < 1e-9, "{} vs {rise}", p.gap);
            assert!((p.on_a - p.on_b - p.gap * Vec3::z()).norm() < 1e-9);
        }
        assert!(detect(&cube, &base, &params(0.01)).unwrap().approaching.is_empty());
    }

    #[test]
    fn parallel_edges_touch_along_their_overlap() {
        // Two cubes on their edges, edges parallel (both along x), offset along x.
        let lower = rotated(&cube(Vec3::zeros(), 1.0), [45.0, 0.0, 0.0]);
        let h = 2f64.sqrt();
        let upper = rotated(&cube(Vec3::new(0.4, 0.0, h - 0.001), 1.0), [45.0, 0.0, 0.0]);
        let c = detect(&upper, &lower, &DetectParams { margin: 0.01, support_tolerance: 1e-4, thin_distance: 1e-2 })
            .unwrap();
        assert_eq!(c.points.len(), 2, "{:?}", c.points);
        let xs: Vec<f64> = c.points.iter().map(|p| p.on_a.x).collect();
        assert!((xs[0].min(xs[1]) + 0.1).abs() < 1e-9 && (xs[0].max(xs[1]) - 0.5).abs() < 1e-9, "{xs:?}");
    }

    /// How far `x` lies off the surface of `p` [m] (0 on a face, within its outline).
    fn off_surface(p: &ConvexPolyhedron, x: &Vec3) -> f64 {
        let out =
            p.faces.iter().map(|f| f.area_vector().normalize().dot(&(x - f.vertices[0]))).fold(f64::MIN, f64::max);
        out.abs()
    }

    #[test]
    fn long_blocks_crossing_at_an_edge_meet_on_the_least_penetrating_edge_pair() {
        // Two 4 m blocks of the thesis slope (case A with slivers merged, t = 2.701 s; pieces as
        // detected, shifted by (16, 6, −8) m): A's edge crosses B's edge 0.67 mm deep. Another
        // edge pair gives an axis 1.14 mm deep, within the support tolerance (1 mm) of the best;
        // on it A's support is one corner 1.3 m from B's supporting edge. Taken for a point,
        // its material point on B lay 11 cm inside B and the pair read as open while the blocks
        // passed 7 cm into each other.
        // As detected: the faces of deformed pieces are flat and convex only nearly (0.07 mm).
        let piece = |x: &[[f64; 3]], faces: &[Vec<usize>]| ConvexPolyhedron {
            faces: faces
                .iter()
                .map(|f| Face {
                    vertices: f.iter().map(|&i| Vec3::new(x[i][0], x[i][1], x[i][2])).collect(),
                    tag: FaceTag(0),
                })
                .collect(),
        };
        let a = piece(
            &[
                [4.542754, 1.207786, -1.431591],
                [0.563929, 1.469752, -1.085520],
                [0.654957, 1.468208, -0.340606],
                [3.485905, 1.281815, -0.586828],
                [4.628907, 1.206323, -0.726679],
                [3.416076, 0.212850, -0.580511],
                [4.560584, 0.160422, -0.720499],
                [4.475756, 0.182155, -1.425531],
                [0.491963, 0.368162, -1.079010],
                [0.581591, 0.345197, -0.333968],
            ],
            &[
                vec![0, 1, 2, 3, 4],
                vec![4, 3, 5, 6],
                vec![7, 8, 1, 0],
                vec![5, 3, 2, 9],
                vec![6, 5, 9, 8, 7],
                vec![0, 4, 6, 7],
                vec![2, 1, 8, 9],
            ],
        );
        let b = piece(
            &[
                [-1.991517, 1.244792, 0.497305],
                [1.918835, 1.123406, -0.336013],
                [1.898195, 1.125670, -0.433204],
                [-2.041173, 1.250240, 0.263515],
                [-2.033112, 0.037276, 0.478002],
                [1.879994, -0.004049, -0.354035],
                [1.859451, 0.001056, -0.451181],
                [-2.082532, 0.049557, 0.244321],
            ],
            &[
                vec![0, 1, 2, 3],
                vec![1, 0, 4, 5],
                vec![6, 7, 3, 2],
                vec![5, 4, 7, 6],
                vec![2, 1, 5, 6],
                vec![0, 3, 7, 4],
            ],
        );
        let tol = 1e-3;
        let c =
            detect(&a, &b, &DetectParams { margin: 0.01, support_tolerance: tol, thin_distance: 10.0 * tol }).unwrap();
        assert!((c.separation + 0.67e-3).abs() < 0.05e-3, "separation {}", c.separation);
        assert!((c.normal - Vec3::new(-0.0858, 0.0189, -0.9961)).norm() < 2e-4, "normal {}", c.normal);
        assert_eq!(count(&c, Mode::EdgeEdge), 1, "{:?}", c.points);
        for q in &c.points {
            assert!(off_surface(&a, &q.on_a) < tol && off_surface(&b, &q.on_b) < tol, "{q:?} is not on both pieces");
        }
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
