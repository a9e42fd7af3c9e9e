//! A shear cell's rheology read from its run file: one
//! [`CellSample`] per snapshot, and their means over the steady part.

use std::path::Path;

use floe_analysis::love_weber::ContactForces;
use floe_analysis::rheology::{
    cell_sample, inertial_number, CellSample, CellSnapshot, NOT_TOUCHING,
};
use floe_analysis::uncertainty::{blocked_mean, blocked_ratio, MeanError};
use floe_analysis::AnalysisError;
use floe_io::{RunFile, Series};

use floe_run::Error;

/// The cell's samples at every snapshot after the first (which has no
/// contacts yet), with their times; `None` where the free floes touched
/// only one wall or none (the layer lost its confinement for a moment).
pub fn cell_samples(path: &Path) -> Result<Vec<(f64, Option<CellSample>)>, Error> {
    let run = RunFile::open(path)?;
    let meta = run.metadata()?;
    if !meta.domain.periodic[0] || meta.domain.periodic[1] {
        return Err(Error::Usage(format!(
            "{}: a shear cell is periodic along x only, with walls at the bottom and top",
            path.display()
        )));
    }
    let mut out = Vec::new();
    for k in 1..run.snapshot_count()? {
        let floes = run.floes_at(k)?;
        let snap = run.snapshot(k)?;
        let contacts = run.contacts(k)?;
        let vertices: Vec<Vec<[f64; 2]>> = (0..floes.len())
            .map(|i| snap.world_vertices(&floes, i))
            .collect();
        let cell = CellSnapshot {
            period_x_m: meta.domain.size_m[0],
            position: &snap.position,
            velocity: &snap.velocity,
            area_m2: &floes.area_m2,
            mass_kg: &floes.mass_kg,
            prescribed: &floes.prescribed,
            vertices: &vertices,
            contacts: ContactForces {
                pair: &contacts.pair,
                point: &contacts.point,
                normal: &contacts.normal,
                normal_force_n: &contacts.normal_force_n,
                tangential_force_n: &contacts.tangential_force_n,
            },
        };
        let sample = match cell_sample(&cell) {
            Ok(sample) => Some(sample),
            Err(AnalysisError::NotEnoughData(NOT_TOUCHING)) => None,
            Err(e) => return Err(Error::analysis(e)),
        };
        out.push((snap.time_s, sample));
    }
    Ok(out)
}

/// A mean over a run's steady samples, with its standard error from
/// blocking ([`blocked_mean`]: successive snapshots are correlated, and
/// the error allows for it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mean {
    /// The mean.
    pub value: f64,
    /// Its standard error.
    pub error: f64,
}

impl From<MeanError> for Mean {
    fn from(e: MeanError) -> Self {
        Self {
            value: e.mean,
            error: e.error,
        }
    }
}

fn mean(values: impl Iterator<Item = f64>) -> Mean {
    blocked_mean(&values.collect::<Vec<f64>>()).into()
}

