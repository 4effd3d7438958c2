//! The initial equilibrium: the static state under the initial loads, with every contact
//! locked or with the contacts free, from which a run starts at t = 0.

use nmm3d_geom::Vec3;

use super::state::State;
use super::stepper::Stepper;
use crate::error::Result;
use crate::scenario::{AnalysisKind, InitialEquilibrium};
use crate::system::System;

impl Stepper {
    /// The static equilibrium under the initial loads — the stressed state a run starts from
    /// (the usual first stage of a jointed-rock model): with every contact locked, or with the
    /// contacts free (`analysis.initial_equilibrium`). Velocities, time and step count are
    /// restored afterwards.
    pub fn settle(&mut self, sys: &System, state: &mut State) -> Result<Settled> {
        let m = &mut state.motion;
        let (v, a, dt, u_start) = (m.v.clone(), m.a.clone(), m.dt, m.u.clone());
        m.v.iter_mut().chain(m.a.iter_mut()).for_each(|x| *x = Vec3::zeros());
        let (steps, unbalanced, u_last) = match sys.scenario.analysis.initial_equilibrium {
            InitialEquilibrium::Frictional => self.relax(sys, state, &u_start)?,
            _ => self.settle_locked(sys, state, (dt, &u_start))?,
        };
        if let Some(c) = state.contact.as_mut() {
            c.release();
        }
        let m = &mut state.motion;
        (m.v, m.a, m.dt, m.time, m.step) = (v, a, dt, 0.0, 0);
        let mut out = Settled { steps, unbalanced, moving: Vec::new(), names: Vec::new(), exhausted: false };
        // A static analysis's travel starts from a converged settlement, which is no block's
        // failure (on 10 MPa/m joints the tunnel's roof key block, at rest at 45°, settled
        // 10 mm); an unconverged one may hold a block's sliding (8 cm at 10°): counted.
        if sys.scenario.analysis.kind == AnalysisKind::Static && out.converged(sys) {
            m.travel_origin = m.u.clone();
        }
        if !out.converged(sys) {
            out.exhausted = !sunk(sys, &m.u, &u_start);
            let last_move: Vec<f64> = m.u.iter().zip(&u_last).map(|(u, u0)| (u - u0).norm()).collect();
            out.moving = still_moving(sys, &last_move);
            out.names = out.moving.iter().map(|&b| block_name(sys, b)).collect();
        }
        // The run starts from the acceleration of the settled state, whose contacts hold the
        // blocks (not from the one before it, where nothing held them yet).
        let residual = self.initial_residual(sys, state);
        self.start_acceleration(sys, state, residual)?;
        Ok(out)
    }

    /// The locked equilibrium: first by Newton iterations of the static equilibrium (no
    /// inertia: the locked springs hold every touching block, so a few iterations suffice,
    /// however soft the joints). Where that cannot work — a block held by nothing makes the
    /// matrix singular, an iteration moves too far, or `max_static_iterations` do not converge
    /// — it goes on by implicit steps of `dt` whose velocity is reset each step: the mass term
    /// regularises, at the cost of many steps for soft, rocking modes. Its steps, the
    /// unbalanced force ratio reached, and where its last step started.
    fn settle_locked(
        &mut self,
        sys: &System,
        state: &mut State,
        (dt, u_start): (f64, &[Vec3]),
    ) -> Result<(u64, f64, Vec<Vec3>)> {
        lock(state, true);
        let analysis = &sys.scenario.analysis;
        let (mut steps, mut damped, mut unbalanced) = (0, 0, f64::INFINITY);
        // Where the last step started (its motion names the blocks still moving).
        let mut u_last = u_start.to_vec();
        state.stepper.inertia = false;
        while steps < analysis.max_steps && damped < analysis.max_settle_steps && !sunk(sys, &state.motion.u, u_start) {
            // A static iteration that fails is undone before the damped steps take over.
            let before = (!state.stepper.inertia).then(|| state.clone());
            let u0 = state.motion.u.clone();
            let r = match (self.step(sys, state, f64::INFINITY), before) {
                (Ok(r), None) => r,
                (Ok(r), Some(_)) if r.cuts == 0 && steps < analysis.max_static_iterations => r,
                (Ok(_) | Err(_), Some(saved)) => {
                    // Not statically solvable as it stands: regularise with the mass term.
                    *state = saved;
                    state.stepper.inertia = true;
                    state.motion.dt = dt;
                    continue;
                }
                (Err(e), None) => {
                    lock(state, false);
                    return Err(e);
                }
            };
            steps += 1;
            damped += u64::from(state.stepper.inertia);
            unbalanced = r.unbalanced;
            u_last = u0;
            if steps > 1 && unbalanced <= analysis.equilibrium_tolerance {
                break;
            }
        }
        state.stepper.inertia = true;
        lock(state, false);
        Ok((steps, unbalanced, u_last))
    }

