//! The scenario file, version 1 (`docs/scenario.md`): typed, with defaults and units.
//! Unknown keys are rejected. Semantic checks live in `validate.rs`.

use serde::{Deserialize, Serialize};

/// A whole scenario.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Name and description.
    #[serde(default)]
    pub scenario: Meta,
    /// Analysis controls.
    #[serde(default)]
    pub analysis: Analysis,
    /// The mathematical cover.
    #[serde(default)]
    pub cover: CoverSpec,
    /// Contact penalties.
    #[serde(default)]
    pub contact: ContactSpec,
    /// Block cutting controls (addition to v1).
    #[serde(default)]
    pub cutting: CuttingSpec,
    /// Materials (unique names).
    #[serde(default)]
    pub material: Vec<Material>,
    /// Joint strengths (unique names).
    #[serde(default)]
    pub joint: Vec<Joint>,
    /// Bodies (unique names).
    #[serde(default)]
    pub body: Vec<Body>,
    /// Joint sets (cutting).
    #[serde(default)]
    pub joint_set: Vec<JointSet>,
    /// Single joints (cutting).
    #[serde(default)]
    pub joint_plane: Vec<JointPlane>,
    /// Excavations.
    #[serde(default)]
    pub excavation: Vec<Excavation>,
    /// Joint between two bodies.
    #[serde(default)]
    pub interface: Vec<Interface>,
    /// Penalty constraints on boundary vertices in a region.
    #[serde(default)]
    pub constraint: Vec<Constraint>,
    /// Penalty constraints at points.
    #[serde(default)]
    pub fixed_point: Vec<FixedPoint>,
    /// Dead point loads.
    #[serde(default)]
    pub point_load: Vec<PointLoad>,
    /// Dead tractions on block boundary faces in a region (addition to v1).
    #[serde(default)]
    pub surface_load: Vec<SurfaceLoad>,
    /// Initial stress.
    #[serde(default)]
    pub in_situ_stress: Option<InSituStress>,
    /// Monitored quantities.
    #[serde(default)]
    pub monitor: Vec<Monitor>,
    /// Reference values the monitored quantities should reach (addition to v1).
    #[serde(default)]
    pub expect: Vec<Expect>,
    /// A study over many runs (addition to v1): kept as given here and validated and run by the
    /// Python package (`nmm3d study`, `docs/studies.md`); a single run ignores it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub study: Option<toml::Table>,
}

/// `[scenario]`.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Meta {
    /// Short name.
    #[serde(default)]
    pub name: String,
    /// Free text.
    #[serde(default)]
    pub description: String,
}

/// Dynamic or static analysis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AnalysisKind {
    /// Inertia kept; velocities carried between steps.
    #[default]
    Dynamic,
    /// Velocities reset every step; runs to equilibrium.
    Static,
}

/// Time integration scheme.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Integrator {
    /// DDA scheme: Newmark β = ½, γ = 1 (first order, dissipative, exact for constant acceleration).
    #[default]
    Dda,
    /// Newmark with `newmark_beta`, `newmark_gamma` (default ¼, ½: trapezoidal, no numerical damping).
    Newmark,
}

