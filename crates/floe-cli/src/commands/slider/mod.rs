//! `floe slider ...`: the spring-slider experiments of Lishman, Sammonds &
//! Feltham (2011), a protocol file's run, and fits to measured series.

pub mod experiments;
pub mod series_csv;

use std::path::PathBuf;

use clap::{Subcommand, ValueEnum};
use floe_friction::experiments::{Preset, MAX_SLIDER_STEPS};
use floe_friction::{Form, StateLaw};

use super::values::{load_point_speed, normal_load, positive, slider_dt, step_count};
use crate::CliError;
use experiments::ExperimentOptions;

/// `floe slider ...`
#[derive(Debug, Subcommand)]
#[allow(missing_docs)] // A variant's help is its Args' doc comment.
pub enum Command {
    #[command(allow_negative_numbers = true)]
    Hold(HoldArgs),
    #[command(allow_negative_numbers = true)]
    Step(StepArgs),
    #[command(allow_negative_numbers = true)]
    Run(RunArgs),
    #[command(allow_negative_numbers = true)]
    Fit(FitArgs),
}

impl Command {
    /// Runs the experiment; returns what to print.
    pub fn run(self) -> Result<String, CliError> {
        match self {
            Command::Hold(args) => args.run(),
            Command::Step(args) => args.run(),
            Command::Run(args) => args.run(),
            Command::Fit(args) => args.run(),
        }
    }
}

