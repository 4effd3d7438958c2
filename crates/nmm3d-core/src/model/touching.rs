//! Where blocks touch: the parts of a block's boundary face that faces of other blocks cover
//! (lying on its plane, facing it). Block theory's free faces and a drained water table's wet
//! faces (the joints, not the open faces) both ask it.

use nmm3d_geom::{polygon, Aabb, Face, Vec3};

use super::{tags, Block};

/// Two faces touch when their planes are parallel to within this angle [rad] …
pub const PARALLEL_ANGLE: f64 = 1e-4;
/// … and coincide to within this fraction of the model's diagonal (the planes of bodies given
/// separately by the user, e.g. a layer on its bedrock, agree only to their digits).
pub const COINCIDENT_RATIO: f64 = 1e-6;

/// One boundary face of a block, with what the tests need.
pub struct Surface<'a> {
    /// Its block.
    pub block: usize,
    /// The face.
    pub face: &'a Face,
    /// Unit outward normal.
    pub normal: Vec3,
    /// Area [m²].
    pub area: f64,
    /// Bounding box.
    pub aabb: Aabb,
}

/// The faces on the surface of each block (not the glue between its convex pieces).
pub fn boundary_faces(blocks: &[Block]) -> Vec<Surface<'_>> {
    let mut out = Vec::new();
    for (k, b) in blocks.iter().enumerate() {
        for f in b.pieces.iter().flat_map(|p| &p.faces).filter(|f| tags::is_boundary(f.tag)) {
            let av = f.area_vector();
            let area = av.norm();
            if area > 0.0 {
                let aabb = Aabb::from_points(&f.vertices).expect("a face has vertices");
                out.push(Surface { block: k, face: f, normal: av / area, area, aabb });
            }
        }
    }
    out
}

/// The parts of the polygon `vertices` (of block `block`, unit outward normal `normal`) that
/// faces of other blocks among `all` cover, each with the block covering it; `tol` [m] the
/// coincidence tolerance.
pub fn touched(vertices: &[Vec3], normal: &Vec3, block: usize, all: &[Surface], tol: f64) -> Vec<(usize, Vec<Vec3>)> {
    let offset = normal.dot(&vertices[0]);
    let Some(bb) = Aabb::from_points(vertices) else { return Vec::new() };
    let grown = Aabb { min: bb.min.add_scalar(-tol), max: bb.max.add_scalar(tol) };
    let mut out = Vec::new();
    for o in all.iter().filter(|o| o.block != block && grown.overlaps(&o.aabb)) {
        if normal.dot(&o.normal) > -PARALLEL_ANGLE.cos() || (o.normal.dot(&o.face.vertices[0]) + offset).abs() > tol {
            continue;
        }
        // The other face, seen from this one's side: its vertices reversed, projected on this plane.
        let other: Vec<Vec3> = o.face.vertices.iter().rev().map(|v| v - normal * (normal.dot(v) - offset)).collect();
        let common = polygon::intersect_convex(vertices, &other, normal, tol);
        if common.len() >= 3 && polygon::area_vector(&common).norm() > 0.0 {
            out.push((o.block, common));
        }
    }
    out
}
