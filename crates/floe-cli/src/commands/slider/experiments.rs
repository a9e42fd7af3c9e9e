//! `floe slider ...`: the paper's spring-slider experiments.

use floe_scenario::numbers::sig;
use std::path::{Path, PathBuf};

use floe_friction::experiments::{
    hold_test, hold_test_duration_s, velocity_step, velocity_step_duration_s, Preset, PAPER_DT_S,
};
use floe_friction::fit::{compare_models, Experiment, ModelComparison};
use floe_friction::protocol::Protocol;
use floe_friction::spring_slider::{Apparatus, OutputThinning, Sample, SpringSlider};
use floe_friction::{Form, FrictionLaw, Law, LawRegistry, RateDependent, RateState, StateLaw};
use serde::Serialize;

use super::series_csv::{read_fit_data, write_series};
use crate::CliError;
use floe_scenario::protocol_file::{self, SliderSetup};
use floe_study::plot::friction_figure;

/// Options shared by `hold` and `step`.
#[derive(Debug, Clone, Copy)]
pub struct ExperimentOptions {
    /// Laboratory or ice-tank apparatus and parameters.
    pub preset: Preset,
    /// Published or regularised form.
    pub form: Form,
    /// Slip or aging state evolution.
    pub state_law: StateLaw,
    /// Effective normal load override, N.
    pub normal_load_n: Option<f64>,
    /// Time step override, s.
    pub dt_s: Option<f64>,
    /// Most time steps a run may take
    /// ([`floe_friction::experiments::MAX_SLIDER_STEPS`] unless raised).
    pub step_limit: f64,
}

/// Refuses a run of `duration_s` at `dt_s` above `step_limit` steps,
/// naming what made it long.
fn check_steps(
    duration_s: f64,
    options: &ExperimentOptions,
    dt_s: f64,
    what: &str,
) -> Result<(), CliError> {
    let steps = duration_s / dt_s;
    if steps.is_finite() && steps <= options.step_limit {
        return Ok(());
    }
    let dt = match options.dt_s {
        Some(_) => format!("--dt {}", sig(dt_s)),
        None => format!("the default dt {} s", sig(dt_s)),
    };
    // A large load lengthens the reslide (mu N / k of spring to reload).
    let dt = match options.normal_load_n {
        Some(n) => format!("{dt} and --normal-load {}", sig(n)),
        None => dt,
    };
    Err(CliError::Usage(format!(
        "{what} at {dt}: a {} s test is {} time steps, above the limit of {}; \
         a longer --dt, a shorter test, or --step-limit N",
        sig(duration_s),
        sig(steps),
        sig(options.step_limit)
    )))
}

impl ExperimentOptions {
    fn law_and_apparatus(&self) -> Result<(Law, Apparatus), CliError> {
        let apparatus = Apparatus::new(
            self.preset.stiffness_n_per_m(),
            self.normal_load_n.unwrap_or(self.preset.normal_load_n()),
            self.dt_s.unwrap_or(PAPER_DT_S),
        )
        .map_err(|e| CliError::Usage(format!("invalid option: {e}")))?;
        Ok((
            Law::RateState(RateState::new(
                self.preset.params(),
                self.form,
                self.state_law,
            )),
            apparatus,
        ))
    }
}

/// One line of `floe slider hold --json`.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct HoldLine {
    /// Hold time, s.
    pub hold_s: f64,
    /// Steady-state friction before the hold.
    pub mu_ss: f64,
    /// Peak friction on reslide.
    pub mu_peak: f64,
    /// `mu_peak - mu_ss`.
    pub delta_mu: f64,
}

/// Slide-hold-slide tests at the preset's speed, one per hold time.
pub fn hold(options: &ExperimentOptions, holds_s: &[f64]) -> Result<Vec<HoldLine>, CliError> {
    if let Some(bad) = holds_s.iter().find(|h| !(h.is_finite() && **h > 0.0)) {
        return Err(CliError::Usage(format!(
            "--hold: {bad} is not a hold time > 0 s"
        )));
    }
    let (law, apparatus) = options.law_and_apparatus()?;
    let speed = options.preset.speed_m_per_s();
    // The holds run one after another: their total is what is bounded.
    let total: f64 = holds_s
        .iter()
        .map(|&h| hold_test_duration_s(&law, apparatus, speed, h))
        .sum();
    let holds: Vec<String> = holds_s.iter().map(|&h| sig(h)).collect();
    let what = format!("--hold {}", holds.join(","));
    check_steps(total, options, apparatus.dt_s, &what)?;
    Ok(holds_s
        .iter()
        .map(|&h| {
            let r = hold_test(law.clone(), apparatus, options.preset.speed_m_per_s(), h);
            HoldLine {
                hold_s: r.hold_s,
                mu_ss: r.mu_ss,
                mu_peak: r.mu_peak,
                delta_mu: r.delta_mu,
            }
        })
        .collect())
}

