//! Boundary conditions and loads: constraints, fixed points, point and surface loads, in-situ
//! stress.

use serde::{Deserialize, Serialize};

/// A region of space.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum Region {
    /// Axis-aligned box.
    Box {
        /// Lower corner [m].
        min: [f64; 3],
        /// Upper corner [m].
        max: [f64; 3],
    },
}

/// Axis names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    /// East.
    X,
    /// North.
    Y,
    /// Up.
    Z,
}

/// `[[constraint]]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Constraint {
    /// Region whose boundary vertices are held.
    pub select: Region,
    /// Held directions.
    pub directions: Vec<Axis>,
}

/// `[[fixed_point]]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FixedPoint {
    /// Point [m].
    pub point: [f64; 3],
    /// Held directions.
    pub directions: Vec<Axis>,
}

/// `[[point_load]]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointLoad {
    /// Point [m].
    pub point: [f64; 3],
    /// Force [N].
    pub force: [f64; 3],
}

/// `[[surface_load]]`: a dead traction on the block boundary faces inside a region.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceLoad {
    /// Region: boundary faces with every vertex inside are loaded.
    pub select: Region,
    /// Only faces whose outward normal lies within 1° of this direction (optional).
    #[serde(default)]
    pub normal: Option<[f64; 3]>,
    /// Traction [Pa].
    pub traction: [f64; 3],
}

/// `[in_situ_stress]`, compression negative.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InSituStress {
    /// xx, yy, zz, xy, yz, zx [Pa].
    pub stress: [f64; 6],
    /// Gradient in z [Pa/m].
    #[serde(default)]
    pub gradient: [f64; 6],
    /// Height where `stress` applies [m].
    #[serde(default)]
    pub reference_z: f64,
}

/// `[water]`: a water table; hydrostatic pressure on every boundary face of the movable blocks
/// below it (addition to v1). On the two faces of a joint the pressures push the blocks apart,
/// so the contact carries the effective normal force, which the Coulomb law then takes.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Water {
    /// Height of the water table [m]: pressure ρ_w |g| (table − h) below it, h the height
    /// against gravity (z for the usual gravity [0, 0, −g]).
    pub table: f64,
    /// Density of water [kg/m³].
    #[serde(default = "water_density")]
    pub density: f64,
    /// Whether free faces (not touching rock) below the table carry the pressure too.
    #[serde(default)]
    pub free_faces: FreeFaces,
}

/// Water on the free faces below the table.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FreeFaces {
    /// Under water too (a flooded excavation, a reservoir): the hydrostatic field everywhere.
    #[default]
    Submerged,
    /// Drained (a seepage face, Hoek & Bray's slope face): pressure only where blocks touch
    /// (the joints and the interfaces between bodies).
    Drained,
}

fn water_density() -> f64 {
    1000.0
}

/// `[seismic]`: earthquake loading (addition to v1). The fixed bodies shake together as one
/// rigid base; the run is computed in the base's frame, where the shaking is the body force
/// −m a_base(t) on every movable block, so displacements and velocities in the outputs are
/// relative to the base (Chopra, Dynamics of Structures, §1.7: effective earthquake force).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Seismic {
    /// Pseudo-static coefficients [kx, ky, kz]: a constant extra body force k·m·|g| [-].
    #[serde(default)]
    pub coefficient: [f64; 3],
    /// Rectangular acceleration pulses of the base.
    #[serde(default)]
    pub pulse: Vec<Pulse>,
    /// Sinusoidal base accelerations.
    #[serde(default)]
    pub sine: Vec<Sine>,
    /// A recorded base motion, linear between samples.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub series: Option<Series>,
}

/// A rectangular pulse: a constant base acceleration over `[start, start + duration)`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Pulse {
    /// Base acceleration [m/s²].
    pub acceleration: [f64; 3],
    /// Start time [s].
    #[serde(default)]
    pub start: f64,
    /// Duration [s].
    pub duration: f64,
}

/// A sine: a = amplitude · sin(2π f (t − start)) over `[start, start + cycles / f)`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sine {
    /// Acceleration amplitude [m/s²].
    pub amplitude: [f64; 3],
    /// Frequency [Hz].
    pub frequency: f64,
    /// Start time [s].
    #[serde(default)]
    pub start: f64,
    /// Number of cycles (whole or not).
    pub cycles: f64,
}

