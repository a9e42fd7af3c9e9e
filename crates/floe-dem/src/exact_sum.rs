//! Exact, order-independent summation of `f64` terms.
//!
//! A floating-point sum depends on the order of its additions, so a total
//! computed by two threads, or by several MPI ranks that each sum their own
//! floes, changes in its last bits with the number of workers and with how
//! the terms were split among them. [`ExactSum`] removes that dependence: it
//! accumulates every term *exactly*, as an integer multiple of 2^-1074 (the
//! smallest subnormal), and rounds only once, in [`ExactSum::value`], to the
//! nearest double (ties to even). Partial accumulators combine exactly with
//! [`ExactSum::merge`] or, across ranks, by an integer `MPI_SUM` of
//! [`ExactSum::to_words`], so any split of the same terms gives bitwise the
//! same correctly rounded result: the reproducibility that ReproBLAS gives
//! BLAS (there with binned rather than exact sums). The accumulator is
//! R. M. Neal's "small superaccumulator" ("Fast exact summation using small
//! and large superaccumulators", 2015, arXiv:1505.05571): [`EXACT_SUM_LIMBS`]
//! `i64` limbs, limb `k` holding 32 bits of payload at bit `32 k`; the 31
//! spare bits of each limb let 2^30 additions go without carry propagation,
//! and one is done every 2^30 adds or merges, so the number of terms is
//! unlimited.
//!
//! (measured: 2.2 ns per add vs 0.47 ns naive `+=`, 1e6 random terms of
//! random sign with exponents over 2^-60..2^60, `cargo bench -p floe-dem
//! --bench exact_sum` on the 2-core AMD EPYC development machine; the cost is
//! the three read-modify-writes of limbs that consecutive terms share, plus
//! 0.1 ns for the carry-propagation counter)
//!
//! Zeros: the sum of terms that are all zeros, or whose exact sum is zero, is
//! `+0.0`, also for `-0.0` terms (IEEE addition would give `-0.0` for a sum of
//! `-0.0` only). Non-finite terms are counted apart: any NaN, or both an
//! infinity of each sign, makes the value NaN; otherwise an infinity makes it
//! that infinity. A finite exact sum beyond the range of `f64` rounds to an
//! infinity, as IEEE round-to-nearest does.

/// Number of `i64` limbs: 66 cover the bit positions of every finite
/// double's mantissa in units of 2^-1074 (0..2098), the 67th takes carries.
pub const EXACT_SUM_LIMBS: usize = 67;

/// Number of `i64` words of [`ExactSum::to_words`]: the limbs, then the
/// counts of `+inf`, `-inf` and NaN terms.
pub const EXACT_SUM_WORDS: usize = EXACT_SUM_LIMBS + 3;

/// Payload bits of each limb.
const LIMB_BITS: u32 = 32;
/// Mask of a limb's payload.
const LIMB_MASK: u64 = (1 << LIMB_BITS) - 1;
/// Mask of a double's stored fraction.
const FRAC_MASK: u64 = (1 << 52) - 1;
/// Biased exponent of infinities and NaNs.
const EXP_NON_FINITE: u64 = 0x7ff;
/// Carries are propagated once the operations since the last propagation
/// reach this count; below it no limb's magnitude reaches 2^62.
const NORMALIZE_EVERY: u32 = 1 << 30;

/// An exact accumulator of `f64` terms (a "small superaccumulator").
///
/// Adding is exact and cheap (three integer additions);
/// [`value`](ExactSum::value) rounds the exact sum once. Accumulators of
/// disjoint parts of the terms [`merge`](ExactSum::merge) exactly, so the
/// result depends neither on the order of the terms nor on how they were
/// split.
/// Equality compares the exact sums (and the counts of non-finite terms),
/// not the limbs' representation, which depends on when carries were
/// propagated.
#[derive(Clone, Debug)]
pub struct ExactSum {
    /// Limb `k` holds a signed multiple of 2^(32 k - 1074); the sum is
    /// `sum_k limbs[k] * 2^(32 k)` units of 2^-1074.
    limbs: [i64; EXACT_SUM_LIMBS],
    /// Number of `+inf` terms.
    pos_inf: u64,
    /// Number of `-inf` terms.
    neg_inf: u64,
    /// Number of NaN terms.
    nan: u64,
    /// Bound on the limbs since the last carry propagation: every limb
    /// below the top one has magnitude at most `(pending + 1) * 2^32`.
    pending: u32,
}

