//! Body shapes of the scenario turned into convex polyhedra (this version: convex shapes).

use nmm3d_geom::{orientation, ConvexPolyhedron, GeomError, Plane, Vec3};

use crate::scenario::Shape;

/// The convex polyhedron of a shape; on failure (sub-path, reason).
pub fn shape_to_convex(shape: &Shape) -> Result<ConvexPolyhedron, (String, String)> {
    let geom = |sub: &str, e: GeomError| (sub.to_string(), e.to_string());
    match shape {
        Shape::Box { min, max } => {
            if (0..3).any(|i| !(min[i] < max[i])) {
                return Err((".box".into(), "min must be below max in every axis (an empty box)".into()));
            }
            Ok(ConvexPolyhedron::from_box(Vec3::from(*min), Vec3::from(*max)))
        }
        Shape::Convex { planes } => {
            let mut ps = Vec::with_capacity(planes.len());
            for (k, c) in planes.iter().enumerate() {
                ps.push(Plane::from_coefficients(*c).ok_or_else(|| geom(".convex.planes", GeomError::ZeroNormal { index: k }))?);
            }
            ConvexPolyhedron::from_planes(&ps).map_err(|e| geom(".convex.planes", e))
        }
        Shape::Polyhedron { vertices, faces } => {
            let vs: Vec<Vec3> = vertices.iter().map(|v| Vec3::from(*v)).collect();
            ConvexPolyhedron::from_vertices_faces(&vs, faces).map_err(|e| match e {
                GeomError::NotConvex { .. } => (
                    ".polyhedron".to_string(),
                    format!("{e}; non-convex bodies are not supported by this version of nmm3d yet"),
                ),
                other => geom(".polyhedron", other),
            })
        }
        Shape::Prism { polygon, z } => prism(polygon, *z),
        Shape::Tunnel(_) => Err((".tunnel".into(), "a tunnel is only allowed as an excavation shape".into())),
    }
}

fn prism(polygon: &[[f64; 2]], z: [f64; 2]) -> Result<ConvexPolyhedron, (String, String)> {
    let bad = |r: &str| Err((".prism".to_string(), r.to_string()));
    if polygon.len() < 3 {
        return bad("the polygon needs at least 3 vertices");
    }
    if !(z[0] < z[1]) {
        return bad("z = [z0, z1] needs z0 < z1");
    }
    let n = polygon.len();
    let area2: f64 = (0..n).map(|i| {
        let (a, b) = (polygon[i], polygon[(i + 1) % n]);
        a[0] * b[1] - a[1] * b[0]
    }).sum();
    if area2.abs() <= 1e-14 {
        return bad("the polygon has no area");
    }
    let sign = area2.signum();
    let mut planes = vec![
        Plane::from_coefficients([0.0, 0.0, -1.0, -z[0]]).unwrap(),
        Plane::from_coefficients([0.0, 0.0, 1.0, z[1]]).unwrap(),
    ];
    for i in 0..n {
        let (a, b, c) = (polygon[i], polygon[(i + 1) % n], polygon[(i + 2) % n]);
        let turn = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
        if turn * sign < -1e-12 {
            return bad("the polygon is not convex; non-convex prisms are not supported by this version of nmm3d yet");
        }
        let edge = Vec3::new(b[0] - a[0], b[1] - a[1], 0.0);
        let outward = Vec3::new(edge.y, -edge.x, 0.0) * sign;
        let p = Plane::from_point_normal(Vec3::new(a[0], a[1], 0.0), outward)
            .ok_or_else(|| (".prism".to_string(), format!("polygon vertices {i} and {} coincide", (i + 1) % n)))?;
        planes.push(p);
    }
    ConvexPolyhedron::from_planes(&planes).map_err(|e| (".prism".into(), e.to_string()))
}

/// Unit normal from a dip / dip direction pair (re-exported for joints).
pub fn plane_normal(dip: f64, dip_direction: f64) -> Vec3 {
    orientation::normal_from_dip(dip, dip_direction)
}
