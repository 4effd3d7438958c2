//! `--set KEY=VALUE` overrides applied to the parsed TOML tree before typing.
//! A named entry (`[[material]]`, `[[joint]]`, `[[body]]`, `[[monitor]]`) is addressed by its
//! name: `joint.smooth.friction_angle=24`; other arrays by index: `constraint.0.directions=["z"]`.

/// Apply one override; on failure return (key path, reason).
pub fn apply(root: &mut toml::Value, spec: &str) -> Result<(), (String, String)> {
    let (key, raw) =
        spec.split_once('=').ok_or_else(|| (spec.to_string(), "an override must look like KEY=VALUE".to_string()))?;
    set(root, key.trim(), parse_value(raw.trim()))
}

/// Set `key` (a dotted path as in `--set`) to `value`; on failure return (key path, reason).
pub fn set(root: &mut toml::Value, key: &str, value: toml::Value) -> Result<(), (String, String)> {
    let parts: Vec<&str> = key.split('.').collect();
    let err = |reason: String| (key.to_string(), reason);
    let mut cur = root;
    let mut i = 0;
    while i + 1 < parts.len() {
        let seg = parts[i];
        let table = cur.as_table_mut().ok_or_else(|| err(format!("'{seg}' is not inside a table")))?;
        let entry = table.entry(seg.to_string()).or_insert_with(|| toml::Value::Table(toml::Table::new()));
        if let toml::Value::Array(items) = entry {
            let sel = parts[i + 1];
            let pos = match sel.parse::<usize>() {
                Ok(k) if k < items.len() => Some(k),
                _ => items.iter().position(|it| it.get("name").and_then(|n| n.as_str()) == Some(sel)),
            };
            let k = pos.ok_or_else(|| err(format!("there is no {seg} named '{sel}'")))?;
            cur = &mut items[k];
            i += 2;
        } else {
            cur = entry;
            i += 1;
        }
    }
    let last = parts[parts.len() - 1];
    if i >= parts.len() {
        return Err(err("the key names a whole entry, not a value".into()));
    }
    let table = cur.as_table_mut().ok_or_else(|| err(format!("'{last}' is not inside a table")))?;
    let _ = table.insert(last.to_string(), value);
    Ok(())
}

/// A TOML value if it parses as one, else a string.
fn parse_value(raw: &str) -> toml::Value {
    toml::from_str::<toml::Table>(&format!("v = {raw}"))
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| toml::Value::String(raw.to_string()))
}
