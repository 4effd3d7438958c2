//! Analysis controls: kind, time step and its control, integrator, ordering, strain measure,
//! penalties; the cover; cutting; key blocks.

use serde::{Deserialize, Serialize};

use super::contact::Stiffness;

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
    /// Precision of the direct solver's numeric factorisations (addition).
    pub factor_precision: FactorPrecision,
    /// Linear solver: "auto" (multigrid-preconditioned CG for a large single block, else the
    /// direct Cholesky), "direct", "amg" or "blocks" (addition).
    pub linear_solver: SolverChoice,
    /// With "auto", a single block with at least this many equations is solved by multigrid
    /// PCG [-] (addition).
    pub amg_min_equations: u64,
    /// Relative preconditioned residual at which the multigrid PCG has converged [-] (addition).
    pub amg_tolerance: f64,
    /// In a static analysis, the relative residual to which multigrid PCG solves the Newton
    /// corrections after a hierarchy's first solve [-] (addition).
    pub amg_newton_tolerance: f64,
    /// Open–close iterations per step before the step is cut.
    pub max_open_close: u32,
    /// Factor applied to Δt when the open–close iteration does not settle [-].
    pub open_close_cut: f64,
    /// The open–close iteration has settled when the contact forces the last solve applied
    /// differ from those of the updated states by at most this fraction of their sum [-]
    /// (0, the default: only when no point changes state; 1e-3 suits jointed rock masses).
    pub open_close_tolerance: f64,
    /// The same in a static analysis, where it is the larger of the two: a static run's steps
    /// are iterates towards the equilibrium it ends in (checked to `equilibrium_tolerance`),
    /// not states in time [-] (addition).
    pub static_open_close_tolerance: f64,
    /// A dynamic step with contact whose points that closed or opened gave the blocks more
    /// energy than this fraction of the run's largest energy account is repeated with Δt ×
    /// `open_close_cut`, while that halves the energy (0: never) [-] (addition).
    pub max_energy_gain: f64,
    /// Modified Newton iterations that bring a dynamic step's end to equilibrium with the
    /// co-rotated elements' forces at the end (0: one linear solve per step, as DDA) (addition).
    pub step_equilibrium_iterations: u32,
    /// A dynamic step's end is in equilibrium when the next correction would move it by at most
    /// this fraction of the step's largest displacement [-] (addition).
    pub step_equilibrium_tolerance: f64,
    /// When the corrections stall (stop shrinking, or the iterations run out), the step keeps
    /// its last iterate if the last correction moved it by at most this fraction of the step's
    /// largest displacement, else its linear increment [-] (addition).
    pub step_equilibrium_stall: f64,
    /// A dynamic step keeps a block's tangent while none of its MEs has turned by more than this
    /// angle (and its tensile stress has not changed by more than this fraction of Young's
    /// modulus) since the tangent was made: the tangent only steers the solve, the forces are
    /// exact (0: every tangent made afresh at every step) [rad] (addition).
    pub tangent_keep_angle: f64,
    /// Strain measure: "corotational" (small strain in each ME's rotated frame) or
    /// "green_lagrange" (St Venant–Kirchhoff for large strains).
    pub strain_measure: StrainMeasure,
    /// Before the run, find the static equilibrium under the initial loads and start from it
    /// with the given velocities at t = 0: `true` / "locked" with every contact locked (no
    /// sliding, no opening), "frictional" with the contacts free (Coulomb friction, opening) by
    /// static steps of `settle_dt`; `false`: none (addition).
    pub initial_equilibrium: InitialEquilibrium,
    /// Pseudo-time step of the frictional initial equilibrium's static steps [s]: it only
    /// regularises (the mass term M/(β Δt²) holds what the joints do not yet), so a larger one
    /// settles soft joints in fewer steps (addition).
    pub settle_dt: f64,
    /// Wall-clock seconds between checkpoints written during a run (`checkpoint.json`, for
    /// `--resume`); one is always written when a run completes or is interrupted; 0 = only
    /// then [s] (addition).
    pub checkpoint_interval: f64,
    /// Newton iterations of the initial equilibrium before damped steps take over (addition).
    pub max_static_iterations: u64,
    /// Damped steps of the initial equilibrium after the Newton iterations; at this bound the
    /// run starts from where it got, and the summary names the blocks still moving (addition).
    pub max_settle_steps: u64,
    /// Smallest factor one cut applies to Δt when a step moved too far (DDA: 0.1) [-]
    /// (addition).
    pub max_step_cut: f64,
    /// Solve a matrix close to the last one factorised by PCG with that factor as the
    /// preconditioner, factorising only when PCG does not converge (addition).
    pub factor_reuse: bool,
    /// Relative preconditioned residual at which that PCG has converged [-] (addition).
    pub krylov_tolerance: f64,
    /// PCG iterations before the matrix is factorised instead; a factor that needed more
    /// than half of them is renewed at the next solve (addition).
    pub krylov_max_iterations: u32,
    /// A matrix whose every entry differs from the last factorised one's by at most this
    /// fraction of that matrix's largest entry is solved on its factor whatever its contact
    /// springs (the same contact states, a block system at rest) until the PCG iterations
    /// spent on such matrices cost a factorisation; 0: only matrices without closed contacts
    /// are [-] (addition).
    pub factor_reuse_closeness: f64,
    /// Memory a run may plan to use [B]; a scenario estimated beyond it is refused as input;
    /// 0 = 80 % of this machine's memory (addition).
    pub max_memory: f64,
    /// A static analysis leaves the blocks whose covers moved this far from the reference
    /// configuration out of its unbalanced force and ends (not converged, naming them: not
    /// held) once the others are in equilibrium — a verdict for every block without following
    /// a failing one down its slope; 0 = off [m] (addition).
    pub static_travel_limit: f64,
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
    /// Both analysed at every new pattern, the smaller factor kept (AMD on a tie): which wins
    /// depends on the blocks' shape (docs/ordering.md).
    Smallest,
}

