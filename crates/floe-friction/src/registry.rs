//! The law registry: every friction law a file may name, with its
//! parameter table. A built-in law is its own file (the law, its
//! [`ParamSpec`] table and its [`LawEntry`]), one entry in
//! [`LawRegistry::builtin`] and one in the `builtin_laws!` list of
//! `any_law.rs`; a law outside this crate is a [`LawRegistry::register`]
//! call (see the `custom_law` example of `floe-scenario`).

use crate::any_law::Law;
use crate::builtin_entries;
use crate::error::FrictionError;
use crate::law::{FrictionLaw, LAW_STATE_SLOTS};
pub use crate::law_entry::LawEntry;
use crate::law_table::{LawContext, LawParams, ParamDefault, ParamKind, ParamValue};
use crate::reference_match::ReferenceMatch;

/// The laws files can name.
#[derive(Debug, Clone)]
pub struct LawRegistry {
    entries: Vec<LawEntry>,
}

/// A parameter that cannot be taken, with the key to point at.
#[derive(Debug, Clone, PartialEq)]
pub struct LawParamError {
    /// The key at fault; `None` for the law as a whole.
    pub key: Option<String>,
    /// Whether the key's value is at fault (out of range), rather than the
    /// key itself (not one of the law's).
    pub value_at_fault: bool,
    /// What is wrong and what would be accepted.
    pub message: String,
}

impl LawRegistry {
    /// The laws of this crate: Amontons, rate-dependent, rate-and-state.
    pub fn builtin() -> Self {
        LawRegistry {
            entries: vec![
                builtin_entries::AMONTONS,
                builtin_entries::RATE_DEPENDENT,
                builtin_entries::RATE_STATE,
            ],
        }
    }

    /// Adds a law; refuses a name already taken.
    pub fn register(&mut self, entry: LawEntry) -> Result<(), FrictionError> {
        if self.get(entry.name).is_some() {
            return Err(FrictionError::InvalidLaw(format!(
                "a law named `{}` is already registered",
                entry.name
            )));
        }
        self.entries.push(entry);
        Ok(())
    }

    /// The law named `name`.
    pub fn get(&self, name: &str) -> Option<&LawEntry> {
        self.entries.iter().find(|e| e.name == name)
    }

    /// Every law, in registration order.
    pub fn entries(&self) -> &[LawEntry] {
        &self.entries
    }

    /// The names, as a message lists them: "`amontons`, `rate` or `rate-state`".
    pub fn names_text(&self) -> String {
        names_text(self.entries.iter())
    }

    /// The names of the laws a comparison can match to its rate-and-state
    /// reference, as [`LawRegistry::names_text`] lists them.
    pub fn comparable_names_text(&self) -> String {
        names_text(
            self.entries
                .iter()
                .filter(|e| !matches!(e.reference_match, ReferenceMatch::Unmatched)),
        )
    }

    /// The law `name` from the parameters `given` (key, value, in the
    /// file's order), after checking each against the law's table and
    /// filling the defaults for `context`. The first problem is the error:
    /// an unknown law, a key the law does not have, a value out of range,
    /// a required key missing.
    pub fn build(
        &self,
        name: &str,
        given: &[(&str, ParamValue)],
        context: LawContext,
    ) -> Result<Law, LawParamError> {
        let Some(entry) = self.get(name) else {
            return Err(LawParamError {
                key: None,
                value_at_fault: false,
                message: format!("unknown law `{name}`, expected {}", self.names_text()),
            });
        };
        for (key, value) in given {
            let Some(spec) = entry.params.iter().find(|s| s.key == *key) else {
                let any_law = self
                    .entries
                    .iter()
                    .any(|e| e.params.iter().any(|s| s.key == *key));
                let takes: Vec<String> = entry
                    .params
                    .iter()
                    .map(|s| format!("`{}`", s.key))
                    .collect();
                let takes = if takes.is_empty() {
                    "no parameters".to_string()
                } else {
                    takes.join(", ")
                };
                return Err(LawParamError {
                    key: Some(key.to_string()),
                    value_at_fault: false,
                    message: if any_law {
                        format!("does not apply to law `{name}` (it takes {takes})")
                    } else {
                        format!("unknown key `{key}`; law `{name}` takes {takes}")
                    },
                });
            };
            let ok = match (&spec.kind, value) {
                (ParamKind::Word(words), ParamValue::Word(w)) => words.contains(&w.as_str()),
                (kind @ ParamKind::Number { .. }, ParamValue::Number(x)) => kind.accepts(*x),
                _ => false,
            };
            if !ok {
                let message = match (&spec.kind, value) {
                    (ParamKind::Word(words), ParamValue::Word(w)) => format!(
                        "unknown value `{w}`, expected {}",
                        ParamKind::Word(words).describe()
                    ),
                    (kind, _) => format!("must be {}, got {value}", kind.describe()),
                };
                return Err(LawParamError {
                    key: Some(key.to_string()),
                    value_at_fault: true,
                    message,
                });
            }
        }
        let mut values = Vec::with_capacity(entry.params.len());
        for spec in entry.params {
            let value = match given.iter().find(|(k, _)| *k == spec.key) {
                Some((_, v)) => v.clone(),
                None => match spec.default {
                    ParamDefault::Required => {
                        return Err(LawParamError {
                            key: None,
                            value_at_fault: false,
                            message: format!(
                                "law `{name}` needs `{}` ({})",
                                spec.key, spec.meaning
                            ),
                        })
                    }
                    ParamDefault::Number(x) => ParamValue::Number(x),
                    ParamDefault::ByPreset(f) => ParamValue::Number(f(context.preset)),
                    ParamDefault::Word(w) => ParamValue::Word(w.to_string()),
                    ParamDefault::Form => ParamValue::Word(
                        match context.default_form {
                            crate::params::Form::Published => "published",
                            crate::params::Form::Regularized => "regularized",
                        }
                        .to_string(),
                    ),
                },
            };
            values.push((spec.key, value));
        }
        let law = (entry.build)(&LawParams::new(values)).map_err(|message| LawParamError {
            key: None,
            value_at_fault: false,
            message,
        })?;
        if law.state_slots() > LAW_STATE_SLOTS {
            return Err(LawParamError {
                key: None,
                value_at_fault: false,
                message: format!(
                    "law `{name}` declares {} state slots per contact; a contact holds {LAW_STATE_SLOTS}",
                    law.state_slots()
                ),
            });
        }
        Ok(law)
    }

