//! The detection driver: the contact surfaces of every block, and per step the warning list,
//! detection on the current geometry, the contact points of each detected pair and their
//! transfer from the previous step.

use std::sync::OnceLock;
use std::time::Instant;

use rayon::prelude::*;
use rustc_hash::{FxHashMap, FxHashSet};

use nmm3d_geom::contact::{detect_prepared, Contact, ContactPoint, DetectParams, Prepared};
use nmm3d_geom::{Aabb, ConvexPolyhedron, Vec3};

use super::facets::{self, Candidate, Wanted};
use super::history::ContactHistory;
use super::joint_force::{self, Redetection};
use super::record::{ContactParams, ContactRecord, ContactState};
use super::set::{ContactSurfaces, ContactTimes};
use super::surface::ContactPiece;
use super::transfer::{bound_missed_overlap, inherit, missed_floor, REACH};
use super::travel::Travel;
use crate::scenario::Joint;
use crate::state::Motion;
use crate::system::System;

impl ContactSurfaces {
    /// Contact surfaces of every block (`None` with fewer than two blocks).
    pub fn new(sys: &System) -> Option<Self> {
        if sys.geometry.blocks.len() < 2 {
            return None;
        }
        let pieces = sys
            .geometry
            .blocks
            .iter()
            .enumerate()
            .flat_map(|(b, block)| block.pieces.iter().filter_map(move |p| ContactPiece::new(sys, b, p)))
            .collect();
        Some(Self { pieces, times: ContactTimes::default() })
    }

    /// Re-detect the points of `h` on the current geometry; transfer state, shear, preload and
    /// bond from the previous points. `initial`: the first detection, where touching points
    /// take the in-situ traction and the joint's bond. `reach` [m]: how far a point may move in
    /// the coming step (infinite: as far as the step control allows); pairs farther apart than
    /// twice it get no points — the lagged verification adds those that arrive all the same.
    /// `rule`: what a joint pair found again keeps of its previous points
    /// ([`super::joint_force`]).
    pub fn detect(
        &mut self,
        sys: &System,
        state: &Motion,
        h: &mut ContactHistory,
        (initial, reach, rule): (bool, f64, Redetection),
    ) {
        let clock = Instant::now();
        let current: Vec<_> = self.pieces.par_iter().map(|p| p.current(sys, state)).collect();
        let p = h.params;
        let pieces = &self.pieces;
        let keep = |i: usize, j: usize| {
            pieces[i].block != pieces[j].block && !both_fixed(sys, pieces[i].block, pieces[j].block)
        };
        let pairs = h.warning.update(&current, p.margin, p.skin, keep).to_vec();
        self.times.warning += clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        // Only pairs whose boxes lie within this step's margin can have points (the warning
        // list's margin is the widest step's). Of those, pairs whose blocks have not moved
        // against each other by the tolerance since their last detection keep their points
        // (`travel`); the others are detected again.
        let narrow = ContactParams { margin: p.margin.min(p.tolerance + (2.0 * reach).max(p.tolerance)), ..p };
        let boxes: Vec<Aabb> = current.par_iter().map(ConvexPolyhedron::aabb).collect();
        // Blocks a static analysis no longer holds are released: no points on them.
        let released = sys.released(&state.travel());
        let near: Vec<Pair> = (pairs.into_iter())
            .filter(|&(i, j)| !released[pieces[i].block] && !released[pieces[j].block])
            .filter(|&(i, j)| boxes[i].separation(&boxes[j]) <= narrow.margin)
            .collect();
        let candidates: FxHashSet<(usize, usize)> = near.iter().map(|&q| self.blocks_of(q)).collect();
        h.travel.retain(|q| candidates.contains(q));
        let (redo, stay): (Vec<Pair>, Vec<Pair>) =
            near.iter().partition(|&&q| initial || h.travel.since(self.blocks_of(q), None) >= p.tolerance);
        let kept: FxHashSet<(usize, usize)> = stay.iter().map(|&q| self.blocks_of(q)).collect();
        let found = self.find(sys, state, &current, &narrow, (&redo, f64::NEG_INFINITY), &|_, _, _| true);
        let previous = std::mem::take(&mut h.records);
        let mut by_pair: FxHashMap<(usize, usize), Vec<usize>> = FxHashMap::default();
        for (k, r) in previous.iter().enumerate() {
            if kept.contains(&r.blocks) {
                let mut r = r.clone();
                r.refresh(sys, state);
                h.records.push(r);
            } else {
                by_pair.entry(r.blocks).or_default().push(k);
            }
        }
        for &q in &redo {
            h.travel.mark(self.blocks_of(q));
        }
        for (i, j, normal, points) in found {
            let blocks = (self.pieces[i].block, self.pieces[j].block);
            let joint = joint_between(sys, blocks.0, blocks.1);
            for q in points {
                let mut r = ContactRecord::fresh(sys, q, blocks, normal, joint, initial, &p);
                inherit(&mut r, &previous, by_pair.get(&blocks), &p, h.locked);
                if !initial
                    && bound_missed_overlap(&mut r, missed_floor(&previous, by_pair.get(&blocks), REACH * p.tolerance))
                {
                    h.missed_overlaps += 1;
                }
                h.records.push(r);
            }
        }
        if !initial {
            let changed = joint_force::redetected(rule, &previous, &by_pair, &mut h.records);
            h.carried_forces += changed.carried_force as u64;
        }
        self.times.detection += clock.elapsed().as_secs_f64();
    }

