//! Geometry for the three-dimensional numerical manifold method (NMM).
//!
//! No physics lives here: vectors and planes, geological orientation
//! (dip / dip direction, x = East, y = North, z = Up), convex polyhedra held as
//! outward-oriented face polygons, half-space clipping and splitting, axis-aligned
//! bounding boxes, and exact integration of polynomials over simplices and polyhedra.
//!
//! | symbol | meaning | type |
//! |---|---|---|
//! | $\mathbf n \cdot \mathbf x \le d$ | half-space | [`Plane`] |
//! | $P$ | convex polyhedron | [`ConvexPolyhedron`] |
//! | $\int_P x^a y^b z^c\,dV$ | monomial moment | [`integrate`] |
#![warn(missing_docs)]

pub mod aabb;
pub mod clip;
pub mod contact;
pub mod decompose;
pub mod error;
pub mod flat;
pub mod integrate;
pub mod math;
pub mod orientation;
pub mod plane;
pub mod polygon;
pub mod polyhedron;
pub mod prepared;
pub mod winding;

pub use aabb::Aabb;
pub use error::GeomError;
pub use math::{Mat3, Vec3};
pub use plane::Plane;
pub use polyhedron::{ConvexPolyhedron, Face, FaceTag};
