//! What a scenario will cost before anything is built: blocks, equations and memory, from its
//! bounding box, cover size, joint spacings and tunnel segments. Beyond `analysis.max_memory`
//! the scenario is refused as input, naming the key that drives the estimate — instead of an
//! allocation abort or hours of cutting (`cover.size = 1e-4`, `spacing = 1e-12`,
//! `segments = 4294967295`).

use nmm3d_geom::orientation::normal_from_dip;
use nmm3d_geom::{Aabb, Vec3};

use super::shape::shape_to_pieces;
use crate::error::Problem;
use crate::scenario::{CoverSpec, Scenario, Shape};

/// Memory per equation of a run [B]: measured 10.8 GB for 526 848 equations (a continuum of
/// 10⁶ MEs, `docs/performance.md`) and 3.1 GB for 192 000 (8 000 jointed blocks in contact).
pub const BYTES_PER_EQUATION: f64 = 20.0e3;
/// Memory per block of the cut rock mass [B] (8 000 blocks cut in 130 MB, Python included).
pub const BYTES_PER_BLOCK: f64 = 16.0e3;
/// Memory per straight piece of a tunnel profile [B] (its convex pieces and their faces).
pub const BYTES_PER_SEGMENT: f64 = 4.0e3;
/// Fraction of the machine's memory a run may plan to use when `analysis.max_memory` is 0.
pub const MEMORY_SHARE: f64 = 0.8;

/// The cost of a scenario, estimated from its input.
#[derive(Debug, Clone, PartialEq)]
pub struct Estimate {
    /// Cell edge of the mesh with the most nodes [m].
    pub cover_size: f64,
    /// The key that sets it (`cover.size` or `body.NAME.cover_size`).
    pub cover_key: String,
    /// Cover nodes over the bounding box, without the copies blocks make [-].
    pub nodes: f64,
    /// Blocks the joints may make (upper bound) [-].
    pub blocks: f64,
    /// Joint planes per `[[joint_set]]` crossing the bounding box [-].
    pub planes: Vec<f64>,
    /// Straight pieces of tunnel profiles [-].
    pub segments: f64,
    /// Memory [B].
    pub bytes: f64,
}

/// The cover size a run uses: `[cover] size`, or a tenth of the smallest extent of the model.
pub fn cover_size(cover: &CoverSpec, extent: Vec3) -> f64 {
    cover.size.unwrap_or(0.1 * extent.x.min(extent.y).min(extent.z))
}

/// The estimate, or `None` when a shape does not make a solid (reported elsewhere).
pub fn estimate(s: &Scenario) -> Option<Estimate> {
    // Each body's box (`None`: a tunnel profile, which only carves).
    let mut own: Vec<Option<Aabb>> = Vec::with_capacity(s.body.len());
    for b in &s.body {
        own.push(match &b.shape {
            Shape::Tunnel(_) => None,
            shape => shape_to_pieces(shape).ok()?.iter().map(|p| p.aabb()).reduce(|a, c| a.union(&c)),
        });
    }
    let bb = own.iter().filter_map(|b| *b).reduce(|a, c| a.union(&c))?;
    let ext = bb.extent();
    let size = cover_size(&s.cover, ext);
    // Each mesh (`[cover]`'s and one per body cover size) covers the box of the bodies it meshes
    // with at most one more cell per axis on each side (a rotated mesh); a fixed body not
    // meshed is one element per block (counted below).
    let mut meshes: Vec<(String, f64, Aabb)> = Vec::new();
    for (b, bx) in s.body.iter().zip(&own).filter(|(b, _)| !b.fixed || b.fixed_mesh) {
        let Some(bx) = bx else { continue };
        let (key, sz) = match b.cover_size {
            Some(c) if c != size => (format!("body.{}.cover_size", b.name), c),
            _ => ("cover.size".to_string(), size),
        };
        match meshes.iter_mut().find(|m| m.1 == sz) {
            Some(m) => m.2 = m.2.union(bx),
            None => meshes.push((key, sz, *bx)),
        }
    }
    let count = |(_, sz, bx): &(String, f64, Aabb)| (0..3).map(|i| bx.extent()[i] / sz + 3.0).product::<f64>();
    let nodes: f64 = meshes.iter().map(count).sum();
    let finest = meshes.iter().max_by(|a, b| count(a).total_cmp(&count(b)));
    let (cover_key, size) = finest.map_or(("cover.size".to_string(), size), |m| (m.0.clone(), m.1));
    let planes: Vec<f64> =
        s.joint_set.iter().map(|j| across(&bb, normal_from_dip(j.dip, j.dip_direction)) / j.spacing).collect();
    // Per body, the sets and planes that cut it (without names every body not fixed, as
    // `cutting::cut`): parallel planes across the body's own box make n + 1 slabs per set; m
    // planes in general position at most 1 + m + C(m, 2) + C(m, 3) cells.
    let cuts = |bodies: &Option<Vec<String>>, b: &crate::scenario::Body| {
        bodies.as_ref().map_or(!b.fixed, |names| names.contains(&b.name))
    };
    let blocks: f64 = (s.body.iter().zip(&own))
        .map(|(b, own)| {
            let slabs: f64 = (s.joint_set.iter().zip(&planes))
                .filter(|(j, _)| cuts(&j.bodies, b))
                .map(|(j, n)| match own {
                    Some(o) => across(o, normal_from_dip(j.dip, j.dip_direction)) / j.spacing + 1.0,
                    None => n + 1.0,
                })
                .product();
            let m = s.joint_plane.iter().filter(|j| cuts(&j.bodies, b)).count() as f64;
            slabs * (1.0 + m + m * (m - 1.0) / 2.0 + m * (m - 1.0) * (m - 2.0) / 6.0)
        })
        .sum();
    let segments: f64 = s
        .body
        .iter()
        .map(|b| &b.shape)
        .chain(s.excavation.iter().map(|e| &e.shape))
        .filter_map(|shape| match shape {
            Shape::Tunnel(t) => Some(f64::from(t.segments.unwrap_or(0))),
            _ => None,
        })
        .sum();
    // Each block carries its own covers: at least the 8 nodes of one cell.
    let equations = 3.0 * (nodes + 8.0 * blocks);
    let bytes = BYTES_PER_EQUATION * equations + BYTES_PER_BLOCK * blocks + BYTES_PER_SEGMENT * segments;
    Some(Estimate { cover_size: size, cover_key, nodes, blocks, planes, segments, bytes })
}

