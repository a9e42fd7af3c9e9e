//! Simulated time as people read it.

/// Simulated time in the largest sensible unit: `2.50 d`, `3.00 h`,
/// `12.5 min`, `3.000 s`.
pub fn format_sim_time(t_s: f64) -> String {
    match t_s.abs() {
        x if x >= 86_400.0 => format!("{:.2} d", t_s / 86_400.0),
        x if x >= 3_600.0 => format!("{:.2} h", t_s / 3_600.0),
        x if x >= 60.0 => format!("{:.1} min", t_s / 60.0),
        _ => format!("{t_s:.3} s"),
    }
}
