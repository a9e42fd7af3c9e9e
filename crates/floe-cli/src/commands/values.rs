//! What each flag's value may be: clap value parsers whose messages state
//! the accepted range.

use floe_scenario::value_ranges;

/// A finite number > 0.
pub fn positive(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if x > 0.0 && x.is_finite() => Ok(x),
        _ => Err(format!("expected a finite number > 0, got `{text}`")),
    }
}

/// `text` as a number that `check` accepts (a range of
/// `floe_scenario::value_ranges`), or the range it must lie in.
fn checked(text: &str, check: impl Fn(f64) -> Result<f64, String>) -> Result<f64, String> {
    let number = text.parse::<f64>().unwrap_or(f64::NAN);
    check(number).map_err(|range| format!("expected {range}, got `{text}`"))
}

/// A number in `(min, max]` (`[min, max]` when `closed`), for a flag
/// whose accepted range the message states.
fn bounded(text: &str, min: f64, closed: bool, max: f64, what: &str) -> Result<f64, String> {
    checked(text, |x| value_ranges::in_range(x, min, closed, max, what))
}

/// A movie's frame rate.
pub fn frame_rate(text: &str) -> Result<f64, String> {
    let (min, max) = floe_study::render::movie::FPS_RANGE;
    bounded(text, min, true, max, "frames per second")
}

/// A spring-slider time step, s.
pub fn slider_dt(text: &str) -> Result<f64, String> {
    let max = floe_friction::experiments::MAX_SLIDER_DT_S;
    bounded(text, 0.0, false, max, "a time step in s")
}

/// A spring-slider normal load, N.
pub fn normal_load(text: &str) -> Result<f64, String> {
    let (min, max) = floe_friction::experiments::SLIDER_NORMAL_LOAD_RANGE_N;
    bounded(text, min, true, max, "a load in N")
}

/// A load-point speed, m/s.
pub fn load_point_speed(text: &str) -> Result<f64, String> {
    checked(text, value_ranges::load_point_speed)
}

/// A friction coefficient: 0 to 10 (sea ice's are below 1).
pub fn friction_coefficient(text: &str) -> Result<f64, String> {
    checked(text, value_ranges::friction_coefficient)
}

/// A finite factor > 1.
pub fn above_one(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if x > 1.0 && x.is_finite() => Ok(x),
        _ => Err(format!("expected a finite factor > 1, got `{text}`")),
    }
}

/// Bins of the velocity profile: 1 to 10,000.
pub fn profile_bins(text: &str) -> Result<usize, String> {
    match text.parse::<usize>() {
        Ok(n) if (1..=10_000).contains(&n) => Ok(n),
        _ => Err(format!(
            "expected a whole number from 1 to 10000, got `{text}`"
        )),
    }
}

/// A whole number of steps >= 1.
pub fn whole_steps(text: &str) -> Result<u64, String> {
    match text.parse::<u64>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!(
            "expected a whole number of steps >= 1, got `{text}`"
        )),
    }
}

/// A step limit: a number >= 1 (1e9 and 1000000000 alike).
pub fn step_count(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(n) if n >= 1.0 && n.is_finite() => Ok(n),
        _ => Err(format!(
            "expected a number of steps >= 1, e.g. 1e10, got `{text}`"
        )),
    }
}

/// A fraction > 0 (the halo's skin, the rebalance threshold).
pub fn positive_fraction(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if x > 0.0 && x.is_finite() => Ok(x),
        _ => Err(format!("expected a fraction > 0, e.g. 0.2, got `{text}`")),
    }
}
