//! `floe grid`: a run's snapshots coarse-grained onto a regular grid
//! (`floe_analysis::grid_fields`) and written as CF NetCDF through the
//! system's NetCDF-C library (the `netcdf` crate): NetCDF-4 files in the
//! classic data model, so that each record is compressed (deflate and
//! shuffle, as the run files) while classic tools' conversions
//! (`nccopy -k classic`) still work. One record per snapshot taken (a
//! [`Cadence`] of its own) along the unlimited `time` dimension (dates
//! when the scenario has a `start_time`); variables
//! on `(time, y, x)` with CF standard names and units where CF has them;
//! cells without ice hold the fill value (`_FillValue`, NetCDF's default
//! for doubles, 9.97e36, rather than NaN, which compares unequal to
//! itself).

use std::path::{Path, PathBuf};

use floe_analysis::grid_fields::{grid_fields, FloeSnapshot, Grid};
use floe_analysis::love_weber::{stress_moments, ContactForces};
use floe_io::RunFile;
use netcdf::{FileMut, Options};

use crate::cadence::Cadence;
use crate::partial_file::PartialFile;
use floe_run::same_file::refuse_overwriting_input;
use floe_run::Error;

/// What `floe grid` was asked to do.
#[derive(Debug, Clone)]
pub struct GridArgs {
    /// The run file.
    pub run: PathBuf,
    /// The NetCDF file to write.
    pub output: PathBuf,
    /// Largest cell size, m (the domain is split into whole cells of at most this).
    pub cell_m: f64,
    /// Which snapshots become records.
    pub cadence: Cadence,
    /// Replace an existing output.
    pub force: bool,
}

/// The value of cells without ice: NetCDF's default fill value for doubles
/// (`NC_FILL_DOUBLE`).
pub const FILL_VALUE: f64 = 9.969_209_968_386_869e36;

/// Deflate level of the fields (with byte shuffle), as the run files'.
const DEFLATE_LEVEL: i32 = 4;

/// Most cells along an axis of a chunk (one record per chunk): 2 MiB
/// chunks at most, so a reader of a small region decompresses little.
const CHUNK_CELLS: usize = 512;

/// Most cells along one axis, and in all.
const MAX_CELLS_PER_AXIS: usize = 4096;
const MAX_CELLS: usize = 4_000_000;

/// The fields written, with their CF standard name (empty: none), units and description.
pub(crate) const FIELDS: [(&str, &str, &str, &str); 11] = [
    (
        "concentration",
        "sea_ice_area_fraction",
        "1",
        "ice area over cell area (the floes' union: a place under two floes counted once)",
    ),
    (
        "thickness",
        "sea_ice_thickness",
        "m",
        "the floes' volume in the cell over its ice area",
    ),
    (
        "u",
        "sea_ice_x_velocity",
        "m s-1",
        "ice velocity along x: the floes' momentum in the cell over their mass",
    ),
    (
        "v",
        "sea_ice_y_velocity",
        "m s-1",
        "ice velocity along y: the floes' momentum in the cell over their mass",
    ),
    (
        "stress_xx",
        "",
        "N m-1",
        "vertically integrated Love-Weber stress, xx (tension positive)",
    ),
    (
        "stress_xy",
        "",
        "N m-1",
        "vertically integrated Love-Weber stress, force x times arm y",
    ),
    (
        "stress_yx",
        "",
        "N m-1",
        "vertically integrated Love-Weber stress, force y times arm x",
    ),
    (
        "stress_yy",
        "",
        "N m-1",
        "vertically integrated Love-Weber stress, yy (tension positive)",
    ),
    (
        "divergence",
        "divergence_of_sea_ice_velocity",
        "s-1",
        "u_x + v_y",
    ),
    (
        "shear",
        "",
        "s-1",
        "maximum shear rate sqrt((u_x - v_y)^2 + (u_y + v_x)^2)",
    ),
    (
        "total_deformation",
        "",
        "s-1",
        "sqrt(divergence^2 + shear^2)",
    ),
];

