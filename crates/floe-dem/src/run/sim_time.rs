//! Simulated time as people read it.

/// Simulated time in the largest sensible unit: `2.50 d`, `3.00 h`,
/// `12.5 min`, `3.000 s`.
pub fn format_sim_time(t_s: f64) -> String {
    match t_s.abs() {
        // Beyond a thousand years, days in scientific form.
        x if x >= 3.65e5 * 86_400.0 || !x.is_finite() => format!("{:.3e} d", t_s / 86_400.0),
        x if x >= 86_400.0 => format!("{:.2} d", t_s / 86_400.0),
        x if x >= 3_600.0 => format!("{:.2} h", t_s / 3_600.0),
        x if x >= 60.0 => format!("{:.1} min", t_s / 60.0),
        _ => format!("{t_s:.3} s"),
    }
}

#[cfg(test)]
mod tests {
    use super::format_sim_time;

    #[test]
    fn each_range_has_its_unit_and_huge_times_stay_short() {
        assert_eq!(format_sim_time(1.5), "1.500 s");
        assert_eq!(format_sim_time(90.0), "1.5 min");
        assert_eq!(format_sim_time(7200.0), "2.00 h");
        assert_eq!(format_sim_time(3.0 * 86_400.0), "3.00 d");
        assert_eq!(format_sim_time(8.64e304), "1.000e300 d");
        assert!(format_sim_time(f64::INFINITY).len() < 12);
    }
}
