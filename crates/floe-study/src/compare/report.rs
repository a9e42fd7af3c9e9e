//! `report.md` and its figures: the variants' metrics side by side.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use floe_analysis::slip_events::log_histogram;

use super::metrics::RunMetrics;
use crate::plot::{grid, Axes, Line};
use floe_run::Error;
use floe_scenario::numbers::sig;

/// One variant of the comparison: its label, what was changed, its metrics.
#[derive(Debug, Clone)]
pub struct Variant {
    /// Short name (`amontons`, `rate`, `rate-state`), also the file stem.
    pub name: String,
    /// The friction table the variant ran with, as TOML.
    pub friction_toml: String,
    /// Its metrics.
    pub metrics: RunMetrics,
    /// Its HDF5 file, relative to the report.
    pub file: PathBuf,
}

/// One row of the report's table, in SI units (`None`: not measured).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Summary {
    /// Peak over steady shear stress.
    pub peak_to_steady: Option<f64>,
    /// Steady shear stress, N/m.
    pub steady_shear_stress_n_per_m: Option<f64>,
    /// Normal stress at the end, N/m.
    pub final_normal_stress_n_per_m: Option<f64>,
    /// Velocity change across the pack, m/s.
    pub velocity_change_m_per_s: Option<f64>,
    /// Shear band's equivalent width, m.
    pub band_equivalent_width_m: Option<f64>,
    /// Shear band's 10-90 width, m.
    pub band_10_90_width_m: Option<f64>,
    /// Slip events.
    pub slip_events: usize,
    /// Median slip of an event, m.
    pub median_event_slip_m: Option<f64>,
    /// Mean fraction of contacts sliding.
    pub mean_sliding_fraction: f64,
    /// Energy dissipated by friction, J.
    pub friction_dissipation_j: Option<f64>,
    /// Whether the pack moved as a plug (the band widths measure noise).
    pub plug_flow: bool,
}

impl Summary {
    /// The row of `m`.
    pub fn of(m: &RunMetrics) -> Self {
        let mut sizes: Vec<f64> = m.slip_events.iter().map(|e| e.slip_m).collect();
        sizes.sort_by(f64::total_cmp);
        Summary {
            peak_to_steady: m.peak_to_steady.map(|p| p.ratio),
            steady_shear_stress_n_per_m: m.peak_to_steady.map(|p| p.steady),
            final_normal_stress_n_per_m: m.normal_stress_n_per_m.last().copied(),
            velocity_change_m_per_s: m.band.map(|b| b.velocity_jump_m_per_s),
            band_equivalent_width_m: m.band.map(|b| b.equivalent_width_m),
            band_10_90_width_m: m.band.map(|b| b.width_10_90_m),
            slip_events: m.slip_events.len(),
            median_event_slip_m: (!sizes.is_empty()).then(|| sizes[sizes.len() / 2]),
            mean_sliding_fraction: m.mean_sliding_fraction(),
            friction_dissipation_j: m.friction_dissipation_j.last().copied(),
            plug_flow: is_plug_flow(m),
        }
    }
}

fn hours(t: &[f64]) -> impl Iterator<Item = f64> + '_ {
    t.iter().map(|t| t / 3600.0)
}

fn lines(variants: &[Variant], pick: impl Fn(&RunMetrics) -> &[f64], scale: f64) -> Vec<Line> {
    variants
        .iter()
        .map(|v| {
            let y = pick(&v.metrics);
            Line::new(
                v.name.clone(),
                hours(&v.metrics.time_s)
                    .zip(y)
                    .map(|(t, y)| (t, y * scale))
                    .collect(),
            )
        })
        .collect()
}

