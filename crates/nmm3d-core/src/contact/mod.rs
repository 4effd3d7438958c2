//! Contact between blocks: warning, detection on the current geometry, transfer of contact
//! state, penalty springs, Coulomb friction with cohesion and tensile strength, in-situ stress
//! as joint traction, and the open–close state rules (thesis Part 3; DDA, Shi 1988; the state
//! rules of ntdda `df22`).
//!
//! Per step the candidate pairs of pieces come from the warning list ([`broad`]); each pair is
//! detected on the current geometry (one plane per pair of pieces, `nmm3d_geom::contact`). A
//! new point inherits state, shear history, in-situ preload and bond from the previous step's
//! point of the same block pair nearest to it (within the transfer distance), else starts locked
//! with zero shear and no bond. Within the step the open–close iteration solves with the
//! springs of the current states and updates the states until none changes. With the force on
//! A split into N = n·f (compression positive) and the tangential part F_t:
//!
//! | state | force on A | leaves when |
//! |---|---|---|
//! | open | none | the gap closes (→ stick) |
//! | stick | P − k_n g n − k_s s | N < −T A (→ open); \|F_t\| > N tan φ + c A (→ slide) |
//! | slide | (n·P) n − k_n g n − N tan φ ŝ | N < −T A (→ open); the slip reverses (→ stick) |
//!
//! P is the in-situ preload σ₀·(−n) A of a point touching at the start, g the gap, s the
//! shear-spring extension, ŝ the slip direction, A the point's share of the contact area,
//! c and T the joint's cohesion and tensile strength. A bond (c, T) exists only for points
//! touching at the start and is lost for good when the point slides or opens; the preload is
//! lost when it opens.

pub mod broad;
pub mod facets;
pub mod snapshot;
pub mod surface;

use std::sync::OnceLock;
use std::time::Instant;

use rayon::prelude::*;
use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

use nmm3d_geom::contact::{detect_prepared, Contact, DetectParams, Mode, Prepared};
use nmm3d_geom::ConvexPolyhedron;
use nmm3d_geom::{Mat3, Vec3};

use crate::assembly::{Coupling, SparsityPattern};
use crate::error::Problem;
use crate::scenario::Joint;
use crate::state::State;
use crate::system::System;
use broad::Warning;
use facets::Candidate;
use surface::{ContactPiece, MaterialPoint};

/// State of one contact point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum ContactState {
    /// Separated: no force.
    Open,
    /// Locked: normal and shear springs.
    Stick,
    /// Sliding: normal spring and Coulomb friction.
    Slide,
}

impl ContactState {
    /// Code written to the contact frames: 0 open, 1 stick, 2 slide.
    pub fn code(self) -> i64 {
        match self {
            ContactState::Open => 0,
            ContactState::Stick => 1,
            ContactState::Slide => 2,
        }
    }
}

/// One contact point between blocks A and B.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ContactRecord {
    /// Blocks (A, B).
    pub blocks: (usize, usize),
    /// Entrance mode (which features meet).
    pub mode: Mode,
    /// Material point on A.
    pub a: MaterialPoint,
    /// Material point on B.
    pub b: MaterialPoint,
    /// Unit normal from B to A.
    pub normal: Vec3,
    /// Gap at the start of the step [m] (negative: penetration), measured from `offset`.
    pub gap0: f64,
    /// Geometric gap taken as zero [m]: the gap or overlap of a point touching at the start, so
    /// that input overlapping or apart within the tolerance (coordinates rounded to a few digits)
    /// gives no impulsive force and no fall; carried to the point's successors.
    pub offset: f64,
    /// State.
    pub state: ContactState,
    /// Shear-spring extension at the start of the step (tangential) [m].
    pub shear0: Vec3,
    /// Unit slip direction of A relative to B while sliding.
    pub slip: Vec3,
    /// Joint strength at this point.
    pub strength: Strength,
    /// The point's share of the contact area [m²].
    pub area: f64,
    /// Normal penalty of this point [N/m].
    pub kn: f64,
    /// Shear penalty of this point [N/m].
    pub ks: f64,
    /// The penalties are the joint's own stiffness (Pa/m × area): physical, never raised, and
    /// the overlap they allow is the joint's closure, not a penetration error.
    pub joint_stiffness: bool,
    /// In-situ traction on A times the area [N] (zero once the point has opened).
    pub preload: Vec3,
    /// Gap after the last solve [m].
    pub gap: f64,
    /// Relative displacement increment of A with respect to B after the last solve [m].
    pub rel: Vec3,
    /// Force on A after the last solve [N].
    pub force: Vec3,
    /// Times the point closed in this step's open–close iterations.
    pub reclosed: u32,
    /// The point opened in this step's open–close iterations.
    pub opened: bool,
    /// Friction limit tan φ N + c applied while sliding [N].
    pub limit: f64,
}

