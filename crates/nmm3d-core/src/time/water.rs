//! Hydrostatic water pressure on the faces as they are now: a follower load.
//!
//! Each wet ME is taken as moved rigidly by its co-rotation R and the displacement of its
//! centroid X_c: x = x_c + R (X − X_c). The height of a point is then up·x = up·x_c −
//! up′·X_c + up′·X with up′ = Rᵀ up, so the reference faces are integrated below the table
//! table′ = table − up·x_c + up′·X_c along up′, and the forces turned by R. A pressure held on
//! the reference faces (a dead load) is wrong as soon as a block turns: the pushes on opposite
//! faces then make a couple that grows with the turn — a sliding submerged block spun up.

use nmm3d_geom::Vec3;
use rayon::prelude::*;

use crate::element::loads::{hydrostatic_forces, weights_at};
use crate::state::Motion;
use crate::system::System;

/// Add the water pressure's nodal forces at the current state to `loads`.
pub(super) fn add_water(sys: &System, state: &Motion, loads: &mut [Vec3]) {
    let Some(w) = sys.water.as_ref() else { return };
    let forces: Vec<(usize, Vec<Vec3>)> = w
        .elements
        .par_iter()
        .enumerate()
        .filter_map(|(k, &e)| {
            let me = &sys.covers.elements[e];
            let r = state.rotations[e];
            let x0 = me.centroid(sys.covers.mesh_of(me));
            let u: Vec3 = weights_at(&sys.covers, me, &x0).iter().zip(&me.covers).map(|(w, &c)| *w * state.u[c]).sum();
            let up = r.transpose() * w.up;
            let table = w.table - w.up.dot(&(x0 + u)) + up.dot(&x0);
            let f = match &w.wet {
                Some(wet) => {
                    hydrostatic_forces(&sys.covers, me, wet[k].iter().map(|p| p.as_slice()), (table, up), w.unit_weight)
                }
                None => {
                    let faces = me.boundary_faces().map(|f| f.vertices.as_slice());
                    hydrostatic_forces(&sys.covers, me, faces, (table, up), w.unit_weight)
                }
            }?;
            Some((e, f.iter().map(|f| r * f).collect()))
        })
        .collect();
    for (e, f) in forces {
        for (&c, f) in sys.covers.elements[e].covers.iter().zip(f) {
            loads[c] += f;
        }
    }
}
