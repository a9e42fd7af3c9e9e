//! A shear cell's runs at one law and speed, over their seeds: means with
//! 95 % confidence intervals from the seeds' scatter.

use floe_analysis::uncertainty::{seed_mean, SeedMean};

use super::CellRun;

/// One law and wall speed over its seeds.
#[derive(Debug, Clone)]
pub struct SeedPoint {
    /// The law's name.
    pub law: String,
    /// The top wall's speed, m/s.
    pub speed_m_per_s: f64,
    /// Inertial number.
    pub inertial_number: SeedMean,
    /// The layer's friction, tau/P on the walls.
    pub mu: SeedMean,
    /// Solid fraction in the middle half of the layer.
    pub solid_fraction: SeedMean,
    /// The contacts' own friction.
    pub contact_mu: SeedMean,
    /// Normal stress on the bottom and on the top wall, N/m (apart: the
    /// layer was not yet steady).
    pub wall_normal_stress_bottom_top_n_per_m: [SeedMean; 2],
    /// The runs' own (blocked) errors of mu, averaged: the uncertainty of
    /// one run, to set beside the seeds' scatter.
    pub mean_run_error_of_mu: f64,
    /// This law's mu less the first law's at the same speed, seed by seed
    /// (a seed draws the same floes for every law, so the pairs differ in
    /// the law only), over the seeds both ran; `None` for the first law
    /// or without common seeds.
    pub mu_less_first_law: Option<SeedMean>,
}

/// `runs` grouped by law and speed (in the order first met), each group
/// over its seeds, each law paired with `first_law` (the first of
/// `--laws`) seed by seed; a group of one run has NaN intervals.
pub fn over_seeds(runs: &[CellRun], first_law: &str) -> Vec<SeedPoint> {
    let mut keys: Vec<(&str, f64)> = Vec::new();
    for r in runs {
        if !keys.contains(&(r.law.as_str(), r.speed_m_per_s)) {
            keys.push((r.law.as_str(), r.speed_m_per_s));
        }
    }
    keys.into_iter()
        .map(|(law, v)| {
            let group: Vec<&CellRun> = runs
                .iter()
                .filter(|r| r.law == law && r.speed_m_per_s == v)
                .collect();
            let of = |f: &dyn Fn(&CellRun) -> f64| {
                seed_mean(&group.iter().map(|r| f(r)).collect::<Vec<f64>>())
            };
            SeedPoint {
                law: law.to_string(),
                speed_m_per_s: v,
                inertial_number: of(&|r| r.steady.inertial_number),
                mu: of(&|r| r.steady.mu.value),
                solid_fraction: of(&|r| r.steady.solid_fraction.value),
                contact_mu: of(&|r| r.steady.contact_mu),
                wall_normal_stress_bottom_top_n_per_m: [0, 1]
                    .map(|k| of(&|r| r.steady.wall_normal_stress_bottom_top_n_per_m[k].value)),
                mean_run_error_of_mu: of(&|r| r.steady.mu.error).mean,
                mu_less_first_law: paired_with(runs, first_law, law, v),
            }
        })
        .collect()
}

/// The seed-by-seed difference in mu between `law` and `first` at the
/// speed `v`, over the seeds both have measured.
fn paired_with(runs: &[CellRun], first: &str, law: &str, v: f64) -> Option<SeedMean> {
    if first == law {
        return None;
    }
    let at = |l: &str, seed: Option<u64>| {
        runs.iter()
            .find(|r| r.law == l && r.speed_m_per_s == v && r.seed == seed)
    };
    let differences: Vec<f64> = runs
        .iter()
        .filter(|r| r.law == law && r.speed_m_per_s == v && r.seed.is_some())
        .filter_map(|r| Some(r.steady.mu.value - at(first, r.seed)?.steady.mu.value))
        .collect();
    (!differences.is_empty()).then(|| seed_mean(&differences))
}
