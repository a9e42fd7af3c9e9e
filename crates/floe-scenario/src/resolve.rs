//! From the file as written ([`super::spec`]) to checked values with their
//! defaults: every number is range-checked here, with its location, so that
//! building the world ([`super::build`]) only has to check what depends on
//! several values together ([`super::checks`]).

use crate::stress_wall::{resolve_control_keys, ControlKeys};
use std::ops::Not;
use std::ops::Range;
use std::path::Path;

use floe_dem::contact_model::ContactModel;
use floe_dem::forcing::{Coriolis, DragParameters, Envelope, Forcing, VelocityField};
use floe_dem::motion_schedule::MotionSchedule;
use floe_dem::tessellation::{max_jitter_fraction, ThicknessDistribution, MAX_FLOES};
use floe_dem::{DemError, Vec2};
use floe_friction::experiments::Preset;
use floe_friction::{Form, LawContext, LawRegistry};
use toml::Spanned;

use crate::domain::Domain;
use crate::error::ScenarioError;
use crate::extent::{Extent, MAX_ANGULAR_VELOCITY_RAD_PER_S, MAX_TRAVEL_DOMAINS};
use crate::gridded_inputs::{
    resolve_gridded_velocity, resolve_sea_surface_height, GridContext, InputFile,
};
use crate::ice_grid_keys::{resolve_ice_grids, IceGrids};
use crate::law_table::{law_from_table, preset_applies, RawLawTable};
use crate::motion_segments::resolve_schedule;
use crate::numbers::{short, short_list, sig, thousands};
use crate::output_cadence::{OutputCadence, OutputWindow};
use crate::size_distribution::{resolve_size_distribution, SizeDistribution};
use crate::source_file::SourceFile;
use crate::spec::*;

/// Fraction of the nominal floe area below which generated floes (pieces
/// clipped at the domain edges) are dropped, unless the file says otherwise.
pub const DEFAULT_MIN_AREA_FRACTION: f64 = 0.1;

/// Ice density when `[ice] density_kg_per_m3` is absent, kg/m^3.
pub const DEFAULT_ICE_DENSITY_KG_PER_M3: f64 = 917.0;

/// Ice thickness when `[ice]` gives none, m.
pub const DEFAULT_THICKNESS_M: f64 = 1.0;

/// Auto time step as a fraction of the stable limit.
pub const AUTO_DT_FRACTION: f64 = 0.5;

/// A user-chosen or automatic time step.
#[derive(Debug, Clone)]
pub(crate) enum DtChoice {
    /// [`AUTO_DT_FRACTION`] of the stable limit.
    Auto,
    /// `dt_fraction` of the stable limit, at this location.
    Fraction(f64, Range<usize>),
    /// Given in the file, at this location.
    Given(f64, Range<usize>),
}

/// Most `[[output.window]]` tables a file may give: each is looked at
/// whenever an output falls due.
pub const MAX_OUTPUT_WINDOWS: usize = 1000;

/// Which side of the domain a wall closes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Side {
    Left,
    Right,
    Bottom,
    Top,
}

impl Side {
    pub fn name(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
            Side::Bottom => "bottom",
            Side::Top => "top",
        }
    }

    /// 0 for walls across x (left, right), 1 for walls across y.
    pub fn axis(self) -> usize {
        match self {
            Side::Left | Side::Right => 0,
            Side::Bottom | Side::Top => 1,
        }
    }
}

/// A `[[wall]]`, checked.
#[derive(Debug, Clone)]
pub(crate) struct Wall {
    pub index: usize,
    pub side: Side,
    /// The velocity at the start (the schedule's, when it has one).
    pub velocity: Vec2,
    /// `[[wall.segment]]`, when given.
    pub schedule: Option<MotionSchedule>,
    /// `normal_stress_n_per_m` and the control's keys, when the wall holds
    /// a stress.
    pub stress: Option<(f64, ControlKeys)>,
    /// Floes whose centroid lies within this distance of the wall's face
    /// move with it (a rough wall), m; 0: none.
    pub glue_depth_m: f64,
    pub inset_m: f64,
    pub thickness_m: Option<f64>,
    pub span: Range<usize>,
    pub velocity_span: Range<usize>,
    pub inset_span: Range<usize>,
}

impl Wall {
    /// The most the wall can be from where it started over `duration_s`, m.
    pub(crate) fn most_travel_m(&self, duration_s: f64) -> f64 {
        match &self.schedule {
            Some(s) => s.most_travel_m(duration_s),
            None => self.velocity.length() * duration_s,
        }
    }

    /// Its velocity at time `t_s`, m/s.
    pub(crate) fn velocity_at(&self, t_s: f64) -> Vec2 {
        match &self.schedule {
            Some(s) => s.velocity_at(t_s).0,
            None => self.velocity,
        }
    }

    /// Its displacement from the start at time `t_s`, m.
    pub(crate) fn travel_to(&self, t_s: f64) -> Vec2 {
        match &self.schedule {
            Some(s) => s.travel_to(t_s).0,
            None => self.velocity * t_s,
        }
    }
}

/// A `[[floe]]`, checked.
#[derive(Debug, Clone)]
pub(crate) struct ExplicitFloe {
    pub vertices: Vec<Vec2>,
    pub thickness_m: Option<f64>,
    pub velocity: Option<Vec2>,
    pub angular_velocity_rad_per_s: f64,
    pub prescribed: bool,
    /// `[[floe.segment]]` of a prescribed floe.
    pub schedule: Option<MotionSchedule>,
    /// `[floe.load_point]` of a free floe: stiffness (N/m) and schedule.
    pub load_point: Option<(f64, MotionSchedule)>,
    pub span: Range<usize>,
}

/// Where the floes come from.
#[derive(Debug, Clone)]
pub(crate) enum FloeSource {
    Diamond {
        side_m: f64,
        acute_angle_deg: f64,
        orientation_deg: f64,
        /// `Some((along, across))` when given by the diagonals.
        diagonals_m: Option<(f64, f64)>,
        jitter_fraction: f64,
    },
    Voronoi {
        /// Floe count, or `None` to derive it from `floe_scale_m`.
        count: Option<usize>,
        floe_scale_m: Option<f64>,
        relax_iterations: usize,
    },
    Grid {
        columns: usize,
        rows: usize,
        gap_m: f64,
    },
    /// Voronoi with `size_distribution`: Laguerre cells of drawn areas.
    PowerLaw {
        sizes: SizeDistribution,
        relax_iterations: usize,
        relax_span: Option<Range<usize>>,
    },
    DoubleShear {
        block_m: [f64; 2],
        side_block_m: [f64; 2],
        pusher_m: [f64; 2],
        normal_load_per_face_n: f64,
        /// The pusher's velocity at the start.
        push_velocity_m_per_s: f64,
        /// `[[tessellation.segment]]`, when the pusher follows a schedule.
        push_schedule: Option<MotionSchedule>,
    },
    Explicit(Vec<ExplicitFloe>),
}

/// The scenario with every default applied and every single value checked.
#[derive(Debug, Clone)]
pub(crate) struct Resolved {
    pub title: Option<String>,
    pub seed: u64,
    pub threads: Option<usize>,
    pub duration_s: f64,
    /// Location of `duration_s`.
    pub duration_span: Range<usize>,
    pub dt: DtChoice,
    pub domain: Domain,
    pub floes: FloeSource,
    /// Location of `[tessellation]` (or of the first `[[floe]]`).
    pub floes_span: Range<usize>,
    pub min_area_fraction: f64,
    pub thickness: ThicknessDistribution,
    /// `[ice] concentration_grid` and `thickness_grid`.
    pub ice_grids: IceGrids,
    pub density_kg_per_m3: f64,
    pub initial_velocity: Vec2,
    pub model: ContactModel,
    pub forcing: Forcing,
    pub walls: Vec<Wall>,
    /// `[map]`: the projection of longitude and latitude onto the plane.
    pub map: Option<floe_basin::MapProjection>,
    /// `[[land]]` tables (the files are read when the floes are built).
    pub land: Vec<crate::land_spec::LandFile>,
    pub output: OutputCadence,
    /// Location of each `[[output.window]]`.
    pub window_spans: Vec<Range<usize>>,
    /// `start_time`.
    pub start_time: Option<String>,
    /// Files read besides the scenario.
    pub inputs: Vec<InputFile>,
    /// The gridded fields, with their keys.
    pub(crate) gridded: Vec<crate::gridded_inputs::GriddedOrigin>,
}

