//! A staged analysis's state carried from the model of one stage onto the next's: the same
//! rock mass less the plugs a stage excavates, plus the bolts it installs. Covers and MEs are
//! built block by block in block order, so a kept block's covers and MEs keep their order and
//! the maps are running counts; displacements, velocities, co-rotations, the bolts' plastic
//! state and the contact points between kept blocks (springs, slips, preloads, bonds) carry
//! over; points on a removed plug go with it. New bolts start unstressed where the rock is.

use nmm3d_geom::Vec3;
use rustc_hash::FxHashMap;

use super::free_fall::FreeFall;
use super::state::State;
use super::stepper::Stepper;
use crate::contact::{ContactHistory, ContactRecord};
use crate::element::bolt::BoltState;
use crate::scenario::AnalysisKind;
use crate::state::Motion;
use crate::system::System;

/// Old → new index of each item of blocks `blocks` (`block_of(i)`), where `kept[b]` is the
/// new index of old block `b`.
fn running(n: usize, block_of: impl Fn(usize) -> usize, kept: &[Option<usize>]) -> Vec<Option<usize>> {
    let mut next = 0;
    (0..n)
        .map(|i| {
            kept[block_of(i)].map(|_| {
                next += 1;
                next - 1
            })
        })
        .collect()
}

/// The maps of one stage change: covers, MEs and blocks (old → new).
struct Maps<'a> {
    covers: Vec<Option<usize>>,
    elements: Vec<Option<usize>>,
    blocks: &'a [Option<usize>],
}

impl Maps<'_> {
    fn new<'a>(old: &System, new: &System, blocks: &'a [Option<usize>]) -> Maps<'a> {
        let covers = running(old.covers.covers.len(), |c| old.covers.covers[c].block, blocks);
        let elements = running(old.covers.elements.len(), |e| old.covers.elements[e].block, blocks);
        let same = covers.iter().enumerate().all(|(c, m)| {
            m.is_none_or(|n| {
                let (a, b) = (&old.covers.covers[c], &new.covers.covers[n]);
                blocks[a.block] == Some(b.block) && a.node == b.node
            })
        });
        let counts = covers.iter().flatten().count() == new.covers.covers.len()
            && elements.iter().flatten().count() == new.covers.elements.len();
        // Both models are cut and covered from one rock mass: a mismatch is a bug, not input.
        assert!(same && counts, "a stage's covers do not match the previous stage's");
        Maps { covers, elements, blocks }
    }

    /// `values` (one per old item, `map`) on the new items.
    fn carry<T: Clone>(map: &[Option<usize>], values: &[T], fill: T) -> Vec<T> {
        let mut out = vec![fill; map.iter().flatten().count()];
        for (v, m) in values.iter().zip(map) {
            if let Some(n) = m {
                out[*n] = v.clone();
            }
        }
        out
    }
}

/// The state `state` of model `old` carried onto model `new`, whose blocks are `old`'s with
/// old block `b` at `blocks[b]` (`None`: removed).
pub fn carry(old: &System, new: &System, blocks: &[Option<usize>], state: &State) -> State {
    let m = Maps::new(old, new, blocks);
    let z = Vec3::zeros();
    let u = Maps::carry(&m.covers, &state.motion.u, z);
    let motion = Motion {
        v: Maps::carry(&m.covers, &state.motion.v, z),
        a: Maps::carry(&m.covers, &state.motion.a, z),
        rotations: Maps::carry(&m.elements, &state.motion.rotations, nmm3d_geom::Mat3::identity()),
        bolts: bolts(old, new, &state.motion.bolts, &u),
        // A static stage's travel starts where the stage does.
        travel_origin: if new.scenario.analysis.kind == AnalysisKind::Static { u.clone() } else { Vec::new() },
        u,
        // A stage asking for a shorter step starts with it (a longer one is grown to).
        dt: state.motion.dt.min(new.scenario.analysis.dt),
        ..state.motion.clone()
    };
    let contact = match (&state.contact, new.geometry.blocks.len() > 1 && new.scenario.contact.enabled) {
        (Some(h), true) => Some(contacts(h, &m)),
        _ => None,
    };
    let mut stepper = state.stepper.clone();
    stepper.contact_end = Maps::carry(&m.covers, &stepper.contact_end, z);
    stepper.locked = false;
    // The free-fall record names a block of the old model: renumbered, or started again if
    // the stage removed it.
    stepper.free_fall = stepper.free_fall.map(|f| match m.blocks[f.block] {
        Some(block) => FreeFall { block, ..f },
        None => FreeFall { ratio: 0.0, block: 0, ..f },
    });
    // Every pair is detected afresh at the stage's first step, the points inheriting from these.
    stepper.undetected = f64::MAX;
    State { motion, contact, stepper }
}

/// Each new spring takes the state of the same bolt's same spring before; a bolt installed now
/// starts unstressed at the rock's current displacement `u`.
fn bolts(old: &System, new: &System, states: &[BoltState], u: &[Vec3]) -> Vec<BoltState> {
    let before: FxHashMap<(&str, usize), BoltState> = springs(old).zip(states.iter().copied()).collect();
    springs(new)
        .zip(&new.bolts)
        .map(|(key, b)| {
            before.get(&key).copied().unwrap_or(BoltState { installed: b.relative(u), ..Default::default() })
        })
        .collect()
}

/// Each spring of a model as (its bolt's name, its place among that bolt's springs).
fn springs(sys: &System) -> impl Iterator<Item = (&str, usize)> {
    let mut seen: FxHashMap<usize, usize> = FxHashMap::default();
    sys.bolts.iter().map(move |b| {
        let k = seen.entry(b.bolt).or_default();
        *k += 1;
        (sys.scenario.bolt[b.bolt].name.as_str(), *k - 1)
    })
}

/// The points between kept blocks, renumbered; the broad phase and travel start afresh.
fn contacts(h: &ContactHistory, m: &Maps) -> ContactHistory {
    let mut out = ContactHistory::new(h.params);
    out.missed_overlaps = h.missed_overlaps;
    out.carried_forces = h.carried_forces;
    out.records = h.records.iter().filter_map(|r| renumbered(r, m)).collect();
    out
}

fn renumbered(r: &ContactRecord, m: &Maps) -> Option<ContactRecord> {
    let mut r = r.clone();
    r.blocks = (m.blocks[r.blocks.0]?, m.blocks[r.blocks.1]?);
    r.a.element = m.elements[r.a.element]?;
    r.b.element = m.elements[r.b.element]?;
    Some(r)
}

impl Stepper {
    /// A stepper on a stage's model continuing the carried state `state` (no initial detection:
    /// the first step detects, the points inheriting from the carried ones).
    pub fn carried(sys: &System, state: &State) -> Self {
        let mut stepper = Self::on_model(sys);
        stepper.ensure_contact_pattern(sys, state.contact.as_ref(), state.motion.step);
        stepper
    }
}
