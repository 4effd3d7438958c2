//! Rock-mass modelling: bodies become blocks by joint sets, single joints and excavations.
//!
//! * A joint set is the family of parallel planes n·x = n·origin + k·spacing (n from dip / dip
//!   direction); each convex piece is split only by the planes that cross its extent along n.
//! * A joint plane is one plane (point + dip / dip direction, or normal).
//! * Joints act on the named bodies (default: every non-fixed body); new faces remember their
//!   joint feature (`tags::joint`).
//! * An excavation removes its shape: pieces inside are dropped, pieces across are split by
//!   the shape's planes (`nmm3d_geom::decompose::subtract_convex`).
//! * After each stage the pieces of a block are regrouped into connected blocks through glue
//!   faces (coplanar, opposite, overlapping); what stays connected is one (possibly non-convex)
//!   block.
//! * Slivers: a block smaller than `cutting.sliver_ratio` × its largest neighbour (a block
//!   sharing a face with it) is merged into that neighbour, the shared faces becoming glue; a
//!   sliver with no neighbour is dropped. The report counts both.
//! * Blocks are ordered by centroid (x, then y, then z) so reruns agree.

use rayon::prelude::*;

use nmm3d_geom::{orientation, polygon, Aabb, ConvexPolyhedron, Face, Plane, Vec3};

use super::excavate::split_pieces;
use super::shape::shape_to_pieces;
use super::tags;
use super::union_find::UnionFind;
use crate::scenario::Scenario;

/// One joint feature (a set or a single plane).
#[derive(Debug, Clone)]
pub struct JointFeature {
    /// Unit normal (upward for dip-given planes).
    pub normal: Vec3,
    /// Offset of plane 0: n·x = offset (+ k·spacing).
    pub offset: f64,
    /// Spacing of a set [m]; `None` for a single plane.
    pub spacing: Option<f64>,
    /// Bodies cut (indices).
    pub bodies: Vec<usize>,
    /// Joint (strength) index, if named.
    pub joint: Option<usize>,
}

/// What cutting did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CutReport {
    /// Volume removed by excavations [m³].
    pub excavated_volume: f64,
    /// Slivers merged into a neighbour.
    pub slivers_merged: usize,
    /// Slivers dropped (no neighbour).
    pub slivers_dropped: usize,
}

/// A block under construction.
#[derive(Debug, Clone)]
pub struct RawBlock {
    /// Body index.
    pub body: usize,
    /// Convex pieces glued by `tags::GLUE` faces.
    pub pieces: Vec<ConvexPolyhedron>,
    /// The excavation whose opening it fills, kept until a stage removes it (`None`: rock).
    pub excavation: Option<usize>,
}

impl RawBlock {
    /// Rock of body `body` made of `pieces`.
    pub fn new(body: usize, pieces: Vec<ConvexPolyhedron>) -> Self {
        Self { body, pieces, excavation: None }
    }
    fn volume(&self) -> f64 {
        self.pieces.iter().map(|p| p.volume()).sum()
    }
    pub(super) fn aabb(&self) -> Aabb {
        self.pieces.iter().map(|p| p.aabb()).reduce(|a, b| a.union(&b)).expect("a block has a piece")
    }
}