/// What a table allows, for refusing keys that do not apply.
fn refuse_given(
    f: &SourceFile,
    table: &str,
    what: &str,
    given: &[(Option<Range<usize>>, &str)],
    allowed: &[&str],
) -> Result<(), ScenarioError> {
    for (span, name) in given {
        if let Some(span) = span {
            if !allowed.contains(name) {
                return Err(f.error(
                    span.clone(),
                    format!("{table}.{name}"),
                    format!("does not apply to {what}"),
                ));
            }
        }
    }
    Ok(())
}

fn span_of<T>(v: &Option<Spanned<T>>) -> Option<Range<usize>> {
    v.as_ref().map(|s| s.span())
}

/// A count in `[min, max]`: every count of work is bounded before the
/// work starts.
fn count(
    f: &SourceFile,
    v: &Spanned<i64>,
    key: &str,
    min: i64,
    max: u64,
) -> Result<usize, ScenarioError> {
    let n = *v.get_ref();
    if n >= min && n as u64 <= max {
        Ok(n as usize)
    } else {
        Err(f.error(
            v.span(),
            key,
            format!("must be an integer from {min} to {max}, got {n}"),
        ))
    }
}

/// Most time steps a run may take unless raised (`floe run --step-limit`):
/// about a day at 1e4 steps/s, beyond which a step count is a typo.
pub const MAX_RUN_STEPS: f64 = 1e9;

/// Most worker threads a file may ask for.
pub const MAX_THREADS: u64 = 1024;

/// Most Lloyd iterations of a Voronoi tessellation (it converges in tens).
pub const MAX_RELAX_ITERATIONS: u64 = 10_000;

pub use crate::length_limit::MAX_LENGTH_M;

/// Thinnest ice a file may give, m: new ice (nilas) is centimetres thick;
/// far thinner floes have a time-step limit that underflows.
pub const MIN_THICKNESS_M: f64 = 1e-3;

/// Thickest ice a file may give, m (icebergs reach a few hundred metres).
pub const MAX_THICKNESS_M: f64 = 1e4;

/// Densest ice, air or water a file may give, kg/m^3.
pub const MAX_DENSITY_KG_PER_M3: f64 = 1e5;

/// Refuses values whose magnitude is above `max` (`unit` for the message).
fn at_most(
    f: &SourceFile,
    span: Range<usize>,
    key: &str,
    values: &[f64],
    max: f64,
    unit: &str,
) -> Result<(), ScenarioError> {
    match values.iter().find(|x| (x.abs() <= max).not()) {
        None => Ok(()),
        Some(&x) => Err(f.error(
            span,
            key,
            format!(
                "{} {unit} is beyond the largest accepted magnitude, {} {unit}",
                short(x),
                sig(max)
            ),
        )),
    }
}

/// Refuses a constant `velocity` (at `v`) that would carry a prescribed
/// `what` more than [`MAX_TRAVEL_DOMAINS`] domain sizes across the
/// domain's non-periodic axes within the run.
fn travel_within(
    f: &SourceFile,
    v: &Spanned<Exact<f64, 2>>,
    key: &str,
    velocity: Vec2,
    extent: Extent,
    what: &str,
) -> Result<(), ScenarioError> {
    let d = extent.domain;
    let across = |axis: usize, speed: f64| if d.periodic[axis] { 0.0 } else { speed.abs() };
    let travel = across(0, velocity.x).hypot(across(1, velocity.y)) * extent.duration_s;
    let most = MAX_TRAVEL_DOMAINS * d.size_m.x.max(d.size_m.y);
    if travel <= most {
        return Ok(());
    }
    Err(f.error(
        v.span(),
        key,
        format!(
            "moves the {what} {} m across the domain's non-periodic axes in duration_s = {} s, \
             more than {MAX_TRAVEL_DOMAINS} domain sizes ({} m)",
            sig(travel),
            sig(extent.duration_s),
            sig(most)
        ),
    ))
}

/// A number > 0 (>= 0 when `zero_ok`) and at most `max` (in `unit`).
fn sized(
    f: &SourceFile,
    v: &Spanned<f64>,
    key: &str,
    zero_ok: bool,
    (max, unit): (f64, &str),
) -> Result<f64, ScenarioError> {
    let x = if zero_ok {
        f.non_negative(v, key)?
    } else {
        f.positive(v, key)?
    };
    at_most(f, v.span(), key, &[x], max, unit)?;
    Ok(x)
}

/// A length > 0 and at most [`MAX_LENGTH_M`].
fn length(f: &SourceFile, v: &Spanned<f64>, key: &str) -> Result<f64, ScenarioError> {
    sized(f, v, key, false, (MAX_LENGTH_M, "m"))
}

/// A length >= 0 and at most [`MAX_LENGTH_M`].
fn distance(f: &SourceFile, v: &Spanned<f64>, key: &str) -> Result<f64, ScenarioError> {
    sized(f, v, key, true, (MAX_LENGTH_M, "m"))
}

/// A thickness from [`MIN_THICKNESS_M`] (or 0 when `zero_ok`, for a
/// spread) to [`MAX_THICKNESS_M`].
fn thickness(
    f: &SourceFile,
    v: &Spanned<f64>,
    key: &str,
    zero_ok: bool,
) -> Result<f64, ScenarioError> {
    let h = sized(f, v, key, zero_ok, (MAX_THICKNESS_M, "m"))?;
    if zero_ok || h >= MIN_THICKNESS_M {
        return Ok(h);
    }
    Err(f.error(
        v.span(),
        key,
        format!(
            "{} m is thinner than the thinnest accepted ice, {MIN_THICKNESS_M} m",
            short(h)
        ),
    ))
}

/// A density (> 0 unless `zero_ok`) at most [`MAX_DENSITY_KG_PER_M3`].
fn density(
    f: &SourceFile,
    v: &Spanned<f64>,
    key: &str,
    zero_ok: bool,
) -> Result<f64, ScenarioError> {
    sized(f, v, key, zero_ok, (MAX_DENSITY_KG_PER_M3, "kg/m^3"))
}

/// Largest normal stress a wall may hold, N/m (vertically integrated; the
/// pack's strength is tens of kN/m).
pub const MAX_WALL_STRESS_N_PER_M: f64 = 1e9;

/// Accepted load-point spring stiffnesses, N/m (the paper's apparatus:
/// 2e7 lab, 2e6 tank).
pub const LOAD_POINT_STIFFNESS_RANGE_N_PER_M: (f64, f64) = (1e-3, 1e12);

/// Accepted contact Young's moduli, Pa: sea ice is about 1e9; below 1e3 Pa
/// floes pass through each other, above 1e13 the stable step vanishes.
pub const YOUNGS_MODULUS_RANGE_PA: (f64, f64) = (1e3, 1e13);

/// Most Voronoi work, sites x (Lloyd iterations + 1): one pass over 1e6
/// sites takes about 5 s, so the limit is about 8 minutes.
pub const MAX_VORONOI_WORK: f64 = 1e8;

/// Refuses a tessellation of `sites` Voronoi sites relaxed `iterations`
/// times whose work is above [`MAX_VORONOI_WORK`], blaming `key` at `span`.
pub(crate) fn voronoi_work(
    f: &SourceFile,
    span: Range<usize>,
    key: &str,
    sites: usize,
    iterations: usize,
) -> Result<(), ScenarioError> {
    let work = sites as f64 * (iterations as f64 + 1.0);
    if work <= MAX_VORONOI_WORK {
        return Ok(());
    }
    Err(f.error(
        span,
        key,
        format!(
            "{} sites x ({iterations} + 1) Lloyd passes is {} site-passes, above the limit of \
             {} (about 8 minutes); use fewer iterations (Lloyd converges in tens) or fewer floes",
            thousands(sites),
            sig(work),
            sig(MAX_VORONOI_WORK)
        ),
    ))
}

