//! The variants of a sweep: `--set key.path=v1,v2,...` options, their
//! cartesian product, and each variant's scenario text (the user's text with
//! those keys replaced, comments and layout kept).

use std::path::Path;

use toml_edit::{Item, Table, TableLike, Value};

use crate::error::ScenarioError;
use crate::source_file::SourceFile;

/// One `--set` option: a dotted key and the values it takes. A part
/// `name[k]` names the k-th `[[name]]` table (from 0): `wall[1].velocity_m_per_s`.
#[derive(Debug, Clone, PartialEq)]
pub struct Setting {
    /// Dotted key, e.g. `friction.a`.
    pub key: Vec<String>,
    /// The values as written (TOML syntax: `0.31`, `"tank"`, `[1.0, 2.0]`).
    pub values: Vec<String>,
}

impl Setting {
    /// The dotted key as written.
    pub fn dotted(&self) -> String {
        self.key.join(".")
    }
}

/// Parses `key.path=v1,v2,...`. Commas inside brackets or quotes belong to
/// the value (`wind.velocity_m_per_s=[5,0],[10,0]` has two values).
pub fn parse_setting(spec: &str) -> Result<Setting, ScenarioError> {
    let bad = |why: &str| ScenarioError::Usage(format!("--set {spec}: {why}"));
    let (key, values) = spec
        .split_once('=')
        .ok_or_else(|| bad("expected KEY=VALUE[,VALUE...]"))?;
    let key: Vec<String> = key
        .trim()
        .split('.')
        .map(|k| k.trim().to_string())
        .collect();
    if key.iter().any(|k| k.is_empty()) {
        return Err(bad("empty part in the key"));
    }
    let mut out = Vec::new();
    let (mut depth, mut quoted, mut start) = (0i32, false, 0usize);
    for (i, ch) in values.char_indices() {
        match ch {
            '"' => quoted = !quoted,
            '[' | '{' if !quoted => depth += 1,
            ']' | '}' if !quoted => depth -= 1,
            ',' if !quoted && depth == 0 => {
                out.push(values[start..i].trim().to_string());
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(values[start..].trim().to_string());
    if out.iter().any(|v| v.is_empty()) {
        return Err(bad("empty value"));
    }
    for v in &out {
        v.parse::<Value>().map_err(|e| {
            bad(&format!(
                "`{v}` is not a TOML value ({})",
                e.to_string().trim()
            ))
        })?;
    }
    Ok(Setting { key, values: out })
}

/// Refuses a key set twice, or set both as a whole table and inside it
/// (`wind=...` with `wind.velocity_m_per_s=...`): one would silently win.
pub fn check_distinct(settings: &[Setting]) -> Result<(), ScenarioError> {
    for (i, a) in settings.iter().enumerate() {
        for b in &settings[..i] {
            let n = a.key.len().min(b.key.len());
            if a.key[..n] == b.key[..n] {
                let why = if a.key == b.key {
                    format!(
                        "set twice (`{}` and `{}`); give the values in one --set {}={},{}",
                        b.values.join(","),
                        a.values.join(","),
                        a.dotted(),
                        b.values.join(","),
                        a.values.join(",")
                    )
                } else {
                    format!("overlaps --set {}: set one or the other", b.dotted())
                };
                return Err(ScenarioError::Usage(format!("--set {}: {why}", a.dotted())));
            }
        }
    }
    Ok(())
}

/// Every combination of the settings' values, first setting slowest.
pub fn cartesian(settings: &[Setting]) -> Vec<Vec<usize>> {
    let mut combos = vec![Vec::new()];
    for s in settings {
        combos = combos
            .into_iter()
            .flat_map(|c| {
                (0..s.values.len()).map(move |k| {
                    let mut c = c.clone();
                    c.push(k);
                    c
                })
            })
            .collect();
    }
    combos
}

/// `text` with each setting's key set to its chosen value; tables on the
/// way are created when missing. Whether the key means anything is left to
/// the scenario reader, which rejects unknown keys.
pub fn apply(
    text: &str,
    origin: &Path,
    settings: &[Setting],
    choice: &[usize],
) -> Result<String, ScenarioError> {
    let mut doc = SourceFile {
        path: origin.to_path_buf(),
        text: text.to_string(),
    }
    .parse_document()?;
    for (s, &k) in settings.iter().zip(choice) {
        let value: Value = s.values[k].parse().map_err(|_| {
            ScenarioError::Usage(format!("--set {}: bad value `{}`", s.dotted(), s.values[k]))
        })?;
        let (last, path) = s.key.split_last().expect("non-empty key");
        // Standard tables, then (once inside one) inline tables:
        // `wind.shear.y_min_m` sets a key of `shear = { ... }`.
        let mut table: &mut dyn TableLike = doc.as_table_mut();
        let mut inline = false;
        for part in path {
            let not_there = |what: &str| {
                ScenarioError::Usage(format!(
                    "--set {}: `{part}` is not {what} in {}",
                    s.dotted(),
                    origin.display()
                ))
            };
            table = match indexed(part) {
                // `wall[1]`: the second `[[wall]]` table, which must exist.
                Some((name, k)) => table
                    .get_mut(name)
                    .and_then(Item::as_array_of_tables_mut)
                    .and_then(|array| array.get_mut(k))
                    .map(|t| t as &mut dyn TableLike)
                    .ok_or_else(|| not_there(&format!("one of the `[[{name}]]` tables")))?,
                None => {
                    if !table.contains_key(part) {
                        let empty = if inline {
                            Item::Value(Value::InlineTable(Default::default()))
                        } else {
                            Item::Table(Table::new())
                        };
                        table.insert(part, empty);
                    }
                    let item = table.get_mut(part).expect("present or just inserted");
                    inline |= item.is_inline_table();
                    item.as_table_like_mut()
                        .ok_or_else(|| not_there("a table"))?
                }
            };
        }
        // In place when the key exists, so its comments stay with it.
        match table.get_mut(last).and_then(Item::as_value_mut) {
            Some(old) => {
                let decor = old.decor().clone();
                *old = value;
                *old.decor_mut() = decor;
            }
            None => {
                table.insert(last, Item::Value(value));
            }
        }
    }
    Ok(doc.to_string())
}

/// The item at a dotted key of `text` (a part `name[k]` names the k-th
/// `[[name]]` table, as in a setting), or `None` where the file does not
/// have it.
pub fn get(text: &str, origin: &Path, key: &[String]) -> Result<Option<Item>, ScenarioError> {
    let doc = SourceFile {
        path: origin.to_path_buf(),
        text: text.to_string(),
    }
    .parse_document()?;
    let mut item: Item = doc.as_item().clone();
    for part in key {
        let next = match indexed(part) {
            Some((name, k)) => item
                .get(name)
                .and_then(Item::as_array_of_tables)
                .and_then(|array| array.get(k))
                .map(|t| Item::Table(t.clone())),
            None => item.get(part.as_str()).cloned(),
        };
        match next {
            Some(next) => item = next,
            None => return Ok(None),
        }
    }
    Ok(Some(item))
}

/// The index of the first `[[array]]` table of `text` whose `key` is the
/// string `value` (e.g. the `[[wall]]` with `side = "top"`), for a `--set`
/// path `array[k]`.
pub fn find_table(
    text: &str,
    origin: &Path,
    array: &str,
    key: &str,
    value: &str,
) -> Result<Option<usize>, ScenarioError> {
    let doc = SourceFile {
        path: origin.to_path_buf(),
        text: text.to_string(),
    }
    .parse_document()?;
    Ok(doc
        .get(array)
        .and_then(Item::as_array_of_tables)
        .and_then(|tables| {
            tables
                .iter()
                .position(|t| t.get(key).and_then(Item::as_str) == Some(value))
        }))
}

/// `name[k]` as `(name, k)` (k counts from 0, as error messages do).
fn indexed(part: &str) -> Option<(&str, usize)> {
    let (name, rest) = part.split_once('[')?;
    let k = rest.strip_suffix(']')?.trim().parse().ok()?;
    Some((name.trim(), k))
}

/// A short label of a combination, e.g. `friction.a=0.25 friction.critical_slip_m=0.005`.
pub fn label(settings: &[Setting], choice: &[usize]) -> String {
    settings
        .iter()
        .zip(choice)
        .map(|(s, &k)| format!("{}={}", s.dotted(), s.values[k]))
        .collect::<Vec<_>>()
        .join(" ")
}
