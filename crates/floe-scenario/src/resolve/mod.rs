//! From the file as written ([`super::spec`]) to checked values with their
//! defaults: every number is range-checked here, with its location, so that
//! building the world ([`super::build`]) only has to check what depends on
//! several values together ([`super::checks`]). One file per section of
//! the scenario file; `limits.rs` holds the range checks they share.

mod contact;
mod domain;
mod floes;
mod forcing;
mod ice;
pub(crate) mod land;
mod life_cycle;
pub(crate) mod limits;
mod output;
mod walls;

use std::ops::Range;
use std::path::Path;

use floe_dem::contact_model::ContactModel;
use floe_dem::forcing::Forcing;
use floe_dem::tessellation::ThicknessDistribution;
use floe_friction::LawRegistry;
use toml::Spanned;

use crate::domain::Domain;
use crate::error::ScenarioError;
use crate::extent::Extent;
use crate::gridded_inputs::{GridContext, InputFile};
use crate::ice_grid_keys::{resolve_ice_grids, IceGrids};
use crate::numbers::short;
use crate::output_cadence::OutputCadence;
use crate::source_file::SourceFile;
use crate::spec::RawScenario;
use crate::tessellation::{names_text, KINDS};

use contact::resolve_contact;
use domain::resolve_domain;
use floes::resolve_floes;
use forcing::resolve_forcing;
use ice::resolve_ice;
use life_cycle::{
    resolve_cohesion, resolve_floe_stress, resolve_fracture, resolve_ridging, resolve_welding,
};
pub use life_cycle::{FractureSettings, DEFAULT_CHECK_EVERY_S, DEFAULT_MIN_FLOE_AREA_M2};
use limits::count;
use output::resolve_output;
use walls::resolve_walls;

pub use crate::tessellation::{DEFAULT_MIN_AREA_FRACTION, MAX_RELAX_ITERATIONS, MAX_VORONOI_WORK};
pub use contact::YOUNGS_MODULUS_RANGE_PA;
pub(crate) use floes::FloeSource;
pub use floes::LOAD_POINT_STIFFNESS_RANGE_N_PER_M;
pub use ice::{InitialVelocity, DEFAULT_ICE_DENSITY_KG_PER_M3, DEFAULT_THICKNESS_M};
pub(crate) use limits::dem_error;
pub use limits::{MAX_DENSITY_KG_PER_M3, MAX_LENGTH_M, MAX_THICKNESS_M, MIN_THICKNESS_M};
pub use output::MAX_OUTPUT_WINDOWS;
pub use walls::MAX_WALL_STRESS_N_PER_M;
pub(crate) use walls::{Side, Wall};

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
    pub initial_velocity: InitialVelocity,
    pub model: ContactModel,
    pub forcing: Forcing,
    pub walls: Vec<Wall>,
    /// `[map]`: the projection of longitude and latitude onto the plane.
    pub map: Option<floe_basin::MapProjection>,
    /// `[[land]]` tables (the files are read when the floes are built).
    pub land: Vec<land::LandFile>,
    pub output: OutputCadence,
    /// Location of each `[[output.window]]`.
    pub window_spans: Vec<Range<usize>>,
    /// `start_time`.
    pub start_time: Option<String>,
    /// Files read besides the scenario.
    pub inputs: Vec<InputFile>,
    /// The gridded fields, with their keys.
    pub(crate) gridded: Vec<crate::gridded_inputs::GriddedOrigin>,
    /// `[floe_stress]`: the floe stress's time average, if computed.
    pub floe_stress: Option<floe_dem::pipeline::floe_stress::StressFilter>,
    /// `[fracture]`, if floes break.
    pub fracture: Option<FractureSettings>,
    /// Where `[fracture]` stands (for the build's checks).
    pub fracture_spans: life_cycle::FractureSpans,
    /// `[cohesion]`, if floes freeze together.
    pub cohesion: Option<floe_dem::cohesion::Cohesion>,
    /// `[ridging]`, if floes ridge.
    pub ridging: Option<floe_dem::ridging::Ridging>,
    /// `[welding]`, if bonded floes weld.
    pub welding: Option<floe_dem::welding::Welding>,
}
/// Most time steps a run may take unless raised (`floe run --step-limit`):
/// about a day at 1e4 steps/s, beyond which a step count is a typo.
pub const MAX_RUN_STEPS: f64 = 1e9;

/// Most worker threads a file may ask for.
pub const MAX_THREADS: u64 = 1024;
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
        if !floes.kind().is_some_and(|k| k.sea_ice) {
            let kinds = names_text(KINDS.iter().filter(|k| k.sea_ice));
            return Err(f.error(
                g.span.clone(),
                g.key,
                format!(
                    "places the floes of a [tessellation] of kind {kinds}; \
                     not explicit [[floe]] tables or a double-shear set-up"
                ),
            ));
        }
    }
    let model = resolve_contact(f, raw.contact.as_ref(), raw.friction.as_ref(), registry)?;
    let map = land::resolve_map(f, raw.map.as_ref())?;
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
    let land = land::resolve_land(
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
    if let (Some(kind), Some(first)) = (floes.kind(), land.first()) {
        if !kind.sea_ice {
            return Err(f.error(
                first.span.clone(),
                "land[0].file",
                format!("land does not apply to the {} set-up", kind.name),
            ));
        }
    }
    let (output, window_spans) = resolve_output(f, raw.output.as_ref(), duration_s)?;
    let floe_stress = resolve_floe_stress(f, raw.floe_stress.as_ref())?;
    let cohesion = resolve_cohesion(f, raw.cohesion.as_ref())?;
    let ridging = resolve_ridging(f, raw.ridging.as_ref())?;
    let welding = resolve_welding(f, raw.welding.as_ref(), cohesion.as_ref())?;
    if let Some(log) = raw.output.as_ref().and_then(|o| o.ridging_log.as_ref()) {
        if *log.get_ref() && ridging.is_none() {
            return Err(f.error(
                log.span(),
                "output.ridging_log",
                "logs ridging events, and the scenario has no [ridging] table: add one, or drop the key",
            ));
        }
    }
    let (fracture, fracture_spans) = match resolve_fracture(f, raw.fracture.as_ref())? {
        Some((settings, spans)) => (Some(settings), spans),
        None => (
            None,
            life_cycle::FractureSpans {
                table: 0..0,
                min_piece: None,
            },
        ),
    };
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
        floe_stress,
        fracture,
        fracture_spans,
        cohesion,
        ridging,
        welding,
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
