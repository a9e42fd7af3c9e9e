//! `floe rheology`'s outputs: `results.csv`, `report.md`, `rheology.png`.

use std::fmt::Write as _;
use std::path::Path;

use floe_analysis::rheology::MuOfI;

use super::{CellRun, RheologyArgs};
use crate::plot::{panels, Axes, Line};
use floe_run::Error;
use floe_scenario::numbers::{parameter, sig, significant};

/// Writes the three files into `dir`.
pub(super) fn write(
    dir: &Path,
    scenario: &Path,
    args: &RheologyArgs,
    runs: &[CellRun],
    fits: &[(String, Option<MuOfI>)],
) -> Result<(), Error> {
    write_csv(&dir.join("results.csv"), runs)?;
    draw(&dir.join("rheology.png"), runs, fits)?;
    let md = markdown(scenario, args, runs, fits);
    let path = dir.join("report.md");
    std::fs::write(&path, md).map_err(|e| Error::io(&path, e))
}

fn write_csv(path: &Path, runs: &[CellRun]) -> Result<(), Error> {
    let mut text = String::from(
        "law,speed_m_per_s,samples,inertial_number,mu,mu_error,wall_normal_stress_n_per_m,\
         wall_normal_stress_error,bulk_normal_stress_n_per_m,wall_shear_stress_n_per_m,\
         bulk_shear_stress_n_per_m,solid_fraction,solid_fraction_error,shear_rate_per_s,\
         wall_shear_rate_per_s,height_m,unconfined_snapshots,contact_mu\n",
    );
    for r in runs {
        let s = &r.steady;
        let _ = writeln!(
            text,
            "{},{},{},{:e},{},{},{},{},{},{},{},{},{},{:e},{:e},{},{},{}",
            r.law,
            r.speed_m_per_s,
            s.samples,
            s.inertial_number,
            s.mu.value,
            s.mu.error,
            s.wall_normal_stress_n_per_m.value,
            s.wall_normal_stress_n_per_m.error,
            s.bulk_normal_stress_n_per_m.value,
            s.wall_shear_stress_n_per_m.value,
            s.bulk_shear_stress_n_per_m.value,
            s.solid_fraction.value,
            s.solid_fraction.error,
            s.shear_rate_per_s.value,
            s.wall_shear_rate_per_s.value,
            s.height_m.value,
            s.unconfined,
            s.contact_mu,
        );
    }
    std::fs::write(path, text).map_err(|e| Error::io(path, e))
}

fn draw(path: &Path, runs: &[CellRun], fits: &[(String, Option<MuOfI>)]) -> Result<(), Error> {
    let mut mu_lines = Vec::new();
    let mut phi_lines = Vec::new();
    for (k, (law, fit)) in fits.iter().enumerate() {
        let mine: Vec<&CellRun> = runs.iter().filter(|r| &r.law == law).collect();
        let point = |f: &dyn Fn(&CellRun) -> f64| -> Vec<(f64, f64)> {
            mine.iter()
                .map(|r| (r.steady.inertial_number.log10(), f(r)))
                .collect()
        };
        mu_lines.push(Line::markers(law.clone(), point(&|r| r.steady.mu.value)).coloured(k));
        phi_lines.push(
            Line::markers(law.clone(), point(&|r| r.steady.solid_fraction.value)).coloured(k),
        );
        if let Some(fit) = fit {
            let (lo, hi) = mine
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
                    let x = r.steady.inertial_number.log10();
                    (a.min(x), b.max(x))
                });
            let curve = (0..=100)
                .map(|k| {
                    let x = lo + (hi - lo) * k as f64 / 100.0;
                    (x, fit.mu(10f64.powf(x)))
                })
                .collect();
            mu_lines.push(Line::new(format!("{law} fit"), curve).coloured(k));
        }
    }
    panels(
        path,
        &[
            (
                Axes {
                    title: "friction of the layer, tau/P on the walls",
                    x: "log10 inertial number I",
                    y: "mu",
                },
                mu_lines,
            ),
            (
                Axes {
                    title: "solid fraction (middle half of the layer)",
                    x: "log10 inertial number I",
                    y: "solid fraction",
                },
                phi_lines,
            ),
        ],
    )
}

fn markdown(
    scenario: &Path,
    args: &RheologyArgs,
    runs: &[CellRun],
    fits: &[(String, Option<MuOfI>)],
) -> String {
    let mut md = format!(
        "# Shear-cell rheology: {}\n\nEach run shears the layer to a strain of {} \
         (duration = strain x domain height / wall speed); the means leave out the first {} \
         of its {} snapshots. Stresses are vertically integrated (N/m); `mu = tau/P` on the \
         walls (mean shear stress over mean normal stress); the bulk stresses are the Love-Weber sum of the contacts \
         plus the momentum flux of the fluctuations over the layer, an independent \
         measure of the same stresses. `I = shear rate x floe size x sqrt(areal density / P)`, \
         the shear rate from a linear fit of the floes' velocity across the layer. \
         The contacts' mu is `sum |F_t| / sum F_n` over all contacts (observable `mean_mu`).\n\n",
        scenario.display(),
        parameter(args.strain),
        sig(args.transient_fraction),
        args.snapshots,
    );
    md.push_str(
        "| law | wall speed (m/s) | I | mu (wall) | contacts' mu | P wall / bulk (N/m) | tau wall / bulk (N/m) | solid fraction | shear rate fit / walls (1/s) |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for r in runs {
        let s = &r.steady;
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.3} +- {:.3} | {:.3} | {:.0} / {:.0} | {:.0} / {:.0} | {:.3} +- {:.3} | {} / {} |",
            r.law,
            parameter(r.speed_m_per_s),
            sig(s.inertial_number),
            s.mu.value,
            s.mu.error,
            s.contact_mu,
            s.wall_normal_stress_n_per_m.value,
            s.bulk_normal_stress_n_per_m.value,
            s.wall_shear_stress_n_per_m.value,
            s.bulk_shear_stress_n_per_m.value,
            s.solid_fraction.value,
            s.solid_fraction.error,
            significant(s.shear_rate_per_s.value, 3),
            significant(s.wall_shear_rate_per_s.value, 3),
        );
    }
    for r in runs.iter().filter(|r| r.steady.unconfined > 0) {
        let _ = writeln!(
            md,
            "\n{} at {} m/s: in {} of the steady part's snapshots the floes touched one wall or none (the layer lost its confinement); they are left out.",
            r.law,
            parameter(r.speed_m_per_s),
            r.steady.unconfined
        );
    }
    md.push_str(
        "\n`mu(I) = mu_s + (mu_2 - mu_s) / (I_0 / I + 1)`, least squares:\n\n\
         | law | mu_s | mu_2 | I_0 | rms residual |\n|---|---|---|---|---|\n",
    );
    for (law, fit) in fits {
        match fit {
            Some(f) => {
                let _ = writeln!(
                    md,
                    "| {law} | {:.3} | {:.3} | {}{} | {:.3} |",
                    f.mu_s,
                    f.mu_2,
                    sig(f.i_0),
                    if f.resolved {
                        ""
                    } else {
                        " (at the end of the range searched: no transition in the data)"
                    },
                    f.rms_residual
                );
            }
            None => {
                let _ = writeln!(md, "| {law} | | | | needs three speeds |");
            }
        }
    }
    md.push_str("\n![mu(I) and solid fraction](rheology.png)\n");
    md
}
