//! The discretised, immutable model: geometry, covers, element kernels, loads, constraints,
//! equation numbering and the assembler. Built once per run; `State` carries what changes.

use rustc_hash::FxHashMap;
use std::time::Instant;

use nmm3d_geom::Vec3;

use crate::assembly::assembler::masters_of;
use crate::assembly::{Assembler, DofMap, SparsityPattern};
use crate::cover::pattern::parity;
use crate::cover::{aggregation, Covers, PatternTable};
use crate::element::bolt::BoltSpring;
use crate::element::{element_kernel, loads, penalty, ElementKernel, PointConstraint};
use crate::error::{Error, Result};
use crate::model::Geometry;
use crate::scenario::{Scenario, Stiffness};

mod bolts;
mod held;
mod water;

pub use bolts::BoltNode;

/// Hydrostatic water pressure p = γ_w (table − up·x) on the wet boundary faces.
#[derive(Debug, Clone)]
pub struct WaterLoad {
    /// Height of the water table along `up` [m].
    pub table: f64,
    /// Unit vector against gravity.
    pub up: Vec3,
    /// γ_w = ρ_w g [N/m³].
    pub unit_weight: f64,
    /// MEs of the movable blocks with a wet face.
    pub elements: Vec<usize>,
    /// Drained free faces: each of `elements`' wet polygons (cell-local), the parts of its
    /// boundary faces that other blocks touch; none: every boundary face (submerged).
    pub wet: Option<Vec<Vec<Vec<Vec3>>>>,
}

/// Everything that does not change during a run.
pub struct System {
    /// The validated scenario.
    pub scenario: Scenario,
    /// Blocks and materials.
    pub geometry: Geometry,
    /// Mathematical mesh, MEs and physical covers.
    pub covers: Covers,
    /// Distinct kernels (identical full sub-cells share one).
    pub kernels: Vec<ElementKernel>,
    /// Kernel of each ME.
    pub kernel_of: Vec<usize>,
    /// Initial-stress nodal forces per ME (empty without in-situ stress).
    pub initial_forces: Vec<Vec<Vec3>>,
    /// Mean initial stress per ME [Pa] (zeros without in-situ stress).
    pub initial_stress: Vec<[f64; 6]>,
    /// Equation numbering.
    pub dofs: DofMap,
    /// Scatter maps and pattern.
    pub assembler: Assembler,
    /// Assembled consistent mass (values on the pattern).
    pub mass_values: Vec<f64>,
    /// External dead load per cover [N] (gravity with the pseudo-static seismic coefficient).
    pub external: Vec<Vec3>,
    /// Hydrostatic water pressure (`[water]`), applied on the current faces each step.
    pub water: Option<WaterLoad>,
    /// Mass per cover, ρ ∫ w dV [kg]: the load of a unit uniform acceleration (a base motion).
    pub cover_mass: Vec<f64>,
    /// Penalty points.
    pub constraints: Vec<PointConstraint>,
    /// Rock bolts' springs (an anchored bolt one, a grouted bolt one per joint it crosses);
    /// spring `k` is clique `elements + k` of the assembler.
    pub bolts: Vec<BoltSpring>,
    /// Each scenario bolt's nodes, for the frames.
    pub bolt_paths: Vec<Vec<BoltNode>>,
    /// Penalty stiffness [N/m].
    pub penalty: f64,
    /// Half the largest model extent, w₀ of the displacement ratio [m].
    pub half_size: f64,
    /// Seconds spent building covers and assembling constant parts.
    pub timings: Vec<(String, f64)>,
    /// Each block's vertices as its covers move them (a static analysis's travel limit).
    pub travel_points: held::TravelPoints,
}

impl System {
    /// Discretise a validated scenario (`label` names it in error messages).
    pub fn build(scenario: Scenario, label: &str) -> Result<Self> {
        let geometry = Geometry::from_scenario(&scenario);
        geometry.require_blocks(label)?;
        let extent = geometry.aabb().extent();
        Self::on_geometry(scenario, geometry, extent, label)
    }