    /// The blocks of a pair of pieces as contact records name them (the higher index first).
    fn blocks_of(&self, (i, j): (usize, usize)) -> (usize, usize) {
        let (a, b) = (self.pieces[i].block, self.pieces[j].block);
        (a.max(b), a.min(b))
    }

    /// The contact points of the candidate pairs `pairs` (piece indices) on the pieces' geometry
    /// `current` at `state` with the tolerances of `p`: per detected pair, A's and B's piece
    /// (A of the higher block index), the normal and the points. Pairs separated by more than
    /// −`overlap` (overlapping by less) are left out. `wanted`: which candidates of a pair
    /// (blocks as records name them) get material points ([`Wanted`]).
    fn find(
        &self,
        sys: &System,
        state: &Motion,
        current: &[ConvexPolyhedron],
        p: &ContactParams,
        (pairs, overlap): (&[(usize, usize)], f64),
        wanted: PairWanted,
    ) -> Vec<(usize, usize, Vec3, Vec<Candidate>)> {
        let dp = DetectParams { margin: p.margin, support_tolerance: p.tolerance, thin_distance: 10.0 * p.tolerance };
        let pieces = &self.pieces;
        // Prepared pieces and current facet vertices, once per piece and only for the pieces
        // of the pairs (of a detected pair).
        let prepared: Vec<OnceLock<Prepared>> = pieces.iter().map(|_| OnceLock::new()).collect();
        let prepared_of = |k: usize| prepared[k].get_or_init(|| Prepared::new(&current[k]));
        let facets: Vec<OnceLock<Vec<Vec<Vec3>>>> = pieces.iter().map(|_| OnceLock::new()).collect();
        let facets_of = |k: usize| facets[k].get_or_init(|| pieces[k].facet_positions(sys, state)).as_slice();
        pairs
            .par_iter()
            .map(|&(i, j)| if pieces[i].block > pieces[j].block { (i, j) } else { (j, i) })
            .filter_map(|(i, j)| {
                let c = detect_prepared(prepared_of(i), prepared_of(j), &dp).filter(|c| c.separation <= -overlap)?;
                let on = Surfaces {
                    pieces: (&pieces[i], &pieces[j]),
                    current: (&current[i], &current[j]),
                    facets: (facets_of(i), facets_of(j)),
                };
                let blocks = (pieces[i].block, pieces[j].block);
                let want = |gap: f64, r: &Vec3| wanted(blocks, gap, r);
                Some((i, j, c.normal, candidates(sys, state, &on, &c, p, &want)))
            })
            .collect()
    }

