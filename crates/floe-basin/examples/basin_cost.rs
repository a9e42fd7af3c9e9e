//! What gridded forcing and gridded output cost against a DEM step at 1e5
//! floes (issue 22, item 6; figures in docs/performance.md).
//!
//! Run: `cargo run --release -p floe-basin --example basin_cost [FLOES] [THREADS]`
//! (defaults 100000 and 1). With `[FLOES] 1 uniform|files STEPS` it only
//! steps one of the two worlds STEPS times, for instruction counts
//! (`valgrind --tool=callgrind --toggle-collect='*counted_steps*'`;
//! repeatable where wall time on a shared machine is not).
//!
//! - **Forcing lookup.** The same sheared channel of diamonds is stepped
//!   with a uniform wind and current, and with the same wind and current
//!   read from NetCDF files (an x/y grid of 5 km over the domain, hourly
//!   slices, linear in time), in alternated rounds of equal steps (the two
//!   packs evolve alike); the difference of the median step times is the cost of
//!   the files (the per-step slice check, bilinear lookups, slice loads).
//! - **Gridded output.** `floe_analysis::grid_fields` on the pack's
//!   snapshot at 5 km cells (concentration, thickness, velocity, stress,
//!   deformation), timed against the step.

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use floe_analysis::grid_fields::{grid_fields, FloeSnapshot, Grid};
use floe_basin::{FieldRequest, NetcdfSource};
use floe_dem::contact_model::ContactModel;
use floe_dem::floes::Floes;
use floe_dem::forcing::{Forcing, GriddedField, VelocityField};
use floe_dem::periodicity::Periodicity;
use floe_dem::tessellation::Rect;
use floe_dem::world::World;
use floe_dem::Vec2;

const WIND: [f64; 2] = [8.0, -3.0];
const CURRENT: [f64; 2] = [0.05, 0.02];
const ROUNDS: usize = 5;
const STEPS: usize = 10;

fn write_field(path: &Path, names: [&str; 2], value: [f64; 2], lo: Vec2, hi: Vec2, hours: usize) {
    let spacing = 5000.0;
    let nx = ((hi.x - lo.x) / spacing).ceil() as usize + 3;
    let ny = ((hi.y - lo.y) / spacing).ceil() as usize + 3;
    let mut f = netcdf::create(path).expect("create");
    f.add_dimension("time", hours).unwrap();
    f.add_dimension("y", ny).unwrap();
    f.add_dimension("x", nx).unwrap();
    let axis = |n: usize, start: f64| {
        (0..n)
            .map(|k| start + k as f64 * spacing)
            .collect::<Vec<_>>()
    };
    for (name, values, sn) in [
        ("x", axis(nx, lo.x - spacing), "projection_x_coordinate"),
        ("y", axis(ny, lo.y - spacing), "projection_y_coordinate"),
    ] {
        let mut c = f.add_variable::<f64>(name, &[name]).unwrap();
        c.put_attribute("units", "m").unwrap();
        c.put_attribute("standard_name", sn).unwrap();
        c.put_values(&values, ..).unwrap();
    }
    let mut t = f.add_variable::<f64>("time", &["time"]).unwrap();
    t.put_attribute("units", "hours since 2024-03-01 00:00:00")
        .unwrap();
    t.put_values(&(0..hours).map(|h| h as f64).collect::<Vec<_>>(), ..)
        .unwrap();
    for (name, v) in names.iter().zip(value) {
        let data = vec![v as f32; hours * nx * ny];
        let mut var = f.add_variable::<f32>(name, &["time", "y", "x"]).unwrap();
        var.put_attribute("units", "m s-1").unwrap();
        var.put_values(&data, ..).unwrap();
    }
}

