//! Semantic checks of a typed scenario. Every problem is collected, each with its key path
//! (named entries are addressed by name, as in `--set`).

use std::collections::HashSet;

use super::schema::*;
use crate::error::Problem;

/// Largest `contact.turned_face_angle` [°]: a face turned farther against the contact plane
/// meets it at an edge, not as the same joint face.
const TURNED_FACE_LIMIT: f64 = 10.0;

mod analysis;
mod stages;
mod support;

struct Checker {
    problems: Vec<Problem>,
}

impl Checker {
    fn fail(&mut self, path: impl Into<String>, reason: impl Into<String>) {
        self.problems.push(Problem { path: path.into(), reason: reason.into() });
    }
    fn positive(&mut self, path: &str, v: f64) {
        if !(v > 0.0 && v.is_finite()) {
            self.fail(path, format!("must be a finite number > 0, got {v}"));
        }
    }
    fn unique<'a>(&mut self, kind: &str, names: impl Iterator<Item = &'a String>) {
        let mut seen = HashSet::new();
        for n in names {
            if n.is_empty() {
                self.fail(kind, "every entry needs a non-empty name");
            } else if !seen.insert(n) {
                self.fail(format!("{kind}.{n}"), "the name is used twice");
            }
        }
    }
}

/// Every problem of a scenario but its shapes (whether each makes a solid is the model's to
/// say: `model::shape::shape_problems`), each with its key path.
pub fn problems(s: &Scenario) -> Vec<Problem> {
    let mut c = Checker { problems: Vec::new() };
    analysis::analysis(&mut c, &s.analysis);
    if let Some(size) = s.cover.size {
        c.positive("cover.size", size);
    }
    if !(0.0..1.0).contains(&s.cover.aggregation_threshold) {
        c.fail("cover.aggregation_threshold", "must lie in [0, 1)");
    }
    for (k, v) in [
        ("contact.normal_stiffness", s.contact.normal_stiffness),
        ("contact.shear_stiffness", s.contact.shear_stiffness),
    ] {
        if let Stiffness::Value(x) = v {
            c.positive(k, x);
        }
    }
    c.positive("contact.max_penetration_ratio", s.contact.max_penetration_ratio);
    let k = &s.contact;
    for (key, v) in [
        ("auto_penalty_factor", k.auto_penalty_factor),
        ("tolerance_ratio", k.tolerance_ratio),
        ("warning_skin", k.warning_skin),
        ("reach_safety", k.reach_safety),
        ("overlap_tolerance", k.overlap_tolerance),
        ("gap_band", k.gap_band),
        ("reclose_depth", k.reclose_depth),
        ("slip_turn", k.slip_turn),
        ("touching", k.touching),
        ("min_area_share", k.min_area_share),
        ("merge_ratio", k.merge_ratio),
    ] {
        c.positive(&format!("contact.{key}"), v);
    }
    if !(k.damping_ratio >= 0.0 && k.damping_ratio.is_finite()) {
        c.fail("contact.damping_ratio", format!("must be a finite number ≥ 0, got {}", k.damping_ratio));
    }
    if !(0.0..=TURNED_FACE_LIMIT).contains(&k.turned_face_angle) {
        c.fail(
            "contact.turned_face_angle",
            format!("must lie in [0, {TURNED_FACE_LIMIT}] degrees, got {}", k.turned_face_angle),
        );
    }
    if !(k.static_carry_slack >= 0.0 && k.static_carry_slack.is_finite()) {
        c.fail("contact.static_carry_slack", format!("must be a finite number ≥ 0, got {}", k.static_carry_slack));
    }
    if !(k.penalty_raise > 1.0 && k.penalty_raise.is_finite()) {
        c.fail("contact.penalty_raise", format!("must be a finite number > 1, got {}", k.penalty_raise));
    }
    materials(&mut c, s);
    joints(&mut c, s);
    bodies(&mut c, s);
    cutting(&mut c, s);
    loads(&mut c, s);
    seismic(&mut c, s);
    support::bolts(&mut c, s);
    stages::stages(&mut c, s);
    monitors(&mut c, s);
    expectations(&mut c, s);
    finite(&mut c, s);
    c.problems
}

