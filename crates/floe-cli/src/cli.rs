//! Command-line grammar (clap) and dispatch.

use std::path::PathBuf;

use clap::{Parser, Subcommand, ValueEnum};
use floe_friction::experiments::Preset;
use floe_friction::{Form, StateLaw};

use floe_friction::LawRegistry;
use floe_scenario::law_variants::{LawChoice, Matching};
use floe_scenario::settings::parse_setting;
use floe_study::cadence::Cadence;
use floe_study::compare::{self, CompareArgs};
use floe_study::grid_output::{self, GridArgs};
use floe_study::render::movie::{Encoding, MovieArgs};
use floe_study::render::{self, ColourBy, Snapshots};
use floe_study::rheology::{self, RheologyArgs};
use floe_study::run_file::{self as run, RunArgs};
use floe_study::sweep::{self, SweepArgs};

use crate::hooks::{provenance, TerminalHooks};
use crate::progress_bar::CountProgress;
use crate::slider::{self, ExperimentOptions};
use crate::{info, CliError};
use floe_parallel::Settings;

/// floe: sea-ice floes with rate-and-state friction.
#[derive(Debug, Parser)]
#[command(name = "floe", version, about, propagate_version = true)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Top-level commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Spring-slider experiments of Lishman, Sammonds & Feltham (2011).
    #[command(subcommand)]
    Slider(SliderCommand),
    /// Run a DEM scenario (TOML, see docs/scenarios.md) into an HDF5 file
    /// (H5MD layout, see docs/output.md).
    #[command(allow_negative_numbers = true)]
    Run {
        /// Scenario file (omit with --resume).
        #[arg(required_unless_present = "resume")]
        scenario: Option<PathBuf>,
        /// Output HDF5 file (with --resume: the file to continue, given
        /// either way).
        #[arg(long, short, required_unless_present = "resume")]
        output: Option<PathBuf>,
        /// Worker threads (default: the scenario's `threads`, else every core).
        /// Results are bitwise identical for any count.
        #[arg(long)]
        threads: Option<usize>,
        /// Replace an existing output file.
        #[arg(long)]
        force: bool,
        /// Continue the run in FILE (or in --output) from its last
        /// checkpoint: `floe run --resume OUT.h5`.
        #[arg(long, value_name = "FILE", num_args = 0..=1)]
        resume: Option<Option<PathBuf>>,
        /// Take at most this many steps, then write a checkpoint and stop
        /// (continue with --resume; for batch jobs with a time limit).
        #[arg(long, value_name = "STEPS", value_parser = whole_steps)]
        max_steps: Option<u64>,
        /// Most time steps the scenario may take (default 1e9): a run
        /// longer than this is refused before it starts, naming dt_s or
        /// duration_s.
        #[arg(long, value_name = "N", default_value_t = floe_scenario::MAX_RUN_STEPS, value_parser = step_count)]
        step_limit: f64,
        /// No progress bar or progress lines.
        #[arg(long, short)]
        quiet: bool,
        /// Under mpirun: cut the domain anew when the busiest process's
        /// work (floes plus contacts) exceeds the mean by this fraction.
        #[arg(long, value_name = "FRACTION", default_value_t = Settings::default().rebalance_threshold, value_parser = positive_fraction)]
        rebalance_threshold: f64,
        /// Under mpirun: the ghosts' reach beyond contact, as a fraction of
        /// the largest floe's bounding radius; floes migrate when one has
        /// moved half of it.
        #[arg(long, value_name = "FRACTION", default_value_t = Settings::default().skin_fraction, value_parser = positive_fraction)]
        halo_skin: f64,
    },
    /// Describe a run's output file: scenario, snapshots, floes, contacts, observables.
    #[command(allow_negative_numbers = true)]
    Info {
        /// The run's HDF5 file.
        file: PathBuf,
    },
    /// Run one scenario under several friction laws and report the differences.
    #[command(allow_negative_numbers = true)]
    Compare {
        /// Scenario file.
        scenario: PathBuf,
        /// Laws to compare, comma-separated.
        #[arg(long, default_value = "amontons,rate,rate-state")]
        laws: String,
        /// Output directory: LAW.h5, LAW.toml, LAW/ maps, report.md and figures (LAW each law's name).
        #[arg(long, short)]
        output: PathBuf,
        /// Slip speed at which Amontons' mu equals the rate-and-state steady state, m/s.
        #[arg(long, default_value_t = 1e-2, value_name = "M_PER_S", value_parser = load_point_speed)]
        reference_slip_speed: f64,
        /// Give Amontons' mu explicitly instead.
        #[arg(long, value_name = "MU", value_parser = friction_coefficient, conflicts_with = "reference_slip_speed")]
        amontons_mu: Option<f64>,
        /// Worker threads per run.
        #[arg(long)]
        threads: Option<usize>,
        /// Replace existing outputs.
        #[arg(long)]
        force: bool,
        /// No progress bars.
        #[arg(long, short)]
        quiet: bool,
        /// Metric options.
        #[command(flatten)]
        metrics: MetricArgs,
        /// Most time steps each run may take (default 1e9); a longer one is
        /// refused before anything runs.
        #[arg(long, value_name = "N", default_value_t = floe_scenario::MAX_RUN_STEPS, value_parser = step_count)]
        step_limit: f64,
    },
    /// Run a scenario over the cartesian product of --set values and tabulate metrics.
    #[command(allow_negative_numbers = true)]
    Sweep {
        /// Scenario file (omit with --gather).
        #[arg(required_unless_present = "gather")]
        scenario: Option<PathBuf>,
        /// KEY=V1,V2,...: a dotted scenario key and its values (repeat for more keys).
        #[arg(long = "set", value_name = "KEY=VALUES")]
        set: Vec<String>,
        /// Sweep directory.
        #[arg(long, short)]
        output: PathBuf,
        /// Only write one scenario file per variant, the manifest and two
        /// Slurm job-array scripts (array.slurm: a node per variant;
        /// mpi.slurm: an MPI run over several nodes per variant).
        #[arg(long)]
        emit: bool,
        /// Tabulate the outputs already in the sweep directory.
        #[arg(long, conflicts_with_all = ["emit", "set"])]
        gather: bool,
        /// Total thread budget; variants run in parallel.
        #[arg(long)]
        threads: Option<usize>,
        /// Replace existing files.
        #[arg(long)]
        force: bool,
        /// Metric options.
        #[command(flatten)]
        metrics: MetricArgs,
        /// Most time steps each run may take (default 1e9); a longer one is
        /// refused before anything runs.
        #[arg(long, value_name = "N", default_value_t = floe_scenario::MAX_RUN_STEPS, value_parser = step_count)]
        step_limit: f64,
    },
    /// Shear a constant-pressure cell at several wall speeds under several
    /// laws; report mu = tau/P and the solid fraction against the inertial
    /// number, with a fit of mu(I).
    #[command(allow_negative_numbers = true)]
    Rheology {
        /// Shear-cell scenario (periodic along x; bottom wall; top wall
        /// holding normal_stress_n_per_m), e.g. scenarios/shear_cell.toml.
        scenario: PathBuf,
        /// Laws, comma-separated.
        #[arg(long, default_value = "amontons,rate-state")]
        laws: String,
        /// The top wall's speeds along x, m/s, comma-separated.
        #[arg(long, value_delimiter = ',', default_value = "0.005,0.02,0.1,0.5,2")]
        speeds: Vec<f64>,
        /// Shear strain of each run (its duration is strain x domain height / speed).
        #[arg(long, default_value_t = 6.0)]
        strain: f64,
        /// Snapshots per run (the samples measured).
        #[arg(long, default_value_t = 300)]
        snapshots: usize,
        /// Fraction of each run left out of the means (start-up).
        #[arg(long, default_value_t = 1.0 / 3.0)]
        transient: f64,
        /// Output directory: LAW_vSPEED.{toml,h5}, results.csv, report.md, rheology.png.
        #[arg(long, short)]
        output: PathBuf,
        /// Slip speed at which Amontons' mu equals the rate-and-state steady state, m/s.
        #[arg(long, default_value_t = 1e-2, value_name = "M_PER_S", value_parser = load_point_speed)]
        reference_slip_speed: f64,
        /// Give Amontons' mu explicitly instead.
        #[arg(long, value_name = "MU", value_parser = friction_coefficient, conflicts_with = "reference_slip_speed")]
        amontons_mu: Option<f64>,
        /// Total thread budget; runs go side by side, one thread each.
        #[arg(long)]
        threads: Option<usize>,
        /// Replace existing outputs.
        #[arg(long)]
        force: bool,
        /// Only write the runs' scenario files (LAW_vSPEED.toml), for a job array.
        #[arg(long)]
        emit: bool,
        /// Only measure the runs already in the output directory (same flags as the run).
        #[arg(long, conflicts_with = "emit")]
        gather: bool,
        /// Most time steps each run may take (default 1e9).
        #[arg(long, value_name = "N", default_value_t = floe_scenario::MAX_RUN_STEPS, value_parser = step_count)]
        step_limit: f64,
    },
    /// Coarse-grain a run's snapshots onto a regular grid (concentration,
    /// thickness, velocity, stress, strain rates) and write CF NetCDF.
    #[command(allow_negative_numbers = true)]
    Grid {
        /// The run's HDF5 file.
        file: PathBuf,
        /// Output NetCDF file.
        #[arg(long, short)]
        output: PathBuf,
        /// Largest cell size, m: the domain is split into whole cells of at most this.
        #[arg(long, value_name = "M")]
        cell_m: f64,
        /// Grid every K-th snapshot (default: every snapshot).
        #[arg(long, value_name = "K", conflicts_with = "interval_s")]
        every: Option<usize>,
        /// Grid the snapshot nearest to each multiple of T seconds (0, T,
        /// 2T, ...) that has one within T/2.
        #[arg(long, value_name = "T", value_parser = positive)]
        interval_s: Option<f64>,
        /// Replace an existing output.
        #[arg(long)]
        force: bool,
    },
    /// Draw PNG maps of the floes and plots of the observables, or a movie
    /// of the maps; of a gridded-fields file of `floe grid`, maps or a
    /// movie of its fields.
    #[command(allow_negative_numbers = true)]
    Render {
        /// The run's HDF5 file, or gridded fields (NetCDF) of `floe grid`.
        file: PathBuf,
        /// Draw only this snapshot (0-based; negative counts from the end).
        #[arg(long, allow_negative_numbers = true, conflicts_with = "every")]
        snapshot: Option<i64>,
        /// Draw every K-th snapshot (default: the last snapshot only; every
        /// snapshot for a movie).
        #[arg(long, value_name = "K")]
        every: Option<usize>,
        /// What colours the floes.
        #[arg(long, value_enum, default_value_t = Colour::Speed)]
        color: Colour,
        /// Output directory for the pictures.
        #[arg(long, short, required_unless_present = "movie")]
        output: Option<PathBuf>,
        /// Write a movie of the maps instead: OUT.mp4 (needs ffmpeg),
        /// OUT.gif, or OUT (MP4 if ffmpeg is on PATH, else GIF).
        #[arg(long, value_name = "OUT")]
        movie: Option<PathBuf>,
        /// Frames per second of the movie (default 10).
        #[arg(long, requires = "movie", value_parser = frame_rate)]
        fps: Option<f64>,
        /// The field of a gridded-fields file a movie shows (default
        /// concentration).
        #[arg(long, requires = "movie")]
        field: Option<String>,
        /// Replace existing pictures or movie.
        #[arg(long)]
        force: bool,
    },
}