/// Draws `histories.png`, `profile.png` and `slip_events.png` into `dir`.
pub fn figures(dir: &Path, variants: &[Variant]) -> Result<Vec<PathBuf>, Error> {
    let histories = dir.join("histories.png");
    let axes = |title, y| Axes {
        title,
        x: "time (h)",
        y,
    };
    grid(
        &histories,
        2,
        &[
            (
                axes("mean shear stress (xy)", "stress (kN/m)"),
                lines(variants, |m| &m.shear_stress_n_per_m, 1e-3),
            ),
            (
                axes("normal stress across the channel", "compression (kN/m)"),
                lines(variants, |m| &m.normal_stress_n_per_m, 1e-3),
            ),
            (
                axes("kinetic energy", "energy (MJ)"),
                lines(variants, |m| &m.kinetic_energy_j, 1e-6),
            ),
            (
                axes("frictional dissipation (cumulative)", "energy (MJ)"),
                lines(variants, |m| &m.friction_dissipation_j, 1e-6),
            ),
            (
                axes("contacts sliding", "fraction"),
                lines(variants, |m| &m.sliding_fraction, 1.0),
            ),
        ],
    )?;
    let profile = dir.join("profile.png");
    grid(
        &profile,
        1,
        &[(
            Axes {
                title: "along-channel velocity across the channel (late in the run)",
                x: "y (km)",
                y: "u (m/s)",
            },
            variants
                .iter()
                .map(|v| {
                    let p = &v.metrics.profile;
                    Line::markers(
                        v.name.clone(),
                        p.centre_m
                            .iter()
                            .zip(&p.velocity_m_per_s)
                            .map(|(y, u)| (y * 1e-3, *u))
                            .collect(),
                    )
                })
                .collect(),
        )],
    )?;
    let slips = dir.join("slip_events.png");
    grid(
        &slips,
        1,
        &[(
            Axes {
                title: "slip events: size distribution",
                x: "log10(slip during the event / m)",
                y: "events per bin (4 bins per decade)",
            },
            variants
                .iter()
                .map(|v| {
                    let sizes: Vec<f64> = v.metrics.slip_events.iter().map(|e| e.slip_m).collect();
                    Line::markers(
                        v.name.clone(),
                        log_histogram(&sizes, 4)
                            .into_iter()
                            .map(|(lo, hi, n)| (0.5 * (lo.log10() + hi.log10()), n as f64))
                            .collect(),
                    )
                })
                .collect(),
        )],
    )?;
    Ok(vec![histories, profile, slips])
}

/// Below this fraction of the mean speed, the velocity change across the
/// pack is too small for a band width to mean anything.
const PLUG_FRACTION: f64 = 0.05;

fn is_plug_flow(m: &RunMetrics) -> bool {
    let p = &m.profile;
    let total: f64 = p.weight.iter().sum();
    let mean = p
        .velocity_m_per_s
        .iter()
        .zip(&p.weight)
        .map(|(u, w)| u.abs() * w)
        .sum::<f64>()
        / total.max(f64::MIN_POSITIVE);
    m.band
        .is_some_and(|b| b.velocity_jump_m_per_s.abs() < PLUG_FRACTION * mean)
}

fn width(x: f64, plug: bool) -> String {
    if plug {
        format!("{} (plug)", sig(x * 1e-3))
    } else {
        sig(x * 1e-3)
    }
}

fn or_dash(x: Option<f64>, f: impl Fn(f64) -> String) -> String {
    x.map_or("-".into(), f)
}

