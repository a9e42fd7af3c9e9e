//! The scenario variants of a comparison: the user's scenario text with only
//! its `[friction]` table replaced, so each variant's output file stores the
//! exact scenario it ran (and can be resumed or rerun on its own).

use std::path::Path;

use floe_friction::{FrictionLaw, Law, LawRegistry};
use toml_edit::{value, DocumentMut, Item, Table, Value};

use crate::error::ScenarioError;
use crate::numbers::parameter;
use crate::source_file::SourceFile;

/// A law to compare, as named on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LawChoice {
    /// Constant friction coefficient.
    Amontons,
    /// Rate-dependent friction (no memory).
    Rate,
    /// Rate-and-state friction (memory).
    RateState,
}

impl LawChoice {
    /// The name used in `--laws`, file names and the scenario's `law` key.
    pub fn name(self) -> &'static str {
        match self {
            LawChoice::Amontons => "amontons",
            LawChoice::Rate => "rate",
            LawChoice::RateState => "rate-state",
        }
    }

    /// Parses a comma-separated list, e.g. `amontons,rate,rate-state`:
    /// names of `registry`'s laws that a comparison can match to the
    /// rate-and-state reference.
    pub fn parse_list(list: &str, registry: &LawRegistry) -> Result<Vec<LawChoice>, ScenarioError> {
        let mut out = Vec::new();
        for word in list.split(',').map(str::trim).filter(|w| !w.is_empty()) {
            let law = match word {
                "amontons" => LawChoice::Amontons,
                "rate" => LawChoice::Rate,
                "rate-state" => LawChoice::RateState,
                other if registry.get(other).is_some() => {
                    return Err(ScenarioError::Usage(format!(
                        "--laws: law `{other}` has no rule matching it to the rate-and-state \
                         reference; a comparison takes amontons, rate and rate-state"
                    )))
                }
                other => {
                    return Err(ScenarioError::Usage(format!(
                        "--laws: unknown law `{other}`, expected {}",
                        registry.names_text()
                    )))
                }
            };
            if out.contains(&law) {
                return Err(ScenarioError::Usage(format!(
                    "--laws: `{word}` given twice"
                )));
            }
            out.push(law);
        }
        if out.is_empty() {
            return Err(ScenarioError::Usage("--laws: name at least one law".into()));
        }
        Ok(out)
    }
}

/// How the memoryless laws are matched to the rate-and-state reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Matching {
    /// Slip speed at which Amontons' `mu` equals the rate-and-state steady
    /// state, m/s.
    pub reference_slip_m_per_s: f64,
    /// An explicit Amontons `mu` instead.
    pub amontons_mu: Option<f64>,
}

/// The rate-and-state law the variants are matched to: the scenario's own
/// when it uses one, else Lishman et al.'s at the scenario's `preset` (as
/// the scenario file would build it with `law = "rate-state"`).
pub fn reference_law(
    scenario_text: &str,
    origin: &Path,
    build_law: impl Fn(&str) -> Result<Law, ScenarioError>,
) -> Result<(Law, String), ScenarioError> {
    let text = with_friction(scenario_text, origin, |t| {
        if t.get("law").and_then(Item::as_str) != Some("rate-state") {
            keep_only(t, &["preset", "form", "state_law", "critical_slip_m"]);
            t.insert("law", value("rate-state"));
        }
        Ok(())
    })?;
    Ok((build_law(&text)?, text))
}

/// The scenario text for `choice` (every number exact), and its
/// `[friction]` table alone as the report shows it (numbers to six
/// significant digits, see [`crate::numbers::parameter`]).
pub fn variant(
    scenario_text: &str,
    origin: &Path,
    choice: LawChoice,
    reference: &Law,
    reference_text: &str,
    matching: Matching,
) -> Result<(String, String), ScenarioError> {
    let Law::RateState(rs) = reference else {
        return Err(ScenarioError::Usage(
            "the reference law of a comparison must be rate-and-state".into(),
        ));
    };
    let p = rs.params;
    let text = match choice {
        LawChoice::RateState => reference_text.to_string(),
        LawChoice::Amontons => {
            let mu = matching
                .amontons_mu
                .unwrap_or_else(|| reference.mu_steady(matching.reference_slip_m_per_s));
            with_friction(scenario_text, origin, |t| {
                keep_only(t, &[]);
                t.insert("law", value("amontons"));
                t.insert("mu", value(mu));
                Ok(())
            })?
        }
        LawChoice::Rate => with_friction(scenario_text, origin, |t| {
            keep_only(t, &[]);
            t.insert("law", value("rate"));
            t.insert("mu0", value(p.mu0));
            // C1 = A - B: the same steady-state friction as the reference.
            t.insert("c1", value(p.a - p.b));
            t.insert("v_star_m_per_s", value(p.v_star_m_per_s));
            Ok(())
        })?,
    };
    let friction = friction_table(&text, origin)?;
    Ok((text, friction))
}

fn parse(text: &str, origin: &Path) -> Result<DocumentMut, ScenarioError> {
    SourceFile {
        path: origin.to_path_buf(),
        text: text.to_string(),
    }
    .parse_document()
}

/// `text` with its `[friction]` table (created if absent) edited by `edit`.
fn with_friction(
    text: &str,
    origin: &Path,
    edit: impl FnOnce(&mut Table) -> Result<(), ScenarioError>,
) -> Result<String, ScenarioError> {
    let mut doc = parse(text, origin)?;
    let item = doc
        .entry("friction")
        .or_insert_with(|| Item::Table(Table::new()));
    let Some(table) = item.as_table_mut() else {
        return Err(ScenarioError::Input {
            file: origin.to_path_buf(),
            line: 1,
            column: 1,
            key: Some("friction".into()),
            message: "must be a table ([friction])".into(),
        });
    };
    edit(table)?;
    Ok(doc.to_string())
}

fn keep_only(table: &mut Table, keep: &[&str]) {
    let drop: Vec<String> = table
        .iter()
        .map(|(k, _)| k.to_string())
        .filter(|k| !keep.contains(&k.as_str()))
        .collect();
    for k in drop {
        table.remove(&k);
    }
}

fn friction_table(text: &str, origin: &Path) -> Result<String, ScenarioError> {
    let doc = parse(text, origin)?;
    let mut only = DocumentMut::new();
    if let Some(t) = doc.get("friction") {
        let mut t = t.clone();
        if let Some(table) = t.as_table_like_mut() {
            for (_, item) in table.iter_mut() {
                if let Some(v) = item.as_value_mut() {
                    round_for_people(v);
                }
            }
        }
        only.insert("friction", t);
    }
    Ok(only.to_string())
}

/// `v` with its floats (also inside arrays and inline tables) rounded as
/// [`crate::numbers::parameter`] shows them, comments kept.
fn round_for_people(v: &mut Value) {
    match v {
        Value::Float(f) => {
            let x = *f.value();
            let shown: f64 = parameter(x).parse().unwrap_or(x);
            if shown != x {
                let decor = f.decor().clone();
                *v = Value::from(shown);
                *v.decor_mut() = decor;
            }
        }
        Value::Array(a) => a.iter_mut().for_each(round_for_people),
        Value::InlineTable(t) => t.iter_mut().for_each(|(_, v)| round_for_people(v)),
        _ => {}
    }
}