/// Strength of a contact point: tan φ, and the bond (cohesion and tensile forces) it still has.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Strength {
    /// tan φ.
    pub tan_phi: f64,
    /// Cohesion × area [N] (0 once broken).
    pub cohesion: f64,
    /// Tensile strength × area [N] (0 once broken).
    pub tension: f64,
}

impl Strength {
    fn broken(self) -> Self {
        Self { cohesion: 0.0, tension: 0.0, ..self }
    }
}

/// Penalties and tolerances of the contact algorithm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactParams {
    /// Normal penalty of a point carrying one cover cell's face of area (size²), and of a point
    /// contact [N/m].
    pub kn: f64,
    /// Shear penalty, likewise [N/m].
    pub ks: f64,
    /// Cover size [m]: the area unit of the penalties.
    pub size: f64,
    /// Detection margin [m].
    pub margin: f64,
    /// Warning skin [m]: the candidate list is rebuilt when a vertex has moved half of it.
    pub skin: f64,
    /// Support tolerance and transfer distance [m].
    pub tolerance: f64,
}

/// All contact surfaces and the current contact points.
pub struct ContactSet {
    pieces: Vec<ContactPiece>,
    /// Current contact points.
    pub records: Vec<ContactRecord>,
    /// Penalties and tolerances.
    pub params: ContactParams,
    /// The warning (candidate pair) list.
    pub warning: Warning,
    /// Seconds spent so far.
    pub times: ContactTimes,
    /// Closed points stay closed and stuck whatever the force (initial equilibrium).
    pub locked: bool,
}

/// Seconds spent in the contact phases.
#[derive(Debug, Clone, Copy, Default)]
pub struct ContactTimes {
    /// Warning (candidate pairs, including the current geometry of the pieces).
    pub warning: f64,
    /// Detection and transfer.
    pub detection: f64,
}

impl ContactSet {
    /// Contact surfaces of every block (`None` with fewer than two blocks).
    pub fn new(sys: &System, params: ContactParams) -> Option<Self> {
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
        Some(Self {
            pieces,
            records: Vec::new(),
            params,
            warning: Warning::default(),
            times: ContactTimes::default(),
            locked: false,
        })
    }

    /// Re-detect on the current geometry; transfer state, shear, preload and bond from the
    /// previous points. `initial`: the first detection, where touching points take the in-situ
    /// traction and the joint's bond.
    pub fn detect(&mut self, sys: &System, state: &State, initial: bool) {
        let clock = Instant::now();
        let current: Vec<_> = self.pieces.par_iter().map(|p| p.current(sys, state)).collect();
        let p = self.params;
        let dp = DetectParams { margin: p.margin, support_tolerance: p.tolerance, thin_distance: 10.0 * p.tolerance };
        let pieces = &self.pieces;
        let keep = |i: usize, j: usize| {
            pieces[i].block != pieces[j].block && !both_fixed(sys, pieces[i].block, pieces[j].block)
        };
        let pairs = self.warning.update(&current, p.margin, p.skin, keep);
        self.times.warning += clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        let prepared: Vec<Prepared> = current.par_iter().map(Prepared::new).collect();
        // Current facet vertices, once per piece and only for pieces in a detected pair.
        let facets: Vec<OnceLock<Vec<Vec<Vec3>>>> = pieces.iter().map(|_| OnceLock::new()).collect();
        let facets_of = |k: usize| facets[k].get_or_init(|| pieces[k].facet_positions(sys, state)).as_slice();
        // A is the piece of the higher block index.
        let found: Vec<(usize, usize, Vec3, Vec<Candidate>)> = pairs
            .par_iter()
            .map(|&(i, j)| if pieces[i].block > pieces[j].block { (i, j) } else { (j, i) })
            .filter_map(|(i, j)| {
                let c = detect_prepared(&prepared[i], &prepared[j], &dp)?;
                let on = Surfaces {
                    pieces: (&pieces[i], &pieces[j]),
                    current: (&current[i], &current[j]),
                    facets: (facets_of(i), facets_of(j)),
                };
                Some((i, j, c.normal, candidates(sys, state, &on, &c, p.tolerance)))
            })
            .collect();
        let previous = std::mem::take(&mut self.records);
        let mut by_pair: FxHashMap<(usize, usize), Vec<usize>> = FxHashMap::default();
        for (k, r) in previous.iter().enumerate() {
            by_pair.entry(r.blocks).or_default().push(k);
        }
        for (i, j, normal, points) in found {
            let blocks = (self.pieces[i].block, self.pieces[j].block);
            let joint = joint_between(sys, blocks.0, blocks.1);
            for q in points {
                let mut r = ContactRecord::fresh(sys, q, blocks, normal, joint, initial, &p);
                inherit(&mut r, &previous, by_pair.get(&blocks), &p, self.locked);
                self.records.push(r);
            }
        }
        self.times.detection += clock.elapsed().as_secs_f64();
    }