    /// Discretise the blocks `geometry` of a validated scenario, the cover sized for a model of
    /// `ext` [m] (a stage's blocks take the whole rock mass's, so that every stage has one mesh).
    pub fn on_geometry(scenario: Scenario, geometry: Geometry, ext: Vec3, label: &str) -> Result<Self> {
        geometry.require_blocks(label)?;
        let t = Instant::now();
        // Everything else in the blocks' local frame too (points, regions, the cover's origin).
        let scenario = scenario.shifted(geometry.origin.into());
        let size = crate::model::estimate::cover_size(&scenario.cover, ext);
        let c = &scenario.cover;
        let (meshes, of_block) = crate::cover::meshes::model_meshes(&scenario, &geometry, size, Vec3::from(c.origin));
        let covers = Covers::build(&geometry, meshes, of_block, PatternTable::new(c.pattern));
        let t_covers = t.elapsed().as_secs_f64();

        let t = Instant::now();
        let (kernels, kernel_of) = build_kernels(&covers, &geometry);
        let (initial_forces, initial_stress) = match &scenario.in_situ_stress {
            Some(s) => covers.elements.iter().map(|e| loads::initial_stress(&covers, e, s)).unzip(),
            None => (vec![Vec::new(); covers.elements.len()], vec![[0.0; 6]; covers.elements.len()]),
        };
        let fixed_block: Vec<bool> = geometry.blocks.iter().map(|b| b.fixed).collect();
        let tied = aggregation::tie_ill_posed(&covers, &fixed_block, scenario.cover.aggregation_threshold);
        let fixed: Vec<bool> = covers.covers.iter().map(|c| fixed_block[c.block]).collect();
        let dofs = DofMap::new(&fixed, &tied);
        let (bolts, bolt_paths) = bolts::bolt_springs(&scenario, &geometry, &covers, label)?;
        let bolt_cliques: Vec<&[usize]> = bolts.iter().map(|b| b.covers.as_slice()).collect();
        let (assembler, mass_values) = pattern_and_mass(&covers, &dofs, &kernels, &kernel_of, &bolt_cliques);
        let max_young = geometry.materials.iter().map(|m| m.young).fold(0.0, f64::max);
        let penalty = match scenario.analysis.penalty_stiffness {
            Stiffness::Value(v) => v,
            Stiffness::Auto => scenario.analysis.penalty_factor * max_young * size,
        };
        let mut sys = Self {
            external: vec![Vec3::zeros(); covers.covers.len()],
            water: None,
            cover_mass: vec![0.0; covers.covers.len()],
            constraints: Vec::new(),
            bolts,
            bolt_paths,
            half_size: 0.5 * ext.max(),
            scenario,
            geometry,
            covers,
            kernels,
            kernel_of,
            initial_forces,
            initial_stress,
            dofs,
            assembler,
            mass_values,
            penalty,
            timings: Vec::new(),
            travel_points: Vec::new(),
        };
        sys.travel_points = held::travel_points(&sys.scenario, &sys.geometry, &sys.covers);
        sys.add_loads(label)?;
        sys.add_constraints(label)?;
        sys.timings = vec![("covers".into(), t_covers), ("assembly_setup".into(), t.elapsed().as_secs_f64())];
        Ok(sys)
    }

    /// Number of free equations.
    pub fn n_eq(&self) -> usize {
        self.dofs.n_eq
    }

    /// Total linear momentum Σ M v of the movable blocks [kg m/s] (consistent masses).
    pub fn momentum(&self, v: &[Vec3]) -> Vec3 {
        let mut p = Vec3::zeros();
        for (e, me) in self.covers.elements.iter().enumerate() {
            if self.geometry.blocks[me.block].fixed {
                continue;
            }
            let k = self.kernel(e);
            let n = me.covers.len();
            for a in 0..n {
                for b in 0..n {
                    p += k.mass[a * n + b] * v[me.covers[b]];
                }
            }
        }
        p
    }

