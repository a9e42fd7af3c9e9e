//! The scenario file as written: serde structures that mirror the TOML
//! tables, with every value kept with its location ([`Spanned`]) so that
//! [`super::resolve`] can point at the offending key. Unknown keys are
//! refused everywhere (`deny_unknown_fields`). Every key is documented in
//! docs/scenarios.md.

use std::ops::Range;

use serde::Deserialize;
use toml::Spanned;

use crate::law_table::RawLawTable;

pub use crate::exact::Exact;

/// A number with its location.
pub(crate) type Num = Option<Spanned<f64>>;
/// A word with its location.
pub(crate) type Word = Option<Spanned<String>>;
/// An `[x, y]` pair with its location.
pub(crate) type Pair = Option<Spanned<Exact<f64, 2>>>;
/// A flag with its location.
pub(crate) type Flag = Option<Spanned<bool>>;
/// A count with its location.
pub(crate) type Count = Option<Spanned<i64>>;

/// The whole file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawScenario {
    pub title: Option<Spanned<String>>,
    /// The date of model time 0, for forcing files with dates.
    pub start_time: Option<Spanned<String>>,
    pub seed: Count,
    pub threads: Count,
    pub duration_s: Option<Spanned<f64>>,
    pub dt_s: Num,
    pub dt_fraction: Num,
    pub domain: Option<Spanned<RawDomain>>,
    pub tessellation: Option<Spanned<RawTessellation>>,
    pub floe: Option<Vec<Spanned<RawFloe>>>,
    pub ice: Option<Spanned<RawIce>>,
    pub contact: Option<RawContact>,
    /// `[friction]`: `law`, `preset` and the law's parameters, checked
    /// against its table in the law registry ([`crate::law_table`]).
    pub friction: Option<Spanned<RawLawTable>>,
    pub wind: Option<Spanned<RawFluid>>,
    pub ocean: Option<Spanned<RawFluid>>,
    pub coriolis: Option<Spanned<RawCoriolis>>,
    pub wall: Option<Vec<Spanned<RawWall>>>,
    pub map: Option<Spanned<RawMap>>,
    pub land: Option<Vec<Spanned<RawLand>>>,
    pub output: Option<RawOutput>,
    /// `[floe_stress]`: each floe's stress from its contacts, averaged.
    pub floe_stress: Option<Spanned<RawFloeStress>>,
    /// `[fracture]`: floes that break when their stress leaves a criterion.
    pub fracture: Option<Spanned<RawFracture>>,
    /// `[cohesion]`: floes that freeze together.
    pub cohesion: Option<Spanned<RawCohesion>>,
    /// `[ridging]`: floes that ridge under pressure.
    pub ridging: Option<Spanned<RawRidging>>,
    /// `[welding]`: bonded floes that become one.
    pub welding: Option<Spanned<RawWelding>>,
}

/// `[welding]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawWelding {
    pub after_s: Num,
    pub max_added_area_fraction: Num,
    pub max_area_m2: Num,
    pub max_centre_shift_fraction: Num,
    pub check_every_s: Num,
}

/// `[ridging]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawRidging {
    pub strength_n_per_m: Num,
    pub thickness_exponent: Num,
    pub max_thickness_m: Num,
    pub min_floe_area_m2: Num,
    pub rubble: Option<Spanned<String>>,
}

/// `[cohesion]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCohesion {
    pub quiet_speed_m_per_s: Num,
    pub bond_after_s: Num,
    pub tensile_strength_n_per_m: Num,
    pub shear_strength_n_per_m: Num,
    pub growth_time_s: Num,
}

/// `[fracture]`: which keys apply depends on `criterion`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawFracture {
    pub criterion: Word,
    pub check_every_s: Num,
    pub min_floe_area_m2: Num,
    pub min_piece_area_m2: Num,
    pub pieces: Count,
    pub attempts: Count,
    pub q: Num,
    pub sigma_c_pa: Num,
    pub sigma_11_pa: Num,
    pub p_star_pa_per_m: Num,
    pub c: Num,
    pub strength_thickness: Word,
}

/// `[floe_stress]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawFloeStress {
    pub time_scale_s: Num,
}

/// `[map]`: the model plane of everything given in longitude and latitude.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawMap {
    pub projection: Word,
}

/// `[[land]]`: coastlines and islands from one GeoJSON file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawLand {
    pub file: Word,
    pub coordinates: Word,
}

