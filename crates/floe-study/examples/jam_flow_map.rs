//! The jam/flow map of docs/studies/jam-flow.md: reads `floe sweep`
//! directories of scenarios/jam_flow.toml and says, for each run, whether
//! the pack jammed (floe_analysis::jam, default rule: over the last 10 % of
//! the run, kinetic energy below 1 % of its peak and the free floes' drift
//! speed below 1 % of the free-drift speed of the channel's mean wind), with
//! the numbers behind it.
//!
//!     cargo run --release -p floe-study --example jam_flow_map -- OUT_DIR SWEEP_DIR...
//!
//! Each SWEEP_DIR's variants.csv gives the top wind speed
//! (`wind.shear.velocity_at_y_max_m_per_s`), the law (`friction.law`,
//! rate-and-state when absent) and L (`friction.critical_slip_m`); the
//! seed is read from each variant's scenario. Writes OUT_DIR/table.md (one
//! row per law, L and wind speed, over the seeds), OUT_DIR/runs.md and
//! OUT_DIR/results.csv (one row per run), OUT_DIR/map.png and
//! OUT_DIR/histories.png (kinetic energy against time, lowest seed).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use floe_analysis::jam::{jam_state, JamRule, JamState};
use floe_analysis::stress::channel_stress;
use floe_io::RunFile;
use floe_run::Error;
use floe_study::plot::{grid, Axes, Line};

/// Free drift without Coriolis, default drag: sqrt(rho_a C_a / (rho_w C_w)).
const FREE_DRIFT_FRACTION: f64 = 0.015_967;
/// Rate-and-state B and V* (Lishman et al. 2011, the scenario's).
const B: f64 = 0.382;
const V_STAR: f64 = 1e-5;

struct Row {
    seed: u64,
    law: String,
    critical_slip_m: Option<f64>,
    top_wind: f64,
    jam: JamState,
    mean_speed: f64,
    drift_speed: f64,
    median_slip: f64,
    state_speed: Option<f64>,
    time_h: Vec<f64>,
    kinetic: Vec<f64>,
    shear_kn: f64,
    normal_kn: f64,
    mean_mu: f64,
    sliding: f64,
}