/// The markdown report.
pub fn markdown(scenario: &Path, variants: &[Variant], notes: &[String]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# floe compare: {}\n", scenario.display());
    let _ = writeln!(
        s,
        "The same ice, forcing and seed under {} friction laws; only the `[friction]` table differs.\n",
        variants.len()
    );
    for n in notes {
        let _ = writeln!(s, "{n}\n");
    }
    let _ = writeln!(
        s,
        "| law | peak / steady shear stress | steady shear stress (kN/m) | final normal stress (kN/m) | velocity change across the pack (m/s) | shear band, equivalent width (km) | shear band, 10-90 width (km) | slip events | median event slip (m) | mean sliding fraction | frictional dissipation (MJ) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|");
    let mut any_plug = false;
    for v in variants {
        let r = Summary::of(&v.metrics);
        let plug = r.plug_flow;
        any_plug |= plug;
        let kilo = |x: Option<f64>| x.map(|x| x * 1e-3);
        let km = |x: f64| width(x, plug);
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            v.name,
            or_dash(r.peak_to_steady, sig),
            or_dash(kilo(r.steady_shear_stress_n_per_m), sig),
            or_dash(kilo(r.final_normal_stress_n_per_m), sig),
            or_dash(r.velocity_change_m_per_s, sig),
            or_dash(r.band_equivalent_width_m, km),
            or_dash(r.band_10_90_width_m, km),
            r.slip_events,
            or_dash(r.median_event_slip_m, sig),
            sig(r.mean_sliding_fraction),
            or_dash(r.friction_dissipation_j.map(|x| x * 1e-6), sig),
        );
    }
    if any_plug {
        let _ = writeln!(
            s,
            "\n(plug) The velocity changes across the pack by less than {:.0} % of its mean: the pack moves nearly as one block (shear is at its edges or walls), and a band width measures noise.",
            PLUG_FRACTION * 100.0
        );
    }
    let _ = writeln!(
        s,
        "\n![histories](histories.png)\n\n![velocity profile](profile.png)\n\n![slip events](slip_events.png)\n"
    );
    let broke = |m: &RunMetrics| match &m.sizes {
        [Some(a), Some(b)] => a.floes != b.floes,
        _ => false,
    };
    if variants.iter().any(|v| broke(&v.metrics)) {
        let _ = writeln!(
            s,
            "## Floe sizes\n\nFree floes and their sizes `d = sqrt(area)` at the first and the last snapshot; the exponent of `N(>d) ~ d^-a` fitted by maximum likelihood between the smallest and the largest size (- where the sizes pile up at the large end).\n\n| law | floes | median size (m) | exponent a at the end |\n|---|---|---|---|"
        );
        for v in variants {
            if let [Some(a), Some(b)] = &v.metrics.sizes {
                let _ = writeln!(
                    s,
                    "| {} | {} -> {} | {} -> {} | {} |",
                    v.name,
                    a.floes,
                    b.floes,
                    sig(a.median_m),
                    sig(b.median_m),
                    or_dash(b.fit.map(|f| f.exponent), |x| format!(
                        "{} +- {}",
                        sig(x),
                        sig(b.fit.map_or(0.0, |f| f.std_error))
                    )),
                );
            }
        }
        let _ = writeln!(s);
    }
    let _ = writeln!(
        s,
        "## Variants\n\nNumbers in the tables below are shown to six significant digits; each variant's scenario file (`NAME.toml`, also stored in its output) holds them exactly.\n"
    );
    for v in variants {
        let _ = writeln!(
            s,
            "### {}\n\nOutput: `{}`; floe speeds at the last snapshot: `{}/`.\n\n```toml\n{}```\n",
            v.name,
            v.file.display(),
            v.name,
            v.friction_toml
        );
    }
    let _ = writeln!(
        s,
        "## Definitions\n\n\
         * Stresses are the assembly's mean stress (Love-Weber, vertically integrated), compression positive; shear is `(σxy + σyx)/2`.\n\
         * Peak / steady: the largest |shear stress| over its mean over time in the last quarter of the run (samples weighted by the time each stands for).\n\
         * Shear band: from the area-weighted profile of along-channel velocity in bins across the channel, pooled over the snapshots of the second half of the run. Equivalent width = velocity jump / peak shear rate (a uniform shear gives the channel width less one bin); 10-90 width = distance over which the velocity goes from 10 % to 90 % of its jump.\n\
         * Slip event: a contact whose slip rate jumps tenfold between snapshots to at least 1 mm/s; it lasts while it slips at 1 mm/s or more; its size is the slip in that time. Only as fine as the snapshot cadence.\n"
    );
    s
}
