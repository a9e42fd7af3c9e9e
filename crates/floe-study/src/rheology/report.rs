//! `floe rheology`'s outputs: `results.csv`, `report.md`, `rheology.png`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use floe_analysis::rheology::MuOfI;

use super::over_seeds::SeedPoint;
use super::{CellRun, RheologyArgs};
use crate::plot::{panels, Axes, Line};
use floe_run::Error;
use floe_scenario::numbers::{parameter, sig, significant};

/// Writes the three files into `dir`.
pub(super) fn write(
    dir: &Path,
    scenario: &Path,
    args: &RheologyArgs,
    (runs, unconfined): (&[CellRun], &[PathBuf]),
    points: &[SeedPoint],
    fits: &[(String, Option<MuOfI>)],
) -> Result<(), Error> {
    write_csv(&dir.join("results.csv"), runs)?;
    let seeded = runs.iter().any(|r| r.seed.is_some());
    if seeded {
        write_seed_csv(&dir.join("over_seeds.csv"), points)?;
    }
    draw(&dir.join("rheology.png"), runs, points, fits)?;
    let mut md = markdown(scenario, args, runs, points, fits);
    if !unconfined.is_empty() {
        md.push_str(
            "\nNot measured: in these runs fewer than two snapshots of the steady part have \
             the floes touching both walls (the layer lost its confinement; not a dense flow):\n\n",
        );
        for path in unconfined {
            let _ = writeln!(md, "- {}", path.display());
        }
    }
    let path = dir.join("report.md");
    std::fs::write(&path, md).map_err(|e| Error::io(&path, e))
}

fn write_csv(path: &Path, runs: &[CellRun]) -> Result<(), Error> {
    let mut text = String::from(
        "law,speed_m_per_s,seed,samples,inertial_number,mu,mu_error,mu_error_converged,wall_normal_stress_n_per_m,\
         wall_normal_stress_error,bulk_normal_stress_n_per_m,wall_shear_stress_n_per_m,\
         bulk_shear_stress_n_per_m,solid_fraction,solid_fraction_error,shear_rate_per_s,\
         wall_shear_rate_per_s,height_m,unconfined_snapshots,contact_mu,\
         bottom_wall_normal_stress_n_per_m,top_wall_normal_stress_n_per_m\n",
    );
    for r in runs {
        let s = &r.steady;
        let _ = writeln!(
            text,
            "{},{},{},{},{:e},{},{},{},{},{},{},{},{},{},{},{:e},{:e},{},{},{},{},{}",
            r.law,
            r.speed_m_per_s,
            r.seed.map_or(String::new(), |s| s.to_string()),
            s.samples,
            s.inertial_number,
            s.mu.value,
            s.mu.error,
            s.mu_error_converged,
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
            s.wall_normal_stress_bottom_top_n_per_m[0].value,
            s.wall_normal_stress_bottom_top_n_per_m[1].value,
        );
    }
    std::fs::write(path, text).map_err(|e| Error::io(path, e))
}

fn write_seed_csv(path: &Path, points: &[SeedPoint]) -> Result<(), Error> {
    let mut text = String::from(
        "law,speed_m_per_s,runs,inertial_number,inertial_number_ci95,mu,mu_ci95,mu_spread,\
         mean_run_error_of_mu,solid_fraction,solid_fraction_ci95,contact_mu,contact_mu_ci95,\
         mu_less_first_law_paired,mu_less_first_law_paired_ci95\n",
    );
    for p in points {
        let _ = writeln!(
            text,
            "{},{},{},{:e},{:e},{},{},{},{},{},{},{},{},{},{}",
            p.law,
            p.speed_m_per_s,
            p.mu.n,
            p.inertial_number.mean,
            p.inertial_number.ci95,
            p.mu.mean,
            p.mu.ci95,
            p.mu.spread,
            p.mean_run_error_of_mu,
            p.solid_fraction.mean,
            p.solid_fraction.ci95,
            p.contact_mu.mean,
            p.contact_mu.ci95,
            p.mu_less_first_law
                .map_or(String::new(), |d| d.mean.to_string()),
            p.mu_less_first_law
                .map_or(String::new(), |d| d.ci95.to_string()),
        );
    }
    std::fs::write(path, text).map_err(|e| Error::io(path, e))
}