/// `[analysis]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Analysis {
    /// "dynamic" | "static".
    pub kind: AnalysisKind,
    /// Simulated time to reach [s].
    pub duration: f64,
    /// Hard cap on accepted steps.
    pub max_steps: u64,
    /// Maximum (and initial) time step [s].
    pub dt: f64,
    /// Largest step displacement / half the model size (DDA g2) [-].
    pub max_displacement_ratio: f64,
    /// Gravity [m/s²].
    pub gravity: [f64; 3],
    /// Simulated time between saved frames [s]; 0 = only first and last.
    pub output_interval: f64,
    /// Simulated time between history rows [s]; absent = every accepted step.
    pub history_interval: Option<f64>,
    /// Time integration scheme.
    pub integrator: Integrator,
    /// Newmark β (only with `integrator = "newmark"`).
    pub newmark_beta: f64,
    /// Newmark γ (only with `integrator = "newmark"`).
    pub newmark_gamma: f64,
    /// Static runs stop when the unbalanced force ≤ this × the largest applied force [-].
    pub equilibrium_tolerance: f64,
    /// Penalty stiffness of constraints and fixed points [N/m], or "auto".
    pub penalty_stiffness: Stiffness,
    /// "auto" penalty = this factor × largest Young's modulus × cover size [-].
    pub penalty_factor: f64,
    /// Smallest time step allowed by step cuts, as a fraction of `dt` [-].
    pub min_dt_ratio: f64,
    /// Largest growth of the time step between accepted steps [-].
    pub max_dt_growth: f64,
    /// Step displacement ratio aimed at when the step is resized [-].
    pub target_displacement_ratio: f64,
    /// A run whose displacement ratio exceeds this after the smallest step is diverging [-].
    pub divergence_ratio: f64,
    /// Fill-reducing ordering of the sparse factorisation.
    pub ordering: Ordering,
    /// Open–close iterations per step before the step is cut.
    pub max_open_close: u32,
    /// Factor applied to Δt when the open–close iteration does not settle [-].
    pub open_close_cut: f64,
    /// The open–close iteration has settled when the contact forces the last solve applied
    /// differ from those of the updated states by at most this fraction of their sum [-]
    /// (0, the default: only when no point changes state; 1e-3 suits jointed rock masses).
    pub open_close_tolerance: f64,
    /// Strain measure: "corotational" (small strain in each ME's rotated frame) or
    /// "green_lagrange" (St Venant–Kirchhoff for large strains).
    pub strain_measure: StrainMeasure,
    /// Before the run, solve the static equilibrium under the initial loads with every contact
    /// locked (no sliding, no opening), then start from that state with the given velocities
    /// at t = 0 (addition).
    pub initial_equilibrium: bool,
    /// Wall-clock seconds between checkpoints written during a run (`checkpoint.json`, for
    /// `--resume`); one is always written when a run completes or is interrupted; 0 = only
    /// then [s] (addition).
    pub checkpoint_interval: f64,
}

/// Fill-reducing ordering of the sparse Cholesky factorisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Ordering {
    /// Nested dissection for large systems (≥ 2000 covers), AMD below.
    #[default]
    Auto,
    /// Approximate minimum degree.
    Amd,
    /// METIS nested dissection.
    NestedDissection,
}

/// How strain is measured in each manifold element.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StrainMeasure {
    /// Linear strain in the ME's co-rotated frame: exact for large rotations, small strains.
    #[default]
    Corotational,
    /// Green–Lagrange strain with second Piola–Kirchhoff stress (St Venant–Kirchhoff).
    GreenLagrange,
}

impl Default for Analysis {
    fn default() -> Self {
        Self {
            kind: AnalysisKind::Dynamic,
            duration: 1.0,
            max_steps: 200_000,
            dt: 0.001,
            max_displacement_ratio: 0.001,
            gravity: [0.0, 0.0, -9.81],
            output_interval: 0.05,
            history_interval: None,
            integrator: Integrator::Dda,
            newmark_beta: 0.25,
            newmark_gamma: 0.5,
            equilibrium_tolerance: 1e-7,
            penalty_stiffness: Stiffness::Auto,
            penalty_factor: 1e4,
            min_dt_ratio: 1e-4,
            max_dt_growth: 1.2,
            target_displacement_ratio: 0.8,
            divergence_ratio: 1e3,
            strain_measure: StrainMeasure::Corotational,
            ordering: Ordering::Auto,
            max_open_close: 12,
            open_close_cut: 0.3,
            open_close_tolerance: 0.0,
            initial_equilibrium: false,
            checkpoint_interval: 600.0,
        }
    }
}

/// A stiffness [N/m] or "auto".
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Stiffness {
    /// Chosen from the model (documented per key).
    #[default]
    Auto,
    /// Given value [N/m].
    Value(f64),
}

impl Serialize for Stiffness {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Stiffness::Auto => s.serialize_str("auto"),
            Stiffness::Value(v) => s.serialize_f64(*v),
        }
    }
}

impl<'de> Deserialize<'de> for Stiffness {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Raw {
            Num(f64),
            Int(i64),
            Text(String),
        }
        match Raw::deserialize(d)? {
            Raw::Num(v) => Ok(Stiffness::Value(v)),
            Raw::Int(v) => Ok(Stiffness::Value(v as f64)),
            Raw::Text(t) if t == "auto" => Ok(Stiffness::Auto),
            Raw::Text(t) => Err(serde::de::Error::custom(format!("expected a number or \"auto\", found \"{t}\""))),
        }
    }
}

