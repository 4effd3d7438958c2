//! Rock bolts in the model: each bolt's springs (an anchored bolt one, between its head and
//! its anchor; a grouted bolt one across each joint it crosses) and its nodes for the frames,
//! located in the covers.

use nmm3d_geom::Vec3;

use super::locate;
use crate::cover::Covers;
use crate::element::bolt::{BoltSpring, SpringLaw};
use crate::element::{grout, loads};
use crate::error::{Error, Result};
use crate::model::{traverse, Geometry};
use crate::scenario::Scenario;

/// Bolt springs and each bolt's nodes.
type BoltSprings = (Vec<BoltSpring>, Vec<Vec<BoltNode>>);

/// A point of a bolt drawn in the frames: its reference position, the covers of its ME and
/// their weights there, and the spring whose forces it shows.
#[derive(Debug, Clone)]
pub struct BoltNode {
    /// Reference position [m].
    pub x: Vec3,
    /// Covers of its ME.
    pub covers: Vec<usize>,
    /// Their weight-function values at `x`.
    pub weights: Vec<f64>,
    /// The spring whose forces it shows (none: a grouted bolt's ends, which carry nothing).
    pub spring: Option<usize>,
}

/// The scenario's bolts as springs (an anchored bolt one, a grouted bolt one per joint it
/// crosses) and, per bolt, its nodes for the frames.
pub(super) fn bolt_springs(s: &Scenario, geometry: &Geometry, covers: &Covers, label: &str) -> Result<BoltSprings> {
    let tol = 1e-9 * covers.mesh().size;
    let node = |block: usize, x: Vec3, spring: Option<usize>| -> Option<BoltNode> {
        let e = covers.locate(block, &x, tol)?;
        let me = &covers.elements[e];
        Some(BoltNode { x, covers: me.covers.clone(), weights: loads::weights_at(covers, me, &x), spring })
    };
    let (mut springs, mut paths) = (Vec::new(), Vec::new());
    for (i, b) in s.bolt.iter().enumerate() {
        let (head, anchor) = (Vec3::from(b.head), Vec3::from(b.anchor));
        let path = if b.grout.grouted {
            let runs = traverse::runs(geometry, &head, &anchor, traverse::BOLT_SAMPLING * covers.mesh().size, tol);
            grouted(i, b, &runs, (&head, &anchor), &mut springs, &node).map_err(|p| {
                let p = p + geometry.origin;
                let at = format!("({:.6}, {:.6}, {:.6})", p.x, p.y, p.z);
                Error::input(label, format!("bolt.{}", b.name), format!("no element holds its joint at {at}"))
            })?
        } else {
            anchored(i, b, &mut springs, &|key, x| {
                let (blk, _) = locate(geometry, covers, &x).ok_or_else(|| {
                    Error::input(label, format!("bolt.{}.{key}", b.name), "the point is not inside any block")
                })?;
                node(blk, x, None)
                    .ok_or_else(|| Error::input(label, format!("bolt.{}.{key}", b.name), "no element holds the point"))
            })?
        };
        if path.is_empty() {
            return Err(Error::input(
                label,
                format!("bolt.{}.head", b.name),
                "the bolt does not pass through any block",
            ));
        }
        paths.push(path);
    }
    Ok((springs, paths))
}

/// An anchored bolt's spring between its head and its anchor (located by `at`), appended to
/// `springs`; its nodes.
fn anchored(
    i: usize,
    b: &crate::scenario::Bolt,
    springs: &mut Vec<BoltSpring>,
    at: &dyn Fn(&str, Vec3) -> Result<BoltNode>,
) -> Result<Vec<BoltNode>> {
    let (head, anchor) = (Vec3::from(b.head), Vec3::from(b.anchor));
    let (mut h, mut a) = (at("head", head)?, at("anchor", anchor)?);
    (h.spring, a.spring) = (Some(springs.len()), Some(springs.len()));
    let law = SpringLaw::anchored(b);
    springs.push(BoltSpring::new(
        i,
        (&h.covers, h.weights.clone()),
        (&a.covers, a.weights.clone()),
        head - anchor,
        law,
    ));
    Ok(vec![h, a])
}

/// A joint's material points lie this fraction of the bar's length inside their blocks (100 ×
/// the containment tolerance for a bar as long as a cover cell).
const NODE_NUDGE: f64 = 1e-7;

/// A grouted bolt's springs, one across each joint between two blocks it runs through (a void
/// between them: none), appended to `springs`; its nodes (its ends in rock and its crossings).
/// Err: a joint's point that no ME of its block holds.
fn grouted(
    i: usize,
    b: &crate::scenario::Bolt,
    runs: &[traverse::Run],
    ends: (&Vec3, &Vec3),
    springs: &mut Vec<BoltSpring>,
    node: &dyn Fn(usize, Vec3, Option<usize>) -> Option<BoltNode>,
) -> std::result::Result<Vec<BoltNode>, Vec3> {
    let (head, axis) = (ends.0, ends.1 - ends.0);
    let len = axis.norm();
    let x = |t: f64| head + axis * t;
    // The material points a hair inside each block: a joint (or the rock's face) is found only
    // to the blocks' containment tolerance, which an ME's clipped faces need not share.
    let nudge = |r: &traverse::Run| NODE_NUDGE.min(0.5 * (r.to - r.from));
    let mut path = Vec::new();
    let rock: Vec<(usize, &traverse::Run)> = runs.iter().filter_map(|r| r.block.map(|k| (k, r))).collect();
    if let Some(n) = rock.first().and_then(|(k, r)| node(*k, x(r.from + nudge(r)), None)) {
        path.push(n);
    }
    for w in runs.windows(2) {
        let (Some(ka), Some(kb)) = (w[0].block, w[1].block) else { continue };
        let (pa, pb) = (x(w[0].to - nudge(&w[0])), x(w[1].from + nudge(&w[1])));
        let na = node(ka, pa, Some(springs.len())).ok_or(pa)?;
        let nb = node(kb, pb, None).ok_or(pb)?;
        let law = grout::crossing_law(b, (w[0].to - w[0].from) * len, (w[1].to - w[1].from) * len);
        springs.push(BoltSpring::new(i, (&nb.covers, nb.weights), (&na.covers, na.weights.clone()), axis, law));
        path.push(na);
    }
    if let Some(n) = rock.last().and_then(|(k, r)| node(*k, x(r.to - nudge(r)), None)) {
        path.push(n);
    }
    Ok(path)
}
