//! Uncertainties a study can quote: the standard error of a time series'
//! mean that allows for the correlation between successive samples
//! (blocking, Flyvbjerg & Petersen 1989), and a mean over independent
//! repetitions (seeds) with its Student-t confidence interval.
//!
//! Successive snapshots of a sheared pack are correlated over the time a
//! floe takes to rearrange; the naive `s / sqrt(n)` of such a series is too
//! small by `sqrt(2 tau_int)` (tau_int in samples). Blocking averages
//! neighbouring samples in pairs, again and again; once the blocks are
//! longer than the correlation time their means are independent and the
//! naive error of the block means stops growing (the plateau).

/// A mean and the standard error that goes with it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeanError {
    /// The mean.
    pub mean: f64,
    /// Its standard error (one standard deviation of the mean).
    pub error: f64,
    /// Samples per block at which the error was read (1: none blocked).
    pub block_samples: usize,
    /// Whether the blocked errors reached a plateau: the error at the
    /// chosen level exceeds the previous (shorter-block) level's by no more
    /// than its own statistical uncertainty. `false`: the series is too short for its correlation time,
    /// and the error is a lower bound.
    pub converged: bool,
}

/// Fewest blocks a level may have to be read: the relative error of a
/// standard error from `m` blocks is `1 / sqrt(2 (m - 1))`, 18 % at 16.
const MIN_BLOCKS: usize = 16;

/// The mean of `values` with its blocked standard error: the naive
/// standard error of block means for blocks of 1, 2, 4, ... samples, read
/// at the largest of those levels that still has [`MIN_BLOCKS`] blocks (the
/// conservative choice: below the plateau the levels underestimate, and
/// the plateau's levels agree within their noise). Fewer than 2 values:
/// the error is NaN.
pub fn blocked_mean(values: &[f64]) -> MeanError {
    let n = values.len();
    let mean = values.iter().sum::<f64>() / n as f64;
    if n < 2 {
        return MeanError {
            mean,
            error: f64::NAN,
            block_samples: 1,
            converged: false,
        };
    }
    // Standard errors per level, from the block means (a trailing odd
    // sample is dropped at each halving, as in Flyvbjerg & Petersen).
    let mut levels: Vec<(usize, f64, usize)> = Vec::new();
    let mut blocks: Vec<f64> = values.to_vec();
    let mut size = 1;
    while blocks.len() >= 2 {
        let m = blocks.len();
        let (_, var) = mean_and_variance(&blocks);
        levels.push((size, (var / m as f64).sqrt(), m));
        blocks = blocks
            .chunks_exact(2)
            .map(|p| 0.5 * (p[0] + p[1]))
            .collect();
        size *= 2;
    }
    let usable = levels
        .iter()
        .rposition(|&(_, _, m)| m >= MIN_BLOCKS)
        .unwrap_or(0);
    let (block_samples, error, m) = levels[usable];
    // Converged if the error barely grows to the previous level: within
    // the noise of the estimate at this level.
    let converged = usable > 0 && {
        let below = levels[usable - 1].1;
        error - below <= error / (2.0 * (m as f64 - 1.0)).sqrt()
    };
    MeanError {
        mean,
        error,
        block_samples,
        converged,
    }
}

/// The blocked error of a ratio of means `<num> / <den>` (e.g. a layer's
/// friction, mean shear stress over mean pressure), by the delta method:
/// the blocked error of the series `(num_k - R den_k) / <den>` with
/// `R = <num> / <den>`, which carries the correlation of numerator and
/// denominator. `num` and `den` have the same length.
pub fn blocked_ratio(num: &[f64], den: &[f64]) -> MeanError {
    debug_assert_eq!(num.len(), den.len());
    let n = num.len().min(den.len()) as f64;
    let mn = num.iter().sum::<f64>() / n;
    let md = den.iter().sum::<f64>() / n;
    let r = mn / md;
    let linear: Vec<f64> = num.iter().zip(den).map(|(a, b)| (a - r * b) / md).collect();
    let e = blocked_mean(&linear);
    MeanError { mean: r, ..e }
}

/// A mean over independent repetitions (seeds) with the half-width of its
/// two-sided 95 % confidence interval, `t(0.975, n - 1) s / sqrt(n)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeedMean {
    /// The mean over repetitions.
    pub mean: f64,
    /// Half-width of the 95 % confidence interval (NaN for one repetition).
    pub ci95: f64,
    /// Sample standard deviation over repetitions (NaN for one).
    pub spread: f64,
    /// Repetitions.
    pub n: usize,
}

/// The mean of independent repetitions `values` and its 95 % confidence
/// interval from their scatter (Student's t).
pub fn seed_mean(values: &[f64]) -> SeedMean {
    let n = values.len();
    let mean = values.iter().sum::<f64>() / n as f64;
    if n < 2 {
        return SeedMean {
            mean,
            ci95: f64::NAN,
            spread: f64::NAN,
            n,
        };
    }
    let spread = mean_and_variance(values).1.sqrt();
    SeedMean {
        mean,
        ci95: t975(n - 1) * spread / (n as f64).sqrt(),
        spread,
        n,
    }
}

/// The mean of at least two `values` and their unbiased sample variance.
fn mean_and_variance(values: &[f64]) -> (f64, f64) {
    let n = values.len();
    let mean = values.iter().sum::<f64>() / n as f64;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
    (mean, var)
}

/// Student's t quantile at 0.975 for `dof` degrees of freedom (a table for
/// 1-30, then the series in 1/dof, which is within 2e-4 of the exact value
/// beyond 30). A table, not a statistics crate: one function's worth.
pub fn t975(dof: usize) -> f64 {
    const TABLE: [f64; 30] = [
        12.7062, 4.3027, 3.1824, 2.7764, 2.5706, 2.4469, 2.3646, 2.3060, 2.2622, 2.2281, 2.2010,
        2.1788, 2.1604, 2.1448, 2.1314, 2.1199, 2.1098, 2.1009, 2.0930, 2.0860, 2.0796, 2.0739,
        2.0687, 2.0639, 2.0595, 2.0555, 2.0518, 2.0484, 2.0452, 2.0423,
    ];
    match dof {
        0 => f64::NAN,
        1..=30 => TABLE[dof - 1],
        _ => {
            // Cornish-Fisher expansion about the normal quantile.
            let z: f64 = 1.959_964;
            let v = dof as f64;
            z + (z.powi(3) + z) / (4.0 * v)
                + (5.0 * z.powi(5) + 16.0 * z.powi(3) + 3.0 * z) / (96.0 * v * v)
        }
    }
}