impl ExactSum {
    /// The empty sum (value `+0.0`).
    pub const fn new() -> Self {
        Self {
            limbs: [0; EXACT_SUM_LIMBS],
            pos_inf: 0,
            neg_inf: 0,
            nan: 0,
            pending: 0,
        }
    }

    /// Adds `x` exactly: its 53-bit mantissa, placed at its exponent, is
    /// spread over three consecutive limbs, each getting less than 2^32 in
    /// magnitude. No allocation and no loop; a carry propagation every 2^30
    /// operations keeps the limbs from overflowing for any number of terms.
    #[inline]
    pub fn add(&mut self, x: f64) {
        let bits = x.to_bits();
        let biased = (bits >> 52) & EXP_NON_FINITE;
        if biased == EXP_NON_FINITE {
            self.add_non_finite(x);
            return;
        }
        let normal = u64::from(biased != 0);
        // x = mantissa * 2^(shift - 1074); subnormals have shift 0.
        let mantissa = (bits & FRAC_MASK) | (normal << 52);
        let shift = biased - normal;
        let k = (shift / u64::from(LIMB_BITS)) as usize;
        let r = (shift % u64::from(LIMB_BITS)) as u32;
        // mantissa << r, up to 85 bits, cut into 32 + 32 + 21 bits.
        let low = (mantissa << r) & LIMB_MASK;
        let high = mantissa >> (LIMB_BITS - r);
        let mid = high & LIMB_MASK;
        let top = high >> LIMB_BITS;
        // Two's-complement negation when the sign bit is set: 0 or -1.
        let neg = (bits as i64) >> 63;
        let limbs = &mut self.limbs[k..k + 3];
        limbs[0] += (low as i64 ^ neg) - neg;
        limbs[1] += (mid as i64 ^ neg) - neg;
        limbs[2] += (top as i64 ^ neg) - neg;
        self.pending += 1;
        if self.pending >= NORMALIZE_EVERY {
            self.normalize();
        }
    }

    /// Counts a NaN or an infinity (kept out of the hot path).
    #[cold]
    #[inline(never)]
    fn add_non_finite(&mut self, x: f64) {
        if x.is_nan() {
            self.nan += 1;
        } else if x > 0.0 {
            self.pos_inf += 1;
        } else {
            self.neg_inf += 1;
        }
    }

    /// Adds the terms of `other` to `self`, exactly: a limb-wise integer
    /// addition, so `merge` of partial sums equals the sum of all the terms.
    pub fn merge(&mut self, other: &ExactSum) {
        for (a, b) in self.limbs.iter_mut().zip(&other.limbs) {
            *a += *b;
        }
        self.pos_inf += other.pos_inf;
        self.neg_inf += other.neg_inf;
        self.nan += other.nan;
        // Both limb bounds add: (pa + 1) + (pb + 1) = (pa + pb + 1) + 1.
        self.pending += other.pending + 1;
        if self.pending >= NORMALIZE_EVERY {
            self.normalize();
        }
    }

    /// Propagates carries: every limb but the top one into `0..2^32`, the
    /// top one keeps the (signed) rest. The sum is unchanged.
    fn normalize(&mut self) {
        for k in 0..EXACT_SUM_LIMBS - 1 {
            let carry = self.limbs[k] >> LIMB_BITS;
            self.limbs[k] -= carry << LIMB_BITS;
            self.limbs[k + 1] += carry;
        }
        self.pending = 0;
    }

    /// The exact sum of the terms, correctly rounded to the nearest `f64`
    /// (ties to even); see the module docs for zeros and non-finite terms.
    pub fn value(&self) -> f64 {
        if self.nan > 0 || (self.pos_inf > 0 && self.neg_inf > 0) {
            return f64::NAN;
        }
        if self.pos_inf > 0 {
            return f64::INFINITY;
        }
        if self.neg_inf > 0 {
            return f64::NEG_INFINITY;
        }
        let mut m = self.clone();
        m.normalize();
        // Lower limbs are non-negative now, so the top limb has the sign.
        let negative = m.limbs[EXACT_SUM_LIMBS - 1] < 0;
        if negative {
            for l in &mut m.limbs {
                *l = -*l;
            }
            m.normalize();
        }
        let magnitude = rounded_magnitude(&m.limbs);
        if negative {
            -magnitude
        } else {
            magnitude
        }
    }