/// A number in `[lo, hi]` (or `[lo, hi)` when `open_hi`).
fn within(
    f: &SourceFile,
    v: &Spanned<f64>,
    key: &str,
    lo: f64,
    hi: f64,
    open_hi: bool,
) -> Result<f64, ScenarioError> {
    let x = *v.get_ref();
    let ok = x.is_finite() && x >= lo && if open_hi { x < hi } else { x <= hi };
    if ok {
        Ok(x)
    } else {
        let close = if open_hi { ")" } else { "]" };
        Err(f.error(
            v.span(),
            key,
            format!(
                "must lie in [{}, {}{close}, got {}",
                sig(lo),
                sig(hi),
                short(x)
            ),
        ))
    }
}

/// A [`DemError`] about something at `span`.
pub(crate) fn dem_error(
    f: &SourceFile,
    span: Range<usize>,
    key: &str,
    e: DemError,
) -> ScenarioError {
    f.error(span, key, e.to_string())
}

/// Reads the file, applies defaults and checks every value on its own.
/// Resolves `f`; relative input file paths are taken from `base_dir`.
pub(crate) fn resolve(
    f: &SourceFile,
    registry: &LawRegistry,
    base_dir: &Path,
) -> Result<Resolved, ScenarioError> {
    let raw: RawScenario = f.parse_toml()?;

    let title = raw.title.as_ref().map(|t| t.get_ref().clone());
    let seed = match &raw.seed {
        Some(s) => count(f, s, "seed", 0, i64::MAX as u64)? as u64,
        None => 0,
    };
    let threads = raw
        .threads
        .as_ref()
        .map(|t| count(f, t, "threads", 1, MAX_THREADS))
        .transpose()?;
    let Some(duration) = &raw.duration_s else {
        return Err(f.error_in_file("missing `duration_s`: how long to simulate, in seconds"));
    };
    let duration_s = f.positive(duration, "duration_s")?;
    let dt = match (&raw.dt_s, &raw.dt_fraction) {
        (Some(_), Some(fraction)) => {
            return Err(f.error(
                fraction.span(),
                "dt_fraction",
                "give either dt_s (the step in seconds) or dt_fraction (of the stable \
                 limit), not both",
            ))
        }
        (Some(v), None) => DtChoice::Given(f.positive(v, "dt_s")?, v.span()),
        (None, Some(v)) => DtChoice::Fraction(dt_fraction(f, v)?, v.span()),
        (None, None) => DtChoice::Auto,
    };

    let domain = resolve_domain(f, raw.domain.as_ref())?;
    let (thickness, density_kg_per_m3, initial_velocity) = resolve_ice(f, raw.ice.as_ref())?;
    let extent = Extent { duration_s, domain };
    let (floes, floes_span, min_area_fraction) = resolve_floes(f, &raw, extent)?;
    let ice_grids = resolve_ice_grids(f, raw.ice.as_ref(), base_dir)?;
    if let Some(g) = ice_grids.first() {
        if matches!(
            floes,
            FloeSource::Explicit(_) | FloeSource::DoubleShear { .. }
        ) {
            return Err(f.error(
                g.span.clone(),
                g.key,
                "places the floes of a [tessellation] of kind `diamond`, `voronoi` or `grid`; \
                 not explicit [[floe]] tables or a double-shear set-up",
            ));
        }
    }
    let model = resolve_contact(f, raw.contact.as_ref(), raw.friction.as_ref(), registry)?;
    let map = crate::land_spec::resolve_map(f, raw.map.as_ref())?;
    let mut grids = GridContext {
        projection: map.as_ref(),
        start_time: resolve_start_time(f, raw.start_time.as_ref())?,
        region: domain,
        base_dir: base_dir.to_path_buf(),
        inputs: Vec::new(),
        origins: Vec::new(),
    };
    let forcing = resolve_forcing(
        f,
        raw.wind.as_ref(),
        raw.ocean.as_ref(),
        raw.coriolis.as_ref(),
        &mut grids,
    )?;
    let walls = resolve_walls(f, raw.wall.as_deref().unwrap_or(&[]), extent)?;
    let land = crate::land_spec::resolve_land(
        f,
        raw.land.as_deref().unwrap_or(&[]),
        map.as_ref(),
        base_dir,
    )?;
    for g in [&ice_grids.concentration, &ice_grids.thickness]
        .into_iter()
        .flatten()
    {
        grids.inputs.push(InputFile {
            role: g.key.to_string(),
            path: g.path.clone(),
        });
    }
    for l in &land {
        grids.inputs.push(InputFile {
            role: format!("land[{}]", l.index),
            path: l.path.clone(),
        });
    }
    if let (FloeSource::DoubleShear { .. }, Some(first)) = (&floes, land.first()) {
        return Err(f.error(
            first.span.clone(),
            "land[0].file",
            "land does not apply to the double-shear set-up",
        ));
    }
    let (output, window_spans) = resolve_output(f, raw.output.as_ref(), duration_s)?;
    let GridContext {
        start_time,
        inputs,
        origins,
        ..
    } = grids;
    Ok(Resolved {
        title,
        seed,
        threads,
        duration_s,
        duration_span: duration.span(),
        dt,
        domain,
        floes,
        floes_span,
        min_area_fraction,
        thickness,
        ice_grids,
        density_kg_per_m3,
        initial_velocity,
        model,
        forcing,
        walls,
        map,
        land,
        output,
        window_spans,
        start_time,
        inputs,
        gridded: origins,
    })
}

/// `start_time`: a date like "2024-03-01 00:00:00".
fn resolve_start_time(
    f: &SourceFile,
    raw: Option<&Spanned<String>>,
) -> Result<Option<String>, ScenarioError> {
    let Some(t) = raw else { return Ok(None) };
    floe_basin::cf_time::offset_and_unit(
        "seconds since 2000-01-01",
        "proleptic_gregorian",
        t.get_ref(),
    )
    .map_err(|_| {
        f.error(
            t.span(),
            "start_time",
            format!(
                "\"{}\" is not a date and time like \"2024-03-01 00:00:00\" (UTC)",
                t.get_ref()
            ),
        )
    })?;
    Ok(Some(t.get_ref().trim().to_string()))
}

/// `dt_fraction`: a number in (0, 1].
fn dt_fraction(f: &SourceFile, v: &Spanned<f64>) -> Result<f64, ScenarioError> {
    let x = *v.get_ref();
    if x.is_finite() && x > 0.0 && x <= 1.0 {
        return Ok(x);
    }
    Err(f.error(
        v.span(),
        "dt_fraction",
        format!(
            "must lie in (0, 1], a fraction of the stable time step (omit it for \
             {AUTO_DT_FRACTION}), got {}",
            short(x)
        ),
    ))
}

fn resolve_domain(
    f: &SourceFile,
    raw: Option<&Spanned<RawDomain>>,
) -> Result<Domain, ScenarioError> {
    let Some(raw) = raw else {
        return Err(f.error_in_file(
            "missing [domain]: give at least `size_m = [width, height]` in metres",
        ));
    };
    let d = raw.get_ref();
    let min_m = match &d.min_m {
        Some(v) => {
            let p = f.pair(v, "domain.min_m")?;
            at_most(f, v.span(), "domain.min_m", &[p.x, p.y], MAX_LENGTH_M, "m")?;
            p
        }
        None => Vec2::ZERO,
    };
    let Some(size) = &d.size_m else {
        return Err(f.error(
            raw.span(),
            "domain.size_m",
            "missing: give the domain's `size_m = [width, height]` in metres",
        ));
    };
    let size_m = f.pair(size, "domain.size_m")?;
    if !(size_m.x > 0.0 && size_m.y > 0.0) {
        return Err(f.error(
            size.span(),
            "domain.size_m",
            format!(
                "width and height must be > 0, got {}",
                short_list(&[size_m.x, size_m.y])
            ),
        ));
    }
    at_most(
        f,
        size.span(),
        "domain.size_m",
        &[size_m.x, size_m.y, min_m.x + size_m.x, min_m.y + size_m.y],
        MAX_LENGTH_M,
        "m",
    )?;
    let periodic = d.periodic.as_ref().map_or([false; 2], |p| p.get_ref().0);
    Ok(Domain {
        min_m,
        size_m,
        periodic,
    })
}

