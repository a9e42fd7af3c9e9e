//! Scenario files (TOML) for `floe run`: the domain, the floes, the ice,
//! the contact model and friction law, wind, ocean, Coriolis, walls, the
//! time step and the output cadence. Every key is documented in
//! docs/scenarios.md; shipped examples are in `scenarios/`.
//!
//! * `spec`: the file as written (serde, unknown keys refused, every value
//!   with its location);
//! * `resolve`: defaults and single-value checks, with file:line:column;
//! * `checks`: consistency of several values together (walls, overlaps,
//!   the double-shear geometry);
//! * `build`: floe-dem objects (floes, walls as prescribed floes, the
//!   contact model, the forcing) and the time step.
//!
//! Every problem with a file is one [`CliError::Input`] (exit code 2) that
//! names the file, line, column and key; nothing in here panics on input.

mod build;
pub mod checks;
mod resolve;
mod spec;

pub use resolve::{
    AUTO_DT_FRACTION, DEFAULT_ICE_DENSITY_KG_PER_M3, DEFAULT_MIN_AREA_FRACTION, DEFAULT_THICKNESS_M,
};

use std::path::Path;

use floe_dem::contact_model::ContactModel;
use floe_dem::forcing::Forcing;
use floe_dem::periodicity::{Period, Periodicity};
use floe_dem::world::World;
use floe_dem::Vec2;

use crate::error::CliError;
use crate::input::SourceFile;
use resolve::Resolved;

/// The rectangle the run covers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Domain {
    /// Lower-left corner, m.
    pub min_m: Vec2,
    /// Width and height, m.
    pub size_m: Vec2,
    /// Periodic along x, along y.
    pub periodic: [bool; 2],
}

impl Domain {
    /// Area, m^2.
    pub fn area_m2(&self) -> f64 {
        self.size_m.x * self.size_m.y
    }

    /// The engine's periodicity for this domain.
    pub fn periodicity(&self) -> Periodicity {
        let period = |axis: usize| {
            self.periodic[axis].then(|| Period {
                min_m: self.min_m[axis],
                length_m: self.size_m[axis],
            })
        };
        Periodicity {
            x: period(0),
            y: period(1),
        }
    }
}

/// How often a run writes its outputs, in simulated seconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputCadence {
    /// Floe snapshots (default: duration / 100).
    pub snapshot_every_s: f64,
    /// Observables: energies, stress, contact statistics (default: duration / 1000).
    pub observables_every_s: f64,
    /// Checkpoints to resume from (default: duration / 10).
    pub checkpoint_every_s: f64,
}

/// A built scenario, ready to step.
pub struct Setup {
    /// The world at time 0 (contacts detected, forces evaluated).
    pub world: World<Forcing>,
    /// What was built, for the terminal: floes, walls, dropped slivers,
    /// the time step and its stable limit, friction, forcing.
    pub report: Vec<String>,
    /// The time step, s.
    pub dt_s: f64,
    /// The stable limit of the time step, s.
    pub stable_limit_s: f64,
}

/// What [`World::resume`] needs besides the saved state.
#[derive(Debug, Clone)]
pub struct EngineParts {
    /// Contact parameters and friction law.
    pub model: ContactModel,
    /// Wind, ocean, Coriolis.
    pub forcing: Forcing,
    /// Periodic axes.
    pub periodicity: Periodicity,
}

/// A scenario file, read and checked (but not yet built).
#[derive(Debug, Clone)]
pub struct Scenario {
    source: SourceFile,
    resolved: Resolved,
}

impl Scenario {
    /// Reads, parses and checks a scenario file.
    pub fn load(path: &Path) -> Result<Scenario, CliError> {
        let source = SourceFile::read(path)?;
        let resolved = resolve::resolve(&source)?;
        Ok(Scenario { source, resolved })
    }

    /// Parses and checks scenario text; `origin` names it in error messages.
    pub fn from_text(text: &str, origin: &Path) -> Result<Scenario, CliError> {
        let source = SourceFile {
            path: origin.to_path_buf(),
            text: text.to_string(),
        };
        let resolved = resolve::resolve(&source)?;
        Ok(Scenario { source, resolved })
    }

    /// The file, verbatim.
    pub fn text(&self) -> &str {
        &self.source.text
    }

    /// The `title`, if any.
    pub fn title(&self) -> Option<&str> {
        self.resolved.title.as_deref()
    }

    /// Worker threads asked for by the file.
    pub fn threads(&self) -> Option<usize> {
        self.resolved.threads
    }

    /// Simulated time, s.
    pub fn duration_s(&self) -> f64 {
        self.resolved.duration_s
    }

    /// The domain.
    pub fn domain(&self) -> Domain {
        self.resolved.domain
    }

    /// The output cadence.
    pub fn output(&self) -> OutputCadence {
        self.resolved.output
    }

    /// The contact model, friction law included.
    pub fn contact_model(&self) -> &ContactModel {
        &self.resolved.model
    }

