//! Monitors: quantities of one block, recorded in `history.csv` and `summary.json`.
//! A block's displacement and velocity are those of its centroid (volume-weighted mean);
//! its rotation is the polar factor of the mean deformation gradient; stress is the
//! volume mean; volume is that of the current geometry.

use nmm3d_geom::{Mat3, Vec3};

use crate::element::kernel::stress_components;
use crate::element::loads::weights_at;
use crate::error::{Error, Result};
use crate::scenario::{MonitorLocation, MonitorSelect, Quantity};
use crate::state::Motion;
use crate::system::System;
use crate::time::corotation;

/// A monitor resolved against the model.
#[derive(Debug, Clone)]
pub struct MonitorPlan {
    /// Name.
    pub name: String,
    /// Block followed.
    pub block: usize,
    /// Quantities.
    pub quantities: Vec<Quantity>,
    /// (cover, ∫_block w dV / V): the centroid's interpolation weights.
    weights: Vec<(usize, f64)>,
    /// (cover, ∫_block ∇w dV / V): mean-gradient weights.
    gradients: Vec<(usize, Vec3)>,
    /// MEs of the block.
    elements: Vec<usize>,
}

impl MonitorPlan {
    /// Resolve every monitor of the scenario.
    pub fn all(sys: &System, label: &str) -> Result<Vec<Self>> {
        let mut out = Vec::new();
        for m in &sys.scenario.monitor {
            let block = match &m.select {
                MonitorSelect::Point(p) => sys.locate(&Vec3::from(*p)).map(|(b, _)| b).ok_or_else(|| {
                    Error::input(label, format!("monitor.{}.select.point", m.name), "the point is not inside any block")
                })?,
                MonitorSelect::Body(name) => {
                    let body = sys.scenario.body.iter().position(|b| &b.name == name).expect("validated");
                    let blocks: Vec<usize> =
                        (0..sys.geometry.blocks.len()).filter(|&b| sys.geometry.blocks[b].body == body).collect();
                    if blocks.len() != 1 {
                        return Err(Error::input(
                            label,
                            format!("monitor.{}.select.body", m.name),
                            format!("body '{name}' has {} blocks; select a block by point", blocks.len()),
                        ));
                    }
                    blocks[0]
                }
                MonitorSelect::Block(id) if *id < sys.geometry.blocks.len() => *id,
                MonitorSelect::Block(id) => {
                    let n = sys.geometry.blocks.len();
                    return Err(Error::input(
                        label,
                        format!("monitor.{}.select.block", m.name),
                        format!("there is no block {id} (the model has {n} blocks, ids 0..{n})"),
                    ));
                }
            };
            let mut plan = Self::new(sys, m.name.clone(), block, m.quantities.clone());
            if let (MonitorLocation::Point, MonitorSelect::Point(p)) = (m.location, &m.select) {
                let x = Vec3::from(*p);
                let (_, e) = sys.locate(&x).expect("located above");
                let me = &sys.covers.elements[e];
                plan.weights = me.covers.iter().copied().zip(weights_at(&sys.covers, me, &x)).collect();
            }
            out.push(plan);
        }
        Ok(out)
    }

    fn new(sys: &System, name: String, block: usize, quantities: Vec<Quantity>) -> Self {
        let vol = sys.geometry.blocks[block].volume;
        // Sums per cover, by cover index (a dense array: a block may hold 10⁶ MEs).
        let mut w: Vec<Option<(f64, Vec3)>> = vec![None; sys.covers.covers.len()];
        let elements: Vec<usize> =
            (0..sys.covers.elements.len()).filter(|&e| sys.covers.elements[e].block == block).collect();
        for &e in &elements {
            let k = sys.kernel(e);
            for (a, &c) in sys.covers.elements[e].covers.iter().enumerate() {
                let slot = w[c].get_or_insert((0.0, Vec3::zeros()));
                slot.0 += k.integral_w[a] / vol;
                slot.1 += k.mean_gradient[a] * k.volume / vol;
            }
        }
        let sums: Vec<(usize, (f64, Vec3))> =
            w.into_iter().enumerate().filter_map(|(c, s)| s.map(|s| (c, s))).collect();
        Self {
            name,
            block,
            quantities,
            weights: sums.iter().map(|(c, (a, _))| (*c, *a)).collect(),
            gradients: sums.iter().map(|(c, (_, g))| (*c, *g)).collect(),
            elements,
        }
    }

    /// Column names `<monitor>.<quantity>.<component>`.
    pub fn columns(&self) -> Vec<String> {
        self.quantities
            .iter()
            .flat_map(|q| q.components().iter().map(move |c| format!("{}.{}.{}", self.name, q.name(), c)))
            .collect()
    }

    /// Current values, in column order.
    pub fn values(&self, sys: &System, state: &Motion) -> Vec<f64> {
        let mut out = Vec::new();
        for q in &self.quantities {
            match q {
                Quantity::Displacement => out.extend(self.mean(|c| state.displacement(sys, c)).iter()),
                Quantity::Velocity => out.extend(self.mean(|c| state.v[c]).iter()),
                Quantity::Rotation => out.extend(corotation::rotation_vector(&self.rotation(state)).iter()),
                Quantity::Volume => out.push(self.volume(sys, state)),
                Quantity::Stress => out.extend(self.stress(sys, state)),
            }
        }
        out
    }

    fn mean(&self, f: impl Fn(usize) -> Vec3) -> Vec3 {
        self.weights.iter().map(|(c, w)| *w * f(*c)).sum()
    }

    fn rotation(&self, state: &Motion) -> Mat3 {
        let f: Mat3 = Mat3::identity() + self.gradients.iter().map(|(c, g)| state.u[*c] * g.transpose()).sum::<Mat3>();
        corotation::rotation(&f, &Mat3::identity())
    }

    fn volume(&self, sys: &System, state: &Motion) -> f64 {
        self.elements.iter().map(|&e| current_volume(sys, state, e)).sum()
    }

    fn stress(&self, sys: &System, state: &Motion) -> [f64; 6] {
        let vol = sys.geometry.blocks[self.block].volume;
        let s: Mat3 =
            self.elements.iter().map(|&e| corotation::element_stress(sys, state, e) * sys.kernel(e).volume / vol).sum();
        stress_components(&s)
    }
}

/// Current volume of ME `e`: every vertex mapped by x(ξ) = Σ w_a(ξ) x_a (exact for linear
/// covers; hex8 faces are flattened through their mapped vertices).
pub fn current_volume(sys: &System, state: &Motion, e: usize) -> f64 {
    let me = &sys.covers.elements[e];
    let w = sys.covers.weights(me);
    let place =
        |xi: &Vec3| -> Vec3 { me.covers.iter().zip(w).map(|(&c, wa)| wa.eval(xi) * state.position(sys, c)).sum() };
    me.parts.iter().map(|p| p.map(place).volume()).sum()
}