    /// Kernel of ME `e`.
    pub fn kernel(&self, e: usize) -> &ElementKernel {
        &self.kernels[self.kernel_of[e]]
    }

    /// The block holding a reference point (first match), and the ME.
    pub fn locate(&self, x: &Vec3) -> Option<(usize, usize)> {
        locate(&self.geometry, &self.covers, x)
    }

    /// The body force of a base acceleration `a` [m/s²]: −m a per cover [N] (the run is in the
    /// base's frame).
    pub fn base_force(&self, a: [f64; 3]) -> Vec<Vec3> {
        let a = Vec3::from(a);
        self.cover_mass.iter().map(|m| -m * a).collect()
    }

    fn add_loads(&mut self, label: &str) -> Result<()> {
        let g = Vec3::from(self.scenario.analysis.gravity);
        // Pseudo-static seismic coefficients: an extra body force k m |g|.
        let g = g + Vec3::from(self.scenario.seismic.coefficient) * g.norm();
        for (e, me) in self.covers.elements.iter().enumerate() {
            let rho = self.geometry.materials[self.geometry.blocks[me.block].material].density;
            let k = &self.kernels[self.kernel_of[e]];
            for (a, &c) in me.covers.iter().enumerate() {
                self.external[c] += rho * k.integral_w[a] * g;
                self.cover_mass[c] += rho * k.integral_w[a];
            }
        }
        if let Some(w) = self.scenario.water.clone() {
            let g = Vec3::from(self.scenario.analysis.gravity);
            if g.norm() > 0.0 {
                let drained = w.free_faces == crate::scenario::FreeFaces::Drained;
                self.add_water((w.table, -g.normalize()), w.density * g.norm(), drained);
            }
        }
        for (i, pl) in self.scenario.point_load.clone().iter().enumerate() {
            let x = Vec3::from(pl.point);
            let (_, e) = self.locate(&x).ok_or_else(|| {
                Error::input(label, format!("point_load[{i}].point"), "the point is not inside any block")
            })?;
            let w = loads::weights_at(&self.covers, &self.covers.elements[e], &x);
            for (a, &c) in self.covers.elements[e].covers.iter().enumerate() {
                self.external[c] += w[a] * Vec3::from(pl.force);
            }
        }
        for (i, sl) in self.scenario.surface_load.clone().iter().enumerate() {
            let mut hit = false;
            for me in &self.covers.elements {
                if let Some(ints) =
                    loads::boundary_face_integrals(&self.covers, me, &sl.select, sl.normal.map(Vec3::from))
                {
                    hit = true;
                    for (a, &c) in me.covers.iter().enumerate() {
                        self.external[c] += ints[a] * Vec3::from(sl.traction);
                    }
                }
            }
            if !hit {
                return Err(Error::input(
                    label,
                    format!("surface_load[{i}].select"),
                    "no block boundary face lies in the region (facing `normal`, if given)",
                ));
            }
        }
        Ok(())
    }

    /// Hydrostatic pressure below the water table (height along `table.1`, against gravity) on
    /// the boundary faces of the movable blocks (the fixed ones cannot move: their forces would
    /// go nowhere). A follower load: the stepper puts it on the faces as they have moved.
    fn add_water(&mut self, (table, up): (f64, Vec3), unit_weight: f64, drained: bool) {
        let movable = |e: &usize| {
            let me = &self.covers.elements[*e];
            !self.geometry.blocks[me.block].fixed && me.boundary_faces().next().is_some()
        };
        let mut elements: Vec<usize> = (0..self.covers.elements.len()).filter(movable).collect();
        let wet = drained.then(|| {
            let all = water::wet_faces(&self.geometry, &self.covers, &elements);
            elements = all.iter().filter(|(_, w)| !w.is_empty()).map(|(e, _)| *e).collect();
            all.into_iter().filter(|(_, w)| !w.is_empty()).map(|(_, w)| w).collect()
        });
        self.water = Some(WaterLoad { table, up, unit_weight, elements, wet });
    }

