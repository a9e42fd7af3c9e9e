//! A scenario: the file read and checked ([`Scenario`]), and what
//! building it makes ([`Setup`]): the floes, walls, contact model, forcing
//! and time step, ready to step.

use std::path::Path;

use floe_dem::contact_model::ContactModel;
use floe_dem::forcing::Forcing;
use floe_dem::fracture::rule::{FractureRule, Fracturing};
use floe_dem::fracture::split::SplitRule;
use floe_dem::load_point::LoadPoint;
use floe_dem::motion_schedule::MotionSchedule;
use floe_dem::periodicity::Periodicity;
use floe_dem::pipeline::integrator::floe_stable_step;
use floe_dem::stress_control::StressControl;
use floe_dem::world::World;
use floe_dem::DemError;

use floe_friction::LawRegistry;

use crate::build;
use crate::checks;
use crate::describe::{
    describe_cohesion, describe_contact, describe_forcing, describe_fracture, describe_ridging,
    describe_thickness, describe_welding,
};
pub use crate::domain::Domain;
use crate::error::ScenarioError;
use crate::gridded_inputs::InputFile;
use crate::numbers::{parameter, sig, thousands};
pub use crate::output_cadence::{OutputCadence, OutputWindow};
use crate::resolve::MAX_RUN_STEPS;
use crate::resolve::{self, FloeSource, Resolved};
use crate::source_file::SourceFile;
use crate::stress_wall::{control_law, stress_gain_limit, MeanFloe};

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
    /// Ids of the floes that are land (`[[land]]`: fixed prescribed
    /// pieces), increasing; a run file marks them so that pictures tell
    /// land from walls.
    pub land_floe_ids: Vec<u64>,
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
    max_steps: f64,
}

impl Scenario {
    /// Reads, parses and checks a scenario file, with the friction laws of
    /// [`LawRegistry::builtin`].
    pub fn load(path: &Path) -> Result<Scenario, ScenarioError> {
        Self::load_with(path, &LawRegistry::builtin())
    }

    /// [`Scenario::load`] with the laws of `registry` (laws defined
    /// outside floe-friction).
    pub fn load_with(path: &Path, registry: &LawRegistry) -> Result<Scenario, ScenarioError> {
        let source = SourceFile::read(path)?;
        let resolved = resolve::resolve(&source, registry, &directory_of(path))?;
        Ok(Scenario {
            source,
            resolved,
            max_steps: MAX_RUN_STEPS,
        })
    }

    /// Parses and checks scenario text; `origin` names it in error messages,
    /// and relative input files (forcing, coastlines) are found from its
    /// directory.
    pub fn from_text(text: &str, origin: &Path) -> Result<Scenario, ScenarioError> {
        Self::from_text_with(text, origin, &LawRegistry::builtin())
    }

    /// [`Scenario::from_text`] with the laws of `registry`.
    pub fn from_text_with(
        text: &str,
        origin: &Path,
        registry: &LawRegistry,
    ) -> Result<Scenario, ScenarioError> {
        Self::from_text_in(text, origin, &directory_of(origin), registry)
    }

    /// [`Scenario::from_text_with`] with relative input files found from
    /// `base_dir` (a scenario stored in a run file, whose `origin` is not a
    /// path).
    pub fn from_text_in(
        text: &str,
        origin: &Path,
        base_dir: &Path,
        registry: &LawRegistry,
    ) -> Result<Scenario, ScenarioError> {
        let source = SourceFile {
            path: origin.to_path_buf(),
            text: text.to_string(),
        };
        let resolved = resolve::resolve(&source, registry, base_dir)?;
        Ok(Scenario {
            source,
            resolved,
            max_steps: MAX_RUN_STEPS,
        })
    }