    /// The accumulator as plain `i64` words: the carry-propagated limbs (each
    /// but the top one in `0..2^32`), then the counts of `+inf`, `-inf` and
    /// NaN terms. The element-wise integer sum of the words of up to 2^31
    /// accumulators (an `MPI_Allreduce` with `MPI_SUM` on `MPI_INT64_T`) is
    /// the words of their merge, to be read back with
    /// [`from_words`](ExactSum::from_words).
    pub fn to_words(&self) -> [i64; EXACT_SUM_WORDS] {
        let mut m = self.clone();
        m.normalize();
        let mut words = [0; EXACT_SUM_WORDS];
        words[..EXACT_SUM_LIMBS].copy_from_slice(&m.limbs);
        words[EXACT_SUM_LIMBS] = m.pos_inf as i64;
        words[EXACT_SUM_LIMBS + 1] = m.neg_inf as i64;
        words[EXACT_SUM_LIMBS + 2] = m.nan as i64;
        words
    }

    /// The accumulator whose [`to_words`](ExactSum::to_words) are `words`,
    /// or the element-wise sum of several accumulators' words (at most 2^31
    /// of them, so that no word overflowed).
    pub fn from_words(words: &[i64; EXACT_SUM_WORDS]) -> Self {
        let mut s = Self::new();
        s.limbs.copy_from_slice(&words[..EXACT_SUM_LIMBS]);
        s.pos_inf = words[EXACT_SUM_LIMBS] as u64;
        s.neg_inf = words[EXACT_SUM_LIMBS + 1] as u64;
        s.nan = words[EXACT_SUM_LIMBS + 2] as u64;
        s.normalize();
        s
    }
}

/// The non-negative integer `sum_k limbs[k] * 2^(32 k)` (limbs normalized:
/// all but the top one in `0..2^32`, the top one non-negative) times
/// 2^-1074, rounded to the nearest `f64`, ties to even.
fn rounded_magnitude(limbs: &[i64; EXACT_SUM_LIMBS]) -> f64 {
    let Some(h) = limbs.iter().rposition(|&l| l != 0) else {
        return 0.0;
    };
    if h == EXACT_SUM_LIMBS - 1 {
        // At least 2^(32 * 66 - 1074) = 2^1038: beyond f64::MAX.
        return f64::INFINITY;
    }
    // The top (up to) three limbs in a window whose bit 0 is bit `base` of
    // the sum; below it only whether anything is non-zero matters.
    let lo = h.saturating_sub(2);
    let base = LIMB_BITS * lo as u32;
    let window = limbs[lo..=h]
        .iter()
        .rev()
        .fold(0u128, |w, &l| (w << LIMB_BITS) | l as u128);
    let below_nonzero = limbs[..lo].iter().any(|&l| l != 0);
    // Position of the leading bit in the sum.
    let p = base + 127 - window.leading_zeros();
    // Result = mantissa * 2^(d - 1074), mantissa of 53 bits unless the sum
    // is below 2^53 units (a subnormal or the smallest normal binade, exact).
    let d = p.saturating_sub(52);
    let mantissa = if d == 0 {
        window as u64
    } else {
        // p >= base + 64 when lo = h - 2, so the shift is at least 12.
        let s = d - base;
        let truncated = (window >> s) as u64;
        let round_bit = (window >> (s - 1)) & 1 == 1;
        let sticky = window & ((1u128 << (s - 1)) - 1) != 0 || below_nonzero;
        if round_bit && (sticky || truncated & 1 == 1) {
            truncated + 1
        } else {
            truncated
        }
    };
    // With biased exponent d + 1 and the hidden bit in `mantissa`, the bits
    // are (d << 52) + mantissa; a mantissa rounded up to 2^53 carries into
    // the exponent, as it should, and for d = 0 these are the subnormal bits.
    let bits = (u64::from(d) << 52) + mantissa;
    if bits >= EXP_NON_FINITE << 52 {
        f64::INFINITY
    } else {
        f64::from_bits(bits)
    }
}

impl Default for ExactSum {
    /// The empty sum, as [`ExactSum::new`].
    fn default() -> Self {
        Self::new()
    }
}

