//! The wind-pause study of docs/studies/wind-pause.md: scenarios/wind_pause.toml
//! with calms of several lengths, each run under Amontons and rate-and-state
//! friction (`floe compare`), then the shear stress's answer to the restart.
//! The wind's envelope and the top wall's schedule (it slides with the wind,
//! stops in the calm and restarts with it) are rewritten together.
//!
//!     cargo run --release -p floe-study --example wind_pause_study -- \
//!         [OUT_DIR [slip|aging]] [--seed N] [--calms H1,H2,...] [--set KEY=VALUE]...
//!         [--laws L1,L2] [--amontons-mu MU]
//!     cargo run --release -p floe-study --example wind_pause_study -- --gather OUT_DIR...
//!
//! Writes OUT_DIR (default out/studies/wind-pause): one compare directory per
//! pause, `table.md` (the table of the study), `rows.csv` (its numbers) and
//! `restart.png`; copy `table.md` and `restart.png` into docs/studies/ to
//! update the study. The second argument sets the rate-and-state state law
//! (default: the scenario's, the slip law); `--seed` the scenario's seed,
//! `--calms` the calm lengths in hours (default 0.25,1,4,12), `--set` any
//! other key (`contact.youngs_modulus_pa=6e7`), `--laws` the laws (default
//! amontons,rate-state), `--amontons-mu` Amontons' mu instead of the
//! rate-and-state steady state at 1 cm/s. `--gather` reads the
//! `rows.csv` of several such directories (one per seed) and prints, per
//! calm and law, each number's mean over them with its 95 % interval, and
//! the rate-and-state less Amontons difference paired by directory.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use floe_analysis::stress::restart_response;
use floe_analysis::time_mean::time_mean;
use floe_run::run_file::{Provenance, RunHooks};
use floe_run::Error as CliError;
use floe_scenario::law_variants::{LawChoice, Matching};
use floe_scenario::settings::{apply, find_table, parse_setting};
use floe_study::compare::metrics::{measure, MetricOptions};
use floe_study::compare::{compare, CompareArgs};
use floe_study::plot::{grid, Axes, Line};

/// The wind blows for this long before the calm, s.
const BLOW_S: f64 = 10800.0;
/// Ramps down and up, s.
const RAMP_S: f64 = 600.0;
/// Wind after the restart, s.
const AFTER_S: f64 = 10800.0;
/// The top wall's speed along x while the wind blows, m/s.
const WALL_SPEED_M_PER_S: f64 = 0.2;
/// Calm lengths, s (by default).
const PAUSES_S: [f64; 4] = [900.0, 3600.0, 4.0 * 3600.0, 12.0 * 3600.0];
/// The columns of `rows.csv` after calm and law.
const COLUMNS: [&str; 6] = [
    "kinetic energy before the calm (% of its peak)",
    "shear stress before the calm (kN/m)",
    "at the end of the calm (kN/m)",
    "peak after restart (kN/m)",
    "peak / before",
    "peak after restart (min)",
];
/// The stress level before the calm and the peak after the restart are
/// taken over windows of this length, s.
const WINDOW_S: f64 = 3600.0;

fn main() {
    if let Err(e) = study() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

/// What the command line asked for.
struct Options {
    out: PathBuf,
    state_law: Option<String>,
    seed: Option<u64>,
    pauses_s: Vec<f64>,
    settings: Vec<String>,
    laws: String,
    amontons_mu: Option<f64>,
    gather: Option<Vec<PathBuf>>,
}

fn usage(why: String) -> CliError {
    CliError::Usage(format!("wind_pause_study: {why}"))
}

fn options() -> Result<Options, CliError> {
    let mut o = Options {
        out: PathBuf::from("out/studies/wind-pause"),
        state_law: None,
        seed: None,
        pauses_s: PAUSES_S.to_vec(),
        settings: Vec::new(),
        laws: "amontons,rate-state".into(),
        amontons_mu: None,
        gather: None,
    };
    let mut positional = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = |flag: &str| {
            args.next()
                .ok_or_else(|| usage(format!("{flag} needs a value")))
        };
        match a.as_str() {
            "--seed" => {
                let v = value("--seed")?;
                o.seed = Some(
                    v.parse()
                        .map_err(|_| usage(format!("--seed {v}: a whole number")))?,
                );
            }
            "--calms" => {
                let v = value("--calms")?;
                o.pauses_s = v
                    .split(',')
                    .map(|h| match h.trim().parse::<f64>() {
                        Ok(h) if h > 0.0 && h.is_finite() => Ok(h * 3600.0),
                        _ => Err(usage(format!("--calms {v}: hours > 0, comma-separated"))),
                    })
                    .collect::<Result<_, _>>()?;
            }
            "--set" => o.settings.push(value("--set")?),
            "--laws" => o.laws = value("--laws")?,
            "--amontons-mu" => {
                let v = value("--amontons-mu")?;
                o.amontons_mu = match v.parse::<f64>() {
                    Ok(mu) if (0.0..=10.0).contains(&mu) => Some(mu),
                    _ => {
                        return Err(usage(format!(
                            "--amontons-mu {v}: a friction coefficient, 0 to 10"
                        )))
                    }
                };
            }
            "--gather" => o.gather = Some(args.by_ref().map(PathBuf::from).collect()),
            flag if flag.starts_with("--") => return Err(usage(format!("unknown flag {flag}"))),
            _ => positional.push(a),
        }
    }
    let mut positional = positional.into_iter();
    if let Some(out) = positional.next() {
        o.out = PathBuf::from(out);
    }
    o.state_law = positional.next();
    if let Some(extra) = positional.next() {
        return Err(usage(format!("unexpected argument {extra}")));
    }
    Ok(o)
}