/// Precision of the sparse Cholesky factorisations (`docs/theory/solver.md`, *Single-precision
/// factors*).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FactorPrecision {
    /// Single precision, refined to double, where a factorisation costs many triangular
    /// solves (its factor fills: jointed rock masses); double precision elsewhere.
    #[default]
    Auto,
    /// Always double precision.
    Double,
    /// Single precision, refined to double, wherever it factorises.
    Single,
}

/// Which linear solver solves the systems.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolverChoice {
    /// Multigrid PCG for one block of at least `amg_min_equations` equations, else direct.
    #[default]
    Auto,
    /// Sparse Cholesky (faer), with factor reuse.
    Direct,
    /// Conjugate gradients preconditioned by smoothed-aggregation multigrid.
    Amg,
    /// Conjugate gradients preconditioned by the blocks: each block's equations solved by its
    /// own factor, the blocks' rigid motions by a coarse factor (many blocks on soft joints).
    Blocks,
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

impl Analysis {
    /// The open–close iteration's tolerance for this kind of analysis [-].
    pub fn settle_tolerance(&self) -> f64 {
        match self.kind {
            AnalysisKind::Static => self.open_close_tolerance.max(self.static_open_close_tolerance),
            AnalysisKind::Dynamic => self.open_close_tolerance,
        }
    }
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
            factor_precision: FactorPrecision::Auto,
            linear_solver: SolverChoice::Auto,
            amg_min_equations: 20_000,
            amg_tolerance: 1e-8,
            amg_newton_tolerance: 1e-3,
            max_open_close: 12,
            open_close_cut: 0.3,
            open_close_tolerance: 0.0,
            static_open_close_tolerance: 1e-3,
            max_energy_gain: 0.01,
            step_equilibrium_iterations: 4,
            step_equilibrium_tolerance: 1e-4,
            step_equilibrium_stall: 1e-2,
            tangent_keep_angle: 1e-6,
            initial_equilibrium: InitialEquilibrium::Off,
            settle_dt: 1.0,
            checkpoint_interval: 600.0,
            max_static_iterations: 50,
            max_settle_steps: 5000,
            max_step_cut: 0.1,
            factor_reuse: true,
            krylov_tolerance: 1e-10,
            krylov_max_iterations: 12,
            factor_reuse_closeness: 1e-6,
            max_memory: 0.0,
            static_travel_limit: 0.0,
        }
    }
}

