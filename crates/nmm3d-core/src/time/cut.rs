//! Why a trial step was rejected, and which blocks made it so (`cuts.csv`, summary): the step
//! diagnostics a user reads to see why a run is slow.

use nmm3d_geom::Vec3;
use serde::{Deserialize, Serialize};

use crate::contact::{ContactHistory, ContactState};
use crate::error::Error;
use crate::state::Motion;
use crate::system::System;

/// Blocks named per cut at most.
pub const MAX_BLOCKS: usize = 4;

/// Why a trial was rejected.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CutReason {
    /// The step moved some point farther than `max_displacement_ratio` allows.
    DisplacementRatio,
    /// The open–close iteration did not settle in `max_open_close` iterations.
    OpenCloseUnsettled,
    /// A contact overlapped deeper than `max_penetration_ratio` × the cover size, and the
    /// penalty could no longer be raised.
    Overlap,
    /// The same step repeated with the contact penalties raised (Δt kept).
    PenaltyRaised,
    /// The step gave the blocks energy at its contacts (`analysis.max_energy_gain`).
    EnergyGain,
}

impl CutReason {
    /// The name in `cuts.csv` and `summary.json`.
    pub fn name(self) -> &'static str {
        match self {
            Self::DisplacementRatio => "displacement_ratio",
            Self::OpenCloseUnsettled => "open_close_unsettled",
            Self::Overlap => "overlap",
            Self::PenaltyRaised => "penalty_raised",
            Self::EnergyGain => "energy_gain",
        }
    }
}

/// One rejected trial.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Cut {
    /// The step being tried (the one that is eventually accepted or fails).
    pub step: u64,
    /// Time at the start of that step [s].
    pub time: f64,
    /// The rejected trial's Δt [s].
    pub dt: f64,
    /// Why.
    pub reason: CutReason,
    /// Its measure: the displacement ratio [-], the points that changed state in the last
    /// open–close iteration (and the sliding point whose friction turned beyond `slip_turn`,
    /// if one did) [-], the deepest overlap [m], or the energy gained [J].
    pub value: f64,
    /// The blocks responsible, worst first (at most [`MAX_BLOCKS`]).
    pub blocks: Vec<usize>,
}

/// Blocks whose covers moved more than `limit` [m], the farthest first.
pub fn moved_too_far(sys: &System, d: &[Vec3], limit: f64) -> Vec<usize> {
    let mut worst: Vec<(usize, f64)> = Vec::new();
    for (c, x) in d.iter().enumerate() {
        let m = x.norm();
        if m > limit {
            let block = sys.covers.covers[c].block;
            match worst.iter_mut().find(|(b, _)| *b == block) {
                Some(w) => w.1 = w.1.max(m),
                None => worst.push((block, m)),
            }
        }
    }
    ranked(worst)
}

/// Blocks with the most points that changed state in the last open–close iteration (`changes`:
/// the block pairs of those points).
pub fn unsettled(changes: &[(usize, usize)]) -> Vec<usize> {
    counted(changes.iter().copied())
}

/// The blocks of the pairs `pairs` by how often they appear.
fn counted(pairs: impl Iterator<Item = (usize, usize)>) -> Vec<usize> {
    let mut count: Vec<(usize, f64)> = Vec::new();
    for (a, b) in pairs {
        for block in [a, b] {
            match count.iter_mut().find(|(x, _)| *x == block) {
                Some(w) => w.1 += 1.0,
                None => count.push((block, 1.0)),
            }
        }
    }
    ranked(count)
}

/// Blocks of the closed points overlapping deeper than `depth` [m], the deepest first, and the
/// deepest overlap.
pub fn overlapping(contacts: Option<&ContactHistory>, depth: f64) -> (Vec<usize>, f64) {
    let mut worst: Vec<(usize, f64)> = Vec::new();
    for r in contacts.map_or(&[][..], |c| &c.records) {
        if r.state != ContactState::Open && -r.gap > depth {
            for block in [r.blocks.0, r.blocks.1] {
                match worst.iter_mut().find(|(b, _)| *b == block) {
                    Some(w) => w.1 = w.1.max(-r.gap),
                    None => worst.push((block, -r.gap)),
                }
            }
        }
    }
    let deepest = worst.iter().map(|w| w.1).fold(0.0, f64::max);
    (ranked(worst), deepest)
}