/// The memory a run may plan to use [B]: `analysis.max_memory`, or [`MEMORY_SHARE`] of this
/// machine's memory.
pub fn memory_limit(s: &Scenario) -> f64 {
    if s.analysis.max_memory > 0.0 {
        s.analysis.max_memory
    } else {
        MEMORY_SHARE * physical_memory()
    }
}

/// Installed memory [B] (Linux: `/proc/meminfo`; elsewhere 16 GB is assumed).
fn physical_memory() -> f64 {
    let kib = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|t| t.lines().find(|l| l.starts_with("MemTotal:"))?.split_whitespace().nth(1)?.parse::<f64>().ok());
    kib.map_or(16.0e9, |k| 1024.0 * k)
}

/// An estimate beyond the memory limit, as one problem naming the key that drives it.
pub fn problems(s: &Scenario) -> Vec<Problem> {
    let Some(e) = estimate(s) else { return Vec::new() };
    let limit = memory_limit(s);
    if e.bytes.is_finite() && e.bytes <= limit {
        return Vec::new();
    }
    let gb = |b: f64| match b / 1e9 {
        g if !g.is_finite() => "unbounded memory".to_string(),
        g if g < 1e4 => format!("about {g:.1} GB"),
        g => format!("about {g:.2e} GB"),
    };
    let (cover, blocks, tunnels) = (
        BYTES_PER_EQUATION * 3.0 * e.nodes,
        BYTES_PER_EQUATION * 24.0 * e.blocks + BYTES_PER_BLOCK * e.blocks,
        BYTES_PER_SEGMENT * e.segments,
    );
    let (path, what) = if tunnels >= cover.max(blocks) {
        (tunnel_path(s), format!("{:.3e} tunnel segments", e.segments))
    } else if blocks >= cover {
        let k = (0..e.planes.len()).max_by(|&a, &b| e.planes[a].total_cmp(&e.planes[b]));
        let path = k.map_or("joint_plane".to_string(), |k| format!("joint_set[{k}].spacing"));
        (path, format!("up to {:.3e} blocks", e.blocks))
    } else {
        (e.cover_key.clone(), format!("{:.3e} cover nodes of {:.3e} m", e.nodes, e.cover_size))
    };
    let reason = format!(
        "the model would need {} ({what}), more than the {} allowed (analysis.max_memory; 0 = {:.0} % of this machine's memory)",
        gb(e.bytes),
        gb(limit).trim_start_matches("about "),
        100.0 * MEMORY_SHARE
    );
    vec![Problem { path, reason }]
}

/// Extent of the box along a unit normal [m].
fn across(bb: &Aabb, n: Vec3) -> f64 {
    let e = bb.extent();
    e.x * n.x.abs() + e.y * n.y.abs() + e.z * n.z.abs()
}