fn resolve_ice(
    f: &SourceFile,
    raw: Option<&Spanned<RawIce>>,
) -> Result<(ThicknessDistribution, f64, Vec2), ScenarioError> {
    let Some(raw) = raw else {
        return Ok((
            ThicknessDistribution::Uniform {
                thickness_m: DEFAULT_THICKNESS_M,
            },
            DEFAULT_ICE_DENSITY_KG_PER_M3,
            Vec2::ZERO,
        ));
    };
    let ice = raw.get_ref();
    let ways = [
        ice.thickness_m.is_some(),
        ice.thickness_mean_m.is_some(),
        ice.thickness_range_m.is_some(),
        ice.thickness_grid.is_some(),
    ];
    if ways.iter().filter(|&&w| w).count() > 1 {
        return Err(f.error(
            raw.span(),
            "ice",
            "give one of `thickness_m`, `thickness_mean_m` (with `thickness_std_m`), `thickness_range_m` or `thickness_grid`",
        ));
    }
    if ice.thickness_std_m.is_some() && ice.thickness_mean_m.is_none() {
        let s = ice
            .thickness_std_m
            .as_ref()
            .map(|s| s.span())
            .unwrap_or(0..0);
        return Err(f.error(
            s,
            "ice.thickness_std_m",
            "needs `thickness_mean_m` (log-normal thickness)",
        ));
    }
    let thickness = if let Some(h) = &ice.thickness_m {
        ThicknessDistribution::Uniform {
            thickness_m: thickness(f, h, "ice.thickness_m", false)?,
        }
    } else if let Some(mean) = &ice.thickness_mean_m {
        ThicknessDistribution::LogNormal {
            mean_m: thickness(f, mean, "ice.thickness_mean_m", false)?,
            std_m: match &ice.thickness_std_m {
                Some(s) => thickness(f, s, "ice.thickness_std_m", true)?,
                None => 0.0,
            },
        }
    } else if let Some(r) = &ice.thickness_range_m {
        let [lo, hi] = r.get_ref().0;
        if !(lo.is_finite() && hi.is_finite() && lo >= MIN_THICKNESS_M && hi >= lo) {
            return Err(f.error(
                r.span(),
                "ice.thickness_range_m",
                format!(
                    "must be [min, max] with {MIN_THICKNESS_M} m <= min <= max, got {}",
                    short_list(&[lo, hi])
                ),
            ));
        }
        at_most(
            f,
            r.span(),
            "ice.thickness_range_m",
            &[hi],
            MAX_THICKNESS_M,
            "m",
        )?;
        ThicknessDistribution::UniformRange {
            min_m: lo,
            max_m: hi,
        }
    } else {
        ThicknessDistribution::Uniform {
            thickness_m: DEFAULT_THICKNESS_M,
        }
    };
    let density = match &ice.density_kg_per_m3 {
        Some(v) => match density(f, v, "ice.density_kg_per_m3", false)? {
            // Far lighter than any ice, and the masses underflow.
            rho if rho >= 100.0 => rho,
            rho => {
                return Err(f.error(
                    v.span(),
                    "ice.density_kg_per_m3",
                    format!(
                        "{} kg/m^3 is lighter than any ice (at least 100)",
                        short(rho)
                    ),
                ))
            }
        },
        None => DEFAULT_ICE_DENSITY_KG_PER_M3,
    };
    let velocity = match &ice.initial_velocity_m_per_s {
        Some(v) => f.pair(v, "ice.initial_velocity_m_per_s")?,
        None => Vec2::ZERO,
    };
    Ok((thickness, density, velocity))
}

fn resolve_floes(
    f: &SourceFile,
    raw: &RawScenario,
    extent: Extent,
) -> Result<(FloeSource, Range<usize>, f64), ScenarioError> {
    match (&raw.tessellation, &raw.floe) {
        (Some(t), Some(floes)) => {
            let span = floes.first().map_or(t.span(), |fl| fl.span());
            Err(f.error(
                span,
                "floe",
                "explicit [[floe]] tables and [tessellation] exclude each other: use one",
            ))
        }
        (None, None) => Err(f.error_in_file(
            "no floes: add a [tessellation] (diamond, voronoi, grid, double-shear) or [[floe]] tables",
        )),
        (None, Some(floes)) => {
            let mut out = Vec::with_capacity(floes.len());
            for (i, fl) in floes.iter().enumerate() {
                out.push(resolve_explicit_floe(f, fl, i, extent)?);
            }
            let span = floes.first().map_or(0..0, |fl| fl.span());
            Ok((FloeSource::Explicit(out), span, 0.0))
        }
        (Some(t), None) => resolve_tessellation(f, t, extent),
    }
}

fn resolve_explicit_floe(
    f: &SourceFile,
    raw: &Spanned<RawFloe>,
    i: usize,
    extent: Extent,
) -> Result<ExplicitFloe, ScenarioError> {
    let fl = raw.get_ref();
    let key = |k: &str| format!("floe[{i}].{k}");
    let vertices = match (&fl.vertices_m, &fl.box_m) {
        (Some(v), None) => {
            let pts: Vec<Vec2> = v
                .get_ref()
                .iter()
                .map(|&Exact([x, y])| Vec2::new(x, y))
                .collect();
            if pts.iter().any(|p| !(p.x.is_finite() && p.y.is_finite())) {
                return Err(f.error(v.span(), key("vertices_m"), "coordinates must be finite"));
            }
            let coords: Vec<f64> = pts.iter().flat_map(|p| [p.x, p.y]).collect();
            at_most(f, v.span(), &key("vertices_m"), &coords, MAX_LENGTH_M, "m")?;
            pts
        }
        (None, Some(b)) => {
            let [x0, y0, x1, y1] = b.get_ref().0;
            if !([x0, y0, x1, y1].iter().all(|v| v.is_finite()) && x1 > x0 && y1 > y0) {
                return Err(f.error(
                    b.span(),
                    key("box_m"),
                    format!(
                        "must be [x_min, y_min, x_max, y_max] with max > min, got {}",
                        short_list(&[x0, y0, x1, y1])
                    ),
                ));
            }
            at_most(f, b.span(), &key("box_m"), &[x0, y0, x1, y1], MAX_LENGTH_M, "m")?;
            vec![
                Vec2::new(x0, y0),
                Vec2::new(x1, y0),
                Vec2::new(x1, y1),
                Vec2::new(x0, y1),
            ]
        }
        _ => {
            return Err(f.error(
                raw.span(),
                format!("floe[{i}]"),
                "give exactly one of `vertices_m = [[x, y], ...]` (convex outline) or `box_m = [x_min, y_min, x_max, y_max]`",
            ))
        }
    };
    let prescribed = fl.prescribed.as_ref().is_some_and(|p| *p.get_ref());
    let schedule = match &fl.segment {
        None => None,
        Some(segments) => {
            let first = segments.first().map_or(raw.span(), |s| s.span());
            if !prescribed {
                return Err(f.error(
                    first,
                    key("segment"),
                    "only a prescribed floe (prescribed = true) follows a motion schedule",
                ));
            }
            for (given, name) in [
                (
                    fl.velocity_m_per_s.as_ref().map(|v| v.span()),
                    "velocity_m_per_s",
                ),
                (
                    fl.angular_velocity_rad_per_s.as_ref().map(|v| v.span()),
                    "angular_velocity_rad_per_s",
                ),
            ] {
                if let Some(span) = given {
                    return Err(f.error(
                        span,
                        key(name),
                        "give the floe's motion either as velocities or as [[floe.segment]] \
                         tables, not both",
                    ));
                }
            }
            Some(resolve_schedule(
                f,
                (segments, raw.span()),
                &format!("floe[{i}]"),
                true,
                extent,
            )?)
        }
    };
    let load_point = match &fl.load_point {
        None => None,
        Some(lp) => {
            let owner = format!("floe[{i}].load_point");
            if prescribed {
                return Err(f.error(
                    lp.span(),
                    key("load_point"),
                    "a load point drives a free floe through its spring; a prescribed floe \
                     ignores forces (drop prescribed = true, or give it [[floe.segment]])",
                ));
            }
            let r = lp.get_ref();
            let Some(k) = &r.stiffness_n_per_m else {
                return Err(f.error(
                    lp.span(),
                    format!("{owner}.stiffness_n_per_m"),
                    "missing: the spring's stiffness in N/m (the paper's apparatus: 2e7 lab, \
                     2e6 tank)",
                ));
            };
            let k = f.in_range(
                k,
                &format!("{owner}.stiffness_n_per_m"),
                LOAD_POINT_STIFFNESS_RANGE_N_PER_M,
                "N/m",
            )?;
            let Some(segments) = &r.segment else {
                return Err(f.error(
                    lp.span(),
                    format!("{owner}.segment"),
                    "missing: [[floe.load_point.segment]] tables saying how the load point moves",
                ));
            };
            Some((
                k,
                resolve_schedule(f, (segments, lp.span()), &owner, false, extent)?,
            ))
        }
    };
    Ok(ExplicitFloe {
        vertices,
        thickness_m: fl
            .thickness_m
            .as_ref()
            .map(|h| thickness(f, h, &key("thickness_m"), false))
            .transpose()?,
        velocity: fl
            .velocity_m_per_s
            .as_ref()
            .map(|v| {
                let velocity = f.pair(v, &key("velocity_m_per_s"))?;
                // A prescribed floe keeps its velocity: bound its travel.
                if fl.prescribed.as_ref().is_some_and(|p| *p.get_ref()) {
                    travel_within(f, v, &key("velocity_m_per_s"), velocity, extent, "floe")?;
                }
                Ok::<_, ScenarioError>(velocity)
            })
            .transpose()?,
        angular_velocity_rad_per_s: fl
            .angular_velocity_rad_per_s
            .as_ref()
            .map(|w| {
                let most = MAX_ANGULAR_VELOCITY_RAD_PER_S;
                f.in_range(
                    w,
                    &key("angular_velocity_rad_per_s"),
                    (-most, most),
                    "rad/s",
                )
            })
            .transpose()?
            .unwrap_or(0.0),
        prescribed: fl.prescribed.as_ref().is_some_and(|p| *p.get_ref()),
        schedule,
        load_point,
        span: raw.span(),
    })
}