fn main() {
    if let Err(e) = study() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn usage(msg: String) -> Error {
    Error::Usage(msg)
}

fn mean_from(time: &[f64], value: &[f64], from: f64) -> f64 {
    let v: Vec<f64> = time
        .iter()
        .zip(value)
        .filter(|(t, _)| **t >= from)
        .map(|(_, v)| *v)
        .collect();
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

fn measure(
    path: &Path,
    law: String,
    critical_slip_m: Option<f64>,
    top_wind: f64,
) -> Result<Row, Error> {
    let run = RunFile::open(path)?;
    let status = run.status()?;
    if status != "completed" {
        return Err(usage(format!("{}: {status}", path.display())));
    }
    let series = |name: &str| -> Result<(Vec<f64>, Vec<f64>), Error> {
        let s = run.observable(name)?;
        Ok((s.time_s, s.value))
    };
    let (time, trans) = series("kinetic_translational")?;
    let (_, rot) = series("kinetic_rotational")?;
    let kinetic: Vec<f64> = trans.iter().zip(&rot).map(|(a, b)| a + b).collect();
    let (_, friction) = series("friction_dissipation")?;
    let (_, stress) = series("mean_stress")?;
    let (_, mu) = series("mean_mu")?;
    let (_, sliding) = series("sliding_fraction")?;
    let (shear, normal): (Vec<f64>, Vec<f64>) = stress
        .chunks_exact(4)
        .map(|s| {
            let c = channel_stress([s[0], s[1], s[2], s[3]]);
            (c.shear_n_per_m.abs(), c.normal_n_per_m)
        })
        .unzip();
    let rule = JamRule::default();
    let (t0, t1) = (time[0], time[time.len() - 1]);
    let final_from = t1 - rule.final_fraction * (t1 - t0);
    let quarter_from = t1 - 0.25 * (t1 - t0);

    // The free floes' area-weighted mean speed over the final window's
    // snapshots, and their mean drift speed: displacement between the
    // window's first and last snapshots (nearest image along a periodic
    // axis) over the time between them. Ringing about a stuck state has a
    // speed but no drift.
    let floes = run.static_floes()?;
    let count = run.snapshot_count()?;
    if count > 0 && run.floes_at(count - 1)?.id != floes.id {
        return Err(usage(format!(
            "{}: its floes broke; this map follows floes by their place in a fixed set",
            path.display()
        )));
    }
    let domain = run.metadata()?.domain;
    let mut window = Vec::new();
    for k in 0..run.snapshot_count()? {
        let snap = run.snapshot(k)?;
        if snap.time_s >= final_from {
            window.push(snap);
        }
    }
    let (first, last) = match (window.first(), window.last()) {
        (Some(a), Some(b)) if b.time_s > a.time_s => (a, b),
        _ => {
            return Err(usage(format!(
                "{}: fewer than two snapshots in the final window",
                path.display()
            )))
        }
    };
    let (mut speed, mut drift, mut weight) = (0.0, 0.0, 0.0);
    for i in (0..floes.len()).filter(|&i| !floes.prescribed[i]) {
        let a = floes.area_m2[i];
        for snap in &window {
            let [u, v] = snap.velocity[i];
            speed += a * u.hypot(v) / window.len() as f64;
        }
        let mut d = [0.0; 2];
        for (axis, d) in d.iter_mut().enumerate() {
            *d = last.position[i][axis] - first.position[i][axis];
            if domain.periodic[axis] {
                let p = domain.size_m[axis];
                *d -= p * (*d / p).round();
            }
        }
        drift += a * d[0].hypot(d[1]) / (last.time_s - first.time_s);
        weight += a;
    }
    let (mean_speed, drift_speed) = (speed / weight, drift / weight);

    // The contacts at the end: their median slip rate, and their median
    // state as the slip rate whose steady state it is (rate-and-state only:
    // V* exp(-theta / B), Lishman et al.'s B and V*; low is healed).
    let contacts = run.contacts(run.snapshot_count()? - 1)?;
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
    };
    let median_slip = median(contacts.slip_rate_m_per_s.iter().map(|v| v.abs()).collect());
    let state_speed =
        (law == "rate-state").then(|| V_STAR * (-median(contacts.theta.clone()) / B).exp());
    let reference = FREE_DRIFT_FRACTION * 0.5 * top_wind;
    let jam = jam_state(&time, &kinetic, &friction, drift_speed, reference, &rule)
        .map_err(Error::analysis)?;
    Ok(Row {
        seed: 0,
        law,
        critical_slip_m,
        top_wind,
        jam,
        mean_speed,
        drift_speed,
        median_slip,
        state_speed,
        time_h: time.iter().map(|t| t / 3600.0).collect(),
        kinetic,
        shear_kn: mean_from(&time, &shear, quarter_from) * 1e-3,
        normal_kn: mean_from(&time, &normal, quarter_from) * 1e-3,
        mean_mu: mean_from(&time, &mu, final_from),
        sliding: mean_from(&time, &sliding, final_from),
    })
}

fn read_sweep(dir: &Path, rows: &mut Vec<Row>) -> Result<(), Error> {
    let manifest = dir.join("variants.csv");
    let text = std::fs::read_to_string(&manifest).map_err(|e| Error::io(&manifest, e))?;
    let mut lines = text.lines();
    let header = split_csv(lines.next().unwrap_or_default());
    let col = |name: &str| header.iter().position(|h| h == name);
    let wind = col("wind.shear.velocity_at_y_max_m_per_s")
        .ok_or_else(|| usage(format!("{}: no wind speed column", manifest.display())))?;
    let (law_col, slip_col) = (col("friction.law"), col("friction.critical_slip_m"));
    for line in lines.filter(|l| !l.trim().is_empty()) {
        let cells = split_csv(line);
        let number = |s: &str| -> Result<f64, Error> {
            s.trim()
                .parse()
                .map_err(|_| usage(format!("{}: `{s}` is not a number", manifest.display())))
        };
        let top = cells[wind]
            .trim_matches(['[', ']'])
            .split(',')
            .next()
            .unwrap_or("");
        let top_wind = number(top)?;
        let law = law_col.map_or("rate-state".to_string(), |c| {
            cells[c].trim_matches('"').to_string()
        });
        let critical_slip_m = slip_col.map(|c| number(&cells[c])).transpose()?;
        let toml = dir.join(format!("{}.toml", cells[0]));
        let scenario = std::fs::read_to_string(&toml).map_err(|e| Error::io(&toml, e))?;
        let seed = scenario
            .lines()
            .find_map(|l| l.trim().strip_prefix("seed")?.trim().strip_prefix('='))
            .and_then(|v| v.split('#').next()?.trim().parse().ok())
            .unwrap_or(0);
        let h5 = dir.join(format!("{}.h5", cells[0]));
        eprintln!("{}", h5.display());
        let mut row = measure(&h5, law, critical_slip_m, top_wind)?;
        row.seed = seed;
        rows.push(row);
    }
    Ok(())
}

/// Splits a CSV line written by `floe sweep` (quoted cells hold commas).
fn split_csv(line: &str) -> Vec<String> {
    let (mut out, mut cell, mut quoted) = (Vec::new(), String::new(), false);
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                cell.push('"');
                chars.next();
            }
            '"' => quoted = !quoted,
            ',' if !quoted => out.push(std::mem::take(&mut cell)),
            _ => cell.push(c),
        }
    }
    out.push(cell);
    out
}

