//! Scenario shapes turned into convex pieces. Convex shapes are one piece; a non-convex
//! polyhedron or prism becomes several convex pieces glued by internal faces
//! (`nmm3d_geom::decompose`), so covers, integration and contact see one solid. Faces keep the
//! index of the shape face they lie on (`tags::body_face`), internal faces are `tags::GLUE`.

use nmm3d_geom::decompose::{convex_pieces, NewFaceTags};
use nmm3d_geom::polyhedron::check_closed;
use nmm3d_geom::{ConvexPolyhedron, Face, GeomError, Plane, Vec3};

use super::tags;
use super::tunnel::tunnel_polyhedron;
use crate::error::Problem;
use crate::scenario::{Scenario, Shape};

/// Failure: (sub-path below the shape, reason).
pub type ShapeError = (String, String);

/// Every body and excavation shape that does not make a solid, as input problems with their
/// key paths (a tunnel as a body is the scenario checks' to report).
pub fn shape_problems(s: &Scenario) -> Vec<Problem> {
    let bodies = s
        .body
        .iter()
        .filter(|b| !matches!(b.shape, Shape::Tunnel(_)))
        .map(|b| (format!("body.{}.shape", b.name), &b.shape));
    let holes = s.excavation.iter().enumerate().map(|(k, ex)| (format!("excavation[{k}].shape"), &ex.shape));
    bodies
        .chain(holes)
        .filter_map(|(path, shape)| {
            shape_to_pieces(shape).err().map(|(sub, reason)| Problem { path: format!("{path}{sub}"), reason })
        })
        .collect()
}

/// The convex pieces of a shape (an excavation may also be a tunnel).
pub fn shape_to_pieces(shape: &Shape) -> Result<Vec<ConvexPolyhedron>, ShapeError> {
    let geom = |sub: &str, e: GeomError| (sub.to_string(), e.to_string());
    match shape {
        Shape::Box { min, max } => {
            if (0..3).any(|i| !(min[i] < max[i])) {
                return Err((".box".into(), "min must be below max in every axis (an empty box)".into()));
            }
            Ok(vec![ConvexPolyhedron::from_box(Vec3::from(*min), Vec3::from(*max))])
        }
        Shape::Convex { planes, faces } => {
            let mut ps = Vec::with_capacity(planes.len() + faces.len());
            for (k, c) in planes.iter().enumerate() {
                ps.push(
                    Plane::from_coefficients(*c)
                        .ok_or_else(|| geom(".convex.planes", GeomError::ZeroNormal { index: k }))?,
                );
            }
            for (k, f) in faces.iter().enumerate() {
                if !(0.0..=90.0).contains(&f.dip)
                    || !f.dip_direction.is_finite()
                    || !f.point.iter().all(|x| x.is_finite())
                {
                    return Err((format!(".convex.faces[{k}]"), format!("dip must lie in [0, 90] and dip_direction and point be finite, got dip {}, dip_direction {}", f.dip, f.dip_direction)));
                }
                ps.push(
                    Plane::from_coefficients(f.half_space())
                        .ok_or_else(|| geom(".convex.faces", GeomError::ZeroNormal { index: ps.len() }))?,
                );
            }
            let sub = if faces.is_empty() { ".convex.planes" } else { ".convex" };
            ConvexPolyhedron::from_planes(&ps).map(|p| vec![p]).map_err(|e| geom(sub, e))
        }
        Shape::Polyhedron { vertices, faces } => {
            polyhedron(vertices, faces).map_err(|(s, r)| (format!(".polyhedron{s}"), r))
        }
        Shape::Prism { polygon, z } => prism(polygon, *z).map_err(|r| (".prism".to_string(), r)),
        Shape::Tunnel(t) => tunnel_polyhedron(t).map(|p| vec![p]).map_err(|r| (".tunnel".to_string(), r)),
    }
}

fn polyhedron(vertices: &[[f64; 3]], faces: &[Vec<usize>]) -> Result<Vec<ConvexPolyhedron>, ShapeError> {
    let vs: Vec<Vec3> = vertices.iter().map(|v| Vec3::from(*v)).collect();
    check_closed(&vs, faces).map_err(|e| (String::new(), e.to_string()))?;
    let signed: f64 = ConvexPolyhedron {
        faces: faces
            .iter()
            .map(|f| Face { vertices: f.iter().map(|&i| vs[i]).collect(), tag: tags::body_face(0) })
            .collect(),
    }
    .volume();
    if signed < 0.0 {
        return Err((
            ".faces".into(),
            "the faces are oriented inwards: list each face's vertices counter-clockwise seen from outside".into(),
        ));
    }
    match ConvexPolyhedron::from_vertices_faces(&vs, faces) {
        Ok(p) => Ok(vec![p]),
        Err(GeomError::NotConvex { .. }) => {
            let fs: Vec<Face> = faces
                .iter()
                .enumerate()
                .map(|(k, f)| Face { vertices: f.iter().map(|&i| vs[i]).collect(), tag: tags::body_face(k) })
                .collect();
            let vol: f64 = ConvexPolyhedron { faces: fs.clone() }.volume();
            if !(vol > 0.0) {
                return Err((
                    String::new(),
                    "the faces are oriented inwards (they must be counter-clockwise seen from outside)".into(),
                ));
            }
            let pieces = convex_pieces(&fs, NewFaceTags { glue: tags::GLUE });
            check_volume(&pieces, vol).map_err(|r| (String::new(), r))?;
            Ok(pieces)
        }
        Err(e) => Err((String::new(), e.to_string())),
    }
}

