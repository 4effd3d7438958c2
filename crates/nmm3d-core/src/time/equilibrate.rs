//! A dynamic step's end brought to equilibrium with the elements' own forces there.
//!
//! A step solves the linearised system (the tangent at the start): its end meets the forces
//! f(u₀) + K_t d, not the co-rotated elements' forces f(u₀ + d). Over a rotation of θ per step
//! the two differ by O(θ²) — the centripetal forces that turn a spinning block's velocity —
//! and a linear step leaves that to the next step's unbalanced force: the block spirals out,
//! stretches, and loses kinetic energy that no account holds (a free block turning at 2 rad/s
//! lost 1.5 % of it in 0.2 s; a stiffer one, 96 %). Modified Newton iterations on the step's
//! own matrix (its factor reused) add the difference m = r(u₀ + d) − (r(u₀) − K_t d) until it
//! stops changing: d ← d + A⁻¹ Δm (Crisfield 1991, "Non-linear finite element analysis of
//! solids and structures", vol. 1, §9.3; Newmark with equilibrium iterations, Hughes 2000,
//! §9.1.2). Contact springs are linear in d with their states fixed, so they stay in A.

use nmm3d_geom::{Mat3, Vec3};

use super::state::StepperState;
use super::stepper::Stepper;
use super::vectors::{equation_vector, gather, scatter_into, solver_error};
use crate::error::Result;
use crate::state::Motion;
use crate::system::System;

impl Stepper {
    /// Correct the trial increment `d` from `state` until the end's unbalanced force, under
    /// the step's loads, matches what the solve assumed; `r0` is the unbalanced force at the
    /// start. Returns the unbalanced force at the end (the elements' true forces). When the
    /// corrections stall (they stop shrinking, or the iterations run out) the last iterate is
    /// kept if its last correction was small (`step_equilibrium_stall`: a block tumbling fast
    /// turns so far in a step that the start's tangent contracts slowly, yet its iterate is far
    /// nearer equilibrium than the linear step); otherwise `d` is restored as it came and `None`
    /// returned (the tangent does not describe the step — an element turning inside out).
    pub(super) fn equilibrate(
        &mut self,
        sys: &System,
        (state, run): (&Motion, &mut StepperState),
        r0: &[Vec3],
        d: &mut [Vec3],
    ) -> Result<Option<Vec<Vec3>>> {
        let a = &sys.scenario.analysis;
        let linear = d.to_vec();
        let mut last = f64::INFINITY;
        let g0 = gather(sys, r0);
        let mut end = state.clone();
        // Start from each block's rotation made exact (the linear step moved its points along
        // the tangents): what the rhs must carry for that start, A δ, is applied already.
        // (Tied covers follow their masters.)
        let x = equation_vector(sys, &exact_rotations(sys, state, &self.lumped_mass, d));
        let mut predicted = vec![Vec3::zeros(); d.len()];
        scatter_into(sys, &x, &mut predicted);
        let mut applied = vec![0.0; g0.len()];
        self.pattern.pattern(sys).symmetric_times(&self.values, &x, &mut applied);
        d.iter_mut().zip(&predicted).for_each(|(d, p)| *d += p);
        let mut ktd = vec![0.0; g0.len()];
        let mut delta = vec![Vec3::zeros(); d.len()];
        for it in 1.. {
            end.u.iter_mut().zip(&state.u).zip(d.iter()).for_each(|((e, u), d)| *e = u + d);
            let r1 = self.residual_at(sys, &end);
            let stalled = |d: &mut [Vec3], last: f64| {
                let keep = last <= a.step_equilibrium_stall * largest(d);
                if !keep {
                    d.copy_from_slice(&linear);
                }
                keep.then_some(r1.clone())
            };
            if it > a.step_equilibrium_iterations {
                return Ok(stalled(d, last));
            }
            sys.assembler.pattern.symmetric_times(&self.tangent, &equation_vector(sys, d), &mut ktd);
            // m = r(u₀ + d) − (r(u₀) − K_t d); the rhs lacks its change since the last solve.
            let m: Vec<f64> = gather(sys, &r1).iter().zip(&g0).zip(&ktd).map(|((r1, r0), kd)| r1 - r0 + kd).collect();
            let mut change: Vec<f64> = m.iter().zip(&applied).map(|(m, a)| m - a).collect();
            // The correction is judged against `step_equilibrium_tolerance` of the increment: on
            // a kept factor it is solved to that relative accuracy, not to `krylov_tolerance`.
            self.solver
                .solve_to(self.pattern.pattern(sys), &self.values, &mut change, true, a.step_equilibrium_tolerance)
                .map_err(|f| solver_error(sys, state.step + 1, f))?;
            scatter_into(sys, &change, &mut delta);
            // Settled when the correction is below the tolerance of the increment: the end
            // stays where its forces were measured.
            let size = largest(&delta);
            if size <= a.step_equilibrium_tolerance * largest(d) {
                return Ok(Some(r1));
            }
            if size >= last {
                return Ok(stalled(d, last));
            }
            last = size;
            d.iter_mut().zip(&delta).for_each(|(d, x)| *d += x);
            applied = m;
            run.equilibrium_iterations += 1;
        }
        unreachable!("the loop returns at its last iteration")
    }
}

/// The largest displacement of `v` [m].
fn largest(v: &[Vec3]) -> f64 {
    v.iter().map(|x| x.norm()).fold(0.0, f64::max)
}

/// Per cover, what turns each moving block's rigid rotation in `d` (the least-squares fit
/// d_c ≈ t + ω × r_c over its covers, weighted by their lumped masses `mass`, r_c from their
/// centre of mass at `state`) from the linear ω × r_c into the exact (R(ω) − I) r_c. About the
/// centre of mass the correction carries no momentum.
fn exact_rotations(sys: &System, state: &Motion, mass: &[f64], d: &[Vec3]) -> Vec<Vec3> {
    let mut by_block: Vec<Vec<usize>> = vec![Vec::new(); sys.geometry.blocks.len()];
    for c in (0..d.len()).filter(|&c| sys.dofs.moves(c) && mass[c] > 0.0) {
        by_block[sys.covers.covers[c].block].push(c);
    }
    let mut out = vec![Vec3::zeros(); d.len()];
    for covers in by_block.iter().filter(|c| c.len() >= 3) {
        let x = |c: usize| sys.covers.covers[c].position + state.u[c];
        let total: f64 = covers.iter().map(|&c| mass[c]).sum();
        let centre = covers.iter().map(|&c| mass[c] * x(c)).sum::<Vec3>() / total;
        let t = covers.iter().map(|&c| mass[c] * d[c]).sum::<Vec3>() / total;
        let (mut j, mut b) = (Mat3::zeros(), Vec3::zeros());
        for &c in covers {
            let r = x(c) - centre;
            j += mass[c] * (Mat3::identity() * r.norm_squared() - r * r.transpose());
            b += mass[c] * r.cross(&(d[c] - t));
        }
        let Some(omega) = j.try_inverse().map(|inv| inv * b) else { continue };
        let turn = nalgebra::Rotation3::from_scaled_axis(omega).into_inner() - Mat3::identity();
        for &c in covers {
            let r = x(c) - centre;
            out[c] = turn * r - omega.cross(&r);
        }
    }
    out
}
