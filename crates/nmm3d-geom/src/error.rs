//! Typed geometry errors.

/// What went wrong with a piece of geometry, and where.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GeomError {
    /// The shape encloses no volume (empty or flat).
    #[error("the shape is empty or degenerate (volume {volume:e} m^3)")]
    Degenerate {
        /// Computed volume.
        volume: f64,
    },
    /// A plane normal of zero length.
    #[error("plane {index} has a zero normal")]
    ZeroNormal {
        /// Index of the plane in its list.
        index: usize,
    },
    /// The half-spaces do not bound a finite region.
    #[error("the half-spaces do not bound a finite region")]
    Unbounded,
    /// A polyhedron given by vertices and faces is not closed or not consistently oriented.
    #[error("polyhedron is not closed or not consistently oriented: {reason}")]
    NotClosed {
        /// Explanation naming the offending edge or face.
        reason: String,
    },
    /// A polyhedron is not convex.
    #[error("polyhedron is not convex: vertex {vertex} lies outside the plane of face {face}")]
    NotConvex {
        /// Face index.
        face: usize,
        /// Vertex index.
        vertex: usize,
    },
    /// A face or polygon index refers to a vertex that does not exist.
    #[error("face {face} refers to vertex {vertex}, but there are only {count} vertices")]
    BadIndex {
        /// Face index.
        face: usize,
        /// Vertex index.
        vertex: usize,
        /// Number of vertices.
        count: usize,
    },
    /// A polygon that is not simple or has fewer than three vertices.
    #[error("polygon is invalid: {reason}")]
    BadPolygon {
        /// Explanation.
        reason: String,
    },
}
