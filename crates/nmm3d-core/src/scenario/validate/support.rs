//! Checks of the support: rock bolts, anchored or grouted.

use super::Checker;
use crate::scenario::{Bolt, Scenario};

/// Bolts: unique names (not a monitor's either), a length, and the keys of their kind.
pub(super) fn bolts(c: &mut Checker, s: &Scenario) {
    c.unique("bolt", s.bolt.iter().map(|b| &b.name));
    for b in &s.bolt {
        let p = format!("bolt.{}", b.name);
        if s.monitor.iter().any(|m| m.name == b.name) {
            c.fail(format!("{p}.name"), "a monitor has this name too (their history columns would clash)");
        }
        if b.grout.grouted {
            grouted_bolt(c, &p, b);
        } else {
            anchored_bolt(c, &p, b);
        }
        for (key, v) in [("yield_force", b.yield_force), ("rupture_elongation", b.rupture_elongation)] {
            if let Some(v) = v {
                c.positive(&format!("{p}.{key}"), v);
            }
        }
        let d: f64 = (0..3).map(|i| (b.head[i] - b.anchor[i]).powi(2)).sum::<f64>().sqrt();
        if !(d > 0.0) {
            c.fail(format!("{p}.anchor"), "the anchor must differ from the head");
        }
    }
}

/// An anchored bolt: a stiffness, a pretension within its yield force, no grout keys.
fn anchored_bolt(c: &mut Checker, p: &str, b: &Bolt) {
    match b.stiffness {
        Some(k) => c.positive(&format!("{p}.stiffness"), k),
        None => c.fail(format!("{p}.stiffness"), "required for an anchored bolt (or set grouted = true)"),
    }
    if !(b.pretension >= 0.0 && b.pretension.is_finite()) {
        c.fail(format!("{p}.pretension"), format!("must be a finite number >= 0, got {}", b.pretension));
    }
    if b.yield_force.is_some_and(|y| b.pretension > y) {
        c.fail(format!("{p}.pretension"), "exceeds the yield force");
    }
    let g = &b.grout;
    for (key, v) in [
        ("axial_rigidity", g.axial_rigidity),
        ("bond_stiffness", g.bond_stiffness),
        ("bond_strength", g.bond_strength),
        ("foundation_modulus", g.foundation_modulus),
        ("diameter", g.diameter),
        ("shear_capacity", g.shear_capacity),
    ] {
        if v.is_some() {
            c.fail(format!("{p}.{key}"), "a grouted bolt's key (set grouted = true)");
        }
    }
}

/// A grouted bolt: its bar's axial rigidity and its grout's stiffness, the dowel's foundation
/// with a diameter, no stiffness or pretension of an anchored bolt.
fn grouted_bolt(c: &mut Checker, p: &str, b: &Bolt) {
    let g = &b.grout;
    for (key, v) in [("axial_rigidity", g.axial_rigidity), ("bond_stiffness", g.bond_stiffness)] {
        match v {
            Some(v) => c.positive(&format!("{p}.{key}"), v),
            None => c.fail(format!("{p}.{key}"), "required for a grouted bolt"),
        }
    }
    for (key, v) in [
        ("bond_strength", g.bond_strength),
        ("foundation_modulus", g.foundation_modulus),
        ("diameter", g.diameter),
        ("shear_capacity", g.shear_capacity),
    ] {
        if let Some(v) = v {
            c.positive(&format!("{p}.{key}"), v);
        }
    }
    if g.foundation_modulus.is_some() != g.diameter.is_some() {
        c.fail(format!("{p}.diameter"), "the dowel action takes both foundation_modulus and diameter");
    }
    if b.stiffness.is_some() {
        c.fail(
            format!("{p}.stiffness"),
            "an anchored bolt's key: a grouted bolt takes axial_rigidity and bond_stiffness",
        );
    }
    if b.pretension != 0.0 {
        c.fail(format!("{p}.pretension"), "a grouted bolt is not pretensioned here (use an anchored bolt)");
    }
}
