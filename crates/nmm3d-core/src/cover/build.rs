//! Building manifold elements and physical covers for every block.
//!
//! For each convex piece of a block, every cell of the mathematical mesh that its bounding box
//! touches is visited. A cell whose eight corners lie inside the piece (or on its faces)
//! contributes its sub-cells whole, faces on the piece's boundary taking the piece's tags;
//! otherwise the piece is clipped by each sub-cell's planes. Cells are visited in parallel by
//! layers and gathered in order. The physical covers are numbered in [`super::numbering`].

use rustc_hash::FxHashMap;

use rayon::prelude::*;

use nmm3d_geom::polyhedron::CLIP_TOLERANCE;
use nmm3d_geom::{integrate, polygon, ConvexPolyhedron, FaceTag, Plane, Vec3};

use super::manifold_element::ManifoldElement;
use super::mesh::{cell_corner, MathMesh};
use super::numbering;
use super::pattern::{parity, PatternTable, CELL_TAG};
use super::physical_cover::PhysicalCover;
use super::poly::{self, TERMS};
use crate::model::cutting::faces_touch;

/// A block face within this fraction of a cell of a cell plane is taken as on it: no manifold
/// element thinner than that is cut off (a face meant to lie on a mesh plane, given at survey
/// coordinates or computed, misses it by round-off; a 10⁻¹⁰-thin sliver ME made the
/// initial equilibrium of the incline wander).
const SNAP: f64 = 1e-9;
use crate::model::union_find::UnionFind;
use crate::model::{tags, Block, Geometry};

/// The cover system of a model.
#[derive(Debug, Clone)]
pub struct Covers {
    /// Every mesh in use: `[cover]`'s first ([`Covers::mesh`]), then those of bodies with their
    /// own `cover_size`.
    pub meshes: Vec<MathMesh>,
    /// Index into `meshes` of each block's mesh.
    pub block_mesh: Vec<usize>,
    /// The pattern's sub-cells.
    pub pattern: PatternTable,
    /// Manifold elements, ordered by block, then cell, then sub-cell.
    pub elements: Vec<ManifoldElement>,
    /// Physical covers, numbered by first appearance in `elements`.
    pub covers: Vec<PhysicalCover>,
    /// MEs of each (mesh, cell), for locating points.
    pub by_cell: FxHashMap<(usize, [i32; 3]), Vec<usize>>,
    /// The ME of each block that is one ME (`Block::whole`), which reaches beyond its cell.
    pub whole: FxHashMap<usize, usize>,
}

/// Relative tolerance of the "cell strictly inside the piece" test (× piece diagonal).
const FULL_CELL_TOLERANCE: f64 = 1e-10;
/// A clipped piece within this relative volume of its sub-cell is the whole sub-cell.
const WHOLE_TOLERANCE: f64 = 1e-13;

impl Covers {
    /// Build MEs and physical covers of every block, block `b` on `meshes[block_mesh[b]]`
    /// (`meshes[0]`: the mesh of `[cover]`).
    pub fn build(geometry: &Geometry, meshes: Vec<MathMesh>, block_mesh: Vec<usize>, pattern: PatternTable) -> Self {
        let full_moments = full_subcell_moments(&pattern);
        // Blocks are independent; collecting in block order keeps the numbering deterministic.
        let per_block: Vec<Vec<ManifoldElement>> = geometry
            .blocks
            .par_iter()
            .enumerate()
            .map(|(b, block)| {
                block_elements((b, block_mesh[b]), block, &meshes[block_mesh[b]], &pattern, &full_moments)
            })
            .collect();
        let mut elements: Vec<ManifoldElement> = Vec::with_capacity(per_block.iter().map(Vec::len).sum());
        per_block.into_iter().for_each(|v| elements.extend(v));
        let (elements, covers) = numbering::number_covers(elements, &meshes, &pattern);
        let mut by_cell: FxHashMap<(usize, [i32; 3]), Vec<usize>> = FxHashMap::default();
        for (i, e) in elements.iter().enumerate() {
            by_cell.entry((e.mesh, e.cell)).or_default().push(i);
        }
        let whole = elements
            .iter()
            .enumerate()
            .filter(|(_, e)| geometry.blocks[e.block].whole)
            .map(|(i, e)| (e.block, i))
            .collect();
        Self { meshes, block_mesh, pattern, elements, covers, by_cell, whole }
    }

