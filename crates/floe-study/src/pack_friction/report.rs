//! `floe pack-friction`'s outputs: `events.csv`, `series.csv`,
//! `report.md`, `pack_friction.png`.

use std::fmt::Write as _;
use std::path::Path;

use floe_analysis::uncertainty::{seed_mean, SeedMean};
use floe_friction::Law;
use floe_run::Error;
use floe_scenario::numbers::{parameter, sig};

use super::events::{EventKind, LawEvents, Measured, Schedule};
use super::PackFrictionArgs;
use crate::plot::{grid, Axes, Line};

/// Writes the four files into `dir`.
pub(super) fn write(
    dir: &Path,
    args: &PackFrictionArgs,
    (schedule, times): (&Schedule, &[f64]),
    contact_law: &Law,
    laws: &[LawEvents],
) -> Result<(), Error> {
    write_events_csv(&dir.join("events.csv"), schedule, laws)?;
    write_series_csv(&dir.join("series.csv"), schedule, times, laws)?;
    draw(&dir.join("pack_friction.png"), schedule, times, laws)?;
    let md = markdown(args, schedule, contact_law, laws);
    let path = dir.join("report.md");
    std::fs::write(&path, md).map_err(|e| Error::io(&path, e))
}

fn write_events_csv(path: &Path, schedule: &Schedule, laws: &[LawEvents]) -> Result<(), Error> {
    let mut text = String::from(
        "law,seed,event,kind,at_s,from_m_per_s,to_m_per_s,hold_s,before,extreme,after,\
         direct_per_ln,steady_per_ln,evolution_per_ln,decay_slip_m,extreme_slip_m,healing\n",
    );
    let events = schedule.events();
    for law in laws {
        let rows = std::iter::once(("mean".to_string(), &law.on_mean))
            .chain(law.per_seed.iter().map(|(seed, m)| (seed.to_string(), m)));
        for (seed, measured) in rows {
            for (k, (event, m)) in events.iter().zip(measured).enumerate() {
                let (kind, from, to, hold) = match event.kind {
                    EventKind::Step { from, to } => ("step", from, to, f64::NAN),
                    EventKind::Hold { hold_s, speed } => ("hold", speed, speed, hold_s),
                };
                let _ = write!(
                    text,
                    "{},{seed},{k},{kind},{},{from},{to},{hold},",
                    law.law, event.at_s
                );
                let _ = match m {
                    Some(Measured::Step(s)) => writeln!(
                        text,
                        "{},{},{},{},{},{},{},{},",
                        s.before,
                        s.extreme,
                        s.after,
                        s.direct_per_ln,
                        s.steady_per_ln,
                        s.evolution_per_ln(),
                        s.decay_slip_m,
                        s.extreme_slip_m
                    ),
                    Some(Measured::Hold(h)) => {
                        writeln!(text, "{},{},,,,,,,{}", h.before, h.peak, h.healing)
                    }
                    None => writeln!(text, ",,,,,,,,"),
                };
            }
        }
    }
    std::fs::write(path, text).map_err(|e| Error::io(path, e))
}

fn write_series_csv(
    path: &Path,
    schedule: &Schedule,
    times: &[f64],
    laws: &[LawEvents],
) -> Result<(), Error> {
    let mut text = String::from("t_s,wall_speed_m_per_s");
    for law in laws {
        let _ = write!(text, ",{0}_mu,{0}_pressure_n_per_m", law.law);
    }
    text.push('\n');
    for (i, &t) in times.iter().enumerate() {
        let _ = write!(text, "{t},{}", schedule.speed_at(t));
        for law in laws {
            let _ = write!(text, ",{},{}", law.mean_mu[i], law.mean_p[i]);
        }
        text.push('\n');
    }
    std::fs::write(path, text).map_err(|e| Error::io(path, e))
}

/// The seeds' values of `f` at event `k` (those measured), over seeds.
fn over_seeds(law: &LawEvents, k: usize, f: impl Fn(&Measured) -> Option<f64>) -> SeedMean {
    let values: Vec<f64> = law
        .per_seed
        .iter()
        .filter_map(|(_, m)| m[k].as_ref().and_then(&f))
        .filter(|v| v.is_finite())
        .collect();
    seed_mean(&values)
}

/// `law`'s value of `f` at event `k` less `first`'s, seed by seed.
fn paired(
    law: &LawEvents,
    first: &LawEvents,
    k: usize,
    f: impl Fn(&Measured) -> Option<f64>,
) -> Option<SeedMean> {
    let values: Vec<f64> = law
        .per_seed
        .iter()
        .filter_map(|(seed, m)| {
            let other = first.per_seed.iter().find(|(s, _)| s == seed)?;
            Some(m[k].as_ref().and_then(&f)? - other.1[k].as_ref().and_then(&f)?)
        })
        .filter(|v| v.is_finite())
        .collect();
    (!values.is_empty()).then(|| seed_mean(&values))
}