/// Slide-hold-slide tests: peak friction on reslide after each hold.
#[derive(Debug, clap::Args)]
pub struct HoldArgs {
    /// Shared options.
    #[command(flatten)]
    pub options: ExperimentArgs,
    /// Hold times in seconds, comma separated.
    #[arg(long, value_delimiter = ',', default_value = "1,10,100,1000", value_parser = positive)]
    pub hold: Vec<f64>,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

impl HoldArgs {
    /// A line per hold time, as a table or JSON.
    pub fn run(self) -> Result<String, CliError> {
        let lines = experiments::hold(&self.options.options(), &self.hold)?;
        if self.json {
            return Ok(json(&lines));
        }
        let mut out = format!(
            "{:>10} {:>10} {:>10} {:>10}\n",
            "hold_s", "mu_ss", "mu_peak", "delta_mu"
        );
        for l in lines {
            out += &format!(
                "{:>10} {:>10.6} {:>10.6} {:>10.6}\n",
                l.hold_s, l.mu_ss, l.mu_peak, l.delta_mu
            );
        }
        Ok(out.trim_end().to_string())
    }
}

/// A velocity step from steady sliding.
#[derive(Debug, clap::Args)]
pub struct StepArgs {
    /// Shared options.
    #[command(flatten)]
    pub options: ExperimentArgs,
    /// Load-point speed before the step, m/s.
    #[arg(long, value_parser = load_point_speed)]
    pub from: f64,
    /// Load-point speed after the step, m/s.
    #[arg(long, value_parser = load_point_speed)]
    pub to: f64,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

impl StepArgs {
    /// Friction before, at the peak and after the step.
    pub fn run(self) -> Result<String, CliError> {
        let r = experiments::step(&self.options.options(), self.from, self.to)?;
        Ok(if self.json {
            json(&r)
        } else {
            format!(
                "mu_ss_before {:.6}\nmu_peak      {:.6}\nmu_ss_after  {:.6}",
                r.mu_ss_before, r.mu_peak, r.mu_ss_after
            )
        })
    }
}

/// Run a load-point protocol file; write series.csv, summary.json, friction.png.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// Protocol file (TOML; see docs/friction.md).
    pub protocol: PathBuf,
    /// Output directory.
    #[arg(long, short)]
    pub out: PathBuf,
    /// Overwrite existing output files.
    #[arg(long)]
    pub force: bool,
    /// Most time steps the protocol may take (default 1e9: about 2 minutes at 110 ns a step).
    #[arg(long, value_name = "N", default_value_t = MAX_SLIDER_STEPS, value_parser = step_count)]
    pub step_limit: f64,
}

impl RunArgs {
    /// Runs the protocol; returns what was written.
    pub fn run(self) -> Result<String, CliError> {
        let s = experiments::run(&self.protocol, &self.out, self.force, self.step_limit)?;
        Ok(format!(
            "{} steps, {} s simulated, {} rows: {}/{{{}}}",
            s.steps,
            s.duration_s,
            s.rows,
            self.out.display(),
            experiments::RUN_FILES.join(",")
        ))
    }
}

/// Fit constant, rate-dependent and rate-and-state models to a measured series.
#[derive(Debug, clap::Args)]
pub struct FitArgs {
    /// CSV with columns t_s (s from the protocol start) and mu.
    pub data: PathBuf,
    /// The protocol the data were measured under.
    #[arg(long)]
    pub protocol: PathBuf,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

impl FitArgs {
    /// The three models' fits, as a table or JSON.
    pub fn run(self) -> Result<String, CliError> {
        let c = experiments::fit(&self.data, &self.protocol)?;
        if self.json {
            return Ok(json(&c));
        }
        let mut out =
            String::from("model        mse          parameters (value +- standard error)\n");
        for m in [&c.constant, &c.rate, &c.rate_state] {
            let params: Vec<String> = m
                .parameters
                .iter()
                .map(|p| {
                    format!(
                        "{} = {:.5e} +- {:.1e} {}",
                        p.name, p.value, p.std_error, p.unit
                    )
                })
                .collect();
            out += &format!("{:<12} {:<12.4e} {}\n", m.model, m.mse, params.join(", "));
        }
        Ok(out.trim_end().to_string())
    }
}

fn json<T: serde::Serialize>(value: &T) -> String {
    serde_json::to_string_pretty(value).expect("plain data serialises")
}

/// Options of `hold` and `step`.
#[derive(Debug, Clone, clap::Args)]
pub struct ExperimentArgs {
    /// Apparatus and parameters: lab (20 MN/m, 0.1 mm/s, L 0.2 mm, N 2 kN) or
    /// tank (2 MN/m, 8 mm/s, L 5 mm, N 10 kN).
    #[arg(long, value_enum)]
    pub preset: PresetArg,
    /// Form of the law: published (eq. 4b, as in the paper) or regularized.
    #[arg(long, value_enum, default_value_t = FormArg::Published)]
    pub form: FormArg,
    /// State evolution: slip (eq. 3b) or aging.
    #[arg(long, value_enum, default_value_t = StateLawArg::Slip)]
    pub state_law: StateLawArg,
    /// Effective normal load in newtons (both faces; default: the preset's).
    #[arg(long, value_name = "NEWTONS", value_parser = normal_load)]
    pub normal_load: Option<f64>,
    /// Time step in seconds (default 0.001, as in the paper).
    #[arg(long, value_name = "SECONDS", value_parser = slider_dt)]
    pub dt: Option<f64>,
    /// Most time steps a run may take (default 1e9: about 2 minutes at 110 ns a step).
    #[arg(long, value_name = "N", default_value_t = MAX_SLIDER_STEPS, value_parser = step_count)]
    pub step_limit: f64,
}

/// `--preset`
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum PresetArg {
    /// UCL laboratory.
    Lab,
    /// HSVA ice tank.
    Tank,
}

/// `--form`
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum FormArg {
    /// Eq. 4b.
    Published,
    /// Sign-consistent arcsinh form.
    Regularized,
}

/// `--state-law`
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum StateLawArg {
    /// Ruina slip law.
    Slip,
    /// Dieterich aging law.
    Aging,
}

impl ExperimentArgs {
    fn options(&self) -> ExperimentOptions {
        ExperimentOptions {
            preset: match self.preset {
                PresetArg::Lab => Preset::Lab,
                PresetArg::Tank => Preset::Tank,
            },
            form: match self.form {
                FormArg::Published => Form::Published,
                FormArg::Regularized => Form::Regularized,
            },
            state_law: match self.state_law {
                StateLawArg::Slip => StateLaw::Slip,
                StateLawArg::Aging => StateLaw::Aging,
            },
            normal_load_n: self.normal_load,
            dt_s: self.dt,
            step_limit: self.step_limit,
        }
    }
}
