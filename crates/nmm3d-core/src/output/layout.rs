//! A frame's layout: what a `.vtu` frame holds that stays while the model's MEs do — the
//! polyhedral cells with their shared points, the ME and own coordinates each point is
//! interpolated from, and the order the cells are written in. Made by the first frame of a
//! model and kept for the next ones, so a frame computes only what moves (stresses, positions,
//! velocities). The cell shapes are made in parallel; only the sharing of points between cells
//! is sequential, so the layout is the same for any number of threads.

use rayon::prelude::*;

use nmm3d_geom::Vec3;

use super::vtu::{point_key, Cells, Shape, POINT_QUANTUM};
use crate::system::System;

/// The cells of a model's frames and where their points come from.
pub struct FrameLayout {
    /// The cells; their `points` are placed by each frame.
    pub(super) cells: Cells,
    /// Each point's ME and its coordinates in that ME's frame, in point order.
    pub(super) sources: Vec<(usize, Vec3)>,
    /// The order the cells are written in ([`Cells::order`]).
    pub(super) order: Vec<usize>,
    /// Each written cell's ME, in that order.
    pub(super) written: Vec<usize>,
    /// The model's MEs and covers when it was made.
    made_for: (usize, usize),
}

impl FrameLayout {
    /// The layout of `sys`'s MEs: one cell per part of each ME.
    pub fn of(sys: &System) -> Self {
        let quantum = POINT_QUANTUM * sys.covers.mesh().size;
        let elements = &sys.covers.elements;
        let shapes: Vec<Vec<Shape>> = (elements.par_iter())
            .map(|me| {
                let key = |xi: &Vec3| point_key(me.block, &sys.covers.global(me, xi), quantum);
                me.parts.iter().map(|p| Shape::of(p, key)).collect()
            })
            .collect();
        let mut cells = Cells::with_capacity(elements.len());
        let (mut sources, mut element_of) = (Vec::new(), Vec::with_capacity(elements.len()));
        for (e, parts) in shapes.iter().enumerate() {
            for shape in parts {
                sources.extend(cells.add(shape).into_iter().map(|k| (e, shape.verts[k])));
                element_of.push(e);
            }
        }
        let order = cells.order();
        let written = order.iter().map(|&i| element_of[i]).collect();
        Self { cells, sources, order, written, made_for: (elements.len(), sys.covers.covers.len()) }
    }

    /// Whether this layout may be of `sys`'s model (the recorder drops it when a stage changes
    /// the model; this guards against a layout of another model's size).
    pub fn fits(&self, sys: &System) -> bool {
        self.made_for == (sys.covers.elements.len(), sys.covers.covers.len())
    }
}
