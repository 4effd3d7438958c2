//! CSV tables: `blocks.csv` (one row per block) and `history.csv` (one row per recorded step).
//! Numbers use Rust's shortest round-trip formatting, so values read back bit for bit.

use std::fmt::Write as _;
use std::path::Path;

use super::atomic;
use crate::error::Result;
use crate::system::System;

/// Write `blocks.csv`: id, body, volume, centroid, fixed.
pub fn write_blocks(sys: &System, dir: &Path) -> Result<()> {
    write_block_rows(&sys.scenario, &sys.geometry, dir)
}

/// `blocks.csv` of a geometry.
pub fn write_block_rows(
    scenario: &crate::scenario::Scenario,
    geometry: &crate::model::Geometry,
    dir: &Path,
) -> Result<()> {
    let mut s = String::from("id,body,volume,centroid_x,centroid_y,centroid_z,fixed\n");
    for (i, b) in geometry.blocks.iter().enumerate() {
        let body = &scenario.body[b.body].name;
        let centroid = b.centroid + geometry.origin;
        let _ =
            writeln!(s, "{i},{},{},{},{},{},{}", csv_text(body), b.volume, centroid.x, centroid.y, centroid.z, b.fixed);
    }
    atomic::write(&dir.join("blocks.csv"), s.as_bytes())
}

fn csv_text(t: &str) -> String {
    if t.contains([',', '"', '\n']) {
        format!("\"{}\"", t.replace('"', "\"\""))
    } else {
        t.to_string()
    }
}

/// The monitored history, kept in memory and written atomically.
#[derive(Debug, Clone)]
pub struct History {
    /// Column names after `time` and `step`.
    pub columns: Vec<String>,
    /// Rows: time, step, values.
    pub rows: Vec<(f64, u64, Vec<f64>)>,
}

impl History {
    /// Empty history with the given monitor columns.
    pub fn new(columns: Vec<String>) -> Self {
        Self { columns, rows: Vec::new() }
    }

    /// Write `history.csv`.
    pub fn write(&self, dir: &Path) -> Result<()> {
        let mut s = String::from("time,step");
        for c in &self.columns {
            s.push(',');
            s.push_str(c);
        }
        s.push('\n');
        for (t, step, vals) in &self.rows {
            let _ = write!(s, "{t},{step}");
            for v in vals {
                let _ = write!(s, ",{v}");
            }
            s.push('\n');
        }
        atomic::write(&dir.join("history.csv"), s.as_bytes())
    }
}

/// Write `diagnostics.csv`: per accepted step the time step, the rejected trials, the
/// displacement ratio, the unbalanced force ratio at the start of the step, and the energy
/// accounts after it [J] (`crate::time::energy`; zero in static runs), then the contact points,
/// the deepest overlap at its end [m], the contact dashpots' dissipation [J], then the accepted
/// trial's open–close iterations and the step's factorisations (added in that order).
pub fn write_diagnostics(dir: &Path, rows: &[(f64, u64, crate::time::StepReport)]) -> Result<()> {
    let mut s = String::from(
        "time,step,dt,cuts,displacement_ratio,unbalanced_force_ratio,kinetic_energy,elastic_energy,external_work,contact_energy,friction_dissipation,numerical_dissipation,energy_error,contact_event_dissipation,contact_points,max_penetration,damping_dissipation,open_close_iterations,factorizations\n",
    );
    for (t, step, r) in rows {
        let e = &r.energy;
        let _ = writeln!(
            s,
            "{t},{step},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.dt,
            r.cuts,
            r.ratio,
            r.unbalanced,
            e.kinetic,
            e.elastic,
            e.external_work,
            e.contact,
            e.friction,
            e.numerical,
            e.error(),
            e.contact_events,
            r.contacts,
            r.max_penetration,
            e.damping,
            r.open_close,
            r.factorizations
        );
    }
    atomic::write(&dir.join("diagnostics.csv"), s.as_bytes())
}
