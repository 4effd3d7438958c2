//! A contact point: its identity (block pair, entrance mode, material points on A and B), its
//! state and history, and how a newly detected point starts (touching points closed, the bond
//! and in-situ preload at the start).

use serde::{Deserialize, Serialize};

use nmm3d_geom::contact::Mode;
use nmm3d_geom::{Mat3, Vec3};

use super::facets::Candidate;
use super::point::MaterialPoint;
use crate::scenario::Joint;
use crate::system::System;

/// State of one contact point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum ContactState {
    /// Separated: no force.
    Open,
    /// Locked: normal and shear springs.
    Stick,
    /// Sliding: normal spring and Coulomb friction.
    Slide,
}

impl ContactState {
    /// Code written to the contact frames: 0 open, 1 stick, 2 slide.
    pub fn code(self) -> i64 {
        match self {
            ContactState::Open => 0,
            ContactState::Stick => 1,
            ContactState::Slide => 2,
        }
    }
}

/// One contact point between blocks A and B.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ContactRecord {
    /// Blocks (A, B).
    pub blocks: (usize, usize),
    /// Entrance mode (which features meet).
    pub mode: Mode,
    /// Material point on A.
    pub a: MaterialPoint,
    /// Material point on B.
    pub b: MaterialPoint,
    /// Unit normal from B to A.
    pub normal: Vec3,
    /// Gap at the start of the step [m] (negative: penetration), measured from `offset`.
    pub gap0: f64,
    /// Geometric gap taken as zero [m]: the gap or overlap of a point touching at the start, so
    /// that input overlapping or apart within the tolerance (coordinates rounded to a few digits)
    /// gives no impulsive force and no fall; carried to the point's successors.
    pub offset: f64,
    /// Overlap moved into `offset` when the penalty was raised (≤ 0) [m]: the raised spring
    /// keeps the force it had rather than pushing ten times harder (energy from nowhere); the
    /// geometric overlap is −(gap + raised). Carried to the point's successors.
    #[serde(default)]
    pub raised: f64,
    /// State.
    pub state: ContactState,
    /// Shear-spring extension at the start of the step (tangential) [m].
    pub shear0: Vec3,
    /// Unit slip direction of A relative to B while sliding.
    pub slip: Vec3,
    /// Joint strength at this point.
    pub strength: Strength,
    /// The point's share of the contact area [m²].
    pub area: f64,
    /// Normal penalty of this point [N/m].
    pub kn: f64,
    /// Shear penalty of this point [N/m].
    pub ks: f64,
    /// The penalties are the joint's own stiffness (Pa/m × area): physical, never raised, and
    /// the overlap they allow is the joint's closure, not a penetration error.
    pub joint_stiffness: bool,
    /// In-situ traction on A times the area [N] (zero once the point has opened).
    pub preload: Vec3,
    /// Gap after the last solve [m].
    pub gap: f64,
    /// Relative displacement increment of A with respect to B after the last solve [m].
    pub rel: Vec3,
    /// Force on A after the last solve [N].
    pub force: Vec3,
    /// Force on A the last solve applied (the spring it was solved with, linearised about the
    /// iterate before it) [N]: what the step's end acceleration carries (energy accounts).
    #[serde(default = "no_force")]
    pub applied: Vec3,
    /// Times the point closed in this step's open–close iterations.
    pub reclosed: u32,
    /// The point opened in this step's open–close iterations.
    pub opened: bool,
    /// Friction limit tan φ N + c applied while sliding [N].
    pub limit: f64,
    /// The point's dashpot in this step (`contact.damping_ratio`).
    #[serde(default)]
    pub damper: Damper,
}

impl ContactRecord {
    /// The point opened or closed during this step's open–close iterations (an impact's or a
    /// release's point).
    pub fn event(&self) -> bool {
        self.opened || self.reclosed > 0
    }
}

/// A point's dashpot in the current step (`super::damping`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Damper {
    /// Stiffness-proportional factor of the pair, c = 2ξ √(m/K) where the step resolves the
    /// bounce [s] (0: no damping).
    pub c: f64,
    /// γ/(βΔt): the end velocity per unit increment [1/s].
    pub rate: f64,
    /// The end velocity of A relative to B at zero increment, (1 − γ/β) v₀ + Δt (1 − γ/(2β)) a₀
    /// [m/s].
    pub lag: Vec3,
    /// Damper force on A the last solve applied [N].
    pub end: Vec3,
}