/// What a recorded series gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SeriesQuantity {
    /// Base acceleration [m/s²], linear between samples.
    Acceleration,
    /// Base velocity [m/s], linear between samples (so the acceleration is constant between them).
    Velocity,
    /// Base displacement [m]: the acceleration at each sample by the second difference, linear
    /// between samples (how strong-motion records are differentiated).
    Displacement,
}

/// `[seismic.series]`: samples of the base motion; zero before the first and after the last.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Series {
    /// What the values are.
    pub quantity: SeriesQuantity,
    /// Sample times [s], increasing.
    #[serde(default)]
    pub time: Vec<f64>,
    /// One [x, y, z] value per sample.
    #[serde(default)]
    pub values: Vec<[f64; 3]>,
    /// A CSV file of `time, x, y, z` rows (a header line is skipped), relative to the scenario
    /// file; read into `time` and `values` when the scenario is loaded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// Factor on the file's values (e.g. 9.81 for a record in g).
    #[serde(default = "unit_scale")]
    pub scale: f64,
}

fn unit_scale() -> f64 {
    1.0
}

impl Seismic {
    /// Whether the base moves (pulses, sines or a series; the coefficient is a constant load).
    pub fn moves(&self) -> bool {
        !self.pulse.is_empty() || !self.sine.is_empty() || self.series.is_some()
    }

    /// History columns of a moving base: `base.velocity.x` … `base.displacement.z`.
    pub fn columns(&self) -> Vec<String> {
        if !self.moves() {
            return Vec::new();
        }
        ["velocity", "displacement"].iter().flat_map(|q| ["x", "y", "z"].map(|c| format!("base.{q}.{c}"))).collect()
    }

    /// Base acceleration just before `t` (the left limit, where a pulse ends) [m/s²].
    pub fn acceleration_before(&self, t: f64) -> [f64; 3] {
        self.base_acceleration(t - jump_width(t))
    }

    /// Base acceleration just after `t` (the right limit, where a pulse starts) [m/s²].
    pub fn acceleration_after(&self, t: f64) -> [f64; 3] {
        self.base_acceleration(t + jump_width(t))
    }

    /// The first time after `t` where the base acceleration may jump (a pulse, sine or series
    /// starts or ends): steps end there, so that no step straddles a jump.
    pub fn next_jump(&self, t: f64) -> Option<f64> {
        let pulses = self.pulse.iter().flat_map(|p| [p.start, p.start + p.duration]);
        let sines = self.sine.iter().flat_map(|s| [s.start, s.start + s.cycles / s.frequency]);
        let series = self.series.iter().flat_map(|s| [s.time[0], s.time[s.time.len() - 1]]);
        pulses.chain(sines).chain(series).filter(|&b| b > t + jump_width(t)).min_by(f64::total_cmp)
    }

    /// Base acceleration at time `t` [m/s²] (intervals closed on the left).
    pub fn base_acceleration(&self, t: f64) -> [f64; 3] {
        let mut a = [0.0; 3];
        let mut add = |v: [f64; 3], s: f64| (0..3).for_each(|i| a[i] += s * v[i]);
        for p in self.pulse.iter().filter(|p| t >= p.start && t < p.start + p.duration) {
            add(p.acceleration, 1.0);
        }
        for s in self.sine.iter().filter(|s| t >= s.start && t < s.start + s.cycles / s.frequency) {
            add(s.amplitude, (2.0 * std::f64::consts::PI * s.frequency * (t - s.start)).sin());
        }
        if let Some(s) = &self.series {
            add(s.acceleration_at(t), 1.0);
        }
        a
    }
}

/// How far around `t` the limits of a jump are taken [s]: far above the round-off of a time
/// summed from steps, far below any step.
fn jump_width(t: f64) -> f64 {
    1e-9 * t.abs().max(1.0)
}