    /// Build MEs and physical covers of every block on one mesh.
    pub fn on_mesh(geometry: &Geometry, mesh: MathMesh, pattern: PatternTable) -> Self {
        Self::build(geometry, vec![mesh], vec![0; geometry.blocks.len()], pattern)
    }

    /// Weight functions of an ME's nodes.
    pub fn weights(&self, e: &ManifoldElement) -> &[poly::Poly] {
        &self.pattern.of_cell(e.cell)[e.subcell].weights
    }

    /// The mathematical mesh of `[cover]`: its size is the model's length scale (tolerances).
    pub fn mesh(&self) -> &MathMesh {
        &self.meshes[0]
    }

    /// The mesh an ME is cut from.
    pub fn mesh_of(&self, e: &ManifoldElement) -> &MathMesh {
        &self.meshes[e.mesh]
    }

    /// Cell-local coordinates of a global reference point in the ME's cell.
    pub fn cell_local(&self, e: &ManifoldElement, x: &Vec3) -> Vec3 {
        self.mesh_of(e).to_local(x) - cell_corner(e.cell)
    }

    /// Global position of a cell-local point of an ME.
    pub fn global(&self, e: &ManifoldElement, xi: &Vec3) -> Vec3 {
        self.mesh_of(e).to_global(&(cell_corner(e.cell) + xi))
    }

    /// The ME containing a reference point of block `block` (`None` if outside): the point's
    /// cell and, for points on a cell face or edge, its neighbours are searched.
    pub fn locate(&self, block: usize, x: &Vec3, tol: f64) -> Option<usize> {
        let m = self.block_mesh[block];
        let mesh = &self.meshes[m];
        let local = mesh.to_local(x);
        let t = tol / mesh.size;
        let c = mesh.cell_of(&local);
        let mut candidates: Vec<usize> = Vec::new();
        for dk in -1..=1 {
            for dj in -1..=1 {
                for di in -1..=1 {
                    candidates.extend(self.by_cell.get(&(m, [c[0] + di, c[1] + dj, c[2] + dk])).into_iter().flatten());
                }
            }
        }
        candidates.extend(self.whole.get(&block));
        candidates.sort_unstable();
        candidates.into_iter().find(|&i| {
            let e = &self.elements[i];
            e.block == block && e.contains(&(local - cell_corner(e.cell)), t)
        })
    }
}

/// The moment exponents a pattern needs: total degree ≤ 2 for linear weights, all 27 for hex8.
fn needed(pattern: &PatternTable) -> Vec<usize> {
    let mask = poly::degree_two_mask();
    (0..TERMS).filter(|&k| !pattern.is_linear() || mask[k]).collect()
}

/// Moments over `p` for the needed exponents, NaN elsewhere.
pub fn moments(p: &ConvexPolyhedron, pattern: &PatternTable) -> [f64; TERMS] {
    if !pattern.is_linear() {
        // All 27 at once (the series form of the closed formula); same index a + 3b + 9c.
        let all = integrate::polyhedron_box_moments(p, 2);
        return std::array::from_fn(|k| all[k]);
    }
    let idx = needed(pattern);
    let exps: Vec<_> = idx.iter().map(|&k| poly::exponent(k)).collect();
    let vals = integrate::polyhedron_moments(p, &exps);
    let mut m = [f64::NAN; TERMS];
    for (k, v) in idx.into_iter().zip(vals) {
        m[k] = v;
    }
    m
}

fn full_subcell_moments(pattern: &PatternTable) -> [Vec<[f64; TERMS]>; 2] {
    let side = |k: usize| pattern.subcells[k].iter().map(|s| moments(&s.shape, pattern)).collect();
    [side(0), side(1)]
}

/// A part of a block piece in one sub-cell: (cell, sub-cell, the part, its moments, whether
/// it is the whole sub-cell).
type Part = ([i32; 3], usize, ConvexPolyhedron, [f64; TERMS], bool);

