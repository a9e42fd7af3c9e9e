//! Periodic axes of the domain: wrapping positions into the period and the
//! image of one floe nearest another.

use crate::Vec2;

/// One periodic axis: positions wrap into `[min_m, min_m + length_m)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Period {
    /// Lower edge of the period, m.
    pub min_m: f64,
    /// Length of the period, m.
    pub length_m: f64,
}

impl Period {
    /// `x` wrapped into the period.
    #[inline]
    pub fn wrap(&self, x: f64) -> f64 {
        let d = x - self.min_m;
        // `rem_euclid` returns an offset already in `[0, length)` unchanged,
        // bit for bit; testing first skips its library `fmod` for every floe
        // but the few crossing the boundary (about 1 % of a DEM step).
        let r = if d >= 0.0 && d < self.length_m {
            d
        } else {
            d.rem_euclid(self.length_m)
        };
        self.min_m + r
    }
}

/// `x.round()`, bit for bit, with the common case of `|x| < 0.5` (two
/// floes less than half a period apart) answered without the call: on the
/// baseline x86-64 target `round` is a library function, about 1 % of a DEM
/// step when called for every candidate pair.
#[inline(always)]
fn round_near_zero(x: f64) -> f64 {
    if x.abs() < 0.5 {
        // round keeps the sign: round(-0.3) is -0.0.
        0.0f64.copysign(x)
    } else {
        x.round()
    }
}

/// Periodicity of the domain in x and/or y.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Periodicity {
    /// Period along x, if periodic in x.
    pub x: Option<Period>,
    /// Period along y, if periodic in y.
    pub y: Option<Period>,
}

impl Periodicity {
    /// The image offset of `b` closest to `a` (to add to `b`'s position).
    #[inline]
    pub fn nearest_image(&self, a: Vec2, b: Vec2) -> Vec2 {
        let d = b - a;
        let shift = |delta: f64, period: Option<Period>| {
            period.map_or(0.0, |p| -p.length_m * round_near_zero(delta / p.length_m))
        };
        Vec2::new(shift(d.x, self.x), shift(d.y, self.y))
    }

    /// `p` wrapped into the periodic axes' ranges.
    #[inline]
    pub fn wrap(&self, p: Vec2) -> Vec2 {
        Vec2::new(
            self.x.map_or(p.x, |q| q.wrap(p.x)),
            self.y.map_or(p.y, |q| q.wrap(p.y)),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_near_zero_is_round_bit_for_bit() {
        let below_half = 0.5f64.next_down();
        for x in [
            0.0,
            -0.0,
            1e-300,
            -1e-300,
            0.3,
            -0.3,
            below_half,
            -below_half,
            0.5,
            -0.5,
            0.5f64.next_up(),
            1.5,
            -2.5,
            1e17,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ] {
            assert_eq!(round_near_zero(x).to_bits(), x.round().to_bits(), "x {x}");
        }
    }

    proptest::proptest! {
        /// The wrap's shortcut for positions already inside the period
        /// gives `rem_euclid`'s result bit for bit, at the period's edges
        /// and beyond them too.
        #[test]
        fn wrapping_is_rem_euclid_bit_for_bit(
            min_m in -1e6..1e6f64,
            length_m in 1.0..2e6f64,
            t in -3.0..3.0f64,
            ulps in -2i64..=2,
        ) {
            let p = Period { min_m, length_m };
            let exact = |x: f64| min_m + (x - min_m).rem_euclid(length_m);
            let edge = |x: f64| f64::from_bits((x.to_bits() as i64 + ulps) as u64);
            for x in [min_m + t * length_m, edge(min_m), edge(min_m + length_m), edge(min_m + 0.5 * length_m)] {
                proptest::prop_assert_eq!(p.wrap(x).to_bits(), exact(x).to_bits(), "x {}", x);
            }
        }
    }
}