/// A run's snapshots on a grid, computed record by record: the file
/// `floe grid` writes and the Python package's `floe.grid` both come from
/// it.
pub struct GridPlan {
    /// The run file.
    pub run: RunFile,
    /// The cells.
    pub grid: Grid,
    /// Whether the domain is periodic along x and y.
    pub periodic: [bool; 2],
    /// The domain's size, m.
    pub size_m: [f64; 2],
    /// Every snapshot's time, s.
    pub times: Vec<f64>,
    /// The snapshots taken, one per record.
    pub taken: Vec<usize>,
    /// The scenario's `start_time`, if it has one.
    pub start_time: Option<String>,
}

impl GridPlan {
    /// The grid of at most `cell_m` cells over `run`'s domain and the
    /// snapshots `cadence` takes; a bad cell size or cadence is refused
    /// naming its flag.
    pub fn new(run: &Path, cell_m: f64, cadence: Cadence) -> Result<Self, Error> {
        if !(cell_m.is_finite() && cell_m > 0.0) {
            return Err(Error::Usage(format!(
                "--cell-m {cell_m}: a cell size in m, > 0"
            )));
        }
        cadence.check()?;
        let file = RunFile::open(run)?;
        let meta = file.metadata()?;
        let (min, size) = (meta.domain.min_m, meta.domain.size_m);
        let shape = [0, 1].map(|a| (size[a] / cell_m).ceil().max(1.0));
        if shape.iter().any(|&n| n > MAX_CELLS_PER_AXIS as f64)
            || shape[0] * shape[1] > MAX_CELLS as f64
        {
            return Err(Error::Usage(format!(
                "--cell-m {cell_m}: {} x {} cells for the {} m x {} m domain; at most {MAX_CELLS_PER_AXIS} per axis and {MAX_CELLS} in all",
                shape[0], shape[1], size[0], size[1]
            )));
        }
        let shape = shape.map(|n| n as usize);
        let grid = Grid {
            origin_m: min,
            cell_m: [size[0] / shape[0] as f64, size[1] / shape[1] as f64],
            shape,
        };
        let times = file.snapshot_times()?;
        let taken = cadence.select(&times)?;
        let start_time = floe_scenario::start_time::stored_start_time(&meta.scenario_toml)
            .map_err(|e| Error::Usage(format!("{}: {e}", run.display())))?;
        Ok(GridPlan {
            run: file,
            grid,
            periodic: meta.domain.periodic,
            size_m: size,
            times,
            taken,
            start_time,
        })
    }

    /// The cells' centres along `axis` (0: x, 1: y), m.
    pub fn centres(&self, axis: usize) -> Vec<f64> {
        (0..self.grid.shape[axis])
            .map(|i| self.grid.centre(i, i)[axis])
            .collect()
    }

    /// Record `record`'s fields in the order of [`FIELDS`], row-major
    /// (x fastest); NaN in cells without ice.
    pub fn record(&self, record: usize) -> Result<Vec<Vec<f64>>, Error> {
        let k = self.taken[record];
        let floes = self.run.floes_at(k)?;
        snapshot_fields(&self.run, &floes, &self.grid, self.periodic, self.size_m, k)
    }
}

/// The names of the gridded fields, in the order [`GridPlan::record`]
/// gives them, with their CF standard name (empty: none), units and
/// description.
pub fn field_names() -> &'static [(&'static str, &'static str, &'static str, &'static str)] {
    &FIELDS
}

