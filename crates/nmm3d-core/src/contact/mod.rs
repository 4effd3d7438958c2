//! Contact between blocks: detection on the current geometry, transfer of contact state,
//! penalty springs, Coulomb friction and the open–close state rules (thesis Part 3; DDA,
//! Shi 1988; the state rules of ntdda `df22`).
//!
//! Per step the contact set is re-detected on the current geometry (one plane per pair of
//! pieces, `nmm3d_geom::contact`); a new point inherits state and shear history from the
//! previous step's point of the same block pair nearest to it (within the transfer distance),
//! else starts locked with zero shear. Within the step the open–close iteration solves with the
//! springs of the current states and updates the states until none changes:
//!
//! | state | force | leaves when |
//! |---|---|---|
//! | open | none | the gap closes (→ stick) |
//! | stick | normal spring k_n, shear spring k_s | tension (→ open); shear force > N tan φ + c A (→ slide) |
//! | slide | normal spring, friction N tan φ against the slip | tension (→ open); the slip reverses (→ stick) |

pub mod surface;

use nmm3d_geom::contact::{detect, DetectParams};
use nmm3d_geom::{Aabb, Mat3, Vec3};

use crate::state::State;
use crate::system::System;
use surface::{ContactPiece, MaterialPoint};

/// State of one contact point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactState {
    /// Separated: no force.
    Open,
    /// Locked: normal and shear springs.
    Stick,
    /// Sliding: normal spring and Coulomb friction.
    Slide,
}

/// One contact point between blocks A and B.
#[derive(Debug, Clone)]
pub struct ContactRecord {
    /// Blocks (A, B).
    pub blocks: (usize, usize),
    /// Material point on A.
    pub a: MaterialPoint,
    /// Material point on B.
    pub b: MaterialPoint,
    /// Unit normal from B to A.
    pub normal: Vec3,
    /// Gap at the start of the step [m] (negative: penetration).
    pub gap0: f64,
    /// State.
    pub state: ContactState,
    /// Shear-spring extension at the start of the step (tangential) [m].
    pub shear0: Vec3,
    /// Unit slip direction of A relative to B while sliding.
    pub slip: Vec3,
    /// tan φ of the joint.
    pub tan_phi: f64,
    /// Gap after the last solve [m].
    pub gap: f64,
    /// Relative displacement increment of A with respect to B after the last solve [m].
    pub rel: Vec3,
}

/// Penalties and tolerances of the contact algorithm.
#[derive(Debug, Clone, Copy)]
pub struct ContactParams {
    /// Normal penalty [N/m].
    pub kn: f64,
    /// Shear penalty [N/m].
    pub ks: f64,
    /// Detection margin [m].
    pub margin: f64,
    /// Support tolerance and transfer distance [m].
    pub tolerance: f64,
}

/// All contact surfaces and the current contact points.
pub struct ContactSet {
    pieces: Vec<ContactPiece>,
    /// Current contact points.
    pub records: Vec<ContactRecord>,
    /// Penalties and tolerances.
    pub params: ContactParams,
}

impl ContactSet {
    /// Contact surfaces of every block (`None` with fewer than two blocks).
    pub fn new(sys: &System, params: ContactParams) -> Option<Self> {
        if sys.geometry.blocks.len() < 2 {
            return None;
        }
        let pieces = sys
            .geometry
            .blocks
            .iter()
            .enumerate()
            .flat_map(|(b, block)| block.pieces.iter().filter_map(move |p| ContactPiece::new(sys, b, p)))
            .collect();
        Some(Self { pieces, records: Vec::new(), params })
    }

