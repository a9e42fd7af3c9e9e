//! Means of sampled series whose samples need not be evenly spaced: a run
//! writes denser output in its windows (`[[output.window]]`), so a plain
//! average over samples would weigh those stretches more.

/// The time each of the increasing `time_s` stands for: half the gap to
/// each neighbour, the first and last a whole gap on their inner side, so
/// that evenly spaced samples weigh alike. One sample, or samples all at
/// one time, weigh 1 each.
pub fn time_weights(time_s: &[f64]) -> Vec<f64> {
    let n = time_s.len();
    let gap = |k: usize| time_s[k + 1] - time_s[k];
    let weights: Vec<f64> = (0..n)
        .map(|k| match (k > 0, k + 1 < n) {
            (false, true) => gap(0),
            (true, false) => gap(k - 1),
            (true, true) => 0.5 * (gap(k - 1) + gap(k)),
            (false, false) => 1.0,
        })
        .collect();
    if weights.iter().sum::<f64>() > 0.0 {
        weights
    } else {
        vec![1.0; n]
    }
}

/// The mean of `value(time_s)` over the samples with `t0 <= t < t1`, each
/// weighted by the time it stands for ([`time_weights`] of those samples):
/// evenly spaced samples give the plain average. `None` when no sample
/// falls in `[t0, t1)`. `time_s` must be increasing.
pub fn time_mean(time_s: &[f64], value: &[f64], (t0, t1): (f64, f64)) -> Option<f64> {
    let (times, values): (Vec<f64>, Vec<f64>) = time_s
        .iter()
        .zip(value)
        .filter(|(&t, _)| t >= t0 && t < t1)
        .unzip();
    if times.is_empty() {
        return None;
    }
    let weights = time_weights(&times);
    let sum: f64 = weights.iter().zip(&values).map(|(w, v)| w * v).sum();
    Some(sum / weights.iter().sum::<f64>())
}

#[cfg(test)]
mod tests {
    use super::{time_mean, time_weights};

    #[test]
    fn evenly_spaced_samples_give_the_plain_average() {
        let t: Vec<f64> = (0..=10).map(f64::from).collect();
        let v: Vec<f64> = t.iter().map(|t| t * t).collect();
        let plain = v.iter().sum::<f64>() / v.len() as f64;
        let m = time_mean(&t, &v, (0.0, 11.0)).unwrap();
        assert!((m - plain).abs() < 1e-12 * plain, "{m} {plain}");
        assert_eq!(time_mean(&t, &v, (3.0, 4.0)), Some(9.0));
        assert_eq!(time_mean(&t, &v, (20.0, 30.0)), None);
    }

    #[test]
    fn a_dense_stretch_weighs_no_more_than_its_length() {
        // 1 over [0, 10), 3 over [10, 20]: sampled every 1 s, then every
        // 0.01 s. The mean over time is 2; a plain average would be near 3.
        let mut t: Vec<f64> = (0..10).map(f64::from).collect();
        t.extend((0..=1000).map(|k| 10.0 + 0.01 * f64::from(k)));
        let v: Vec<f64> = t
            .iter()
            .map(|&t| if t < 10.0 { 1.0 } else { 3.0 })
            .collect();
        let m = time_mean(&t, &v, (0.0, 21.0)).unwrap();
        // The boundary sample at 10 s stands for half a second of each side.
        assert!((m - 2.0).abs() < 0.06, "{m}");
        let plain = v.iter().sum::<f64>() / v.len() as f64;
        assert!(plain > 2.9, "{plain}");
    }

    #[test]
    fn weights_cover_the_span_with_a_gap_beyond_each_end() {
        let w = time_weights(&[0.0, 1.0, 3.0, 3.5]);
        assert_eq!(w, vec![1.0, 1.5, 1.25, 0.5]);
        assert_eq!(time_weights(&[2.0]), vec![1.0]);
        assert_eq!(time_weights(&[2.0, 2.0]), vec![1.0, 1.0]);
        assert!(time_weights(&[]).is_empty());
    }
}