    /// The forcing (wind, ocean, Coriolis).
    pub fn forcing(&self) -> &Forcing {
        &self.resolved.forcing
    }

    /// Builds the world: floes, walls, contact model, forcing, time step.
    /// Refuses (located at the key) a time step above the stable limit,
    /// overlapping explicit floes, walls outside the domain or across a
    /// periodic axis, and set-ups that do not fit.
    pub fn build(&self) -> Result<Setup, CliError> {
        let f = &self.source;
        let r = &self.resolved;
        let built = build::build_floes(f, r)?;
        let (dt_s, stable_limit_s, dt_line) = build::time_step(f, r, &built)?;
        let mut report = built.report.clone();
        report.push(format!(
            "  {} free floes, {} prescribed (walls, fixed blocks); ice density {} kg/m^3, thickness {}",
            build::thousands(built.free),
            build::thousands(built.floes.len() - built.free),
            r.density_kg_per_m3,
            describe_thickness(r)
        ));
        report.push(dt_line);
        report.push(describe_contact(&r.model));
        report.push(describe_forcing(&r.forcing));
        let world = World::new(
            built.floes,
            r.model.clone(),
            r.forcing.clone(),
            r.domain.periodicity(),
            dt_s,
        )?;
        report.push(format!(
            "  {} contacts at the start",
            build::thousands(world.contacts().len())
        ));
        Ok(Setup {
            world,
            report,
            dt_s,
            stable_limit_s,
        })
    }

    /// What [`World::resume`] needs besides the checkpoint: the same
    /// model, forcing and periodicity as [`Scenario::build`].
    pub fn engine_parts(&self) -> EngineParts {
        let r = &self.resolved;
        EngineParts {
            model: r.model.clone(),
            forcing: r.forcing.clone(),
            periodicity: r.domain.periodicity(),
        }
    }

    /// The time step [`Scenario::build`] chooses, s: the floes are built to
    /// find the automatic one (deterministically). Only checkpoints of
    /// format 1 and 2, which do not store it, need this.
    pub fn time_step(&self) -> Result<f64, CliError> {
        let f = &self.source;
        let r = &self.resolved;
        let built = build::build_floes(f, r)?;
        Ok(build::time_step(f, r, &built)?.0)
    }
}

fn describe_thickness(r: &Resolved) -> String {
    use floe_dem::tessellation::ThicknessDistribution as T;
    match r.thickness {
        T::Uniform { thickness_m } => format!("{thickness_m} m"),
        T::UniformRange { min_m, max_m } => format!("uniform in [{min_m}, {max_m}] m"),
        T::LogNormal { mean_m, std_m } => format!("log-normal, mean {mean_m} m, std {std_m} m"),
    }
}

fn describe_contact(m: &ContactModel) -> String {
    use floe_friction::{Form, Law, StateLaw};
    let law = match &m.law {
        Law::Amontons(a) => format!("Amontons mu = {}", a.mu),
        Law::RateDependent(r) => format!(
            "rate-dependent mu0 = {}, c1 = {}, V* = {} m/s",
            r.mu0, r.c1, r.v_star_m_per_s
        ),
        Law::Custom(_) => format!("custom law `{}`", m.law.name()),
        Law::RateState(rs) => format!(
            "rate-and-state ({} form, {} law) mu0 = {}, A = {}, B = {}, V* = {} m/s, L = {} m",
            match rs.form {
                Form::Published => "published",
                Form::Regularized => "regularized",
            },
            match rs.state_law {
                StateLaw::Slip => "slip",
                StateLaw::Aging => "aging",
            },
            rs.params.mu0,
            rs.params.a,
            rs.params.b,
            rs.params.v_star_m_per_s,
            rs.params.critical_slip_m
        ),
    };
    format!(
        "contacts: E = {} Pa, nu = {}, restitution {}; friction: {law}",
        m.youngs_modulus_pa, m.poisson_ratio, m.restitution
    )
}

fn describe_forcing(fo: &Forcing) -> String {
    use floe_dem::forcing::VelocityField as V;
    let field = |v: &V| match v {
        V::Uniform(u) if *u == Vec2::ZERO => "at rest".to_string(),
        V::Uniform(u) => format!("uniform [{}, {}] m/s", u.x, u.y),
        V::TimeSeries { times_s, .. } => format!("time series of {} samples", times_s.len()),
        V::LinearShear { .. } => "linear shear".to_string(),
        V::Gyre { .. } => "gyre".to_string(),
        V::Scaled { .. } => "scaled by an envelope".to_string(),
    };
    let f = fo.coriolis.parameter_per_s();
    format!(
        "forcing: wind {} (Cd {}), ocean {} (Cd {}), Coriolis {}",
        field(&fo.wind),
        fo.air.drag_coefficient,
        field(&fo.current),
        fo.ocean.drag_coefficient,
        if f == 0.0 {
            "off".to_string()
        } else {
            format!("f = {} /s", build::sig(f))
        }
    )
}
