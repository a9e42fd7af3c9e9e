//! Colour scales for floe maps: viridis (perceptually uniform, readable in
//! grey and by colour-blind readers) for magnitudes, a blue-white-red
//! diverging scale for signed quantities centred on zero.

use plotters::style::RGBColor;

/// Viridis at nine evenly spaced points (matplotlib's table, every 32nd entry).
const VIRIDIS: [(u8, u8, u8); 9] = [
    (68, 1, 84),
    (71, 44, 122),
    (59, 81, 139),
    (44, 113, 142),
    (33, 144, 141),
    (39, 173, 129),
    (92, 200, 99),
    (170, 220, 50),
    (253, 231, 37),
];

/// Blue, white, red.
const DIVERGING: [(u8, u8, u8); 3] = [(33, 102, 172), (247, 247, 247), (178, 24, 43)];

/// Piecewise-linear interpolation in a colour table, `t` clamped to [0, 1].
fn interpolate(table: &[(u8, u8, u8)], t: f64) -> RGBColor {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (table.len() - 1) as f64;
    let i = (x.floor() as usize).min(table.len() - 2);
    let f = x - i as f64;
    let mix = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
    let (a, b) = (table[i], table[i + 1]);
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// A map from values to colours.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColourScale {
    /// Value at the bottom of the scale.
    pub lo: f64,
    /// Value at the top.
    pub hi: f64,
    /// Diverging (centred on zero) rather than sequential.
    pub diverging: bool,
}

impl ColourScale {
    /// A scale covering the 1st to 99th percentile of the finite values
    /// (one runaway floe should not wash out the map); symmetric about zero
    /// when `diverging`. Values that are never negative get a scale that
    /// does not reach below zero, also when they are all the same.
    pub fn fit(values: impl Iterator<Item = f64>, diverging: bool) -> Self {
        let mut v: Vec<f64> = values.filter(|x| x.is_finite()).collect();
        if v.is_empty() {
            return Self {
                lo: 0.0,
                hi: 1.0,
                diverging,
            };
        }
        v.sort_by(f64::total_cmp);
        let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
        let (mut lo, mut hi) = (at(0.01), at(0.99));
        if diverging {
            let m = lo.abs().max(hi.abs());
            (lo, hi) = (-m, m);
        }
        if hi <= lo {
            // One value throughout: a range about it, on its side of zero.
            let pad = if lo == 0.0 { 1.0 } else { lo.abs() };
            (lo, hi) = match (lo >= 0.0 && !diverging, hi < 0.0) {
                (true, _) => (lo - pad.min(lo), hi + pad),
                (_, true) => (lo - pad, hi + pad.min(-hi)),
                _ => (lo - pad, hi + pad),
            };
        }
        Self { lo, hi, diverging }
    }

    /// The colour of `value`.
    pub fn colour(&self, value: f64) -> RGBColor {
        let t = (value - self.lo) / (self.hi - self.lo);
        if self.diverging {
            interpolate(&DIVERGING, t)
        } else {
            interpolate(&VIRIDIS, t)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ends_of_the_scale_are_the_ends_of_the_table() {
        let s = ColourScale {
            lo: 2.0,
            hi: 4.0,
            diverging: false,
        };
        assert_eq!(s.colour(2.0), RGBColor(68, 1, 84));
        assert_eq!(s.colour(4.0), RGBColor(253, 231, 37));
        assert_eq!(s.colour(100.0), RGBColor(253, 231, 37));
        let d = ColourScale::fit([-1.0, 3.0].into_iter(), true);
        assert_eq!((d.lo, d.hi), (-3.0, 3.0));
        assert_eq!(d.colour(0.0), RGBColor(247, 247, 247));
    }

    #[test]
    fn a_field_that_is_never_negative_gets_a_scale_from_zero_up() {
        let range = |v: &[f64], diverging| {
            let s = ColourScale::fit(v.iter().copied(), diverging);
            (s.lo, s.hi)
        };
        // Zero shear everywhere (a pack at rest), one thickness everywhere.
        assert_eq!(range(&[0.0; 50], false), (0.0, 1.0));
        assert_eq!(range(&[1.5; 50], false), (0.0, 3.0));
        assert_eq!(range(&[-2.0; 50], false), (-4.0, 0.0));
        assert_eq!(range(&[0.0; 50], true), (-1.0, 1.0));
        // Otherwise the data's percentiles, which are not below zero either.
        let shear: Vec<f64> = (0..1000).map(|k| 1e-7 * k as f64).collect();
        let (lo, hi) = range(&shear, false);
        assert_eq!((lo, hi), (shear[10], shear[989]));
    }
}
