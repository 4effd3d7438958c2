//! The tangent and the unbalanced force at the current state: the co-rotated elements, the
//! penalty constraints and the loads (thesis §3.3).

use nmm3d_geom::Vec3;

use super::corotation;
use super::stepper::Stepper;
use crate::state::State;
use crate::system::System;

impl Stepper {
    /// Tangent into `self.tangent`, unbalanced force per cover returned; updates rotations.
    pub fn assemble(&mut self, sys: &System, state: &mut State) -> Vec<Vec3> {
        self.tangent.iter_mut().for_each(|v| *v = 0.0);
        let mut residual = sys.external.clone();
        for e in 0..sys.covers.elements.len() {
            if sys.geometry.blocks[sys.covers.elements[e].block].fixed {
                continue; // its covers cannot move; its forces would go nowhere
            }
            let f = corotation::deformation_gradient(sys, state, e);
            let r = corotation::rotation(&f, &state.rotations[e]);
            state.rotations[e] = r;
            let (fint, t) = corotation::internal_force_and_tangent(sys, state, e, &r);
            sys.assembler.add(&mut self.tangent, e, &t);
            for (a, &c) in sys.covers.elements[e].covers.iter().enumerate() {
                residual[c] -= fint[a];
            }
        }
        self.add_penalties(sys, state, &mut residual);
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