fn pm(m: &SeedMean) -> String {
    match m.n {
        0 => "-".into(),
        1 => format!("{:.3} (1)", m.mean),
        n => format!("{:.3} +- {:.3} ({n})", m.mean, m.ci95),
    }
}

fn step_value(
    f: fn(&floe_analysis::step_response::VelocityStep) -> f64,
) -> impl Fn(&Measured) -> Option<f64> {
    move |m| match m {
        Measured::Step(s) => Some(f(s)),
        Measured::Hold(_) => None,
    }
}

fn healing(m: &Measured) -> Option<f64> {
    match m {
        Measured::Hold(h) => Some(h.healing),
        Measured::Step(_) => None,
    }
}

fn markdown(
    args: &PackFrictionArgs,
    schedule: &Schedule,
    contact_law: &Law,
    laws: &[LawEvents],
) -> String {
    let seeds: Vec<String> = args.seeds.iter().map(u64::to_string).collect();
    let mut md = format!(
        "# The pack as a friction sample: {}\n\n\
         The top wall follows its schedule (below) under each law, seeds {}; the pack's \
         friction is `mu = tau / P`, the free floes' mean shear stress over their mean \
         pressure (Love-Weber, the `mean_stress` observable), sampled every {} s. Each event \
         is read as a laboratory reads a velocity step or a slide-hold-slide \
         (floe-analysis `step_response`), slip being the wall's travel since the event: \
         `a` = (extreme - before) / ln(V1/V0), `a - b` = (new steady - before) / ln(V1/V0), \
         `b` their difference, `D` the slip over which friction relaxes from its extreme to \
         the new steady state (least-squares exponential); a hold's healing is the peak of \
         the first half of the reslide over the friction before the hold. \"Curve\" is \
         read from the mean over seeds (`sum tau / sum P`); \"seeds\" is the mean of the \
         seeds' own readings with its 95 % interval (Student's t, number of seeds in \
         brackets): a single run's extreme is biased by its noise, the curve's less so.\n\n",
        args.scenario.display(),
        seeds.join(", "),
        parameter(args.sample_every_s),
    );
    let events = schedule.events();
    md.push_str("Schedule:\n\n| event | at (s) | what |\n|---|---|---|\n");
    for (k, e) in events.iter().enumerate() {
        let what = match e.kind {
            EventKind::Step { from, to } => {
                format!("step {} -> {} m/s", parameter(from), parameter(to))
            }
            EventKind::Hold { hold_s, speed } => {
                format!(
                    "hold {} s, reslide at {} m/s",
                    parameter(hold_s),
                    parameter(speed)
                )
            }
        };
        let _ = writeln!(md, "| {k} | {} | {what} |", parameter(e.at_s));
    }
    if let Law::RateState(r) = contact_law {
        let _ = writeln!(
            md,
            "\nThe contacts' own law (rate-and-state): a = A = {}, a - b = A - B = {}, b = B = {}, \
             D = L = {} m. Amontons contacts have a = b = 0 and no slip distance; the rate law \
             has a = a - b = A - B and b = 0.",
            sig(r.params.a),
            sig(r.params.a - r.params.b),
            sig(r.params.b),
            sig(r.params.critical_slip_m)
        );
    }
    let first = &laws[0];
    md.push_str(
        "\n## Velocity steps\n\n\
         | law | event | step (m/s) | before | a: curve | a: seeds | a - b: curve | a - b: seeds | b: curve | D (m): curve | D (m): seeds | a less the first law's, paired |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for law in laws {
        for (k, e) in events.iter().enumerate() {
            let EventKind::Step { from, to } = e.kind else {
                continue;
            };
            let curve = match &law.on_mean[k] {
                Some(Measured::Step(s)) => format!(
                    "{:.3} | {:.3} | {} | {:.3} | {} | {:.3}",
                    s.before,
                    s.direct_per_ln,
                    pm(&over_seeds(law, k, step_value(|s| s.direct_per_ln))),
                    s.steady_per_ln,
                    pm(&over_seeds(law, k, step_value(|s| s.steady_per_ln))),
                    s.evolution_per_ln()
                ),
                _ => "- | - | - | - | - | -".into(),
            };
            let decay = match &law.on_mean[k] {
                Some(Measured::Step(s)) if s.decay_slip_m.is_finite() => {
                    format!("{:.0}", s.decay_slip_m)
                }
                _ => "-".into(),
            };
            let paired_a = if std::ptr::eq(law, first) {
                String::new()
            } else {
                paired(law, first, k, step_value(|s| s.direct_per_ln))
                    .map_or(String::new(), |m| pm(&m))
            };
            let _ = writeln!(
                md,
                "| {} | {k} | {} -> {} | {curve} | {decay} | {} | {paired_a} |",
                law.law,
                parameter(from),
                parameter(to),
                pm(&over_seeds(law, k, step_value(|s| s.decay_slip_m))),
            );
        }
    }
    md.push_str(
        "\n## Holds\n\n\
         | law | event | hold (s) | before: curve | peak: curve | healing: curve | healing: seeds | healing less the first law's, paired |\n\
         |---|---|---|---|---|---|---|---|\n",
    );
    for law in laws {
        for (k, e) in events.iter().enumerate() {
            let EventKind::Hold { hold_s, .. } = e.kind else {
                continue;
            };
            let curve = match &law.on_mean[k] {
                Some(Measured::Hold(h)) => {
                    format!("{:.3} | {:.3} | {:.3}", h.before, h.peak, h.healing)
                }
                _ => "- | - | -".into(),
            };
            let paired_h = if std::ptr::eq(law, first) {
                String::new()
            } else {
                paired(law, first, k, healing).map_or(String::new(), |m| pm(&m))
            };
            let _ = writeln!(
                md,
                "| {} | {k} | {} | {curve} | {} | {paired_h} |",
                law.law,
                parameter(hold_s),
                pm(&over_seeds(law, k, healing)),
            );
        }
    }
    let missing: usize = laws
        .iter()
        .flat_map(|l| &l.per_seed)
        .map(|(_, m)| m.iter().filter(|x| x.is_none()).count())
        .sum();
    if missing > 0 {
        let _ = writeln!(
            md,
            "\n{missing} event readings of single runs were left out (a window without a finite \
             friction, where no contact carried the layer, or too few samples in it for \
             --sample-every); events.csv has them empty."
        );
    }
    md.push_str("\n![pack friction](pack_friction.png)\n");
    md
}