/// Pulses and sines last a positive time; a series has increasing times and one value each.
fn seismic(c: &mut Checker, s: &Scenario) {
    let q = &s.seismic;
    for (i, p) in q.pulse.iter().enumerate() {
        c.positive(&format!("seismic.pulse[{i}].duration"), p.duration);
    }
    for (i, w) in q.sine.iter().enumerate() {
        c.positive(&format!("seismic.sine[{i}].frequency"), w.frequency);
        c.positive(&format!("seismic.sine[{i}].cycles"), w.cycles);
    }
    if let Some(series) = &q.series {
        if series.time.len() < 2 || series.time.len() != series.values.len() {
            c.fail("seismic.series", "needs at least two samples and one value [x, y, z] per time");
        } else if series.time.windows(2).any(|w| !(w[1] > w[0])) {
            c.fail("seismic.series.time", "must increase strictly");
        }
    }
    if q.moves() && s.monitor.iter().any(|m| m.name == "base") {
        c.fail("monitor.base", "the name `base` is taken by the shaking base's history columns");
    }
    if let Some(w) = &s.water {
        c.positive("water.density", w.density);
    }
    if q.moves() && s.analysis.kind == AnalysisKind::Static {
        c.fail("seismic", "a moving base needs a dynamic analysis (`analysis.kind = \"dynamic\"`)");
    }
}

/// Every number of the scenario is finite: NaN and ±inf anywhere (an origin, a velocity, a
/// point of a shape) are named by their key path, unless a check above named that key (or the
/// array or table holding it) already.
fn finite(c: &mut Checker, s: &Scenario) {
    let Ok(value) = toml::Value::try_from(s) else { return };
    let mut found = Vec::new();
    non_finite("", &value, &mut found);
    for (path, x) in found {
        let named =
            |p: &Problem| p.path == path || path.strip_prefix(&p.path).is_some_and(|rest| rest.starts_with(['[', '.']));
        if !c.problems.iter().any(named) {
            c.fail(path, format!("must be a finite number, got {x}"));
        }
    }
}

/// Key paths of the non-finite floats under `v` (entries with a `name` addressed by it).
fn non_finite(path: &str, v: &toml::Value, found: &mut Vec<(String, f64)>) {
    let join = |key: &str| if path.is_empty() { key.to_string() } else { format!("{path}.{key}") };
    match v {
        toml::Value::Float(x) if !x.is_finite() => found.push((path.to_string(), *x)),
        toml::Value::Table(t) => t.iter().for_each(|(k, x)| non_finite(&join(k), x, found)),
        toml::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                let named = x.get("name").and_then(toml::Value::as_str).filter(|n| !n.is_empty());
                let at = named.map_or_else(|| format!("{path}[{i}]"), join);
                non_finite(&at, x, found);
            }
        }
        _ => {}
    }
}

fn materials(c: &mut Checker, s: &Scenario) {
    c.unique("material", s.material.iter().map(|m| &m.name));
    for m in &s.material {
        let p = format!("material.{}", m.name);
        c.positive(&format!("{p}.density"), m.density);
        c.positive(&format!("{p}.young"), m.young);
        if !(m.poisson > -1.0 && m.poisson < 0.5) {
            c.fail(format!("{p}.poisson"), format!("must lie in (-1, 0.5), got {}", m.poisson));
        }
    }
}

