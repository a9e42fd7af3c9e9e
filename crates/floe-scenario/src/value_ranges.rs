//! The ranges accepted for values given outside a scenario file: the
//! command line's flags and the Python package's arguments check against
//! the same bounds and state them in the same words.

use crate::numbers::short;

/// `x` if it lies in `(min, max]` (`[min, max]` when `closed`), else the
/// range it must lie in, as `"{what} > min and <= max"`.
pub fn in_range(x: f64, min: f64, closed: bool, max: f64, what: &str) -> Result<f64, String> {
    if (x > min || (closed && x == min)) && x <= max {
        Ok(x)
    } else {
        Err(format!(
            "{what} {} {} and <= {}",
            if closed { ">=" } else { ">" },
            short(min),
            short(max)
        ))
    }
}

/// A load-point speed (the reference slip rate of a comparison), m/s.
pub fn load_point_speed(x: f64) -> Result<f64, String> {
    let max = floe_friction::experiments::MAX_LOAD_POINT_SPEED_M_PER_S;
    in_range(x, 0.0, false, max, "a speed in m/s")
}

/// A friction coefficient: 0 to 10 (sea ice's are below 1).
pub fn friction_coefficient(x: f64) -> Result<f64, String> {
    in_range(x, 0.0, true, 10.0, "a friction coefficient")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bounds_are_inclusive_only_where_said() {
        assert_eq!(friction_coefficient(0.0), Ok(0.0));
        assert_eq!(friction_coefficient(10.0), Ok(10.0));
        assert!(friction_coefficient(10.000001).is_err());
        assert!(friction_coefficient(f64::NAN).is_err());
        assert!(load_point_speed(0.0).is_err());
        assert_eq!(load_point_speed(100.0), Ok(100.0));
        assert_eq!(
            load_point_speed(-1.0).unwrap_err(),
            "a speed in m/s > 0 and <= 100"
        );
    }
}
