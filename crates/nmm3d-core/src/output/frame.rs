//! A frame's `.vtu`: every manifold element as a polyhedral cell at its current position, with
//! the point and cell data listed in [`super::vtu`]. The cells and their points' sources come
//! from the model's [`FrameLayout`] (made by its first frame); the per-element work (stresses)
//! and the per-point work (interpolated positions, displacements, velocities) run in parallel,
//! so the file is the same for any number of threads.

use rayon::prelude::*;
use std::path::Path;

use nmm3d_geom::Vec3;

use super::layout::FrameLayout;
use super::vtu::Appended;
use crate::element::kernel::stress_components;
use crate::error::Result;
use crate::state::Motion;
use crate::system::System;
use crate::time::corotation;

/// Write one frame, with `layout` (made here if it is `None` or of another model).
pub fn write_frame(sys: &System, state: &Motion, path: &Path, layout: &mut Option<FrameLayout>) -> Result<()> {
    let layout = match layout {
        Some(l) if l.fits(sys) => l,
        _ => layout.insert(FrameLayout::of(sys)),
    };
    let elements = &sys.covers.elements;
    let stress: Vec<[f64; 6]> = (0..elements.len())
        .into_par_iter()
        .map(|e| stress_components(&corotation::element_stress(sys, state, e)))
        .collect();
    // Positions in the scenario's coordinates (the model runs in a local frame).
    let o = sys.geometry.origin;
    let values: Vec<[Vec3; 4]> = (layout.sources.par_iter())
        .map(|&(e, xi)| {
            let me = &elements[e];
            let w = sys.covers.weights(me);
            let interpolate = |f: &dyn Fn(usize) -> Vec3| -> Vec3 {
                me.covers.iter().zip(w).map(|(&c, wa)| wa.eval(&xi) * f(c)).sum()
            };
            [
                interpolate(&|c| state.position(sys, c)) + o,
                interpolate(&|c| state.u[c]),
                interpolate(&|c| state.v[c]),
                interpolate(&|c| sys.covers.covers[c].position) + o,
            ]
        })
        .collect();
    layout.cells.points = values.iter().map(|v| v[0]).collect();
    let column = |k: usize| values.iter().map(|v| v[k]).collect::<Vec<_>>();
    let mut bin = Appended::default();
    let mut point_data = String::from("<PointData Vectors=\"displacement\">\n");
    bin.vec3(&mut point_data, "displacement", &column(1));
    bin.vec3(&mut point_data, "velocity", &column(2));
    bin.vec3(&mut point_data, "reference_position", &column(3));
    point_data.push_str("</PointData>\n");
    let written = &layout.written;
    let block_id: Vec<i64> = written.iter().map(|&e| elements[e].block as i64).collect();
    let element_id: Vec<i64> = written.iter().map(|&e| e as i64).collect();
    let stress: Vec<f64> = written.iter().flat_map(|&e| stress[e]).collect();
    let mut cell_data = String::from("<CellData Scalars=\"block_id\">\n");
    bin.i64(&mut cell_data, "block_id", 1, &block_id);
    bin.i64(&mut cell_data, "element_id", 1, &element_id);
    bin.f64(&mut cell_data, "stress", 6, &stress);
    cell_data.push_str("</CellData>\n");
    let field = super::vtu::field_data(state.time);
    layout.cells.write(path, &layout.order, bin, &field, &point_data, &cell_data)
}