fn joints(c: &mut Checker, s: &Scenario) {
    c.unique("joint", s.joint.iter().map(|j| &j.name));
    for j in &s.joint {
        let p = format!("joint.{}", j.name);
        if !(j.friction_angle >= 0.0 && j.friction_angle < 90.0) {
            c.fail(format!("{p}.friction_angle"), format!("must lie in [0, 90) degrees, got {}", j.friction_angle));
        }
        if !(j.cohesion >= 0.0) {
            c.fail(format!("{p}.cohesion"), "must be ≥ 0");
        }
        if !(j.tensile_strength >= 0.0) {
            c.fail(format!("{p}.tensile_strength"), "must be ≥ 0");
        }
        for (key, k) in [("normal_stiffness", j.normal_stiffness), ("shear_stiffness", j.shear_stiffness)] {
            if k.is_some_and(|k| !(k > 0.0 && k.is_finite())) {
                c.fail(
                    format!("{p}.{key}"),
                    format!("must be a positive stiffness per unit area in Pa/m, got {}", k.unwrap_or_default()),
                );
            }
        }
        if j.shear_stiffness.is_some() && j.normal_stiffness.is_none() {
            c.fail(
                format!("{p}.shear_stiffness"),
                "needs normal_stiffness on the same joint (a joint's stiffness is given whole, in Pa/m)",
            );
        }
    }
}

fn has_joint(s: &Scenario, name: &str) -> bool {
    s.joint.iter().any(|j| j.name == name)
}

fn bodies(c: &mut Checker, s: &Scenario) {
    if s.body.is_empty() {
        c.fail("body", "the scenario needs at least one [[body]]");
    }
    c.unique("body", s.body.iter().map(|b| &b.name));
    for b in &s.body {
        let p = format!("body.{}", b.name);
        if !s.material.iter().any(|m| m.name == b.material) {
            c.fail(format!("{p}.material"), format!("there is no material named '{}'", b.material));
        }
        if let Some(j) = &b.joint {
            if !has_joint(s, j) {
                c.fail(format!("{p}.joint"), format!("there is no joint named '{j}'"));
            }
        }
        if b.velocity.iter().chain(b.angular_velocity.iter()).any(|v| !v.is_finite()) {
            c.fail(format!("{p}.velocity"), "must be finite");
        }
        if let Some(size) = b.cover_size {
            c.positive(&format!("{p}.cover_size"), size);
        }
        if matches!(b.shape, Shape::Tunnel(_)) {
            c.fail(format!("{p}.shape.tunnel"), "a tunnel is only allowed as an excavation shape");
        }
    }
}

fn cutting(c: &mut Checker, s: &Scenario) {
    let body_known = |n: &String| s.body.iter().any(|b| &b.name == n);
    if !(s.cutting.sliver_ratio >= 0.0 && s.cutting.sliver_ratio < 1.0) {
        c.fail("cutting.sliver_ratio", "must lie in [0, 1)");
    }
    for (k, js) in s.joint_set.iter().enumerate() {
        let p = format!("joint_set[{k}]");
        if !(0.0..=90.0).contains(&js.dip) {
            c.fail(format!("{p}.dip"), format!("must lie in [0, 90], got {}", js.dip));
        }
        if !js.dip_direction.is_finite() {
            c.fail(format!("{p}.dip_direction"), "must be finite");
        }
        c.positive(&format!("{p}.spacing"), js.spacing);
        for n in js.bodies.iter().flatten().filter(|n| !body_known(n)) {
            c.fail(format!("{p}.bodies"), format!("there is no body named '{n}'"));
        }
        if let Some(j) = js.joint.as_ref().filter(|j| !has_joint(s, j)) {
            c.fail(format!("{p}.joint"), format!("there is no joint named '{j}'"));
        }
    }
    for (k, jp) in s.joint_plane.iter().enumerate() {
        let p = format!("joint_plane[{k}]");
        match (jp.dip, jp.dip_direction, jp.normal) {
            (Some(d), Some(_), None) if !(0.0..=90.0).contains(&d) => {
                c.fail(format!("{p}.dip"), format!("must lie in [0, 90], got {d}"))
            }
            (Some(_), Some(_), None) => {}
            (None, None, Some(n)) if n.iter().map(|x| x * x).sum::<f64>() > 0.0 => {}
            (None, None, Some(_)) => c.fail(format!("{p}.normal"), "must be a non-zero vector"),
            _ => c.fail(p.clone(), "give either dip and dip_direction, or normal"),
        }
        for n in jp.bodies.iter().flatten().filter(|n| !body_known(n)) {
            c.fail(format!("{p}.bodies"), format!("there is no body named '{n}'"));
        }
        if let Some(j) = jp.joint.as_ref().filter(|j| !has_joint(s, j)) {
            c.fail(format!("{p}.joint"), format!("there is no joint named '{j}'"));
        }
    }
    for (k, i) in s.interface.iter().enumerate() {
        for n in i.bodies.iter().filter(|n| !body_known(n)) {
            c.fail(format!("interface[{k}].bodies"), format!("there is no body named '{n}'"));
        }
        if !has_joint(s, &i.joint) {
            c.fail(format!("interface[{k}].joint"), format!("there is no joint named '{}'", i.joint));
        }
    }
}