fn resolve_tessellation(
    f: &SourceFile,
    raw: &Spanned<RawTessellation>,
    extent: Extent,
) -> Result<(FloeSource, Range<usize>, f64), ScenarioError> {
    let t = raw.get_ref();
    let span = raw.span();
    let Some(kind_word) = &t.kind else {
        return Err(f.error(
            span,
            "tessellation.kind",
            "missing: `diamond`, `voronoi`, `grid` or `double-shear`",
        ));
    };
    let kind = kind_word.get_ref().as_str();
    let given = [
        (span_of(&t.min_area_fraction), "min_area_fraction"),
        (span_of(&t.side_m), "side_m"),
        (span_of(&t.diagonals_m), "diagonals_m"),
        (span_of(&t.acute_angle_deg), "acute_angle_deg"),
        (span_of(&t.orientation_deg), "orientation_deg"),
        (span_of(&t.jitter_fraction), "jitter_fraction"),
        (span_of(&t.floe_scale_m), "floe_scale_m"),
        (span_of(&t.count), "count"),
        (span_of(&t.relax_iterations), "relax_iterations"),
        (span_of(&t.columns), "columns"),
        (span_of(&t.rows), "rows"),
        (span_of(&t.gap_m), "gap_m"),
        (span_of(&t.block_m), "block_m"),
        (span_of(&t.side_block_m), "side_block_m"),
        (span_of(&t.pusher_m), "pusher_m"),
        (span_of(&t.normal_load_per_face_n), "normal_load_per_face_n"),
        (span_of(&t.push_velocity_m_per_s), "push_velocity_m_per_s"),
        (
            t.segment.as_ref().and_then(|s| s.first()).map(|s| s.span()),
            "segment",
        ),
        (span_of(&t.size_distribution), "size_distribution"),
    ];
    let allowed: &[&str] = match kind {
        "diamond" => &[
            "min_area_fraction",
            "side_m",
            "diagonals_m",
            "acute_angle_deg",
            "orientation_deg",
            "jitter_fraction",
        ],
        "voronoi" => &[
            "min_area_fraction",
            "floe_scale_m",
            "count",
            "relax_iterations",
            "size_distribution",
        ],
        "grid" => &["columns", "rows", "gap_m"],
        "double-shear" => &[
            "block_m",
            "side_block_m",
            "pusher_m",
            "normal_load_per_face_n",
            "push_velocity_m_per_s",
            "segment",
        ],
        other => {
            return Err(f.error(
                kind_word.span(),
                "tessellation.kind",
                format!(
                "unknown kind `{other}`, expected `diamond`, `voronoi`, `grid` or `double-shear`"
            ),
            ))
        }
    };
    refuse_given(
        f,
        "tessellation",
        &format!("kind `{kind}`"),
        &given,
        allowed,
    )?;
    let min_area_fraction = match &t.min_area_fraction {
        Some(v) => within(f, v, "tessellation.min_area_fraction", 0.0, 1.0, true)?,
        None => DEFAULT_MIN_AREA_FRACTION,
    };
    let need = |what: &str| {
        f.error(
            span.clone(),
            format!("tessellation.{what}"),
            format!("missing: kind `{kind}` needs it"),
        )
    };
    let source = match kind {
        "diamond" => {
            let orientation_deg = match &t.orientation_deg {
                Some(v) => f.finite(v, "tessellation.orientation_deg")?,
                None => 0.0,
            };
            let (side_m, acute_angle_deg, diagonals_m) = match (&t.side_m, &t.diagonals_m) {
                (Some(s), None) => {
                    let side = length(f, s, "tessellation.side_m")?;
                    let angle = match &t.acute_angle_deg {
                        Some(a) => {
                            let a_deg = *a.get_ref();
                            if !(a_deg.is_finite() && a_deg > 0.0 && a_deg < 180.0) {
                                return Err(f.error(
                                    a.span(),
                                    "tessellation.acute_angle_deg",
                                    format!(
                                        "must lie strictly between 0 and 180, got {}",
                                        short(a_deg)
                                    ),
                                ));
                            }
                            a_deg
                        }
                        None => 60.0,
                    };
                    (side, angle, None)
                }
                (None, Some(d)) => {
                    if let Some(a) = &t.acute_angle_deg {
                        return Err(f.error(
                            a.span(),
                            "tessellation.acute_angle_deg",
                            "does not apply with `diagonals_m` (the diagonals set the angle)",
                        ));
                    }
                    let [along, across] = d.get_ref().0;
                    if !(along.is_finite() && across.is_finite() && along > 0.0 && across > 0.0) {
                        return Err(f.error(
                            d.span(),
                            "tessellation.diagonals_m",
                            format!(
                                "must be [along, across] > 0, got {}",
                                short_list(&[along, across])
                            ),
                        ));
                    }
                    at_most(
                        f,
                        d.span(),
                        "tessellation.diagonals_m",
                        &[along, across],
                        MAX_LENGTH_M,
                        "m",
                    )?;
                    let angle = 2.0 * across.atan2(along).to_degrees();
                    (0.5 * along.hypot(across), angle, Some((along, across)))
                }
                (Some(s), Some(_)) => {
                    return Err(f.error(
                        s.span(),
                        "tessellation.side_m",
                        "give `side_m` (with `acute_angle_deg`) or `diagonals_m`, not both",
                    ))
                }
                (None, None) => return Err(need("side_m` or `diagonals_m")),
            };
            let jitter_fraction = match &t.jitter_fraction {
                Some(v) => {
                    let max = max_jitter_fraction(acute_angle_deg);
                    within(f, v, "tessellation.jitter_fraction", 0.0, max, false)?
                }
                None => 0.0,
            };
            FloeSource::Diamond {
                side_m,
                acute_angle_deg,
                orientation_deg,
                diagonals_m,
                jitter_fraction,
            }
        }
        "voronoi" if t.size_distribution.is_some() => {
            let sizes = t.size_distribution.as_ref().expect("checked by the guard");
            if let Some((span, name)) = [
                (span_of(&t.count), "count"),
                (span_of(&t.floe_scale_m), "floe_scale_m"),
            ]
            .into_iter()
            .find_map(|(s, n)| s.map(|s| (s, n)))
            {
                return Err(f.error(
                    span,
                    format!("tessellation.{name}"),
                    "give `size_distribution` or the floes' count or scale, not both \
                     (the distribution sets how many floes fill the region)",
                ));
            }
            let relax_iterations = match &t.relax_iterations {
                Some(r) => count(
                    f,
                    r,
                    "tessellation.relax_iterations",
                    0,
                    MAX_RELAX_ITERATIONS,
                )?,
                None => 1,
            };
            FloeSource::PowerLaw {
                sizes: resolve_size_distribution(f, sizes)?,
                relax_iterations,
                relax_span: span_of(&t.relax_iterations),
            }
        }
        "voronoi" => {
            let (count_n, scale) = match (&t.count, &t.floe_scale_m) {
                (Some(c), None) => (
                    Some(count(f, c, "tessellation.count", 1, MAX_FLOES as u64)?),
                    None,
                ),
                (None, Some(s)) => (None, Some(length(f, s, "tessellation.floe_scale_m")?)),
                (Some(c), Some(_)) => {
                    return Err(f.error(
                        c.span(),
                        "tessellation.count",
                        "give `count` or `floe_scale_m`, not both",
                    ))
                }
                (None, None) => return Err(need("count` or `floe_scale_m")),
            };
            let relax_iterations = match &t.relax_iterations {
                Some(r) => {
                    let key = "tessellation.relax_iterations";
                    let n = count(f, r, key, 0, MAX_RELAX_ITERATIONS)?;
                    if let Some(sites) = count_n {
                        voronoi_work(f, r.span(), key, sites, n)?;
                    }
                    n
                }
                None => 1,
            };
            FloeSource::Voronoi {
                count: count_n,
                floe_scale_m: scale,
                relax_iterations,
            }
        }
        "grid" => {
            let (Some(c), Some(r)) = (&t.columns, &t.rows) else {
                return Err(need(if t.columns.is_none() {
                    "columns"
                } else {
                    "rows"
                }));
            };
            let most = MAX_FLOES as u64;
            let columns = count(f, c, "tessellation.columns", 1, most)?;
            let rows = count(f, r, "tessellation.rows", 1, most)?;
            if columns.saturating_mul(rows) > MAX_FLOES {
                let (v, key) = if columns >= rows {
                    (c, "tessellation.columns")
                } else {
                    (r, "tessellation.rows")
                };
                return Err(f.error(
                    v.span(),
                    key,
                    format!("{columns} x {rows} floes is above the cap of {MAX_FLOES}"),
                ));
            }
            FloeSource::Grid {
                columns,
                rows,
                gap_m: match &t.gap_m {
                    Some(g) => distance(f, g, "tessellation.gap_m")?,
                    None => 0.0,
                },
            }
        }
        _ => {
            // "double-shear", the only kind left.
            let size = |v: &Pair, key: &str| -> Result<[f64; 2], ScenarioError> {
                let Some(v) = v else {
                    return Err(need(key));
                };
                let p = f.pair(v, &format!("tessellation.{key}"))?;
                if !(p.x > 0.0 && p.y > 0.0) {
                    return Err(f.error(
                        v.span(),
                        format!("tessellation.{key}"),
                        format!("lengths must be > 0, got {}", short_list(&[p.x, p.y])),
                    ));
                }
                at_most(
                    f,
                    v.span(),
                    &format!("tessellation.{key}"),
                    &[p.x, p.y],
                    MAX_LENGTH_M,
                    "m",
                )?;
                Ok([p.x, p.y])
            };
            let block_m = size(&t.block_m, "block_m")?;
            let side_block_m = size(&t.side_block_m, "side_block_m")?;
            let pusher_m = match &t.pusher_m {
                Some(_) => size(&t.pusher_m, "pusher_m")?,
                None => [0.25 * block_m[0], block_m[1]],
            };
            let Some(load) = &t.normal_load_per_face_n else {
                return Err(need("normal_load_per_face_n"));
            };
            let (push_velocity_m_per_s, push_schedule) =
                match (&t.push_velocity_m_per_s, &t.segment) {
                    (Some(push), None) => (
                        f.non_negative(push, "tessellation.push_velocity_m_per_s")?,
                        None,
                    ),
                    (None, Some(segments)) => {
                        let s = resolve_schedule(
                            f,
                            (segments, span.clone()),
                            "tessellation",
                            false,
                            extent,
                        )?;
                        (s.velocity_at(0.0).0.x, Some(s))
                    }
                    (Some(push), Some(_)) => {
                        return Err(f.error(
                            push.span(),
                            "tessellation.push_velocity_m_per_s",
                            "give the pusher's motion either as push_velocity_m_per_s or as \
                         [[tessellation.segment]] tables, not both",
                        ))
                    }
                    (None, None) => return Err(need("push_velocity_m_per_s")),
                };
            if let Some(s) = &push_schedule {
                // The pusher pushes along +x: a segment across is refused.
                if let Some(k) = s
                    .segments()
                    .iter()
                    .position(|g| g.velocity_start.y != 0.0 || g.velocity_end.y != 0.0)
                {
                    let segments = t.segment.as_deref().unwrap_or(&[]);
                    return Err(f.error(
                        segments[k].span(),
                        format!("tessellation.segment[{k}]"),
                        "the pusher moves along the block (x) only: give velocities [v, 0.0]",
                    ));
                }
            }
            FloeSource::DoubleShear {
                block_m,
                side_block_m,
                pusher_m,
                normal_load_per_face_n: f.positive(load, "tessellation.normal_load_per_face_n")?,
                push_velocity_m_per_s,
                push_schedule,
            }
        }
    };
    Ok((source, span, min_area_fraction))
}

