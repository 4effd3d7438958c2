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

use std::borrow::Cow;

use rustc_hash::FxHashMap;

use nmm3d_geom::contact::Mode;
use nmm3d_geom::polygon;
use nmm3d_geom::{Plane, Vec3};

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
    /// Its material points were made: false for a candidate the caller did not want (their
    /// weights left empty), kept so that corners found again merge with it as before.
    pub resolved: bool,
}

/// Which candidates get material points, by their gap [m] and reference position on A [m]
/// (the lagged verification wants only deep points it does not know: most found again are known,
/// and their material coordinates were most of its cost).
pub type Wanted<'a> = &'a (dyn Fn(f64, &Vec3) -> bool + Sync);

/// Boundary facets of every ME of `block` lying on the reference piece `piece` (its surface).
pub fn facets_of_piece(sys: &System, block: usize, piece: &nmm3d_geom::ConvexPolyhedron) -> Vec<Facet> {
    let tol = ON_PIECE * sys.covers.mesh().size;
    let covers = &sys.covers;
    let mut out = Vec::new();
    for (e, me) in covers.elements.iter().enumerate().filter(|(_, me)| me.block == block) {
        for f in me.boundary_faces() {
            let x: Vec<Vec3> = f.vertices.iter().map(|xi| covers.global(me, xi)).collect();
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

/// A facet chosen for the overlay: the facet, its current vertices, its area vector and the
/// part of it that takes part (the whole facet, or its part within the band).
type Chosen<'a> = (&'a Facet, &'a [Vec3], Vec3, Cow<'a, [Vec3]>);

/// Facets of a piece (with their current vertices `x`) facing along `outward` that lie in the
/// band `(low, high)` of levels (n·x) — every vertex of its part inside `window` when one is
/// given (see [`window`]). A facet that faces the plane within `turned` (a cosine; 1: off) but
/// reaches out of the band takes part with its part inside it: on a joint that closes by
/// millimetres a face turned by millimetres over a metre against the other's straddles the
/// band, and taken whole or not at all its area comes and goes with the cover's cells — on the
/// thesis slope on 10 MPa/m joints a pair carrying 7 kN fell from 1.13 to 0.09 m²
/// (`contact.turned_face_angle`, `docs/theory/contact.md`).
fn in_band<'a>(
    facets: &'a [Facet],
    x: &'a [Vec<Vec3>],
    n: &Vec3,
    (low, high): (f64, f64),
    (outward, turned): (f64, f64),
    window: Option<&[Plane]>,
) -> Vec<Chosen<'a>> {
    let within = |p: &Vec3| (low..=high).contains(&n.dot(p));
    let slab = [Plane { normal: *n, offset: high }, Plane { normal: -n, offset: -low }];
    let clip = |q: Vec<Vec3>, planes: &[Plane]| planes.iter().fold(q, |q, pl| polygon::clip_polygon_to(&q, pl, 0.0));
    facets
        .iter()
        .zip(x)
        .filter_map(|(f, x)| {
            let m = polygon::area_vector(x);
            let facing = outward * m.dot(n);
            if facing <= 0.0 {
                return None;
            }
            let part = window.map(|planes| clip(x.to_vec(), planes));
            if part.as_ref().is_some_and(Vec::is_empty) {
                return None;
            }
            if part.as_deref().unwrap_or(x).iter().all(within) {
                return Some((f, x.as_slice(), m, Cow::Borrowed(x.as_slice())));
            }
            if turned >= 1.0 || facing < turned * m.norm() {
                return None;
            }
            let q = clip(part.unwrap_or_else(|| x.to_vec()), &slab);
            (q.len() >= 3).then_some((f, x.as_slice(), m, Cow::Owned(q)))
        })
        .collect()
}

/// The prism over the footprint (seen along `n`) of the facets `selected`, grown by `margin`:
/// a fixed block's face is one facet metres wide, and a tilt of the contact normal by a
/// thousandth would lift its far corners out of the band; only its part over the other side's
/// facets has to lie on the contact plane, as a facet of the mesh there would.
fn window(selected: &[Chosen], n: &Vec3, margin: f64) -> Vec<Plane> {
    let flat = |p: &Vec3| p - n * n.dot(p);
    let (lo, hi) = selected
        .iter()
        .flat_map(|(_, _, _, part)| part.iter().map(flat))
        .fold((Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY)), |(lo, hi), v| (lo.inf(&v), hi.sup(&v)));
    let mut planes = Vec::new();
    for k in 0..3 {
        // flat(x)_k = (e_k − n_k n)·x: a plane normal unless the axis is along n.
        let a = Vec3::ith(k, 1.0) - n * n[k];
        let len = a.norm();
        if len > 1e-6 {
            planes.push(Plane { normal: a / len, offset: (hi[k] + margin) / len });
            planes.push(Plane { normal: -a / len, offset: -(lo[k] - margin) / len });
        }
    }
    planes
}