/// Writes the gridded fields of the snapshots of `args.run` that
/// `args.cadence` takes; returns the output's path.
pub fn write_grid(args: &GridArgs) -> Result<PathBuf, Error> {
    let plan = GridPlan::new(&args.run, args.cell_m, args.cadence)?;
    refuse_overwriting_input(&args.run, "run file", [args.output.as_path()])?;
    if args.output.exists() && !args.force {
        return Err(Error::WouldOverwrite(args.output.clone()));
    }
    let shape = plan.grid.shape;

    // Written beside the target and renamed at the end: a failure leaves
    // no half file under the output's name.
    let partial = PartialFile::new(&args.output);
    let nc = |e: netcdf::Error| Error::NetCdf {
        path: args.output.clone(),
        message: e.to_string(),
    };
    partial.create()?;
    let mut file =
        netcdf::create_with(partial.path(), Options::NETCDF4 | Options::CLASSIC).map_err(nc)?;
    define(&mut file, &args.run, &plan.grid, plan.start_time.as_deref()).map_err(nc)?;
    // The classic model has a define mode to leave before writing data.
    file.enddef().map_err(nc)?;
    for (axis, name) in [(0, "x"), (1, "y")] {
        variable(&mut file, name)
            .and_then(|mut v| v.put_values(&plan.centres(axis), ..))
            .map_err(nc)?;
    }
    for (record, &k) in plan.taken.iter().enumerate() {
        variable(&mut file, "time")
            .and_then(|mut v| v.put_value(plan.times[k], [record]))
            .map_err(nc)?;
        let fields = plan.record(record)?;
        for ((name, ..), mut values) in FIELDS.iter().zip(fields) {
            // Cells without ice (NaN) get the fill value.
            for v in values.iter_mut().filter(|v| v.is_nan()) {
                *v = FILL_VALUE;
            }
            variable(&mut file, name)
                .and_then(|mut v| {
                    v.put_values(&values, [record..record + 1, 0..shape[1], 0..shape[0]])
                })
                .map_err(nc)?;
        }
    }
    file.close().map_err(nc)?;
    partial.commit()
}

/// The dimensions, variables and attributes of a gridded-fields file;
/// with the scenario's `start_time`, a time axis of dates.
fn define(
    file: &mut FileMut,
    run: &Path,
    grid: &Grid,
    start_time: Option<&str>,
) -> Result<(), netcdf::Error> {
    let [nx, ny] = grid.shape;
    file.add_unlimited_dimension("time")?;
    file.add_dimension("y", ny)?;
    file.add_dimension("x", nx)?;
    for (name, text) in [
        ("Conventions", "CF-1.8".to_string()),
        ("title", format!("floe run {} on a grid", run.display())),
        ("source", format!("floe {} (floe grid)", env!("CARGO_PKG_VERSION"))),
        ("comment", "floes coarse-grained onto the grid: each floe clipped exactly to the cells, a place under overlapping floes counted once in the concentration; prescribed floes (walls, blocks, glued rows) left out".to_string()),
    ] {
        file.add_attribute(name, text)?;
    }
    let mut time = file.add_variable::<f64>("time", &["time"])?;
    match start_time {
        // Model time is seconds after start_time, a UTC date the scenario
        // reads in the proleptic Gregorian calendar (also before 1582, where
        // CF's "standard" would turn Julian).
        Some(date) => {
            time.put_attribute("units", format!("seconds since {date}"))?;
            time.put_attribute("calendar", "proleptic_gregorian")?;
            time.put_attribute("standard_name", "time")?;
            time.put_attribute("axis", "T")?;
            time.put_attribute("long_name", "time of the snapshot")?;
        }
        None => {
            time.put_attribute("units", "s")?;
            time.put_attribute("long_name", "time since the start of the run")?;
        }
    }
    for (axis, dim) in [("X", "x"), ("Y", "y")] {
        let mut coordinate = file.add_variable::<f64>(dim, &[dim])?;
        coordinate.put_attribute("units", "m")?;
        coordinate.put_attribute("axis", axis)?;
        coordinate.put_attribute("standard_name", format!("projection_{dim}_coordinate"))?;
        coordinate.put_attribute("long_name", format!("cell centre, {dim}"))?;
    }
    for (name, standard, units, long) in FIELDS {
        let mut field = file.add_variable::<f64>(name, &["time", "y", "x"])?;
        field.set_chunking(&[1, ny.min(CHUNK_CELLS), nx.min(CHUNK_CELLS)])?;
        field.set_compression(DEFLATE_LEVEL, true)?;
        field.set_fill_value(FILL_VALUE)?;
        field.put_attribute("units", units)?;
        field.put_attribute("long_name", long)?;
        if !standard.is_empty() {
            field.put_attribute("standard_name", standard)?;
        }
    }
    Ok(())
}

