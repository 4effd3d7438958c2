//! The meshes of a model: the mesh of `[cover]`, and one more for each cover size bodies ask
//! for (`[[body]] cover_size`): the same node and the same rotation, another cell edge. A block
//! is covered by its body's mesh; its covers are its own, so no two meshes meet in one block.

use nmm3d_geom::Vec3;

use super::MathMesh;
use crate::model::Geometry;
use crate::scenario::Scenario;

/// The meshes (`[cover]`'s of edge `size` first, through `origin` in the model's frame) and the
/// index of each block's mesh.
pub fn model_meshes(scenario: &Scenario, geometry: &Geometry, size: f64, origin: Vec3) -> (Vec<MathMesh>, Vec<usize>) {
    let c = &scenario.cover;
    let mut meshes = vec![MathMesh::new(size, origin, c.rotation)];
    let of_block = geometry
        .blocks
        .iter()
        .map(|b| {
            let s = scenario.body[b.body].cover_size.unwrap_or(size);
            match meshes.iter().position(|m| m.size == s) {
                Some(k) => k,
                None => {
                    meshes.push(MathMesh::new(s, origin, c.rotation));
                    meshes.len() - 1
                }
            }
        })
        .collect();
    (meshes, of_block)
}
