//! What a stepper is built from, read once from the scenario: the linear solver with its factor
//! reuse, and the contact penalties and tolerances.

use crate::contact::ContactParams;
use crate::scenario::Stiffness;
use crate::solver::{FactorReuse, FaerCholesky, ReusingSolver};
use crate::system::System;

/// The direct solver (faer's Cholesky) with factor reuse as `[analysis]` asks.
pub(super) fn solver(sys: &System) -> ReusingSolver {
    let a = &sys.scenario.analysis;
    let reuse = FactorReuse {
        enabled: a.factor_reuse,
        tolerance: a.krylov_tolerance,
        max_iterations: a.krylov_max_iterations,
        closeness: a.factor_reuse_closeness,
    };
    ReusingSolver::new(Box::new(FaerCholesky::new(a.ordering)), reuse)
}

/// Contact penalties and tolerances from the scenario's `[contact]`, read once ("auto":
/// k_n = `auto_penalty_factor` × largest E × cover size, k_s = k_n; detection margin twice the
/// largest step displacement plus the support tolerance, the warning skin `warning_skin` × it).
pub(super) fn contact_params(sys: &System) -> ContactParams {
    let (a, k) = (&sys.scenario.analysis, &sys.scenario.contact);
    let young = sys.geometry.materials.iter().map(|m| m.young).fold(0.0, f64::max);
    let size = sys.covers.mesh().size;
    let kn = match k.normal_stiffness {
        Stiffness::Value(v) => v,
        Stiffness::Auto => k.auto_penalty_factor * young * size,
    };
    let ks = match k.shear_stiffness {
        Stiffness::Value(v) => v,
        Stiffness::Auto => kn,
    };
    let tolerance = k.tolerance_ratio * size;
    let margin = 2.0 * a.max_displacement_ratio * sys.half_size + tolerance;
    ContactParams {
        kn,
        ks,
        size,
        margin,
        skin: k.warning_skin * margin,
        tolerance,
        band: k.gap_band * size,
        reclose: k.reclose_depth * tolerance,
        max_reclose: k.max_reclose,
        slip_turn: k.slip_turn,
        touching: k.touching * tolerance,
        min_share: k.min_area_share,
        merge: k.merge_ratio * tolerance,
        damping_ratio: k.damping_ratio,
    }
}