/// Output of `floe slider step --json`.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct StepLine {
    /// Steady-state friction at the first speed.
    pub mu_ss_before: f64,
    /// Transient extreme (maximum on a step up, minimum on a step down).
    pub mu_peak: f64,
    /// Friction 40 L after the step.
    pub mu_ss_after: f64,
}

/// A velocity step from `from` to `to` (m/s).
pub fn step(options: &ExperimentOptions, from: f64, to: f64) -> Result<StepLine, CliError> {
    for (name, v) in [("--from", from), ("--to", to)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(CliError::Usage(format!(
                "{name}: {v} is not a speed > 0 m/s"
            )));
        }
    }
    let (law, apparatus) = options.law_and_apparatus()?;
    let duration = velocity_step_duration_s(&law, from, to);
    check_steps(
        duration,
        options,
        apparatus.dt_s,
        &format!("--from {} --to {}", sig(from), sig(to)),
    )?;
    let r = velocity_step(law, apparatus, from, to);
    Ok(StepLine {
        mu_ss_before: r.mu_ss_before,
        mu_peak: r.mu_peak,
        mu_ss_after: r.mu_ss_after,
    })
}

/// Friction statistics of one protocol segment, for `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct SegmentSummary {
    /// Segment index (0-based, file order).
    pub index: usize,
    /// Start time, s.
    pub start_s: f64,
    /// End time, s.
    pub end_s: f64,
    /// Load-point velocity at start and end, m/s.
    pub velocity_m_per_s: [f64; 2],
    /// Friction at the end of the segment.
    pub mu_end: f64,
    /// Highest friction during the segment.
    pub mu_max: f64,
    /// Lowest friction during the segment.
    pub mu_min: f64,
}

/// `summary.json` of `floe slider run`.
#[derive(Debug, Clone, Serialize)]
pub struct RunSummary {
    /// The protocol file.
    pub protocol_file: PathBuf,
    /// floe version that produced the run.
    pub floe_version: &'static str,
    /// The law, with all its parameters.
    pub law: Law,
    /// Spring, normal load and time step.
    pub apparatus: Apparatus,
    /// Slip rate of the initial steady sliding, m/s.
    pub initial_slip_rate_m_per_s: f64,
    /// Steady-state friction at that rate.
    pub mu_initial: f64,
    /// Duration, s.
    pub duration_s: f64,
    /// Time steps taken.
    pub steps: u64,
    /// Rows in series.csv.
    pub rows: usize,
    /// Critical stiffness `N (B - A) / L` for rate-and-state laws, N/m.
    pub critical_stiffness_n_per_m: Option<f64>,
    /// Per-segment friction.
    pub segments: Vec<SegmentSummary>,
}

