//! The surfaces of the cut blocks, for limit-equilibrium (key-block) analysis: every boundary
//! face of every block with its origin (joint, excavation, body face), its joint strength and
//! the area of it that another block's face touches.

use nmm3d_geom::{polygon, Face, Vec3};
use serde_json::{json, Value};

use crate::element::grout;
use crate::model::touching::{self, boundary_faces, Surface, COINCIDENT_RATIO};
use crate::model::{tags, traverse, Geometry};
use crate::scenario::Scenario;

/// Blocks, faces and features of the scenario's rock mass as JSON (see `python/nmm3d/block_theory.py`).
pub fn surfaces(scenario: &Scenario) -> Value {
    let g = Geometry::from_scenario(scenario);
    if g.blocks.is_empty() {
        return json!({ "blocks": [], "faces": [], "features": [], "bolts": [], "bounds": Value::Null });
    }
    let bounds = g.aabb();
    let all = boundary_faces(&g.blocks);
    // Positions in the scenario's coordinates (the blocks are in a local frame).
    let o = g.origin;
    let xyz = |v: Vec3| [v.x + o.x, v.y + o.y, v.z + o.z];
    let faces: Vec<Value> = all
        .iter()
        .map(|s| {
            let (touching, partner) = touched_area(s, &all, bounds.diagonal());
            let joint = joint_of(scenario, &g, s, partner);
            let (kind, index) = origin(s.face);
            json!({
                "block": s.block, "kind": kind, "index": index, "joint": joint, "partner": partner,
                "normal": [s.normal.x, s.normal.y, s.normal.z], "area": s.area, "touching": touching,
                "vertices": s.face.vertices.iter().map(|v| xyz(*v)).collect::<Vec<_>>(),
            })
        })
        .collect();
    let blocks: Vec<Value> = g
        .blocks
        .iter()
        .map(|b| {
            json!({
                "body": scenario.body[b.body].name, "fixed": b.fixed, "volume": b.volume,
                "density": scenario.material[b.material].density,
                "centroid": xyz(b.centroid),
            })
        })
        .collect();
    let features: Vec<Value> = g
        .features
        .iter()
        .map(|f| json!({ "normal": [f.normal.x, f.normal.y, f.normal.z], "set": f.spacing.is_some() }))
        .collect();
    let tol = 1e-9 * bounds.diagonal();
    let cover_size = crate::model::estimate::cover_size(&scenario.cover, bounds.extent());
    let holding = |x: [f64; 3]| g.blocks.iter().position(|b| b.contains(&(Vec3::from(x) - o), tol));
    let bolts: Vec<Value> = scenario
        .bolt
        .iter()
        .map(|b| {
            let mut v = json!({ "name": b.name, "head_block": holding(b.head), "anchor_block": holding(b.anchor) });
            if b.grout.grouted {
                v["crossings"] = grouted_crossings(&g, b, cover_size, tol).into();
            }
            v
        })
        .collect();
    json!({
        "blocks": blocks, "faces": faces, "features": features, "bolts": bolts,
        "bounds": { "min": xyz(bounds.min), "max": xyz(bounds.max) },
    })
}

/// The joints a grouted bolt crosses: the blocks on its head's and its anchor's side and the
/// axial capacity there [N] (none: unlimited), as the run's springs have them.
fn grouted_crossings(g: &Geometry, b: &crate::scenario::Bolt, cover_size: f64, tol: f64) -> Vec<Value> {
    let (head, anchor) = (Vec3::from(b.head) - g.origin, Vec3::from(b.anchor) - g.origin);
    let len = (anchor - head).norm();
    let runs = traverse::runs(g, &head, &anchor, traverse::BOLT_SAMPLING * cover_size, tol);
    runs.windows(2)
        .filter_map(|w| {
            let (near, far) = (w[0].block?, w[1].block?);
            let law = grout::crossing_law(b, (w[0].to - w[0].from) * len, (w[1].to - w[1].from) * len);
            let capacity = Some(law.yield_force).filter(|f| f.is_finite());
            Some(json!({ "near_block": near, "far_block": far, "capacity": capacity }))
        })
        .collect()
}