fn draw(path: &Path, schedule: &Schedule, times: &[f64], laws: &[LawEvents]) -> Result<(), Error> {
    let hours = |t: f64| t / 3600.0;
    let mut mu_lines = Vec::new();
    let mut p_lines = Vec::new();
    for (k, law) in laws.iter().enumerate() {
        let pts = |y: &[f64]| -> Vec<(f64, f64)> {
            times
                .iter()
                .zip(y)
                .filter(|(_, v)| v.is_finite())
                .map(|(&t, &v)| (hours(t), v))
                .collect()
        };
        mu_lines.push(
            Line::new(format!("{}: mean over seeds", law.law), pts(&law.mean_mu)).coloured(k),
        );
        p_lines.push(Line::new(law.law.clone(), pts(&law.mean_p)).coloured(k));
    }
    let speed: Vec<(f64, f64)> = times
        .iter()
        .map(|&t| (hours(t), schedule.speed_at(t)))
        .collect();
    let mut heal_lines = Vec::new();
    let events = schedule.events();
    for (k, law) in laws.iter().enumerate() {
        let mut centres = Vec::new();
        for (j, e) in events.iter().enumerate() {
            let EventKind::Hold { hold_s, .. } = e.kind else {
                continue;
            };
            let m = over_seeds(law, j, healing);
            if m.n == 0 {
                continue;
            }
            let x = hold_s.log10();
            centres.push((x, m.mean));
            if m.ci95.is_finite() {
                heal_lines.push(
                    Line::new("", vec![(x, m.mean - m.ci95), (x, m.mean + m.ci95)]).coloured(k),
                );
            }
        }
        if !centres.is_empty() {
            heal_lines.push(Line::new(format!("{}: seeds, 95 % CI", law.law), centres).coloured(k));
        }
    }
    let mut panels = vec![
        (
            Axes {
                title: "pack friction tau/P",
                x: "time (h)",
                y: "mu",
            },
            mu_lines,
        ),
        (
            Axes {
                title: "mean pressure",
                x: "time (h)",
                y: "P (N/m)",
            },
            p_lines,
        ),
        (
            Axes {
                title: "top wall",
                x: "time (h)",
                y: "speed (m/s)",
            },
            vec![Line::new("schedule", speed)],
        ),
    ];
    if !heal_lines.is_empty() {
        panels.push((
            Axes {
                title: "healing on reslide",
                x: "log10 hold (s)",
                y: "peak - before",
            },
            heal_lines,
        ));
    }
    grid(path, 2, &panels)
}