/// Decomposition of the cubic cells of the mathematical mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PatternKind {
    /// Five tetrahedra, mirrored plans alternating (conforming).
    Tet5,
    /// Six tetrahedra around the main diagonal (Kuhn / Freudenthal).
    #[default]
    Tet6,
    /// 24 tetrahedra from face and body centres.
    Tet24,
    /// One trilinear hexahedron.
    Hex8,
}

/// `[cover]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CoverSpec {
    /// Pattern.
    pub pattern: PatternKind,
    /// Edge of the cubic cells [m]; absent = a tenth of the smallest model extent.
    pub size: Option<f64>,
    /// A mesh node [m].
    pub origin: [f64; 3],
    /// Rotation of the mesh about x, then y, then z [deg].
    pub rotation: [f64; 3],
    /// An ME smaller than this fraction of its sub-cell does not anchor its covers; covers
    /// with no anchoring ME are tied to the nearest anchored ME (aggregation) [-]; 0 = off.
    pub aggregation_threshold: f64,
}

impl Default for CoverSpec {
    fn default() -> Self {
        Self {
            pattern: PatternKind::Tet6,
            size: None,
            origin: [0.0; 3],
            rotation: [0.0; 3],
            aggregation_threshold: 0.1,
        }
    }
}

/// `[contact]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ContactSpec {
    /// Contact between blocks (addition; `false` lets blocks pass through each other, for
    /// continuum checks).
    pub enabled: bool,
    /// Normal penalty [N/m] or "auto".
    pub normal_stiffness: Stiffness,
    /// Shear penalty [N/m] or "auto".
    pub shear_stiffness: Stiffness,
    /// Largest contact overlap allowed at the end of a step, as a fraction of the cover size;
    /// beyond it the step is cut (addition) [-].
    pub max_penetration_ratio: f64,
}

impl Default for ContactSpec {
    fn default() -> Self {
        Self {
            enabled: true,
            normal_stiffness: Stiffness::Auto,
            shear_stiffness: Stiffness::Auto,
            max_penetration_ratio: 0.01,
        }
    }
}

/// `[cutting]`: controls of the rock-mass cutting.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CuttingSpec {
    /// A block smaller than this fraction of its largest neighbour is merged into it
    /// (dropped if it has none) [-]; 0 = keep every block.
    pub sliver_ratio: f64,
}

impl Default for CuttingSpec {
    fn default() -> Self {
        Self { sliver_ratio: 1e-4 }
    }
}

/// `[[material]]`: isotropic linear elasticity.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Unique name.
    pub name: String,
    /// Density [kg/m³].
    pub density: f64,
    /// Young's modulus [Pa].
    pub young: f64,
    /// Poisson's ratio [-].
    pub poisson: f64,
}

/// `[[joint]]`: Coulomb strength.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Joint {
    /// Unique name.
    pub name: String,
    /// Friction angle [deg].
    #[serde(default)]
    pub friction_angle: f64,
    /// Cohesion [Pa].
    #[serde(default)]
    pub cohesion: f64,
    /// Tensile strength [Pa].
    #[serde(default)]
    pub tensile_strength: f64,
    /// Normal stiffness per unit joint area [Pa/m] (as 3DEC and UDEC take it); absent: the
    /// contact penalty `contact.normal_stiffness`.
    #[serde(default)]
    pub normal_stiffness: Option<f64>,
    /// Shear stiffness per unit joint area [Pa/m]; absent: the normal stiffness when that is
    /// given, else the contact penalty `contact.shear_stiffness`.
    #[serde(default)]
    pub shear_stiffness: Option<f64>,
}

impl Joint {
    /// The joint's own (normal, shear) stiffness per unit area [Pa/m], when it has one.
    pub fn stiffness(&self) -> Option<(f64, f64)> {
        let kn = self.normal_stiffness?;
        Some((kn, self.shear_stiffness.unwrap_or(kn)))
    }
}

/// `[[body]]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Body {
    /// Unique name.
    pub name: String,
    /// Material name.
    pub material: String,
    /// Joint name (cuts inside, contacts).
    #[serde(default)]
    pub joint: Option<String>,
    /// Every block of this body is fixed.
    #[serde(default)]
    pub fixed: bool,
    /// Initial velocity [m/s].
    #[serde(default)]
    pub velocity: [f64; 3],
    /// Initial angular velocity about the body's centroid [rad/s] (addition to v1).
    #[serde(default)]
    pub angular_velocity: [f64; 3],
    /// Shape.
    pub shape: Shape,
}