/// `floe compare` / `floe sweep` metric options shared by both.
#[derive(Debug, Clone, clap::Args)]
pub struct MetricArgs {
    /// Bins across the channel for the velocity profile.
    #[arg(long, default_value_t = 25, value_parser = profile_bins)]
    pub profile_bins: usize,
    /// A slip event: the slip rate jumps by at least this factor between snapshots...
    #[arg(long, default_value_t = 10.0, value_parser = above_one)]
    pub slip_jump: f64,
    /// ...to at least this slip rate, m/s.
    #[arg(long, default_value_t = 1e-3, value_parser = positive)]
    pub slip_min_rate: f64,
}

impl MetricArgs {
    fn options(&self) -> floe_study::compare::metrics::MetricOptions {
        floe_study::compare::metrics::MetricOptions {
            profile_bins: self.profile_bins,
            slip: floe_analysis::slip_events::SlipEventRule {
                jump_factor: self.slip_jump,
                min_rate_m_per_s: self.slip_min_rate,
            },
            ..Default::default()
        }
    }
}

/// `floe render --color`
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Colour {
    /// Floe speed, m/s.
    Speed,
    /// Mean rate-and-state theta over the floe's contacts.
    Theta,
    /// Floe pressure from its contact forces, N/m (compression positive).
    Stress,
}