/// Strength of a contact point: tan φ, and the bond (cohesion and tensile forces) it still has.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Strength {
    /// tan φ.
    pub tan_phi: f64,
    /// Cohesion × area [N] (0 once broken).
    pub cohesion: f64,
    /// Tensile strength × area [N] (0 once broken).
    pub tension: f64,
}

impl Strength {
    /// The strength after the bond is lost: friction only.
    pub(super) fn broken(self) -> Self {
        Self { cohesion: 0.0, tension: 0.0, ..self }
    }
}

/// Penalties and tolerances of the contact algorithm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactParams {
    /// Normal penalty of a point carrying one cover cell's face of area (size²), and of a point
    /// contact [N/m].
    pub kn: f64,
    /// Shear penalty, likewise [N/m].
    pub ks: f64,
    /// Cover size [m]: the area unit of the penalties.
    pub size: f64,
    /// Detection margin [m].
    pub margin: f64,
    /// Warning skin [m]: the candidate list is rebuilt when a vertex has moved half of it.
    pub skin: f64,
    /// Support tolerance and transfer distance [m].
    pub tolerance: f64,
    /// Half-width of the open–close hysteresis on the gap [m].
    pub band: f64,
    /// Overlap at which a point that opened during the step's iterations closes again [m].
    pub reclose: f64,
    /// Closings within one step's iterations after which a point stays open.
    pub max_reclose: u32,
    /// Settled change of the friction forces, relative to the largest limit [-].
    pub slip_turn: f64,
    /// Gap below which a new point is touching [m].
    pub touching: f64,
    /// Smallest stiffness share of a point of an area contact [-].
    pub min_share: f64,
    /// Distance under which facet-overlay corners are one point [m].
    pub merge: f64,
    /// Contact dashpots: fraction of critical damping of a block pair's normal mode [-].
    #[serde(default)]
    pub damping_ratio: f64,
    /// Cosine of `contact.turned_face_angle`: a facet reaching out of the band that faces the
    /// plane within it takes part with its part inside (1: off) [-].
    #[serde(default = "no_turned_face")]
    pub turned_face: f64,
    /// `contact.carry_joint_force` (false in a run that predates it).
    #[serde(default)]
    pub carry_joint_force: bool,
    /// `contact.static_carry_slack` [-].
    #[serde(default = "static_carry_slack")]
    pub static_slack: f64,
}

/// `ContactParams::static_slack` of a run that predates it: the default.
fn static_carry_slack() -> f64 {
    crate::scenario::ContactSpec::default().static_carry_slack
}

/// `ContactParams::turned_face` of a run that predates it: off.
fn no_turned_face() -> f64 {
    1.0
}

impl ContactRecord {
    /// A point detected now, before any transfer: touching points are closed (stuck), and at
    /// the start take their gap as zero level, the joint's bond and the in-situ preload.
    pub(super) fn fresh(
        sys: &System,
        q: Candidate,
        blocks: (usize, usize),
        normal: Vec3,
        joint: Option<&Joint>,
        initial: bool,
        p: &ContactParams,
    ) -> Self {
        // Touching counts as closed: blocks placed on each other start in contact.
        let touching = q.gap <= p.touching;
        let bonded = initial && touching;
        let area = q.area;
        let strength = |f: fn(&Joint) -> f64| if bonded { joint.map_or(0.0, f) * area } else { 0.0 };
        let (kn, ks, joint_stiffness) = match joint.and_then(Joint::stiffness) {
            // Per unit area × the point's area (a point contact: one cover cell's face).
            Some((kn, ks)) => {
                let a = if area > 0.0 { area } else { p.size * p.size };
                (kn * a, ks * a, true)
            }
            None => (p.kn * stiffness_share(area, p), p.ks * stiffness_share(area, p), false),
        };
        Self {
            blocks,
            mode: q.mode,
            normal,
            gap0: q.gap,
            offset: if bonded { q.gap } else { 0.0 },
            raised: 0.0,
            state: if touching { ContactState::Stick } else { ContactState::Open },
            shear0: Vec3::zeros(),
            slip: Vec3::zeros(),
            strength: Strength {
                tan_phi: joint.map_or(0.0, |j| j.friction_angle.to_radians().tan()),
                cohesion: strength(|j| j.cohesion),
                tension: strength(|j| j.tensile_strength),
            },
            area,
            kn,
            ks,
            joint_stiffness,
            preload: if bonded { in_situ_traction(sys, &q.on_a, &normal) * area } else { Vec3::zeros() },
            gap: q.gap,
            rel: Vec3::zeros(),
            force: Vec3::zeros(),
            applied: Vec3::zeros(),
            reclosed: 0,
            opened: false,
            limit: 0.0,
            damper: Damper::default(),
            a: q.a,
            b: q.b,
        }
    }