fn resolve_contact(
    f: &SourceFile,
    raw: Option<&RawContact>,
    friction: Option<&Spanned<RawLawTable>>,
    registry: &LawRegistry,
) -> Result<ContactModel, ScenarioError> {
    let mut m = ContactModel::default();
    if let Some(c) = raw {
        if let Some(v) = &c.youngs_modulus_pa {
            m.youngs_modulus_pa = f.in_range(
                v,
                "contact.youngs_modulus_pa",
                YOUNGS_MODULUS_RANGE_PA,
                "Pa",
            )?;
        }
        if let Some(v) = &c.poisson_ratio {
            m.poisson_ratio = within(f, v, "contact.poisson_ratio", 0.0, 0.5, true)?;
        }
        if let Some(v) = &c.restitution {
            m.restitution = within(f, v, "contact.restitution", 0.0, 1.0, false)?;
            if m.restitution < 1e-12 {
                return Err(f.error(
                    v.span(),
                    "contact.restitution",
                    "must lie in [1e-12, 1]; 0 would be an infinitely stiff dashpot, and \
                     below 1e-12 the stable time step vanishes",
                ));
            }
        }
        if let Some(v) = &c.new_contact_slip_rate_m_per_s {
            m.new_contact_slip_rate_m_per_s =
                f.positive(v, "contact.new_contact_slip_rate_m_per_s")?;
        }
        if let Some(v) = &c.sliding_threshold_m_per_s {
            m.sliding_threshold_m_per_s = f.positive(v, "contact.sliding_threshold_m_per_s")?;
        }
        if let Some(v) = &c.memory_s {
            m.memory_s = f.non_negative(v, "contact.memory_s")?;
        }
    }
    let empty = RawLawTable::new();
    let fr = friction.map_or(&empty, |t| t.get_ref());
    // The law's name first: a misspelt law is reported as that, not as a
    // key that does not apply to it.
    if let Some(law) = fr.get("law") {
        let known = law
            .get_ref()
            .as_str()
            .is_some_and(|n| registry.get(n).is_some());
        if !known {
            return Err(f.error(
                law.span(),
                "friction.law",
                format!(
                    "unknown law {}, expected {}",
                    law.get_ref()
                        .as_str()
                        .map_or_else(|| law.get_ref().to_string(), |n| format!("`{n}`")),
                    registry.names_text()
                ),
            ));
        }
    }
    let preset = match fr.get("preset") {
        None => Preset::Tank,
        Some(p) => {
            if !preset_applies(fr, "law", registry) {
                let law = fr
                    .get("law")
                    .and_then(|l| l.get_ref().as_str())
                    .unwrap_or("");
                return Err(f.error(
                    p.span(),
                    "friction.preset",
                    format!("does not apply to law `{law}` (no default depends on it)"),
                ));
            }
            match p.get_ref().as_str() {
                Some("lab") => Preset::Lab,
                Some("tank") => Preset::Tank,
                _ => {
                    return Err(f.error(
                        p.span(),
                        "friction.preset",
                        format!(
                            "unknown value {}, expected one of `lab`, `tank`",
                            p.get_ref()
                        ),
                    ))
                }
            }
        }
    };
    m.law = law_from_table(
        f,
        fr,
        "friction",
        "law",
        &["preset"],
        registry,
        LawContext {
            preset,
            default_form: Form::Regularized,
        },
    )?;
    // The published form (eq. 4b) slips only forward, `V > 0`: in the DEM,
    // "forward" is the contact's tangent `perp(normal)`, a counter-clockwise
    // turn from the pair's normal, so the law favours one sense of relative
    // rotation and mirror-image contacts get different friction (the
    // double shear's two faces: 0.737 against 3.50). Refused here, not
    // in `floe_dem`: the spring-slider protocols use it as the paper does.
    if let floe_friction::Law::RateState(rs) = &m.law {
        if rs.form == Form::Published {
            let span = fr
                .get("form")
                .or_else(|| fr.get("law"))
                .map_or(0..0, |v| v.span());
            return Err(f.error(
                span,
                "friction.form",
                "`published` (eq. 4b) is for the spring-slider (`floe slider`), not DEM \
                 contacts: its slip rate is positive whatever the force, so a contact slips \
                 only counter-clockwise (along perp(normal)), creeps against a reversed force, \
                 and mirror-image contacts get different friction; use `regularized` \
                 (sign-consistent: V = 2 V* exp(-(mu0 + theta)/A) sinh(mu/A), docs/friction.md)",
            ));
        }
    }
    Ok(m)
}

