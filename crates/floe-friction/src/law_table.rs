//! What a law publishes about its parameters: key, unit, default, valid
//! range and a one-line meaning ([`ParamSpec`]), and the checked values a law
//! is built from ([`LawParams`]). The [`crate::registry`] holds the
//! entries; scenario files, spring-slider protocol files, `floe compare`
//! and docs/scenarios.md all read them from there.

use std::fmt;

use crate::params::{Form, Preset};

/// What values a parameter takes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ParamKind {
    /// A finite number between `min` and `max` (each bound excluded when
    /// its flag says so; infinite bounds are open).
    Number {
        /// Lower bound.
        min: f64,
        /// Whether `min` itself is excluded.
        min_open: bool,
        /// Upper bound.
        max: f64,
        /// Whether `max` itself is excluded.
        max_open: bool,
    },
    /// One of these words (the first of each meaning is the one written in
    /// docs; the others are accepted spellings).
    Word(&'static [&'static str]),
}

impl ParamKind {
    /// Any finite number.
    pub const FINITE: ParamKind = ParamKind::Number {
        min: f64::NEG_INFINITY,
        min_open: true,
        max: f64::INFINITY,
        max_open: true,
    };
    /// A finite number > 0.
    pub const POSITIVE: ParamKind = ParamKind::Number {
        min: 0.0,
        min_open: true,
        max: f64::INFINITY,
        max_open: true,
    };
    /// A finite number >= 0.
    pub const NON_NEGATIVE: ParamKind = ParamKind::Number {
        min: 0.0,
        min_open: false,
        max: f64::INFINITY,
        max_open: true,
    };

    /// A friction coefficient, 0 to 10: sea ice's are below 1, and a
    /// value above 10 is a typo, not friction.
    pub const FRICTION_COEFFICIENT: ParamKind = ParamKind::Number {
        min: 0.0,
        min_open: false,
        max: 10.0,
        max_open: false,
    };
    /// A rate or state coefficient of friction (A, B, C1): at most 10 in
    /// magnitude (the paper's are about 0.3).
    pub const FRICTION_RATE: ParamKind = ParamKind::Number {
        min: -10.0,
        min_open: false,
        max: 10.0,
        max_open: false,
    };
    /// A positive rate coefficient, at most 10.
    pub const POSITIVE_FRICTION_RATE: ParamKind = ParamKind::Number {
        min: 0.0,
        min_open: true,
        max: 10.0,
        max_open: false,
    };
    /// A non-negative rate coefficient, at most 10.
    pub const NON_NEGATIVE_FRICTION_RATE: ParamKind = ParamKind::Number {
        min: 0.0,
        min_open: false,
        max: 10.0,
        max_open: false,
    };

    /// Whether `x` is in range.
    pub fn accepts(&self, x: f64) -> bool {
        match *self {
            ParamKind::Number {
                min,
                min_open,
                max,
                max_open,
            } => {
                x.is_finite()
                    && if min_open { x > min } else { x >= min }
                    && if max_open { x < max } else { x <= max }
            }
            ParamKind::Word(_) => false,
        }
    }

    /// The range as a message says it: "a finite number > 0", "one of
    /// `slip`, `aging`".
    pub fn describe(&self) -> String {
        match *self {
            ParamKind::Number {
                min,
                min_open,
                max,
                max_open,
            } => {
                let lo = (min > f64::NEG_INFINITY)
                    .then(|| format!("{} {min}", if min_open { ">" } else { ">=" }));
                let hi = (max < f64::INFINITY)
                    .then(|| format!("{} {max}", if max_open { "<" } else { "<=" }));
                match (lo, hi) {
                    (None, None) => "a finite number".into(),
                    (Some(l), None) => format!("a finite number {l}"),
                    (None, Some(h)) => format!("a finite number {h}"),
                    (Some(l), Some(h)) => format!("a finite number {l} and {h}"),
                }
            }
            ParamKind::Word(words) => format!(
                "one of {}",
                words
                    .iter()
                    .map(|w| format!("`{w}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }
    }
}

/// A parameter's default.
#[derive(Debug, Clone, Copy)]
pub enum ParamDefault {
    /// None: the parameter must be given.
    Required,
    /// This number.
    Number(f64),
    /// The published value at the preset's scale (lab or tank).
    ByPreset(fn(Preset) -> f64),
    /// This word.
    Word(&'static str),
    /// The law's form: where the file is read decides ([`LawContext`]).
    Form,
}

/// One parameter of a law.
#[derive(Debug, Clone, Copy)]
pub struct ParamSpec {
    /// Key in the file (`critical_slip_m`).
    pub key: &'static str,
    /// Unit, SI (`m/s`), empty for dimensionless numbers and words.
    pub unit: &'static str,
    /// What values it takes.
    pub kind: ParamKind,
    /// Its default.
    pub default: ParamDefault,
    /// What it means, in one line.
    pub meaning: &'static str,
}

/// A checked value.
#[derive(Debug, Clone, PartialEq)]
pub enum ParamValue {
    /// A number.
    Number(f64),
    /// A word.
    Word(String),
}

impl fmt::Display for ParamValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            // Scientific past 16 characters: 1e300, not its 301 digits.
            ParamValue::Number(x) if format!("{x}").len() > 16 => write!(f, "{x:e}"),
            ParamValue::Number(x) => write!(f, "{x}"),
            ParamValue::Word(w) => write!(f, "`{w}`"),
        }
    }
}

/// Where a law is read: decides the defaults that depend on the use.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LawContext {
    /// The published parameter set that fills preset-dependent defaults.
    pub preset: Preset,
    /// The rate-and-state form when none is given: regularized for DEM
    /// contacts (scenario files), published for the paper's spring-slider.
    pub default_form: Form,
}

/// Every parameter of a law, checked and with defaults applied: what a
/// `LawEntry::build` ([`crate::registry`]) reads.
#[derive(Debug, Clone, PartialEq)]
pub struct LawParams {
    values: Vec<(&'static str, ParamValue)>,
}

impl LawParams {
    pub(crate) fn new(values: Vec<(&'static str, ParamValue)>) -> Self {
        LawParams { values }
    }

    /// The number under `key`. Panics if the law's table has no such
    /// number (a mistake in the law's own code, not in a file).
    pub fn number(&self, key: &str) -> f64 {
        match self.get(key) {
            Some(ParamValue::Number(x)) => *x,
            other => panic!("law parameter `{key}` is not a number in the table: {other:?}"),
        }
    }

    /// The word under `key` (its canonical spelling is not guaranteed:
    /// compare with every spelling the table accepts). Panics as
    /// [`LawParams::number`].
    pub fn word(&self, key: &str) -> &str {
        match self.get(key) {
            Some(ParamValue::Word(w)) => w,
            other => panic!("law parameter `{key}` is not a word in the table: {other:?}"),
        }
    }

    /// The value under `key`, if the table has it.
    pub fn get(&self, key: &str) -> Option<&ParamValue> {
        self.values.iter().find(|(k, _)| *k == key).map(|(_, v)| v)
    }

    /// Every key and value, in the table's order.
    pub fn iter(&self) -> impl Iterator<Item = (&'static str, &ParamValue)> {
        self.values.iter().map(|(k, v)| (*k, v))
    }
}
