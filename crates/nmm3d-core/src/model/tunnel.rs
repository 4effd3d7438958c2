//! Tunnel profiles swept along an axis (excavation shapes).
//!
//! The profile lies in the plane normal to the axis start → end, centred on the axis, with its
//! floor (bottom) `height / 2` (`radius`) below it; "up" is +z projected off the axis (+x for a
//! vertical axis). Curves are approximated by inscribed polygons:
//! * `horseshoe`: flat floor, vertical walls, semicircular crown of diameter `width`, total
//!   `height` (≥ width / 2); `segments` straight pieces on the crown (default 16);
//! * `circular`: `radius`, `segments` pieces on the full circle (default 32);
//!   `segments` at most [`MAX_SEGMENTS`];
//! * `rectangular`: `width` × `height`.

use nmm3d_geom::{ConvexPolyhedron, Plane, Vec3};

use crate::scenario::Tunnel;

/// Default pieces of a horseshoe crown.
pub const HORSESHOE_SEGMENTS: u32 = 16;
/// Default pieces of a circle.
pub const CIRCLE_SEGMENTS: u32 = 32;

/// The profile polygon (counter-clockwise, in (side, up) coordinates) or the reason it is invalid.
pub fn profile(t: &Tunnel) -> Result<Vec<[f64; 2]>, String> {
    let pos = |name: &str, v: Option<f64>| -> Result<f64, String> {
        match v {
            Some(x) if x > 0.0 && x.is_finite() => Ok(x),
            Some(x) => Err(format!("{name} must be > 0, got {x}")),
            None => Err(format!("profile \"{}\" needs {name}", t.profile)),
        }
    };
    match t.profile.as_str() {
        "rectangular" => {
            let (w, h) = (pos("width", t.width)?, pos("height", t.height)?);
            Ok(vec![[-w / 2.0, -h / 2.0], [w / 2.0, -h / 2.0], [w / 2.0, h / 2.0], [-w / 2.0, h / 2.0]])
        }
        "circular" => {
            let r = pos("radius", t.radius)?;
            let n = segments(t, CIRCLE_SEGMENTS)?;
            Ok((0..n)
                .map(|i| {
                    let a = -std::f64::consts::FRAC_PI_2 + 2.0 * std::f64::consts::PI * i as f64 / n as f64;
                    [r * a.cos(), r * a.sin()]
                })
                .collect())
        }
        "horseshoe" => {
            let (w, h) = (pos("width", t.width)?, pos("height", t.height)?);
            if h < w / 2.0 {
                return Err(format!("a horseshoe needs height ≥ width / 2 (got {h} < {})", w / 2.0));
            }
            let n = segments(t, HORSESHOE_SEGMENTS)?;
            let centre = h / 2.0 - w / 2.0;
            let mut p = vec![[-w / 2.0, -h / 2.0], [w / 2.0, -h / 2.0]];
            for i in 0..=n {
                let a = std::f64::consts::PI * i as f64 / n as f64;
                p.push([w / 2.0 * a.cos(), centre + w / 2.0 * a.sin()]);
            }
            if centre <= -h / 2.0 {
                // No vertical wall: the crown starts on the floor.
                p.retain(|q| q[1] > -h / 2.0 || q[0].abs() == w / 2.0);
                p.dedup();
            }
            Ok(p)
        }
        other => Err(format!("unknown profile \"{other}\" (horseshoe, circular, rectangular)")),
    }
}

/// Most straight pieces of a profile: a circle of 10⁴ chords deviates by 5·10⁻⁸ of its radius,
/// far below any rock joint's roughness; more would only cost memory and time.
pub const MAX_SEGMENTS: u32 = 10_000;

fn segments(t: &Tunnel, default: u32) -> Result<u32, String> {
    match t.segments {
        None => Ok(default),
        Some(n) if (3..=MAX_SEGMENTS).contains(&n) => Ok(n),
        Some(n) => Err(format!("segments must lie in 3..={MAX_SEGMENTS}, got {n}")),
    }
}

/// Axis frame: unit axis, side and up vectors.
fn frame(t: &Tunnel) -> Result<(Vec3, Vec3, Vec3), String> {
    if !t.start.iter().chain(&t.end).all(|v| v.is_finite()) {
        return Err("start and end must be finite points".into());
    }
    let axis = Vec3::from(t.end) - Vec3::from(t.start);
    let len = axis.norm();
    if !(len > 0.0) {
        return Err("the tunnel has zero length (start = end)".into());
    }
    let a = axis / len;
    let up_hint = if a.z.abs() > 1.0 - 1e-9 { Vec3::x() } else { Vec3::z() };
    let up = (up_hint - a * a.dot(&up_hint)).normalize();
    let side = a.cross(&up);
    Ok((a, side, up))
}

/// The tunnel as a convex polyhedron (faces: the two ends, then one per profile edge).
pub fn tunnel_polyhedron(t: &Tunnel) -> Result<ConvexPolyhedron, String> {
    let prof = profile(t)?;
    let (a, side, up) = frame(t)?;
    let (s, e) = (Vec3::from(t.start), Vec3::from(t.end));
    let point = |q: &[f64; 2]| s + side * q[0] + up * q[1];
    let mut planes =
        vec![Plane::from_point_normal(s, -a).expect("unit"), Plane::from_point_normal(e, a).expect("unit")];
    let n = prof.len();
    for i in 0..n {
        let (p0, p1) = (point(&prof[i]), point(&prof[(i + 1) % n]));
        // (side, up) turn about −a (side × up = −a), so a counter-clockwise profile's outward
        // edge normal is (p1 − p0) × (−a) = a × (p1 − p0).
        let outward = a.cross(&(p1 - p0));
        planes.push(Plane::from_point_normal(p0, outward).ok_or("two profile points coincide")?);
    }
    ConvexPolyhedron::from_planes(&planes).map_err(|e| e.to_string())
}

/// Area of the profile polygon [m²].
pub fn profile_area(t: &Tunnel) -> Result<f64, String> {
    let p = profile(t)?;
    Ok(0.5
        * (0..p.len())
            .map(|i| {
                let (a, b) = (p[i], p[(i + 1) % p.len()]);
                a[0] * b[1] - a[1] * b[0]
            })
            .sum::<f64>())
}
