//! What a scenario gives in short is spelled out when it is loaded, into the scenario itself —
//! records named by file (a base-motion CSV), bolt patterns as bolts: `check` and `run` then
//! see the same numbers, and a run's checkpoint holds them.

use std::path::Path;

use super::schema::Scenario;
use crate::error::{Error, Result};

/// Read `[seismic.series] file` (relative to `base`) into its `time` and `values`, and apply
/// `scale` (then 1: loading the loaded scenario again changes nothing).
pub fn spell_out(mut s: Scenario, base: &Path, label: &str) -> Result<Scenario> {
    expand_patterns(&mut s, label)?;
    let Some(series) = s.seismic.series.as_mut() else { return Ok(s) };
    if let Some(file) = series.file.take() {
        read_csv(series, base, &file, label)?;
    }
    let scale = std::mem::replace(&mut series.scale, 1.0);
    series.values.iter_mut().for_each(|v| *v = v.map(|x| x * scale));
    Ok(s)
}

/// Each `[[bolt_pattern]]` becomes its bolts (the pattern leaves the scenario; a stage that
/// installs the pattern installs its bolts).
fn expand_patterns(s: &mut Scenario, label: &str) -> Result<()> {
    for p in std::mem::take(&mut s.bolt_pattern) {
        let at = format!("bolt_pattern.{}", p.name);
        if !(p.length > p.head_depth && p.head_depth > 0.0 && p.length.is_finite()) {
            return Err(Error::input(label, format!("{at}.length"), "must exceed head_depth, which must be > 0"));
        }
        let bolts = p.bolts();
        if bolts.is_empty() {
            return Err(Error::input(label, at, "gives no bolt (a count of 0, or a zero direction)"));
        }
        for st in &mut s.stage {
            if let Some(i) = st.install.iter().position(|n| n == &p.name) {
                st.install.splice(i..=i, bolts.iter().map(|b| b.name.clone()));
            }
        }
        s.bolt.extend(bolts);
    }
    Ok(())
}

fn read_csv(series: &mut super::schema::Series, base: &Path, file: &str, label: &str) -> Result<()> {
    let key = "seismic.series.file";
    if !series.time.is_empty() || !series.values.is_empty() {
        return Err(Error::input(label, key, "give the record either as a file or as time and values, not both"));
    }
    let path = base.join(file);
    let text =
        std::fs::read_to_string(&path).map_err(|e| Error::input(label, key, format!("cannot read {file}: {e}")))?;
    for (k, line) in text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        let numbers: Option<Vec<f64>> = cells.iter().map(|c| c.parse().ok()).collect();
        match numbers {
            Some(v) if v.len() == 4 => {
                series.time.push(v[0]);
                series.values.push([v[1], v[2], v[3]]);
            }
            // A header line.
            None if k == 0 => {}
            _ => {
                let why = format!("{file}, line {}: expected four numbers `time, x, y, z`, got `{line}`", k + 1);
                return Err(Error::input(label, key, why));
            }
        }
    }
    Ok(())
}