/// Whether the facets are a whole fixed block's faces (`model::Block::whole`).
fn of_whole_block(sys: &System, facets: &[Facet]) -> bool {
    facets.first().is_some_and(|f| sys.geometry.blocks[sys.covers.elements[f.vertices[0].element].block].whole)
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
    (tol, merge, turned): (f64, f64, f64),
    wanted: Wanted,
) -> Vec<Candidate> {
    // Every facet in the slab between the two extreme levels (widened by `tol`) touches: on a
    // compliant joint a face closes by millimetres, more on its lower side when it carries a
    // moment; only the facets within `tol` of the deepest corner lost the rest of the face (the
    // 3DEC sliding wedge on 10 MPa/m joints kept 1 % of its contact area and slid off).
    let band = (level_a.min(level_b) - tol, level_a.max(level_b) + tol);
    // A fixed block's faces are tested over the other side's facets (fixed pairs never meet).
    let (wa, wb) = (of_whole_block(sys, fa), of_whole_block(sys, fb));
    let mut sa = if wa { Vec::new() } else { in_band(fa, xa, n, band, (-1.0, turned), None) };
    let sb = in_band(fb, xb, n, band, (1.0, turned), wb.then(|| window(&sa, n, tol)).as_deref());
    if wa {
        sa = in_band(fa, xa, n, band, (-1.0, turned), Some(&window(&sb, n, tol)));
    }
    if sa.is_empty() || sb.is_empty() {
        return Vec::new();
    }
    let flat = |p: &Vec3| p - n * n.dot(p);
    // A's facets are clockwise about n (they face −n): reverse them for the 2-D overlay.
    let pa: Vec<Vec<Vec3>> = sa.iter().map(|(_, _, _, part)| part.iter().rev().map(flat).collect()).collect();
    let pb: Vec<Vec<Vec3>> = sb.iter().map(|(_, _, _, part)| part.iter().map(flat).collect()).collect();
    let eps = 1e-6 * tol;
    let overlapping = Sweep::new(&pa, &pb, n, eps);
    let mut points: Vec<Candidate> = Vec::new();
    let mut index: FxHashMap<[i64; 3], Vec<usize>> = FxHashMap::default();
    for (i, (fa_, xa, ma, _)) in sa.iter().enumerate() {
        for j in overlapping.of(i) {
            let (fb_, xb, mb, _) = &sb[j];
            let cell = polygon::intersect_convex(&pa[i], &pb[j], n, eps);
            if cell.len() < 3 {
                continue;
            }
            let share = polygon::area_vector(&cell).norm() / cell.len() as f64;
            for p in &cell {
                // Corners shared by neighbouring overlaps are found again: merge them before
                // the costlier material coordinates.
                let on_a = above(p, n, xa, ma);
                if let Some(k) = find(&index, &points, &on_a, merge) {
                    points[k].area += share;
                    continue;
                }
                let on_b = above(p, n, xb, mb);
                let mode = if xa.iter().any(|v| (flat(v) - p).norm() <= merge) {
                    Mode::VertexOfA
                } else if xb.iter().any(|v| (flat(v) - p).norm() <= merge) {
                    Mode::VertexOfB
                } else {
                    Mode::EdgeEdge
                };
                let (ra, rb, gap) = (reference(&on_a, xa, fa_), reference(&on_b, xb, fb_), n.dot(&(on_a - on_b)));
                let resolved = wanted(gap, &ra);
                let point = |element: usize, x: Vec3| match resolved {
                    true => MaterialPoint::on_element(sys, element, x),
                    false => MaterialPoint { element, weights: Vec::new(), reference: x },
                };
                let (a, b) = (point(fa_.vertices[0].element, ra), point(fb_.vertices[0].element, rb));
                index.entry(key(&on_a, merge)).or_default().push(points.len());
                points.push(Candidate { mode, a, b, on_a, gap, area: share, resolved });
            }
        }
    }
    points
}

/// An axis-aligned box: low and high corners [m].
type Box3 = (Vec3, Vec3);

