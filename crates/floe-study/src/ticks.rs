//! Ticks and their labels for the axes of plots and the colour bars of
//! maps: steps of 1, 2, 2.5 or 5 times a power of ten inside the range,
//! every label with the decimals the step needs (so neighbours always
//! differ, and none reads `-0`), and a common power of ten for the title
//! when the numbers are very small or very large (`shear (1e-5 s-1)`).
//! Labels are made from integers, not by rounding floats, so they are
//! exact.

/// The ticks of one axis or colour bar.
#[derive(Debug, Clone, PartialEq)]
pub struct Ticks {
    /// Tick values, increasing, all within the range asked for.
    pub values: Vec<f64>,
    /// Each tick's label, in units of `10^exponent`.
    pub labels: Vec<String>,
    /// The labels' common power of ten (0: the labels are the values).
    pub exponent: i32,
    /// The step as `(m, q)`: `m x 10^q`, `m` one of 1, 2, 25, 5.
    step: (i64, i32),
}

/// Steps `m x 10^dq` per decade, increasing (2.5 is 25 x 10^-1).
const MANTISSAS: [(i64, i32); 4] = [(1, 0), (2, 0), (25, -1), (5, 0)];

/// A power of ten in the labels' title from values of 10^5 up, and below
/// 10^-2 (`0.001` still reads well; `0.00003` does not).
const PLAIN_EXPONENTS: std::ops::Range<i32> = -2..5;

/// Most ticks over any range (labels of ranges wider than about 1e15
/// steps fall back to the two ends).
const MAX_STEPS: f64 = 1e15;

impl Ticks {
    /// About `target` (at least 2) ticks over `[lo, hi]`: the smallest
    /// step of 1, 2, 2.5 or 5 x 10^q that makes at most `target`
    /// intervals, which leaves at least two ticks inside the range.
    pub fn over(lo: f64, hi: f64, target: usize) -> Self {
        let target = target.max(2) as f64;
        let span = hi - lo;
        let big = lo.abs().max(hi.abs());
        if !(span > 0.0 && span.is_finite() && big / span < MAX_STEPS / target) {
            return Self::ends(lo, hi);
        }
        // Candidate steps by index i: MANTISSAS[i mod 4] x 10^(i div 4).
        let step_of = |i: i64| {
            let (m, dq) = MANTISSAS[i.rem_euclid(4) as usize];
            (m, i.div_euclid(4) as i32 + dq)
        };
        let multiples_of = |(m, q): (i64, i32)| {
            let size = value(m, q);
            let first = (lo / size - 1e-9).ceil() as i64;
            let last = (hi / size + 1e-9).floor() as i64;
            (first, last)
        };
        let raw = span / target;
        let mut i = 4 * (raw.log10().floor() as i64 - 1);
        while value(step_of(i).0, step_of(i).1) < raw * (1.0 - 1e-12) {
            i += 1;
        }
        // At least two ticks inside: a smaller step if need be.
        while multiples_of(step_of(i)).1 <= multiples_of(step_of(i)).0 {
            i -= 1;
        }
        let step = step_of(i);
        let (m, q) = step;
        let (first, last) = multiples_of(step);
        let exponent = common_exponent(big);
        let multiples: Vec<i64> = (first..=last).map(|k| k * m).collect();
        Self {
            values: multiples
                .iter()
                .map(|&n| value(n, q).clamp(lo, hi))
                .collect(),
            labels: multiples
                .iter()
                .map(|&n| decimal(n, q - exponent))
                .collect(),
            exponent,
            step,
        }
    }

    /// A range too narrow or wide for steps: its two ends, labelled in full.
    fn ends(lo: f64, hi: f64) -> Self {
        let values: Vec<f64> = if lo == hi || !(lo.is_finite() && hi.is_finite()) {
            vec![lo]
        } else {
            vec![lo, hi]
        };
        Self {
            labels: values.iter().map(|v| format!("{v}")).collect(),
            values,
            exponent: 0,
            step: (0, 0),
        }
    }

    /// The label of the tick nearest `v` (for a plot's label formatter).
    pub fn label_of(&self, v: f64) -> String {
        let nearest = self
            .values
            .iter()
            .enumerate()
            .min_by(|a, b| (a.1 - v).abs().total_cmp(&(b.1 - v).abs()))
            .map(|(i, _)| i);
        nearest.map_or_else(String::new, |i| self.labels[i].clone())
    }

