//! Convex decomposition and convex subtraction, by splitting with face planes.
//!
//! A closed polyhedron P (possibly non-convex) becomes convex pieces: a box around P is split
//! by the distinct planes of P's faces, each plane splitting every cell it crosses (the plane
//! arrangement). Every cell is then wholly inside or outside P, and every cell face borders
//! exactly one other cell, so a single probe just beyond a face tells its side: a face of a kept
//! cell is on the boundary of P (it keeps the face's tag) when the probe is outside P, and a
//! *glue* face between pieces of one solid otherwise. Cells are kept when the winding number at
//! their centroid says inside.
//!
//! Subtraction P \ E of a convex E splits each piece of P by the arrangement of E's planes that
//! cross it; cells inside E are dropped; a new face is hole surface when E lies beyond it, glue
//! otherwise. Both produce more pieces than a minimal decomposition; pieces are glued, so the
//! covers and the contact see one block.

use crate::aabb::Aabb;
use crate::math::Vec3;
use crate::plane::Plane;
use crate::polygon;
use crate::polyhedron::{ConvexPolyhedron, Face, FaceTag, CLIP_TOLERANCE};
use crate::winding;

/// How far beyond a face the side test looks, relative to the piece's diagonal.
const SIDE_PROBE: f64 = 1e-7;

/// Tags given to the faces created by a decomposition or subtraction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NewFaceTags {
    /// Tag of a face inside the solid (between two of its pieces).
    pub glue: FaceTag,
}

/// Convex pieces of the closed polyhedron with outward faces `faces` (tagged by the caller);
/// new internal faces get `tags.glue`.
pub fn convex_pieces(faces: &[Face], tags: NewFaceTags) -> Vec<ConvexPolyhedron> {
    let solid: Vec<&[Vec3]> = faces.iter().map(|f| f.vertices.as_slice()).collect();
    let bb = Aabb::from_points(faces.iter().flat_map(|f| f.vertices.iter())).expect("faces have vertices");
    let pad = 0.01 * bb.diagonal();
    let start = ConvexPolyhedron::from_box(bb.min - Vec3::repeat(pad), bb.max + Vec3::repeat(pad));
    let mut cells = vec![start];
    for (plane, tag) in distinct_planes(faces, bb.diagonal()) {
        cells = split_all(cells, &plane, tag);
    }
    cells
        .into_iter()
        .filter(|c| winding::inside(&c.centroid(), solid.iter().copied()))
        .map(|c| retag_sides(c, |p| winding::inside(p, solid.iter().copied()), tags.glue))
        .collect()
}

/// The pieces of `piece` outside the convex `hole` (`None` if untouched). New faces on the
/// hole's planes get `hole_tag(k)` (plane k) where the hole lies beyond them, `tags.glue` where
/// other kept pieces do.
pub fn subtract_convex(
    piece: &ConvexPolyhedron,
    hole: &ConvexPolyhedron,
    hole_tag: impl Fn(usize) -> FaceTag,
    tags: NewFaceTags,
) -> Option<Vec<ConvexPolyhedron>> {
    split_by_convex(piece, hole, hole_tag, tags).map(|(outside, _)| outside)
}

/// `piece` split by the convex `hole` into the pieces outside it and those inside (`None` if
/// untouched): the same cells [`subtract_convex`] keeps, and their complement, so the two
/// together are the piece exactly. New faces on a hole plane get `hole_tag(k)` where the other
/// side lies beyond the hole's surface, `tags.glue` where a piece of the same side does.
pub fn split_by_convex(
    piece: &ConvexPolyhedron,
    hole: &ConvexPolyhedron,
    hole_tag: impl Fn(usize) -> FaceTag,
    tags: NewFaceTags,
) -> Option<(Vec<ConvexPolyhedron>, Vec<ConvexPolyhedron>)> {
    if !piece.aabb().overlaps(&hole.aabb()) {
        return None;
    }
    let planes = hole.face_planes();
    let mut cells = vec![piece.clone()];
    for (k, p) in planes.iter().enumerate() {
        cells = split_all(cells, p, hole_tag(k));
    }
    let touched = cells.len() > 1;
    let eps = CLIP_TOLERANCE * piece.aabb().diagonal().max(hole.aabb().diagonal());
    let in_hole = |x: &Vec3| planes.iter().all(|p| p.signed_distance(x) < -eps);
    let (inside, outside): (Vec<_>, Vec<_>) = cells.into_iter().partition(|c| in_hole(&c.centroid()));
    if !touched && inside.is_empty() {
        return None;
    }
    let out_hole = |x: &Vec3| !in_hole(x);
    let outside = outside.into_iter().map(|c| retag_new_faces(c, &planes, &in_hole, &hole_tag, tags.glue)).collect();
    let inside = inside.into_iter().map(|c| retag_new_faces(c, &planes, &out_hole, &hole_tag, tags.glue)).collect();
    Some((outside, inside))
}