fn resolve_field(
    f: &SourceFile,
    raw: &RawFluid,
    table: &str,
    grids: &mut GridContext<'_>,
) -> Result<VelocityField, ScenarioError> {
    let ways = [
        raw.velocity_m_per_s.is_some(),
        raw.time_series.is_some(),
        raw.shear.is_some(),
        raw.gyre.is_some(),
        raw.file.is_some(),
    ];
    if ways.iter().filter(|&&w| w).count() > 1 {
        let span = [
            span_of(&raw.time_series),
            span_of(&raw.shear),
            span_of(&raw.gyre),
            span_of(&raw.file),
        ]
        .into_iter()
        .flatten()
        .next_back()
        .unwrap_or(0..0);
        return Err(f.error(
            span,
            table,
            "give one of `velocity_m_per_s`, `time_series`, `shear`, `gyre` or `file`",
        ));
    }
    if raw.plane_spacing_m.is_some() && raw.file.is_none() && raw.sea_surface_height.is_none() {
        return Err(f.error(
            span_of(&raw.plane_spacing_m).unwrap_or(0..0),
            format!("{table}.plane_spacing_m"),
            "applies only to a field read from a `file`",
        ));
    }
    let check = |field: VelocityField, span: Range<usize>, key: &str| {
        field
            .validate()
            .map(|()| field)
            .map_err(|e| f.error(span, format!("{table}.{key}"), e.to_string()))
    };
    let field = if let Some(g) = resolve_gridded_velocity(f, raw, table, grids)? {
        g
    } else if let Some(v) = &raw.velocity_m_per_s {
        VelocityField::Uniform(f.pair(v, &format!("{table}.velocity_m_per_s"))?)
    } else if let Some(ts) = &raw.time_series {
        let t = ts.get_ref();
        check(
            VelocityField::TimeSeries {
                times_s: t.times_s.clone(),
                values: t
                    .velocities_m_per_s
                    .iter()
                    .map(|&Exact([x, y])| Vec2::new(x, y))
                    .collect(),
            },
            ts.span(),
            "time_series",
        )?
    } else if let Some(s) = &raw.shear {
        let r = s.get_ref();
        let [a, b] = r.velocity_at_y_min_m_per_s.0;
        let [c, d] = r.velocity_at_y_max_m_per_s.0;
        check(
            VelocityField::LinearShear {
                y_min_m: r.y_min_m,
                y_max_m: r.y_max_m,
                velocity_at_y_min_m_per_s: Vec2::new(a, b),
                velocity_at_y_max_m_per_s: Vec2::new(c, d),
            },
            s.span(),
            "shear",
        )?
    } else if let Some(g) = &raw.gyre {
        let r = g.get_ref();
        check(
            VelocityField::Gyre {
                center_m: Vec2::new(r.center_m.0[0], r.center_m.0[1]),
                core_radius_m: r.core_radius_m,
                max_speed_m_per_s: r.max_speed_m_per_s,
            },
            g.span(),
            "gyre",
        )?
    } else {
        VelocityField::Uniform(Vec2::ZERO)
    };
    match &raw.envelope {
        None => Ok(field),
        Some(e) => {
            let env = Envelope {
                times_s: e.get_ref().times_s.clone(),
                factors: e.get_ref().factors.clone(),
            };
            env.validate()
                .map_err(|err| f.error(e.span(), format!("{table}.envelope"), err.to_string()))?;
            Ok(field.scaled(env))
        }
    }
}

fn resolve_drag(
    f: &SourceFile,
    raw: &RawFluid,
    table: &str,
    mut drag: DragParameters,
) -> Result<DragParameters, ScenarioError> {
    if let Some(v) = &raw.density_kg_per_m3 {
        drag.density_kg_per_m3 = density(f, v, &format!("{table}.density_kg_per_m3"), true)?;
    }
    if let Some(v) = &raw.drag_coefficient {
        drag.drag_coefficient = f.non_negative(v, &format!("{table}.drag_coefficient"))?;
    }
    if let Some(v) = &raw.turning_angle_deg {
        let a = *v.get_ref();
        if !(a.is_finite() && a.abs() < 90.0) {
            return Err(f.error(
                v.span(),
                format!("{table}.turning_angle_deg"),
                format!("must lie strictly between -90 and 90, got {}", short(a)),
            ));
        }
        drag.turning_angle_deg = a;
    }
    if let Some(v) = &raw.relative_to_ice {
        drag.relative_to_ice = *v.get_ref();
    }
    Ok(drag)
}

fn resolve_forcing(
    f: &SourceFile,
    wind: Option<&Spanned<RawFluid>>,
    ocean: Option<&Spanned<RawFluid>>,
    coriolis: Option<&Spanned<RawCoriolis>>,
    grids: &mut GridContext<'_>,
) -> Result<Forcing, ScenarioError> {
    let mut forcing = Forcing::default();
    if let Some(w) = wind {
        let w = w.get_ref();
        if let Some(v) = &w.sea_surface_height {
            return Err(f.error(
                v.span(),
                "wind.sea_surface_height",
                "belongs in [ocean], not [wind]",
            ));
        }
        for (flag, name) in [
            (&w.sea_surface_tilt, "sea_surface_tilt"),
            (&w.rotational_drag, "rotational_drag"),
        ] {
            if let Some(v) = flag {
                return Err(f.error(
                    v.span(),
                    format!("wind.{name}"),
                    "belongs in [ocean], not [wind]",
                ));
            }
        }
        forcing.wind = resolve_field(f, w, "wind", grids)?;
        forcing.air = resolve_drag(f, w, "wind", forcing.air)?;
    }
    if let Some(o) = ocean {
        let o = o.get_ref();
        forcing.current = resolve_field(f, o, "ocean", grids)?;
        forcing.sea_surface_height = resolve_sea_surface_height(f, o, grids)?;
        forcing.ocean = resolve_drag(f, o, "ocean", forcing.ocean)?;
        if let Some(v) = &o.sea_surface_tilt {
            forcing.sea_surface_tilt = *v.get_ref();
        }
        if let Some(v) = &o.rotational_drag {
            forcing.rotational_drag = *v.get_ref();
        }
    }
    if let Some(c) = coriolis {
        let r = c.get_ref();
        forcing.coriolis = match (&r.latitude_deg, &r.f_per_s) {
            (Some(lat), None) => {
                Coriolis::LatitudeDeg(within(f, lat, "coriolis.latitude_deg", -90.0, 90.0, false)?)
            }
            (None, Some(fp)) => Coriolis::ParameterPerS(f.finite(fp, "coriolis.f_per_s")?),
            _ => {
                return Err(f.error(
                    c.span(),
                    "coriolis",
                    "give exactly one of `latitude_deg` or `f_per_s` (omit [coriolis] for none)",
                ))
            }
        };
    }
    Ok(forcing)
}

