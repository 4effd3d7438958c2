//! Loads on the covers: body force, initial (in-situ) stress, point loads and surface tractions.
//! All are dead loads evaluated in the reference configuration; initial stress co-rotates with
//! each ME (see `time::corotation`).

use nmm3d_geom::{integrate, Vec3};

use super::kernel::stress_matrix;
use crate::cover::mesh::cell_corner;
use crate::cover::poly::{self, Poly, TERMS};
use crate::cover::{Covers, ManifoldElement};
use crate::scenario::{InSituStress, Region};

/// In-situ stress at height z: σ(z) = σ_ref + (z − z_ref) · gradient, compression negative.
pub fn in_situ_at(s: &InSituStress, z: f64) -> [f64; 6] {
    let mut out = s.stress;
    for (o, g) in out.iter_mut().zip(s.gradient.iter()) {
        *o += (z - s.reference_z) * g;
    }
    out
}

/// Initial-stress nodal forces f_a = ∫ σ₀(z) ∇w_a dV (the internal force of the initial
/// stress, thesis §3.3 "initial stress matrix") and the ME's mean initial stress.
pub fn initial_stress(covers: &Covers, e: &ManifoldElement, s: &InSituStress) -> (Vec<Vec3>, [f64; 6]) {
    let mesh = covers.mesh_of(e);
    let (sz, r) = (mesh.size, mesh.rotation);
    let z_corner = mesh.to_global(&cell_corner(e.cell)).z;
    let rz = r.row(2).transpose() * sz; // z(ξ) = z_corner + rz·ξ
    let base = stress_matrix(&s.stress);
    let grad = stress_matrix(&s.gradient);
    let dz = Poly::affine(z_corner - s.reference_z, rz);
    let forces = covers
        .weights(e)
        .iter()
        .map(|w| {
            let d = [w.derivative(0), w.derivative(1), w.derivative(2)];
            let h = Vec3::new(d[0].integrate(&e.moments), d[1].integrate(&e.moments), d[2].integrate(&e.moments));
            let q = Vec3::new(
                dz.mul(&d[0]).integrate(&e.moments),
                dz.mul(&d[1]).integrate(&e.moments),
                dz.mul(&d[2]).integrate(&e.moments),
            );
            // ∫ ∂_i w dV = s² (R h)_i; ∫ (z − z_ref) ∂_i w dV = s² (R q)_i.
            base * (sz * sz * (r * h)) + grad * (sz * sz * (r * q))
        })
        .collect();
    (forces, in_situ_at(s, e.centroid(mesh).z))
}

/// Nodal forces of hydrostatic water pressure p = γ_w (table − h) on the parts of an ME's
/// wet `faces` (cell-local polygons, outward by their vertex order: its boundary faces, or
/// the parts of them other blocks touch) below the water table, h = up·x the height along `up`
/// (against gravity): f_a = −n ∫ w_a p dA per face (the pressure pushes into the block);
/// `None` when no face is wet.
pub fn hydrostatic_forces<'a>(
    covers: &Covers,
    e: &ManifoldElement,
    faces: impl Iterator<Item = &'a [Vec3]>,
    (table, up): (f64, Vec3),
    unit_weight: f64,
) -> Option<Vec<Vec3>> {
    let mesh = covers.mesh_of(e);
    let (sz, r) = (mesh.size, mesh.rotation);
    let h_corner = up.dot(&mesh.to_global(&cell_corner(e.cell)));
    let rz = r.transpose() * up * sz; // h(ξ) = h_corner + rz·ξ
                                      // Below the table: rz·ξ ≤ table − h_corner.
    let wet = nmm3d_geom::Plane::from_coefficients([rz.x, rz.y, rz.z, table - h_corner])?;
    let pressure = Poly::affine(unit_weight * (table - h_corner), -unit_weight * rz);
    let exps = poly::all_exponents();
    let weights = covers.weights(e);
    let mut total: Option<Vec<Vec3>> = None;
    for f in faces {
        let part = nmm3d_geom::polygon::clip_polygon_to(f, &wet, 1e-12);
        if part.len() < 3 {
            continue;
        }
        let m: [f64; TERMS] = integrate::polygon_moments(&part, &exps).try_into().expect("27 moments");
        let n = (r * nmm3d_geom::polygon::area_vector(f)).normalize();
        let forces = weights.iter().map(|w| -n * (w.mul(&pressure).integrate(&m) * sz * sz));
        total = Some(match total {
            None => forces.collect(),
            Some(t) => t.iter().zip(forces).map(|(a, b)| a + b).collect(),
        });
    }
    total
}

/// Weight-function values of an ME's nodes at a global reference point.
pub fn weights_at(covers: &Covers, e: &ManifoldElement, x: &Vec3) -> Vec<f64> {
    let xi = covers.cell_local(e, x);
    covers.weights(e).iter().map(|w| w.eval(&xi)).collect()
}

/// Largest angle between a loaded face's normal and the requested one.
const NORMAL_TOLERANCE_DEG: f64 = 1.0;

/// ∫_F w_a dA over the ME's boundary faces lying in `region` (every vertex inside) and, when
/// `normal` is given, facing that way; per node [m²].
pub fn boundary_face_integrals(
    covers: &Covers,
    e: &ManifoldElement,
    region: &Region,
    normal: Option<Vec3>,
) -> Option<Vec<f64>> {
    let Region::Box { min, max } = region;
    let bb = nmm3d_geom::Aabb { min: Vec3::from(*min), max: Vec3::from(*max) };
    let mesh = covers.mesh_of(e);
    let s2 = mesh.size * mesh.size;
    let exps: Vec<_> = (0..TERMS).map(poly::exponent).filter(|e| e.iter().all(|&k| k <= 1)).collect();
    let mut total: Option<Vec<f64>> = None;
    let cos_tol = NORMAL_TOLERANCE_DEG.to_radians().cos();
    for f in e.boundary_faces() {
        let inside = f.vertices.iter().all(|v| bb.contains(&covers.global(e, v), 1e-9 * covers.mesh().size));
        let facing =
            normal.is_none_or(|n| (mesh.rotation * f.area_vector()).normalize().dot(&n.normalize()) >= cos_tol);
        if !inside || !facing {
            continue;
        }
        let vals = integrate::polygon_moments(&f.vertices, &exps);
        let mut m = [f64::NAN; TERMS];
        for (ex, v) in exps.iter().zip(vals) {
            m[ex[0] as usize + 3 * ex[1] as usize + 9 * ex[2] as usize] = v;
        }
        let per_node: Vec<f64> = covers.weights(e).iter().map(|w| w.integrate(&m) * s2).collect();
        total = Some(match total {
            None => per_node,
            Some(t) => t.iter().zip(per_node).map(|(a, b)| a + b).collect(),
        });
    }
    total
}
