//! The rock: materials, joints, bodies and their shapes, joint sets and planes, excavations,
//! interfaces.

use serde::{Deserialize, Serialize};

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
    /// A fixed body covered by the mesh like a moving one (addition to v1). By default each
    /// fixed block is one manifold element: only its surface matters for contact, it has no
    /// equations either way, and a fine mesh of it would cost memory and detection time.
    #[serde(default)]
    pub fixed_mesh: bool,
    /// Cell edge of this body's mesh [m] (addition to v1; default `[cover] size`): the same
    /// node and rotation as `[cover]`, e.g. a fine mesh where stresses matter.
    #[serde(default)]
    pub cover_size: Option<f64>,
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
    /// Name, for a stage to remove it by (addition to v1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
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