impl From<Colour> for ColourBy {
    fn from(c: Colour) -> Self {
        match c {
            Colour::Speed => ColourBy::Speed,
            Colour::Theta => ColourBy::Theta,
            Colour::Stress => ColourBy::Stress,
        }
    }
}

/// `floe slider ...`
#[derive(Debug, Subcommand)]
pub enum SliderCommand {
    /// Slide-hold-slide tests: peak friction on reslide after each hold.
    #[command(allow_negative_numbers = true)]
    Hold {
        /// Shared options.
        #[command(flatten)]
        options: ExperimentArgs,
        /// Hold times in seconds, comma separated.
        #[arg(long, value_delimiter = ',', default_value = "1,10,100,1000", value_parser = positive)]
        hold: Vec<f64>,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// A velocity step from steady sliding.
    #[command(allow_negative_numbers = true)]
    Step {
        /// Shared options.
        #[command(flatten)]
        options: ExperimentArgs,
        /// Load-point speed before the step, m/s.
        #[arg(long, value_parser = load_point_speed)]
        from: f64,
        /// Load-point speed after the step, m/s.
        #[arg(long, value_parser = load_point_speed)]
        to: f64,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Run a load-point protocol file; write series.csv, summary.json, friction.png.
    #[command(allow_negative_numbers = true)]
    Run {
        /// Protocol file (TOML; see docs/friction.md).
        protocol: PathBuf,
        /// Output directory.
        #[arg(long, short)]
        out: PathBuf,
        /// Overwrite existing output files.
        #[arg(long)]
        force: bool,
        /// Most time steps the protocol may take (default 1e9: about 2 minutes at 110 ns a step).
        #[arg(long, value_name = "N", default_value_t = floe_friction::experiments::MAX_SLIDER_STEPS, value_parser = step_count)]
        step_limit: f64,
    },
    /// Fit constant, rate-dependent and rate-and-state models to a measured series.
    #[command(allow_negative_numbers = true)]
    Fit {
        /// CSV with columns t_s (s from the protocol start) and mu.
        data: PathBuf,
        /// The protocol the data were measured under.
        #[arg(long)]
        protocol: PathBuf,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
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
    #[arg(long, value_name = "N", default_value_t = floe_friction::experiments::MAX_SLIDER_STEPS, value_parser = step_count)]
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

/// A finite number > 0.
fn positive(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if x > 0.0 && x.is_finite() => Ok(x),
        _ => Err(format!("expected a finite number > 0, got `{text}`")),
    }
}

/// A number in `(min, max]` (`[min, max]` when `closed`), for a flag
/// whose accepted range the message states.
fn bounded(text: &str, min: f64, closed: bool, max: f64, what: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if (x > min || (closed && x == min)) && x <= max => Ok(x),
        _ => Err(format!(
            "expected {what} {} {} and <= {}, got `{text}`",
            if closed { ">=" } else { ">" },
            floe_scenario::numbers::short(min),
            floe_scenario::numbers::short(max)
        )),
    }
}

/// Frames per second of a movie unless `--fps` says otherwise.
const DEFAULT_FPS: f64 = 10.0;

/// A movie's frame rate.
fn frame_rate(text: &str) -> Result<f64, String> {
    let (min, max) = render::movie::FPS_RANGE;
    bounded(text, min, true, max, "frames per second")
}

/// A spring-slider time step, s.
fn slider_dt(text: &str) -> Result<f64, String> {
    let max = floe_friction::experiments::MAX_SLIDER_DT_S;
    bounded(text, 0.0, false, max, "a time step in s")
}

/// A spring-slider normal load, N.
fn normal_load(text: &str) -> Result<f64, String> {
    let (min, max) = floe_friction::experiments::SLIDER_NORMAL_LOAD_RANGE_N;
    bounded(text, min, true, max, "a load in N")
}

/// A load-point speed, m/s.
fn load_point_speed(text: &str) -> Result<f64, String> {
    let max = floe_friction::experiments::MAX_LOAD_POINT_SPEED_M_PER_S;
    bounded(text, 0.0, false, max, "a speed in m/s")
}

/// A friction coefficient: 0 to 10 (sea ice's are below 1).
fn friction_coefficient(text: &str) -> Result<f64, String> {
    bounded(text, 0.0, true, 10.0, "a friction coefficient")
}

/// A finite factor > 1.
fn above_one(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if x > 1.0 && x.is_finite() => Ok(x),
        _ => Err(format!("expected a finite factor > 1, got `{text}`")),
    }
}

/// Bins of the velocity profile: 1 to 10,000.
fn profile_bins(text: &str) -> Result<usize, String> {
    match text.parse::<usize>() {
        Ok(n) if (1..=10_000).contains(&n) => Ok(n),
        _ => Err(format!(
            "expected a whole number from 1 to 10000, got `{text}`"
        )),
    }
}

/// A whole number of steps >= 1.
fn whole_steps(text: &str) -> Result<u64, String> {
    match text.parse::<u64>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!(
            "expected a whole number of steps >= 1, got `{text}`"
        )),
    }
}

