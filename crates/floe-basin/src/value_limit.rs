//! The largest magnitude a forcing value can have on Earth, so that a file
//! whose values are not the field's (a wrong variable, unit or scale
//! factor; a fill value the file does not declare) is refused when read,
//! instead of driving floes until they leave the grid.

/// The bound on the magnitude of a field's values (of each component of a
/// vector), with what it is for the message.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ValueLimit {
    /// Largest `|value|` accepted, in `units`.
    pub max_abs: f64,
    /// What the values are, e.g. "a wind velocity component".
    pub what: &'static str,
    /// Their units, e.g. "m/s".
    pub units: &'static str,
}

impl ValueLimit {
    /// Near-surface wind: the strongest measured gust is 113 m/s (Barrow
    /// Island, 1996).
    pub const WIND: ValueLimit = ValueLimit {
        max_abs: 150.0,
        what: "a wind velocity component",
        units: "m/s",
    };
    /// Surface ocean current: the fastest tidal races run at about 10 m/s.
    pub const CURRENT: ValueLimit = ValueLimit {
        max_abs: 20.0,
        what: "a current velocity component",
        units: "m/s",
    };
    /// Sea-surface height: heights above the reference ellipsoid span
    /// about -110 to +90 m (the geoid); tides and surges add metres.
    pub const SEA_SURFACE_HEIGHT: ValueLimit = ValueLimit {
        max_abs: 200.0,
        what: "a sea-surface height",
        units: "m",
    };

    /// Whether `value` is within the limit. Missing values (NaN) are not
    /// judged here: the engine refuses floes on them.
    pub fn admits(&self, value: f64) -> bool {
        value.is_nan() || value.abs() <= self.max_abs
    }

    /// `value` to six significant digits for a message (`1e30`, `-212.5`;
    /// a value read as f32 shows its f32 digits, not f64's).
    pub fn shown(value: f64) -> String {
        let e = format!("{value:.5e}");
        let (mantissa, exponent) = e.split_once('e').unwrap_or((&e, "0"));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        match exponent.parse::<i32>() {
            Ok(x) if (-4..6).contains(&x) => {
                let plain = format!("{value:.*}", (5 - x).max(0) as usize);
                if plain.contains('.') {
                    plain
                        .trim_end_matches('0')
                        .trim_end_matches('.')
                        .to_string()
                } else {
                    plain
                }
            }
            _ => format!("{mantissa}e{exponent}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::ValueLimit;

    #[test]
    fn values_show_six_significant_digits() {
        assert_eq!(ValueLimit::shown(1.0000000150474662e30), "1e30");
        assert_eq!(ValueLimit::shown(-212.5), "-212.5");
        assert_eq!(ValueLimit::shown(151.0), "151");
        assert_eq!(ValueLimit::shown(123456.7), "123457");
        assert_eq!(ValueLimit::shown(1234567.0), "1.23457e6");
        assert_eq!(ValueLimit::shown(0.000123), "0.000123");
        assert_eq!(ValueLimit::shown(f64::INFINITY), "inf");
    }
}