/// Split every cell the plane crosses.
fn split_all(cells: Vec<ConvexPolyhedron>, plane: &Plane, tag: FaceTag) -> Vec<ConvexPolyhedron> {
    let mut next = Vec::with_capacity(cells.len() + 4);
    for c in cells {
        match c.split(plane, tag) {
            (Some(a), Some(b)) => {
                next.push(a);
                next.push(b);
            }
            (a, b) => next.extend(a.or(b)),
        }
    }
    next
}

/// The face planes of a solid, coplanar faces merged (first face's tag), as outward planes.
fn distinct_planes(faces: &[Face], size: f64) -> Vec<(Plane, FaceTag)> {
    let mut out: Vec<(Plane, FaceTag)> = Vec::new();
    for f in faces {
        let Some(p) = Plane::from_point_normal(polygon::centroid(&f.vertices), f.area_vector()) else { continue };
        let same = |q: &Plane| {
            let d = p.normal.dot(&q.normal);
            d.abs() > 1.0 - 1e-12 && (p.offset - d.signum() * q.offset).abs() <= 1e-12 * size
        };
        if !out.iter().any(|(q, _)| same(q)) {
            out.push((p, f.tag));
        }
    }
    out
}

/// Faces of a kept cell lying on a face plane of the solid keep their tag if the solid ends
/// there (the probe beyond the face is outside), else become glue.
fn retag_sides(mut c: ConvexPolyhedron, inside: impl Fn(&Vec3) -> bool, glue: FaceTag) -> ConvexPolyhedron {
    let probe = SIDE_PROBE * c.aabb().diagonal();
    for f in &mut c.faces {
        let n = f.area_vector().normalize();
        let beyond = polygon::centroid(&f.vertices) + probe * n;
        if inside(&beyond) {
            f.tag = glue;
        }
    }
    c
}