/// The parts of a piece (`local`: in mesh coordinates, with its face planes) in the sub-cells
/// of `cell`, appended to `out`.
fn cell_parts(
    cell: [i32; 3],
    (local, planes, eps, on): (&ConvexPolyhedron, &[(Plane, FaceTag)], f64, f64),
    pattern: &PatternTable,
    full_moments: &[Vec<[f64; TERMS]>; 2],
    out: &mut Vec<Part>,
) {
    let c = cell_corner(cell);
    // Farthest corner's signed distance: < −eps strictly inside; ≤ `on` inside with some cell
    // faces on the piece's boundary (convexity: corners in ⇒ cell in).
    let reach = (0..8)
        .map(|q| {
            let x = c + Vec3::new((q & 1) as f64, ((q >> 1) & 1) as f64, ((q >> 2) & 1) as f64);
            planes.iter().map(|(p, _)| p.signed_distance(&x)).fold(f64::NEG_INFINITY, f64::max)
        })
        .fold(f64::NEG_INFINITY, f64::max);
    let full = reach < -eps;
    let inside = reach <= on;
    for (si, sub) in pattern.of_cell(cell).iter().enumerate() {
        let geom = if full {
            Some(sub.shape.clone())
        } else if inside {
            Some(tag_boundary_faces(&sub.shape, planes, c, on))
        } else {
            clip_to_subcell(local, sub, c)
        };
        let Some(g) = geom else { continue };
        let whole = full_moments[parity(cell)][si];
        // A clipped piece with the whole sub-cell's volume is the sub-cell (only its faces on
        // the block boundary are tagged differently): reuse its moments.
        let is_whole = inside || (g.volume() - whole[0]).abs() <= WHOLE_TOLERANCE * whole[0];
        let m = if is_whole { whole } else { moments(&g, pattern) };
        out.push((cell, si, g, m, is_whole));
    }
}

fn block_elements(
    (b, mesh_index): (usize, usize),
    block: &Block,
    mesh: &MathMesh,
    pattern: &PatternTable,
    full_moments: &[Vec<[f64; TERMS]>; 2],
) -> Vec<ManifoldElement> {
    if block.whole {
        return vec![whole_element((b, mesh_index), block, mesh, pattern)];
    }
    let s3 = mesh.size.powi(3);
    // Parts of every piece in every sub-cell: (cell, sub-cell) → [(part, moments, whole)].
    let mut parts: Vec<Part> = Vec::new();
    for piece in &block.pieces {
        let local = piece.map(|x| mesh.to_local(x));
        let planes: Vec<(Plane, FaceTag)> = local
            .faces
            .iter()
            .filter_map(|f| {
                Plane::from_point_normal(polygon::centroid(&f.vertices), f.area_vector()).map(|p| (p, f.tag))
            })
            .collect();
        let bb = local.aabb();
        let eps = FULL_CELL_TOLERANCE * bb.diagonal();
        let on = (CLIP_TOLERANCE * bb.diagonal()).max(SNAP);
        let (lo, hi) = (mesh.cell_of(&bb.min), mesh.cell_of(&bb.max));
        // Layers of cells in parallel (one block may be the whole model), gathered in order.
        let layers: Vec<Vec<Part>> = (lo[2]..=hi[2])
            .into_par_iter()
            .map(|k| {
                let mut layer = Vec::new();
                for j in lo[1]..=hi[1] {
                    for i in lo[0]..=hi[0] {
                        cell_parts([i, j, k], (&local, &planes, eps, on), pattern, full_moments, &mut layer);
                    }
                }
                layer
            })
            .collect();
        parts.extend(layers.into_iter().flatten());
    }
    if block.pieces.len() > 1 {
        parts.sort_by_key(|p| (p.0[2], p.0[1], p.0[0], p.1));
    }
    let mut out = Vec::with_capacity(parts.len());
    let mut start = 0;
    while start < parts.len() {
        let end = start + parts[start..].iter().take_while(|p| p.0 == parts[start].0 && p.1 == parts[start].1).count();
        for group in connected_parts(&parts[start..end]) {
            let (cell, subcell) = (parts[start].0, parts[start].1);
            let mut m = [0.0; TERMS];
            for &g in &group {
                m.iter_mut().zip(parts[g + start].3.iter()).for_each(|(a, b)| *a += b);
            }
            let full = group.len() == 1 && parts[group[0] + start].4;
            // Each part belongs to one group: its geometry moves into the ME (no copy).
            let geom = group
                .iter()
                .map(|&g| std::mem::replace(&mut parts[g + start].2, ConvexPolyhedron { faces: Vec::new() }))
                .collect();
            out.push(ManifoldElement {
                block: b,
                mesh: mesh_index,
                cell,
                subcell,
                covers: Vec::new(),
                volume: m[0] * s3,
                parts: geom,
                full,
                moments: m,
            });
        }
        start = end;
    }
    out
}