/// Runs a protocol; returns all recorded samples and the summary.
pub fn simulate(setup: &SliderSetup) -> (Vec<Sample>, RunSummary) {
    let mut slider = SpringSlider::new(
        setup.law.clone(),
        setup.apparatus,
        setup.initial_slip_rate_m_per_s,
    );
    let mu_initial = slider.sample().mu;
    let every = setup.every_s;
    let mut samples = vec![slider.sample()];
    let mut segments = Vec::new();
    let mut steps = 0u64;
    let mut thinning = OutputThinning::new(0.0, every);
    for (index, seg) in setup.protocol.segments().iter().enumerate() {
        let start_s = slider.sample().t_s;
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let single = Protocol::new(vec![*seg]).expect("segments were validated");
        slider.run(&single, |s| {
            steps += 1;
            lo = lo.min(s.mu);
            hi = hi.max(s.mu);
            if thinning.keep(s.t_s) {
                samples.push(*s);
            }
        });
        let end = slider.sample();
        if samples.last().map(|s| s.t_s) != Some(end.t_s) {
            samples.push(end);
        }
        segments.push(SegmentSummary {
            index,
            start_s,
            end_s: end.t_s,
            velocity_m_per_s: [seg.start_velocity_m_per_s, seg.end_velocity_m_per_s],
            mu_end: end.mu,
            mu_max: hi,
            mu_min: lo,
        });
    }
    let critical = setup
        .law
        .critical_stiffness_n_per_m(setup.apparatus.normal_load_n);
    let summary = RunSummary {
        protocol_file: setup.source.path.clone(),
        floe_version: env!("CARGO_PKG_VERSION"),
        law: setup.law.clone(),
        apparatus: setup.apparatus,
        initial_slip_rate_m_per_s: setup.initial_slip_rate_m_per_s,
        mu_initial,
        duration_s: setup.protocol.duration_s(),
        steps,
        rows: samples.len(),
        critical_stiffness_n_per_m: critical,
        segments,
    };
    (samples, summary)
}

/// The files `floe slider run` writes into its output directory.
pub const RUN_FILES: [&str; 3] = ["series.csv", "summary.json", "friction.png"];

/// `floe slider run PROTOCOL --out DIR`: writes series.csv, summary.json and
/// friction.png, refusing to overwrite them unless `force`.
pub fn run(
    protocol_path: &Path,
    out: &Path,
    force: bool,
    step_limit: f64,
) -> Result<RunSummary, CliError> {
    let setup = protocol_file::load_with(protocol_path, &LawRegistry::builtin(), step_limit)?;
    let outputs: Vec<PathBuf> = RUN_FILES.iter().map(|f| out.join(f)).collect();
    floe_run::same_file::refuse_overwriting_input(
        protocol_path,
        "protocol file",
        outputs.iter().map(PathBuf::as_path),
    )?;
    if !force {
        if let Some(existing) = RUN_FILES.iter().map(|f| out.join(f)).find(|p| p.exists()) {
            return Err(CliError::WouldOverwrite(existing));
        }
    }
    std::fs::create_dir_all(out).map_err(|e| CliError::io(out, e))?;
    let (samples, summary) = simulate(&setup);
    write_series(&out.join("series.csv"), &samples)?;
    let json = serde_json::to_string_pretty(&summary).expect("summary serialises");
    let path = out.join("summary.json");
    std::fs::write(&path, json + "\n").map_err(|e| CliError::io(&path, e))?;
    let title = protocol_path
        .file_stem()
        .map_or("spring-slider".into(), |s| s.to_string_lossy().into_owned());
    friction_figure(
        &out.join("friction.png"),
        &format!("{title} ({})", setup.law.name()),
        &samples,
    )?;
    Ok(summary)
}

/// `floe slider fit DATA --protocol PROTOCOL`: the three models of section 5
/// fitted to a measured series. The protocol's law (if rate-and-state) is the
/// starting guess; otherwise Lishman et al. at the protocol's preset scale.
pub fn fit(data_path: &Path, protocol_path: &Path) -> Result<ModelComparison, CliError> {
    let setup = protocol_file::load(protocol_path)?;
    let data = read_fit_data(data_path)?;
    if let Some(&t) = data.t_s().last() {
        let duration = setup.protocol.duration_s();
        if t > duration * (1.0 + 1e-9) {
            return Err(CliError::Scenario(floe_scenario::ScenarioError::Input {
                file: data_path.to_path_buf(),
                line: data.len() + 1,
                column: 1,
                key: Some("t_s".into()),
                message: format!("time {t} s is beyond the end of the protocol ({duration} s)"),
            }));
        }
    }
    let experiment = Experiment::new(
        setup.protocol.clone(),
        setup.apparatus,
        setup.initial_slip_rate_m_per_s,
    )?;
    let template = match setup.law {
        Law::RateState(r) => r,
        _ => RateState::new(Preset::Lab.params(), Form::Published, StateLaw::Slip),
    };
    let p = template.params;
    let rate = RateDependent {
        mu0: p.mu0,
        c1: p.a - p.b,
        v_star_m_per_s: p.v_star_m_per_s,
        v_floor_m_per_s: p.v_star_m_per_s,
    };
    Ok(compare_models(&data, &experiment, &template, &rate)?)
}