    /// Points that arrive during a step without having been detected at its start (lagged
    /// verification, as DDA verifies its contacts at the end of each step): detection on the
    /// trial's end configuration `end` finds overlaps deeper than the tolerance with no point
    /// of the pair within the transfer distance. Each is added as a point of the step's start
    /// (its gap measured at `start`), so the step can be solved again with it; without it the
    /// corner would pass into the face unresisted and be found deep at the next detection.
    /// Returns the points added (to `h` too). `carry`: an arrival on a joint's own stiffness
    /// deep at the start pushes from the transfer distance ([`joint_force::arrived`]; dynamic
    /// runs).
    pub fn arrivals(
        &mut self,
        sys: &System,
        (start, end): (&Motion, &Motion),
        h: &mut ContactHistory,
        carry: bool,
    ) -> Vec<ContactRecord> {
        let clock = Instant::now();
        let current: Vec<_> = self.pieces.par_iter().map(|p| p.current(sys, end)).collect();
        // Only pairs whose blocks have moved against each other by the tolerance since their
        // detection, this trial included, can have a point arrive.
        let trial: Vec<Vec3> = end.u.iter().zip(&start.u).map(|(e, s)| e - s).collect();
        let moved = Travel::per_block(sys, &trial);
        let p = h.params;
        // Only pairs overlapping can have a point that arrived deeper than the tolerance (half
        // of it: the points' gaps are measured between material points, the separation between
        // the pieces' faces) — their boxes overlap by as much.
        let overlap = 0.5 * p.tolerance;
        let boxes: Vec<Aabb> = current.par_iter().map(ConvexPolyhedron::aabb).collect();
        let released = sys.released(&start.travel());
        let pairs: Vec<(usize, usize)> = (h.warning.pairs.iter().copied())
            .filter(|&(i, j)| !released[self.pieces[i].block] && !released[self.pieces[j].block])
            .filter(|&(i, j)| boxes[i].separation(&boxes[j]) <= -overlap)
            .filter(|&q| h.travel.since(self.blocks_of(q), Some(&moved)) >= p.tolerance)
            .collect();
        let reach = REACH * p.tolerance;
        let mut known_at: FxHashMap<(usize, usize), Vec<Vec3>> = FxHashMap::default();
        for r in &h.records {
            known_at.entry(r.blocks).or_default().push(r.a.reference);
        }
        let known = |blocks, x: &Vec3| known_at.get(&blocks).is_some_and(|k| k.iter().any(|r| (r - x).norm() < reach));
        let wanted = |blocks, gap: f64, x: &Vec3| gap < -p.tolerance && !known(blocks, x);
        let found = self.find(sys, end, &current, &p, (&pairs, overlap), &wanted);
        let mut added = Vec::new();
        for (i, j, normal, points) in found {
            let blocks = (self.pieces[i].block, self.pieces[j].block);
            let same: Vec<usize> = (0..h.records.len()).filter(|&k| h.records[k].blocks == blocks).collect();
            let joint = joint_between(sys, blocks.0, blocks.1);
            for mut q in points {
                if !q.resolved || q.gap >= -p.tolerance || known(blocks, &q.a.reference) {
                    continue;
                }
                q.gap = normal.dot(&(q.a.position(sys, start) - q.b.position(sys, start)));
                let mut r = ContactRecord::fresh(sys, q, blocks, normal, joint, false, &p);
                inherit(&mut r, &h.records, Some(&same), &p, h.locked);
                if bound_missed_overlap(&mut r, missed_floor(&h.records, Some(&same), reach)) {
                    h.missed_overlaps += 1;
                }
                if carry && joint_force::arrived(&mut r, reach) {
                    h.carried_forces += 1;
                }
                added.push(r);
            }
        }
        h.records.extend(added.iter().cloned());
        self.times.detection += clock.elapsed().as_secs_f64();
        added
    }
}