/// The joint features of a scenario: joint sets first, then joint planes.
pub fn joint_features(s: &Scenario) -> Vec<JointFeature> {
    let bodies = |names: &Option<Vec<String>>| -> Vec<usize> {
        match names {
            Some(list) => list.iter().filter_map(|n| s.body.iter().position(|b| &b.name == n)).collect(),
            None => (0..s.body.len()).filter(|&i| !s.body[i].fixed).collect(),
        }
    };
    let joint = |name: &Option<String>| name.as_ref().and_then(|n| s.joint.iter().position(|j| &j.name == n));
    let mut out = Vec::new();
    for js in &s.joint_set {
        let n = orientation::normal_from_dip(js.dip, js.dip_direction);
        out.push(JointFeature {
            normal: n,
            offset: n.dot(&Vec3::from(js.origin)),
            spacing: Some(js.spacing),
            bodies: bodies(&js.bodies),
            joint: joint(&js.joint),
        });
    }
    for jp in &s.joint_plane {
        let n = match jp.normal {
            Some(v) => Vec3::from(v).normalize(),
            None => orientation::normal_from_dip(jp.dip.unwrap_or(0.0), jp.dip_direction.unwrap_or(0.0)),
        };
        out.push(JointFeature {
            normal: n,
            offset: n.dot(&Vec3::from(jp.point)),
            spacing: None,
            bodies: bodies(&jp.bodies),
            joint: joint(&jp.joint),
        });
    }
    out
}

/// Cut the bodies of a validated scenario into blocks; the rock inside the excavations with
/// `keep[e]` stays as plug blocks (after the rock, in the same order among themselves).
pub fn cut(s: &Scenario, initial: Vec<RawBlock>, keep: &[bool]) -> (Vec<RawBlock>, CutReport) {
    let mut blocks = initial;
    let mut report = CutReport::default();
    for (f, feat) in joint_features(s).iter().enumerate() {
        blocks = blocks
            .into_par_iter()
            .flat_map_iter(|b| {
                if feat.bodies.contains(&b.body) {
                    regroup(b.body, cut_by_feature(b.pieces, feat, f))
                } else {
                    vec![b]
                }
            })
            .collect();
    }
    for (e, ex) in s.excavation.iter().enumerate() {
        let holes = shape_to_pieces(&ex.shape).expect("validated");
        let before: f64 = blocks.iter().map(RawBlock::volume).sum();
        let kept = keep.get(e).copied().unwrap_or(false);
        blocks = blocks.into_par_iter().flat_map_iter(|b| excavate(b, &holes, e, kept)).collect();
        report.excavated_volume += before - blocks.iter().map(RawBlock::volume).sum::<f64>();
    }
    merge_slivers(&mut blocks, s.cutting.sliver_ratio, &mut report);
    sort_by_centroid(&mut blocks);
    (blocks, report)
}

/// Split pieces by the planes of one feature.
fn cut_by_feature(pieces: Vec<ConvexPolyhedron>, feat: &JointFeature, f: usize) -> Vec<ConvexPolyhedron> {
    let tag = tags::joint(f);
    let mut out = Vec::with_capacity(pieces.len());
    for piece in pieces {
        let (lo, hi) = extent(&piece, &feat.normal);
        let offsets: Vec<f64> = match feat.spacing {
            None => vec![feat.offset],
            Some(sp) => {
                let (k0, k1) = (((lo - feat.offset) / sp).ceil() as i64, ((hi - feat.offset) / sp).floor() as i64);
                (k0..=k1).map(|k| feat.offset + k as f64 * sp).collect()
            }
        };
        let mut rest = Some(piece);
        for d in offsets {
            let Some(p) = rest.take() else { break };
            let (below, above) = p.split(&Plane { normal: feat.normal, offset: d }, tag);
            out.extend(below);
            rest = above;
        }
        out.extend(rest);
    }
    out
}

fn extent(p: &ConvexPolyhedron, n: &Vec3) -> (f64, f64) {
    p.faces.iter().flat_map(|f| f.vertices.iter()).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        let t = n.dot(v);
        (lo.min(t), hi.max(t))
    })
}

