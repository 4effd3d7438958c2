//! A frame's `.vtu`: every manifold element as a polyhedral cell at its current position, with
//! the point and cell data listed in [`super::vtu`]. The per-element work (cell shapes,
//! stresses) and the per-point work (interpolated positions, displacements, velocities) run in
//! parallel; only the sharing of points between cells is sequential, so the file is the same
//! for any number of threads.

use rayon::prelude::*;
use std::path::Path;

use nmm3d_geom::Vec3;

use super::vtu::{permute, point_key, Appended, Cells, Shape, POINT_QUANTUM};
use crate::element::kernel::stress_components;
use crate::error::Result;
use crate::state::Motion;
use crate::system::System;
use crate::time::corotation;

/// Write one frame.
pub fn write_frame(sys: &System, state: &Motion, path: &Path) -> Result<()> {
    let quantum = POINT_QUANTUM * sys.covers.mesh().size;
    let elements = &sys.covers.elements;
    let gathered: Vec<(Vec<Shape>, [f64; 6])> = (elements.par_iter().enumerate())
        .map(|(e, me)| {
            let key = |xi: &Vec3| point_key(me.block, &sys.covers.global(me, xi), quantum);
            let shapes = me.parts.iter().map(|p| Shape::of(p, key)).collect();
            (shapes, stress_components(&corotation::element_stress(sys, state, e)))
        })
        .collect();
    let mut cells = Cells::with_capacity(elements.len());
    // Each point's element and own coordinates, in point order.
    let mut sources: Vec<(usize, Vec3)> = Vec::new();
    let (mut block_id, mut element_id, mut stress) = (Vec::new(), Vec::new(), Vec::new());
    for (e, (shapes, sigma)) in gathered.iter().enumerate() {
        for shape in shapes {
            sources.extend(cells.add(shape).into_iter().map(|k| (e, shape.verts[k])));
            block_id.push(elements[e].block as i64);
            element_id.push(e as i64);
            stress.extend(sigma);
        }
    }
    drop(gathered);
    // Positions in the scenario's coordinates (the model runs in a local frame).
    let o = sys.geometry.origin;
    let values: Vec<[Vec3; 4]> = (sources.par_iter())
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
    cells.points = values.iter().map(|v| v[0]).collect();
    let column = |k: usize| values.iter().map(|v| v[k]).collect::<Vec<_>>();
    let mut bin = Appended::default();
    let mut point_data = String::from("<PointData Vectors=\"displacement\">\n");
    bin.vec3(&mut point_data, "displacement", &column(1));
    bin.vec3(&mut point_data, "velocity", &column(2));
    bin.vec3(&mut point_data, "reference_position", &column(3));
    point_data.push_str("</PointData>\n");
    let order = cells.order();
    let mut cell_data = String::from("<CellData Scalars=\"block_id\">\n");
    bin.i64(&mut cell_data, "block_id", 1, &permute(&block_id, 1, &order));
    bin.i64(&mut cell_data, "element_id", 1, &permute(&element_id, 1, &order));
    bin.f64(&mut cell_data, "stress", 6, &permute(&stress, 6, &order));
    cell_data.push_str("</CellData>\n");
    cells.write(path, &order, bin, &super::vtu::field_data(state.time), &point_data, &cell_data)
}
