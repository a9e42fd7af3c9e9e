//! Spring-slider protocol files (TOML): apparatus, friction law, initial
//! state, output spacing and the load-point segments. Every key is documented
//! in docs/friction.md ("Protocol files").

use std::path::Path;

use floe_friction::experiments::{Preset, PAPER_DT_S};
use floe_friction::protocol::{Protocol, Segment};
use floe_friction::spring_slider::Apparatus;
use floe_friction::{Amontons, Form, Law, RateDependent, RateState, RateStateParams, StateLaw};
use serde::Deserialize;
use toml::Spanned;

use crate::error::CliError;
use crate::input::SourceFile;

type Num = Option<Spanned<f64>>;
type Word = Option<Spanned<String>>;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    apparatus: Option<RawApparatus>,
    law: Option<RawLaw>,
    initial: Option<RawInitial>,
    output: Option<RawOutput>,
    segment: Option<Vec<Spanned<RawSegment>>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawApparatus {
    preset: Word,
    stiffness_n_per_m: Num,
    normal_load_n: Num,
    dt_s: Num,
}

/// The `[law]` table; which keys apply depends on `kind`.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawLaw {
    pub(crate) kind: Word,
    pub(crate) form: Word,
    pub(crate) state_law: Word,
    pub(crate) mu: Num,
    pub(crate) mu0: Num,
    pub(crate) a: Num,
    pub(crate) b: Num,
    pub(crate) c1: Num,
    pub(crate) v_star_m_per_s: Num,
    pub(crate) critical_slip_m: Num,
    pub(crate) v_floor_m_per_s: Num,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawInitial {
    slip_rate_m_per_s: Num,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawOutput {
    every_s: Num,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSegment {
    velocity_m_per_s: Num,
    ramp_m_per_s: Option<Spanned<Vec<f64>>>,
    duration_s: Spanned<f64>,
}

/// Everything a spring-slider run needs, read from a protocol file.
#[derive(Debug, Clone)]
pub struct SliderSetup {
    /// The friction law.
    pub law: Law,
    /// Spring, normal load, time step.
    pub apparatus: Apparatus,
    /// Load-point history.
    pub protocol: Protocol,
    /// Steady sliding rate the slider starts from, m/s.
    pub initial_slip_rate_m_per_s: f64,
    /// Spacing of output samples, s.
    pub every_s: f64,
    /// The file, verbatim (kept for provenance).
    pub source: SourceFile,
}

/// At most this many rows are written by default; longer runs are thinned.
const DEFAULT_MAX_ROWS: f64 = 100_000.0;

/// Reads and checks a protocol file.
pub fn load(path: &Path) -> Result<SliderSetup, CliError> {
    let source = SourceFile::read(path)?;
    let raw: RawFile = source.parse_toml()?;
    let f = &source;

    let no_preset = None;
    let preset_word = raw.apparatus.as_ref().map_or(&no_preset, |a| &a.preset);
    let preset = keyword(
        f,
        preset_word,
        "apparatus.preset",
        &[("lab", Preset::Lab), ("tank", Preset::Tank)],
        Preset::Lab,
    )?;
    let get =
        |v: &Num, key: &str, default: f64| v.as_ref().map_or(Ok(default), |v| f.positive(v, key));
    let apparatus = match &raw.apparatus {
        None => preset.apparatus(PAPER_DT_S),
        Some(a) => Apparatus {
            stiffness_n_per_m: get(
                &a.stiffness_n_per_m,
                "apparatus.stiffness_n_per_m",
                preset.stiffness_n_per_m(),
            )?,
            normal_load_n: get(
                &a.normal_load_n,
                "apparatus.normal_load_n",
                preset.normal_load_n(),
            )?,
            dt_s: get(&a.dt_s, "apparatus.dt_s", PAPER_DT_S)?,
        },
    };
    let law = build_law(
        f,
        raw.law.as_ref().unwrap_or(&RawLaw::default()),
        preset,
        Form::Published,
    )?;

    let Some(raw_segments) = raw.segment.as_ref().filter(|s| !s.is_empty()) else {
        return Err(
            f.error_in_file("no load-point history: add at least one [[segment]] with duration_s")
        );
    };
    let mut segments = Vec::with_capacity(raw_segments.len());
    for (i, s) in raw_segments.iter().enumerate() {
        let key = |k: &str| format!("segment[{i}].{k}");
        let seg = s.get_ref();
        let duration = f.positive(&seg.duration_s, &key("duration_s"))?;
        segments.push(match (&seg.velocity_m_per_s, &seg.ramp_m_per_s) {
            (Some(v), None) => Segment::constant(f.finite(v, &key("velocity_m_per_s"))?, duration),
            (None, Some(r)) => {
                let [from, to] = r.get_ref()[..] else {
                    return Err(f.error(
                        r.span(),
                        key("ramp_m_per_s"),
                        "must be [from, to] in m/s",
                    ));
                };
                if !(from.is_finite() && to.is_finite()) {
                    return Err(f.error(
                        r.span(),
                        key("ramp_m_per_s"),
                        "velocities must be finite",
                    ));
                }
                Segment::ramp(from, to, duration)
            }
            _ => return Err(f.error(
                s.span(),
                format!("segment[{i}]"),
                "give exactly one of velocity_m_per_s (0 for a hold) or ramp_m_per_s = [from, to]",
            )),
        });
    }
    let protocol = Protocol::new(segments)?;

    let initial = match raw
        .initial
        .as_ref()
        .and_then(|i| i.slip_rate_m_per_s.as_ref())
    {
        Some(v) => f.finite(v, "initial.slip_rate_m_per_s")?,
        None => protocol.initial_velocity_m_per_s(),
    };
    let default_every = apparatus.dt_s.max(protocol.duration_s() / DEFAULT_MAX_ROWS);
    let every_s = match raw.output.as_ref().and_then(|o| o.every_s.as_ref()) {
        Some(v) => f.positive(v, "output.every_s")?,
        None => default_every,
    };
    Ok(SliderSetup {
        law,
        apparatus,
        protocol,
        initial_slip_rate_m_per_s: initial,
        every_s,
        source: source.clone(),
    })
}

/// The value named by a keyword, or `default` if the key is absent.
pub(crate) fn keyword<T: Copy>(
    f: &SourceFile,
    word: &Word,
    key: &str,
    choices: &[(&str, T)],
    default: T,
) -> Result<T, CliError> {
    let Some(w) = word else {
        return Ok(default);
    };
    choices
        .iter()
        .find(|(name, _)| *name == w.get_ref())
        .map(|&(_, value)| value)
        .ok_or_else(|| {
            let names: Vec<String> = choices
                .iter()
                .map(|(name, _)| format!("`{name}`"))
                .collect();
            f.error(
                w.span(),
                key,
                format!(
                    "unknown value `{}`, expected one of {}",
                    w.get_ref(),
                    names.join(", ")
                ),
            )
        })
}

/// Builds a law from a `[law]` table. Unset parameters come from Lishman et
/// al. (2011) at the preset's scale; keys that do not apply to the chosen kind
/// are refused rather than ignored.
pub fn build_law(
    f: &SourceFile,
    raw: &RawLaw,
    preset: Preset,
    default_form: Form,
) -> Result<Law, CliError> {
    build_law_in(f, raw, preset, default_form, "law", "kind")
}

/// [`build_law`] for a table named `table` whose law is chosen by the key
/// `kind_key`: `[law] kind = ...` in protocol files, `[friction] law = ...`
/// in scenario files. Error messages name the keys as `table.key`.
pub fn build_law_in(
    f: &SourceFile,
    raw: &RawLaw,
    preset: Preset,
    default_form: Form,
    table: &str,
    kind_key: &str,
) -> Result<Law, CliError> {
    let kind = raw
        .kind
        .as_ref()
        .map_or("rate-state", |k| k.get_ref().as_str());
    // Keys that do not apply to the chosen law are refused, not ignored.
    let allowed: &[&str] = match kind {
        "amontons" => &["mu"],
        "rate" => &["mu0", "c1", "v_star_m_per_s", "v_floor_m_per_s"],
        "rate-state" => &[
            "mu0",
            "a",
            "b",
            "v_star_m_per_s",
            "critical_slip_m",
            "form",
            "state_law",
        ],
        other => {
            let span = raw.kind.as_ref().map(|k| k.span()).unwrap_or(0..0);
            return Err(f.error(
                span,
                format!("{table}.{kind_key}"),
                format!("unknown law `{other}`, expected `amontons`, `rate` or `rate-state`"),
            ));
        }
    };
    let numbers = [
        (&raw.mu, "mu"),
        (&raw.mu0, "mu0"),
        (&raw.a, "a"),
        (&raw.b, "b"),
        (&raw.c1, "c1"),
        (&raw.v_star_m_per_s, "v_star_m_per_s"),
        (&raw.critical_slip_m, "critical_slip_m"),
        (&raw.v_floor_m_per_s, "v_floor_m_per_s"),
    ];
    let words = [(&raw.form, "form"), (&raw.state_law, "state_law")];
    let given = numbers
        .iter()
        .filter_map(|(v, name)| v.as_ref().map(|v| (v.span(), *name)))
        .chain(
            words
                .iter()
                .filter_map(|(v, name)| v.as_ref().map(|v| (v.span(), *name))),
        );
    for (span, name) in given {
        if !allowed.contains(&name) {
            return Err(f.error(
                span,
                format!("{table}.{name}"),
                format!("does not apply to law `{kind}`"),
            ));
        }
    }
    let p = preset.params();
    let or = |v: &Num,
              name: &str,
              default: f64,
              check: fn(&SourceFile, &Spanned<f64>, &str) -> Result<f64, CliError>| {
        v.as_ref()
            .map_or(Ok(default), |v| check(f, v, &format!("{table}.{name}")))
    };
    match kind {
        "amontons" => {
            let Some(mu) = &raw.mu else {
                return Err(f.error_in_file(format!("law `amontons` needs `mu` in [{table}]")));
            };
            Ok(Law::Amontons(Amontons {
                mu: f.non_negative(mu, &format!("{table}.mu"))?,
            }))
        }
        "rate" => Ok(Law::RateDependent(RateDependent {
            mu0: or(&raw.mu0, "mu0", p.mu0, SourceFile::finite)?,
            c1: or(&raw.c1, "c1", p.a - p.b, SourceFile::finite)?,
            v_star_m_per_s: or(
                &raw.v_star_m_per_s,
                "v_star_m_per_s",
                p.v_star_m_per_s,
                SourceFile::positive,
            )?,
            v_floor_m_per_s: or(
                &raw.v_floor_m_per_s,
                "v_floor_m_per_s",
                p.v_star_m_per_s,
                SourceFile::positive,
            )?,
        })),
        _ => {
            // "rate-state", the only kind left after the check above.
            let params = RateStateParams {
                mu0: or(&raw.mu0, "mu0", p.mu0, SourceFile::finite)?,
                a: or(&raw.a, "a", p.a, SourceFile::positive)?,
                b: or(&raw.b, "b", p.b, SourceFile::non_negative)?,
                v_star_m_per_s: or(
                    &raw.v_star_m_per_s,
                    "v_star_m_per_s",
                    p.v_star_m_per_s,
                    SourceFile::positive,
                )?,
                critical_slip_m: or(
                    &raw.critical_slip_m,
                    "critical_slip_m",
                    p.critical_slip_m,
                    SourceFile::positive,
                )?,
            };
            let form = keyword(
                f,
                &raw.form,
                &format!("{table}.form"),
                &[
                    ("published", Form::Published),
                    ("regularized", Form::Regularized),
                    ("regularised", Form::Regularized),
                ],
                default_form,
            )?;
            let state_law = keyword(
                f,
                &raw.state_law,
                &format!("{table}.state_law"),
                &[
                    ("slip", StateLaw::Slip),
                    ("aging", StateLaw::Aging),
                    ("ageing", StateLaw::Aging),
                ],
                StateLaw::Slip,
            )?;
            Ok(Law::RateState(RateState::new(params, form, state_law)))
        }
    }
}