/// `[domain]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawDomain {
    pub min_m: Pair,
    pub size_m: Pair,
    pub periodic: Option<Spanned<Exact<bool, 2>>>,
}

/// `[tessellation]`: which keys apply depends on `kind`
/// ([`crate::tessellation::KINDS`]).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawTessellation {
    pub kind: Word,
    pub min_area_fraction: Num,
    // diamond
    pub side_m: Num,
    pub diagonals_m: Pair,
    pub acute_angle_deg: Num,
    pub orientation_deg: Num,
    pub jitter_fraction: Num,
    // voronoi
    pub floe_scale_m: Num,
    pub count: Count,
    pub relax_iterations: Count,
    pub fill_fraction: Num,
    // grid
    pub columns: Count,
    pub rows: Count,
    pub gap_m: Num,
    // double-shear
    pub block_m: Pair,
    pub side_block_m: Pair,
    pub pusher_m: Pair,
    pub normal_load_per_face_n: Num,
    pub push_velocity_m_per_s: Num,
    /// `[[tessellation.segment]]`: the double shear's pusher on a schedule.
    pub segment: Option<Vec<Spanned<RawSegment>>>,
    /// voronoi: `size_distribution = { kind = "power_law", exponent, min_m, max_m }`.
    pub size_distribution: Option<Spanned<RawSizeDistribution>>,
}

impl RawTessellation {
    /// Every key but `kind`, in this struct's order, with its location when
    /// given: the kinds of [`crate::tessellation`] say which apply.
    pub fn given(&self) -> [(Option<Range<usize>>, &'static str); 20] {
        fn at<T>(v: &Option<Spanned<T>>) -> Option<Range<usize>> {
            v.as_ref().map(|s| s.span())
        }
        [
            (at(&self.min_area_fraction), "min_area_fraction"),
            (at(&self.side_m), "side_m"),
            (at(&self.diagonals_m), "diagonals_m"),
            (at(&self.acute_angle_deg), "acute_angle_deg"),
            (at(&self.orientation_deg), "orientation_deg"),
            (at(&self.jitter_fraction), "jitter_fraction"),
            (at(&self.floe_scale_m), "floe_scale_m"),
            (at(&self.count), "count"),
            (at(&self.relax_iterations), "relax_iterations"),
            (at(&self.fill_fraction), "fill_fraction"),
            (at(&self.columns), "columns"),
            (at(&self.rows), "rows"),
            (at(&self.gap_m), "gap_m"),
            (at(&self.block_m), "block_m"),
            (at(&self.side_block_m), "side_block_m"),
            (at(&self.pusher_m), "pusher_m"),
            (at(&self.normal_load_per_face_n), "normal_load_per_face_n"),
            (at(&self.push_velocity_m_per_s), "push_velocity_m_per_s"),
            (
                self.segment
                    .as_ref()
                    .and_then(|s| s.first())
                    .map(|s| s.span()),
                "segment",
            ),
            (at(&self.size_distribution), "size_distribution"),
        ]
    }
}

/// `size_distribution = { kind = "power_law", exponent, min_m, max_m }`:
/// floe sizes `sqrt(area)` with `N(>d) ∝ d^−exponent` in `[min_m, max_m]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSizeDistribution {
    pub kind: Word,
    pub exponent: Num,
    pub min_m: Num,
    pub max_m: Num,
}

/// `[[floe]]`: one explicit floe.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawFloe {
    pub vertices_m: Option<Spanned<Vec<Exact<f64, 2>>>>,
    pub box_m: Option<Spanned<Exact<f64, 4>>>,
    pub thickness_m: Num,
    pub velocity_m_per_s: Pair,
    pub angular_velocity_rad_per_s: Num,
    pub prescribed: Flag,
    pub segment: Option<Vec<Spanned<RawSegment>>>,
    pub load_point: Option<Spanned<RawLoadPoint>>,
}

/// `[floe.load_point]`: a spring from a moving point to a free floe.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawLoadPoint {
    pub stiffness_n_per_m: Num,
    pub segment: Option<Vec<Spanned<RawSegment>>>,
}

/// `[ice]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawIce {
    pub thickness_m: Num,
    pub thickness_mean_m: Num,
    pub thickness_std_m: Num,
    pub thickness_range_m: Pair,
    pub density_kg_per_m3: Num,
    pub initial_velocity_m_per_s: Pair,
    pub initial_shear_rate_per_s: Num,
    /// `concentration_grid = { file, variable, time_index, units }`
    pub concentration_grid: Option<Spanned<RawGridField>>,
    /// `thickness_grid = { file, variable, time_index }`
    pub thickness_grid: Option<Spanned<RawGridField>>,
}

