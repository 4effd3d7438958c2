//! The initial equilibrium: the static state under the initial loads with every contact locked,
//! from which a run starts at t = 0.

use nmm3d_geom::Vec3;

use super::state::State;
use super::stepper::Stepper;
use crate::error::Result;
use crate::system::System;

impl Stepper {
    /// Static equilibrium under the initial loads with every contact locked — the stressed
    /// state a run starts from (the usual first stage of a jointed-rock model). Velocities,
    /// time and step count are restored afterwards; returns (steps, final unbalanced ratio).
    ///
    /// First by Newton iterations of the static equilibrium (no inertia: the locked springs
    /// hold every touching block, so a few iterations suffice, however soft the joints). Where
    /// that cannot work — a block held by nothing makes the matrix singular, an iteration
    /// moves too far, or 50 iterations do not converge — it goes on as before, by implicit steps whose velocity is reset each
    /// step: the mass term regularises, at the cost of many steps for soft, rocking modes.
    pub fn settle(&mut self, sys: &System, state: &mut State) -> Result<(u64, f64)> {
        let m = &mut state.motion;
        let (v, a, dt) = (m.v.clone(), m.a.clone(), m.dt);
        m.v.iter_mut().chain(m.a.iter_mut()).for_each(|x| *x = Vec3::zeros());
        lock(state, true);
        let analysis = &sys.scenario.analysis;
        let (mut steps, mut unbalanced) = (0, f64::INFINITY);
        state.stepper.inertia = false;
        while steps < analysis.max_steps {
            // A static iteration that fails is undone before the damped steps take over.
            let before = (!state.stepper.inertia).then(|| state.clone());
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
            unbalanced = r.unbalanced;
            if steps > 1 && unbalanced <= analysis.equilibrium_tolerance {
                break;
            }
        }
        state.stepper.inertia = true;
        lock(state, false);
        if let Some(c) = state.contact.as_mut() {
            c.release();
        }
        let m = &mut state.motion;
        (m.v, m.a, m.dt, m.time, m.step) = (v, a, dt, 0.0, 0);
        Ok((steps, unbalanced))
    }
}

/// Lock or unlock the contacts: locked, closed points stick whatever the force.
fn lock(state: &mut State, locked: bool) {
    state.stepper.locked = locked;
    if let Some(c) = state.contact.as_mut() {
        c.locked = locked;
    }
}