/// The variable `name`, which [`define`] made.
fn variable<'f>(
    file: &'f mut FileMut,
    name: &str,
) -> Result<netcdf::VariableMut<'f>, netcdf::Error> {
    file.variable_mut(name)
        .ok_or_else(|| netcdf::Error::NotFound(format!("variable {name}")))
}

/// The fields of snapshot `k`, in the order of [`FIELDS`].
fn snapshot_fields(
    run: &RunFile,
    floes: &floe_io::StaticFloes,
    grid: &Grid,
    periodic: [bool; 2],
    period: [f64; 2],
    k: usize,
) -> Result<Vec<Vec<f64>>, Error> {
    let snap = run.snapshot(k)?;
    let contacts = run.contacts(k)?;
    let n = floes.len();
    // Each floe's Love-Weber moment sum f (x) (x_c - x).
    let moment = stress_moments(
        &snap.position,
        &ContactForces {
            pair: &contacts.pair,
            point: &contacts.point,
            normal: &contacts.normal,
            normal_force_n: &contacts.normal_force_n,
            tangential_force_n: &contacts.tangential_force_n,
        },
        [0, 1].map(|a| periodic[a].then_some(period[a])),
    );
    // Free floes, with their periodic images where they cross an edge.
    let (mut vertices, mut position, mut velocity, mut spin, mut thickness, mut moments) = (
        Vec::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
    );
    let lo = grid.origin_m;
    for i in (0..n).filter(|&i| !floes.prescribed[i]) {
        let poly = snap.world_vertices(floes, i);
        let shifts = |axis: usize| -> Vec<f64> {
            if !periodic[axis] {
                return vec![0.0];
            }
            let (min, max) = poly
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                    (a.min(p[axis]), b.max(p[axis]))
                });
            let mut s = vec![0.0];
            if min < lo[axis] {
                s.push(period[axis]);
            }
            if max > lo[axis] + period[axis] {
                s.push(-period[axis]);
            }
            s
        };
        for dx in shifts(0) {
            for &dy in &shifts(1) {
                vertices.push(
                    poly.iter()
                        .map(|p| [p[0] + dx, p[1] + dy])
                        .collect::<Vec<_>>(),
                );
                let [px, py] = snap.position[i];
                position.push([px + dx, py + dy]);
                velocity.push(snap.velocity[i]);
                spin.push(snap.angular_velocity[i]);
                thickness.push(floes.thickness_m[i]);
                // The moment goes with the image's share of the area, so
                // the whole floe's moment is counted once over its images.
                moments.push(moment[i]);
            }
        }
    }
    let fields = grid_fields(
        grid,
        &FloeSnapshot {
            vertices: &vertices,
            position: &position,
            velocity: &velocity,
            angular_velocity: &spin,
            thickness_m: &thickness,
            stress_moment_n_m: Some(&moments),
        },
    )
    .map_err(Error::analysis)?;
    let component = |k: usize| {
        fields
            .stress_n_per_m
            .iter()
            .map(|s| s[k])
            .collect::<Vec<_>>()
    };
    Ok(vec![
        fields.concentration,
        fields.thickness_m,
        fields.velocity.iter().map(|v| v[0]).collect(),
        fields.velocity.iter().map(|v| v[1]).collect(),
        component(0),
        component(1),
        component(2),
        component(3),
        fields.divergence_per_s,
        fields.shear_per_s,
        fields.total_deformation_per_s,
    ])
}