/// A fixed block as one ME: all its pieces, on the first sub-cell of the cell holding its
/// first vertex. The weights reach beyond that sub-cell, but they are a partition of unity
/// everywhere, so the block's covers (no equations; moved only together by base motion) carry
/// it rigidly; its faces are the contact surface, unbroken by the mesh.
fn whole_element(
    (b, mesh_index): (usize, usize),
    block: &Block,
    mesh: &MathMesh,
    pattern: &PatternTable,
) -> ManifoldElement {
    let first = block.pieces[0].faces[0].vertices[0];
    let cell = mesh.cell_of(&mesh.to_local(&first));
    let c = cell_corner(cell);
    let parts: Vec<ConvexPolyhedron> = block.pieces.iter().map(|p| p.map(|x| mesh.to_local(x) - c)).collect();
    let mut m = [0.0; TERMS];
    for p in &parts {
        m.iter_mut().zip(moments(p, pattern)).for_each(|(a, b)| *a += b);
    }
    let volume = m[0] * mesh.size.powi(3);
    ManifoldElement {
        block: b,
        mesh: mesh_index,
        cell,
        subcell: 0,
        covers: Vec::new(),
        parts,
        full: false,
        volume,
        moments: m,
    }
}

/// Groups (indices) of the parts in one sub-cell that touch through glue faces.
fn connected_parts(parts: &[Part]) -> Vec<Vec<usize>> {
    if parts.len() == 1 {
        return vec![vec![0]];
    }
    let mut uf = UnionFind::new(parts.len());
    for a in 0..parts.len() {
        for b in a + 1..parts.len() {
            let touch =
                parts[a].2.faces.iter().filter(|f| f.tag == tags::GLUE).any(|fa| {
                    parts[b].2.faces.iter().filter(|f| f.tag == tags::GLUE).any(|fb| faces_touch(fa, fb, 1.0))
                });
            if touch {
                uf.union(a, b);
            }
        }
    }
    let mut groups: Vec<(usize, Vec<usize>)> = Vec::new();
    for i in 0..parts.len() {
        let r = uf.find(i);
        match groups.iter_mut().find(|(root, _)| *root == r) {
            Some((_, g)) => g.push(i),
            None => groups.push((r, vec![i])),
        }
    }
    groups.into_iter().map(|(_, g)| g).collect()
}

/// A sub-cell inside the piece (cell-local coordinates, corner `c`) whose faces lying on a
/// piece face take that face's tag, as clipping would leave them.
fn tag_boundary_faces(shape: &ConvexPolyhedron, planes: &[(Plane, FaceTag)], c: Vec3, on: f64) -> ConvexPolyhedron {
    let mut g = shape.clone();
    for f in &mut g.faces {
        let n = f.area_vector();
        if let Some((_, tag)) = planes
            .iter()
            .find(|(p, _)| p.normal.dot(&n) > 0.0 && f.vertices.iter().all(|v| p.signed_distance(&(v + c)).abs() <= on))
        {
            f.tag = *tag;
        }
    }
    g
}

/// (piece ∩ sub-cell) in cell-local coordinates.
fn clip_to_subcell(local_piece: &ConvexPolyhedron, sub: &super::pattern::SubCell, c: Vec3) -> Option<ConvexPolyhedron> {
    let mut g = local_piece.clone();
    for (k, p) in sub.planes.iter().enumerate() {
        let shifted = nmm3d_geom::Plane { normal: p.normal, offset: p.offset + p.normal.dot(&c) };
        g = g.clip_within(&shifted, FaceTag(CELL_TAG + k as u32), SNAP)?;
    }
    Some(g.map(|x| x - c))
}