/// Blocks with the most points that opened or closed during the step's open–close iterations
/// (where a step gives energy at its contacts).
pub fn impacts(contacts: Option<&ContactHistory>) -> Vec<usize> {
    let records = contacts.map_or(&[][..], |c| &c.records);
    counted(records.iter().filter(|r| r.event()).map(|r| r.blocks))
}

/// ": blocks 3 (body \"layer\"), 7 (…)" for the error message, or nothing.
pub fn named(sys: &System, blocks: &[usize]) -> String {
    if blocks.is_empty() {
        return String::new();
    }
    let named: Vec<String> = blocks
        .iter()
        .map(|&b| format!("{b} (body \"{}\")", sys.scenario.body[sys.geometry.blocks[b].body].name))
        .collect();
    format!("; blocks responsible: {}", named.join(", "))
}

/// The blocks by decreasing measure (ties by block number), at most [`MAX_BLOCKS`].
fn ranked(mut measured: Vec<(usize, f64)>) -> Vec<usize> {
    measured.sort_by(|p, q| q.1.total_cmp(&p.1).then(p.0.cmp(&q.0)));
    measured.into_iter().take(MAX_BLOCKS).map(|(b, _)| b).collect()
}

impl CutReason {
    /// Why a trial was rejected: its open–close iteration did not settle, or a contact
    /// overlapped too deep, or else it moved too far.
    pub fn of(settled: bool, too_deep: bool) -> Self {
        match (settled, too_deep) {
            (false, _) => CutReason::OpenCloseUnsettled,
            (true, true) => CutReason::Overlap,
            (true, false) => CutReason::DisplacementRatio,
        }
    }
}

/// The run error of a step that failed at the smallest Δt for `reason` (with the trial's
/// displacement ratio), naming the blocks of the last cut.
pub fn diverged(sys: &System, state: &Motion, dt: f64, (reason, ratio): (CutReason, f64), last: Option<&Cut>) -> Error {
    let blocks = last.map_or(String::new(), |c| named(sys, &c.blocks));
    let reason = match reason {
        CutReason::OpenCloseUnsettled => format!(
            "the open–close iteration did not settle in {} iterations even at the smallest time step {dt:.3e} s",
            sys.scenario.analysis.max_open_close
        ),
        CutReason::Overlap => format!(
            "a contact overlaps by more than {} × the cover size even at the smallest time step {dt:.3e} s and the raised penalty",
            sys.scenario.contact.max_penetration_ratio
        ),
        _ => format!("the step displacement ratio is {ratio:.3e} even at the smallest time step {dt:.3e} s"),
    } + &blocks;
    Error::Diverged { step: state.step + 1, time: state.time, reason }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_are_ranked_worst_first_and_capped() {
        let m = vec![(3, 0.1), (7, 0.5), (1, 0.5), (9, 0.2), (4, 0.05), (2, 0.3)];
        assert_eq!(ranked(m), vec![1, 7, 2, 9]);
        assert!(ranked(Vec::new()).is_empty());
    }

    #[test]
    fn reasons_have_stable_names() {
        let names: Vec<&str> = [
            CutReason::DisplacementRatio,
            CutReason::OpenCloseUnsettled,
            CutReason::Overlap,
            CutReason::PenaltyRaised,
            CutReason::EnergyGain,
        ]
        .iter()
        .map(|r| r.name())
        .collect();
        assert_eq!(names, ["displacement_ratio", "open_close_unsettled", "overlap", "penalty_raised", "energy_gain"]);
        for r in [CutReason::Overlap, CutReason::PenaltyRaised] {
            assert_eq!(serde_json::to_value(r).unwrap(), r.name());
        }
    }
}