impl ContactHistory {
    /// The same points as after the last step, at the current positions, without detecting
    /// again: each keeps its normal, state, springs and bond; its gap is re-measured between
    /// its material points. For steps after which no point has moved by the contact tolerance
    /// since the last detection, where a new detection would only make points at the edge of a
    /// face come and go with round-off — each arrival inheriting its neighbour's springs.
    /// Points on blocks a static analysis has released (`System::released`) are dropped.
    pub fn refresh(&mut self, sys: &System, state: &Motion) {
        let released = sys.released(&state.travel());
        self.records.retain(|r| !released[r.blocks.0] && !released[r.blocks.1]);
        self.records.iter_mut().for_each(|r| r.refresh(sys, state));
    }
}

impl ContactRecord {
    /// The same point at the current positions: its gap re-measured between its material
    /// points; normal, state, springs and bond kept (see [`ContactHistory::refresh`]).
    fn refresh(&mut self, sys: &System, state: &Motion) {
        let gap = self.normal.dot(&(self.a.position(sys, state) - self.b.position(sys, state))) - self.offset;
        (self.gap0, self.gap, self.reclosed, self.opened) = (gap, gap, 0, false);
        if self.state != ContactState::Slide {
            self.rel = Vec3::zeros();
        }
        self.limit = self.coulomb_limit(gap);
    }
}

/// Two pieces (indices into the contact surfaces).
type Pair = (usize, usize);

/// [`Wanted`] for the candidates of a pair of blocks (higher first).
type PairWanted<'a> = &'a (dyn Fn((usize, usize), f64, &Vec3) -> bool + Sync);

fn both_fixed(sys: &System, a: usize, b: usize) -> bool {
    sys.geometry.blocks[a].fixed && sys.geometry.blocks[b].fixed
}

/// The two sides (A, B) of a detected pair: pieces, their current geometry and the current
/// vertices of their facets.
struct Surfaces<'a> {
    pieces: (&'a ContactPiece, &'a ContactPiece),
    current: (&'a ConvexPolyhedron, &'a ConvexPolyhedron),
    facets: (&'a [Vec<Vec3>], &'a [Vec<Vec3>]),
}

/// Contact point candidates of a detected pair: on the facets for a face-to-face contact, else
/// the piece-level points (area shared equally); and the corners approaching the plane's face.
fn candidates(
    sys: &System,
    state: &Motion,
    on: &Surfaces,
    c: &Contact,
    p: &ContactParams,
    wanted: Wanted,
) -> Vec<Candidate> {
    let (tol, merge) = (p.tolerance, p.merge);
    let ((pa, pb), (ca, cb)) = (on.pieces, on.current);
    let (n, merge_sq) = (c.normal, merge * merge);
    let level = |p: &ConvexPolyhedron, f: fn(f64, f64) -> f64, init: f64| {
        p.faces.iter().flat_map(|x| x.vertices.iter()).map(|v| n.dot(v)).fold(init, f)
    };
    let (level_a, level_b) = (level(ca, f64::min, f64::INFINITY), level(cb, f64::max, f64::NEG_INFINITY));
    let on_facets = facets::overlay(
        sys,
        (&pa.facets, on.facets.0),
        (&pb.facets, on.facets.1),
        &n,
        (level_a, level_b),
        (tol, merge, p.turned_face),
        wanted,
    );
    let mut found = if on_facets.is_empty() {
        let area = if c.points.is_empty() { 0.0 } else { c.area / c.points.len() as f64 };
        piece_points(sys, state, on, &c.points, (c.normal, area, tol), c.separation)
    } else {
        // The overlay sees only facets on the pieces' two extreme levels. A piece-level point
        // deeper than all it found (an edge crossing an edge beside a face contact) is a point
        // contact too: unresisted, two blocks on the thesis slope crossed by 9 cm in 100 steps,
        // to be pushed apart with 4 MJ from nowhere once the plane changed.
        let deepest = on_facets.iter().map(|f| f.gap).fold(f64::INFINITY, f64::min);
        let deeper: Vec<ContactPoint> = c.points.iter().filter(|q| q.gap < deepest - tol).copied().collect();
        let mut found = on_facets;
        for q in piece_points(sys, state, on, &deeper, (c.normal, 0.0, tol), c.separation) {
            if found.iter().all(|f| (f.on_a - q.on_a).norm_squared() >= merge_sq) {
                found.push(q);
            }
        }
        found
    };
    // Corners approaching the face are point contacts (no area), unless a point is there.
    for q in piece_points(sys, state, on, &c.approaching, (c.normal, 0.0, tol), c.separation) {
        if found.iter().all(|f| (f.on_a - q.on_a).norm_squared() >= merge_sq) {
            found.push(q);
        }
    }
    found
}

