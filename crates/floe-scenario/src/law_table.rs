//! A friction law's table in a file (`[friction]` of a scenario, `[law]` of
//! a spring-slider protocol): its keys are read generically and checked
//! against the law's parameter table in the
//! [`floe_friction::LawRegistry`], so that a law registered
//! there is read here without a line of this crate changing.

use std::collections::BTreeMap;
use std::ops::Range;

use floe_friction::{Law, LawContext, LawRegistry, ParamValue};
use toml::Spanned;

use crate::error::ScenarioError;
use crate::source_file::SourceFile;

/// A law's table as written: every key with its value and location.
pub type RawLawTable = BTreeMap<String, Spanned<toml::Value>>;

/// The law the table `raw` (named `table` in messages) describes: `kind_key`
/// names the law (`rate-state` when absent), `own_keys` are the caller's
/// (read elsewhere, not the law's), every other key is a parameter of the
/// law, checked against its table, with the defaults of `context`.
pub fn law_from_table(
    f: &SourceFile,
    raw: &RawLawTable,
    table: &str,
    kind_key: &str,
    own_keys: &[&str],
    registry: &LawRegistry,
    context: LawContext,
) -> Result<Law, ScenarioError> {
    let key = |k: &str| format!("{table}.{k}");
    let (name, name_span) = match raw.get(kind_key) {
        Some(v) => match v.get_ref() {
            toml::Value::String(s) => (s.as_str(), Some(v.span())),
            _ => {
                return Err(f.error(
                    v.span(),
                    key(kind_key),
                    format!("must be a law's name: {}", registry.names_text()),
                ))
            }
        },
        None => ("rate-state", None),
    };
    if registry.get(name).is_none() {
        return Err(f.error(
            name_span.unwrap_or(0..0),
            key(kind_key),
            format!("unknown law `{name}`, expected {}", registry.names_text()),
        ));
    }
    // The law's parameters in the file's order, so the first bad one is
    // the first reported.
    let mut given: Vec<(&str, Range<usize>, ParamValue)> = Vec::new();
    for (k, v) in raw {
        if k == kind_key || own_keys.contains(&k.as_str()) {
            continue;
        }
        let value = match v.get_ref() {
            toml::Value::Float(x) => ParamValue::Number(*x),
            toml::Value::Integer(i) => ParamValue::Number(*i as f64),
            toml::Value::String(s) => ParamValue::Word(s.clone()),
            other => {
                return Err(f.error(
                    v.span(),
                    key(k),
                    format!("must be a number or a word, got {}", other.type_str()),
                ))
            }
        };
        given.push((k.as_str(), v.span(), value));
    }
    given.sort_by_key(|(_, span, _)| span.start);
    let pairs: Vec<(&str, ParamValue)> = given.iter().map(|(k, _, v)| (*k, v.clone())).collect();
    registry.build(name, &pairs, context).map_err(|e| {
        let at = e
            .key
            .as_deref()
            .and_then(|k| given.iter().find(|(g, _, _)| *g == k))
            .map(|(_, span, _)| span.clone());
        match (at, &e.key) {
            (Some(span), Some(k)) => {
                let span = if e.value_at_fault {
                    span
                } else {
                    f.key_start(span)
                };
                f.error(span, key(k), e.message)
            }
            _ => match &name_span {
                Some(span) => f.error(span.clone(), key(kind_key), e.message),
                None => f.error_in_file(format!("[{table}]: {}", e.message)),
            },
        }
    })
}

/// Whether `own_key` (a key of the caller's, such as a preset) changes
/// anything for the law `raw` names: the preset only for laws with a
/// preset-dependent default.
pub fn preset_applies(raw: &RawLawTable, kind_key: &str, registry: &LawRegistry) -> bool {
    let name = raw
        .get(kind_key)
        .and_then(|v| v.get_ref().as_str())
        .unwrap_or("rate-state");
    registry.get(name).is_some_and(|e| {
        e.params
            .iter()
            .any(|p| matches!(p.default, floe_friction::ParamDefault::ByPreset(_)))
    })
}
