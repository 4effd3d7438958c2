//! The tangent and the unbalanced force at the current state: the co-rotated elements, the
//! penalty constraints and the loads (thesis §3.3).

use nmm3d_geom::{Mat3, Vec3};
use rayon::prelude::*;

use super::corotation;
use super::stepper::Stepper;
use crate::state::Motion;
use crate::system::System;

/// Elements whose local blocks are computed together (in parallel) before they are scattered.
const ELEMENT_CHUNK: usize = 2048;

impl Stepper {
    /// Tangent into `self.tangent`, unbalanced force per cover returned, the loads into
    /// `self.loads` (the water pressure at the rotations of the last step); updates rotations.
    pub fn assemble(&mut self, sys: &System, state: &mut Motion) -> Vec<Vec3> {
        self.tangent.iter_mut().for_each(|v| *v = 0.0);
        self.start_forces(sys, state, true)
    }

    /// The unbalanced force at the start of a step (the loads into `self.loads`, the rotations
    /// updated), the tangent into `self.tangent` if `with_tangent`.
    pub(super) fn start_forces(&mut self, sys: &System, state: &mut Motion, with_tangent: bool) -> Vec<Vec3> {
        let mut residual = sys.external.clone();
        super::water::add_water(sys, state, &mut residual);
        self.loads.clone_from(&residual);
        let tangent = with_tangent.then_some(&mut self.tangent);
        for (e, r) in subtract_inner_forces(sys, state, &mut residual, tangent) {
            state.rotations[e] = r;
        }
        residual
    }

    /// [`Self::assemble`], or what `initialize` assembled if the displacements are still the
    /// ones it saw (a run's first step: one element loop fewer).
    pub(super) fn assembled(&mut self, sys: &System, state: &mut Motion) -> Vec<Vec3> {
        match self.fresh.take() {
            Some((u, residual)) if u == state.u => residual,
            _ => self.assemble(sys, state),
        }
    }

    /// The unbalanced force at `state` under the loads of the step's start (`self.loads`),
    /// without a tangent: where a trial's end stands (see `super::equilibrate`).
    pub(super) fn residual_at(&self, sys: &System, state: &Motion) -> Vec<Vec3> {
        let mut residual = self.loads.clone();
        subtract_inner_forces(sys, state, &mut residual, None);
        residual
    }
}

/// Subtract the forces of the co-rotated elements, the penalty constraints and the bolts at
/// `state` from `residual`, adding their stiffness to `tangent` if given; the elements'
/// rotations returned.
fn subtract_inner_forces(
    sys: &System,
    state: &Motion,
    residual: &mut [Vec3],
    mut tangent: Option<&mut Vec<f64>>,
) -> Vec<(usize, Mat3)> {
    // Fixed blocks' covers cannot move; their forces would go nowhere.
    let moving: Vec<usize> =
        (0..sys.covers.elements.len()).filter(|&e| !sys.geometry.blocks[sys.covers.elements[e].block].fixed).collect();
    let mut rotations = Vec::with_capacity(moving.len());
    let with_tangent = tangent.is_some();
    // The local blocks of a chunk in parallel, scattered in element order: the same sums in the
    // same order whatever the thread count (bit-identical results), and memory for one chunk's
    // blocks only.
    for chunk in moving.chunks(ELEMENT_CHUNK) {
        let local: Vec<(Mat3, Vec<Vec3>, Vec<f64>)> = chunk
            .par_iter()
            .map(|&e| {
                let f = corotation::deformation_gradient(sys, state, e);
                let r = corotation::rotation(&f, &state.rotations[e]);
                let (fint, t) = match with_tangent {
                    true => corotation::internal_force_and_tangent(sys, state, e, &r),
                    false => (corotation::internal_force(sys, state, e, &r), Vec::new()),
                };
                (r, fint, t)
            })
            .collect();
        for (&e, (r, fint, t)) in chunk.iter().zip(local) {
            rotations.push((e, r));
            if let Some(tangent) = tangent.as_deref_mut() {
                sys.assembler.add(tangent, e, &t);
            }
            for (a, &c) in sys.covers.elements[e].covers.iter().enumerate() {
                residual[c] -= fint[a];
            }
        }
    }
    add_penalties(sys, state, residual, tangent.as_deref_mut());
    super::bolts::add_bolts(sys, state, residual, tangent);
    rotations
}

/// The penalty constraints' forces into `residual`, their stiffness into `tangent` if given.
fn add_penalties(sys: &System, state: &Motion, residual: &mut [Vec3], tangent: Option<&mut Vec<f64>>) {
    let k = sys.penalty;
    let mut tangent = tangent;
    for p in &sys.constraints {
        let me = &sys.covers.elements[p.element];
        let n = me.covers.len();
        let u: Vec3 = me.covers.iter().zip(&p.weights).map(|(&c, w)| *w * state.displacement(sys, c)).sum();
        let mut local = vec![0.0; 9 * n * n];
        for dir in &p.directions {
            let nn = dir * dir.transpose();
            for a in 0..n {
                residual[me.covers[a]] -= k * p.weights[a] * dir.dot(&u) * dir;
                for b in 0..n {
                    let s = k * p.weights[a] * p.weights[b];
                    for i in 0..3 {
                        for j in 0..3 {
                            local[(3 * a + i) * 3 * n + 3 * b + j] += s * nn[(i, j)];
                        }
                    }
                }
            }
        }
        if let Some(t) = tangent.as_deref_mut() {
            sys.assembler.add(t, p.element, &local);
        }
    }
}