    /// `title` with the labels' power of ten in its unit:
    /// `shear (s-1)` becomes `shear (1e-5 s-1)`, `concentration (1)`
    /// becomes `concentration (1e-5)`, a title without a unit gets
    /// ` (1e-5)`.
    pub fn title(&self, title: &str) -> String {
        if self.exponent == 0 {
            return title.to_string();
        }
        let power = format!("1e{}", self.exponent);
        match title.rsplit_once(" (") {
            Some((name, "1)")) => format!("{name} ({power})"),
            Some((name, unit)) if unit.ends_with(')') => format!("{name} ({power} {unit}"),
            _ => format!("{title} ({power})"),
        }
    }

    /// Values between the ticks for a light mesh: fifths of the step
    /// (quarters of a step of 2), within `[lo, hi]`, the ticks left out.
    pub fn light_values(&self, lo: f64, hi: f64) -> Vec<f64> {
        // The step is m x 10^q; the sub-step sub x 10^p, and every
        // parts-th multiple of it is a tick.
        let (m, q) = self.step;
        let (sub, p, parts) = match m {
            0 => return Vec::new(),
            1 => (2, q - 1, 5),
            2 => (5, q - 1, 4),
            25 => (5, q, 5),
            _ => (1, q, 5),
        };
        let size = value(sub, p);
        let first = (lo / size - 1e-9).ceil() as i64;
        let last = (hi / size + 1e-9).floor() as i64;
        (first..=last)
            .filter(|k| k.rem_euclid(parts) != 0)
            .map(|k| value(k * sub, p))
            .collect()
    }
}

/// `n x 10^q`, rounded once.
fn value(n: i64, q: i32) -> f64 {
    if q >= 0 {
        n as f64 * 10f64.powi(q)
    } else {
        n as f64 / 10f64.powi(-q)
    }
}

/// The power of ten of `big` when it is outside [`PLAIN_EXPONENTS`], else 0.
fn common_exponent(big: f64) -> i32 {
    if big == 0.0 {
        return 0;
    }
    // From the digits, not log10, so that 1e-5 is exactly 10^-5.
    let e: i32 = format!("{big:e}")
        .split_once('e')
        .and_then(|(_, e)| e.parse().ok())
        .unwrap_or(0);
    if PLAIN_EXPONENTS.contains(&e) {
        0
    } else {
        e
    }
}