fn check_volume(pieces: &[ConvexPolyhedron], expected: f64) -> Result<(), String> {
    let got: f64 = pieces.iter().map(|p| p.volume()).sum();
    if (got - expected).abs() > 1e-9 * expected {
        return Err(format!(
            "the solid could not be decomposed (volume {got} instead of {expected}): is it self-intersecting?"
        ));
    }
    Ok(())
}

fn prism(polygon: &[[f64; 2]], z: [f64; 2]) -> Result<Vec<ConvexPolyhedron>, String> {
    if polygon.len() < 3 {
        return Err("the polygon needs at least 3 vertices".into());
    }
    if !(z[0] < z[1]) {
        return Err("z = [z0, z1] needs z0 < z1".into());
    }
    if let Some((i, j)) = self_intersection(polygon) {
        return Err(format!("the polygon is not simple: edges {i} and {j} cross"));
    }
    let n = polygon.len();
    let area2: f64 = (0..n)
        .map(|i| {
            let (a, b) = (polygon[i], polygon[(i + 1) % n]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum();
    if area2.abs() <= 1e-14 {
        return Err("the polygon has no area".into());
    }
    let ccw: Vec<[f64; 2]> = if area2 > 0.0 { polygon.to_vec() } else { polygon.iter().rev().copied().collect() };
    let v = |i: usize, zz: f64| Vec3::new(ccw[i % n][0], ccw[i % n][1], zz);
    let mut faces = vec![
        Face { vertices: (0..n).rev().map(|i| v(i, z[0])).collect(), tag: tags::body_face(0) },
        Face { vertices: (0..n).map(|i| v(i, z[1])).collect(), tag: tags::body_face(1) },
    ];
    for i in 0..n {
        faces.push(Face {
            vertices: vec![v(i, z[0]), v(i + 1, z[0]), v(i + 1, z[1]), v(i, z[1])],
            tag: tags::body_face(2 + i),
        });
    }
    let convex = (0..n).all(|i| {
        let (a, b, c) = (ccw[i], ccw[(i + 1) % n], ccw[(i + 2) % n]);
        (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]) >= -1e-12
    });
    let vol = 0.5 * area2.abs() * (z[1] - z[0]);
    if convex {
        let planes: Vec<Plane> = faces
            .iter()
            .map(|f| Plane::from_point_normal(f.vertices[0], f.area_vector()).expect("non-degenerate"))
            .collect();
        let mut p = ConvexPolyhedron::from_planes(&planes).map_err(|e| e.to_string())?;
        p.faces.iter_mut().enumerate().for_each(|(k, f)| f.tag = tags::body_face(k));
        return Ok(vec![p]);
    }
    let pieces = convex_pieces(&faces, NewFaceTags { glue: tags::GLUE });
    check_volume(&pieces, vol)?;
    Ok(pieces)
}

/// First pair of non-adjacent edges that intersect.
fn self_intersection(p: &[[f64; 2]]) -> Option<(usize, usize)> {
    let n = p.len();
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    for i in 0..n {
        for j in i + 1..n {
            if j == i + 1 || (i == 0 && j == n - 1) {
                continue;
            }
            let (a, b, c, d) = (p[i], p[(i + 1) % n], p[j], p[(j + 1) % n]);
            let (d1, d2) = (cross(a, b, c), cross(a, b, d));
            let (d3, d4) = (cross(c, d, a), cross(c, d, b));
            if d1 * d2 <= 0.0 && d3 * d4 <= 0.0 && (d1 != 0.0 || d2 != 0.0) {
                return Some((i, j));
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_non_convex_prism_is_glued_pieces_of_the_right_volume() {
        let l = vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]];
        let pieces = prism(&l, [0.0, 1.0]).unwrap();
        let v: f64 = pieces.iter().map(|p| p.volume()).sum();
        assert!((v - 3.0).abs() < 1e-12);
        assert!(pieces.len() > 1);
        let reversed: Vec<[f64; 2]> = l.iter().rev().copied().collect();
        assert!((prism(&reversed, [0.0, 1.0]).unwrap().iter().map(|p| p.volume()).sum::<f64>() - 3.0).abs() < 1e-12);
        assert!(prism(&[[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]], [0.0, 1.0])
            .unwrap_err()
            .contains("not simple"));
    }
}