/// A field of a NetCDF file: `{ file, variable, time_index, units }`
/// (`units` for a concentration only).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawGridField {
    pub file: Word,
    pub variable: Word,
    pub time_index: Count,
    pub units: Word,
}

/// `[contact]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawContact {
    pub youngs_modulus_pa: Num,
    pub poisson_ratio: Num,
    pub restitution: Num,
    pub new_contact_slip_rate_m_per_s: Num,
    pub sliding_threshold_m_per_s: Num,
    pub memory_s: Num,
}

/// `[wind]` and `[ocean]`: the velocity field and the drag.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawFluid {
    pub velocity_m_per_s: Pair,
    pub time_series: Option<Spanned<RawTimeSeries>>,
    pub shear: Option<Spanned<RawShear>>,
    pub gyre: Option<Spanned<RawGyre>>,
    pub envelope: Option<Spanned<RawEnvelope>>,
    /// A CF NetCDF file of the field, with `variables` (x/east, y/north).
    pub file: Option<Spanned<String>>,
    pub variables: Option<Spanned<Vec<String>>>,
    pub plane_spacing_m: Num,
    pub density_kg_per_m3: Num,
    pub drag_coefficient: Num,
    pub turning_angle_deg: Num,
    pub relative_to_ice: Flag,
    // [ocean] only
    pub sea_surface_height: Option<Spanned<RawGridVariable>>,
    pub sea_surface_tilt: Flag,
    pub rotational_drag: Flag,
}

/// `sea_surface_height = { variable = "zos", file = "ssh.nc" }` (the
/// file defaults to the table's `file`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawGridVariable {
    pub variable: String,
    pub file: Option<String>,
}

/// `time_series = { times_s = [...], velocities_m_per_s = [[u, v], ...] }`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawTimeSeries {
    pub times_s: Vec<f64>,
    pub velocities_m_per_s: Vec<Exact<f64, 2>>,
}

/// `shear = { y_min_m, y_max_m, velocity_at_y_min_m_per_s, velocity_at_y_max_m_per_s }`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawShear {
    pub y_min_m: f64,
    pub y_max_m: f64,
    pub velocity_at_y_min_m_per_s: Exact<f64, 2>,
    pub velocity_at_y_max_m_per_s: Exact<f64, 2>,
}

/// `gyre = { center_m, core_radius_m, max_speed_m_per_s }`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawGyre {
    pub center_m: Exact<f64, 2>,
    pub core_radius_m: f64,
    pub max_speed_m_per_s: f64,
}

/// `envelope = { times_s = [...], factors = [...] }`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawEnvelope {
    pub times_s: Vec<f64>,
    pub factors: Vec<f64>,
}

/// `[coriolis]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCoriolis {
    pub latitude_deg: Num,
    pub f_per_s: Num,
}

/// `[[wall]]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawWall {
    pub side: Option<Spanned<String>>,
    pub velocity_m_per_s: Pair,
    pub inset_m: Num,
    pub thickness_m: Num,
    pub segment: Option<Vec<Spanned<RawSegment>>>,
    pub normal_stress_n_per_m: Num,
    pub stress_control: Option<Spanned<String>>,
    pub stress_gain_m_per_s_per_n_per_m: Num,
    pub servo_mass_kg_per_m: Num,
    pub servo_damping_ratio: Num,
    pub glue_depth_m: Num,
}

/// `[[wall.segment]]`, `[[floe.segment]]`: one piece of a motion schedule.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSegment {
    pub duration_s: Num,
    pub velocity_m_per_s: Pair,
    pub end_velocity_m_per_s: Pair,
    pub angular_velocity_rad_per_s: Num,
    pub end_angular_velocity_rad_per_s: Num,
}

/// `[output]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawOutput {
    pub snapshot_every_s: Num,
    pub observables_every_s: Num,
    pub checkpoint_every_s: Num,
    pub ridging_log: Flag,
    pub window: Option<Vec<Spanned<RawOutputWindow>>>,
}

/// `[[output.window]]`: denser output over a stretch of the run.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawOutputWindow {
    pub from_s: Num,
    pub to_s: Num,
    pub snapshot_every_s: Num,
    pub observables_every_s: Num,
}