fn study() -> Result<(), CliError> {
    let o = options()?;
    if let Some(dirs) = &o.gather {
        return gather(dirs);
    }
    let out = o.out.clone();
    std::fs::create_dir_all(&out).map_err(|e| CliError::io(&out, e))?;
    let base_path = Path::new("scenarios/wind_pause.toml");
    let mut base = std::fs::read_to_string(base_path).map_err(|e| CliError::io(base_path, e))?;
    let mut settings = Vec::new();
    if let Some(state_law) = &o.state_law {
        settings.push(parse_setting(&format!(
            "friction.state_law=\"{state_law}\""
        ))?);
    }
    if let Some(seed) = o.seed {
        settings.push(parse_setting(&format!("seed={seed}"))?);
    }
    for s in &o.settings {
        settings.push(parse_setting(s)?);
    }
    if !settings.is_empty() {
        base = apply(&base, base_path, &settings, &vec![0; settings.len()])?;
    }
    let mut csv = format!("calm_h,law,{}\n", COLUMNS.join(","));
    let top = find_table(&base, base_path, "wall", "side", "top")?.ok_or_else(|| {
        CliError::from(floe_scenario::ScenarioError::Usage(format!(
            "{}: no top wall to put on the wind's schedule",
            base_path.display()
        )))
    })?;
    let laws = LawChoice::parse_list(&o.laws, &floe_friction::LawRegistry::builtin())?;
    let mut table = String::from(
        "| calm | law | kinetic energy before the calm (% of its peak) | shear stress before the calm (kN/m) | at the end of the calm (kN/m) | peak after restart (kN/m) | peak / before | peak after restart (min) |\n|---|---|---|---|---|---|---|---|\n",
    );
    let mut panels: Vec<Vec<Line>> = vec![Vec::new(); laws.len()];
    let mut energy: Vec<Vec<Line>> = vec![Vec::new(); laws.len()];
    for &pause in &o.pauses_s {
        let restart = BLOW_S + RAMP_S + pause;
        let times = format!(
            "{{ times_s = [0.0, {BLOW_S}, {}, {restart}, {}, {}], factors = [1.0, 1.0, 0.0, 0.0, 1.0, 1.0] }}",
            BLOW_S + RAMP_S,
            restart + RAMP_S,
            restart + AFTER_S
        );
        // The top wall on the same envelope: slide, ramp down, hold, ramp up, slide.
        let v = WALL_SPEED_M_PER_S;
        let segments = format!(
            "[{{ duration_s = {BLOW_S}, velocity_m_per_s = [{v}, 0.0] }}, \
             {{ duration_s = {RAMP_S}, velocity_m_per_s = [{v}, 0.0], end_velocity_m_per_s = [0.0, 0.0] }}, \
             {{ duration_s = {pause} }}, \
             {{ duration_s = {RAMP_S}, velocity_m_per_s = [0.0, 0.0], end_velocity_m_per_s = [{v}, 0.0] }}, \
             {{ duration_s = {}, velocity_m_per_s = [{v}, 0.0] }}]",
            AFTER_S - RAMP_S
        );
        let settings = [
            parse_setting(&format!("wind.envelope={times}"))?,
            parse_setting(&format!("wall[{top}].segment={segments}"))?,
            parse_setting(&format!("duration_s={}", restart + AFTER_S))?,
        ];
        let text = apply(&base, base_path, &settings, &[0, 0, 0])?;
        let name = format!("calm_{:.2}h", pause / 3600.0);
        let scenario = out.join(format!("{name}.toml"));
        std::fs::write(&scenario, text).map_err(|e| CliError::io(&scenario, e))?;
        let dir = out.join(&name);
        // Runs already made are measured again, not rerun (delete to rerun).
        if !dir.join("report.md").exists() {
            compare(
                &CompareArgs {
                    scenario,
                    laws: laws.to_vec(),
                    out_dir: dir.clone(),
                    threads: None,
                    force: true,
                    matching: Matching {
                        reference_slip_m_per_s: 1e-2,
                        amontons_mu: o.amontons_mu,
                    },
                    metrics: MetricOptions::default(),
                    provenance: Provenance::of_this_process("unknown"),
                    registry: floe_friction::LawRegistry::builtin(),
                    step_limit: floe_scenario::MAX_RUN_STEPS,
                },
                &Printed,
            )?;
        }
        for (k, law) in laws.iter().enumerate() {
            let m = measure(
                &dir.join(format!("{}.h5", law.name())),
                &MetricOptions::default(),
            )?;
            let r = restart_response(
                &m.time_s,
                &m.shear_stress_n_per_m,
                BLOW_S,
                restart,
                WINDOW_S,
            )
            .map_err(CliError::analysis)?;
            // Mean |stress| over time in the last half of the calm (before the ramp up).
            let magnitude: Vec<f64> = m.shear_stress_n_per_m.iter().map(|s| s.abs()).collect();
            let calm_mean =
                time_mean(&m.time_s, &magnitude, (restart - 0.5 * pause, restart)).unwrap_or(0.0);
            // Does the pack still flow when the wind drops? Mean kinetic
            // energy over the hour before, against its peak in the first blow.
            let blow: Vec<(f64, f64)> = m
                .time_s
                .iter()
                .zip(&m.kinetic_energy_j)
                .filter(|(t, _)| **t <= BLOW_S)
                .map(|(t, e)| (*t, *e))
                .collect();
            let ke_peak = blow.iter().map(|p| p.1).fold(0.0, f64::max);
            let late: Vec<f64> = blow
                .iter()
                .filter(|p| p.0 >= BLOW_S - WINDOW_S)
                .map(|p| p.1)
                .collect();
            let ke_late = late.iter().sum::<f64>() / late.len().max(1) as f64;
            let row = [
                100.0 * ke_late / ke_peak.max(f64::MIN_POSITIVE),
                r.before * 1e-3,
                calm_mean * 1e-3,
                r.peak * 1e-3,
                r.ratio,
                r.peak_delay_s / 60.0,
            ];
            let _ = writeln!(
                table,
                "| {} h | {} | {:.0} | {:.3} | {:.3} | {:.3} | {:.2} | {:.0} |",
                pause / 3600.0,
                law.name(),
                row[0],
                row[1],
                row[2],
                row[3],
                row[4],
                row[5]
            );
            let numbers: Vec<String> = row.iter().map(|x| format!("{x:e}")).collect();
            let label = match (law.is_amontons(), o.amontons_mu) {
                (true, Some(mu)) => format!("amontons mu {mu}"),
                _ => law.name().to_string(),
            };
            let _ = writeln!(csv, "{},{label},{}", pause / 3600.0, numbers.join(","));
            let points = m
                .time_s
                .iter()
                .zip(&m.shear_stress_n_per_m)
                .filter(|(t, _)| **t >= restart - 3600.0 && **t <= restart + 3.0 * 3600.0)
                .map(|(t, s)| ((t - restart) / 3600.0, s.abs() * 1e-3))
                .collect();
            panels[k].push(Line::new(format!("calm {} h", pause / 3600.0), points));
            let points = m
                .time_s
                .iter()
                .zip(&m.kinetic_energy_j)
                .map(|(t, e)| (t / 3600.0, e * 1e-9))
                .collect();
            energy[k].push(Line::new(format!("calm {} h", pause / 3600.0), points));
        }
    }
    let csv_path = out.join("rows.csv");
    std::fs::write(&csv_path, &csv).map_err(|e| CliError::io(&csv_path, e))?;
    let table_path = out.join("table.md");
    std::fs::write(&table_path, &table).map_err(|e| CliError::io(&table_path, e))?;
    let figure = out.join("restart.png");
    let titles = ["Amontons", "rate-and-state"];
    let mut rows: Vec<(Axes, Vec<Line>)> = panels
        .into_iter()
        .zip(titles)
        .map(|(lines, title)| {
            (
                Axes {
                    title,
                    x: "time since the wind restarted (h)",
                    y: "|mean shear stress| (kN/m)",
                },
                lines,
            )
        })
        .collect();
    rows.extend(energy.into_iter().zip(titles).map(|(lines, title)| {
        (
            Axes {
                title,
                x: "time (h)",
                y: "kinetic energy of the free floes (GJ)",
            },
            lines,
        )
    }));
    grid(&figure, 2, &rows)?;
    println!("{table}\n{} and {}", table_path.display(), figure.display());
    Ok(())
}

