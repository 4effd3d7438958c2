//! Checks of a staged analysis: names, durations, what each stage removes, installs and
//! changes; the scenario of every stage is checked whole.

use super::Checker;
use crate::scenario::Scenario;

/// Stages: unique names, positive durations, excavations and bolts that exist and are named by
/// one stage only, and `set`s that give a valid scenario at every stage.
pub(super) fn stages(c: &mut Checker, s: &Scenario) {
    if !s.staged() {
        return;
    }
    c.unique("stage", s.stage.iter().map(|st| &st.name));
    c.unique("excavation", s.excavation.iter().filter_map(|e| e.name.as_ref()));
    let mut removed: Vec<&String> = Vec::new();
    let mut installed: Vec<&String> = Vec::new();
    for st in &s.stage {
        let p = format!("stage.{}", st.name);
        c.positive(&format!("{p}.duration"), st.duration);
        for n in &st.excavate {
            if !s.excavation.iter().any(|e| e.name.as_ref() == Some(n)) {
                c.fail(
                    format!("{p}.excavate"),
                    format!("there is no excavation named '{n}' (give it `name = \"{n}\"`)"),
                );
            } else if removed.contains(&n) {
                c.fail(format!("{p}.excavate"), format!("excavation '{n}' is removed by an earlier stage"));
            }
            removed.push(n);
        }
        for n in &st.install {
            if !s.bolt.iter().any(|b| &b.name == n) {
                c.fail(format!("{p}.install"), format!("there is no bolt or bolt pattern named '{n}'"));
            } else if installed.contains(&n) {
                c.fail(format!("{p}.install"), format!("bolt '{n}' is installed by an earlier stage"));
            }
            installed.push(n);
        }
    }
    if !c.problems.is_empty() {
        return;
    }
    for k in 0..s.stage.len() {
        match s.at_stage(k) {
            Err((path, reason)) => c.fail(path, reason),
            Ok(at) => {
                let prefix = format!("stage.{}.set: ", s.stage[k].name);
                for p in super::problems(&at) {
                    c.fail(p.path, prefix.clone() + &p.reason);
                }
            }
        }
        if !c.problems.is_empty() {
            return;
        }
    }
}
