//! `nmm3d blocks`: cut the rock mass and report the blocks, without running.

use std::path::Path;

use serde_json::{json, Value};

use crate::error::{Error, Result};
use crate::model::Geometry;
use crate::output::{tables, vtu};
use crate::scenario::Scenario;

/// Build the blocks, write `blocks.csv` and `blocks.vtu` to `out`, return the report (an input
/// error naming `label` when no block is left).
pub fn report(scenario: &Scenario, label: &str, out: &Path) -> Result<Value> {
    let t = std::time::Instant::now();
    let geometry = Geometry::from_scenario(scenario);
    geometry.require_blocks(label)?;
    let cutting_seconds = t.elapsed().as_secs_f64();
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
        "excavated_volume": geometry.report.excavated_volume,
        "slivers_merged": geometry.report.slivers_merged,
        "slivers_dropped": geometry.report.slivers_dropped,
        "pieces": geometry.blocks.iter().map(|b| b.pieces.len()).sum::<usize>(),
        "non_convex_blocks": geometry.blocks.iter().filter(|b| b.pieces.len() > 1).count(),
        "cutting_seconds": cutting_seconds,
    }))
}

/// Build the blocks and their covers only (no element matrices): counts and seconds per stage.
pub fn cover_report(scenario: &Scenario) -> Value {
    let t = std::time::Instant::now();
    let geometry = Geometry::from_scenario(scenario);
    let cutting = t.elapsed().as_secs_f64();
    let t = std::time::Instant::now();
    let c = &scenario.cover;
    let ext = geometry.aabb().extent();
    let size = crate::model::estimate::cover_size(c, ext);
    let origin = nmm3d_geom::Vec3::from(c.origin) - geometry.origin;
    let (meshes, of_block) = crate::cover::meshes::model_meshes(scenario, &geometry, size, origin);
    let covers = crate::cover::Covers::build(&geometry, meshes, of_block, crate::cover::PatternTable::new(c.pattern));
    json!({
        "blocks": geometry.blocks.len(),
        "manifold_elements": covers.elements.len(),
        "physical_covers": covers.covers.len(),
        "cutting_seconds": cutting,
        "covers_seconds": t.elapsed().as_secs_f64(),
    })
}

/// The block table (id, body, volume, centroid, fixed) as JSON arrays.
pub fn table(scenario: &Scenario) -> Value {
    let g = Geometry::from_scenario(scenario);
    let col = |f: &dyn Fn(&crate::model::Block) -> Value| -> Vec<Value> { g.blocks.iter().map(f).collect() };
    json!({
        "id": (0..g.blocks.len()).collect::<Vec<_>>(),
        "body": col(&|b| json!(scenario.body[b.body].name)),
        "volume": col(&|b| json!(b.volume)),
        "centroid_x": col(&|b| json!(b.centroid.x + g.origin.x)),
        "centroid_y": col(&|b| json!(b.centroid.y + g.origin.y)),
        "centroid_z": col(&|b| json!(b.centroid.z + g.origin.z)),
        "fixed": col(&|b| json!(b.fixed)),
    })
}