/// `n x 10^shift` written out exactly: `decimal(25, -1)` is `2.5`,
/// `decimal(-3, -2)` is `-0.03`, `decimal(0, -1)` is `0.0`.
fn decimal(n: i64, shift: i32) -> String {
    if shift >= 0 {
        return if n == 0 {
            "0".to_string()
        } else {
            format!("{n}{}", "0".repeat(shift as usize))
        };
    }
    let places = (-shift) as usize;
    let digits = format!("{:0>width$}", n.unsigned_abs(), width = places + 1);
    let (whole, fraction) = digits.split_at(digits.len() - places);
    let sign = if n < 0 { "-" } else { "" };
    format!("{sign}{whole}.{fraction}")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ranges of every magnitude and sign, some of them awkward.
    fn ranges() -> Vec<(f64, f64)> {
        let mut out = vec![
            (2.390250834193666e-7, 3.35551725156712e-5),
            (0.8520923443704952, 1.001588188852965),
            (-2168.5846023321637, -46.96698538788321),
            (-1.0396221085938545e-5, 2.1842818491312838e-5),
            (0.0, 1.0),
            (-1.0, 1.0),
            (1000.001, 1000.002),
            (-0.3, 0.3),
            (0.0, 0.49999),
        ];
        // A deterministic spread: every decade from 1e-12 to 1e12, spans
        // from a thousandth of the value to a thousand times it.
        let mut x = 0.123_f64;
        for decade in -12..=12 {
            for span_decade in [-3, -1, 0, 1, 3] {
                x = (x * 7.31 + 0.177).fract();
                let lo = (1.0 + 9.0 * x) * 10f64.powi(decade);
                let span = (0.5 + x) * lo * 10f64.powi(span_decade);
                out.push((lo, lo + span));
                out.push((-lo - span, -lo));
                out.push((-lo, span));
            }
        }
        out
    }

    #[test]
    fn labels_differ_and_ticks_lie_within_the_range() {
        for (lo, hi) in ranges() {
            for target in [2, 4, 6, 10] {
                let t = Ticks::over(lo, hi, target);
                let why = format!("[{lo:e}, {hi:e}] target {target}: {t:?}");
                assert!(t.values.len() >= 2, "{why}");
                assert!(t.values.len() <= (target + 1).max(6), "{why}");
                assert_eq!(t.labels.len(), t.values.len(), "{why}");
                for w in t.values.windows(2) {
                    assert!(w[0] < w[1], "{why}");
                }
                assert!(t.values.iter().all(|v| (lo..=hi).contains(v)), "{why}");
                for w in t.labels.windows(2) {
                    assert_ne!(w[0], w[1], "{why}");
                }
                // Each label is its value, to the step's precision.
                let step = t.values[1] - t.values[0];
                for (v, l) in t.values.iter().zip(&t.labels) {
                    let shown: f64 = l.parse::<f64>().unwrap() * 10f64.powi(t.exponent);
                    assert!((shown - v).abs() <= 1e-6 * step, "{why}: {l} for {v:e}");
                    assert!(!l.starts_with("-0") || l.parse::<f64>().unwrap() != 0.0);
                    // Written as people write numbers: no "000", no "00.5".
                    assert!(!l.trim_start_matches('-').starts_with("00"), "{why}");
                }
            }
        }
    }

    #[test]
    fn a_range_that_is_not_negative_gets_no_negative_label() {
        for (lo, hi) in ranges().into_iter().filter(|r| r.0 >= 0.0) {
            let t = Ticks::over(lo, hi, 6);
            assert!(t.values.iter().all(|&v| v >= 0.0), "{t:?}");
            assert!(t.labels.iter().all(|l| !l.starts_with('-')), "{t:?}");
        }
        // Zero itself reads 0, not -0.
        let t = Ticks::over(-1e-6, 1.0, 5);
        assert_eq!(t.labels, ["0.00", "0.25", "0.50", "0.75", "1.00"]);
    }

    #[test]
    fn small_and_large_numbers_share_a_power_of_ten_in_the_title() {
        // The demo's shear rates: 2.4e-7 to 3.4e-5 /s.
        let t = Ticks::over(2.390250834193666e-7, 3.35551725156712e-5, 10);
        assert_eq!(t.exponent, -5);
        assert_eq!(t.labels, ["0.5", "1.0", "1.5", "2.0", "2.5", "3.0"]);
        assert_eq!(t.title("shear (s-1)"), "shear (1e-5 s-1)");
        assert_eq!(t.title("concentration (1)"), "concentration (1e-5)");
        assert_eq!(t.title("fraction"), "fraction (1e-5)");
        let t = Ticks::over(0.0, 2.5e6, 5);
        assert_eq!(t.exponent, 6);
        assert_eq!(t.labels, ["0.0", "0.5", "1.0", "1.5", "2.0", "2.5"]);
        // Numbers that read well plainly keep no power of ten.
        let t = Ticks::over(0.8520923443704952, 1.001588188852965, 6);
        assert_eq!(t.exponent, 0);
        assert_eq!(
            t.labels,
            ["0.875", "0.900", "0.925", "0.950", "0.975", "1.000"]
        );
        assert_eq!(t.title("concentration (1)"), "concentration (1)");
        let t = Ticks::over(-2168.58, -46.97, 5);
        assert_eq!(t.labels, ["-2000", "-1500", "-1000", "-500"]);
        let t = Ticks::over(-2168.58, 2168.58, 10);
        assert_eq!(
            t.labels,
            ["-2000", "-1500", "-1000", "-500", "0", "500", "1000", "1500", "2000"]
        );
    }

    #[test]
    fn light_values_fall_between_the_ticks() {
        let t = Ticks::over(0.0, 1.0, 5);
        assert_eq!(t.labels, ["0.0", "0.2", "0.4", "0.6", "0.8", "1.0"]);
        let light = t.light_values(0.0, 1.0);
        assert_eq!(light.len(), 5 * 3);
        assert!(light
            .iter()
            .all(|v| !t.values.iter().any(|t| (t - v).abs() < 1e-12)));
        let t = Ticks::over(0.0, 10.0, 4);
        assert_eq!(t.labels, ["0.0", "2.5", "5.0", "7.5", "10.0"]);
        assert_eq!(t.light_values(0.0, 10.0).len(), 4 * 4);
    }

    #[test]
    fn decimals_are_written_exactly() {
        assert_eq!(decimal(25, -1), "2.5");
        assert_eq!(decimal(-3, -2), "-0.03");
        assert_eq!(decimal(0, -1), "0.0");
        assert_eq!(decimal(12, 2), "1200");
        assert_eq!(decimal(0, 2), "0");
        assert_eq!(decimal(-7, 0), "-7");
    }
}