    /// Re-detect on the current geometry; transfer state and shear from the previous points.
    pub fn detect(&mut self, sys: &System, state: &State) {
        let current: Vec<_> = self.pieces.iter().map(|p| p.current(sys, state)).collect();
        let boxes: Vec<Aabb> = current.iter().map(|c| c.aabb()).collect();
        let m = Vec3::repeat(self.params.margin);
        let dp = DetectParams { margin: self.params.margin, support_tolerance: self.params.tolerance, thin_distance: 10.0 * self.params.tolerance };
        let previous = std::mem::take(&mut self.records);
        for i in 0..self.pieces.len() {
            for j in 0..self.pieces.len() {
                let (pa, pb) = (&self.pieces[i], &self.pieces[j]);
                // Each pair once: A is the piece of the higher block index.
                if pa.block <= pb.block || both_fixed(sys, pa.block, pb.block) {
                    continue;
                }
                let grown = Aabb { min: boxes[i].min - m, max: boxes[i].max + m };
                if !grown.overlaps(&boxes[j]) {
                    continue;
                }
                let Some(c) = detect(&current[i], &current[j], &dp) else { continue };
                for p in c.points {
                    let xa = pa.reference_of(&current[i], &p.on_a);
                    let xb = pb.reference_of(&current[j], &p.on_b);
                    let (Some(a), Some(b)) = (MaterialPoint::new(sys, pa.block, xa), MaterialPoint::new(sys, pb.block, xb)) else { continue };
                    let mut r = ContactRecord {
                        blocks: (pa.block, pb.block),
                        a,
                        b,
                        normal: c.normal,
                        gap0: p.gap,
                        // Touching counts as closed: blocks placed on each other start in contact.
                        state: if p.gap <= TOUCHING * self.params.tolerance { ContactState::Stick } else { ContactState::Open },
                        shear0: Vec3::zeros(),
                        slip: Vec3::zeros(),
                        tan_phi: friction(sys, pa.block, pb.block),
                        gap: p.gap,
                        rel: Vec3::zeros(),
                    };
                    if let Some(old) = previous
                        .iter()
                        .filter(|o| o.blocks == r.blocks && (o.a.reference - r.a.reference).norm() < 10.0 * self.params.tolerance)
                        .min_by(|x, y| (x.a.reference - r.a.reference).norm().total_cmp(&(y.a.reference - r.a.reference).norm()))
                    {
                        if old.state != ContactState::Open {
                            r.state = if r.gap0 < 0.0 { old.state } else { ContactState::Open };
                            let t = tangential(&r.normal);
                            r.shear0 = t * old.shear0;
                            r.slip = old.slip;
                        }
                    }
                    self.records.push(r);
                }
            }
        }
    }

    /// Covers coupled by each contact (A's ME then B's ME).
    pub fn cliques(&self, sys: &System) -> Vec<Vec<usize>> {
        self.records.iter().map(|r| pair_clique(sys, r.a.element, r.b.element)).collect()
    }

    /// Local matrix (row-major, (3m)²) and force vector (3m) of record `k` in its clique order.
    pub fn local(&self, sys: &System, k: usize) -> (Vec<f64>, Vec<f64>) {
        let r = &self.records[k];
        let (na, nb) = (sys.covers.elements[r.a.element].covers.len(), sys.covers.elements[r.b.element].covers.len());
        let m = na + nb;
        let w: Vec<f64> = r.a.weights.iter().copied().chain(r.b.weights.iter().map(|x| -x)).collect();
        let mut mat = vec![0.0; 9 * m * m];
        let mut f = vec![0.0; 3 * m];
        if r.state == ContactState::Open {
            return (mat, f);
        }
        let (kn, ks) = (self.params.kn, self.params.ks);
        let n = r.normal;
        let t = tangential(&n);
        let mut block = kn * n * n.transpose();
        // Force on A (B gets the opposite through the negative weights).
        let mut force = -kn * r.gap0 * n;
        match r.state {
            ContactState::Stick => {
                block += ks * t;
                force -= ks * r.shear0;
            }
            ContactState::Slide => {
                let normal_force = -kn * r.gap.min(0.0);
                force -= r.tan_phi * normal_force * r.slip;
            }
            ContactState::Open => {}
        }
        for a in 0..m {
            for i in 0..3 {
                f[3 * a + i] = w[a] * force[i];
            }
            for b in 0..m {
                for i in 0..3 {
                    for j in 0..3 {
                        mat[(3 * a + i) * 3 * m + 3 * b + j] = w[a] * w[b] * block[(i, j)];
                    }
                }
            }
        }
        (mat, f)
    }

