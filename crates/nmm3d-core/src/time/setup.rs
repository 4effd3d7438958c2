//! What a stepper is built from, read once from the scenario: the linear solver with its factor
//! reuse, and the contact penalties and tolerances.

use crate::assembly::dof_map::CoverDofs;
use crate::contact::ContactParams;
use crate::scenario::{AnalysisKind, SolverChoice, Stiffness};
use crate::solver::{
    AmgParams, AmgSolver, BlockParams, BlockPcg, FactorReuse, FaerCholesky, LinearSolver, ReusingSolver,
};
use crate::system::System;

/// The linear solver `[analysis]` asks for (faer's Cholesky, multigrid PCG or PCG on the
/// blocks) with factor reuse.
pub(super) fn solver(sys: &System) -> ReusingSolver {
    let a = &sys.scenario.analysis;
    let reuse = FactorReuse {
        enabled: a.factor_reuse,
        tolerance: a.krylov_tolerance,
        max_iterations: a.krylov_max_iterations,
        closeness: a.factor_reuse_closeness,
    };
    ReusingSolver::new(linear_solver(sys), reuse)
}

/// Multigrid when asked, or with "auto" for one block (no contact springs, which multigrid
/// handles poorly) of at least `amg_min_equations` equations, where a factor outgrows its use.
fn linear_solver(sys: &System) -> Box<dyn LinearSolver> {
    let a = &sys.scenario.analysis;
    let amg = match a.linear_solver {
        SolverChoice::Direct => false,
        SolverChoice::Amg => true,
        SolverChoice::Blocks => return Box::new(block_solver(sys)),
        SolverChoice::Auto => sys.geometry.blocks.len() == 1 && sys.dofs.n_eq as u64 >= a.amg_min_equations,
    };
    if !amg {
        return Box::new(FaerCholesky::new(a.ordering).with_precision(a.factor_precision));
    }
    let mut positions = vec![[0.0; 3]; sys.dofs.n_eq / 3];
    for (kind, cover) in sys.dofs.kind.iter().zip(&sys.covers.covers) {
        if let CoverDofs::Free(e) = kind {
            positions[*e as usize / 3] = [cover.position.x, cover.position.y, cover.position.z];
        }
    }
    // A static equilibrium's Newton corrections need not be solved far beyond what the next
    // iteration corrects (inexact Newton: Dembo, Eisenstat & Steihaug, SIAM J. Numer. Anal. 19,
    // 1982); its loop stops on the unbalanced force, whatever the solves left. The first solve
    // is such a correction too, unless `max_steps` leaves no next iteration.
    let newton = a.amg_tolerance.max(a.amg_newton_tolerance);
    let (tolerance, nearby_tolerance) = match a.kind {
        AnalysisKind::Static if a.max_steps > 1 => (newton, newton),
        AnalysisKind::Static => (a.amg_tolerance, newton),
        AnalysisKind::Dynamic => (a.amg_tolerance, a.amg_tolerance),
    };
    let params = AmgParams { tolerance, nearby_tolerance, ..AmgParams::default() };
    Box::new(AmgSolver::new(positions, params))
}

/// Conjugate gradients preconditioned by the blocks ([`BlockPcg`]): each free cover's block
/// and position.
fn block_solver(sys: &System) -> BlockPcg {
    let nodes = sys.dofs.n_eq / 3;
    let (mut block, mut at) = (vec![0u32; nodes], vec![nmm3d_geom::Vec3::zeros(); nodes]);
    for (kind, cover) in sys.dofs.kind.iter().zip(&sys.covers.covers) {
        if let CoverDofs::Free(e) = kind {
            (block[*e as usize / 3], at[*e as usize / 3]) = (cover.block as u32, cover.position);
        }
    }
    let params = BlockParams { tolerance: sys.scenario.analysis.krylov_tolerance, ..BlockParams::default() };
    BlockPcg::new(block, &at, params)
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
        turned_face: k.turned_face_angle.to_radians().cos(),
        carry_joint_force: k.carry_joint_force,
        static_slack: k.static_carry_slack,
    }
}
