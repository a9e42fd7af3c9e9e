//! The metrics of one run, read from its HDF5 file: stress, energy and
//! sliding histories, the velocity profile across the channel and its shear
//! band, slip events, and the peak-to-steady ratio of the shear stress.
//!
//! The channel runs along x, its walls across y (the layout of
//! `scenarios/shear_zone.toml`); the profile bins floe centroids in y over
//! the domain.

use std::path::Path;

use floe_analysis::profile::{shear_band, velocity_profile, ShearBand, VelocityProfile};
use floe_analysis::slip_events::{SlipEvent, SlipEventDetector, SlipEventRule};
use floe_analysis::stress::{channel_stress, peak_to_steady, PeakToSteady};
use floe_analysis::time_mean::{time_mean, time_weights};
use floe_io::RunFile;

use floe_run::Error;

/// Choices that shape the metrics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MetricOptions {
    /// Bins across the channel for the velocity profile.
    pub profile_bins: usize,
    /// The profile pools the snapshots in the last `late_fraction` of the
    /// run's time (0 < f <= 1), when the flow has settled, each weighted by
    /// the time it stands for.
    pub late_fraction: f64,
    /// The slip-event rule.
    pub slip: SlipEventRule,
    /// The steady window of the peak-to-steady ratio, as a fraction of the run.
    pub steady_fraction: f64,
}

impl Default for MetricOptions {
    fn default() -> Self {
        Self {
            profile_bins: 25,
            late_fraction: 0.5,
            slip: SlipEventRule::default(),
            steady_fraction: 0.25,
        }
    }
}

/// Everything `floe compare` reports about one run.
#[derive(Debug, Clone)]
pub struct RunMetrics {
    /// Observable sample times, s.
    pub time_s: Vec<f64>,
    /// Mean shear stress `(σxy + σyx)/2`, N/m.
    pub shear_stress_n_per_m: Vec<f64>,
    /// Mean normal stress across the channel, compression positive, N/m.
    pub normal_stress_n_per_m: Vec<f64>,
    /// Kinetic energy, translational plus rotational, J.
    pub kinetic_energy_j: Vec<f64>,
    /// Cumulative frictional dissipation, J.
    pub friction_dissipation_j: Vec<f64>,
    /// Fraction of contacts sliding.
    pub sliding_fraction: Vec<f64>,
    /// Along-channel velocity across the channel, late in the run.
    pub profile: VelocityProfile,
    /// Its shear band, when the velocity changes across the channel.
    pub band: Option<ShearBand>,
    /// Slip events over all snapshots.
    pub slip_events: Vec<SlipEvent>,
    /// Peak-to-steady ratio of the shear stress magnitude, when defined.
    pub peak_to_steady: Option<PeakToSteady>,
    /// Snapshots read.
    pub snapshots: usize,
    /// The floe size distribution at the first and the last snapshot
    /// (they differ when floes broke).
    pub sizes: [Option<crate::floe_sizes::FloeSizes>; 2],
}

impl RunMetrics {
    /// The sliding fraction averaged over time (samples weighted by the
    /// time each stands for: they need not be evenly spaced); 0 without samples.
    pub fn mean_sliding_fraction(&self) -> f64 {
        time_mean(
            &self.time_s,
            &self.sliding_fraction,
            (f64::NEG_INFINITY, f64::INFINITY),
        )
        .unwrap_or(0.0)
    }
}

fn series(run: &RunFile, name: &str) -> Result<(Vec<f64>, Vec<f64>), Error> {
    let s = run.observable(name)?;
    Ok((s.time_s, s.value))
}

