//! What a face tag means (one place). Faces carry a `FaceTag(u32)` through clipping:
//!
//! | range | meaning | boundary? |
//! |---|---|---|
//! | `0 .. JOINT_BASE` | face `k` of the body's shape | yes |
//! | `JOINT_BASE + f` | cut by joint feature `f` (joint sets, then joint planes) | yes |
//! | `GLUE` | between two convex pieces of one block | no |
//! | `EXCAVATION_BASE + 1024 e + k` | face `k` of excavation `e` | yes |
//! | `CELL_TAG + k` | face `k` of a cover sub-cell (inside a block) | no |

use nmm3d_geom::FaceTag;

/// Tags of the faces of a sub-cell start here (block faces use smaller tags).
pub const CELL_TAG: u32 = 1 << 30;
/// First joint-feature tag.
pub const JOINT_BASE: u32 = 1 << 20;
/// Glue between pieces of one block.
pub const GLUE: FaceTag = FaceTag(1 << 21);
/// First excavation tag.
pub const EXCAVATION_BASE: u32 = 1 << 22;

/// Face `k` of a body shape.
pub fn body_face(k: usize) -> FaceTag {
    FaceTag(k as u32)
}

/// A face cut by joint feature `f`.
pub fn joint(f: usize) -> FaceTag {
    FaceTag(JOINT_BASE + f as u32)
}

/// Face `k` of excavation `e`.
pub fn excavation(e: usize, k: usize) -> FaceTag {
    FaceTag(EXCAVATION_BASE + 1024 * e as u32 + k as u32)
}

/// Whether a face lies on the surface of its block (contact, loads, constraints see it).
pub fn is_boundary(t: FaceTag) -> bool {
    t.0 < CELL_TAG && t != GLUE
}

/// The joint feature that made a face, if any.
pub fn joint_feature(t: FaceTag) -> Option<usize> {
    (JOINT_BASE..GLUE.0).contains(&t.0).then(|| (t.0 - JOINT_BASE) as usize)
}