    /// The parameter tables as Markdown, one table per law (docs/scenarios.md
    /// holds this text; a test keeps them equal).
    pub fn markdown(&self) -> String {
        let mut out = String::new();
        for e in &self.entries {
            out.push_str(&format!("`law = \"{}\"`: {}.\n\n", e.name, e.summary));
            if e.params.is_empty() {
                out.push_str("No parameters.\n\n");
                continue;
            }
            out.push_str("| key | unit | default | valid | meaning |\n|---|---|---|---|---|\n");
            for p in e.params {
                let default = match p.default {
                    ParamDefault::Required => "**required**".to_string(),
                    ParamDefault::Number(x) => short(x),
                    ParamDefault::ByPreset(f) => format!(
                        "lab {}, tank {}",
                        short(f(crate::params::Preset::Lab)),
                        short(f(crate::params::Preset::Tank))
                    ),
                    ParamDefault::Word(w) => format!("`{w}`"),
                    ParamDefault::Form => {
                        "`regularized` (scenarios), `published` (slider protocols)".into()
                    }
                };
                let valid = p.kind.describe();
                let valid = match valid.strip_prefix("a finite number") {
                    Some("") => "any number".to_string(),
                    Some(rest) => rest.trim().to_string(),
                    None => valid,
                };
                out.push_str(&format!(
                    "| `{}` | {} | {default} | {valid} | {} |\n",
                    p.key, p.unit, p.meaning
                ));
            }
            out.push('\n');
        }
        out
    }
}

/// The entries' names, "`a`, `b` or `c`".
fn names_text<'a>(entries: impl Iterator<Item = &'a LawEntry>) -> String {
    let names: Vec<String> = entries.map(|e| format!("`{}`", e.name)).collect();
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        _ => names.join(""),
    }
}

/// A default as docs print it: at most ten significant digits (`A - B`
/// is -0.07200000000000001 in binary).
fn short(x: f64) -> String {
    let plain = format!("{x}");
    if plain.len() <= 12 {
        return plain;
    }
    let rounded: f64 = format!("{x:.9e}").parse().unwrap_or(x);
    format!("{rounded}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiments::Preset;
    use crate::rate_state::Form;
    use crate::{RateDependent, RateState};

    const TANK: LawContext = LawContext {
        preset: Preset::Tank,
        default_form: Form::Regularized,
    };

    #[test]
    fn defaults_give_the_published_laws() {
        let r = LawRegistry::builtin();
        let rs = r.build("rate-state", &[], TANK).unwrap();
        assert_eq!(
            rs,
            Law::RateState(RateState::new(
                crate::RateStateParams::lishman_2011_tank(),
                Form::Regularized,
                crate::StateLaw::Slip
            ))
        );
        let lab = LawContext {
            preset: Preset::Lab,
            default_form: Form::Published,
        };
        let rs = r.build("rate-state", &[], lab).unwrap();
        assert_eq!(
            rs,
            Law::RateState(RateState::new(
                crate::RateStateParams::lishman_2011_lab(),
                Form::Published,
                crate::StateLaw::Slip
            ))
        );
        assert_eq!(
            r.build("rate", &[], TANK).unwrap(),
            Law::RateDependent(RateDependent::lishman_2011(
                crate::params::LISHMAN_A - crate::params::LISHMAN_B
            ))
        );
    }

    #[test]
    fn bad_parameters_name_their_key() {
        let r = LawRegistry::builtin();
        let n = |x: f64| ParamValue::Number(x);
        let e = r.build("amontons", &[], TANK).unwrap_err();
        assert!(e.message.contains("needs `mu`"), "{e:?}");
        let e = r.build("amontons", &[("mu", n(-1.0))], TANK).unwrap_err();
        assert_eq!(e.key.as_deref(), Some("mu"));
        assert!(e.message.contains(">= 0"), "{e:?}");
        let e = r
            .build("amontons", &[("mu", n(0.5)), ("a", n(0.3))], TANK)
            .unwrap_err();
        assert_eq!(e.key.as_deref(), Some("a"));
        let e = r
            .build(
                "rate-state",
                &[("form", ParamValue::Word("x".into()))],
                TANK,
            )
            .unwrap_err();
        assert!(e.message.contains("`published`"), "{e:?}");
        let e = r.build("coulomb", &[], TANK).unwrap_err();
        assert!(
            e.message.contains("`amontons`, `rate` or `rate-state`"),
            "{e:?}"
        );
        let mut more = LawRegistry::builtin();
        assert!(more.register(r.entries()[0]).is_err());
    }
}
