//! `[output]` and `[[output.window]]`: the cadences of snapshots,
//! observables and checkpoints.

use std::ops::Range;

use toml::Spanned;

use crate::error::ScenarioError;
use crate::numbers::short;
use crate::output_cadence::{OutputCadence, OutputWindow};
use crate::source_file::SourceFile;
use crate::spec::{Num, RawOutput, RawOutputWindow};

/// Most `[[output.window]]` tables a file may give: each is looked at
/// whenever an output falls due.
pub const MAX_OUTPUT_WINDOWS: usize = 1000;

pub(crate) fn resolve_output(
    f: &SourceFile,
    raw: Option<&RawOutput>,
    duration_s: f64,
) -> Result<(OutputCadence, Vec<Range<usize>>), ScenarioError> {
    let get = |v: Option<&Spanned<f64>>, key: &str, default: f64| {
        v.map_or(Ok(default), |v| f.positive(v, key))
    };
    let mut cadence = OutputCadence {
        snapshot_every_s: get(
            raw.and_then(|o| o.snapshot_every_s.as_ref()),
            "output.snapshot_every_s",
            duration_s / 100.0,
        )?,
        observables_every_s: get(
            raw.and_then(|o| o.observables_every_s.as_ref()),
            "output.observables_every_s",
            duration_s / 1000.0,
        )?,
        checkpoint_every_s: get(
            raw.and_then(|o| o.checkpoint_every_s.as_ref()),
            "output.checkpoint_every_s",
            duration_s / 10.0,
        )?,
        windows: Vec::new(),
        ridging_log: raw
            .and_then(|o| o.ridging_log.as_ref())
            .is_some_and(|v| *v.get_ref()),
    };
    let raw_windows = raw.and_then(|o| o.window.as_deref()).unwrap_or(&[]);
    for (i, w) in raw_windows.iter().enumerate() {
        cadence.windows.push(resolve_window(f, w, i, duration_s)?);
    }
    Ok((cadence, raw_windows.iter().map(|w| w.span()).collect()))
}

/// `[[output.window]]` number `i`: `0 <= from_s < to_s <= duration_s`,
/// and at least one cadence, each > 0.
pub(crate) fn resolve_window(
    f: &SourceFile,
    w: &Spanned<RawOutputWindow>,
    i: usize,
    duration_s: f64,
) -> Result<OutputWindow, ScenarioError> {
    let key = |k: &str| format!("output.window[{i}].{k}");
    if i >= MAX_OUTPUT_WINDOWS {
        return Err(f.error(
            w.span(),
            format!("output.window[{i}]"),
            format!(
                "more than the {MAX_OUTPUT_WINDOWS} windows a scenario may have; \
                 merge neighbouring windows"
            ),
        ));
    }
    let r = w.get_ref();
    let missing = |k: &str, what: &str| f.error(w.span(), key(k), format!("missing: {what}"));
    let from = (r.from_s.as_ref()).ok_or_else(|| missing("from_s", "when the window starts, s"))?;
    let to = (r.to_s.as_ref()).ok_or_else(|| missing("to_s", "when the window ends, s"))?;
    let duration = (0.0, duration_s);
    let from_s = f.in_range(from, &key("from_s"), duration, "s (within the run)")?;
    let to_s = f.in_range(to, &key("to_s"), duration, "s (within the run)")?;
    if to_s <= from_s {
        return Err(f.error(
            to.span(),
            key("to_s"),
            format!(
                "{} s does not come after from_s = {} s: a window ends after it starts",
                short(to_s),
                short(from_s)
            ),
        ));
    }
    let every = |v: &Num, k: &str| v.as_ref().map(|v| f.positive(v, &key(k))).transpose();
    let snapshot_every_s = every(&r.snapshot_every_s, "snapshot_every_s")?;
    let observables_every_s = every(&r.observables_every_s, "observables_every_s")?;
    if snapshot_every_s.is_none() && observables_every_s.is_none() {
        return Err(f.error(
            w.span(),
            format!("output.window[{i}]"),
            "sets no cadence: give snapshot_every_s, observables_every_s or both",
        ));
    }
    Ok(OutputWindow {
        from_s,
        to_s,
        snapshot_every_s,
        observables_every_s,
    })
}
