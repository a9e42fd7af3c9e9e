//! The floe size distribution of a snapshot: how many floes, their sizes
//! `d = sqrt(area)`, and the exponent of a power law `N(>d) ~ d^-alpha`
//! fitted to them (maximum likelihood for a law truncated to the sizes'
//! range, [`fit_power_law`]: the estimator floe's power-law tessellation
//! draws from). What fracture changes over a run.

use floe_dem::tessellation::{fit_power_law, PowerLawFit};
use floe_io::{IoError, RunFile};

/// The free floes' sizes at one snapshot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FloeSizes {
    /// The snapshot's time, s.
    pub time_s: f64,
    /// Free floes.
    pub floes: usize,
    /// Median size `sqrt(area)`, m.
    pub median_m: f64,
    /// Smallest and largest size, m.
    pub range_m: (f64, f64),
    /// The power law fitted between the smallest and the largest size
    /// (`None` for fewer than two distinct sizes, or sizes that pile up at
    /// the large end).
    pub fit: Option<PowerLawFit>,
}

/// The size distribution of floes of `areas_m2` at `time_s`; `None`
/// without floes.
pub fn of_areas(time_s: f64, areas_m2: &[f64]) -> Option<FloeSizes> {
    let mut d: Vec<f64> = areas_m2.iter().map(|a| a.sqrt()).collect();
    if d.is_empty() {
        return None;
    }
    d.sort_by(f64::total_cmp);
    let (lo, hi) = (d[0], d[d.len() - 1]);
    let n = d.len();
    let median_m = if n % 2 == 1 {
        d[n / 2]
    } else {
        0.5 * (d[n / 2 - 1] + d[n / 2])
    };
    Some(FloeSizes {
        time_s,
        floes: n,
        median_m,
        range_m: (lo, hi),
        fit: (hi > lo).then(|| fit_power_law(&d, lo, hi)).flatten(),
    })
}

/// The free floes' size distribution at snapshot `k` of `run`.
pub fn at_snapshot(run: &RunFile, k: usize) -> Result<Option<FloeSizes>, IoError> {
    let floes = run.floes_at(k)?;
    let time_s = run.snapshot(k)?.time_s;
    let areas: Vec<f64> = (0..floes.id.len())
        .filter(|&i| !floes.prescribed[i])
        .map(|i| floes.area_m2[i])
        .collect();
    Ok(of_areas(time_s, &areas))
}

/// `sizes` in words: count, median, and the fitted exponent with its
/// standard error.
pub fn describe(sizes: &FloeSizes) -> String {
    use floe_scenario::numbers::sig;
    let fit = sizes
        .fit
        .map_or("no power law N(>d) ~ d^-a with a > 0 fits".into(), |f| {
            format!(
                "N(>d) ~ d^-{} +- {} (maximum likelihood on [{}, {}] m)",
                sig(f.exponent),
                sig(f.std_error),
                sig(sizes.range_m.0),
                sig(sizes.range_m.1)
            )
        });
    format!(
        "{} free floes, median size sqrt(A) {} m; {fit}",
        sizes.floes,
        sig(sizes.median_m)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use floe_dem::tessellation::PowerLawSizes;

    #[test]
    fn sizes_drawn_from_a_power_law_give_back_its_exponent() {
        for exponent in [0.8, 1.5, 2.5] {
            let law = PowerLawSizes {
                exponent,
                min_m: 100.0,
                max_m: 5000.0,
            };
            // Evenly spread quantiles: a sample of the law without noise.
            let n = 2000;
            let areas: Vec<f64> = (0..n)
                .map(|i| law.quantile((i as f64 + 0.5) / n as f64).powi(2))
                .collect();
            let s = of_areas(7.0, &areas).unwrap();
            let fit = s.fit.expect("a fit");
            assert_eq!(s.floes, n);
            assert!(
                (fit.exponent - exponent).abs() < 2.0 * fit.std_error,
                "{exponent}: {fit:?}"
            );
            assert!((s.median_m - law.quantile(0.5)).abs() < 1e-3 * s.median_m);
        }
        // Equal floes: no law to fit; none at all: nothing.
        let same = of_areas(0.0, &[4.0, 4.0, 4.0]).unwrap();
        assert!(same.fit.is_none() && same.median_m == 2.0);
        assert!(of_areas(0.0, &[]).is_none());
    }
}
