//! Excavations: the rock inside an excavation's shape is removed at once, or, for an
//! excavation a stage removes (`[[stage]] excavate`), kept as blocks of its own until that
//! stage (the *plug*, `RawBlock::excavation`; `cutting` regroups and tags the pieces). Both
//! split the rock by the same planes (`nmm3d_geom::decompose::split_by_convex`), so the rock
//! left around the opening is the same either way and plug + rock is the rock mass exactly.

use nmm3d_geom::decompose::{split_by_convex, NewFaceTags};
use nmm3d_geom::{polygon, ConvexPolyhedron, FaceTag};

use super::tags;

const GLUE_TAGS: NewFaceTags = NewFaceTags { glue: tags::GLUE };

/// How far beyond a plug face the test for another part of the opening looks (× the piece's
/// diagonal).
const PROBE: f64 = 1e-7;

/// Excavation `e` (convex parts `holes`) applied to a block's pieces: the pieces that stay, and,
/// if `keep`, the plug's pieces inside the opening (empty otherwise).
pub(super) fn split_pieces(
    pieces: Vec<ConvexPolyhedron>,
    holes: &[ConvexPolyhedron],
    e: usize,
    keep: bool,
) -> (Vec<ConvexPolyhedron>, Vec<ConvexPolyhedron>) {
    let mut rock = pieces;
    let mut plug = Vec::new();
    for hole in holes {
        let mut next = Vec::with_capacity(rock.len());
        for p in rock {
            match split_by_convex(&p, hole, |k| tags::excavation(e, k), GLUE_TAGS) {
                Some((outside, inside)) => {
                    next.extend(outside);
                    plug.extend(inside);
                }
                None => next.push(p),
            }
        }
        rock = next;
    }
    let plug = if keep { plug.into_iter().map(|p| glue_inner_faces(p, holes, e)).collect() } else { Vec::new() };
    (rock, plug)
}

/// A plug piece's face on the plane between two convex parts of the opening lies inside the
/// plug: glue, not opening surface.
fn glue_inner_faces(mut p: ConvexPolyhedron, holes: &[ConvexPolyhedron], e: usize) -> ConvexPolyhedron {
    let d = p.aabb().diagonal();
    for f in p.faces.iter_mut().filter(|f| on_excavation(f.tag, e)) {
        let beyond = polygon::centroid(&f.vertices) + PROBE * d * f.area_vector().normalize();
        if holes.iter().any(|h| h.contains(&beyond, -1e-12 * d)) {
            f.tag = tags::GLUE;
        }
    }
    p
}

/// Whether a face tag is on excavation `e`'s surface.
fn on_excavation(t: FaceTag, e: usize) -> bool {
    let first = tags::excavation(e, 0).0;
    (first..first + 1024).contains(&t.0)
}