fn channel(n: usize) -> (Floes, Periodicity, Rect, f64) {
    let c = floe_fixtures::channel::channel(n, 0.0);
    let dt = c.dt_s(&ContactModel::default());
    (c.floes, c.periodicity, c.domain, dt)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args.next().map_or(100_000, |a| a.parse().expect("FLOES"));
    let threads: usize = args.next().map_or(1, |a| a.parse().expect("THREADS"));
    let count: Option<(String, usize)> = args
        .next()
        .map(|m| (m, args.next().map_or(0, |s| s.parse().expect("STEPS"))));
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build_global()
        .expect("pool");
    let dir = tempfile::tempdir().expect("tempdir");
    let (floes, periodic, domain, dt) = channel(n);
    // Hours enough for every round's steps from the same start.
    let hours = 2 + ((ROUNDS * STEPS) as f64 * dt / 3600.0).ceil() as usize;
    let (lo, hi) = (domain.min, domain.max);
    let wind_nc = dir.path().join("wind.nc");
    let ocean_nc = dir.path().join("ocean.nc");
    write_field(&wind_nc, ["u10", "v10"], WIND, lo, hi, hours);
    write_field(&ocean_nc, ["uo", "vo"], CURRENT, lo, hi, hours);
    let gridded = |path: &Path, vars: &[&str]| {
        let source = NetcdfSource::open(FieldRequest {
            path,
            variables: vars,
            projection: None,
            start_time: Some("2024-03-01 00:00:00"),
            region: (lo, hi),
            plane_spacing_m: None,
            margin_m: 0.0,
            limit: None,
        })
        .expect("source");
        VelocityField::Gridded(Box::new(
            GriddedField::new(Arc::new(source)).expect("field"),
        ))
    };
    let uniform = Forcing {
        wind: VelocityField::Uniform(Vec2::from(WIND)),
        current: VelocityField::Uniform(Vec2::from(CURRENT)),
        ..Forcing::default()
    };
    let from_files = Forcing {
        wind: gridded(&wind_nc, &["u10", "v10"]),
        current: gridded(&ocean_nc, &["uo", "vo"]),
        ..Forcing::default()
    };
    let model = ContactModel::default();
    let mut a = World::new(floes.clone(), model.clone(), uniform, periodic, dt).expect("world");
    let mut b = World::new(floes, model, from_files, periodic, dt).expect("world");
    // The sheared lattice's contacts form in the first steps.
    for _ in 0..20 {
        a.step();
        b.step();
    }
    if let Some((mode, steps)) = count {
        let w: &mut dyn Stepper = if mode == "files" { &mut b } else { &mut a };
        counted_steps(w, steps);
        println!("{mode}: {steps} steps");
        return;
    }
    println!(
        "{} floes, {} contacts, dt {:.3} s, {threads} thread(s); {ROUNDS} alternated rounds of {STEPS} steps",
        a.floes().len(),
        a.contacts().len(),
        dt
    );
    let (mut ta, mut tb) = (Vec::new(), Vec::new());
    for _ in 0..ROUNDS {
        for (w, times) in [
            (&mut a as &mut dyn Stepper, &mut ta),
            (&mut b as &mut dyn Stepper, &mut tb),
        ] {
            let t0 = Instant::now();
            for _ in 0..STEPS {
                w.step_once();
            }
            times.push(t0.elapsed().as_secs_f64() / STEPS as f64);
        }
    }
    let (sa, sb) = (median(ta), median(tb));
    println!(
        "step, uniform forcing:   {:.1} ms\nstep, NetCDF forcing:    {:.1} ms\nforcing files cost:      {:+.2} % of a step",
        1e3 * sa,
        1e3 * sb,
        100.0 * (sb - sa) / sa
    );
    // Of which the per-step preparation (slice check of every floe).
    let t = b.time_s();
    let columns = b.floes().columns().clone();
    let mut forcing = b.forcing().clone();
    let t0 = Instant::now();
    for _ in 0..STEPS {
        forcing.prepare(t, &columns).expect("prepare");
    }
    let prep = t0.elapsed().as_secs_f64() / STEPS as f64;
    println!(
        "  of which the per-step check of the floes on the grids: {:.2} ms",
        1e3 * prep
    );
    // Gridded output of the pack at 5 km cells.
    let f = b.floes();
    let vertices: Vec<Vec<[f64; 2]>> = (0..f.len())
        .map(|i| f.world_vertices(i).iter().map(|v| [v.x, v.y]).collect())
        .collect();
    let position: Vec<[f64; 2]> = f.position.iter().map(|p| [p.x, p.y]).collect();
    let velocity: Vec<[f64; 2]> = f.velocity.iter().map(|p| [p.x, p.y]).collect();
    let snapshot = FloeSnapshot {
        vertices: &vertices,
        position: &position,
        velocity: &velocity,
        angular_velocity: &f.angular_velocity,
        thickness_m: &f.thickness_m,
        stress_moment_n_m: None,
    };
    let cell = 5000.0;
    let grid = Grid {
        origin_m: [lo.x, lo.y],
        cell_m: [cell, cell],
        shape: [
            ((hi.x - lo.x) / cell).ceil() as usize,
            ((hi.y - lo.y) / cell).ceil() as usize,
        ],
    };
    let mut tg = Vec::new();
    for _ in 0..3 {
        let t0 = Instant::now();
        let fields = grid_fields(&grid, &snapshot).expect("grid");
        tg.push(t0.elapsed().as_secs_f64());
        std::hint::black_box(fields);
    }
    let g = median(tg);
    println!(
        "gridded output ({} x {} cells): {:.1} ms a snapshot = {:.1} steps; at one snapshot per 100 steps {:.2} % of a step",
        grid.shape[0],
        grid.shape[1],
        1e3 * g,
        g / sa,
        100.0 * g / (100.0 * sa)
    );
}

/// The steps whose instructions are counted.
#[inline(never)]
fn counted_steps(w: &mut dyn Stepper, steps: usize) {
    for _ in 0..steps {
        w.step_once();
    }
}

/// A world of either forcing, stepped.
trait Stepper {
    fn step_once(&mut self);
}

impl<F: floe_dem::forcing::ExternalForces> Stepper for World<F> {
    fn step_once(&mut self) {
        self.step();
    }
}
