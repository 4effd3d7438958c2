//! Steps that give the blocks energy at an impact are repeated smaller.
//!
//! At an impact the scheme takes energy from the blocks, never gives it, when the step
//! resolves it. Where a closed point opens within a step the trapezoidal rule applies its start
//! force over the whole separation and gives the blocks ½ k_n |g₀| g₁ more than the spring
//! released (g₀ its overlap at the start, g₁ its gap at the end): a drop test at Δt = 1 ms (a
//! 5 ms contact) gets 8.6 % of its kinetic energy back at the release step
//! (`docs/theory/energy.md`). That shrinks with Δt, so such a step is cut. What is measured is
//! the energy the points that closed or opened in the step gave
//! ([`crate::contact::ContactHistory::event_gain`]) — not the whole of −Δ(D_c + D_n), which
//! also holds the friction of points sliding on (linearised to a tolerance: hundreds of joules a
//! step under the staged tunnel's in-situ stress, at any Δt) and the springs a detection's new
//! points inherit. Energy that does not shrink with Δt is not the step's doing: the step is
//! then kept — or, where the smaller step gave more, the larger one is taken again.

use super::energy::Energy;
use crate::scenario::Analysis;

/// A repeated step is kept unless its gain fell below this fraction of the last trial's.
const SHRINK: f64 = 0.5;

/// Whether a trial may be cut for the energy it gives (`analysis.max_energy_gain`; dynamic runs
/// with contact).
pub(super) fn guarded(a: &Analysis, dynamic_contact: bool) -> bool {
    a.max_energy_gain > 0.0 && dynamic_contact
}

/// The work [J] beyond which a point that starts the step overlapping with no force is bounded
/// rather than pushed out (`ContactHistory::bound_pushed_overlaps`): a step's gain budget,
/// `max_energy_gain` × the run's largest account; unbounded where the gain is not guarded or no
/// account exists yet (the first step).
pub(super) fn push_budget(a: &Analysis, dynamic_contact: bool, energy: Option<&Energy>) -> f64 {
    match energy {
        Some(e) if guarded(a, dynamic_contact) => a.max_energy_gain * e.largest(),
        _ => f64::INFINITY,
    }
}

/// What to do with a trial that gave the blocks energy.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum GainVerdict {
    /// Keep it.
    Keep,
    /// Repeat the step with this smaller Δt.
    Cut(f64),
    /// The smaller step gave more than the last trial: repeat that trial's Δt, and keep it.
    Back(f64),
}

/// The verdict on a trial of `dt` that `gained` energy, `scale` the run's largest energy account:
/// cut it if it gained more than `max_energy_gain` × `scale` and, after an earlier cut of the
/// same step (`tried`: its gain and Δt), less than [`SHRINK`] × that gain; go back to the earlier
/// trial if it gained more than that one.
pub(super) fn judge(a: &Analysis, dt: f64, gained: f64, scale: f64, tried: Option<(f64, f64)>) -> GainVerdict {
    let dt_min = a.min_dt_ratio * a.dt;
    let large = gained > a.max_energy_gain * scale && dt > dt_min * (1.0 + 1e-12);
    match tried {
        Some((g, dt0)) if gained > g => GainVerdict::Back(dt0),
        Some((g, _)) if gained >= SHRINK * g => GainVerdict::Keep,
        _ if large => GainVerdict::Cut((dt * a.open_close_cut).max(dt_min)),
        _ => GainVerdict::Keep,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_step_that_gives_energy_is_cut_while_the_gain_shrinks() {
        let a = Analysis { dt: 1e-3, ..Analysis::default() };
        // 8 J of 100 J: cut by open_close_cut.
        assert_eq!(judge(&a, 1e-3, 8.0, 100.0, None), GainVerdict::Cut(1e-3 * a.open_close_cut));
        // Within the bound, or taking energy: kept.
        assert_eq!(judge(&a, 1e-3, 0.5, 100.0, None), GainVerdict::Keep);
        assert_eq!(judge(&a, 1e-3, -8.0, 100.0, None), GainVerdict::Keep);
        // Repeated: cut again only while the gain halves; back to the larger step if the
        // smaller one gave more.
        assert!(matches!(judge(&a, 3e-4, 3.0, 100.0, Some((8.0, 1e-3))), GainVerdict::Cut(_)));
        assert_eq!(judge(&a, 3e-4, 5.0, 100.0, Some((8.0, 1e-3))), GainVerdict::Keep);
        assert_eq!(judge(&a, 3e-4, 20.0, 100.0, Some((8.0, 1e-3))), GainVerdict::Back(1e-3));
        // Not below the smallest step, and never when off.
        let smallest = a.min_dt_ratio * a.dt;
        assert_eq!(judge(&a, smallest, 8.0, 100.0, None), GainVerdict::Keep);
        assert!(guarded(&a, true));
        assert!(!guarded(&a, false));
        assert!(!guarded(&Analysis { max_energy_gain: 0.0, ..a }, true));
    }
}
