//! Penalty constraints: a stiff spring ½ k (n · u(p))² holding the displacement of a material
//! point p in direction n at zero (fixed points, constraint regions).

use std::collections::BTreeMap;

use nmm3d_geom::Vec3;

use super::loads::weights_at;
use crate::cover::Covers;
use crate::scenario::{Axis, Region};

/// One penalty point.
#[derive(Debug, Clone)]
pub struct PointConstraint {
    /// ME holding the point.
    pub element: usize,
    /// Weight-function values at the point (aligned with the ME's covers).
    pub weights: Vec<f64>,
    /// Held unit directions.
    pub directions: Vec<Vec3>,
    /// Reference position [m].
    pub position: Vec3,
}

/// Unit vector of an axis.
pub fn axis_vector(a: Axis) -> Vec3 {
    match a {
        Axis::X => Vec3::x(),
        Axis::Y => Vec3::y(),
        Axis::Z => Vec3::z(),
    }
}

/// Distinct boundary vertices inside `region`, each with an ME holding it (reference config).
pub fn boundary_vertices_in(covers: &Covers, region: &Region, weld: f64) -> Vec<(usize, Vec3)> {
    let Region::Box { min, max } = region;
    let bb = nmm3d_geom::Aabb { min: Vec3::from(*min), max: Vec3::from(*max) };
    let mut found: BTreeMap<[i64; 3], (usize, Vec3)> = BTreeMap::new();
    for (ei, e) in covers.elements.iter().enumerate() {
        for f in e.boundary_faces() {
            for v in &f.vertices {
                let x = covers.global(e, v);
                if bb.contains(&x, weld) {
                    let key = [(x.x / weld).round() as i64, (x.y / weld).round() as i64, (x.z / weld).round() as i64];
                    let _ = found.entry(key).or_insert((ei, x));
                }
            }
        }
    }
    found.into_values().collect()
}

/// A constraint at `x` held by ME `element`.
pub fn point_constraint(covers: &Covers, element: usize, x: Vec3, dirs: &[Axis]) -> PointConstraint {
    let e = &covers.elements[element];
    PointConstraint {
        element,
        weights: weights_at(covers, e, &x),
        directions: dirs.iter().map(|a| axis_vector(*a)).collect(),
        position: x,
    }
}
