//! The tangent and the unbalanced force at the current state: the co-rotated elements, the
//! penalty constraints and the loads (thesis §3.3).

use nmm3d_geom::{Mat3, Vec3};
use rayon::prelude::*;

use super::corotation;
use super::stepper::Stepper;
use crate::state::State;
use crate::system::System;

/// Elements whose local blocks are computed together (in parallel) before they are scattered.
const ELEMENT_CHUNK: usize = 2048;

impl Stepper {
    /// Tangent into `self.tangent`, unbalanced force per cover returned, the loads into
    /// `self.loads` (the water pressure at the rotations of the last step); updates rotations.
    pub fn assemble(&mut self, sys: &System, state: &mut State) -> Vec<Vec3> {
        self.tangent.iter_mut().for_each(|v| *v = 0.0);
        let mut residual = sys.external.clone();
        super::water::add_water(sys, state, &mut residual);
        self.loads.clone_from(&residual);
        // Fixed blocks' covers cannot move; their forces would go nowhere.
        let moving: Vec<usize> = (0..sys.covers.elements.len())
            .filter(|&e| !sys.geometry.blocks[sys.covers.elements[e].block].fixed)
            .collect();
        // The local blocks of a chunk in parallel, scattered in element order: the same sums
        // in the same order whatever the thread count (bit-identical results), and memory for
        // one chunk's blocks only.
        for chunk in moving.chunks(ELEMENT_CHUNK) {
            let local: Vec<(Mat3, Vec<Vec3>, Vec<f64>)> = chunk
                .par_iter()
                .map(|&e| {
                    let f = corotation::deformation_gradient(sys, state, e);
                    let r = corotation::rotation(&f, &state.rotations[e]);
                    let (fint, t) = corotation::internal_force_and_tangent(sys, state, e, &r);
                    (r, fint, t)
                })
                .collect();
            for (&e, (r, fint, t)) in chunk.iter().zip(local) {
                state.rotations[e] = r;
                sys.assembler.add(&mut self.tangent, e, &t);
                for (a, &c) in sys.covers.elements[e].covers.iter().enumerate() {
                    residual[c] -= fint[a];
                }
            }
        }
        self.add_penalties(sys, state, &mut residual);
        self.add_bolts(sys, state, &mut residual);
        residual
    }

    pub(super) fn add_penalties(&mut self, sys: &System, state: &State, residual: &mut [Vec3]) {
        let k = sys.penalty;
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
            sys.assembler.add(&mut self.tangent, p.element, &local);
        }
    }
}