    /// Points overlapping deeper than `depth` [m].
    pub fn overlaps(&self, depth: f64) -> impl Iterator<Item = &ContactRecord> {
        self.records.iter().filter(move |r| r.gap0 + r.offset < -depth)
    }

    /// Pairs of MEs (lower first) with a closed point, sorted, each once.
    pub fn closed_pairs(&self) -> Vec<(usize, usize)> {
        let mut pairs: Vec<_> =
            self.records.iter().filter(|r| r.state != ContactState::Open).map(ContactRecord::element_pair).collect();
        pairs.sort_unstable();
        pairs.dedup();
        pairs
    }

    /// The springs of every closed point, summed per pair of MEs and scattered into `values`
    /// (on `pattern`) through the pair's coupling (its covers, lower ME first); the constant
    /// forces go straight to `force` per cover. A point's matrix is w wᵀ ⊗ B, so tied covers
    /// are folded into the weights (Tᵀ w) before the product, not after.
    pub fn assemble<'a>(
        &self,
        sys: &System,
        force: &mut [Vec3],
        pattern: &SparsityPattern,
        coupling: impl Fn((usize, usize)) -> &'a Coupling,
        values: &mut [f64],
    ) {
        let mut order: Vec<usize> =
            (0..self.records.len()).filter(|&k| self.records[k].state != ContactState::Open).collect();
        order.sort_by_key(|&k| self.records[k].element_pair());
        let (mut mat, mut w, mut wm) = (Vec::new(), Vec::new(), Vec::new());
        let mut k = 0;
        while k < order.len() {
            let key = self.records[order[k]].element_pair();
            let cp = coupling(key);
            let m = cp.nodes();
            mat.clear();
            mat.resize(9 * m * m, 0.0);
            while k < order.len() && self.records[order[k]].element_pair() == key {
                let r = &self.records[order[k]];
                k += 1;
                let (block, f) = r.spring();
                // Weights in the clique order of the pair (lower ME first); B's negative.
                let (first, second, sign) =
                    if r.a.element < r.b.element { (&r.a, &r.b, 1.0) } else { (&r.b, &r.a, -1.0) };
                w.clear();
                w.extend(first.weights.iter().map(|x| sign * x).chain(second.weights.iter().map(|x| -sign * x)));
                let covers =
                    sys.covers.elements[first.element].covers.iter().chain(&sys.covers.elements[second.element].covers);
                for (&c, wc) in covers.zip(&w) {
                    force[c] += *wc * f;
                }
                cp.node_weights(&w, &mut wm);
                for (a, wa) in wm.iter().enumerate().filter(|(_, x)| **x != 0.0) {
                    for (b, wb) in wm.iter().enumerate().filter(|(_, x)| **x != 0.0) {
                        let s = wa * wb;
                        for i in 0..3 {
                            for j in 0..3 {
                                mat[(3 * a + i) * 3 * m + 3 * b + j] += s * block[(i, j)];
                            }
                        }
                    }
                }
            }
            cp.add(pattern, values, &mat);
        }
    }

    /// Add each point's force at the start of the step (springs at the start gaps and
    /// extensions) to the per-cover forces `f`.
    pub fn add_start_forces(&self, sys: &System, f: &mut [Vec3]) {
        for r in &self.records {
            let (n, kn) = (r.normal, r.kn);
            let spring = -kn * r.gap0 * n;
            let force = match r.state {
                ContactState::Open => continue,
                ContactState::Stick => r.preload + spring - r.ks * r.shear0,
                ContactState::Slide => {
                    let normal = (n.dot(&r.preload) - kn * r.gap0).max(0.0);
                    n * n.dot(&r.preload) + spring - (r.strength.tan_phi * normal + r.strength.cohesion) * r.slip
                }
            };
            for (mp, sign) in [(&r.a, 1.0), (&r.b, -1.0)] {
                for (&c, w) in sys.covers.elements[mp.element].covers.iter().zip(&mp.weights) {
                    f[c] += sign * w * force;
                }
            }
        }
    }

    /// Update every point from the solved increments `d`: how many changed state, and how far
    /// the forces the solve applied are from the forces of the updated states (summed over the
    /// points, relative to the sum of the updated forces).
    pub fn update_states(&mut self, sys: &System, d: &[Vec3]) -> (usize, f64) {
        let locked = self.locked;
        let band = GAP_BAND * self.params.size;
        let reclose = RECLOSE_DEPTH * self.params.tolerance;
        let mut changed = 0;
        // Largest change of a sliding point's friction force, and the largest friction limit.
        let (mut turned, mut largest) = (0.0f64, 0.0f64);
        let (mut mismatch, mut total) = (0.0f64, 0.0f64);
        for r in &mut self.records {
            // The spring this solve used, linearised about the last iterate.
            let (block, constant) = r.spring();
            let inc = |mp: &MaterialPoint| -> Vec3 {
                sys.covers.elements[mp.element].covers.iter().zip(&mp.weights).map(|(&c, w)| *w * d[c]).sum()
            };
            // The friction this solve used (linearised about the last iterate).
            let used = (r.state == ContactState::Slide).then(|| r.friction().0);
            r.rel = inc(&r.a) - inc(&r.b);
            r.gap = r.gap0 + r.normal.dot(&r.rel);
            let (kn, ks) = (r.kn, r.ks);
            let n = r.normal;
            let t = tangential(&n);
            if r.state == ContactState::Open && r.gap <= 0.0 {
                // Closing: the shear spring starts where the point entered (the fraction of
                // the step's motion spent closing the gap does not stretch it; DDA's entrance).
                let entered = if r.gap0 > 0.0 { r.gap0 / (r.gap0 - r.gap) } else { 0.0 };
                r.shear0 = -entered * (t * r.rel);
            }
            let shear = r.shear0 + t * r.rel;
            // Elastic trial: forces on A if the springs held (return mapping onto the Coulomb
            // limit, as in 3DEC; a sliding point's spring sits at the limit, see `accept`).
            let normal = n.dot(&r.preload) - kn * r.gap;
            let held = t * r.preload - ks * shear;
            let s = r.strength;
            let limit = s.tan_phi * normal.max(0.0) + s.cohesion;
            let closing = r.state == ContactState::Open;
            let new = next_state(r, normal, &held, limit, band, reclose, locked);
            if new == ContactState::Slide && held.norm() > 0.0 {
                // A slips against the force that would hold it.
                largest = largest.max(limit);
                r.slip = -held.normalize();
                // The friction magnitude follows the normal force of the last solve — unless
                // the point was open in it: its overlap there had no spring to stop it, and
                // friction from it would be fictitious (and feed back until the iteration
                // diverges where many points close at once). It starts frictionless and takes
                // its real normal force at the next iteration.
                r.limit = if closing { 0.0 } else { limit };
                if let Some(u) = used {
                    turned = turned.max((-limit * r.slip - u).norm());
                }
            }
            if new != r.state {
                changed += 1;
                if new != ContactState::Stick {
                    r.strength = r.strength.broken();
                }
                if new == ContactState::Open {
                    r.preload = Vec3::zeros();
                    r.opened = true;
                }
                if closing {
                    r.reclosed += 1;
                }
                r.state = new;
            }
            r.force = match r.state {
                ContactState::Open => Vec3::zeros(),
                ContactState::Stick => r.preload - kn * r.gap * n - ks * shear,
                ContactState::Slide => n * n.dot(&r.preload) - kn * r.gap * n + r.friction().0,
            };
            mismatch += (constant - block * r.rel - r.force).norm();
            total += r.force.norm();
        }
        // The friction was linearised about the last iterate (its magnitude from the last
        // normal force, its direction from the last trial): if some sliding point's friction
        // changed by more than the tolerance (relative to the largest friction force), iterate
        // again, as for a change of state.
        if turned > SLIP_TURN * largest {
            changed += 1;
        }
        (changed, if total > 0.0 { mismatch / total } else { 0.0 })
    }

    /// After an accepted step: carry the shear-spring extension. A sliding point's spring is
    /// left at the Coulomb limit, so the force is continuous when it sticks again (a reset
    /// spring would drop the friction force at every stick–slip flip and ratchet the block).
    /// Returns the energy friction dissipated in the step: at each sliding point the limit
    /// times the slip beyond the spring's elastic change [J].
    pub fn accept(&mut self) -> f64 {
        let mut dissipated = 0.0;
        for r in &mut self.records {
            let t = tangential(&r.normal);
            let shear = match r.state {
                ContactState::Stick => r.shear0 + t * r.rel,
                ContactState::Slide => (t * r.preload + r.limit * r.slip) / r.ks,
                ContactState::Open => Vec3::zeros(),
            };
            if r.state == ContactState::Slide {
                dissipated += r.limit * (t * r.rel - (shear - r.shear0)).norm();
            }
            r.shear0 = shear;
        }
        dissipated
    }

    /// Energy in the springs of the closed points: ½ k_n g² for an overlap, ½ k_s |s|² [J]
    /// (after `accept`; an in-situ preload's share is not counted).
    pub fn spring_energy(&self) -> f64 {
        self.records
            .iter()
            .filter(|r| r.state != ContactState::Open)
            .map(|r| 0.5 * r.kn * r.gap.min(0.0).powi(2) + 0.5 * r.ks * r.shear0.norm_squared())
            .sum()
    }

    /// Multiply every penalty by `factor` (new points too), keeping the shear springs' forces.
    pub fn stiffen(&mut self, factor: f64) {
        self.params.kn *= factor;
        self.params.ks *= factor;
        self.records.iter_mut().for_each(|r| r.stiffen(factor));
    }

    /// Whether a closed point overlaps by more than `depth` [m] and more than at the start of the
    /// step: the overlap is growing beyond the allowed depth. (A point found already deeper — a
    /// corner that came in during the last step without a point, detected now — is being pushed
    /// out; no smaller step can undo an overlap that is there at the start.)
    pub fn overlap_growing_beyond(&self, depth: f64) -> bool {
        self.records
            .iter()
            .any(|r| r.state != ContactState::Open && !r.joint_stiffness && -r.gap > depth && r.gap < r.gap0)
    }

    /// Largest penetration among closed points [m].
    pub fn max_penetration(&self) -> f64 {
        self.records.iter().filter(|r| r.state != ContactState::Open).map(|r| -r.gap).fold(0.0, f64::max)
    }
}

