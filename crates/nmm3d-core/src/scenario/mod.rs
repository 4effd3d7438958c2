//! Scenario v1: parsing (TOML or JSON), `--set` overrides and the semantic checks of the keys.
//! `crate::input` loads a scenario whole: parsed here, checked here and by the model (shapes).

mod overrides;
mod records;
pub mod schema;
mod shift;
mod validate;

use std::path::Path;

pub use records::spell_out;
pub use schema::*;
pub use validate::problems;

use crate::error::{Error, Result};

/// Read a scenario file and apply the overrides (not validated: `crate::input::load_file`).
pub fn read_file(path: &Path, overrides: &[String]) -> Result<Scenario> {
    let label = path.display().to_string();
    // A FIFO or device would block or never end; a directory cannot be read.
    if path.exists() && !path.is_file() {
        return Err(Error::input(&label, "<file>", "not a regular file (a directory, FIFO or device)"));
    }
    let text = std::fs::read_to_string(path)
        .map_err(|e| Error::input(&label, "<file>", format!("cannot read the file: {e}")))?;
    let base = path.parent().unwrap_or(Path::new("."));
    records::spell_out(parse_toml(&text, &label, overrides)?, base, &label)
}

/// Parse TOML text (`label` names the source in messages) and apply the overrides (not
/// validated).
pub fn parse_toml(text: &str, label: &str, overrides: &[String]) -> Result<Scenario> {
    let mut value: toml::Value = toml::from_str::<toml::Table>(text)
        .map(toml::Value::Table)
        .map_err(|e| Error::input(label, "<toml>", e.message().to_string() + &location(text, e.span())))?;
    for o in overrides {
        overrides::apply(&mut value, o).map_err(|(path, reason)| Error::input(label, path, reason))?;
    }
    let scenario: Scenario = serde_path_to_error::deserialize(value)
        .map_err(|e| Error::input(label, e.path().to_string(), e.inner().message().to_string()))?;
    Ok(scenario)
}

/// Parse a JSON document (from Python dictionaries) and apply the overrides (not validated).
pub fn parse_json(text: &str, label: &str, overrides: &[String]) -> Result<Scenario> {
    let mut json: serde_json::Value =
        serde_json::from_str(text).map_err(|e| Error::input(label, "<json>", e.to_string()))?;
    drop_nulls(&mut json);
    let toml_text = toml::to_string(&json).map_err(|e| Error::input(label, "<dict>", e.to_string()))?;
    records::spell_out(parse_toml(&toml_text, label, overrides)?, Path::new("."), label)
}

/// `null` means "absent" (TOML has no null).
fn drop_nulls(v: &mut serde_json::Value) {
    match v {
        serde_json::Value::Object(m) => {
            m.retain(|_, x| !x.is_null());
            m.values_mut().for_each(drop_nulls);
        }
        serde_json::Value::Array(a) => a.iter_mut().for_each(drop_nulls),
        _ => {}
    }
}

fn location(text: &str, span: Option<std::ops::Range<usize>>) -> String {
    match span {
        Some(r) => {
            let line = text[..r.start.min(text.len())].matches('\n').count() + 1;
            format!(" (line {line})")
        }
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Problem;

    const MINIMAL: &str = r#"
[[material]]
name = "rock"
density = 2500.0
young = 1e9
poisson = 0.25

[[body]]
name = "cube"
material = "rock"
shape = { box = { min = [0, 0, 0], max = [1, 1, 1] } }
"#;

    fn problems(text: &str, o: &[&str]) -> Vec<Problem> {
        let o: Vec<String> = o.iter().map(|s| s.to_string()).collect();
        match crate::input::from_toml_str(text, "t.toml", &o) {
            Err(Error::Scenario { problems, .. }) => problems,
            other => panic!("expected an input error, got {other:?}"),
        }
    }

    #[test]
    fn minimal_scenario_parses_with_defaults() {
        let s = crate::input::from_toml_str(MINIMAL, "t.toml", &[]).unwrap();
        assert_eq!(s.analysis.dt, 0.001);
        assert_eq!(s.cover.pattern, PatternKind::Tet6);
    }

    #[test]
    fn unknown_keys_are_named_with_their_path() {
        let p = problems(&(MINIMAL.to_string() + "[analysis]\nbogus = 1\n"), &[]);
        assert_eq!(p[0].path, "analysis.bogus");
        assert!(p[0].reason.contains("bogus"), "{}", p[0].reason);
    }

    #[test]
    fn overrides_address_named_entries() {
        let s = crate::input::from_toml_str(
            MINIMAL,
            "t.toml",
            &["material.rock.young=2e9".into(), "analysis.duration=2".into()],
        )
        .unwrap();
        assert_eq!(s.material[0].young, 2e9);
        assert_eq!(s.analysis.duration, 2.0);
        let p = problems(MINIMAL, &["material.granite.young=1"]);
        assert!(p[0].reason.contains("granite"));
    }

    #[test]
    fn bad_values_are_reported_together() {
        let p = problems(MINIMAL, &["material.rock.poisson=0.5", "material.rock.density=0", "cover.size=-1"]);
        let paths: Vec<&str> = p.iter().map(|x| x.path.as_str()).collect();
        assert!(paths.contains(&"material.rock.poisson"), "{paths:?}");
        assert!(paths.contains(&"material.rock.density"));
        assert!(paths.contains(&"cover.size"));
    }

    #[test]
    fn wrong_types_and_unknown_names() {
        let p = problems(MINIMAL, &["analysis.dt=\"fast\""]);
        assert_eq!(p[0].path, "analysis.dt");
        let p = problems(&MINIMAL.replace("material = \"rock\"", "material = \"granite\""), &[]);
        assert_eq!(p[0].path, "body.cube.material");
    }

    #[test]
    fn a_study_table_is_kept_as_given_and_overridable() {
        let text = MINIMAL.to_string() + "[study]\nkind = \"critical_friction\"\nrange = [5.0, 60.0]\n";
        let s = crate::input::from_toml_str(&text, "t.toml", &["study.range=[10.0, 40.0]".into()]).unwrap();
        let study = s.study.expect("kept");
        assert_eq!(study["kind"].as_str(), Some("critical_friction"));
        assert_eq!(study["range"].as_array().unwrap()[0].as_float(), Some(10.0));
        let json = serde_json::to_string(&crate::input::from_toml_str(MINIMAL, "t.toml", &[]).unwrap()).unwrap();
        assert!(!json.contains("study"), "absent study is not written: {json}");
    }

    #[test]
    fn malformed_toml_reports_the_line() {
        let p = problems("[analysis\n", &[]);
        assert!(p[0].reason.contains("line 1"), "{}", p[0].reason);
    }
}