    /// Update every point from the solved increments `d`; returns how many changed state.
    pub fn update_states(&mut self, sys: &System, d: &[Vec3]) -> usize {
        let (kn, ks) = (self.params.kn, self.params.ks);
        let mut changed = 0;
        for r in &mut self.records {
            let inc = |mp: &MaterialPoint| -> Vec3 { sys.covers.elements[mp.element].covers.iter().zip(&mp.weights).map(|(&c, w)| *w * d[c]).sum() };
            r.rel = inc(&r.a) - inc(&r.b);
            r.gap = r.gap0 + r.normal.dot(&r.rel);
            let t = tangential(&r.normal);
            let shear = r.shear0 + t * r.rel;
            let normal_force = -kn * r.gap;
            let new = match r.state {
                _ if r.gap > 0.0 => ContactState::Open,
                ContactState::Open => ContactState::Stick,
                ContactState::Stick if ks * shear.norm() > r.tan_phi * normal_force => ContactState::Slide,
                ContactState::Slide if (t * r.rel).dot(&r.slip) < 0.0 => ContactState::Stick,
                s => s,
            };
            if new == ContactState::Slide {
                let dir = if r.state == ContactState::Stick { shear } else { t * r.rel };
                if dir.norm() > 0.0 {
                    r.slip = dir.normalize();
                }
            }
            if new != r.state {
                changed += 1;
                r.state = new;
            }
        }
        changed
    }

    /// After an accepted step: carry the shear-spring extension (zero unless stuck).
    pub fn accept(&mut self) {
        for r in &mut self.records {
            let t = tangential(&r.normal);
            r.shear0 = if r.state == ContactState::Stick { r.shear0 + t * r.rel } else { Vec3::zeros() };
        }
    }

    /// Largest penetration among closed points [m].
    pub fn max_penetration(&self) -> f64 {
        self.records.iter().filter(|r| r.state != ContactState::Open).map(|r| -r.gap).fold(0.0, f64::max)
    }
}

/// A new point whose gap is below this fraction of the support tolerance is touching (closed):
/// round-off must not turn blocks placed on each other into a fall and an impact.
const TOUCHING: f64 = 1e-6;

/// The covers of two MEs, first then second (the clique a contact between them couples).
pub fn pair_clique(sys: &System, a: usize, b: usize) -> Vec<usize> {
    [sys.covers.elements[a].covers.as_slice(), sys.covers.elements[b].covers.as_slice()].concat()
}

/// Tangential projector I − n nᵀ.
fn tangential(n: &Vec3) -> Mat3 {
    Mat3::identity() - n * n.transpose()
}

fn both_fixed(sys: &System, a: usize, b: usize) -> bool {
    sys.geometry.blocks[a].fixed && sys.geometry.blocks[b].fixed
}

/// tan φ between two blocks: an interface naming both bodies, else A's body joint, else B's.
fn friction(sys: &System, a: usize, b: usize) -> f64 {
    let s = &sys.scenario;
    let (ba, bb) = (&s.body[sys.geometry.blocks[a].body].name, &s.body[sys.geometry.blocks[b].body].name);
    let joint = s
        .interface
        .iter()
        .find(|i| (&i.bodies[0] == ba && &i.bodies[1] == bb) || (&i.bodies[0] == bb && &i.bodies[1] == ba))
        .map(|i| i.joint.clone())
        .or_else(|| s.body[sys.geometry.blocks[a].body].joint.clone())
        .or_else(|| s.body[sys.geometry.blocks[b].body].joint.clone());
    joint.and_then(|j| s.joint.iter().find(|x| x.name == j)).map_or(0.0, |j| j.friction_angle.to_radians().tan())
}
