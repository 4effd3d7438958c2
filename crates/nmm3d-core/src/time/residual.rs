//! The tangent and the unbalanced force at the current state: the co-rotated elements, the
//! penalty constraints and the loads (thesis §3.3).

use nmm3d_geom::{Mat3, Vec3};
use rayon::prelude::*;

use super::corotation;
use super::end_forces::{ElementForces, EndForces};
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
        let known = self.end_forces.take().filter(|k| k.u == state.u && k.guesses == state.rotations);
        for (e, r, _) in subtract_inner_forces(sys, state, &mut residual, tangent, known.map(|k| k.elements)) {
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
    /// without a tangent: where a trial's end stands (see `super::equilibrate`). Its elements'
    /// rotations and forces are kept for the next step's start ([`EndForces`]).
    pub(super) fn residual_at(&mut self, sys: &System, state: &Motion) -> Vec<Vec3> {
        let mut residual = self.loads.clone();
        let elements = subtract_inner_forces(sys, state, &mut residual, None, None);
        self.end_forces = Some(EndForces { u: state.u.clone(), guesses: state.rotations.clone(), elements });
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
/// and forces returned. `known`: the elements' rotations and forces at `state`, if measured
/// already (the same MEs in order; otherwise ignored).
fn subtract_inner_forces(
    sys: &System,
    state: &Motion,
    residual: &mut [Vec3],
    tangent: Option<Tangent>,
    known: Option<Vec<ElementForces>>,
) -> Vec<ElementForces> {
    // Fixed blocks' covers cannot move; their forces would go nowhere.
    let moving: Vec<usize> =
        (0..sys.covers.elements.len()).filter(|&e| !sys.geometry.blocks[sys.covers.elements[e].block].fixed).collect();
    let mut known = known.filter(|k| k.iter().map(|x| x.0).eq(moving.iter().copied())).map(Vec::into_iter);
    let mut forces = Vec::with_capacity(moving.len());
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
        let given: Vec<Option<ElementForces>> = match known.as_mut() {
            Some(k) => k.by_ref().take(chunk.len()).map(Some).collect(),
            None => (0..chunk.len()).map(|_| None).collect(),
        };
        let local: Vec<Local> = (chunk.par_iter().zip(given))
            .map(|(&e, known)| local(sys, state, e, (with_tangent, whole), known))
            .collect();
        for (&e, (r, fint, tension, t)) in chunk.iter().zip(local) {
            match values.as_deref_mut() {
                Some(values) if whole => sys.assembler.add_mapped(values, e, &t),
                Some(_) => poses.push((r, tension)),
                None => {}
            }
            for (a, &c) in sys.covers.elements[e].covers.iter().enumerate() {
                residual[c] -= fint[a];
            }
            forces.push((e, r, fint));
        }
    }
    if let (Some(values), Some((kept, angle))) = (values.as_deref_mut(), kept.as_mut()) {
        values.copy_from_slice(kept.update(sys, &moving, &poses, *angle));
    }
    add_penalties(sys, state, residual, values.as_deref_mut());
    super::bolts::add_bolts(sys, state, residual, values);
    forces
}

/// An ME's rotation, internal force, tensile stress and tangent (the last two if asked for).
type Local = (Mat3, Vec<Vec3>, Mat3, Vec<f64>);

/// [`Local`] of ME `e`: the tensile stress `with_tangent`, the tangent too if `whole` (not kept;
/// as the assembler scatters it); its rotation and force taken from `known` if given.
fn local(
    sys: &System,
    state: &Motion,
    e: usize,
    (with_tangent, whole): (bool, bool),
    known: Option<ElementForces>,
) -> Local {
    let (r, fint, tension) = match known {
        Some((_, r, fint)) => (r, fint, with_tangent.then(|| corotation::tension(sys, state, e, &r))),
        None => {
            let r = corotation::rotation(&corotation::deformation_gradient(sys, state, e), &state.rotations[e]);
            match with_tangent {
                true => {
                    let (fint, tension) = corotation::internal_force_and_tension(sys, state, e, &r);
                    (r, fint, Some(tension))
                }
                false => (r, corotation::internal_force(sys, state, e, &r), None),
            }
        }
    };
    let t = match (whole, &tension) {
        (true, Some(tension)) => sys.assembler.mapped(e, corotation::tangent(sys, e, &r, tension)),
        _ => Vec::new(),
    };
    (r, fint, tension.unwrap_or_else(Mat3::zeros), t)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::time::State;

    /// A slab tumbling onto a fixed floor: every step turns its elements.
    const TUMBLING: &str = r#"
[analysis]
duration = 0.06
dt = 0.002
gravity = [0.0, 0.0, -9.81]
[cover]
size = 0.1
[[material]]
name = "rock"
density = 2500.0
young = 1e9
poisson = 0.25
[[joint]]
name = "j"
friction_angle = 30.0
[[body]]
name = "floor"
material = "rock"
fixed = true
shape = { box = { min = [-0.5, -0.5, -0.1], max = [1.0, 0.5, 0.0] } }
[[body]]
name = "slab"
material = "rock"
joint = "j"
velocity = [0.5, 0.0, -0.2]
angular_velocity = [0.0, 3.0, 1.0]
shape = { box = { min = [0.0, -0.15, 0.01], max = [0.4, 0.15, 0.11] } }
"#;

    /// The state after 30 steps, and how many steps started where the last one's equilibrium
    /// measured the elements' forces; `keep`: the stepper may take those forces.
    fn tumble(keep: bool) -> (State, usize) {
        let scenario = crate::input::from_toml_str(TUMBLING, "<test>", &[]).unwrap();
        let sys = System::build(scenario, "<test>").unwrap();
        let mut state = State::initial(&sys);
        let mut stepper = Stepper::new(&sys, &mut state, "<test>").unwrap();
        stepper.initialize(&sys, &mut state).unwrap();
        let mut ready = 0;
        for _ in 0..30 {
            let m = &state.motion;
            ready += usize::from(stepper.end_forces.as_ref().is_some_and(|k| k.u == m.u && k.guesses == m.rotations));
            if !keep {
                stepper.end_forces = None;
            }
            stepper.step(&sys, &mut state, 1e30).unwrap();
        }
        (state, ready)
    }

    #[test]
    fn a_step_starts_from_the_forces_the_last_one_ended_with_bit_for_bit() {
        let (kept, ready) = tumble(true);
        let (afresh, _) = tumble(false);
        assert!(ready >= 25, "{ready} of 30 steps started where the last equilibrium measured the forces");
        let (a, b) = (&kept.motion, &afresh.motion);
        assert!(a.u == b.u && a.v == b.v && a.rotations == b.rotations, "the runs differ");
    }
}