impl Series {
    /// Base acceleration at `t` from the samples.
    pub fn acceleration_at(&self, t: f64) -> [f64; 3] {
        let (ts, vs) = (&self.time, &self.values);
        let n = ts.len();
        if n < 2 || t < ts[0] || t >= ts[n - 1] {
            return [0.0; 3];
        }
        let k = ts.partition_point(|&x| x <= t) - 1;
        let lerp = |a: [f64; 3], b: [f64; 3]| {
            let s = (t - ts[k]) / (ts[k + 1] - ts[k]);
            [0, 1, 2].map(|i| a[i] + s * (b[i] - a[i]))
        };
        match self.quantity {
            SeriesQuantity::Acceleration => lerp(vs[k], vs[k + 1]),
            SeriesQuantity::Velocity => [0, 1, 2].map(|i| (vs[k + 1][i] - vs[k][i]) / (ts[k + 1] - ts[k])),
            SeriesQuantity::Displacement => lerp(self.second_difference(k), self.second_difference(k + 1)),
        }
    }

    /// d²u/dt² at sample `k` (zero at the ends: the record starts and ends at rest).
    fn second_difference(&self, k: usize) -> [f64; 3] {
        let (ts, vs) = (&self.time, &self.values);
        if k == 0 || k + 1 >= ts.len() {
            return [0.0; 3];
        }
        let (h0, h1) = (ts[k] - ts[k - 1], ts[k + 1] - ts[k]);
        [0, 1, 2].map(|i| 2.0 * ((vs[k + 1][i] - vs[k][i]) / h1 - (vs[k][i] - vs[k - 1][i]) / h0) / (h0 + h1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series(quantity: SeriesQuantity, time: Vec<f64>, x: Vec<f64>) -> Seismic {
        let values = x.iter().map(|&v| [v, 0.0, 0.0]).collect();
        Seismic { series: Some(Series { quantity, time, values, file: None, scale: 1.0 }), ..Default::default() }
    }

    #[test]
    fn a_pulse_acts_on_its_interval_closed_on_the_left() {
        let s = Seismic {
            pulse: vec![Pulse { acceleration: [2.0, 0.0, -1.0], start: 0.5, duration: 0.25 }],
            ..Default::default()
        };
        assert_eq!(s.base_acceleration(0.49)[0], 0.0);
        assert_eq!(s.base_acceleration(0.5), [2.0, 0.0, -1.0]);
        assert_eq!(s.base_acceleration(0.75)[0], 0.0);
        assert_eq!(s.acceleration_before(0.75)[0], 2.0);
        assert_eq!(s.acceleration_after(0.75)[0], 0.0);
        assert_eq!(s.next_jump(0.0), Some(0.5));
        assert_eq!(s.next_jump(0.5), Some(0.75));
        assert_eq!(s.next_jump(0.75), None);
    }

    #[test]
    fn a_sine_runs_for_its_cycles() {
        let s = Seismic {
            sine: vec![Sine { amplitude: [0.0, 3.0, 0.0], frequency: 2.0, start: 1.0, cycles: 1.5 }],
            ..Default::default()
        };
        assert!((s.base_acceleration(1.125)[1] - 3.0).abs() < 1e-12);
        assert_eq!(s.base_acceleration(1.75)[1], 0.0);
        assert_eq!(s.next_jump(1.2), Some(1.75));
    }

    #[test]
    fn records_of_velocity_and_displacement_give_their_accelerations() {
        // v = 0 → 2 m/s over 0.5 s: 4 m/s².
        let v = series(SeriesQuantity::Velocity, vec![0.0, 0.5, 1.0], vec![0.0, 2.0, 2.0]);
        assert!((v.base_acceleration(0.25)[0] - 4.0).abs() < 1e-12);
        assert_eq!(v.base_acceleration(0.75)[0], 0.0);
        // u = t² sampled every 0.1 s: the second difference is 2 m/s² inside the record.
        let t: Vec<f64> = (0..=10).map(|k| 0.1 * k as f64).collect();
        let u = series(SeriesQuantity::Displacement, t.clone(), t.iter().map(|t| t * t).collect());
        assert!((u.base_acceleration(0.45)[0] - 2.0).abs() < 1e-9);
        // An acceleration record is linear between samples.
        let a = series(SeriesQuantity::Acceleration, vec![0.0, 1.0], vec![0.0, 3.0]);
        assert!((a.base_acceleration(0.5)[0] - 1.5).abs() < 1e-12);
    }
}
