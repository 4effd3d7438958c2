//! Where a drained water table wets the blocks: the parts of their boundary faces that other
//! blocks touch (the joints and the interfaces between bodies), not the open faces — Hoek and
//! Bray's seepage face (`[water] free_faces = "drained"`).

use nmm3d_geom::Vec3;
use rayon::prelude::*;

use crate::cover::mesh::cell_corner;
use crate::cover::Covers;
use crate::model::touching::{boundary_faces, touched, COINCIDENT_RATIO};
use crate::model::Geometry;

/// A cell-local polygon.
type Polygon = Vec<Vec3>;

/// For each of `elements`, its wet polygons (cell-local, outward as its faces).
pub(super) fn wet_faces(geometry: &Geometry, covers: &Covers, elements: &[usize]) -> Vec<(usize, Vec<Polygon>)> {
    let all = boundary_faces(&geometry.blocks);
    let tol = COINCIDENT_RATIO * geometry.aabb().diagonal();
    elements
        .par_iter()
        .map(|&e| {
            let me = &covers.elements[e];
            let (mesh, corner) = (covers.mesh_of(me), cell_corner(me.cell));
            let mut wet = Vec::new();
            for f in me.boundary_faces() {
                let global: Vec<Vec3> = f.vertices.iter().map(|v| mesh.to_global(&(corner + v))).collect();
                let area = nmm3d_geom::polygon::area_vector(&global);
                if area.norm() == 0.0 {
                    continue;
                }
                for (_, part) in touched(&global, &area.normalize(), me.block, &all, tol) {
                    wet.push(part.iter().map(|x| mesh.to_local(x) - corner).collect());
                }
            }
            (e, wet)
        })
        .collect()
}