impl PartialEq for ExactSum {
    /// Equal exact sums and equal counts of `+inf`, `-inf` and NaN terms.
    fn eq(&self, other: &Self) -> bool {
        self.to_words() == other.to_words()
    }
}

impl Eq for ExactSum {}

impl FromIterator<f64> for ExactSum {
    /// The exact sum of the terms.
    fn from_iter<I: IntoIterator<Item = f64>>(terms: I) -> Self {
        let mut s = Self::new();
        s.extend(terms);
        s
    }
}

impl Extend<f64> for ExactSum {
    /// Adds each term with [`ExactSum::add`].
    fn extend<I: IntoIterator<Item = f64>>(&mut self, terms: I) {
        for x in terms {
            self.add(x);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::seq::SliceRandom;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use xsum::{Xsum, XsumSmall};

    fn exact(terms: &[f64]) -> f64 {
        terms.iter().copied().collect::<ExactSum>().value()
    }

    /// Neal's xsum (the `xsum` crate), an independent correctly rounded sum.
    ///
    /// Two bugs of xsum 0.1.6 are worked around: its `XsumSmall` rounds a
    /// negative sum whose discarded bits are all zero away from zero (`[-1.5]`
    /// sums to -1.5000000000000002: the port lost the C code's exits to
    /// `done_rounding` on the negative branch), so a negative sum is taken
    /// as minus the sum of the negated terms, which goes through its
    /// positive branch; and its `XsumLarge` is wrong beyond a few thousand
    /// terms (5000 times 0.1 sums to 244.00000000000003), so it is not used.
    /// It also indexes out of bounds on sums far beyond `f64::MAX`.
    fn reference(terms: &[f64]) -> f64 {
        let xsum_small = |terms: &mut dyn Iterator<Item = f64>| {
            let mut acc = XsumSmall::new();
            for x in terms {
                acc.add(x);
            }
            acc.sum()
        };
        let sum = xsum_small(&mut terms.iter().copied());
        if sum < 0.0 {
            -xsum_small(&mut terms.iter().map(|&x| -x))
        } else {
            sum
        }
    }

    /// Bitwise equal, except that the sign of a zero is not compared (xsum
    /// gives -0.0 for some zero sums, this module +0.0).
    fn same(a: f64, b: f64) -> bool {
        a.to_bits() == b.to_bits() || (a == 0.0 && b == 0.0)
    }

    fn check(terms: &[f64]) {
        let got = exact(terms);
        let negated: Vec<f64> = terms.iter().map(|&x| -x).collect();
        assert!(same(exact(&negated), -got), "sum of negated terms");
        let want = reference(terms);
        assert!(
            same(got, want),
            "exact sum {got:e} ({:#x}) vs xsum {want:e} ({:#x}) of {} terms",
            got.to_bits(),
            want.to_bits(),
            terms.len()
        );
    }

    /// 2^e as a double, for e in -1074..1024.
    fn pow2(e: i32) -> f64 {
        if e >= -1022 {
            f64::from_bits(((e + 1023) as u64) << 52)
        } else {
            f64::from_bits(1 << (e + 1074))
        }
    }

    /// A finite double of random sign and mantissa whose leading bit is at
    /// 2^e, e uniform in `lo..hi` (below -1022 the product rounds into the
    /// subnormals, or to zero below -1074).
    fn random_double(rng: &mut ChaCha8Rng, lo: i32, hi: i32) -> f64 {
        let e = rng.gen_range(lo..hi);
        let m = 1.0 + rng.gen::<f64>();
        let x = if e >= -1022 {
            m * pow2(e)
        } else {
            m * pow2(e + 200) * pow2(-200)
        };
        if rng.gen() {
            -x
        } else {
            x
        }
    }

    /// A finite double with uniformly random bits: every exponent field
    /// (subnormals included) equally likely.
    fn random_bits(rng: &mut ChaCha8Rng) -> f64 {
        loop {
            let x = f64::from_bits(rng.gen());
            if x.is_finite() {
                return x;
            }
        }
    }

    #[test]
    fn exact_sum_matches_xsum_on_wide_exponent_ranges() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        for case in 0..3000 {
            let n = rng.gen_range(1..200);
            let (lo, hi) = match case % 4 {
                0 => (-40, 40),
                1 => (-1074, 1024),
                2 => (-1100, -1000),
                _ => (900, 1024),
            };
            let terms: Vec<f64> = (0..n).map(|_| random_double(&mut rng, lo, hi)).collect();
            check(&terms);
        }
        // Long sums: many terms land in each limb.
        for (lo, hi) in [(-30, 30), (-1074, 1000)] {
            let terms: Vec<f64> = (0..100_000)
                .map(|_| random_double(&mut rng, lo, hi))
                .collect();
            check(&terms);
        }
    }

    #[test]
    fn exact_sum_matches_xsum_on_random_bit_patterns() {
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        for _ in 0..3000 {
            let n = rng.gen_range(1..50);
            let terms: Vec<f64> = (0..n).map(|_| random_bits(&mut rng)).collect();
            check(&terms);
        }
    }

    #[test]
    fn exact_sum_matches_xsum_under_cancellation() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for case in 0..3000 {
            // Pairs x, -x that cancel exactly, plus a few tiny terms that
            // are all that is left; in random order.
            let mut terms = Vec::new();
            for _ in 0..rng.gen_range(1..40) {
                let x = random_double(&mut rng, -20, 1000);
                terms.push(x);
                terms.push(-x);
            }
            let (lo, hi) = if case % 2 == 0 {
                (-1074, -1000)
            } else {
                (-60, 0)
            };
            for _ in 0..rng.gen_range(0..4) {
                terms.push(random_double(&mut rng, lo, hi));
            }
            // And near-cancellation: x and -(x with its last bit changed).
            if case % 3 == 0 {
                let x = random_double(&mut rng, -100, 100);
                terms.push(x);
                terms.push(-f64::from_bits(x.to_bits() ^ 1));
            }
            terms.shuffle(&mut rng);
            check(&terms);
        }
    }