/// The key of the tunnel with the most segments.
fn tunnel_path(s: &Scenario) -> String {
    let bodies = s.body.iter().map(|b| (format!("body.{}.shape.tunnel.segments", b.name), &b.shape));
    let holes =
        s.excavation.iter().enumerate().map(|(k, e)| (format!("excavation[{k}].shape.tunnel.segments"), &e.shape));
    bodies
        .chain(holes)
        .filter_map(|(p, shape)| match shape {
            Shape::Tunnel(t) => Some((p, t.segments.unwrap_or(0))),
            _ => None,
        })
        .max_by_key(|(_, n)| *n)
        .map_or_else(|| "excavation".to_string(), |(p, _)| p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::parse_toml;

    /// A 20 m cube cut by three orthogonal joint sets of spacing `spacing`, cover `size`.
    fn cube(spacing: f64, size: f64) -> Scenario {
        let sets: String = [(0.0, 0.0), (90.0, 0.0), (90.0, 90.0)]
            .iter()
            .map(|(d, a)| format!("[[joint_set]]\ndip = {d}\ndip_direction = {a}\nspacing = {spacing}\n"))
            .collect();
        let text = format!(
            "[cover]\nsize = {size}\n[[material]]\nname = \"rock\"\ndensity = 2500.0\nyoung = 1e9\npoisson = 0.25\n\
             [[body]]\nname = \"cube\"\nmaterial = \"rock\"\nshape = {{ box = {{ min = [0.0, 0.0, 0.0], max = [20.0, 20.0, 20.0] }} }}\n{sets}"
        );
        parse_toml(&text, "<test>", &[]).unwrap()
    }

    #[test]
    fn the_estimate_brackets_what_was_measured() {
        // Measured: 8 000 blocks of 1 m on a 1 m cover ran in 3.1 GB (192 000 equations).
        let e = estimate(&cube(1.0, 1.0)).unwrap();
        assert!((8000.0..=10_000.0).contains(&e.blocks), "{e:?}");
        assert!((3.1e9..=2.0 * 3.1e9).contains(&e.bytes), "{e:?}");
        // The flagship cantilever's 1 000 cells: megabytes.
        let text =
            std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/cantilever.toml")).unwrap();
        let e = estimate(&parse_toml(&text, "<test>", &[]).unwrap()).unwrap();
        assert!(e.bytes < 1e9, "{e:?}");
    }

    #[test]
    fn joint_sets_cut_only_the_bodies_they_name() {
        // Ten uncut posts beside the cube add ten blocks, not ten cubes' worth (the thesis
        // slope with its bollards was refused: 64 GB).
        let mut s = cube(1.0, 1.0);
        let alone = estimate(&s).unwrap().blocks;
        let post = s.body[0].clone();
        for k in 0..10 {
            s.body.push(crate::scenario::Body { name: format!("post{k}"), ..post.clone() });
        }
        assert!((estimate(&s).unwrap().blocks - 11.0 * alone).abs() < 1e-6, "without names every set cuts every body");
        for j in &mut s.joint_set {
            j.bodies = Some(vec!["cube".into()]);
        }
        assert!((estimate(&s).unwrap().blocks - (alone + 10.0)).abs() < 1e-6);
    }

    #[test]
    fn a_fixed_body_is_not_meshed_unless_asked() {
        // A fixed 1 km slab under the cube: one element, not 10⁸ nodes of the 1 m cover.
        let mut s = cube(1.0, 1.0);
        let alone = estimate(&s).unwrap().nodes;
        let slab = Shape::Box { min: [-500.0, -500.0, -100.0], max: [500.0, 500.0, 0.0] };
        s.body.push(crate::scenario::Body { name: "slab".into(), fixed: true, shape: slab, ..s.body[0].clone() });
        assert_eq!(estimate(&s).unwrap().nodes, alone);
        assert!(estimate(&s).unwrap().bytes < 2.0 * estimate(&cube(1.0, 1.0)).unwrap().bytes);
        s.body[1].fixed_mesh = true;
        assert!(estimate(&s).unwrap().nodes > 1e8);
    }

    #[test]
    fn what_drives_an_estimate_beyond_the_limit_is_named() {
        let named = |s: &Scenario| problems(s).first().map(|p| p.path.clone());
        assert_eq!(named(&cube(1.0, 1.0)), None);
        assert_eq!(named(&cube(1.0, 1e-4)).as_deref(), Some("cover.size"));
        let mut fine = cube(1.0, 1.0);
        fine.joint_set[1].spacing = 1e-12;
        assert_eq!(named(&fine).as_deref(), Some("joint_set[1].spacing"));
        fine.joint_set[1].spacing = 5e-324;
        assert!(problems(&fine)[0].reason.contains("unbounded"), "{:?}", problems(&fine));
        let mut fine = cube(1.0, 1.0);
        fine.body[0].cover_size = Some(1e-4);
        assert_eq!(named(&fine).as_deref(), Some("body.cube.cover_size"));
        let mut small = cube(1.0, 1.0);
        small.analysis.max_memory = 1e9;
        let p = problems(&small);
        assert!(p[0].reason.contains("1.0 GB allowed"), "{p:?}");
    }
}
