//! Excavations: the rock inside an excavation's shape is removed at once, or, for an
//! excavation a stage removes (`[[stage]] excavate`), kept as blocks of its own until that
//! stage (the *plug*, `RawBlock::excavation`). Both split the rock by the same planes
//! (`nmm3d_geom::decompose::split_by_convex`), so the rock left around the opening is the same
//! either way and plug + rock is the rock mass exactly.

use nmm3d_geom::decompose::{split_by_convex, NewFaceTags};
use nmm3d_geom::{polygon, ConvexPolyhedron, FaceTag};

use super::cutting::{regroup, RawBlock};
use super::tags;

const GLUE_TAGS: NewFaceTags = NewFaceTags { glue: tags::GLUE };

/// How far beyond a plug face the test for another part of the opening looks (× the piece's
/// diagonal).
const PROBE: f64 = 1e-7;

/// Excavation `e` (convex parts `holes`) applied to block `b`: what stays of it, and, if `keep`,
/// the plug blocks inside the opening.
pub(super) fn excavate(b: RawBlock, holes: &[ConvexPolyhedron], e: usize, keep: bool) -> Vec<RawBlock> {
    let hb = holes.iter().map(|h| h.aabb()).reduce(|a, c| a.union(&c)).expect("a shape has a piece");
    // A plug of an earlier staged excavation is not rock to excavate again now.
    if !b.aabb().overlaps(&hb) || (keep && b.excavation.is_some()) {
        return vec![b];
    }
    let (body, excavation) = (b.body, b.excavation);
    let mut rock = b.pieces;
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
    let mut out = if rock.is_empty() { Vec::new() } else { tagged(regroup(body, rock), excavation) };
    if keep && !plug.is_empty() {
        let plug = plug.into_iter().map(|p| glue_inner_faces(p, holes, e)).collect();
        out.extend(tagged(regroup(body, plug), Some(e)));
    }
    out
}

fn tagged(mut blocks: Vec<RawBlock>, excavation: Option<usize>) -> Vec<RawBlock> {
    blocks.iter_mut().for_each(|b| b.excavation = excavation);
    blocks
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
pub fn on_excavation(t: FaceTag, e: usize) -> bool {
    let first = tags::excavation(e, 0).0;
    (first..first + 1024).contains(&t.0)
}
