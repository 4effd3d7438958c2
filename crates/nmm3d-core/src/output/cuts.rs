//! Step diagnostics: `cuts.csv` (every rejected trial, why, and the blocks responsible) and the
//! summary's `step_diagnostics` (cuts per reason, the blocks most often responsible, a
//! histogram of the accepted Δt) — why a run is slow, in one place.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use super::atomic;
use super::summary::{BlockCuts, DtBin, StepDiagnostics};
use crate::error::Result;
use crate::system::System;
use crate::time::{Cut, StepReport};

/// Upper edges of the Δt histogram's bins, as fractions of the requested Δt; the last bin
/// holds the rest (steps at the requested Δt, or grown above it).
const DT_BINS: [f64; 5] = [1e-4, 1e-3, 1e-2, 0.1, 0.99];

/// Blocks listed in the summary as most often responsible.
const TOP_BLOCKS: usize = 10;

/// Write `cuts.csv`: step, time at its start [s], rejected Δt [s], reason, its measure, blocks
/// responsible (`;`-separated block ids of `blocks.csv`, worst first).
pub fn write(dir: &Path, cuts: &[Cut]) -> Result<()> {
    let mut s = String::from("step,time,dt,reason,value,blocks\n");
    for c in cuts {
        let blocks: Vec<String> = c.blocks.iter().map(usize::to_string).collect();
        let _ = writeln!(s, "{},{},{},{},{},{}", c.step, c.time, c.dt, c.reason.name(), c.value, blocks.join(";"));
    }
    atomic::write(&dir.join("cuts.csv"), s.as_bytes())
}

/// The summary's `step_diagnostics`.
pub fn summary(sys: &System, cuts: &[Cut], steps: &[(f64, u64, StepReport)]) -> StepDiagnostics {
    let mut by_reason: BTreeMap<String, u64> = BTreeMap::new();
    let mut by_block: BTreeMap<usize, u64> = BTreeMap::new();
    for c in cuts {
        *by_reason.entry(c.reason.name().to_string()).or_default() += 1;
        for &b in &c.blocks {
            *by_block.entry(b).or_default() += 1;
        }
    }
    let mut blocks: Vec<(usize, u64)> = by_block.into_iter().collect();
    blocks.sort_by(|p, q| q.1.cmp(&p.1).then(p.0.cmp(&q.0)));
    let blocks_most_cut = blocks
        .iter()
        .take(TOP_BLOCKS)
        .map(|&(block, cuts)| BlockCuts {
            block,
            body: sys.scenario.body[sys.geometry.blocks[block].body].name.clone(),
            cuts,
        })
        .collect();
    StepDiagnostics {
        cuts_by_reason: by_reason,
        blocks_most_cut,
        dt_histogram: histogram(sys.scenario.analysis.dt, steps.iter().map(|(_, _, r)| r.dt)),
    }
}

/// Accepted steps per bin of Δt: `[{"from": s, "to": s, "steps": n}]`, the bins' edges the
/// requested Δt times [`DT_BINS`] (the first from 0, the last to the largest step taken).
fn histogram(requested: f64, dts: impl Iterator<Item = f64>) -> Vec<DtBin> {
    let mut counts = [0u64; DT_BINS.len() + 1];
    let mut largest = requested;
    for dt in dts {
        largest = largest.max(dt);
        let bin = DT_BINS.iter().position(|&edge| dt < edge * requested).unwrap_or(DT_BINS.len());
        counts[bin] += 1;
    }
    let mut from = 0.0;
    counts
        .iter()
        .enumerate()
        .map(|(k, &steps)| {
            let to = DT_BINS.get(k).map_or(largest, |e| e * requested);
            let row = DtBin { from, to, steps };
            from = to;
            row
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_step_falls_in_one_bin() {
        let dts = [1e-3, 1e-3, 5e-4, 2e-5, 1e-8, 1.2e-3];
        let rows = histogram(1e-3, dts.into_iter());
        let steps: Vec<u64> = rows.iter().map(|r| r.steps).collect();
        assert_eq!(steps, [1, 0, 0, 1, 1, 3]);
        assert_eq!(rows[0].from, 0.0);
        assert_eq!(rows.last().unwrap().to, 1.2e-3, "the last bin reaches the largest step");
        for w in rows.windows(2) {
            assert_eq!(w[0].to, w[1].from, "bins are contiguous");
        }
    }
}
