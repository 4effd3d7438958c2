//! The elements' tangent kept per block while the block does not turn.
//!
//! Every dynamic step assembles the co-rotated tangent R K Rᵀ of each moving ME (plus the
//! geometric stiffness of its tensile stress). A block resting, or moving without turning,
//! gets the same matrix to round-off step after step: the standing dominos turned by 10⁻⁹–10⁻¹¹
//! rad per step. Blocks share no covers, so the elements' part of the tangent is a sum per
//! block: a block none of whose MEs has turned by more than `analysis.tangent_keep_angle` (nor
//! changed its tensile stress by more than that fraction of Young's modulus) since its part was
//! made keeps that part; the others have theirs zeroed and summed again in ME order, as a full
//! assembly would. The forces stay exact: the tangent only steers a step's solve and its
//! equilibrium corrections (a modified Newton iteration: Bathe, *Finite Element Procedures*,
//! 1996, §8.4.1). Where every part is kept, the step's matrix is the last one's, and the
//! factor is reused (`solver::reuse`).

use nmm3d_geom::Mat3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::corotation;
use crate::scenario::AnalysisKind;
use crate::system::System;

/// Elements whose local blocks are computed together (in parallel) before they are scattered
/// (here and in `residual`): memory for one chunk's blocks only.
pub(super) const ELEMENT_CHUNK: usize = 2048;

/// An ME's rotation and tensile stress [Pa]: what its tangent is made of.
pub(super) type Pose = (Mat3, Mat3);

/// The elements' part of the tangent and what each ME's share was made with.
pub(super) struct KeptTangent {
    /// The elements' part of the tangent, on the elements' pattern.
    elements: Vec<f64>,
    /// Per ME: the pose its share in `elements` was made at (`None`: no share yet).
    made: Vec<Option<Pose>>,
    /// Young's modulus per ME [Pa]: the scale of the tensile stress's tolerance.
    young: Vec<f64>,
}

impl KeptTangent {
    /// For a dynamic analysis with `tangent_keep_angle` > 0 whose blocks share no entry of the
    /// elements' pattern; `None` otherwise (every tangent is made afresh).
    pub(super) fn new(sys: &System) -> Option<Self> {
        let a = &sys.scenario.analysis;
        if a.kind != AnalysisKind::Dynamic || a.tangent_keep_angle <= 0.0 || shared(sys) {
            return None;
        }
        let young = (0..sys.covers.elements.len()).map(|e| corotation::young(sys, e)).collect();
        let elements = vec![0.0; sys.assembler.pattern.nnz()];
        Some(Self { elements, made: vec![None; sys.covers.elements.len()], young })
    }

    /// The elements' part of the tangent at `poses` (of the MEs `moving`, in order): the
    /// shares of the blocks with an ME beyond `angle` of its pose made afresh.
    pub(super) fn update(&mut self, sys: &System, moving: &[usize], poses: &[Pose], angle: f64) -> &[f64] {
        let mut remake = vec![false; sys.geometry.blocks.len()];
        for (&e, pose) in moving.iter().zip(poses) {
            let block = sys.covers.elements[e].block;
            remake[block] |= self.made[e].is_none_or(|was| apart(&was, pose, angle, self.young[e]));
        }
        let again: Vec<(usize, Pose)> = (moving.iter().zip(poses))
            .filter(|(&e, _)| remake[sys.covers.elements[e].block])
            .map(|(&e, p)| (e, *p))
            .collect();
        for &(e, pose) in &again {
            sys.assembler.zero(&mut self.elements, e);
            self.made[e] = Some(pose);
        }
        add_tangents(sys, &mut self.elements, &again);
        &self.elements
    }

    /// What each ME's share was made at (checkpoints).
    pub(super) fn snapshot(&self) -> TangentSnapshot {
        let (mut elements, mut rotations, mut tensions) = (Vec::new(), Vec::new(), Vec::new());
        for (e, (r, t)) in self.made.iter().enumerate().filter_map(|(e, m)| m.map(|m| (e, m))) {
            elements.push(e as u32);
            rotations.push(r);
            tensions.push(t);
        }
        TangentSnapshot { elements, rotations, tensions }
    }

    /// The kept tangent a snapshot describes: each share made again at its pose, summed in ME
    /// order — the sums it held, bit for bit.
    pub(super) fn restore(sys: &System, s: &TangentSnapshot) -> Option<Self> {
        let mut kept = Self::new(sys)?;
        let made: Vec<(usize, Pose)> =
            (s.elements.iter().zip(&s.rotations).zip(&s.tensions)).map(|((&e, &r), &t)| (e as usize, (r, t))).collect();
        for &(e, pose) in &made {
            kept.made[e] = Some(pose);
        }
        add_tangents(sys, &mut kept.elements, &made);
        Some(kept)
    }
}

/// Whether the pose `now` is beyond `angle` [rad] of `was` (rotation entries; the tensile
/// stress against `angle` × `young`).
fn apart(was: &Pose, now: &Pose, angle: f64, young: f64) -> bool {
    (now.0 - was.0).abs().max() > angle || (now.1 - was.1).abs().max() > angle * young
}

/// Whether two blocks' MEs add to one entry of the elements' pattern (covers tied across
/// blocks): then no block's share can be remade alone.
fn shared(sys: &System) -> bool {
    let mut owner = vec![usize::MAX; sys.assembler.pattern.nnz()];
    for (e, me) in sys.covers.elements.iter().enumerate() {
        for p in sys.assembler.positions(e) {
            if owner[p] != usize::MAX && owner[p] != me.block {
                return true;
            }
            owner[p] = me.block;
        }
    }
    false
}

/// `values` += the tangents of the MEs `poses` (each at its pose), in their order: computed a
/// chunk at a time in parallel and scattered in order (the same sums whatever the thread count).
fn add_tangents(sys: &System, values: &mut [f64], poses: &[(usize, Pose)]) {
    for chunk in poses.chunks(ELEMENT_CHUNK) {
        let local: Vec<Vec<f64>> =
            chunk.par_iter().map(|(e, (r, t))| sys.assembler.mapped(*e, corotation::tangent(sys, *e, r, t))).collect();
        for ((e, _), t) in chunk.iter().zip(local) {
            sys.assembler.add_mapped(values, *e, &t);
        }
    }
}

/// A [`KeptTangent`] as data: the MEs with a share and the poses it was made at.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct TangentSnapshot {
    /// MEs with a share.
    #[serde(with = "crate::packed::u32s")]
    pub elements: Vec<u32>,
    /// Their rotations.
    #[serde(with = "crate::packed::mat3s")]
    pub rotations: Vec<Mat3>,
    /// Their tensile stresses [Pa].
    #[serde(with = "crate::packed::mat3s")]
    pub tensions: Vec<Mat3>,
}