/// Half-width of the open–close hysteresis as a fraction of the cover size (far below
/// elastic contact deformations, far above the round-off of gaps).
const GAP_BAND: f64 = 1e-10;

/// Overlap, as a fraction of the support tolerance, at which a point that opened during the
/// step's iterations closes again.
const RECLOSE_DEPTH: f64 = 1e-3;

/// Closings of a point within one step's open–close iterations after which it stays open.
const MAX_RECLOSE: u32 = 2;

/// Largest change of a sliding point's friction force between two open–close iterations,
/// relative to the largest friction limit, that counts as converged (about a 1° turn, or a
/// 1.7 % change, of the largest).
const SLIP_TURN: f64 = 0.017_45;

/// A new point whose gap is below this fraction of the support tolerance is touching (closed):
/// coordinates given to a few digits must not turn blocks placed on each other into a fall and
/// an impact. At the start such a point's gap becomes its zero level (`offset`).
const TOUCHING: f64 = 1e-3;

/// The covers of two MEs, first then second (the clique a contact between them couples).
pub fn pair_clique(sys: &System, a: usize, b: usize) -> Vec<usize> {
    [sys.covers.elements[a].covers.as_slice(), sys.covers.elements[b].covers.as_slice()].concat()
}

/// Tangential projector I − n nᵀ.
fn tangential(n: &Vec3) -> Mat3 {
    Mat3::identity() - n * n.transpose()
}

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
/// the piece-level points (area shared equally).
fn candidates(sys: &System, state: &State, on: &Surfaces, c: &Contact, tol: f64) -> Vec<Candidate> {
    let ((pa, pb), (ca, cb)) = (on.pieces, on.current);
    let n = c.normal;
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
        tol,
        MERGE * tol,
    );
    if !on_facets.is_empty() {
        return on_facets;
    }
    let area = if c.points.is_empty() { 0.0 } else { c.area / c.points.len() as f64 };
    c.points
        .iter()
        .filter_map(|q| {
            let a = MaterialPoint::new(sys, pa.block, pa.reference_of(ca, &q.on_a))?;
            let b = MaterialPoint::new(sys, pb.block, pb.reference_of(cb, &q.on_b))?;
            // The gap the springs act on: between the material points as their covers move them.
            // A piece's faces run straight between its vertices, but a long piece bends between
            // them (the covers interpolate within each ME): a gap measured on the straight faces
            // would not close when the springs push the material points apart.
            let (xa, xb) = (a.position(sys, state), b.position(sys, state));
            Some(Candidate { mode: q.mode, a, b, on_a: xa, gap: n.dot(&(xa - xb)), area })
        })
        .collect()
}

