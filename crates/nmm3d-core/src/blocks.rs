//! `nmm3d blocks`: the blocks of a scenario and their report, without running.
//! (This version does not cut bodies: each convex body is one block; cutting by joint sets and
//! excavations extends this module.)

use std::path::Path;

use serde_json::{json, Value};

use crate::error::{Error, Result};
use crate::model::Geometry;
use crate::output::{tables, vtu};
use crate::scenario::Scenario;

/// Build the blocks, write `blocks.csv` and `blocks.vtu` to `out`, return the report.
pub fn report(scenario: &Scenario, out: &Path) -> Result<Value> {
    let geometry = Geometry::from_scenario(scenario);
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    tables::write_block_rows(scenario, &geometry, out)?;
    vtu::write_blocks(&geometry, &out.join("blocks.vtu"))?;
    let vols: Vec<f64> = geometry.blocks.iter().map(|b| b.volume).collect();
    let total: f64 = vols.iter().sum();
    let (imin, vmin) = vols.iter().enumerate().fold((0, f64::INFINITY), |a, (i, v)| if *v < a.1 { (i, *v) } else { a });
    let vmax = vols.iter().cloned().fold(0.0, f64::max);
    Ok(json!({
        "blocks": vols.len(),
        "total_volume": total,
        "mean_volume": total / vols.len() as f64,
        "min_volume": vmin,
        "max_volume": vmax,
        "smallest_block": imin,
        "excavated_volume": 0.0,
    }))
}

/// The block table (id, body, volume, centroid, fixed) as JSON arrays.
pub fn table(scenario: &Scenario) -> Value {
    let g = Geometry::from_scenario(scenario);
    let col = |f: &dyn Fn(&crate::model::Block) -> Value| -> Vec<Value> { g.blocks.iter().map(f).collect() };
    json!({
        "id": (0..g.blocks.len()).collect::<Vec<_>>(),
        "body": col(&|b| json!(scenario.body[b.body].name)),
        "volume": col(&|b| json!(b.volume)),
        "centroid_x": col(&|b| json!(b.centroid.x)),
        "centroid_y": col(&|b| json!(b.centroid.y)),
        "centroid_z": col(&|b| json!(b.centroid.z)),
        "fixed": col(&|b| json!(b.fixed)),
    })
}