    #[test]
    fn exact_sum_matches_xsum_on_subnormals() {
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        for _ in 0..2000 {
            let n = rng.gen_range(1..100);
            let terms: Vec<f64> = (0..n)
                .map(|_| {
                    let x = f64::from_bits(rng.gen_range(0..1u64 << 53));
                    if rng.gen() {
                        -x
                    } else {
                        x
                    }
                })
                .collect();
            check(&terms);
        }
    }

    #[test]
    fn exact_sum_matches_xsum_near_overflow() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for _ in 0..2000 {
            let n = rng.gen_range(1..8);
            let mut terms: Vec<f64> = (0..n)
                .map(|_| {
                    let x = f64::MAX * (1.0 - rng.gen::<f64>() * 2f64.powi(-rng.gen_range(1..60)));
                    if rng.gen_bool(0.7) {
                        x
                    } else {
                        -x
                    }
                })
                .collect();
            // Sometimes just below f64::MAX by half an ulp or a bit more.
            if rng.gen_bool(0.3) {
                terms.push(2f64.powi(970) * rng.gen_range(0.5..1.5));
            }
            check(&terms);
        }
        // The overflow threshold itself: MAX + half an ulp rounds to even,
        // i.e. up, to infinity; MAX + just under half an ulp stays MAX.
        let half_ulp = 2f64.powi(970);
        assert_eq!(exact(&[f64::MAX, half_ulp]), f64::INFINITY);
        assert_eq!(exact(&[f64::MAX, half_ulp, -f64::MIN_POSITIVE]), f64::MAX);
        assert_eq!(exact(&[-f64::MAX, -half_ulp]), f64::NEG_INFINITY);
        assert_eq!(exact(&[f64::MAX, f64::MAX, -f64::MAX]), f64::MAX);
        check(&[f64::MAX, half_ulp]);
        check(&[f64::MAX, half_ulp, -f64::MIN_POSITIVE]);
    }

    #[test]
    fn exact_sum_rounds_halfway_cases_to_even() {
        let e53 = 2f64.powi(-53);
        let tiny = 2f64.powi(-1000);
        let ulp = 2f64.powi(-52);
        // 1 + half an ulp: a tie, to even (1.0); anything more rounds up.
        assert_eq!(exact(&[1.0, e53]), 1.0);
        assert_eq!(exact(&[1.0, e53, tiny]), 1.0 + ulp);
        assert_eq!(exact(&[1.0, e53, -tiny]), 1.0);
        assert_eq!(exact(&[1.0, e53, f64::from_bits(1)]), 1.0 + ulp);
        // 1 + ulp + half an ulp: a tie, to even (1 + 2 ulp).
        assert_eq!(exact(&[1.0 + ulp, e53]), 1.0 + 2.0 * ulp);
        assert_eq!(exact(&[-1.0, -e53, -tiny]), -1.0 - ulp);
        assert_eq!(exact(&[-1.0 - ulp, -e53]), -1.0 - 2.0 * ulp);
        // The mantissa rounds up into the next binade.
        let below_two = 2.0 - ulp;
        assert_eq!(exact(&[below_two, e53]), 2.0);
        for terms in [
            &[1.0, e53][..],
            &[1.0, e53, tiny],
            &[1.0, e53, -tiny],
            &[1.0 + ulp, e53],
            &[-1.0, -e53, -tiny],
            &[below_two, e53],
        ] {
            check(terms);
        }
    }

    #[test]
    fn exact_sum_of_two_terms_is_ieee_addition() {
        // IEEE addition of two doubles is correctly rounded itself: an
        // oracle independent of xsum, overflow included.
        let mut rng = ChaCha8Rng::seed_from_u64(6);
        for _ in 0..20_000 {
            let a = random_bits(&mut rng);
            let b = if rng.gen() {
                random_bits(&mut rng)
            } else {
                // Close exponents, where rounding happens most.
                a * rng.gen_range(-2.0..2.0)
            };
            let got = exact(&[a, b]);
            assert!(same(got, a + b), "{a:e} + {b:e}: {got:e} vs {:e}", a + b);
        }
    }

    #[test]
    fn exact_sum_hand_checked_cases() {
        // The doubles 0.1, 0.2 and 0.3 add up exactly to
        // 0.6000000000000000055511151231257827... (the sum of their exact
        // decimal expansions). The neighbouring doubles are
        // 0.59999999999999997779... = 0.6 (0x3FE3333333333333, 2.8e-17
        // away) and 0.60000000000000008882... (8.3e-17 away), so the correct
        // rounding is 0.6; the naive left-to-right sum gives the latter.
        let s = exact(&[0.1, 0.2, 0.3]);
        assert_eq!(s.to_bits(), 0x3FE3_3333_3333_3333);
        assert_eq!(s, 0.6);
        assert_eq!((0.1 + 0.2 + 0.3f64).to_bits(), 0x3FE3_3333_3333_3334);
        assert_eq!(exact(&[1e308, 1e308, -1e308]), 1e308);
        assert_eq!(exact(&[1e16, 1.0, -1e16]), 1.0);
        assert_eq!(exact(&[1.0, 2.0, 3.0]), 6.0);
        assert_eq!(exact(&[f64::from_bits(1); 3]), f64::from_bits(3));
        assert_eq!(
            exact(&[f64::MIN_POSITIVE, -f64::from_bits(1)]),
            f64::MIN_POSITIVE - f64::from_bits(1)
        );
        assert_eq!(exact(&[]).to_bits(), 0.0f64.to_bits());
        assert_eq!(exact(&[-0.0, -0.0]).to_bits(), 0.0f64.to_bits());
        assert_eq!(exact(&[5.0, -5.0]).to_bits(), 0.0f64.to_bits());
        assert_eq!(exact(&[-3.5]), -3.5);
        assert_eq!(exact(&[-f64::MAX]), -f64::MAX);
        assert_eq!(exact(&[f64::MAX; 2]), f64::INFINITY);
    }

    #[test]
    fn exact_sum_is_order_and_split_invariant() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for case in 0..300 {
            let n = rng.gen_range(1..500);
            let mut terms: Vec<f64> = (0..n)
                .map(|_| {
                    if case % 2 == 0 {
                        random_double(&mut rng, -60, 60)
                    } else {
                        random_bits(&mut rng)
                    }
                })
                .collect();
            let whole: ExactSum = terms.iter().copied().collect();
            let value = whole.value();
            terms.shuffle(&mut rng);
            let shuffled: ExactSum = terms.iter().copied().collect();
            assert_eq!(shuffled, whole);
            assert_eq!(shuffled.value().to_bits(), value.to_bits());
            // A random split into parts, summed apart and merged in random
            // order, also through to_words / from_words.
            let parts = rng.gen_range(1..8);
            let mut sums = vec![ExactSum::new(); parts];
            for &x in &terms {
                sums[rng.gen_range(0..parts)].add(x);
            }
            sums.shuffle(&mut rng);
            let mut merged = ExactSum::default();
            for s in &sums {
                merged.merge(s);
            }
            assert_eq!(merged, whole);
            assert_eq!(merged.value().to_bits(), value.to_bits());
            let mut words = [0i64; EXACT_SUM_WORDS];
            for s in &sums {
                for (w, v) in words.iter_mut().zip(s.to_words()) {
                    *w += v;
                }
            }
            let reduced = ExactSum::from_words(&words);
            assert_eq!(reduced, whole);
            assert_eq!(reduced.value().to_bits(), value.to_bits());
        }
    }

    #[test]
    fn exact_sum_words_round_trip() {
        let mut rng = ChaCha8Rng::seed_from_u64(8);
        let mut s = ExactSum::new();
        for _ in 0..1000 {
            s.add(random_bits(&mut rng));
        }
        s.add(f64::INFINITY);
        s.add(f64::NAN);
        s.add(f64::NAN);
        let words = s.to_words();
        assert_eq!(&words[EXACT_SUM_LIMBS..], &[1, 0, 2]);
        let back = ExactSum::from_words(&words);
        assert_eq!(back, s);
        assert_eq!(back.to_words(), words);
        // Normalized limbs: all but the top in 0..2^32.
        assert!(words[..EXACT_SUM_LIMBS - 1]
            .iter()
            .all(|&w| (0..1i64 << 32).contains(&w)));
        let mut finite = ExactSum::new();
        finite.add(-1.5);
        finite.add(2f64.powi(-1074));
        let back = ExactSum::from_words(&finite.to_words());
        assert_eq!(back.value().to_bits(), finite.value().to_bits());
        assert_eq!(back.value(), -1.5);
    }

    #[test]
    fn exact_sum_non_finite_rules() {
        let v = |terms: &[f64]| exact(terms);
        assert!(v(&[1.0, f64::NAN]).is_nan());
        assert!(v(&[f64::INFINITY, f64::NEG_INFINITY]).is_nan());
        assert!(v(&[f64::INFINITY, f64::NAN]).is_nan());
        assert_eq!(v(&[1.0, f64::INFINITY, f64::INFINITY]), f64::INFINITY);
        assert_eq!(v(&[1.0, f64::NEG_INFINITY]), f64::NEG_INFINITY);
        // An infinite term wins over a finite sum that overflows the other way.
        assert_eq!(v(&[f64::INFINITY, -f64::MAX, -f64::MAX]), f64::INFINITY);
        // Non-finite terms merge too.
        let mut a: ExactSum = [1.0, f64::INFINITY].into_iter().collect();
        let b: ExactSum = [f64::NEG_INFINITY].into_iter().collect();
        assert_eq!(a.value(), f64::INFINITY);
        a.merge(&b);
        assert!(a.value().is_nan());
        assert_ne!(a, ExactSum::new());
    }

    #[test]
    fn exact_sum_survives_carry_propagation_and_large_limbs() {
        // Force the periodic carry propagation by starting near the bound,
        // then check the sum is still exact.
        let mut s = ExactSum::new();
        s.pending = NORMALIZE_EVERY - 3;
        for _ in 0..10 {
            s.add(f64::MAX);
            s.add(-f64::MAX);
            s.add(1.0);
        }
        assert!(s.pending < 30);
        assert_eq!(s.value(), 10.0);
        // Merges of accumulators with a large pending count propagate too.
        // The merged bound counts one more than the two pending counts.
        let mut a = ExactSum::new();
        a.add(3.0);
        a.pending = NORMALIZE_EVERY / 2 - 1;
        let mut b = ExactSum::new();
        b.add(4.0);
        b.pending = NORMALIZE_EVERY / 2;
        a.merge(&b);
        assert_eq!(a.pending, 0);
        assert_eq!(a.value(), 7.0);
        // Many equal terms pile up in the same limbs without carries.
        check(&vec![0.1; 100_000]);
        check(&vec![-1.5 * 2f64.powi(1000); 100_000]);
        // (xsum 0.1.6 indexes out of its chunks on this one.)
        assert_eq!(exact(&vec![-f64::MAX / 4.0; 100_000]), f64::NEG_INFINITY);
        check(&vec![f64::from_bits(0x000f_ffff_ffff_ffff); 100_000]);
    }
}
