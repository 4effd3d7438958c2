//! Vectors between covers and equations: gathering forces onto the free equations (tied covers
//! pass theirs to their masters), scattering solutions back, the mass product and the measures
//! built on them.

use nmm3d_geom::Vec3;

use super::state::StepperState;
use crate::error::{Error, Pivot};
use crate::solver::SolverFailure;
use crate::state::Motion;
use crate::system::System;

/// ½ vᵀ M v from the velocities and their product `mv` with the mass (fixed covers excluded).
pub(super) fn kinetic_energy(sys: &System, v: &[Vec3], mv: &[Vec3]) -> f64 {
    (0..v.len()).filter(|&c| sys.dofs.moves(c)).map(|c| 0.5 * v[c].dot(&mv[c])).sum()
}

/// Per-cover increments → the equation vector of the free covers (tied covers follow them).
pub(super) fn equation_vector(sys: &System, d: &[Vec3]) -> Vec<f64> {
    let mut x = vec![0.0; sys.n_eq()];
    for (c, v) in d.iter().enumerate() {
        if let Some(e) = sys.dofs.eq(c, 0) {
            x[e..e + 3].copy_from_slice(v.as_slice());
        }
    }
    x
}

/// Each cover's lumped (row-summed) mass [kg].
pub(super) fn lumped_mass(sys: &System) -> Vec<f64> {
    mass_times(sys, &vec![Vec3::repeat(1.0); sys.covers.covers.len()]).iter().map(|m| m.x).collect()
}

/// M w, per cover, from the element masses.
pub(super) fn mass_times(sys: &System, w: &[Vec3]) -> Vec<Vec3> {
    let mut out = vec![Vec3::zeros(); w.len()];
    if w.iter().all(|x| *x == Vec3::zeros()) {
        return out;
    }
    // A fixed block's MEs couple only its own covers, which neither move nor take forces.
    for (e, me) in sys.covers.elements.iter().enumerate().filter(|(_, me)| !sys.geometry.blocks[me.block].fixed) {
        let k = sys.kernel(e);
        let n = me.covers.len();
        for a in 0..n {
            let acc: Vec3 = (0..n).map(|b| k.mass[a * n + b] * w[me.covers[b]]).sum();
            out[me.covers[a]] += acc;
        }
    }
    out
}

/// Largest force magnitude on the free equations (tied covers' forces taken by their masters).
pub(super) fn scale(sys: &System, f: &[Vec3]) -> f64 {
    gather(sys, f).chunks(3).map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()).fold(0.0, f64::max)
}

/// Per-cover forces → equation vector (a tied cover passes its force to its masters, Tᵀ f).
pub(super) fn gather(sys: &System, f: &[Vec3]) -> Vec<f64> {
    let mut out = vec![0.0; sys.n_eq()];
    for (c, v) in f.iter().enumerate() {
        for (m, w) in sys.dofs.masters(c) {
            let e = sys.dofs.eq(m, 0).expect("masters are free");
            for i in 0..3 {
                out[e + i] += w * v[i];
            }
        }
    }
    out
}

/// Equation vector → per-cover vectors (tied covers interpolated, fixed covers untouched).
pub(super) fn scatter_into(sys: &System, x: &[f64], out: &mut [Vec3]) {
    let at = |c: usize| {
        let e = sys.dofs.eq(c, 0).expect("free");
        Vec3::new(x[e], x[e + 1], x[e + 2])
    };
    for (c, o) in out.iter_mut().enumerate() {
        if sys.dofs.moves(c) {
            *o = sys.dofs.masters(c).iter().map(|&(m, w)| w * at(m)).sum();
        }
    }
}

/// The run error of a failed factorisation at `step`, naming the cover, block and body of a
/// non-positive pivot's equation.
pub(super) fn solver_error(sys: &System, step: u64, failure: SolverFailure) -> Error {
    match failure {
        SolverFailure::Analysis(reason) => {
            Error::Solver { step, reason: format!("the symbolic analysis failed: {reason}"), pivot: None }
        }
        SolverFailure::NotPositiveDefinite { equation } => {
            let cover = (0..sys.covers.covers.len())
                .find(|&c| sys.dofs.eq(c, 0).is_some_and(|e| (e..e + 3).contains(&equation)));
            let pivot = cover.map(|c| {
                let pc = &sys.covers.covers[c];
                let body = sys.scenario.body[sys.geometry.blocks[pc.block].body].name.clone();
                Pivot { equation, cover: c, block: pc.block, body, position: pc.position.into() }
            });
            Error::Solver { step, reason: "the system matrix is not positive definite".into(), pivot }
        }
    }
}

/// Unbalanced force ratio of `residual` (static equilibrium measure).
pub(super) fn unbalanced_ratio(sys: &System, run: &StepperState, residual: &[Vec3]) -> f64 {
    if run.force_scale > 0.0 {
        scale(sys, residual) / run.force_scale
    } else {
        0.0
    }
}

/// `into += add`, when there is something to add.
pub(super) fn add_to(into: &mut [Vec3], add: Option<&[Vec3]>) {
    if let Some(f) = add {
        into.iter_mut().zip(f).for_each(|(x, f)| *x += f);
    }
}

/// Where each free cover (node of three equations) is now [m].
pub(super) fn node_positions(sys: &System, state: &Motion) -> Vec<Vec3> {
    let mut out = vec![Vec3::zeros(); sys.n_eq() / 3];
    for (c, cover) in sys.covers.covers.iter().enumerate() {
        if let Some(e) = sys.dofs.eq(c, 0) {
            out[e / 3] = cover.position + state.u[c];
        }
    }
    out
}