fn resolve_walls(
    f: &SourceFile,
    raw: &[Spanned<RawWall>],
    extent: Extent,
) -> Result<Vec<Wall>, ScenarioError> {
    let mut walls: Vec<Wall> = Vec::with_capacity(raw.len());
    for (i, w) in raw.iter().enumerate() {
        let r = w.get_ref();
        let key = |k: &str| format!("wall[{i}].{k}");
        let Some(side_word) = &r.side else {
            return Err(f.error(
                w.span(),
                key("side"),
                "missing: `left`, `right`, `bottom` or `top`",
            ));
        };
        let side = f.keyword(
            &r.side,
            &key("side"),
            &[
                ("left", Side::Left),
                ("right", Side::Right),
                ("bottom", Side::Bottom),
                ("top", Side::Top),
            ],
            Side::Left,
        )?;
        if let Some(other) = walls.iter().find(|o| o.side == side) {
            return Err(f.error(
                side_word.span(),
                key("side"),
                format!(
                    "wall[{}] is already on the {} side",
                    other.index,
                    side.name()
                ),
            ));
        }
        let schedule = match (&r.segment, &r.velocity_m_per_s) {
            (Some(_), Some(v)) => {
                return Err(f.error(
                    v.span(),
                    key("velocity_m_per_s"),
                    "give the wall's motion either as velocity_m_per_s or as [[wall.segment]] \
                     tables, not both",
                ))
            }
            (Some(segments), None) => Some(resolve_schedule(
                f,
                (segments, w.span()),
                &format!("wall[{i}]"),
                false,
                extent,
            )?),
            (None, _) => None,
        };
        let velocity = match (&schedule, &r.velocity_m_per_s) {
            (Some(s), _) => s.velocity_at(0.0).0,
            (None, Some(v)) => {
                let velocity = f.pair(v, &key("velocity_m_per_s"))?;
                // The wall is built as long as its travel: bound that.
                travel_within(f, v, &key("velocity_m_per_s"), velocity, extent, "wall")?;
                velocity
            }
            (None, None) => Vec2::ZERO,
        };
        let control = resolve_control_keys(f, r, i)?;
        let stress = match (&r.normal_stress_n_per_m, control) {
            (None, _) | (_, None) => None,
            (Some(target), Some(control)) => {
                let target = f.in_range(
                    target,
                    &key("normal_stress_n_per_m"),
                    (0.0, MAX_WALL_STRESS_N_PER_M),
                    "N/m",
                )?;
                // The servo sets the normal velocity: none may be given.
                let axis = side.axis();
                let across = |v: Vec2| v[axis] != 0.0;
                let normal_given = match (&schedule, &r.velocity_m_per_s) {
                    (Some(s), _) => s
                        .segments()
                        .iter()
                        .any(|g| across(g.velocity_start) || across(g.velocity_end)),
                    (None, Some(_)) => across(velocity),
                    (None, None) => false,
                };
                if normal_given {
                    let span = r.velocity_m_per_s.as_ref().map_or(w.span(), |v| v.span());
                    return Err(f.error(
                        span,
                        key("velocity_m_per_s"),
                        "a wall holding normal_stress_n_per_m moves across itself as the \
                         stress asks: give its velocity along the wall only",
                    ));
                }
                Some((target, control))
            }
        };
        walls.push(Wall {
            index: i,
            side,
            velocity,
            schedule,
            stress,
            inset_m: match &r.inset_m {
                Some(v) => distance(f, v, &key("inset_m"))?,
                None => 0.0,
            },
            glue_depth_m: match &r.glue_depth_m {
                Some(v) => distance(f, v, &key("glue_depth_m"))?,
                None => 0.0,
            },
            thickness_m: r
                .thickness_m
                .as_ref()
                .map(|v| {
                    // Thicker than the domain adds nothing but segments.
                    let t = f.positive(v, &key("thickness_m"))?;
                    let most = extent.domain.size_m.x.max(extent.domain.size_m.y);
                    if t <= most {
                        return Ok(t);
                    }
                    Err(f.error(
                        v.span(),
                        key("thickness_m"),
                        format!(
                            "{} m is thicker than the domain's larger side, {} m",
                            short(t),
                            sig(most)
                        ),
                    ))
                })
                .transpose()?,
            span: side_word.span(),
            velocity_span: r.velocity_m_per_s.as_ref().map_or(w.span(), |v| v.span()),
            inset_span: r.inset_m.as_ref().map_or(w.span(), |v| v.span()),
        });
    }
    Ok(walls)
}

fn resolve_output(
    f: &SourceFile,
    raw: Option<&RawOutput>,
    duration_s: f64,
) -> Result<(OutputCadence, Vec<Range<usize>>), ScenarioError> {
    let get = |v: Option<&Spanned<f64>>, key: &str, default: f64| {
        v.map_or(Ok(default), |v| f.positive(v, key))
    };
    let mut cadence = OutputCadence {
        snapshot_every_s: get(
            raw.and_then(|o| o.snapshot_every_s.as_ref()),
            "output.snapshot_every_s",
            duration_s / 100.0,
        )?,
        observables_every_s: get(
            raw.and_then(|o| o.observables_every_s.as_ref()),
            "output.observables_every_s",
            duration_s / 1000.0,
        )?,
        checkpoint_every_s: get(
            raw.and_then(|o| o.checkpoint_every_s.as_ref()),
            "output.checkpoint_every_s",
            duration_s / 10.0,
        )?,
        windows: Vec::new(),
    };
    let raw_windows = raw.and_then(|o| o.window.as_deref()).unwrap_or(&[]);
    for (i, w) in raw_windows.iter().enumerate() {
        cadence.windows.push(resolve_window(f, w, i, duration_s)?);
    }
    Ok((cadence, raw_windows.iter().map(|w| w.span()).collect()))
}

/// `[[output.window]]` number `i`: `0 <= from_s < to_s <= duration_s`,
/// and at least one cadence, each > 0.
fn resolve_window(
    f: &SourceFile,
    w: &Spanned<RawOutputWindow>,
    i: usize,
    duration_s: f64,
) -> Result<OutputWindow, ScenarioError> {
    let key = |k: &str| format!("output.window[{i}].{k}");
    if i >= MAX_OUTPUT_WINDOWS {
        return Err(f.error(
            w.span(),
            format!("output.window[{i}]"),
            format!(
                "more than the {MAX_OUTPUT_WINDOWS} windows a scenario may have; \
                 merge neighbouring windows"
            ),
        ));
    }
    let r = w.get_ref();
    let missing = |k: &str, what: &str| f.error(w.span(), key(k), format!("missing: {what}"));
    let from = (r.from_s.as_ref()).ok_or_else(|| missing("from_s", "when the window starts, s"))?;
    let to = (r.to_s.as_ref()).ok_or_else(|| missing("to_s", "when the window ends, s"))?;
    let duration = (0.0, duration_s);
    let from_s = f.in_range(from, &key("from_s"), duration, "s (within the run)")?;
    let to_s = f.in_range(to, &key("to_s"), duration, "s (within the run)")?;
    if to_s <= from_s {
        return Err(f.error(
            to.span(),
            key("to_s"),
            format!(
                "{} s does not come after from_s = {} s: a window ends after it starts",
                short(to_s),
                short(from_s)
            ),
        ));
    }
    let every = |v: &Num, k: &str| v.as_ref().map(|v| f.positive(v, &key(k))).transpose();
    let snapshot_every_s = every(&r.snapshot_every_s, "snapshot_every_s")?;
    let observables_every_s = every(&r.observables_every_s, "observables_every_s")?;
    if snapshot_every_s.is_none() && observables_every_s.is_none() {
        return Err(f.error(
            w.span(),
            format!("output.window[{i}]"),
            "sets no cadence: give snapshot_every_s, observables_every_s or both",
        ));
    }
    Ok(OutputWindow {
        from_s,
        to_s,
        snapshot_every_s,
        observables_every_s,
    })
}
