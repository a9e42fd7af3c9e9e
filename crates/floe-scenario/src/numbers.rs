//! Numbers as messages and reports print them.

/// `x` to `digits` significant digits (at least 1), trailing zeros
/// trimmed: plain from 0.001 up to a million (`0.072`, `2.5`, `20000`),
/// else scientific in Rust's style (`1e-5`, `6e6`, `2.074e6`).
pub fn significant(x: f64, digits: usize) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = digits.max(1);
    // The exponent after rounding: 999.97 to 4 digits is 1000, not 999.9.
    let scientific = format!("{x:.*e}", digits - 1);
    let (mantissa, exponent) = scientific
        .split_once('e')
        .expect("Rust's scientific format has an exponent");
    let e: i32 = exponent.parse().expect("an integer exponent");
    if (-3..6).contains(&e) {
        let decimals = (digits as i32 - 1 - e).max(0) as usize;
        trim_zeros(format!("{x:.decimals$}"))
    } else {
        format!("{}e{e}", trim_zeros(mantissa.to_string()))
    }
}

/// `s` without the trailing zeros of its fraction (and without a bare
/// decimal point).
fn trim_zeros(s: String) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Four significant digits, without trailing noise: measured and derived
/// quantities in messages and reports (`0.6626 s`, `2.074e6 m^2`).
pub fn sig(x: f64) -> String {
    significant(x, 4)
}

/// A parameter as reports show it: six significant digits, so that a
/// value the user wrote reads as written and a derived one without
/// floating-point noise (`0.31 - 0.382` shows as `-0.072`, not
/// `-0.07200000000000001`). Files floe reads back keep every digit.
pub fn parameter(x: f64) -> String {
    significant(x, 6)
}

/// A count with thousands separators.
pub fn thousands(n: usize) -> String {
    let s = n.to_string();
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// A number from a file as a message quotes it: as written when short,
/// else in scientific form when that is shorter (`1e13`, not its 14 digits).
pub fn short(x: f64) -> String {
    let plain = format!("{x}");
    let scientific = format!("{x:e}");
    if plain.len() <= 8 || plain.len() <= scientific.len() {
        plain
    } else {
        scientific
    }
}

/// Numbers from a file as a message quotes an array of them: `[1, 2e300]`.
pub fn short_list(xs: &[f64]) -> String {
    let items: Vec<String> = xs.iter().map(|&x| short(x)).collect();
    format!("[{}]", items.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parameters_lose_floating_point_noise_but_keep_what_was_written() {
        assert_eq!(parameter(0.31 - 0.382), "-0.072");
        assert_eq!(parameter(0.399186490410683), "0.399186");
        assert_eq!(parameter(0.872), "0.872");
        assert_eq!(parameter(1e-5), "1e-5");
        assert_eq!(parameter(6e6), "6e6");
        assert_eq!(parameter(20000.0), "20000");
        assert_eq!(parameter(0.0), "0");
        assert_eq!(parameter(-2.0), "-2");
    }

    #[test]
    fn rounding_up_to_the_next_power_of_ten_changes_the_form_with_it() {
        // 999999.7 to six digits is a million: scientific, not "1000000".
        assert_eq!(parameter(999_999.7), "1e6");
        assert_eq!(sig(9999.7), "10000");
        // 0.00099996 to four digits is 0.001: plain, not "1e-3".
        assert_eq!(sig(0.000_999_96), "0.001");
        assert_eq!(sig(0.6626148), "0.6626");
        assert_eq!(sig(2.0738e6), "2.074e6");
        assert_eq!(significant(1.26e-7, 2), "1.3e-7");
        assert_eq!(significant(f64::NAN, 3), "NaN");
    }
}
