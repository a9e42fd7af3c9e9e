//! The wind-pause study of docs/studies/wind-pause.md: scenarios/wind_pause.toml
//! with calms of several lengths, each run under Amontons and rate-and-state
//! friction (`floe compare`), then the shear stress's answer to the restart.
//! The wind's envelope and the top wall's schedule (it slides with the wind,
//! stops in the calm and restarts with it) are rewritten together.
//!
//!     cargo run --release -p floe-study --example wind_pause_study [-- OUT_DIR [slip|aging]]
//!
//! Writes OUT_DIR (default out/studies/wind-pause): one compare directory per
//! pause, `table.md` (the table of the study) and `restart.png`; copy those
//! two into docs/studies/ to update the study. The second argument sets the
//! rate-and-state state law (default: the scenario's, the slip law).

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
/// Calm lengths, s.
const PAUSES_S: [f64; 4] = [900.0, 3600.0, 4.0 * 3600.0, 12.0 * 3600.0];
/// The stress level before the calm and the peak after the restart are
/// taken over windows of this length, s.
const WINDOW_S: f64 = 3600.0;

fn main() {
    if let Err(e) = study() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn study() -> Result<(), CliError> {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "out/studies/wind-pause".into()),
    );
    std::fs::create_dir_all(&out).map_err(|e| CliError::io(&out, e))?;
    let base_path = Path::new("scenarios/wind_pause.toml");
    let mut base = std::fs::read_to_string(base_path).map_err(|e| CliError::io(base_path, e))?;
    if let Some(state_law) = std::env::args().nth(2) {
        let setting = parse_setting(&format!("friction.state_law=\"{state_law}\""))?;
        base = apply(&base, base_path, &[setting], &[0])?;
    }
    let top = find_table(&base, base_path, "wall", "side", "top")?.ok_or_else(|| {
        CliError::from(floe_scenario::ScenarioError::Usage(format!(
            "{}: no top wall to put on the wind's schedule",
            base_path.display()
        )))
    })?;
    let laws = LawChoice::parse_list(
        "amontons,rate-state",
        &floe_friction::LawRegistry::builtin(),
    )?;
    let mut table = String::from(
        "| calm | law | kinetic energy before the calm (% of its peak) | shear stress before the calm (kN/m) | at the end of the calm (kN/m) | peak after restart (kN/m) | peak / before | peak after restart (min) |\n|---|---|---|---|---|---|---|---|\n",
    );
    let mut panels: Vec<Vec<Line>> = vec![Vec::new(); laws.len()];
    let mut energy: Vec<Vec<Line>> = vec![Vec::new(); laws.len()];
    for pause in PAUSES_S {
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
                        amontons_mu: None,
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
            let _ = writeln!(
                table,
                "| {} h | {} | {:.0} | {:.3} | {:.3} | {:.3} | {:.2} | {:.0} |",
                pause / 3600.0,
                law.name(),
                100.0 * ke_late / ke_peak.max(f64::MIN_POSITIVE),
                r.before * 1e-3,
                calm_mean * 1e-3,
                r.peak * 1e-3,
                r.ratio,
                r.peak_delay_s / 60.0
            );
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