/// A point's penalties relative to `ContactParams::kn`, `ks`: its share of the contact area
/// over one cover cell's face (size²), so a face carries the same stiffness per area however
/// finely its points fall (at least [`MIN_SHARE`]); a point contact (no area) takes them whole.
fn stiffness_share(area: f64, size: f64) -> f64 {
    if area > 0.0 {
        (area / (size * size)).max(MIN_SHARE)
    } else {
        1.0
    }
}

/// Smallest stiffness share of a point of an area contact.
const MIN_SHARE: f64 = 0.05;

/// Facet overlay corners closer than this multiple of the support tolerance are one point (the
/// thinning distance of the piece-level points): near-identical facets of A and B would
/// otherwise give near-duplicate crossings that come and go as the blocks move.
const MERGE: f64 = 10.0;

/// The joint between two blocks: an interface naming both bodies, else A's body joint, else B's.
fn joint_between(sys: &System, a: usize, b: usize) -> Option<&Joint> {
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

/// In-situ traction on A's surface (outward normal −n) at `x`: σ₀(x)·(−n) [Pa].
fn in_situ_traction(sys: &System, x: &Vec3, n: &Vec3) -> Vec3 {
    let Some(s) = &sys.scenario.in_situ_stress else { return Vec3::zeros() };
    let dz = x.z - s.reference_z;
    let c: Vec<f64> = (0..6).map(|k| s.stress[k] + s.gradient[k] * dz).collect();
    // Voigt order xx, yy, zz, xy, yz, zx.
    let sigma = Mat3::new(c[0], c[3], c[5], c[3], c[1], c[4], c[5], c[4], c[2]);
    -(sigma * n)
}

/// The state of point `r` after a solve (the table of the module documentation), from its
/// normal force, elastic trial shear force `held` and Coulomb limit, with hysteresis of ±`band`
/// on gap and cone.
fn next_state(
    r: &ContactRecord,
    normal: f64,
    held: &Vec3,
    limit: f64,
    band: f64,
    reclose: f64,
    locked: bool,
) -> ContactState {
    let closing = r.state == ContactState::Open;
    match r.state {
        // Open until it overlaps beyond the band: a point at zero force (the side faces of
        // neighbouring blocks) must not flip with round-off. A point that closed twice in this
        // step's iterations stays open (it sits where the pressure changes sign and would flip
        // for ever); one that opened closes again only at the re-closing depth (small overlaps
        // there are rocking within the iteration, not contact).
        ContactState::Open if r.gap > -band || r.reclosed >= MAX_RECLOSE => ContactState::Open,
        ContactState::Open if r.opened && r.gap > -reclose => ContactState::Open,
        _ if locked => ContactState::Stick,
        // Tension beyond the bond (and the band's spring force) opens a closed point.
        _ if !closing && normal < -r.strength.tension - r.kn * band => ContactState::Open,
        // A sliding point whose slip would reverse sticks (DDA's rule; the direction of a point
        // barely slipping is noise and would flip between iterations).
        ContactState::Slide if held.dot(&r.slip) > 0.0 => ContactState::Stick,
        ContactState::Slide if held.norm() > limit => ContactState::Slide,
        // A stuck or closing point slides once the trial exceeds the limit by the band's spring
        // force (a point entering while the blocks slip slides at once instead of braking).
        _ if held.norm() > limit + r.ks * band => ContactState::Slide,
        _ => ContactState::Stick,
    }
}

/// Transfer to a new point `r` what its predecessor — the previous point of the same block
/// pair nearest it — carried: zero level always; state, shear, slip, preload and bond when the
/// predecessor is within the transfer distance and closed; a pair already sliding makes a new
/// point slide at the Coulomb limit instead of braking as a fresh stuck spring.
fn inherit(
    r: &mut ContactRecord,
    previous: &[ContactRecord],
    candidates: Option<&Vec<usize>>,
    p: &ContactParams,
    locked: bool,
) {
    let q_gap = r.gap0;
    let nearest_old = nearest(previous, candidates, &r.a.reference, f64::INFINITY);
    if let Some(old) = nearest_old {
        r.offset = old.offset;
    }
    (r.gap0, r.gap) = (q_gap - r.offset, q_gap - r.offset);
    let tan_phi = r.strength.tan_phi;
    if let Some(old) = nearest_old.filter(|o| (o.a.reference - r.a.reference).norm() < 10.0 * p.tolerance) {
        if old.state != ContactState::Open {
            // Still closed unless the springs would pull harder than the bond holds.
            let pull = r.kn * r.gap0 - r.normal.dot(&old.preload);
            let band = GAP_BAND * p.size * r.kn;
            r.state = if locked || pull <= old.strength.tension + band { old.state } else { ContactState::Open };
            r.shear0 = tangential(&r.normal) * old.shear0;
            r.slip = old.slip;
            r.preload = old.preload;
            r.strength = Strength { tan_phi, ..old.strength };
            r.force = old.force;
            if r.state == ContactState::Slide {
                // Linearise the friction about the last step's slip, not about rest.
                r.rel = old.rel;
            }
        }
    } else if let Some(old) = nearest_old {
        if old.state == ContactState::Slide && r.state == ContactState::Stick {
            r.state = ContactState::Slide;
            r.slip = old.slip;
            r.rel = old.rel;
            r.shear0 = r.slip * (tan_phi * (-r.kn * r.gap0).max(0.0) / r.ks);
        }
    }
    r.limit = r.strength.tan_phi * (r.normal.dot(&r.preload) - r.kn * r.gap0).max(0.0) + r.strength.cohesion;
}

/// The previous point (among `candidates`) nearest `x` within `reach`.
fn nearest<'a>(
    previous: &'a [ContactRecord],
    candidates: Option<&Vec<usize>>,
    x: &Vec3,
    reach: f64,
) -> Option<&'a ContactRecord> {
    candidates?
        .iter()
        .map(|&k| &previous[k])
        .map(|o| ((o.a.reference - x).norm(), o))
        .filter(|(d, _)| *d < reach)
        .min_by(|p, q| p.0.total_cmp(&q.0))
        .map(|(_, o)| o)
}