    /// Raises (or lowers) the most time steps [`Scenario::build`] accepts,
    /// [`MAX_RUN_STEPS`] unless set.
    pub fn with_max_steps(mut self, max_steps: f64) -> Self {
        self.max_steps = max_steps;
        self
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
    pub fn output(&self) -> &OutputCadence {
        &self.resolved.output
    }

    /// The `[[wall.segment]]` schedule of the wall on `side` (`"left"`,
    /// `"right"`, `"bottom"` or `"top"`), checked; `None` without such a
    /// wall or without segments.
    pub fn wall_schedule(&self, side: &str) -> Option<&MotionSchedule> {
        self.resolved
            .walls
            .iter()
            .find(|w| w.side.name() == side)
            .and_then(|w| w.schedule.as_ref())
    }

    /// For a double-shear scenario, the normal load per face (N) and the
    /// set-up's stiffnesses (the loading spring in series with the side
    /// contacts: what a spring-slider of the same test needs).
    pub fn double_shear(&self) -> Option<(f64, checks::DoubleShearGeometry)> {
        let r = &self.resolved;
        let FloeSource::Tessellation(t) = &r.floes else {
            return None;
        };
        let d = t.floes.double_shear()?;
        Some((
            d.normal_load_per_face_n,
            checks::double_shear_geometry(
                &r.model,
                r.thickness.mean_m(),
                d.block_m,
                d.pusher_m,
                d.normal_load_per_face_n,
            ),
        ))
    }

    /// The map projection of `[map]`: the model plane of everything given
    /// in longitude and latitude.
    pub fn map_projection(&self) -> Option<&floe_basin::MapProjection> {
        self.resolved.map.as_ref()
    }

    /// The contact model, friction law included.
    pub fn contact_model(&self) -> &ContactModel {
        &self.resolved.model
    }

    /// The forcing (wind, ocean, Coriolis).
    pub fn forcing(&self) -> &Forcing {
        &self.resolved.forcing
    }

    /// `start_time`: the date of model time 0, as written.
    pub fn start_time(&self) -> Option<&str> {
        self.resolved.start_time.as_deref()
    }

    /// The files the run reads besides the scenario (forcing, coastlines,
    /// ice grids), for the run file's provenance.
    pub fn input_files(&self) -> &[InputFile] {
        &self.resolved.inputs
    }

    /// A forcing failure of the run (a floe off a gridded field's grid,
    /// a slice that cannot be read) located at the key of the field's file
    /// (`scenario.toml:12:8: \`wind.file\`: ...`), or as it is.
    pub fn locate_forcing_failure(&self, message: &str) -> String {
        crate::gridded_inputs::locate_failure(&self.source, &self.resolved.gridded, message)
            .map_or_else(|| message.to_string(), |e| e.to_string())
    }

    /// Builds the world: floes, walls, contact model, forcing, time step.
    /// Refuses (located at the key) a time step above the stable limit, a
    /// run of more than [`Scenario::with_max_steps`] steps,
    /// overlapping explicit floes, walls outside the domain or across a
    /// periodic axis, and set-ups that do not fit.
    pub fn build(&self) -> Result<Setup, ScenarioError> {
        let f = &self.source;
        let r = &self.resolved;
        let built = build::build_floes(f, r)?;
        let (mut dt_s, stable_limit_s, mut dt_line) =
            build::time_step(f, r, &built, self.max_steps)?;
        // An automatic step also carries fracture's smallest pieces.
        if let Some((fraction, cap, piece_m2)) = piece_step_cap(r, &built.floes) {
            if cap < dt_s {
                dt_s = cap;
                dt_line = format!(
                    "{dt_line}; shortened to {} s ({} x the stable step of fracture's smallest piece, a square of {} m^2)",
                    sig(dt_s),
                    sig(fraction),
                    sig(piece_m2)
                );
            }
        }
        // Gridded fields must cover the whole run (its last step's time).
        let steps = ((r.duration_s / dt_s).round()).max(1.0);
        crate::gridded_inputs::check_times_cover_run(f, &r.gridded, steps * dt_s)?;
        let mut report = built.report.clone();
        let land_floe_ids = built.land_ids.clone();
        report.push(format!(
            "  {} free floes, {} prescribed (walls, fixed blocks, land); ice density {} kg/m^3, thickness {}",
            thousands(built.free),
            thousands(built.floes.len() - built.free),
            parameter(r.density_kg_per_m3),
            describe_thickness(r)
        ));
        report.push(dt_line);
        report.extend(build::output_windows(f, r, dt_s, self.max_steps)?);
        report.push(describe_contact(&r.model));
        report.push(describe_forcing(&r.forcing));
        let mut world = World::new(
            built.floes,
            r.model.clone(),
            r.forcing.clone(),
            r.domain.periodicity(),
            dt_s,
        )
        .map_err(|e| match e {
            // A floe off a forcing grid: the files do not fit the ice.
            DemError::Forcing(failure) => {
                crate::gridded_inputs::locate_failure(f, &r.gridded, &failure.0)
                    .unwrap_or_else(|| f.error_in_file(failure.to_string()))
            }
            e => e.into(),
        })?;
        for (id, schedule) in built.schedules {
            world.set_schedule(id, schedule)?;
        }
        if let Some(filter) = r.floe_stress {
            world.set_stress_filter(Some(filter));
        }
        if let Some(fracturing) = self.fracturing(dt_s) {
            self.check_pieces_fit_the_step(&world, &fracturing, dt_s)?;
            world.set_fracturing(Some(fracturing))?;
            report.push(describe_fracture(&fracturing, dt_s));
        }
        if let Some(cohesion) = r.cohesion {
            world.set_cohesion(Some(cohesion))?;
            report.push(describe_cohesion(&cohesion));
            let hibler = r.fracture.is_some_and(|f| {
                matches!(
                    f.criterion,
                    floe_dem::fracture::criteria::FractureCriterion::Hibler(_)
                )
            });
            if hibler && cohesion.tensile_strength_n_per_m > 0.0 {
                report.push(
                    "  note: Hibler's ellipse gives a floe no tensile strength, so a bond that pulls breaks the floes it holds; the Mohr-Coulomb cone's tensile strength is sigma_c / (q - 1)".into(),
                );
            }
        }
        if let Some(ridging) = r.ridging {
            world.set_ridging(Some(ridging))?;
            report.push(describe_ridging(&ridging));
        }
        if let Some(welding) = r.welding {
            world.set_welding(Some(welding))?;
            report.push(describe_welding(&welding));
        }
        if let Some(filter) = world.stress_filter() {
            report.push(format!(
                "  floe stress: each floe's, from its contacts, averaged over {} s",
                sig(filter.time_scale_s)
            ));
        }
        if !built.stress_walls.is_empty() {
            // The same for every wall (the mean free floe's): found once.
            let tuning = (MeanFloe::of(&world), stress_gain_limit(&world, dt_s));
            for w in built.stress_walls {
                let (law, words) = control_law(w.control, tuning, w.length_m, dt_s)
                    .map_err(|why| f.error(w.span.clone(), format!("wall[{}]", w.index), why))?;
                report.push(format!(
                    "wall[{}]: holds a normal stress of {} N/m over {} m; {words}",
                    w.index,
                    sig(w.target_n_per_m),
                    sig(w.length_m),
                ));
                let control = StressControl::new(
                    w.floe_ids,
                    w.inward_normal,
                    w.length_m,
                    w.target_n_per_m,
                    law,
                )?;
                world.add_stress_control(control)?;
            }
        }
        for (id, (k, schedule)) in built.load_points {
            let h = world.floes().handle_of(id).expect("built with the floes");
            let anchor = world.floes().position[h];
            world.set_load_point(LoadPoint::new(id, k, anchor, schedule)?)?;
        }
        report.push(format!(
            "  {} contacts at the start",
            thousands(world.contacts().len())
        ));
        Ok(Setup {
            world,
            report,
            dt_s,
            stable_limit_s,
            land_floe_ids,
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

    /// Ridging as the run applies it (`[ridging]`; `None` without).
    pub fn ridging(&self) -> Option<floe_dem::ridging::Ridging> {
        self.resolved.ridging
    }

    /// Welding as the run applies it (`[welding]`; `None` without).
    pub fn welding(&self) -> Option<floe_dem::welding::Welding> {
        self.resolved.welding
    }

    /// Cohesion as the run applies it (`[cohesion]`; `None` without).
    pub fn cohesion(&self) -> Option<floe_dem::cohesion::Cohesion> {
        self.resolved.cohesion
    }

    /// Fracture as the run applies it at time step `dt_s` (`[fracture]`;
    /// `None` without): the check interval in whole steps (at least one),
    /// the scenario's seed, the domain's area.
    pub fn fracturing(&self, dt_s: f64) -> Option<Fracturing> {
        let r = &self.resolved;
        let s = r.fracture?;
        Some(Fracturing {
            rule: FractureRule {
                criterion: s.criterion,
                check_every_steps: floe_dem::run::cadence::whole_steps(s.check_every_s, dt_s),
                min_floe_area_m2: s.min_floe_area_m2,
                split: SplitRule {
                    pieces: s.pieces,
                    min_piece_area_m2: s.min_piece_area_m2,
                    attempts: s.attempts,
                },
                strength_thickness: s.strength_thickness,
                seed: r.seed,
            },
            domain_area_m2: r.domain.size_m.x * r.domain.size_m.y,
        })
    }

    /// Refuses a smallest piece that the time step cannot carry: a square
    /// piece of `min_piece_area_m2`, as thin as the thinnest free floe,
    /// must be stable at `dt_s`, or nearly every split would be refused.
    fn check_pieces_fit_the_step(
        &self,
        world: &World<Forcing>,
        fracturing: &Fracturing,
        dt_s: f64,
    ) -> Result<(), ScenarioError> {
        let (f, model) = (world.floes(), world.model());
        // The thinnest floe found once: the bisection below asks often.
        let thin = thinnest_free(f);
        let square_step = |area: f64| square_piece_step(thin, model, area);
        let h = thin.map_or(0.0, |(h, _)| h);
        let piece = fracturing.rule.split.min_piece_area_m2;
        if square_step(piece) >= dt_s {
            return Ok(());
        }
        // The smallest square piece the step carries (the limit grows with
        // the size): by bisection on the area.
        let (mut lo, mut hi) = (piece.max(f64::MIN_POSITIVE), piece.max(1.0));
        while square_step(hi) < dt_s && hi < 1e18 {
            hi *= 4.0;
        }
        for _ in 0..100 {
            let mid = (lo * hi).sqrt();
            if square_step(mid) < dt_s {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let src = &self.source;
        let raw = self.resolved.fracture_spans.clone();
        Err(src.error(
            raw.min_piece.unwrap_or(raw.table),
            "fracture.min_piece_area_m2",
            format!(
                "a square piece of {} m^2 ({} m thick) needs a time step of at most {} s, and the run's is {} s: \
                 nearly every split would be refused; give fracture.min_piece_area_m2 >= {} m^2, or a shorter dt_s",
                sig(piece),
                sig(h),
                sig(square_step(piece)),
                sig(dt_s),
                sig(hi * 1.01)
            ),
        ))
    }

    /// The time step [`Scenario::build`] chooses, s: the floes are built to
    /// find the automatic one (deterministically). Only checkpoints of
    /// format 1 and 2, which do not store it, need this.
    pub fn time_step(&self) -> Result<f64, ScenarioError> {
        let f = &self.source;
        let r = &self.resolved;
        let built = build::build_floes(f, r)?;
        let dt_s = build::time_step(f, r, &built, f64::INFINITY)?.0;
        // As the build shortens an automatic step for fracture's pieces.
        Ok(match piece_step_cap(r, &built.floes) {
            Some((_, cap, _)) => dt_s.min(cap),
            None => dt_s,
        })
    }
}

/// For an automatic step (`dt_fraction` or none) with `[fracture]`: the
/// step fracture's smallest piece allows, `fraction x` the stable step of a
/// square piece of `min_piece_area_m2` as thin as the thinnest free floe
/// of `floes`, as `(fraction, step, piece area)`; `None` otherwise.
fn piece_step_cap(
    r: &resolve::Resolved,
    floes: &floe_dem::floes::Floes,
) -> Option<(f64, f64, f64)> {
    let fraction = match r.dt {
        resolve::DtChoice::Auto => resolve::AUTO_DT_FRACTION,
        resolve::DtChoice::Fraction(x, _) => x,
        resolve::DtChoice::Given(..) => return None,
    };
    let piece_m2 = r.fracture?.min_piece_area_m2;
    let step = square_piece_step(thinnest_free(floes), &r.model, piece_m2);
    Some((fraction, fraction * step, piece_m2))
}

/// The thinnest free floe's thickness (m) and its density (kg/m^3).
fn thinnest_free(f: &floe_dem::floes::Floes) -> Option<(f64, f64)> {
    (0..f.len())
        .filter(|&i| f.is_free(i))
        .map(|i| {
            (
                f.thickness_m[i],
                f.mass_kg[i] / (f.area_m2[i] * f.thickness_m[i]),
            )
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
}

/// The stable time step of a square piece of `area_m2` as thin as the
/// thinnest free floe, `thin` ([`thinnest_free`]; infinite without free
/// floes), s.
fn square_piece_step(thin: Option<(f64, f64)>, model: &ContactModel, area_m2: f64) -> f64 {
    let Some((h, density)) = thin else {
        return f64::INFINITY;
    };
    let side = area_m2.sqrt();
    let mass = density * h * area_m2;
    floe_stable_step(
        mass,
        mass * side * side / 6.0,
        h,
        area_m2,
        side / 2f64.sqrt(),
        model,
    )
}

/// The directory of a scenario file, where its relative input paths start.
fn directory_of(path: &Path) -> std::path::PathBuf {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    }
}