/// Per calm and law, each column's mean over the directories' `rows.csv`
/// with its 95 % interval, and the rate-and-state less Amontons difference
/// paired by directory (the same seed and settings), as a markdown table.
fn gather(dirs: &[PathBuf]) -> Result<(), CliError> {
    use floe_analysis::uncertainty::seed_mean;
    use std::collections::BTreeMap;
    if dirs.is_empty() {
        return Err(usage(
            "--gather needs the study's output directories".into(),
        ));
    }
    // (calm in hours as text, law) -> per directory, the row.
    let mut rows: BTreeMap<(String, String), Vec<Vec<f64>>> = BTreeMap::new();
    for dir in dirs {
        let path = dir.join("rows.csv");
        let text = std::fs::read_to_string(&path).map_err(|e| CliError::io(&path, e))?;
        for (i, line) in text.lines().enumerate().skip(1) {
            let f: Vec<&str> = line.split(',').collect();
            let numbers: Result<Vec<f64>, _> = f.iter().skip(2).map(|x| x.parse::<f64>()).collect();
            match (f.len() == COLUMNS.len() + 2, numbers) {
                (true, Ok(n)) => rows
                    .entry((f[0].to_string(), f[1].to_string()))
                    .or_default()
                    .push(n),
                _ => {
                    return Err(usage(format!(
                        "{}:{}: not a rows.csv line",
                        path.display(),
                        i + 1
                    )))
                }
            }
        }
    }
    let mut calms: Vec<String> = rows.keys().map(|k| k.0.clone()).collect();
    calms.sort_by(|a, b| {
        a.parse::<f64>()
            .unwrap_or(0.0)
            .total_cmp(&b.parse().unwrap_or(0.0))
    });
    calms.dedup();
    let cell = |values: &[f64]| {
        let m = seed_mean(values);
        format!("{:.3} +- {:.3}", m.mean, m.ci95)
    };
    let mut table = format!(
        "{} directories; mean +- 95 % interval over them.\n\n| calm | law | {} |\n|---|---|{}\n",
        dirs.len(),
        COLUMNS.join(" | "),
        "---|".repeat(COLUMNS.len())
    );
    let mut laws: Vec<String> = rows.keys().map(|k| k.1.clone()).collect();
    laws.sort();
    laws.dedup();
    let paired = |a: &Vec<Vec<f64>>, b: &Vec<Vec<f64>>| -> Vec<String> {
        (0..COLUMNS.len())
            .map(|c| {
                cell(
                    &a.iter()
                        .zip(b)
                        .map(|(x, y)| y[c] - x[c])
                        .collect::<Vec<_>>(),
                )
            })
            .collect()
    };
    for calm in &calms {
        let of = |law: &str| rows.get(&(calm.clone(), law.to_string()));
        for law in &laws {
            if let Some(r) = of(law) {
                let cells: Vec<String> = (0..COLUMNS.len())
                    .map(|c| cell(&r.iter().map(|row| row[c]).collect::<Vec<_>>()))
                    .collect();
                let _ = writeln!(
                    table,
                    "| {calm} h | {law} ({}) | {} |",
                    r.len(),
                    cells.join(" | ")
                );
            }
        }
        // Rate-and-state less each other law, paired by directory order.
        for law in laws.iter().filter(|l| *l != "rate-state") {
            if let (Some(a), Some(b)) = (of(law), of("rate-state")) {
                if a.len() == b.len() {
                    let _ = writeln!(
                        table,
                        "| {calm} h | rate-state less {law}, paired | {} |",
                        paired(a, b).join(" | ")
                    );
                }
            }
        }
    }
    // Each law's longest calm less its shortest, paired by directory: does
    // the restart grow with the calm?
    if let (Some(first), Some(last)) = (calms.first(), calms.last()) {
        for law in &laws {
            let pick = |calm: &String| rows.get(&(calm.clone(), law.clone()));
            if let (Some(a), Some(b), true) = (pick(first), pick(last), first != last) {
                if a.len() == b.len() {
                    let _ = writeln!(
                        table,
                        "| {last} h less {first} h | {law}, paired | {} |",
                        paired(a, b).join(" | ")
                    );
                }
            }
        }
    }
    println!("{table}");
    Ok(())
}

/// The study's runs say what they do on standard error, without progress bars.
struct Printed;

impl RunHooks for Printed {
    fn say(&self, line: &str) {
        eprintln!("{line}");
    }
    fn progress(&self, _: u64, _: u64, _: f64) -> Box<dyn floe_dem::run::Progress> {
        Box::new(floe_dem::run::Silent)
    }
    fn interrupt(&self) -> &std::sync::atomic::AtomicBool {
        static NEVER: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
        &NEVER
    }
}