/// Area of `s` touched by faces of other blocks lying on its plane and facing it, and the block
/// touching most of it.
fn touched_area(s: &Surface, all: &[Surface], diagonal: f64) -> (f64, Option<usize>) {
    let mut by_block: Vec<(usize, f64)> = Vec::new();
    for (o, common) in touching::touched(&s.face.vertices, &s.normal, s.block, all, COINCIDENT_RATIO * diagonal) {
        let a = polygon::area_vector(&common).norm();
        match by_block.iter_mut().find(|(b, _)| *b == o) {
            Some(e) => e.1 += a,
            None => by_block.push((o, a)),
        }
    }
    let total = by_block.iter().map(|(_, a)| a).sum::<f64>().min(s.area);
    (total, by_block.iter().max_by(|x, y| x.1.total_cmp(&y.1)).map(|(b, _)| *b))
}

/// Where a face came from: ("joint", feature), ("excavation", excavation) or ("body", face).
fn origin(f: &Face) -> (&'static str, usize) {
    if let Some(k) = tags::joint_feature(f.tag) {
        ("joint", k)
    } else if f.tag.0 >= tags::EXCAVATION_BASE {
        ("excavation", ((f.tag.0 - tags::EXCAVATION_BASE) / 1024) as usize)
    } else {
        ("body", f.tag.0 as usize)
    }
}

/// The joint (name) whose strength acts on a face: the joint feature's, else the interface
/// between the two bodies that touch there, else the body's own (as contact detection takes it).
fn joint_of(s: &Scenario, g: &Geometry, f: &Surface, partner: Option<usize>) -> Option<String> {
    let body = &s.body[g.blocks[f.block].body];
    if let Some(j) = tags::joint_feature(f.face.tag).and_then(|k| g.features[k].joint) {
        return Some(s.joint[j].name.clone());
    }
    let other = partner.map(|p| &s.body[g.blocks[p].body]);
    let interface = other.and_then(|o| {
        s.interface.iter().find(|i| {
            (i.bodies[0] == body.name && i.bodies[1] == o.name) || (i.bodies[0] == o.name && i.bodies[1] == body.name)
        })
    });
    interface.map(|i| i.joint.clone()).or(body.joint.clone()).or(other.and_then(|o| o.joint.clone()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::from_toml_str;

    /// A 2 m slab with a 1 m cube on it, shifted so that `overhang` [m] of the cube's base hangs
    /// over the slab's east edge.
    fn cube_on_slab(overhang: f64) -> Value {
        let x0 = 1.0 + overhang;
        let text = format!(
            r#"
            [[material]]
            name = "rock"
            density = 2500.0
            young = 1e9
            poisson = 0.2
            [[joint]]
            name = "slab joint"
            friction_angle = 25.0
            [[joint]]
            name = "cube joint"
            friction_angle = 35.0
            [[body]]
            name = "slab"
            material = "rock"
            fixed = true
            joint = "slab joint"
            shape = {{ box = {{ min = [0.0, 0.0, -1.0], max = [2.0, 2.0, 0.0] }} }}
            [[body]]
            name = "cube"
            material = "rock"
            joint = "cube joint"
            shape = {{ box = {{ min = [{x0}, 0.5, 0.0], max = [{x1}, 1.5, 1.0] }} }}
            "#,
            x1 = x0 + 1.0
        );
        surfaces(&from_toml_str(&text, "test", &[]).unwrap())
    }

    fn base_of_cube(v: &Value) -> &Value {
        let faces = v["faces"].as_array().unwrap();
        faces.iter().find(|f| f["block"] == 1 && f["normal"][2].as_f64().unwrap() < -0.99).unwrap()
    }

    #[test]
    fn a_cube_on_a_slab_touches_it_over_its_whole_base() {
        let v = cube_on_slab(0.0);
        let base = base_of_cube(&v);
        assert!((base["touching"].as_f64().unwrap() - 1.0).abs() < 1e-12);
        assert_eq!(base["partner"], 0);
        // The body's own joint, as contact detection takes it (A's body joint first).
        assert_eq!(base["joint"], "cube joint");
        // Its sides and top touch nothing.
        let faces = v["faces"].as_array().unwrap();
        let free = faces.iter().filter(|f| f["block"] == 1 && f["touching"].as_f64().unwrap() == 0.0).count();
        assert_eq!(free, 5);
    }

    #[test]
    fn an_overhanging_cube_touches_only_what_lies_on_the_slab() {
        let base = base_of_cube(&cube_on_slab(0.75)).clone();
        // x from 1.75 to 2.75 over a slab ending at 2: a quarter of the base.
        assert!((base["touching"].as_f64().unwrap() - 0.25).abs() < 1e-12, "{base}");
        let none = base_of_cube(&cube_on_slab(1.5)).clone();
        assert_eq!(none["touching"].as_f64().unwrap(), 0.0);
        assert_eq!(none["partner"], Value::Null);
    }
}
