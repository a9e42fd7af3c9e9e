//! The range checks every section shares: counts, lengths, thicknesses,
//! densities and speeds, each refused with its location and key.

use std::ops::Not;
use std::ops::Range;

use floe_dem::{DemError, Vec2};
use toml::Spanned;

use crate::error::ScenarioError;
use crate::extent::{Extent, MAX_TRAVEL_DOMAINS};
use crate::numbers::{short, sig};
use crate::source_file::SourceFile;
use crate::spec::Exact;

/// What a table allows, for refusing keys that do not apply.
pub(crate) fn refuse_given(
    f: &SourceFile,
    table: &str,
    what: &str,
    given: &[(Option<Range<usize>>, &str)],
    allowed: &[&str],
) -> Result<(), ScenarioError> {
    for (span, name) in given {
        if let Some(span) = span {
            if !allowed.contains(name) {
                return Err(f.error(
                    span.clone(),
                    format!("{table}.{name}"),
                    format!("does not apply to {what}"),
                ));
            }
        }
    }
    Ok(())
}

pub(crate) fn span_of<T>(v: &Option<Spanned<T>>) -> Option<Range<usize>> {
    v.as_ref().map(|s| s.span())
}

/// A count in `[min, max]`: every count of work is bounded before the
/// work starts.
pub(crate) fn count(
    f: &SourceFile,
    v: &Spanned<i64>,
    key: &str,
    min: i64,
    max: u64,
) -> Result<usize, ScenarioError> {
    let n = *v.get_ref();
    if n >= min && n as u64 <= max {
        Ok(n as usize)
    } else {
        Err(f.error(
            v.span(),
            key,
            format!("must be an integer from {min} to {max}, got {n}"),
        ))
    }
}
pub use crate::length_limit::MAX_LENGTH_M;

/// Thinnest ice a file may give, m: new ice (nilas) is centimetres thick;
/// far thinner floes have a time-step limit that underflows.
pub const MIN_THICKNESS_M: f64 = 1e-3;

/// Thickest ice a file may give, m (icebergs reach a few hundred metres).
pub const MAX_THICKNESS_M: f64 = 1e4;

/// Densest ice, air or water a file may give, kg/m^3.
pub const MAX_DENSITY_KG_PER_M3: f64 = 1e5;

/// Refuses values whose magnitude is above `max` (`unit` for the message).
pub(crate) fn at_most(
    f: &SourceFile,
    span: Range<usize>,
    key: &str,
    values: &[f64],
    max: f64,
    unit: &str,
) -> Result<(), ScenarioError> {
    match values.iter().find(|x| (x.abs() <= max).not()) {
        None => Ok(()),
        Some(&x) => Err(f.error(
            span,
            key,
            format!(
                "{} {unit} is beyond the largest accepted magnitude, {} {unit}",
                short(x),
                sig(max)
            ),
        )),
    }
}

/// Refuses a constant `velocity` (at `v`) that would carry a prescribed
/// `what` more than [`MAX_TRAVEL_DOMAINS`] domain sizes across the
/// domain's non-periodic axes within the run.
pub(crate) fn travel_within(
    f: &SourceFile,
    v: &Spanned<Exact<f64, 2>>,
    key: &str,
    velocity: Vec2,
    extent: Extent,
    what: &str,
) -> Result<(), ScenarioError> {
    let d = extent.domain;
    let across = |axis: usize, speed: f64| if d.periodic[axis] { 0.0 } else { speed.abs() };
    let travel = across(0, velocity.x).hypot(across(1, velocity.y)) * extent.duration_s;
    let most = MAX_TRAVEL_DOMAINS * d.size_m.x.max(d.size_m.y);
    if travel <= most {
        return Ok(());
    }
    Err(f.error(
        v.span(),
        key,
        format!(
            "moves the {what} {} m across the domain's non-periodic axes in duration_s = {} s, \
             more than {MAX_TRAVEL_DOMAINS} domain sizes ({} m)",
            sig(travel),
            sig(extent.duration_s),
            sig(most)
        ),
    ))
}

/// A number > 0 (>= 0 when `zero_ok`) and at most `max` (in `unit`).
pub(crate) fn sized(
    f: &SourceFile,
    v: &Spanned<f64>,
    key: &str,
    zero_ok: bool,
    (max, unit): (f64, &str),
) -> Result<f64, ScenarioError> {
    let x = if zero_ok {
        f.non_negative(v, key)?
    } else {
        f.positive(v, key)?
    };
    at_most(f, v.span(), key, &[x], max, unit)?;
    Ok(x)
}

/// A length > 0 and at most [`MAX_LENGTH_M`].
pub(crate) fn length(f: &SourceFile, v: &Spanned<f64>, key: &str) -> Result<f64, ScenarioError> {
    sized(f, v, key, false, (MAX_LENGTH_M, "m"))
}

/// A length >= 0 and at most [`MAX_LENGTH_M`].
pub(crate) fn distance(f: &SourceFile, v: &Spanned<f64>, key: &str) -> Result<f64, ScenarioError> {
    sized(f, v, key, true, (MAX_LENGTH_M, "m"))
}

/// A thickness from [`MIN_THICKNESS_M`] (or 0 when `zero_ok`, for a
/// spread) to [`MAX_THICKNESS_M`].
pub(crate) fn thickness(
    f: &SourceFile,
    v: &Spanned<f64>,
    key: &str,
    zero_ok: bool,
) -> Result<f64, ScenarioError> {
    let h = sized(f, v, key, zero_ok, (MAX_THICKNESS_M, "m"))?;
    if zero_ok || h >= MIN_THICKNESS_M {
        return Ok(h);
    }
    Err(f.error(
        v.span(),
        key,
        format!(
            "{} m is thinner than the thinnest accepted ice, {MIN_THICKNESS_M} m",
            short(h)
        ),
    ))
}

/// A density (> 0 unless `zero_ok`) at most [`MAX_DENSITY_KG_PER_M3`].
pub(crate) fn density(
    f: &SourceFile,
    v: &Spanned<f64>,
    key: &str,
    zero_ok: bool,
) -> Result<f64, ScenarioError> {
    sized(f, v, key, zero_ok, (MAX_DENSITY_KG_PER_M3, "kg/m^3"))
}
/// A number in `[lo, hi]` (or `[lo, hi)` when `open_hi`).
pub(crate) fn within(
    f: &SourceFile,
    v: &Spanned<f64>,
    key: &str,
    lo: f64,
    hi: f64,
    open_hi: bool,
) -> Result<f64, ScenarioError> {
    let x = *v.get_ref();
    let ok = x.is_finite() && x >= lo && if open_hi { x < hi } else { x <= hi };
    if ok {
        Ok(x)
    } else {
        let close = if open_hi { ")" } else { "]" };
        Err(f.error(
            v.span(),
            key,
            format!(
                "must lie in [{}, {}{close}, got {}",
                sig(lo),
                sig(hi),
                short(x)
            ),
        ))
    }
}

/// A [`DemError`] about something at `span`.
pub(crate) fn dem_error(
    f: &SourceFile,
    span: Range<usize>,
    key: &str,
    e: DemError,
) -> ScenarioError {
    f.error(span, key, e.to_string())
}