/// The runs grouped by law, L and wind speed (over seeds), in the order
/// first met.
fn groups(rows: &[Row]) -> Vec<Vec<&Row>> {
    let mut out: Vec<Vec<&Row>> = Vec::new();
    for r in rows {
        match out
            .iter_mut()
            .find(|g| label(g[0]) == label(r) && g[0].top_wind == r.top_wind)
        {
            Some(g) => g.push(r),
            None => out.push(vec![r]),
        }
    }
    for g in &mut out {
        g.sort_by_key(|r| r.seed);
    }
    out
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

fn mean(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    s / n.max(1) as f64
}

/// The table of the study: one row per law, L and wind speed.
fn summary(rows: &[Row]) -> String {
    let mut t = String::from(
        "| law | L (m) | top wind (m/s) | jammed / seeds | drift / free drift, each seed | KE final / peak, each seed | KE < 1 % of peak since (h), each seed | shear stress (kN/m) | normal stress (kN/m) | mobilised friction | state as a steady slip rate (mm/s) | median contact slip rate (mm/s) | sliding fraction |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for g in groups(rows) {
        let each =
            |f: &dyn Fn(&Row) -> String| g.iter().map(|r| f(r)).collect::<Vec<_>>().join(", ");
        let r0 = g[0];
        let _ = writeln!(
            t,
            "| {} | {} | {} | {} / {} | {} | {} | {} | {:.3} | {:.3} | {:.3} | {} | {:.2e} | {:.3} |",
            r0.law,
            r0.critical_slip_m.map_or("-".into(), |l| format!("{l}")),
            r0.top_wind,
            g.iter().filter(|r| r.jam.jammed).count(),
            g.len(),
            each(&|r| format!("{:.1e}", r.jam.speed_ratio)),
            each(&|r| format!("{:.1e}", r.jam.kinetic_ratio)),
            each(&|r| r.jam.below_since_s.map_or("-".into(), |t| format!("{:.2}", t / 3600.0))),
            mean(g.iter().map(|r| r.shear_kn)),
            mean(g.iter().map(|r| r.normal_kn)),
            mean(g.iter().map(|r| r.mean_mu)),
            r0.state_speed.map_or("-".into(), |_| format!(
                "{:.2e}",
                median(g.iter().filter_map(|r| r.state_speed).collect()) * 1e3
            )),
            median(g.iter().map(|r| r.median_slip).collect()) * 1e3,
            mean(g.iter().map(|r| r.sliding)),
        );
    }
    t
}

fn label(r: &Row) -> String {
    match r.critical_slip_m {
        Some(l) => format!("{}, L = {l} m", r.law),
        None => r.law.clone(),
    }
}

fn study() -> Result<(), Error> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 2 {
        return Err(usage("usage: jam_flow_map OUT_DIR SWEEP_DIR...".into()));
    }
    let out = PathBuf::from(&args[0]);
    std::fs::create_dir_all(&out).map_err(|e| Error::io(&out, e))?;
    let mut rows = Vec::new();
    for dir in &args[1..] {
        read_sweep(Path::new(dir), &mut rows)?;
    }

    let mut table = String::from(
        "| law | L (m) | top wind (m/s) | seed | state | drift speed, final 10 % (mm/s) | / free drift | mean speed (mm/s) | KE final / peak | KE < 1 % of peak since (h) | dissipation rate final / peak | shear stress, last quarter (kN/m) | normal stress (kN/m) | shear / normal | mobilised friction, final 10 % | state as a steady slip rate, end (mm/s) | median slip rate, end (mm/s) | sliding fraction |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut csv = String::from("law,critical_slip_m,top_wind_m_per_s,seed,jammed,drift_speed_m_per_s,mean_speed_m_per_s,speed_ratio,kinetic_ratio,below_since_s,dissipation_rate_ratio,shear_kn_per_m,normal_kn_per_m,mean_mu,state_slip_rate_m_per_s,median_slip_m_per_s,sliding_fraction\n");
    for r in &rows {
        let j = &r.jam;
        let since = j
            .below_since_s
            .map_or("-".into(), |t| format!("{:.2}", t / 3600.0));
        let l = r.critical_slip_m.map_or("-".into(), |l| format!("{l}"));
        let _ = writeln!(
            table,
            "| {} | {l} | {} | {} | {} | {:.3} | {:.2e} | {:.3} | {:.1e} | {since} | {:.1e} | {:.3} | {:.3} | {:.3} | {:.3} | {} | {:.2e} | {:.3} |",
            r.law,
            r.top_wind,
            r.seed,
            if j.jammed { "**jam**" } else { "flow" },
            r.drift_speed * 1e3,
            j.speed_ratio,
            r.mean_speed * 1e3,
            j.kinetic_ratio,
            j.dissipation_rate_ratio,
            r.shear_kn,
            r.normal_kn,
            r.shear_kn / r.normal_kn,
            r.mean_mu,
            r.state_speed.map_or("-".into(), |v| format!("{:.2e}", v * 1e3)),
            r.median_slip * 1e3,
            r.sliding,
        );
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{:e},{:e},{:e},{:e},{},{:e},{},{},{},{},{:e},{}",
            r.law,
            r.critical_slip_m.map_or(String::new(), |l| l.to_string()),
            r.top_wind,
            r.seed,
            j.jammed,
            r.drift_speed,
            r.mean_speed,
            j.speed_ratio,
            j.kinetic_ratio,
            j.below_since_s.map_or(String::new(), |t| t.to_string()),
            j.dissipation_rate_ratio,
            r.shear_kn,
            r.normal_kn,
            r.mean_mu,
            r.state_speed.map_or(String::new(), |v| format!("{v:e}")),
            r.median_slip,
            r.sliding
        );
    }
    let write = |name: &str, text: &str| {
        let p = out.join(name);
        std::fs::write(&p, text).map_err(|e| Error::io(&p, e))
    };
    write("runs.md", &table)?;
    write("table.md", &summary(&rows))?;
    write("results.csv", &csv)?;

    // One line per law and L across the wind speeds.
    let mut labels: Vec<String> = Vec::new();
    for r in &rows {
        if !labels.contains(&label(r)) {
            labels.push(label(r));
        }
    }
    let groups = groups(&rows);
    let lines = |f: &dyn Fn(&Row) -> f64| -> Vec<Line> {
        labels
            .iter()
            .map(|lab| {
                let pts = groups
                    .iter()
                    .filter(|g| &label(g[0]) == lab)
                    .map(|g| {
                        (
                            g[0].top_wind.log10(),
                            median(g.iter().map(|r| f(r)).collect()),
                        )
                    })
                    .collect();
                Line::new(format!("{lab} (median)"), pts)
            })
            .collect()
    };
    let x = "log10 top wind speed (m/s)";
    let row = |r: &Row| labels.iter().position(|l| *l == label(r)).unwrap_or(0) as f64;
    let state = |want: fn(usize, usize) -> bool| -> Vec<(f64, f64)> {
        groups
            .iter()
            .filter(|g| want(g.iter().filter(|r| r.jam.jammed).count(), g.len()))
            .map(|g| (g[0].top_wind.log10(), row(g[0])))
            .collect()
    };
    grid(
        &out.join("map.png"),
        2,
        &[
            (
                Axes {
                    title: "jam or flow (rows: see the study)",
                    x,
                    y: "row",
                },
                vec![
                    Line::markers("jam, every seed", state(|k, n| k == n)),
                    Line::markers("flow, every seed", state(|k, _| k == 0)),
                    Line::markers("some seeds jam", state(|k, n| k > 0 && k < n)),
                ],
            ),
            (
                Axes {
                    title: "drift speed / free drift (jam below -2)",
                    x,
                    y: "log10 ratio",
                },
                lines(&|r| r.jam.speed_ratio.max(1e-9).log10()),
            ),
            (
                Axes {
                    title: "kinetic energy, final / peak (jam below -2)",
                    x,
                    y: "log10 ratio",
                },
                lines(&|r| r.jam.kinetic_ratio.max(1e-12).log10()),
            ),
            (
                Axes {
                    title: "mean |shear stress|, last quarter",
                    x,
                    y: "kN/m",
                },
                lines(&|r| r.shear_kn),
            ),
            (
                Axes {
                    title: "mobilised friction sum |Ft| / sum Fn, final 10 %",
                    x,
                    y: "mu",
                },
                lines(&|r| r.mean_mu),
            ),
        ],
    )?;
    // Kinetic energy histories, one panel per wind speed.
    let mut speeds: Vec<f64> = rows.iter().map(|r| r.top_wind).collect();
    speeds.sort_by(f64::total_cmp);
    speeds.dedup();
    let titles: Vec<String> = speeds
        .iter()
        .map(|u| format!("top wind {u} m/s, first seed"))
        .collect();
    let panels: Vec<(Axes, Vec<Line>)> = speeds
        .iter()
        .zip(&titles)
        .map(|(&u, title)| {
            let first_seed = rows.iter().map(|r| r.seed).min().unwrap_or(0);
            let lines = rows
                .iter()
                .filter(|r| r.top_wind == u && r.seed == first_seed)
                .map(|r| {
                    let pts = r
                        .time_h
                        .iter()
                        .zip(&r.kinetic)
                        .map(|(&t, &k)| (t, k.max(1.0).log10()))
                        .collect();
                    Line::new(label(r), pts)
                })
                .collect();
            (
                Axes {
                    title,
                    x: "time (h)",
                    y: "log10 kinetic energy (J)",
                },
                lines,
            )
        })
        .collect();
    grid(&out.join("histories.png"), 2, &panels)?;
    Ok(())
}