/// A step limit: a number >= 1 (1e9 and 1000000000 alike).
fn step_count(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(n) if n >= 1.0 && n.is_finite() => Ok(n),
        _ => Err(format!(
            "expected a number of steps >= 1, e.g. 1e10, got `{text}`"
        )),
    }
}

/// A fraction > 0 (the halo's skin, the rebalance threshold).
fn positive_fraction(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if x > 0.0 && x.is_finite() => Ok(x),
        _ => Err(format!("expected a fraction > 0, e.g. 0.2, got `{text}`")),
    }
}

/// The run's output file and whether it resumes, from `-o FILE` and
/// `--resume [FILE]`: a file given to both must be the same one.
pub fn run_output(
    output: Option<PathBuf>,
    resume: Option<Option<PathBuf>>,
) -> Result<(PathBuf, bool), CliError> {
    match (output, resume) {
        (Some(o), None) => Ok((o, false)),
        (Some(o), Some(None)) | (None, Some(Some(o))) => Ok((o, true)),
        (Some(o), Some(Some(r))) if o == r => Ok((o, true)),
        (Some(o), Some(Some(r))) => Err(floe_study::Error::Usage(format!(
            "--resume {} and --output {} name two files; give the run file once: `floe run --resume {}`",
            r.display(),
            o.display(),
            r.display()
        ))),
        (None, None | Some(None)) => Err(floe_study::Error::Usage(
            "--resume needs the run file: `floe run --resume OUT.h5`".into(),
        )),
    }
}