/// A solid shape (a table with one key).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum Shape {
    /// Axis-aligned box.
    Box {
        /// Lower corner [m].
        min: [f64; 3],
        /// Upper corner [m].
        max: [f64; 3],
    },
    /// Intersection of half-spaces: n·x ≤ d, and sides of planes given by dip and dip direction.
    Convex {
        /// Rows `[nx, ny, nz, d]`.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        planes: Vec<[f64; 4]>,
        /// Planes as geologists give them (addition to v1).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        faces: Vec<OrientedFace>,
    },
    /// Closed polyhedron, faces counter-clockwise seen from outside.
    Polyhedron {
        /// Vertices [m].
        vertices: Vec<[f64; 3]>,
        /// Faces as vertex indices.
        faces: Vec<Vec<usize>>,
    },
    /// Vertical extrusion of a simple polygon.
    Prism {
        /// Polygon `[x, y]` [m].
        polygon: Vec<[f64; 2]>,
        /// `[z0, z1]` [m].
        z: [f64; 2],
    },
    /// Tunnel (excavations only).
    Tunnel(Tunnel),
}

/// One side of a plane given by dip, dip direction and a point (a slope face, a bench, a cut).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OrientedFace {
    /// Dip [deg], 0 to 90.
    pub dip: f64,
    /// Dip direction [deg], clockwise from North (+y).
    pub dip_direction: f64,
    /// A point on the plane [m].
    pub point: [f64; 3],
    /// The side kept: "below" (the rock behind a slope face) or "above".
    #[serde(default)]
    pub keep: Side,
}

/// A side of an oriented plane; for a vertical plane "below" is the side away from its dip
/// direction (the limit of the upward normal).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Side {
    /// Against the upward normal.
    #[default]
    Below,
    /// Along the upward normal.
    Above,
}

impl OrientedFace {
    /// The half-space kept, as `[nx, ny, nz, d]` with n·x ≤ d.
    pub fn half_space(&self) -> [f64; 4] {
        let n = nmm3d_geom::orientation::normal_from_dip(self.dip, self.dip_direction);
        let n = if self.keep == Side::Below { n } else { -n };
        let d = n.x * self.point[0] + n.y * self.point[1] + n.z * self.point[2];
        [n.x, n.y, n.z, d]
    }
}

/// Tunnel profile swept along an axis.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tunnel {
    /// "horseshoe" | "circular" | "rectangular".
    pub profile: String,
    /// Width [m].
    #[serde(default)]
    pub width: Option<f64>,
    /// Height [m].
    #[serde(default)]
    pub height: Option<f64>,
    /// Radius [m] (circular).
    #[serde(default)]
    pub radius: Option<f64>,
    /// Axis start [m].
    pub start: [f64; 3],
    /// Axis end [m].
    pub end: [f64; 3],
    /// Straight pieces approximating a curve.
    #[serde(default)]
    pub segments: Option<u32>,
}

/// `[[joint_set]]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointSet {
    /// Bodies cut (default: all non-fixed).
    #[serde(default)]
    pub bodies: Option<Vec<String>>,
    /// Dip [deg].
    pub dip: f64,
    /// Dip direction [deg].
    pub dip_direction: f64,
    /// Spacing [m].
    pub spacing: f64,
    /// A point on one plane [m].
    #[serde(default)]
    pub origin: [f64; 3],
    /// Joint name.
    #[serde(default)]
    pub joint: Option<String>,
}

/// `[[joint_plane]]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointPlane {
    /// Bodies cut.
    #[serde(default)]
    pub bodies: Option<Vec<String>>,
    /// A point on the plane [m].
    pub point: [f64; 3],
    /// Dip [deg].
    #[serde(default)]
    pub dip: Option<f64>,
    /// Dip direction [deg].
    #[serde(default)]
    pub dip_direction: Option<f64>,
    /// Normal (instead of dip / dip direction).
    #[serde(default)]
    pub normal: Option<[f64; 3]>,
    /// Joint name.
    #[serde(default)]
    pub joint: Option<String>,
}

/// `[[excavation]]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Excavation {
    /// Shape removed.
    pub shape: Shape,
}

