//! The model in a local frame. Rock models sit at mine or survey coordinates (x ≈ 5·10⁵ m,
//! y ≈ 4·10⁶ m), where a double's last digit is ~10⁻⁹ m: cutting, covers and contact, whose
//! tolerances scale with the blocks, would then decide on round-off. A scenario far from the
//! origin against its size is run in a frame moved to a whole-metre point near its bodies;
//! the outputs add it back.

use super::schema::*;

/// A model is moved when its bodies' centre lies farther from the origin than this many times
/// their extent.
const FAR_RATIO: f64 = 100.0;

type V3 = [f64; 3];

impl Scenario {
    /// The local frame's origin [m]: the bodies' centre rounded to whole metres when the bodies
    /// lie far from the origin (`[0, 0, 0]` otherwise, so that such models run as given).
    pub fn local_origin(&self) -> V3 {
        let points: Vec<V3> = self.body.iter().flat_map(|b| shape_points(&b.shape)).collect();
        if points.is_empty() {
            return [0.0; 3];
        }
        let lo = points.iter().fold([f64::INFINITY; 3], |a, p| [0, 1, 2].map(|i| a[i].min(p[i])));
        let hi = points.iter().fold([f64::NEG_INFINITY; 3], |a, p| [0, 1, 2].map(|i| a[i].max(p[i])));
        let centre = [0, 1, 2].map(|i| 0.5 * (lo[i] + hi[i]));
        let extent = (0..3).map(|i| hi[i] - lo[i]).fold(0.0, f64::max);
        let far = centre.iter().map(|c| c.abs()).fold(0.0, f64::max) > FAR_RATIO * extent;
        if far && centre.iter().all(|c| c.is_finite()) {
            centre.map(f64::round)
        } else {
            [0.0; 3]
        }
    }

    /// The same scenario with every position taken relative to `o` [m].
    pub fn shifted(&self, o: V3) -> Scenario {
        if o == [0.0; 3] {
            return self.clone();
        }
        let p = |x: V3| [0, 1, 2].map(|i| x[i] - o[i]);
        let mut s = self.clone();
        s.cover.origin = p(s.cover.origin);
        for b in &mut s.body {
            shift_shape(&mut b.shape, o);
        }
        for e in &mut s.excavation {
            shift_shape(&mut e.shape, o);
        }
        s.joint_set.iter_mut().for_each(|j| j.origin = p(j.origin));
        s.joint_plane.iter_mut().for_each(|j| j.point = p(j.point));
        s.constraint.iter_mut().for_each(|c| shift_region(&mut c.select, o));
        s.surface_load.iter_mut().for_each(|l| shift_region(&mut l.select, o));
        s.fixed_point.iter_mut().for_each(|f| f.point = p(f.point));
        s.point_load.iter_mut().for_each(|f| f.point = p(f.point));
        s.bolt.iter_mut().for_each(|b| (b.head, b.anchor) = (p(b.head), p(b.anchor)));
        for m in &mut s.monitor {
            if let MonitorSelect::Point(x) = &mut m.select {
                *x = p(*x);
            }
        }
        if let Some(st) = &mut s.in_situ_stress {
            st.reference_z -= o[2];
        }
        if let Some(w) = &mut s.water {
            // The table is a height against gravity.
            let g = s.analysis.gravity;
            let norm = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
            if norm > 0.0 {
                w.table += (0..3).map(|i| g[i] / norm * o[i]).sum::<f64>();
            }
        }
        s
    }
}

/// Points that locate a shape: corners, vertices, axis ends, the planes' feet.
fn shape_points(shape: &Shape) -> Vec<V3> {
    match shape {
        Shape::Box { min, max } => vec![*min, *max],
        Shape::Polyhedron { vertices, .. } => vertices.clone(),
        Shape::Prism { polygon, z } => polygon.iter().flat_map(|q| [[q[0], q[1], z[0]], [q[0], q[1], z[1]]]).collect(),
        Shape::Tunnel(t) => vec![t.start, t.end],
        Shape::Convex { planes, faces } => {
            let all: Vec<[f64; 4]> = planes.iter().copied().chain(faces.iter().map(|f| f.half_space())).collect();
            convex_corners(&all)
        }
    }
}

