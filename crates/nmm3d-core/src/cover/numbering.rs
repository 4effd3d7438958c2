//! Physical covers: the classes of (ME, node) incidences merged across the ME faces on cell
//! planes that two MEs of a block share (the face lies in the star of each of its nodes),
//! numbered by first appearance in the MEs' order.

use rayon::prelude::*;

use super::manifold_element::ManifoldElement;
use super::mesh::{MathMesh, NodeKey};
use super::pattern::{PatternTable, CELL_TAG};
use super::physical_cover::PhysicalCover;
use crate::model::union_find::UnionFind;

type FaceKey = (usize, [NodeKey; 4]);

/// Give each ME its physical covers (`ManifoldElement::covers`) and list them.
pub(super) fn number_covers(
    mut elements: Vec<ManifoldElement>,
    meshes: &[MathMesh],
    pattern: &PatternTable,
) -> (Vec<ManifoldElement>, Vec<PhysicalCover>) {
    // Incidence (e, slot) ↦ flat index.
    let mut offset = Vec::with_capacity(elements.len() + 1);
    let mut total = 0;
    for e in &elements {
        offset.push(total);
        total += pattern.of_cell(e.cell)[e.subcell].nodes.len();
    }
    let mut uf = UnionFind::new(total);
    // Every ME face on a cell plane with its key, made in parallel; sorted, the MEs that share
    // a face are neighbours (the classes do not depend on the order of the merges).
    let mut faces: Vec<(FaceKey, usize, usize)> = (elements.par_iter().enumerate())
        .flat_map_iter(|(ei, e)| {
            let sub = &pattern.of_cell(e.cell)[e.subcell];
            e.faces().filter(|f| f.tag.0 >= CELL_TAG).map(move |f| {
                let plane = (f.tag.0 - CELL_TAG) as usize;
                (face_key(e, sub, plane), ei, plane)
            })
        })
        .collect();
    faces.par_sort_unstable();
    for w in faces.windows(2) {
        if w[0].0 == w[1].0 {
            merge_across(&mut uf, &offset, &elements, pattern, (w[0].1, w[0].2), (w[1].1, w[1].2));
        }
    }
    // Union-find root (an incidence index) ↦ cover number, numbered by first appearance.
    let mut class_to_cover = vec![usize::MAX; total];
    let mut covers = Vec::new();
    for (ei, e) in elements.iter_mut().enumerate() {
        let sub = &pattern.of_cell(e.cell)[e.subcell];
        e.covers = (0..sub.nodes.len())
            .map(|slot| {
                let root = uf.find(offset[ei] + slot);
                if class_to_cover[root] == usize::MAX {
                    let node = node_key(e.cell, sub.nodes[slot]);
                    covers.push(PhysicalCover { block: e.block, node, position: meshes[e.mesh].node_position(node) });
                    class_to_cover[root] = covers.len() - 1;
                }
                class_to_cover[root]
            })
            .collect();
    }
    (elements, covers)
}

fn node_key(cell: [i32; 3], offset: [i32; 3]) -> NodeKey {
    [2 * cell[0] + offset[0], 2 * cell[1] + offset[1], 2 * cell[2] + offset[2]]
}

fn face_key(e: &ManifoldElement, sub: &super::pattern::SubCell, plane: usize) -> FaceKey {
    let mut keys = [[i32::MAX; 3]; 4];
    for (slot, &n) in sub.plane_nodes[plane].iter().enumerate() {
        keys[slot] = node_key(e.cell, sub.nodes[n]);
    }
    keys.sort();
    (e.block, keys)
}

/// Join the incidences of the shared face's nodes in two MEs.
fn merge_across(
    uf: &mut UnionFind,
    offset: &[usize],
    elements: &[ManifoldElement],
    pattern: &PatternTable,
    (a, pa): (usize, usize),
    (b, pb): (usize, usize),
) {
    let (ea, eb) = (&elements[a], &elements[b]);
    let (sa, sb) = (&pattern.of_cell(ea.cell)[ea.subcell], &pattern.of_cell(eb.cell)[eb.subcell]);
    for &na in &sa.plane_nodes[pa] {
        let key = node_key(ea.cell, sa.nodes[na]);
        if let Some(&nb) = sb.plane_nodes[pb].iter().find(|&&nb| node_key(eb.cell, sb.nodes[nb]) == key) {
            uf.union(offset[a] + na, offset[b] + nb);
        }
    }
}