/// The steady state of one cell run: means over the samples from
/// `from_fraction` of the run's snapshots on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteadyCell {
    /// Samples averaged.
    pub samples: usize,
    /// Snapshots of the steady part left out because the free floes did
    /// not touch both walls.
    pub unconfined: usize,
    /// Normal stress on the walls, N/m.
    pub wall_normal_stress_n_per_m: Mean,
    /// Normal stress on the bottom wall and on the top wall, N/m (apart
    /// while the layer is not yet steady: its height still changing).
    pub wall_normal_stress_bottom_top_n_per_m: [Mean; 2],
    /// Shear stress on the walls, N/m.
    pub wall_shear_stress_n_per_m: Mean,
    /// Normal stress from the contacts and fluctuations inside, N/m.
    pub bulk_normal_stress_n_per_m: Mean,
    /// Shear stress from the contacts and fluctuations inside, N/m.
    pub bulk_shear_stress_n_per_m: Mean,
    /// `mu = <tau> / <P>` on the walls (a ratio of means: in stick-slip `P`
    /// nearly vanishes between events, and a mean of ratios would not be
    /// defined), its blocked error by the delta method ([`blocked_ratio`]).
    pub mu: Mean,
    /// Whether the blocked error of `mu` reached its plateau (`false`: the
    /// steady part is short for its correlation time; the error is a lower
    /// bound).
    pub mu_error_converged: bool,
    /// Snapshots per block at which the error of `mu` was read.
    pub mu_block_samples: usize,
    /// Solid fraction in the middle half of the layer.
    pub solid_fraction: Mean,
    /// Shear rate of the fitted profile, 1/s.
    pub shear_rate_per_s: Mean,
    /// The walls' speed difference over the layer height, 1/s.
    pub wall_shear_rate_per_s: Mean,
    /// Inertial number from the mean shear rate and wall pressure.
    pub inertial_number: f64,
    /// Layer height, m.
    pub height_m: Mean,
    /// The contacts' own friction, `sum |F_t| / sum F_n` over all contacts
    /// (the `mean_mu` observable), averaged over the same part of the run.
    pub contact_mu: f64,
}

/// Means over the samples from `from_fraction` (in [0, 1)) of the list on;
/// `contact_mu` is the run's `mean_mu` observable. `None` when fewer than
/// two snapshots of that part have the floes touching both walls (the
/// layer lost its confinement: not a dense flow to measure).
pub fn steady(
    samples: &[(f64, Option<CellSample>)],
    contact_mu: &Series,
    from_fraction: f64,
) -> Option<SteadyCell> {
    let start = ((samples.len() as f64) * from_fraction).floor() as usize;
    let part = &samples[start.min(samples.len())..];
    let used: Vec<&CellSample> = part.iter().filter_map(|(_, s)| s.as_ref()).collect();
    if used.len() < 2 {
        return None;
    }
    let from_s = part.first().map_or(f64::INFINITY, |(t, _)| *t);
    let late: Vec<f64> = contact_mu
        .time_s
        .iter()
        .zip(&contact_mu.value)
        .filter(|(t, _)| **t >= from_s)
        .map(|(_, v)| *v)
        .collect();
    let pick = |f: fn(&CellSample) -> f64| mean(used.iter().map(move |s| f(s)));
    let p = pick(|s| s.wall_normal_stress_n_per_m);
    let shear = pick(|s| s.wall_shear_stress_n_per_m);
    let series = |f: fn(&CellSample) -> f64| used.iter().map(|s| f(s)).collect::<Vec<f64>>();
    let mu = blocked_ratio(
        &series(|s| s.wall_shear_stress_n_per_m),
        &series(|s| s.wall_normal_stress_n_per_m),
    );
    let rate = pick(|s| s.shear_rate_per_s);
    let first = used[0];
    Some(SteadyCell {
        samples: used.len(),
        unconfined: part.len() - used.len(),
        wall_normal_stress_n_per_m: p,
        wall_normal_stress_bottom_top_n_per_m: [
            pick(|s| s.wall_normal_stress_bottom_top_n_per_m[0]),
            pick(|s| s.wall_normal_stress_bottom_top_n_per_m[1]),
        ],
        wall_shear_stress_n_per_m: shear,
        bulk_normal_stress_n_per_m: pick(|s| s.bulk_normal_stress_n_per_m()),
        bulk_shear_stress_n_per_m: pick(|s| s.bulk_shear_stress_n_per_m()),
        mu: mu.into(),
        mu_error_converged: mu.converged,
        mu_block_samples: mu.block_samples,
        solid_fraction: pick(|s| s.solid_fraction),
        shear_rate_per_s: rate,
        wall_shear_rate_per_s: pick(|s| s.wall_shear_rate_per_s),
        inertial_number: inertial_number(
            rate.value,
            first.floe_size_m,
            first.areal_density_kg_per_m2,
            p.value,
        ),
        height_m: pick(|s| s.height_m),
        contact_mu: late.iter().sum::<f64>() / late.len().max(1) as f64,
    })
}