/// Blocks overlapping deeper than `depth` at the start, as input problems naming the bodies.
pub fn overlap_problems(sys: &System, set: &ContactSet, depth: f64) -> Vec<Problem> {
    let mut seen = std::collections::BTreeSet::new();
    set.overlaps(depth)
        .filter(|r| seen.insert(r.blocks))
        .map(|r| {
            let name = |b: usize| &sys.scenario.body[sys.geometry.blocks[b].body].name;
            let x = r.a.reference;
            Problem {
                path: format!("body.{}", name(r.blocks.0)),
                reason: format!(
                    "block {} of body '{}' overlaps block {} of body '{}' by {:.3e} m at ({:.4}, {:.4}, {:.4}) (allowed {:.1e} m)",
                    r.blocks.0, name(r.blocks.0), r.blocks.1, name(r.blocks.1), -(r.gap0 + r.offset), x.x, x.y, x.z, depth
                ),
            }
        })
        .collect()
}

impl ContactRecord {
    /// A point detected now, before any transfer: touching points are closed (stuck), and at
    /// the start take their gap as zero level, the joint's bond and the in-situ preload.
    fn fresh(
        sys: &System,
        q: Candidate,
        blocks: (usize, usize),
        normal: Vec3,
        joint: Option<&Joint>,
        initial: bool,
        p: &ContactParams,
    ) -> Self {
        // Touching counts as closed: blocks placed on each other start in contact.
        let touching = q.gap <= TOUCHING * p.tolerance;
        let bonded = initial && touching;
        let area = q.area;
        let strength = |f: fn(&Joint) -> f64| if bonded { joint.map_or(0.0, f) * area } else { 0.0 };
        let (kn, ks, joint_stiffness) = match joint.and_then(Joint::stiffness) {
            // Per unit area × the point's area (a point contact: one cover cell's face).
            Some((kn, ks)) => {
                let a = if area > 0.0 { area } else { p.size * p.size };
                (kn * a, ks * a, true)
            }
            None => (p.kn * stiffness_share(area, p.size), p.ks * stiffness_share(area, p.size), false),
        };
        Self {
            blocks,
            mode: q.mode,
            normal,
            gap0: q.gap,
            offset: if bonded { q.gap } else { 0.0 },
            state: if touching { ContactState::Stick } else { ContactState::Open },
            shear0: Vec3::zeros(),
            slip: Vec3::zeros(),
            strength: Strength {
                tan_phi: joint.map_or(0.0, |j| j.friction_angle.to_radians().tan()),
                cohesion: strength(|j| j.cohesion),
                tension: strength(|j| j.tensile_strength),
            },
            area,
            kn,
            ks,
            joint_stiffness,
            preload: if bonded { in_situ_traction(sys, &q.on_a, &normal) * area } else { Vec3::zeros() },
            gap: q.gap,
            rel: Vec3::zeros(),
            force: Vec3::zeros(),
            reclosed: 0,
            opened: false,
            limit: 0.0,
            a: q.a,
            b: q.b,
        }
    }

