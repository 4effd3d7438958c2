//! A shaking base in the step: the blocks' acceleration where the base's acceleration jumps,
//! and the base's own velocity and displacement over an accepted step.

use nmm3d_geom::Vec3;

use crate::state::Motion;
use crate::system::System;

/// Where the base acceleration jumps at the state's time, the blocks' acceleration (in the
/// base's frame) jumps by minus as much: M⁻¹(−m Δa) = −Δa on every movable cover, since the
/// cover weights sum to one.
pub(super) fn jump_acceleration(sys: &System, state: &mut Motion) {
    let q = &sys.scenario.seismic;
    let (before, after) = (q.acceleration_before(state.time), q.acceleration_after(state.time));
    let jump = Vec3::from(after) - Vec3::from(before);
    if jump != Vec3::zeros() {
        for (c, a) in state.a.iter_mut().enumerate() {
            if !sys.geometry.blocks[sys.covers.covers[c].block].fixed {
                *a -= jump;
            }
        }
    }
}

/// The base's own velocity and displacement over an accepted step from `state.time`: the
/// trapezoidal rule on its acceleration between the limits inside the step (exact where the
/// acceleration is linear, which the steps ending at its jumps make it piecewise).
pub(super) fn advance_base(sys: &System, state: &mut Motion, dt: f64) {
    let q = &sys.scenario.seismic;
    let (a0, a1) = (Vec3::from(q.acceleration_after(state.time)), Vec3::from(q.acceleration_before(state.time + dt)));
    let [v, u] = state.base;
    state.base = [v + 0.5 * dt * (a0 + a1), u + dt * v + dt * dt / 6.0 * (2.0 * a0 + a1)];
}