/// Corners of the solid n·x ≤ d: cut near the planes' least-squares point c₀ (where the
/// clipping is exact), then moved back; c₀ alone when that fails.
fn convex_corners(planes: &[[f64; 4]]) -> Vec<V3> {
    use nmm3d_geom::{ConvexPolyhedron, Mat3, Plane, Vec3};
    let unit: Vec<Plane> = planes.iter().filter_map(|c| Plane::from_coefficients(*c)).collect();
    let a: Mat3 = unit.iter().map(|p| p.normal * p.normal.transpose()).sum();
    let b: Vec3 = unit.iter().map(|p| p.normal * p.offset).sum();
    let Some(c0) = a.try_inverse().map(|inv| inv * b) else {
        return Vec::new();
    };
    let local: Vec<Plane> = unit.iter().map(|p| Plane { offset: p.offset - p.normal.dot(&c0), ..*p }).collect();
    match ConvexPolyhedron::from_planes(&local) {
        Ok(poly) => poly.vertices().iter().map(|v| [v.x + c0.x, v.y + c0.y, v.z + c0.z]).collect(),
        Err(_) => vec![[c0.x, c0.y, c0.z]],
    }
}

fn shift_shape(shape: &mut Shape, o: V3) {
    let p = |x: &mut V3| (0..3).for_each(|i| x[i] -= o[i]);
    match shape {
        Shape::Box { min, max } => {
            p(min);
            p(max);
        }
        Shape::Polyhedron { vertices, .. } => vertices.iter_mut().for_each(p),
        Shape::Prism { polygon, z } => {
            polygon.iter_mut().for_each(|q| (q[0], q[1]) = (q[0] - o[0], q[1] - o[1]));
            z.iter_mut().for_each(|z| *z -= o[2]);
        }
        Shape::Tunnel(t) => {
            p(&mut t.start);
            p(&mut t.end);
        }
        Shape::Convex { planes, faces } => {
            // n·(x + o) ≤ d  ⇔  n·x ≤ d − n·o.
            planes.iter_mut().for_each(|c| c[3] -= c[0] * o[0] + c[1] * o[1] + c[2] * o[2]);
            faces.iter_mut().for_each(|f| p(&mut f.point));
        }
    }
}

fn shift_region(r: &mut Region, o: V3) {
    let Region::Box { min, max } = r;
    (0..3).for_each(|i| (min[i], max[i]) = (min[i] - o[i], max[i] - o[i]));
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scenario(x: f64) -> Scenario {
        let text = format!(
            r#"
            [[material]]
            name = "r"
            density = 2500.0
            young = 1e9
            poisson = 0.2
            [[body]]
            name = "b"
            material = "r"
            shape = {{ box = {{ min = [{x}, 4e6, 100.0], max = [{x1}, 4000001.0, 101.0] }} }}
            [[monitor]]
            name = "m"
            select = {{ point = [{xm}, 4000000.5, 100.5] }}
            quantities = ["displacement"]
            "#,
            x1 = x + 1.0,
            xm = x + 0.5
        );
        toml::from_str(&text).unwrap()
    }

    #[test]
    fn a_model_at_survey_coordinates_moves_to_a_whole_metre_near_it() {
        let s = scenario(500_000.25);
        let o = s.local_origin();
        assert_eq!(o, [500_001.0, 4_000_001.0, 101.0]);
        let local = s.shifted(o);
        let Shape::Box { min, .. } = &local.body[0].shape else { panic!() };
        assert_eq!(*min, [-0.75, -1.0, -1.0]);
        let MonitorSelect::Point(x) = local.monitor[0].select else { panic!() };
        assert_eq!(x, [-0.25, -0.5, -0.5]);
    }

    #[test]
    fn a_model_near_the_origin_stays_where_it_is() {
        let mut s = scenario(0.0);
        s.body[0].shape = Shape::Box { min: [0.0, 0.0, 0.0], max: [1.0, 1.0, 1.0] };
        assert_eq!(s.local_origin(), [0.0; 3]);
    }
}