    /// The pair of MEs the point couples, lower first.
    pub fn element_pair(&self) -> (usize, usize) {
        (self.a.element.min(self.b.element), self.a.element.max(self.b.element))
    }

    /// Multiply the point's penalties by `factor`; the shear spring keeps its force. A joint's
    /// own stiffness is physical and stays.
    pub fn stiffen(&mut self, factor: f64) {
        if self.joint_stiffness {
            return;
        }
        self.kn *= factor;
        self.ks *= factor;
        self.shear0 /= factor;
    }

    /// The point's spring in its current state, linearised: stiffness (3 × 3) and the constant
    /// force on A (B takes the opposite).
    pub fn spring(&self) -> (Mat3, Vec3) {
        let (kn, ks) = (self.kn, self.ks);
        let n = self.normal;
        let t = tangential(&n);
        let mut block = kn * n * n.transpose();
        let mut force = -kn * self.gap0 * n;
        match self.state {
            ContactState::Stick => {
                block += ks * t;
                force += self.preload - ks * self.shear0;
            }
            ContactState::Slide => {
                // Friction linearised about the last iterate (return mapping, consistent
                // tangent; Wriggers, Computational Contact Mechanics §5.2): the force keeps
                // the Coulomb magnitude and turns with the trial direction, so sideways motion
                // of a sliding point meets stiffness instead of a fixed-direction force.
                let (f_k, k_t) = self.friction();
                block += k_t;
                force += n * n.dot(&self.preload) + f_k + k_t * self.rel;
            }
            ContactState::Open => return (Mat3::zeros(), Vec3::zeros()),
        }
        (block, force)
    }

    /// Sliding friction on A at the last iterate and its tangent: f = L ĥ with ĥ the direction of
    /// the elastic trial force h = t·P − k_s (s₀ + t·rel) and L the friction limit (`limit`);
    /// df/d(rel) = −K, K = k_s min(L/|h|, 1) (t − ĥ ĥᵀ).
    pub fn friction(&self) -> (Vec3, Mat3) {
        let ks = self.ks;
        let t = tangential(&self.normal);
        let h = t * self.preload - ks * (self.shear0 + t * self.rel);
        let limit = self.limit;
        if h.norm() <= f64::EPSILON * (limit + ks * self.shear0.norm()) {
            return (-limit * self.slip, Mat3::zeros());
        }
        let hat = h.normalize();
        (limit * hat, ks * (limit / h.norm()).min(1.0) * (t - hat * hat.transpose()))
    }

    /// Compressive normal force on A after the last solve, N = n·P − k_n g, at least 0 [N].
    pub fn normal_force(&self) -> f64 {
        (self.normal.dot(&self.preload) - self.kn * self.gap).max(0.0)
    }
}