/// Reads `path` and computes its metrics.
pub fn measure(path: &Path, options: &MetricOptions) -> Result<RunMetrics, Error> {
    let run = RunFile::open(path)?;
    let (time_s, stress) = series(&run, "mean_stress")?;
    let (shear, normal): (Vec<f64>, Vec<f64>) = stress
        .chunks_exact(4)
        .map(|s| {
            let c = channel_stress([s[0], s[1], s[2], s[3]]);
            (c.shear_n_per_m, c.normal_n_per_m)
        })
        .unzip();
    let (_, translational) = series(&run, "kinetic_translational")?;
    let (_, rotational) = series(&run, "kinetic_rotational")?;
    let kinetic = translational
        .iter()
        .zip(&rotational)
        .map(|(a, b)| a + b)
        .collect();
    let (_, friction) = series(&run, "friction_dissipation")?;
    let (_, sliding) = series(&run, "sliding_fraction")?;

    let meta = run.metadata()?;
    let snapshots = run.snapshot_count()?;
    if snapshots == 0 {
        return Err(Error::Usage(format!(
            "{}: holds no snapshots to measure",
            path.display()
        )));
    }
    // Snapshots need not be evenly spaced: the late ones are chosen by time
    // (the last is always in) and each weighs the time it stands for.
    let times = run.snapshot_times()?;
    let (first, last) = (times[0], times[snapshots - 1]);
    let late_from = times.partition_point(|&t| t < last - options.late_fraction * (last - first));
    let late_weights = time_weights(&times[late_from..]);
    let (mut y, mut u, mut w) = (Vec::new(), Vec::new(), Vec::new());
    let mut detector = SlipEventDetector::new(options.slip).map_err(Error::analysis)?;
    // Contacts are followed by their floes' ids (a floe's index changes
    // when floes break), as dense keys given in id order: new pieces have
    // the largest ids, so the keys keep the contacts' sorted order.
    let mut key_of: std::collections::HashMap<u64, u32> = std::collections::HashMap::new();
    for k in 0..snapshots {
        let contacts = run.contacts(k)?;
        let ids = run.floes_at(k)?.id;
        for &id in &ids {
            let next = key_of.len() as u32;
            key_of.entry(id).or_insert(next);
        }
        let pair: Vec<[u32; 2]> = contacts
            .pair
            .iter()
            .map(|p| p.map(|h| key_of[&ids[h as usize]]))
            .collect();
        detector
            .push(contacts.time_s, &pair, &contacts.slip_rate_m_per_s)
            .map_err(Error::analysis)?;
        if k >= late_from {
            let snap = run.snapshot(k)?;
            let floes = run.floes_at(k)?;
            for i in 0..floes.id.len() {
                if !floes.prescribed[i] {
                    y.push(snap.position[i][1]);
                    u.push(snap.velocity[i][0]);
                    w.push(floes.area_m2[i] * late_weights[k - late_from]);
                }
            }
        }
    }
    // The domain across the channel, widened to every free floe: a wall
    // that holds a stress may have moved out of the domain as the ice dilated.
    let (y0, height) = (meta.domain.min_m[1], meta.domain.size_m[1]);
    let (lo, hi) = y
        .iter()
        .fold((y0, y0 + height), |(a, b), &v| (a.min(v), b.max(v)));
    let hi = if hi > y0 + height {
        hi + 1e-9 * (hi - lo)
    } else {
        hi
    };
    let profile =
        velocity_profile(&y, &u, &w, lo, hi, options.profile_bins).map_err(Error::analysis)?;
    let band = shear_band(&profile).ok();
    let magnitude: Vec<f64> = shear.iter().map(|s: &f64| s.abs()).collect();
    let peak_to_steady = peak_to_steady(&time_s, &magnitude, options.steady_fraction).ok();
    Ok(RunMetrics {
        time_s,
        shear_stress_n_per_m: shear,
        normal_stress_n_per_m: normal,
        kinetic_energy_j: kinetic,
        friction_dissipation_j: friction,
        sliding_fraction: sliding,
        profile,
        band,
        slip_events: detector.finish(),
        peak_to_steady,
        snapshots,
        sizes: [
            crate::floe_sizes::at_snapshot(&run, 0)?,
            crate::floe_sizes::at_snapshot(&run, snapshots - 1)?,
        ],
    })
}