/// Excavation `e` applied to block `b`: what stays of it, and, if `keep`, its plug blocks.
fn excavate(b: RawBlock, holes: &[ConvexPolyhedron], e: usize, keep: bool) -> Vec<RawBlock> {
    let hb = holes.iter().map(|h| h.aabb()).reduce(|a, c| a.union(&c)).expect("a shape has a piece");
    // A plug of an earlier staged excavation is not rock to excavate again now.
    if !b.aabb().overlaps(&hb) || (keep && b.excavation.is_some()) {
        return vec![b];
    }
    let (rock, plug) = split_pieces(b.pieces, holes, e, keep);
    let tagged = |pieces: Vec<ConvexPolyhedron>, excavation| {
        let blocks = if pieces.is_empty() { Vec::new() } else { regroup(b.body, pieces) };
        blocks.into_iter().map(move |r| RawBlock { excavation, ..r })
    };
    tagged(rock, b.excavation).chain(tagged(plug, Some(e))).collect()
}

/// Connected components of pieces through glue faces.
pub fn regroup(body: usize, pieces: Vec<ConvexPolyhedron>) -> Vec<RawBlock> {
    if pieces.len() == 1 {
        return vec![RawBlock::new(body, pieces)];
    }
    let mut uf = UnionFind::new(pieces.len());
    let size = pieces.iter().map(|p| p.aabb().diagonal()).fold(0.0, f64::max);
    // Face boxes are flat: grow them so round-off cannot separate two copies of one face.
    let pad = Vec3::repeat(1e-9 * size);
    let glue: Vec<(usize, &Face, Aabb)> = pieces
        .iter()
        .enumerate()
        .flat_map(|(i, p)| {
            p.faces.iter().filter(|f| f.tag == tags::GLUE).map(move |f| {
                let b = Aabb::from_points(f.vertices.iter()).expect("face");
                (i, f, Aabb { min: b.min - pad, max: b.max + pad })
            })
        })
        .collect();
    for (a, (i, fi, bi)) in glue.iter().enumerate() {
        for (j, fj, bj) in &glue[a + 1..] {
            if i != j && uf.find(*i) != uf.find(*j) && bi.overlaps(bj) && faces_touch(fi, fj, size) {
                uf.union(*i, *j);
            }
        }
    }
    let mut groups: Vec<(usize, Vec<ConvexPolyhedron>)> = Vec::new();
    for (i, p) in pieces.into_iter().enumerate() {
        let root = uf.find(i);
        match groups.iter_mut().find(|(r, _)| *r == root) {
            Some((_, g)) => g.push(p),
            None => groups.push((root, vec![p])),
        }
    }
    groups.into_iter().map(|(_, pieces)| RawBlock::new(body, pieces)).collect()
}

/// Whether two faces are coplanar, opposite, and overlap with positive area.
pub fn faces_touch(a: &Face, b: &Face, size: f64) -> bool {
    overlap_area(a, b, size) > 1e-12 * size * size
}

/// Two faces count as opposite when their normals are anti-parallel within this (the normals of
/// tiny sliver faces are only known to a few digits).
const OPPOSITE_COSINE: f64 = 1.0 - 1e-6;

fn overlap_area(a: &Face, b: &Face, size: f64) -> f64 {
    let (na, nb) = (a.area_vector(), b.area_vector());
    let (la, lb) = (na.norm(), nb.norm());
    if la == 0.0 || lb == 0.0 || na.dot(&nb) > -OPPOSITE_COSINE * la * lb {
        return 0.0;
    }
    // The larger face's normal is the better known.
    let n = if la >= lb { na / la } else { -nb / lb };
    if (n.dot(&(b.vertices[0] - a.vertices[0]))).abs() > 1e-9 * size {
        return 0.0;
    }
    // `b` turns counter-clockwise about its own outward normal, −n.
    polygon::area_vector(&polygon::intersect_convex(&a.vertices, &b.vertices, &(-n), 1e-12 * size)).norm()
}

