//! The tangent and the unbalanced force at the current state: the co-rotated elements, the
//! penalty constraints and the loads (thesis §3.3).

use nmm3d_geom::{Mat3, Vec3};
use rayon::prelude::*;

use super::corotation;
use super::kept_tangent::{KeptTangent, Pose, ELEMENT_CHUNK};
use super::stepper::Stepper;
use crate::state::Motion;
use crate::system::System;

impl Stepper {
    /// Tangent into `self.tangent`, unbalanced force per cover returned, the loads into
    /// `self.loads` (the water pressure at the rotations of the last step); updates rotations.
    /// `keep`: blocks that have not turned keep their tangent ([`KeptTangent`]; dynamic steps).
    pub fn assemble(&mut self, sys: &System, state: &mut Motion, keep: bool) -> Vec<Vec3> {
        self.start_forces(sys, state, Some(keep))
    }

    /// The unbalanced force at the start of a step (the loads into `self.loads`, the rotations
    /// updated), the tangent into `self.tangent` if `tangent` (`Some(keep)`, see
    /// [`Self::assemble`]).
    pub(super) fn start_forces(&mut self, sys: &System, state: &mut Motion, tangent: Option<bool>) -> Vec<Vec3> {
        let mut residual = sys.external.clone();
        super::water::add_water(sys, state, &mut residual);
        self.loads.clone_from(&residual);
        let angle = sys.scenario.analysis.tangent_keep_angle;
        let tangent = tangent.map(|keep| Tangent {
            values: &mut self.tangent,
            kept: self.kept.as_mut().map(|k| (k, if keep { angle } else { 0.0 })),
        });
        for (e, r) in subtract_inner_forces(sys, state, &mut residual, tangent) {
            state.rotations[e] = r;
        }
        residual
    }

    /// [`Self::assemble`], or what `initialize` assembled if the displacements are still the
    /// ones it saw (a run's first step: one element loop fewer).
    pub(super) fn assembled(&mut self, sys: &System, state: &mut Motion, keep: bool) -> Vec<Vec3> {
        match self.fresh.take() {
            Some((u, residual)) if u == state.u => residual,
            _ => self.assemble(sys, state, keep),
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

/// Where the tangent goes: its values, and the kept elements' part with the angle beyond which
/// a block's part is made afresh (0: every part whose MEs moved at all).
struct Tangent<'a> {
    values: &'a mut Vec<f64>,
    kept: Option<(&'a mut KeptTangent, f64)>,
}

/// Subtract the forces of the co-rotated elements, the penalty constraints and the bolts at
/// `state` from `residual`, their stiffness into `tangent` if given; the elements' rotations
/// returned.
fn subtract_inner_forces(
    sys: &System,
    state: &Motion,
    residual: &mut [Vec3],
    tangent: Option<Tangent>,
) -> Vec<(usize, Mat3)> {
    // Fixed blocks' covers cannot move; their forces would go nowhere.
    let moving: Vec<usize> =
        (0..sys.covers.elements.len()).filter(|&e| !sys.geometry.blocks[sys.covers.elements[e].block].fixed).collect();
    let mut rotations = Vec::with_capacity(moving.len());
    let (with_tangent, whole) = (tangent.is_some(), tangent.as_ref().is_some_and(|t| t.kept.is_none()));
    let (mut values, mut kept) = match tangent {
        Some(Tangent { values, kept }) => (Some(values), kept),
        None => (None, None),
    };
    if whole {
        values.iter_mut().for_each(|v| v.fill(0.0));
    }
    let mut poses: Vec<Pose> = Vec::with_capacity(if kept.is_some() { moving.len() } else { 0 });
    // The local blocks of a chunk in parallel, scattered in element order: the same sums in the
    // same order whatever the thread count (bit-identical results), and memory for one chunk's
    // blocks only.
    for chunk in moving.chunks(ELEMENT_CHUNK) {
        let local: Vec<Local> = chunk.par_iter().map(|&e| local(sys, state, e, (with_tangent, whole))).collect();
        for (&e, (r, fint, tension, t)) in chunk.iter().zip(local) {
            rotations.push((e, r));
            match values.as_deref_mut() {
                Some(values) if whole => sys.assembler.add(values, e, &t),
                Some(_) => poses.push((r, tension)),
                None => {}
            }
            for (a, &c) in sys.covers.elements[e].covers.iter().enumerate() {
                residual[c] -= fint[a];
            }
        }
    }
    if let (Some(values), Some((kept, angle))) = (values.as_deref_mut(), kept.as_mut()) {
        values.copy_from_slice(kept.update(sys, &moving, &poses, *angle));
    }
    add_penalties(sys, state, residual, values.as_deref_mut());
    super::bolts::add_bolts(sys, state, residual, values);
    rotations
}

/// An ME's rotation, internal force, tensile stress and tangent (the last two if asked for).
type Local = (Mat3, Vec<Vec3>, Mat3, Vec<f64>);

/// [`Local`] of ME `e`: the tensile stress `with_tangent`, the tangent too if `whole` (not kept).
fn local(sys: &System, state: &Motion, e: usize, (with_tangent, whole): (bool, bool)) -> Local {
    let f = corotation::deformation_gradient(sys, state, e);
    let r = corotation::rotation(&f, &state.rotations[e]);
    if !with_tangent {
        return (r, corotation::internal_force(sys, state, e, &r), Mat3::zeros(), Vec::new());
    }
    let (fint, tension) = corotation::internal_force_and_tension(sys, state, e, &r);
    let t = if whole { corotation::tangent(sys, e, &r, &tension) } else { Vec::new() };
    (r, fint, tension, t)
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
