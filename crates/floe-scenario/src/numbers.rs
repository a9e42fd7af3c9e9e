//! Numbers as messages and reports print them.

/// Four significant digits, without trailing noise.
pub fn sig(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let e = x.abs().log10().floor() as i32;
    if (-3..6).contains(&e) {
        let decimals = (3 - e).max(0) as usize;
        let s = format!("{x:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        let s = format!("{x:.3e}");
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        format!("{mantissa}e{exponent}")
    }
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