/// Merge or drop blocks smaller than `ratio` × their largest neighbour. Volumes are computed
/// once; neighbours are found through a uniform grid of block boxes, so the cost grows with
/// the number of slivers, not with the square of the number of blocks.
fn merge_slivers(blocks: &mut Vec<RawBlock>, ratio: f64, report: &mut CutReport) {
    if ratio <= 0.0 || blocks.len() < 2 {
        return;
    }
    let mut vols: Vec<f64> = blocks.par_iter().map(RawBlock::volume).collect();
    let largest = vols.iter().cloned().fold(0.0, f64::max);
    // Rock and each plug on their own: a plug leaves the rock's slivers as they would be without it.
    let mut top: Vec<(Option<usize>, f64)> = Vec::new();
    for (b, &v) in blocks.iter().zip(&vols) {
        match top.iter_mut().find(|(t, _)| *t == b.excavation) {
            Some((_, m)) => *m = m.max(v),
            None => top.push((b.excavation, v)),
        }
    }
    let largest_like = |i: usize| top.iter().find(|(t, _)| *t == blocks[i].excavation).map_or(largest, |(_, m)| *m);
    let mut candidates: Vec<usize> = (0..blocks.len()).filter(|&i| vols[i] < ratio * largest_like(i)).collect();
    if candidates.is_empty() {
        return;
    }
    candidates.sort_by(|&a, &b| vols[a].total_cmp(&vols[b]).then(a.cmp(&b)));
    let boxes: Vec<Aabb> = blocks.par_iter().map(RawBlock::aabb).collect();
    let model = boxes.iter().copied().reduce(|a, b| a.union(&b)).expect("blocks");
    let size = model.diagonal();
    let grid = BoxGrid::new(&boxes, (largest.cbrt()).max(1e-9 * size));
    let pad = Vec3::repeat(1e-9 * size);
    let mut alive = vec![true; blocks.len()];
    let mut owner: Vec<usize> = (0..blocks.len()).collect();
    for s in candidates {
        if !alive[s] {
            continue;
        }
        let sb = Aabb { min: boxes[s].min - pad, max: boxes[s].max + pad };
        let mut best: Option<usize> = None;
        for j in grid.query(&sb) {
            let j = root(&owner, j);
            if j == s
                || !alive[j]
                || (blocks[j].body, blocks[j].excavation) != (blocks[s].body, blocks[s].excavation)
                || best.is_some_and(|b| vols[b] >= vols[j])
            {
                continue;
            }
            if shared_area(&blocks[s], &blocks[j], size) > 0.0 {
                best = Some(j);
            }
        }
        match best {
            Some(j) if vols[s] < ratio * vols[j] => {
                let body = blocks[s].body;
                let sliver = std::mem::replace(&mut blocks[s], RawBlock::new(body, Vec::new()));
                glue_together(&mut blocks[j], sliver, size);
                vols[j] += vols[s];
                alive[s] = false;
                owner[s] = j;
                report.slivers_merged += 1;
            }
            Some(_) => {}
            None => {
                alive[s] = false;
                report.slivers_dropped += 1;
            }
        }
    }
    let mut k = 0;
    blocks.retain(|_| {
        k += 1;
        alive[k - 1]
    });
}

/// The block that absorbed `i` (following merges).
fn root(owner: &[usize], mut i: usize) -> usize {
    while owner[i] != i {
        i = owner[i];
    }
    i
}

/// Uniform grid of boxes for overlap queries.
struct BoxGrid {
    cell: f64,
    map: rustc_hash::FxHashMap<[i64; 3], Vec<usize>>,
}

impl BoxGrid {
    fn new(boxes: &[Aabb], cell: f64) -> Self {
        let mut map: rustc_hash::FxHashMap<[i64; 3], Vec<usize>> = rustc_hash::FxHashMap::default();
        for (i, b) in boxes.iter().enumerate() {
            let (lo, hi) = (Self::key(&b.min, cell), Self::key(&b.max, cell));
            for x in lo[0]..=hi[0] {
                for y in lo[1]..=hi[1] {
                    for z in lo[2]..=hi[2] {
                        map.entry([x, y, z]).or_default().push(i);
                    }
                }
            }
        }
        Self { cell, map }
    }