/// How the initial equilibrium treats the contacts (`analysis.initial_equilibrium`: a boolean as
/// in v1, or the name of the method).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(try_from = "EquilibriumRepr", into = "EquilibriumRepr")]
pub enum InitialEquilibrium {
    /// None: the run starts from the input.
    #[default]
    Off,
    /// Every contact locked: Newton iterations, then damped steps (`true`).
    Locked,
    /// The contacts free, with friction: static steps of `settle_dt` (velocities reset).
    Frictional,
}

/// What the scenario file holds for [`InitialEquilibrium`].
#[derive(Serialize, Deserialize)]
#[serde(untagged)]
enum EquilibriumRepr {
    Flag(bool),
    Name(String),
}

impl TryFrom<EquilibriumRepr> for InitialEquilibrium {
    type Error = String;
    fn try_from(r: EquilibriumRepr) -> Result<Self, String> {
        match r {
            EquilibriumRepr::Flag(false) => Ok(Self::Off),
            EquilibriumRepr::Flag(true) => Ok(Self::Locked),
            EquilibriumRepr::Name(n) if n == "locked" => Ok(Self::Locked),
            EquilibriumRepr::Name(n) if n == "frictional" => Ok(Self::Frictional),
            EquilibriumRepr::Name(n) => Err(format!("'{n}' is not true, false, \"locked\" or \"frictional\"")),
        }
    }
}

impl From<InitialEquilibrium> for EquilibriumRepr {
    fn from(e: InitialEquilibrium) -> Self {
        match e {
            InitialEquilibrium::Off => Self::Flag(false),
            InitialEquilibrium::Locked => Self::Flag(true),
            InitialEquilibrium::Frictional => Self::Name("frictional".into()),
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

/// `[keyblocks]`: how the key-block analysis (`nmm3d keyblocks`) reads the model (addition to v1).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct KeyBlocksSpec {
    /// Sides of the model's bounding box that are free surfaces; block faces on the other sides
    /// count as rock continuing beyond. Absent: `["+z"]` (the top is the ground) when the
    /// scenario has no excavation, none when it has one (a tunnel model is rock all round).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub free_sides: Option<Vec<BoxSide>>,
}

/// A side of an axis-aligned box.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum BoxSide {
    /// x = min.
    #[serde(rename = "-x")]
    MinX,
    /// x = max.
    #[serde(rename = "+x")]
    MaxX,
    /// y = min.
    #[serde(rename = "-y")]
    MinY,
    /// y = max.
    #[serde(rename = "+y")]
    MaxY,
    /// z = min (the bottom).
    #[serde(rename = "-z")]
    MinZ,
    /// z = max (the top).
    #[serde(rename = "+z")]
    MaxZ,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(v: &str) -> Result<InitialEquilibrium, String> {
        let t: toml::Table = toml::from_str(&format!("x = {v}")).unwrap();
        t["x"].clone().try_into().map_err(|e: toml::de::Error| e.to_string())
    }

    #[test]
    fn initial_equilibrium_reads_v1_booleans_and_method_names_and_writes_them_back() {
        assert_eq!(parse("false"), Ok(InitialEquilibrium::Off));
        assert_eq!(parse("true"), Ok(InitialEquilibrium::Locked));
        assert_eq!(parse("\"locked\""), Ok(InitialEquilibrium::Locked));
        assert_eq!(parse("\"frictional\""), Ok(InitialEquilibrium::Frictional));
        assert!(parse("\"damped\"").unwrap_err().contains("\"frictional\""));
        for e in [InitialEquilibrium::Off, InitialEquilibrium::Locked, InitialEquilibrium::Frictional] {
            assert_eq!(toml::Value::try_from(e).unwrap().try_into::<InitialEquilibrium>().unwrap(), e);
        }
    }
}