    fn add_constraints(&mut self, label: &str) -> Result<()> {
        let weld = 1e-9 * self.half_size.max(self.covers.mesh().size);
        for (i, c) in self.scenario.constraint.clone().iter().enumerate() {
            let pts = penalty::boundary_vertices_in(&self.covers, &c.select, weld);
            if pts.is_empty() {
                return Err(Error::input(
                    label,
                    format!("constraint[{i}].select"),
                    "no block boundary vertex lies in the region",
                ));
            }
            for (e, x) in pts {
                self.constraints.push(penalty::point_constraint(&self.covers, e, x, &c.directions));
            }
        }
        for (i, f) in self.scenario.fixed_point.clone().iter().enumerate() {
            let x = Vec3::from(f.point);
            let (_, e) = self.locate(&x).ok_or_else(|| {
                Error::input(label, format!("fixed_point[{i}].point"), "the point is not inside any block")
            })?;
            self.constraints.push(penalty::point_constraint(&self.covers, e, x, &f.directions));
        }
        Ok(())
    }
}

/// The sparsity pattern of the MEs' cover cliques, its scatter maps, and the consistent mass
/// assembled on it.
/// The block holding a reference point (first match), and the ME.
fn locate(geometry: &Geometry, covers: &Covers, x: &Vec3) -> Option<(usize, usize)> {
    let tol = 1e-9 * covers.mesh().size;
    let b = geometry.blocks.iter().position(|b| b.contains(x, tol))?;
    covers.locate(b, x, tol).map(|e| (b, e))
}

/// The pattern of the elements and of the `extra` cliques (bolts, after the elements), and the
/// assembled mass.
pub fn pattern_and_mass(
    covers: &Covers,
    dofs: &DofMap,
    kernels: &[ElementKernel],
    kernel_of: &[usize],
    extra: &[&[usize]],
) -> (Assembler, Vec<f64>) {
    let cliques: Vec<&[usize]> =
        covers.elements.iter().map(|e| e.covers.as_slice()).chain(extra.iter().copied()).collect();
    let masters: Vec<Vec<usize>> = cliques.iter().map(|c| masters_of(dofs, c).0).collect();
    let pattern = SparsityPattern::from_cliques(dofs, masters.iter().map(|c| c.as_slice()));
    let assembler = Assembler::new(pattern, dofs, &cliques);
    let mut mass = vec![0.0; assembler.pattern.nnz()];
    for (e, me) in covers.elements.iter().enumerate() {
        assembler.add(&mut mass, e, &expand_mass(&kernels[kernel_of[e]].mass, me.covers.len()));
    }
    (assembler, mass)
}

/// n × n scalar mass → (3n) × (3n) block-diagonal-per-pair matrix.
pub fn expand_mass(mass: &[f64], n: usize) -> Vec<f64> {
    let mut out = vec![0.0; 9 * n * n];
    for a in 0..n {
        for b in 0..n {
            for i in 0..3 {
                out[(3 * a + i) * 3 * n + 3 * b + i] = mass[a * n + b];
            }
        }
    }
    out
}

fn build_kernels(covers: &Covers, geometry: &Geometry) -> (Vec<ElementKernel>, Vec<usize>) {
    let mut kernels = Vec::new();
    let mut shared: FxHashMap<(usize, usize, usize, usize), usize> = FxHashMap::default();
    let mut kernel_of = Vec::with_capacity(covers.elements.len());
    for e in &covers.elements {
        let mat_id = geometry.blocks[e.block].material;
        let mat = &geometry.materials[mat_id];
        let make = || element_kernel(&e.moments, covers.weights(e), covers.mesh_of(e), mat);
        let id = if e.full {
            *shared.entry((mat_id, e.mesh, parity(e.cell), e.subcell)).or_insert_with(|| {
                kernels.push(make());
                kernels.len() - 1
            })
        } else {
            kernels.push(make());
            kernels.len() - 1
        };
        kernel_of.push(id);
    }
    (kernels, kernel_of)
}