/// Candidates at the piece-level points `points` of a detected pair, each with `area` (all
/// resolved: whether B's point can be located decides whether one exists).
fn piece_points(
    sys: &System,
    state: &Motion,
    on: &Surfaces,
    points: &[ContactPoint],
    (n, area, tol): (Vec3, f64, f64),
    separation: f64,
) -> Vec<Candidate> {
    let ((pa, pb), (ca, cb)) = (on.pieces, on.current);
    points
        .iter()
        .filter_map(|q| {
            let a = pa.material_point(sys, state, ca, &q.on_a, tol)?;
            let b = pb.material_point(sys, state, cb, &q.on_b, tol)?;
            // The gap the springs act on: between the material points as their covers move them.
            // A piece's faces run straight between its vertices, but a long piece bends between
            // them (the covers interpolate within each ME): a gap measured on the straight faces
            // would not close when the springs push the material points apart.
            let (xa, xb) = (a.position(sys, state), b.position(sys, state));
            // No point overlaps deeper than the pieces do along the normal (their projections'
            // overlap): a material point that cannot follow the detected point (one beyond the
            // other piece's faces) would otherwise turn a touch into a deep overlap — a 0.5 mm
            // touch measured as 13 cm on the thesis slope, pushed apart at 100 m/s.
            let gap = n.dot(&(xa - xb)).max(separation - tol);
            Some(Candidate { mode: q.mode, a, b, on_a: xa, gap, area, resolved: true })
        })
        .collect()
}

/// The joint between two blocks: an interface naming both bodies, else A's body joint, else B's.
/// Until its stage removes it, the rock filling an excavation is intact rock with the rock
/// around it: bonded beyond any load it meets (no slip, no opening), with the contact penalty.
static INTACT: std::sync::LazyLock<Joint> = std::sync::LazyLock::new(|| Joint {
    name: "intact rock (an excavation's plug)".into(),
    friction_angle: 89.0,
    cohesion: 1e15,
    tensile_strength: 1e15,
    normal_stiffness: None,
    shear_stiffness: None,
});

fn joint_between(sys: &System, a: usize, b: usize) -> Option<&Joint> {
    if sys.geometry.blocks[a].excavation != sys.geometry.blocks[b].excavation {
        return Some(&INTACT);
    }
    let s = &sys.scenario;
    let (ba, bb) = (&s.body[sys.geometry.blocks[a].body].name, &s.body[sys.geometry.blocks[b].body].name);
    let name = s
        .interface
        .iter()
        .find(|i| (&i.bodies[0] == ba && &i.bodies[1] == bb) || (&i.bodies[0] == bb && &i.bodies[1] == ba))
        .map(|i| &i.joint)
        .or(s.body[sys.geometry.blocks[a].body].joint.as_ref())
        .or(s.body[sys.geometry.blocks[b].body].joint.as_ref())?;
    s.joint.iter().find(|x| &x.name == name)
}