/// `[[interface]]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Interface {
    /// Two body names.
    pub bodies: [String; 2],
    /// Joint name.
    pub joint: String,
}

/// A region of space.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum Region {
    /// Axis-aligned box.
    Box {
        /// Lower corner [m].
        min: [f64; 3],
        /// Upper corner [m].
        max: [f64; 3],
    },
}

/// Axis names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    /// East.
    X,
    /// North.
    Y,
    /// Up.
    Z,
}

/// `[[constraint]]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Constraint {
    /// Region whose boundary vertices are held.
    pub select: Region,
    /// Held directions.
    pub directions: Vec<Axis>,
}

/// `[[fixed_point]]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FixedPoint {
    /// Point [m].
    pub point: [f64; 3],
    /// Held directions.
    pub directions: Vec<Axis>,
}

/// `[[point_load]]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointLoad {
    /// Point [m].
    pub point: [f64; 3],
    /// Force [N].
    pub force: [f64; 3],
}

/// `[[surface_load]]`: a dead traction on the block boundary faces inside a region.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceLoad {
    /// Region: boundary faces with every vertex inside are loaded.
    pub select: Region,
    /// Only faces whose outward normal lies within 1° of this direction (optional).
    #[serde(default)]
    pub normal: Option<[f64; 3]>,
    /// Traction [Pa].
    pub traction: [f64; 3],
}

/// `[in_situ_stress]`, compression negative.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InSituStress {
    /// xx, yy, zz, xy, yz, zx [Pa].
    pub stress: [f64; 6],
    /// Gradient in z [Pa/m].
    #[serde(default)]
    pub gradient: [f64; 6],
    /// Height where `stress` applies [m].
    #[serde(default)]
    pub reference_z: f64,
}

/// Which block a monitor follows.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum MonitorSelect {
    /// The block containing this point at t = 0.
    Point([f64; 3]),
    /// A body made of a single block.
    Body(String),
    /// The block with this id (as in `blocks.csv`; addition to v1).
    Block(usize),
}

/// Monitored quantities.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Quantity {
    /// Centroid displacement [m].
    Displacement,
    /// Centroid velocity [m/s].
    Velocity,
    /// Rotation vector [rad].
    Rotation,
    /// Volume [m³].
    Volume,
    /// Volume-mean stress [Pa].
    Stress,
}

/// `[[monitor]]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Monitor {
    /// Unique name.
    pub name: String,
    /// The block followed.
    pub select: MonitorSelect,
    /// Quantities recorded.
    pub quantities: Vec<Quantity>,
    /// Where displacement and velocity are taken (addition to v1): the block's centroid, or
    /// the material point at `select.point`.
    #[serde(default)]
    pub location: MonitorLocation,
}

/// Where a monitor takes displacement and velocity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MonitorLocation {
    /// Volume-weighted mean over the block (its centroid).
    #[default]
    Centroid,
    /// The material point at `select.point`.
    Point,
}

impl Quantity {
    /// Name used in column headers.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Displacement => "displacement",
            Quantity::Velocity => "velocity",
            Quantity::Rotation => "rotation",
            Quantity::Volume => "volume",
            Quantity::Stress => "stress",
        }
    }
    /// Component names in column headers.
    pub fn components(self) -> &'static [&'static str] {
        match self {
            Quantity::Volume => &["value"],
            Quantity::Stress => &["xx", "yy", "zz", "xy", "yz", "zx"],
            _ => &["x", "y", "z"],
        }
    }
}

/// `[[expect]]` (addition to v1): the value a monitored quantity should have at the end of the
/// run, from a closed form or an independent reference. Printed beside the answer and reported
/// in `summary.json` under `checks`; it never changes how the run goes.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Expect {
    /// A column of `history.csv`: `<monitor>.<quantity>.<component>`.
    pub quantity: String,
    /// Reference value, in the column's unit.
    pub reference: f64,
    /// Allowed relative difference, a fraction of |reference| [-].
    #[serde(default = "Expect::default_tolerance")]
    pub tolerance: f64,
    /// Allowed absolute difference, in the column's unit (for references near zero).
    #[serde(default)]
    pub absolute_tolerance: f64,
    /// Where the reference comes from.
    #[serde(default)]
    pub source: String,
}

impl Expect {
    fn default_tolerance() -> f64 {
        0.01
    }
}