fn json<T: serde::Serialize>(value: &T) -> String {
    serde_json::to_string_pretty(value).expect("plain data serialises")
}

/// Runs a parsed command; returns what to print on standard output.
pub fn execute(cli: Cli) -> Result<String, CliError> {
    if !matches!(cli.command, Command::Run { .. }) {
        crate::processes::refuse_several()?;
    }
    match cli.command {
        Command::Run {
            scenario,
            output,
            threads,
            force,
            resume,
            max_steps,
            step_limit,
            quiet,
            rebalance_threshold,
            halo_skin,
        } => {
            let (output, resume) = run_output(output, resume)?;
            crate::interrupt::set_run_file(&output);
            let args = RunArgs {
                scenario,
                output,
                threads,
                force,
                resume,
                max_steps,
                step_limit,
                provenance: provenance(),
                laws: LawRegistry::builtin(),
            };
            let hooks = TerminalHooks { progress: !quiet };
            let settings = Settings {
                skin_fraction: halo_skin,
                rebalance_threshold,
            };
            let mpi = crate::processes::start()?;
            #[cfg(feature = "mpi")]
            if let Some(mpi) = &mpi {
                let comm = mpi.world();
                if floe_parallel::Communicator::size(&comm) > 1 {
                    let summary =
                        floe_study::run_parallel::run_parallel(&args, &hooks, &comm, settings)?;
                    return Ok(if floe_parallel::Communicator::rank(&comm) == 0 {
                        summary.describe(&args.output)
                    } else {
                        String::new()
                    });
                }
            }
            let _ = (mpi, settings);
            let summary = run::run(&args, &hooks)?;
            Ok(summary.describe(&args.output))
        }
        Command::Info { file } => info::describe(&file),
        Command::Compare {
            scenario,
            laws,
            output,
            reference_slip_speed,
            amontons_mu,
            threads,
            force,
            quiet,
            metrics,
            step_limit,
        } => {
            let args = CompareArgs {
                scenario,
                laws: LawChoice::parse_list(&laws, &LawRegistry::builtin())?,
                out_dir: output,
                threads,
                force,
                matching: Matching {
                    reference_slip_m_per_s: reference_slip_speed,
                    amontons_mu,
                },
                metrics: metrics.options(),
                provenance: provenance(),
                registry: LawRegistry::builtin(),
                step_limit,
            };
            let report = compare::compare(&args, &TerminalHooks { progress: !quiet })?;
            Ok(format!("report: {}", report.display()))
        }
        Command::Sweep {
            scenario,
            set,
            output,
            emit,
            gather,
            threads,
            force,
            metrics,
            step_limit,
        } => {
            if gather {
                let table = sweep::gather(&output, &metrics.options())?;
                return Ok(format!("results: {}", table.display()));
            }
            let settings = set
                .iter()
                .map(|s| parse_setting(s))
                .collect::<Result<Vec<_>, _>>()?;
            let args = SweepArgs {
                scenario: scenario.expect("clap requires it without --gather"),
                settings,
                out_dir: output,
                threads,
                force,
                emit_only: emit,
                metrics: metrics.options(),
                provenance: provenance(),
                laws: LawRegistry::builtin(),
                step_limit,
            };
            let path = sweep::sweep(&args, &TerminalHooks { progress: false })?;
            Ok(if emit {
                format!("variants written; manifest: {} (run each variant_NNN.toml with `floe run`: sbatch array.slurm, or mpi.slurm for one MPI run per variant; then `floe sweep --gather`)", path.display())
            } else {
                format!("results: {}", path.display())
            })
        }
        Command::Rheology {
            scenario,
            laws,
            speeds,
            strain,
            snapshots,
            transient,
            output,
            reference_slip_speed,
            amontons_mu,
            threads,
            force,
            emit,
            gather,
            step_limit,
        } => {
            let mode = match (emit, gather) {
                (true, _) => rheology::Mode::Emit,
                (_, true) => rheology::Mode::Gather,
                _ => rheology::Mode::Run,
            };
            let args = RheologyArgs {
                scenario,
                laws: LawChoice::parse_list(&laws, &LawRegistry::builtin())?,
                speeds_m_per_s: speeds,
                strain,
                snapshots,
                transient_fraction: transient,
                out_dir: output,
                threads,
                force,
                mode,
                matching: Matching {
                    reference_slip_m_per_s: reference_slip_speed,
                    amontons_mu,
                },
                provenance: provenance(),
                registry: LawRegistry::builtin(),
                step_limit,
            };
            let path = rheology::rheology(&args, &TerminalHooks { progress: false })?;
            Ok(match mode {
                rheology::Mode::Emit => format!(
                    "scenario files written to {}; run each LAW_vSPEED.toml with `floe run ... -o LAW_vSPEED.h5`, then the same command with --gather",
                    path.display()
                ),
                _ => format!("report: {}", path.display()),
            })
        }
        Command::Grid {
            file,
            output,
            cell_m,
            every,
            interval_s,
            force,
        } => {
            let cadence = match (every, interval_s) {
                (Some(k), _) => Cadence::Every(k),
                (None, Some(t)) => Cadence::IntervalS(t),
                (None, None) => Cadence::All,
            };
            let path = grid_output::write_grid(&GridArgs {
                run: file,
                output,
                cell_m,
                cadence,
                force,
            })?;
            Ok(format!("gridded fields: {}", path.display()))
        }
        Command::Render {
            file,
            snapshot,
            every,
            color,
            output,
            movie,
            fps,
            field,
            force,
        } => {
            let which = match (snapshot, every) {
                (Some(k), _) => Snapshots::One(k),
                (None, Some(k)) => Snapshots::Every(k),
                (None, None) if movie.is_some() => Snapshots::Every(1),
                (None, None) => Snapshots::One(-1),
            };
            let grid = render::grid_map::is_grid_file(&file);
            let mut bar = CountProgress::new(if grid && movie.is_none() {
                "maps"
            } else {
                "frames"
            });
            let mut progress = |done, total| bar.update(done, total);
            if movie.is_some() && output.is_some() {
                return Err(CliError::Usage(
                    "render: give -o DIR (pictures) or --movie OUT, not both".into(),
                ));
            }
            if let Some(path) = movie {
                let args = MovieArgs {
                    path,
                    fps: fps.unwrap_or(DEFAULT_FPS),
                    force,
                };
                let written = if grid {
                    let field = field.as_deref().unwrap_or("concentration");
                    render::grid_map::render_grid_movie(&file, which, field, &args, &mut progress)?
                } else {
                    render::render_movie(&file, which, color.into(), &args, &mut progress)?
                };
                return Ok(format!(
                    "movie: {} ({} frames of {} x {} pixels, {})",
                    written.path.display(),
                    written.frames,
                    written.size.0,
                    written.size.1,
                    match written.encoding {
                        Encoding::Mp4 => "H.264 MP4",
                        Encoding::Gif => "GIF",
                    }
                ));
            }
            let Some(output) = output else {
                return Err(CliError::Usage(
                    "render: give -o DIR (pictures) or --movie OUT".into(),
                ));
            };
            let written = if grid {
                render::grid_map::render_grid(&file, which, &output, force, &mut progress)?
            } else {
                render::render_with_progress(
                    &file,
                    which,
                    color.into(),
                    &output,
                    force,
                    &mut progress,
                )?
            };
            Ok(format!(
                "{} pictures in {}",
                written.len(),
                output.display()
            ))
        }
        Command::Slider(SliderCommand::Hold {
            options,
            hold,
            json: as_json,
        }) => {
            let lines = slider::hold(&options.options(), &hold)?;
            if as_json {
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
        Command::Slider(SliderCommand::Step {
            options,
            from,
            to,
            json: as_json,
        }) => {
            let r = slider::step(&options.options(), from, to)?;
            Ok(if as_json {
                json(&r)
            } else {
                format!(
                    "mu_ss_before {:.6}\nmu_peak      {:.6}\nmu_ss_after  {:.6}",
                    r.mu_ss_before, r.mu_peak, r.mu_ss_after
                )
            })
        }
        Command::Slider(SliderCommand::Run {
            protocol,
            out,
            force,
            step_limit,
        }) => {
            let s = slider::run(&protocol, &out, force, step_limit)?;
            Ok(format!(
                "{} steps, {} s simulated, {} rows: {}/{{{}}}",
                s.steps,
                s.duration_s,
                s.rows,
                out.display(),
                slider::RUN_FILES.join(",")
            ))
        }
        Command::Slider(SliderCommand::Fit {
            data,
            protocol,
            json: as_json,
        }) => {
            let c = slider::fit(&data, &protocol)?;
            if as_json {
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
}