fn draw(
    path: &Path,
    runs: &[CellRun],
    points: &[SeedPoint],
    fits: &[(String, Option<MuOfI>)],
) -> Result<(), Error> {
    if runs.iter().any(|r| r.seed.is_some()) {
        return draw_over_seeds(path, runs, points, fits);
    }
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
            let curve = fit_curve(fit, mine.iter().map(|r| r.steady.inertial_number));
            mu_lines.push(Line::new(format!("{law} fit"), curve).coloured(k));
        }
    }
    mu_and_phi_panels(path, mu_lines, phi_lines)
}

/// `fit` drawn over the span of the inertial numbers `i`, against log10 I.
fn fit_curve(fit: &MuOfI, i: impl Iterator<Item = f64>) -> Vec<(f64, f64)> {
    let (lo, hi) = i.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), i| {
        let x = i.log10();
        (a.min(x), b.max(x))
    });
    (0..=100)
        .map(|k| {
            let x = lo + (hi - lo) * k as f64 / 100.0;
            (x, fit.mu(10f64.powf(x)))
        })
        .collect()
}

/// The report's figure: mu and the solid fraction against log10 I.
fn mu_and_phi_panels(path: &Path, mu_lines: Vec<Line>, phi_lines: Vec<Line>) -> Result<(), Error> {
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

/// mu(I) and the solid fraction with every seed's run as a small marker
/// and the means over seeds with their 95 % intervals as bars.
fn draw_over_seeds(
    path: &Path,
    runs: &[CellRun],
    points: &[SeedPoint],
    fits: &[(String, Option<MuOfI>)],
) -> Result<(), Error> {
    let mut mu_lines = Vec::new();
    let mut phi_lines = Vec::new();
    for (k, (law, fit)) in fits.iter().enumerate() {
        let mine: Vec<&SeedPoint> = points.iter().filter(|p| &p.law == law).collect();
        let each: Vec<&CellRun> = runs.iter().filter(|r| &r.law == law).collect();
        let x = |i: f64| i.log10();
        let run_points = |f: &dyn Fn(&CellRun) -> f64| -> Vec<(f64, f64)> {
            each.iter()
                .map(|r| (x(r.steady.inertial_number), f(r)))
                .collect()
        };
        mu_lines.push(
            Line::markers(format!("{law}: runs"), run_points(&|r| r.steady.mu.value)).coloured(k),
        );
        phi_lines.push(
            Line::markers(
                format!("{law}: runs"),
                run_points(&|r| r.steady.solid_fraction.value),
            )
            .coloured(k),
        );
        let means = |f: &dyn Fn(&SeedPoint) -> (f64, f64)| -> (Vec<(f64, f64)>, Vec<Line>) {
            let centres = mine
                .iter()
                .map(|p| (x(p.inertial_number.mean), f(p).0))
                .collect();
            let bars = mine
                .iter()
                .filter(|p| f(p).1.is_finite())
                .map(|p| {
                    let (m, ci) = f(p);
                    let xi = x(p.inertial_number.mean);
                    Line::new("", vec![(xi, m - ci), (xi, m + ci)]).coloured(k)
                })
                .collect();
            (centres, bars)
        };
        let (centres, bars) = means(&|p| (p.mu.mean, p.mu.ci95));
        mu_lines.push(Line::new(format!("{law}: mean over seeds, 95 % CI"), centres).coloured(k));
        mu_lines.extend(bars);
        let (centres, bars) = means(&|p| (p.solid_fraction.mean, p.solid_fraction.ci95));
        phi_lines.push(Line::new(format!("{law}: mean over seeds, 95 % CI"), centres).coloured(k));
        phi_lines.extend(bars);
        if let Some(fit) = fit {
            let curve = fit_curve(fit, mine.iter().map(|p| p.inertial_number.mean));
            mu_lines.push(Line::new(format!("{law}: fit"), curve).coloured(k));
        }
    }
    mu_and_phi_panels(path, mu_lines, phi_lines)
}

fn markdown(
    scenario: &Path,
    args: &RheologyArgs,
    runs: &[CellRun],
    points: &[SeedPoint],
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
         The contacts' mu is `sum |F_t| / sum F_n` over all contacts (observable `mean_mu`). \
         A run's errors are standard errors from blocking the snapshots' series (they allow \
         for the correlation of successive snapshots); an error marked `*` did not reach \
         its plateau (the steady part is short for its correlation time: a lower bound).\n\n",
        scenario.display(),
        parameter(args.strain),
        sig(args.transient_fraction),
        args.snapshots,
    );
    if runs.iter().any(|r| r.seed.is_some()) {
        md.push_str(
            "## Means over seeds\n\nEach law and speed over its seeds (the tessellation drawn \
             anew): means with their 95 % confidence intervals from the seeds' scatter \
             (Student's t); \"one run's error\" is the mean of the runs' own blocked errors, \
             the uncertainty one seed would have claimed. A seed draws the same floes for \
             every law, so a law's difference from the first law is also given seed by seed \
             (paired: the pairs differ in the law only, and their scatter leaves out the \
             packings').\n\n\
             | law | wall speed (m/s) | seeds | I | mu (wall) | one run's error | mu less the first law's, paired by seed | contacts' mu | solid fraction | P bottom / top (N/m) |\n\
             |---|---|---|---|---|---|---|---|---|---|\n",
        );
        for p in points {
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {:.3} +- {:.3} | {:.3} | {} | {:.3} +- {:.3} | {:.3} +- {:.3} | {:.0} / {:.0} |",
                p.law,
                parameter(p.speed_m_per_s),
                p.mu.n,
                sig(p.inertial_number.mean),
                p.mu.mean,
                p.mu.ci95,
                p.mean_run_error_of_mu,
                p.mu_less_first_law
                    .map_or(String::new(), |d| {
                        format!("{:+.3} +- {:.3} ({} pairs)", d.mean, d.ci95, d.n)
                    }),
                p.contact_mu.mean,
                p.contact_mu.ci95,
                p.solid_fraction.mean,
                p.solid_fraction.ci95,
                p.wall_normal_stress_bottom_top_n_per_m[0].mean,
                p.wall_normal_stress_bottom_top_n_per_m[1].mean,
            );
        }
        md.push_str("\n## Runs\n\n");
    }
    md.push_str(
        "| law | wall speed (m/s) | seed | I | mu (wall) | contacts' mu | P bottom / top / bulk (N/m) | tau wall / bulk (N/m) | solid fraction | shear rate fit / walls (1/s) |\n\
         |---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in runs {
        let s = &r.steady;
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {:.3} +- {:.3}{} | {:.3} | {:.0} / {:.0} / {:.0} | {:.0} / {:.0} | {:.3} +- {:.3} | {} / {} |",
            r.law,
            parameter(r.speed_m_per_s),
            r.seed.map_or("-".to_string(), |s| s.to_string()),
            sig(s.inertial_number),
            s.mu.value,
            s.mu.error,
            if s.mu_error_converged { "" } else { "*" },
            s.contact_mu,
            s.wall_normal_stress_bottom_top_n_per_m[0].value,
            s.wall_normal_stress_bottom_top_n_per_m[1].value,
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
            "\n{} at {} m/s{}: in {} of the steady part's snapshots the floes touched one wall or none (the layer lost its confinement); they are left out.",
            r.law,
            parameter(r.speed_m_per_s),
            r.seed.map_or(String::new(), |s| format!(", seed {s}")),
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
                let _ = writeln!(md, "| {law} | | | | needs four speeds (three parameters) |");
            }
        }
    }
    md.push_str("\n![mu(I) and solid fraction](rheology.png)\n");
    md
}