    /// The frictional equilibrium: static steps (velocities reset, `run.relaxing`) of
    /// `analysis.settle_dt` with the contacts free — opening, sliding at the Coulomb limit — as
    /// a static analysis takes them, at most `max_settle_steps` and none once a cover has moved
    /// by a cover cell (a block that slides that far is not held). No lock, so no tension or
    /// over-cone shear for the release to let go, and the points a settlement closes are
    /// detected as it goes. What [`Self::settle_locked`] returns.
    fn relax(&mut self, sys: &System, state: &mut State, u_start: &[Vec3]) -> Result<(u64, f64, Vec<Vec3>)> {
        let analysis = &sys.scenario.analysis;
        let (mut steps, mut unbalanced) = (0, f64::INFINITY);
        let mut u_last = u_start.to_vec();
        (state.stepper.relaxing, state.motion.dt) = (true, analysis.settle_dt);
        while steps < analysis.max_steps.min(analysis.max_settle_steps) && !sunk(sys, &state.motion.u, u_start) {
            let u0 = state.motion.u.clone();
            let r = self.step(sys, state, f64::INFINITY);
            let r = r.inspect_err(|_| state.stepper.relaxing = false)?;
            (steps, unbalanced, u_last) = (steps + 1, r.unbalanced, u0);
            if steps > 1 && unbalanced <= analysis.equilibrium_tolerance {
                break;
            }
        }
        state.stepper.relaxing = false;
        Ok((steps, unbalanced, u_last))
    }
}

/// A settlement is elastic: a block whose cover has moved by a cover cell since `u_start` is
/// held by nothing.
fn sunk(sys: &System, u: &[Vec3], u_start: &[Vec3]) -> bool {
    u.iter().zip(u_start).any(|(u, u0)| (u - u0).norm() > sys.covers.mesh().size)
}

/// How the initial equilibrium ended.
#[derive(Debug, Clone, PartialEq)]
pub struct Settled {
    /// Static iterations and damped steps it took.
    pub steps: u64,
    /// Out-of-balance force ratio it reached.
    pub unbalanced: f64,
    /// When it did not converge: the blocks that moved most in its last step (at least a
    /// tenth of the largest motion) — those nothing holds, or hardly.
    pub moving: Vec<usize>,
    /// Those blocks by name ("block 3 of body 'roof'"), on the model that settled: a staged
    /// run's summary is made on its last stage's model, whose blocks are numbered otherwise.
    pub names: Vec<String>,
    /// When it did not converge: whether it ran out of steps (`max_settle_steps`,
    /// `max_steps`) rather than stopping at a block that moved by a cover cell.
    pub exhausted: bool,
}

impl Settled {
    /// Whether it reached `analysis.equilibrium_tolerance`.
    pub fn converged(&self, sys: &System) -> bool {
        self.unbalanced <= sys.scenario.analysis.equilibrium_tolerance
    }
}

/// "block `b` of body '…'" on the model `sys`.
pub fn block_name(sys: &System, b: usize) -> String {
    format!("block {b} of body '{}'", sys.scenario.body[sys.geometry.blocks[b].body].name)
}

/// Blocks whose covers moved by at least a tenth of the largest cover motion `moved` [m].
fn still_moving(sys: &System, moved: &[f64]) -> Vec<usize> {
    let mut per_block = vec![0.0_f64; sys.geometry.blocks.len()];
    for (c, d) in moved.iter().enumerate() {
        let b = sys.covers.covers[c].block;
        per_block[b] = per_block[b].max(*d);
    }
    let largest = per_block.iter().copied().fold(0.0, f64::max);
    (0..per_block.len()).filter(|&b| largest > 0.0 && per_block[b] >= 0.1 * largest).collect()
}

/// Lock or unlock the contacts: locked, closed points stick whatever the force.
fn lock(state: &mut State, locked: bool) {
    state.stepper.locked = locked;
    if let Some(c) = state.contact.as_mut() {
        c.locked = locked;
    }
}