/// Which facets of B (flat, `pb`) may overlap each facet of A (`pa`): their boxes, swept along
/// the axis the contact plane spans most. Far fewer box tests than every pair on a large face.
struct Sweep {
    /// Boxes of A's and B's facets.
    boxes: (Vec<Box3>, Vec<Box3>),
    /// B's facets by the low end of their box along `axis`.
    order: Vec<usize>,
    axis: usize,
    /// The widest of B's boxes along `axis`, plus `eps`.
    reach: f64,
    eps: f64,
}

impl Sweep {
    fn new(pa: &[Vec<Vec3>], pb: &[Vec<Vec3>], n: &Vec3, eps: f64) -> Self {
        let bounds = |p: &Vec<Vec3>| {
            p.iter().fold((Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY)), |(lo, hi), v| {
                (lo.inf(v), hi.sup(v))
            })
        };
        let (ba, bb): (Vec<_>, Vec<_>) = (pa.iter().map(bounds).collect(), pb.iter().map(bounds).collect());
        let axis = n.abs().imin();
        let mut order: Vec<usize> = (0..bb.len()).collect();
        order.sort_by(|&p, &q| bb[p].0[axis].total_cmp(&bb[q].0[axis]));
        let reach = bb.iter().map(|b| b.1[axis] - b.0[axis]).fold(0.0, f64::max) + eps;
        Self { boxes: (ba, bb), order, axis, reach, eps }
    }

    /// B's facets whose boxes overlap A's facet `i`'s, in index order.
    fn of(&self, i: usize) -> Vec<usize> {
        let ((ba, bb), k) = (&self.boxes, self.axis);
        let (lo_a, hi_a) = ba[i];
        let first = self.order.partition_point(|&j| bb[j].0[k] < lo_a[k] - self.reach);
        let mut out: Vec<usize> = self.order[first..]
            .iter()
            .take_while(|&&j| bb[j].0[k] <= hi_a[k] + self.eps)
            .copied()
            .filter(|&j| {
                let (lo, hi) = (lo_a.sup(&bb[j].0), hi_a.inf(&bb[j].1));
                (0..3).all(|c| lo[c] <= hi[c] + self.eps)
            })
            .collect();
        out.sort_unstable();
        out
    }
}

/// The point of the facet's plane (current vertices `x`, area vector `m`) above the flat point
/// `p` along `n`.
fn above(p: &Vec3, n: &Vec3, x: &[Vec3], m: &Vec3) -> Vec3 {
    p + n * (m.dot(&(x[0] - p)) / m.dot(n))
}

/// The reference position of the facet's point `q` (current vertices `x`): the same affine
/// combination of a fan triangle's reference vertices, of the triangle `q` lies in or nearest.
fn reference(q: &Vec3, x: &[Vec3], f: &Facet) -> Vec3 {
    let mut best = (f64::INFINITY, f.vertices[0].reference);
    for i in 1..x.len() - 1 {
        let (l, d) = barycentric(q, &x[0], &x[i], &x[i + 1]);
        if d < best.0 {
            let r = |k: usize| f.vertices[k].reference;
            best = (d, l[0] * r(0) + l[1] * r(i) + l[2] * r(i + 1));
        }
    }
    best.1
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A facet with current vertices `x` (its material points are not used by `in_band`).
    fn facet(x: &[Vec3]) -> Facet {
        Facet { vertices: x.iter().map(|&p| MaterialPoint { element: 0, weights: vec![], reference: p }).collect() }
    }

    #[test]
    fn a_face_turned_against_the_plane_takes_part_with_its_part_in_the_band() {
        // A 1 m square facing down (A's side of a plane with normal +z), turned so that it
        // rises 3 mm across x; the band holds its lowest 1.5 mm.
        let x = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(1.0, 1.0, 3e-3),
            Vec3::new(1.0, 0.0, 3e-3),
        ];
        let (facets, xs, n, band) = (vec![facet(&x)], vec![x], Vec3::z(), (-1e-4, 1.5e-3));
        assert!(in_band(&facets, &xs, &n, band, (-1.0, 1.0), None).is_empty(), "off: whole facets only");
        let turned = 2f64.to_radians().cos();
        let chosen = in_band(&facets, &xs, &n, band, (-1.0, turned), None);
        assert_eq!(chosen.len(), 1);
        let area = polygon::area_vector(&chosen[0].3).norm();
        assert!((area - 0.5).abs() < 1e-5, "half the face lies in the band: {area}");
        // Turned by 10°, beyond the angle: an edge meeting a face, not taken.
        let steep: Vec<Vec3> = xs[0].iter().map(|p| Vec3::new(p.x, p.y, p.x * 10f64.to_radians().tan())).collect();
        assert!(in_band(&[facet(&steep)], &[steep], &n, band, (-1.0, turned), None).is_empty());
    }
}