fn region_ok(c: &mut Checker, path: &str, r: &Region) {
    let Region::Box { min, max } = r;
    if (0..3).any(|i| !(min[i] <= max[i])) {
        c.fail(format!("{path}.box"), "min must not exceed max in any axis");
    }
}

fn loads(c: &mut Checker, s: &Scenario) {
    for (k, x) in s.constraint.iter().enumerate() {
        region_ok(c, &format!("constraint[{k}].select"), &x.select);
        if x.directions.is_empty() {
            c.fail(format!("constraint[{k}].directions"), "name at least one direction");
        }
    }
    for (k, x) in s.fixed_point.iter().enumerate() {
        if x.directions.is_empty() {
            c.fail(format!("fixed_point[{k}].directions"), "name at least one direction");
        }
    }
    for (k, x) in s.surface_load.iter().enumerate() {
        region_ok(c, &format!("surface_load[{k}].select"), &x.select);
        if x.normal.is_some_and(|n| !(n.iter().map(|v| v * v).sum::<f64>() > 0.0)) {
            c.fail(format!("surface_load[{k}].normal"), "must be a non-zero vector");
        }
    }
}

fn monitors(c: &mut Checker, s: &Scenario) {
    c.unique("monitor", s.monitor.iter().map(|m| &m.name));
    for m in &s.monitor {
        let p = format!("monitor.{}", m.name);
        if m.quantities.is_empty() {
            c.fail(format!("{p}.quantities"), "name at least one quantity");
        }
        if m.location == MonitorLocation::Point && !matches!(m.select, MonitorSelect::Point(_)) {
            c.fail(format!("{p}.location"), "location = \"point\" needs select = { point = [x, y, z] }");
        }
        if let MonitorSelect::Body(b) = &m.select {
            if !s.body.iter().any(|x| &x.name == b) {
                c.fail(format!("{p}.select.body"), format!("there is no body named '{b}'"));
            }
        }
    }
}

fn expectations(c: &mut Checker, s: &Scenario) {
    let columns: HashSet<String> = s
        .monitor
        .iter()
        .flat_map(|m| {
            m.quantities
                .iter()
                .flat_map(move |q| q.components().iter().map(move |k| format!("{}.{}.{k}", m.name, q.name())))
        })
        .chain(s.bolt.iter().flat_map(|b| b.columns()))
        .chain(s.seismic.columns())
        .collect();
    for (i, e) in s.expect.iter().enumerate() {
        let p = format!("expect[{i}]");
        if !columns.contains(&e.quantity) {
            c.fail(
                format!("{p}.quantity"),
                format!("'{}' is not a monitored column (<monitor>.<quantity>.<component>)", e.quantity),
            );
        }
        for (k, v) in [("reference", e.reference), ("at_least", e.at_least), ("at_most", e.at_most)] {
            if v.is_some_and(|v| !v.is_finite()) {
                c.fail(format!("{p}.{k}"), "must be a finite number");
            }
        }
        if e.reference.is_none() && e.at_least.is_none() && e.at_most.is_none() {
            c.fail(p.clone(), "give a reference, at_least or at_most");
        }
        for (k, v) in [("tolerance", e.tolerance), ("absolute_tolerance", e.absolute_tolerance)] {
            if !(v >= 0.0 && v.is_finite()) {
                c.fail(format!("{p}.{k}"), format!("must be a finite number >= 0, got {v}"));
            }
        }
    }
}