    fn key(p: &Vec3, cell: f64) -> [i64; 3] {
        [(p.x / cell).floor() as i64, (p.y / cell).floor() as i64, (p.z / cell).floor() as i64]
    }

    /// Indices of boxes sharing a grid cell with `b`, ascending, without repeats.
    fn query(&self, b: &Aabb) -> Vec<usize> {
        let (lo, hi) = (Self::key(&b.min, self.cell), Self::key(&b.max, self.cell));
        let mut out = Vec::new();
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                for z in lo[2]..=hi[2] {
                    out.extend(self.map.get(&[x, y, z]).into_iter().flatten().copied());
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }
}

fn shared_area(a: &RawBlock, b: &RawBlock, size: f64) -> f64 {
    let boundary = |r: &RawBlock| {
        r.pieces.iter().flat_map(|p| p.faces.iter()).filter(|f| tags::is_boundary(f.tag)).cloned().collect::<Vec<_>>()
    };
    let (fa, fb) = (boundary(a), boundary(b));
    fa.iter().flat_map(|x| fb.iter().map(move |y| (x, y))).map(|(x, y)| overlap_area(x, y, size)).sum()
}

/// Add `sliver`'s pieces to `target`; the faces they share become glue (faces split where only
/// part of them is shared).
fn glue_together(target: &mut RawBlock, mut sliver: RawBlock, size: f64) {
    let eps = 1e-12 * size;
    let others: Vec<Face> =
        sliver.pieces.iter().flat_map(|p| p.faces.iter()).filter(|f| tags::is_boundary(f.tag)).cloned().collect();
    let mine: Vec<Face> =
        target.pieces.iter().flat_map(|p| p.faces.iter()).filter(|f| tags::is_boundary(f.tag)).cloned().collect();
    for p in &mut target.pieces {
        p.faces = p.faces.drain(..).flat_map(|f| split_shared(f, &others, eps, size)).collect();
    }
    for p in &mut sliver.pieces {
        p.faces = p.faces.drain(..).flat_map(|f| split_shared(f, &mine, eps, size)).collect();
    }
    target.pieces.extend(sliver.pieces);
}

/// A boundary face split into the parts shared with `others` (now glue) and the rest: each
/// overlapping face of the other block carves its shared part off what remains.
fn split_shared(f: Face, others: &[Face], eps: f64, size: f64) -> Vec<Face> {
    if !tags::is_boundary(f.tag) {
        return vec![f];
    }
    // `others` face the opposite way: they turn counter-clockwise about −n.
    let minus_n = -f.area_vector().normalize();
    let mut rest = vec![f.vertices.clone()];
    let mut out = Vec::new();
    for o in others.iter().filter(|o| overlap_area(&f, o, size) > 0.0) {
        let mut next = Vec::new();
        for poly in rest {
            let shared = polygon::intersect_convex(&poly, &o.vertices, &minus_n, eps);
            if shared.len() < 3 {
                next.push(poly);
                continue;
            }
            out.push(Face { vertices: shared, tag: tags::GLUE });
            next.extend(polygon::difference_convex(&poly, &o.vertices, &minus_n, eps));
        }
        rest = next;
    }
    out.extend(rest.into_iter().map(|v| Face { vertices: v, tag: f.tag }));
    out
}

/// Stable order: rock, then each excavation's plug; by centroid x, then y, then z (quantised so
/// round-off cannot reorder).
fn sort_by_centroid(blocks: &mut [RawBlock]) {
    let size = blocks.iter().map(|b| b.aabb()).reduce(|a, b| a.union(&b)).map_or(1.0, |b| b.diagonal());
    let q = 1e-9 * size;
    let key = |b: &RawBlock| {
        let v = b.volume();
        let c = b.pieces.iter().map(|p| p.volume() * p.centroid()).sum::<Vec3>() / v;
        (b.excavation, [(c.x / q).round() as i64, (c.y / q).round() as i64, (c.z / q).round() as i64])
    };
    blocks.sort_by_cached_key(key);
}