/// Faces created on the hole's planes: hole surface where the other side (`beyond_other`) lies
/// beyond, glue elsewhere.
fn retag_new_faces(
    mut c: ConvexPolyhedron,
    planes: &[Plane],
    beyond_other: &impl Fn(&Vec3) -> bool,
    hole_tag: &impl Fn(usize) -> FaceTag,
    glue: FaceTag,
) -> ConvexPolyhedron {
    let probe = SIDE_PROBE * c.aabb().diagonal();
    for f in &mut c.faces {
        if let Some(k) = (0..planes.len()).find(|&k| f.tag == hole_tag(k)) {
            let n = f.area_vector().normalize();
            let beyond = polygon::centroid(&f.vertices) + probe * n;
            f.tag = if beyond_other(&beyond) { hole_tag(k) } else { glue };
            let _ = planes[k];
        }
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    const GLUE: NewFaceTags = NewFaceTags { glue: FaceTag(9999) };

    /// An L-shaped prism: the unit square minus its upper-right quarter, extruded 1 m.
    fn l_shape() -> Vec<Face> {
        let poly = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.5], [0.5, 0.5], [0.5, 1.0], [0.0, 1.0]];
        let n = poly.len();
        let v = |i: usize, z: f64| Vec3::new(poly[i % n][0], poly[i % n][1], z);
        let mut faces = vec![
            Face { vertices: (0..n).rev().map(|i| v(i, 0.0)).collect(), tag: FaceTag(0) },
            Face { vertices: (0..n).map(|i| v(i, 1.0)).collect(), tag: FaceTag(1) },
        ];
        for i in 0..n {
            faces.push(Face {
                vertices: vec![v(i, 0.0), v(i + 1, 0.0), v(i + 1, 1.0), v(i, 1.0)],
                tag: FaceTag(2 + i as u32),
            });
        }
        faces
    }

    #[test]
    fn non_convex_prism_becomes_convex_pieces_with_glue() {
        let pieces = convex_pieces(&l_shape(), GLUE);
        let vol: f64 = pieces.iter().map(|p| p.volume()).sum();
        assert!((vol - 0.75).abs() < 1e-12, "{vol}");
        assert!(pieces.len() >= 2);
        // Boundary area (non-glue faces) equals the L-prism's surface: 2 × 0.75 + perimeter 4.
        let boundary: f64 =
            pieces.iter().flat_map(|p| p.faces.iter()).filter(|f| f.tag != GLUE.glue).map(|f| f.area()).sum();
        assert!((boundary - (1.5 + 4.0)).abs() < 1e-12, "{boundary}");
        // Glue faces pair up: their area vectors cancel.
        let glue: Vec3 =
            pieces.iter().flat_map(|p| p.faces.iter()).filter(|f| f.tag == GLUE.glue).map(|f| f.area_vector()).sum();
        assert!(glue.norm() < 1e-12);
    }

    #[test]
    fn subtracting_a_box_leaves_the_difference() {
        let block = ConvexPolyhedron::from_box(Vec3::zeros(), Vec3::new(4.0, 2.0, 2.0));
        let hole = ConvexPolyhedron::from_box(Vec3::new(1.0, -1.0, 0.5), Vec3::new(2.0, 3.0, 1.5));
        let kept = subtract_convex(&block, &hole, |k| FaceTag(100 + k as u32), GLUE).unwrap();
        let vol: f64 = kept.iter().map(|p| p.volume()).sum();
        // The hole crosses the block: 1 × 2 × 1 m of it lies inside.
        assert!((vol - (16.0 - 2.0)).abs() < 1e-12, "{vol}");
        // The tunnel's wall area: 2 faces of 1 × 2 (x = 1, 2) and 2 of 1 × 2 (z = 0.5, 1.5) → 8 m².
        let wall: f64 =
            kept.iter().flat_map(|p| p.faces.iter()).filter(|f| (100..106).contains(&f.tag.0)).map(|f| f.area()).sum();
        assert!((wall - 8.0).abs() < 1e-12, "{wall}");
        assert!(subtract_convex(
            &block,
            &ConvexPolyhedron::from_box(Vec3::repeat(10.0), Vec3::repeat(11.0)),
            |k| FaceTag(k as u32),
            GLUE
        )
        .is_none());
    }

    #[test]
    fn the_inside_of_a_hole_complements_what_subtraction_keeps() {
        let block = ConvexPolyhedron::from_box(Vec3::zeros(), Vec3::new(4.0, 2.0, 2.0));
        let hole = ConvexPolyhedron::from_box(Vec3::new(1.0, -1.0, 0.5), Vec3::new(2.0, 3.0, 1.5));
        let (outside, inside) = split_by_convex(&block, &hole, |k| FaceTag(100 + k as u32), GLUE).unwrap();
        let vol = |v: &[ConvexPolyhedron]| v.iter().map(|p| p.volume()).sum::<f64>();
        assert!((vol(&inside) - 2.0).abs() < 1e-12 && (vol(&outside) - 14.0).abs() < 1e-12);
        // The plug's surface against the rock is the tunnel wall (8 m²); its two ends lie on the
        // block's own faces (y = 0, 2) and keep their tags.
        let wall: f64 = inside
            .iter()
            .flat_map(|p| p.faces.iter())
            .filter(|f| (100..106).contains(&f.tag.0))
            .map(|f| f.area())
            .sum();
        assert!((wall - 8.0).abs() < 1e-12, "{wall}");
        // A piece wholly inside is all plug.
        let small = ConvexPolyhedron::from_box(Vec3::new(1.2, 0.2, 0.7), Vec3::new(1.8, 0.8, 1.3));
        let (outside, inside) = split_by_convex(&small, &hole, |k| FaceTag(100 + k as u32), GLUE).unwrap();
        assert!(outside.is_empty() && (vol(&inside) - 0.216).abs() < 1e-12);
    }
}
