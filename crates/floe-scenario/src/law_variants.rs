//! The scenario variants of a comparison: the user's scenario text with only
//! its `[friction]` table replaced, so each variant's output file stores the
//! exact scenario it ran (and can be resumed or rerun on its own).

use std::path::Path;

use floe_friction::{Law, LawEntry, LawRegistry, NumberStyle, ReferenceMatch};
use toml_edit::{value, DocumentMut, Item, Table, Value};

use crate::error::ScenarioError;
use crate::numbers::{parameter, sig};
use crate::source_file::SourceFile;

/// Numbers in what a law writes about itself (the build report's law, a
/// comparison's notes): parameters to six significant digits, derived
/// values to four.
pub const LAW_NUMBERS: NumberStyle = NumberStyle {
    parameter,
    measured: sig,
};

/// The law whose `mu` `--amontons-mu` gives.
const AMONTONS: &str = "amontons";

/// A law to compare, as named on the command line: a registry entry whose
/// [`ReferenceMatch`] matches it to the rate-and-state reference.
#[derive(Debug, Clone, Copy)]
pub struct LawChoice {
    entry: LawEntry,
}

impl PartialEq for LawChoice {
    /// The same law (names are unique in a registry).
    fn eq(&self, other: &Self) -> bool {
        self.entry.name == other.entry.name
    }
}

impl LawChoice {
    /// `registry`'s law `name`, if a comparison can match it to the
    /// rate-and-state reference.
    pub fn named(name: &str, registry: &LawRegistry) -> Option<LawChoice> {
        let entry = *registry.get(name)?;
        (!matches!(entry.reference_match, ReferenceMatch::Unmatched)).then_some(LawChoice { entry })
    }

    /// The name used in `--laws`, file names and the scenario's `law` key.
    pub fn name(self) -> &'static str {
        self.entry.name
    }

    /// Whether this is Amontons' law, whose `mu` `--amontons-mu` gives.
    pub fn is_amontons(self) -> bool {
        self.entry.name == AMONTONS
    }

    /// How the comparison's notes say this law was matched to `reference`
    /// at the reference slip speed: `None` for the reference itself.
    pub fn note(self, reference: &Law, matching: Matching) -> Option<String> {
        let (ReferenceMatch::Derived(derived), Law::RateState(rs)) =
            (self.entry.reference_match, reference)
        else {
            return None;
        };
        let v = matching.reference_slip_m_per_s;
        Some(match matching.amontons_mu {
            Some(mu) if self.is_amontons() => {
                format!("Amontons: mu = {} as given.", parameter(mu))
            }
            _ => (derived.note)(rs, v, &LAW_NUMBERS),
        })
    }

    /// Parses a comma-separated list, e.g. `amontons,rate,rate-state`:
    /// names of `registry`'s laws that a comparison can match to the
    /// rate-and-state reference.
    pub fn parse_list(list: &str, registry: &LawRegistry) -> Result<Vec<LawChoice>, ScenarioError> {
        let mut out = Vec::new();
        for word in list.split(',').map(str::trim).filter(|w| !w.is_empty()) {
            let law = match LawChoice::named(word, registry) {
                Some(law) => law,
                None if registry.get(word).is_some() => {
                    return Err(ScenarioError::Usage(format!(
                        "--laws: law `{word}` has no rule matching it to the rate-and-state \
                         reference; a comparison takes {}",
                        registry.comparable_names_text()
                    )))
                }
                None => {
                    return Err(ScenarioError::Usage(format!(
                        "--laws: unknown law `{word}`, expected {}",
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

/// How the laws are matched to the rate-and-state reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Matching {
    /// Slip speed at which the derived laws are matched to the
    /// rate-and-state reference (Amontons' `mu` equals its steady state
    /// there), m/s.
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
    let text = match choice.entry.reference_match {
        ReferenceMatch::Reference => reference_text.to_string(),
        ReferenceMatch::Derived(derived) => {
            let mut params = (derived.params)(rs, matching.reference_slip_m_per_s);
            if let (Some(mu), true) = (matching.amontons_mu, choice.is_amontons()) {
                params = vec![("mu", mu)];
            }
            with_friction(scenario_text, origin, |t| {
                keep_only(t, &[]);
                t.insert("law", value(choice.name()));
                for (key, x) in params {
                    t.insert(key, value(x));
                }
                Ok(())
            })?
        }
        ReferenceMatch::Unmatched => {
            return Err(ScenarioError::Usage(format!(
                "law `{}` has no rule matching it to the rate-and-state reference",
                choice.name()
            )))
        }
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