    /// The pair of MEs the point couples, lower first.
    pub fn element_pair(&self) -> (usize, usize) {
        (self.a.element.min(self.b.element), self.a.element.max(self.b.element))
    }

    /// Compressive normal force on A after the last solve, N = n·P − k_n g, at least 0 [N].
    pub fn normal_force(&self) -> f64 {
        self.normal_force_at(self.gap)
    }

    /// The same at gap `gap` [m] [N].
    pub fn normal_force_at(&self, gap: f64) -> f64 {
        (self.normal.dot(&self.preload) - self.kn * gap).max(0.0)
    }
}

fn no_force() -> Vec3 {
    Vec3::zeros()
}

/// Tangential projector I − n nᵀ.
pub(super) fn tangential(n: &Vec3) -> Mat3 {
    Mat3::identity() - n * n.transpose()
}

/// A point's penalties relative to `ContactParams::kn`, `ks`: its share of the contact area
/// over one cover cell's face (size²), so a face carries the same stiffness per area however
/// finely its points fall (at least `min_share`); a point contact (no area) takes them whole.
fn stiffness_share(area: f64, p: &ContactParams) -> f64 {
    if area > 0.0 {
        (area / (p.size * p.size)).max(p.min_share)
    } else {
        1.0
    }
}

/// In-situ traction on A's surface (outward normal −n) at `x`: σ₀(x)·(−n) [Pa].
fn in_situ_traction(sys: &System, x: &Vec3, n: &Vec3) -> Vec3 {
    let Some(s) = &sys.scenario.in_situ_stress else { return Vec3::zeros() };
    let dz = x.z - s.reference_z;
    let c: Vec<f64> = (0..6).map(|k| s.stress[k] + s.gradient[k] * dz).collect();
    // Voigt order xx, yy, zz, xy, yz, zx.
    let sigma = Mat3::new(c[0], c[3], c[5], c[3], c[1], c[4], c[5], c[4], c[2]);
    -(sigma * n)
}

/// A point on a horizontal joint (normal +z from B to A), k_n = k_s = 1e9 N/m, tan φ = 0.5, no
/// bond, at rest: the starting row of the state-rule tables.
#[cfg(test)]
pub(super) fn test_point(state: ContactState, gap: f64) -> ContactRecord {
    let point = |z: f64| MaterialPoint { element: 0, weights: Vec::new(), reference: Vec3::new(0.0, 0.0, z) };
    ContactRecord {
        blocks: (1, 0),
        mode: Mode::VertexOfA,
        a: point(0.0),
        b: point(0.0),
        normal: Vec3::z(),
        gap0: gap,
        offset: 0.0,
        raised: 0.0,
        state,
        shear0: Vec3::zeros(),
        slip: Vec3::zeros(),
        strength: Strength { tan_phi: 0.5, cohesion: 0.0, tension: 0.0 },
        area: 0.0,
        kn: 1e9,
        ks: 1e9,
        joint_stiffness: false,
        preload: Vec3::zeros(),
        gap,
        rel: Vec3::zeros(),
        force: Vec3::zeros(),
        applied: Vec3::zeros(),
        reclosed: 0,
        opened: false,
        limit: 0.0,
        damper: Damper::default(),
    }
}

#[cfg(test)]
impl ContactParams {
    /// The parameters of a 0.5 m cover with the default scenario keys, penalties 1e9 N/m.
    pub(super) fn for_test() -> Self {
        let size = 0.5;
        let tolerance = 1e-3 * size;
        Self {
            kn: 1e9,
            ks: 1e9,
            size,
            margin: 2.0 * tolerance,
            skin: 4.0 * tolerance,
            tolerance,
            band: 1e-10 * size,
            reclose: 1e-3 * tolerance,
            max_reclose: 2,
            slip_turn: 0.017_45,
            turned_face: 1.0,
            carry_joint_force: false,
            static_slack: 0.05,
            touching: 1e-3 * tolerance,
            min_share: 0.05,
            merge: 10.0 * tolerance,
            damping_ratio: 0.0,
        }
    }
}
