//! Spring-slider protocol files (TOML): apparatus, friction law, initial
//! state, output spacing and the load-point segments. Every key is documented
//! in docs/friction.md ("Protocol files").

use std::ops::Not;
use std::path::Path;

use floe_friction::experiments::{
    Preset, MAX_LOAD_POINT_SPEED_M_PER_S, MAX_SLIDER_DT_S, MAX_SLIDER_STEPS, PAPER_DT_S,
    SLIDER_NORMAL_LOAD_RANGE_N, SLIDER_STIFFNESS_RANGE_N_PER_M,
};
use floe_friction::protocol::{Protocol, Segment};
use floe_friction::spring_slider::Apparatus;
use floe_friction::{Form, Law, LawContext, LawRegistry};
use serde::Deserialize;
use toml::Spanned;

use crate::error::ScenarioError;
use crate::law_table::{law_from_table, RawLawTable};
use crate::numbers::{short, short_list};
use crate::source_file::SourceFile;

type Num = Option<Spanned<f64>>;
type Word = Option<Spanned<String>>;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    apparatus: Option<RawApparatus>,
    /// `kind` and the law's parameters ([`crate::law_table`]).
    law: Option<RawLawTable>,
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

/// Reads and checks a protocol file, with the friction laws of
/// [`LawRegistry::builtin`].
pub fn load(path: &Path) -> Result<SliderSetup, ScenarioError> {
    load_with(path, &LawRegistry::builtin(), MAX_SLIDER_STEPS)
}

/// [`load`] with the laws of `registry`, refusing a protocol of more than
/// `max_steps` time steps (located at the longest segment, or at the time
/// step when that is what makes it long).
pub fn load_with(
    path: &Path,
    registry: &LawRegistry,
    max_steps: f64,
) -> Result<SliderSetup, ScenarioError> {
    let source = SourceFile::read(path)?;
    let raw: RawFile = source.parse_toml()?;
    let f = &source;

    let no_preset = None;
    let preset_word = raw.apparatus.as_ref().map_or(&no_preset, |a| &a.preset);
    let preset = f.keyword(
        preset_word,
        "apparatus.preset",
        &[("lab", Preset::Lab), ("tank", Preset::Tank)],
        Preset::Lab,
    )?;
    let apparatus = match &raw.apparatus {
        None => preset.apparatus(PAPER_DT_S),
        Some(a) => Apparatus {
            stiffness_n_per_m: match &a.stiffness_n_per_m {
                Some(v) => f.in_range(
                    v,
                    "apparatus.stiffness_n_per_m",
                    SLIDER_STIFFNESS_RANGE_N_PER_M,
                    "N/m",
                )?,
                None => preset.stiffness_n_per_m(),
            },
            normal_load_n: match &a.normal_load_n {
                Some(v) => f.in_range(
                    v,
                    "apparatus.normal_load_n",
                    SLIDER_NORMAL_LOAD_RANGE_N,
                    "N",
                )?,
                None => preset.normal_load_n(),
            },
            dt_s: match &a.dt_s {
                Some(v) => match f.positive(v, "apparatus.dt_s")? {
                    dt if dt <= MAX_SLIDER_DT_S => dt,
                    dt => {
                        return Err(f.error(
                            v.span(),
                            "apparatus.dt_s",
                            format!(
                                "{} s is above the longest accepted step, {MAX_SLIDER_DT_S} s \
                                 (the paper's is {PAPER_DT_S} s)",
                                short(dt)
                            ),
                        ))
                    }
                },
                None => PAPER_DT_S,
            },
        },
    };
    let law = law_from_table(
        f,
        raw.law.as_ref().unwrap_or(&RawLawTable::new()),
        "law",
        "kind",
        &[],
        registry,
        LawContext {
            preset,
            default_form: Form::Published,
        },
    )?;

    let Some(raw_segments) = raw.segment.as_ref().filter(|s| !s.is_empty()) else {
        return Err(
            f.error_in_file("no load-point history: add at least one [[segment]] with duration_s")
        );
    };
    const SPEEDS: (f64, f64) = (-MAX_LOAD_POINT_SPEED_M_PER_S, MAX_LOAD_POINT_SPEED_M_PER_S);
    let mut segments = Vec::with_capacity(raw_segments.len());
    for (i, s) in raw_segments.iter().enumerate() {
        let key = |k: &str| format!("segment[{i}].{k}");
        let seg = s.get_ref();
        let duration = f.positive(&seg.duration_s, &key("duration_s"))?;
        segments.push(match (&seg.velocity_m_per_s, &seg.ramp_m_per_s) {
            (Some(v), None) => Segment::constant(
                f.in_range(v, &key("velocity_m_per_s"), SPEEDS, "m/s")?,
                duration,
            ),
            (None, Some(r)) => {
                let [from, to] = r.get_ref()[..] else {
                    return Err(f.error(
                        r.span(),
                        key("ramp_m_per_s"),
                        "must be [from, to] in m/s",
                    ));
                };
                let (lo, hi) = SPEEDS;
                if !(from.is_finite() && to.is_finite() && lo <= from.min(to) && from.max(to) <= hi)
                {
                    return Err(f.error(
                        r.span(),
                        key("ramp_m_per_s"),
                        format!(
                            "velocities must lie in [{}, {}] m/s, got {}",
                            short(lo),
                            short(hi),
                            short_list(&[from, to])
                        ),
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
    let steps = protocol.duration_s() / apparatus.dt_s;
    if (steps <= max_steps).not() {
        let dt_given = raw.apparatus.as_ref().and_then(|a| a.dt_s.as_ref());
        let (span, key) = match dt_given {
            Some(dt) if *dt.get_ref() < PAPER_DT_S => (dt.span(), "apparatus.dt_s".to_string()),
            _ => {
                let (i, longest) = raw_segments
                    .iter()
                    .enumerate()
                    .max_by(|a, b| {
                        a.1.get_ref()
                            .duration_s
                            .get_ref()
                            .total_cmp(b.1.get_ref().duration_s.get_ref())
                    })
                    .expect("at least one segment");
                (
                    longest.get_ref().duration_s.span(),
                    format!("segment[{i}].duration_s"),
                )
            }
        };
        return Err(f.error(
            span,
            key,
            format!(
                "the protocol takes {steps:.3e} time steps of {:.3e} s, above the limit of \
                 {max_steps:.0e} (raise it with --step-limit N)",
                apparatus.dt_s
            ),
        ));
    }

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
