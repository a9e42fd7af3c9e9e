//! One full DEM step (broad phase, narrow phase, contact forces with
//! rate-and-state friction, integration) on sheared diamond tessellations.
//!
//! Run: `cargo bench -p floe-dem --bench dem_step`
//! Targets (issue 3): >= 5 M contact updates/s on one core, >= 1.8x that on
//! two threads; figures in docs/performance.md.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use floe_dem::broad_phase::{Period, Periodicity};
use floe_dem::contacts::ContactModel;
use floe_dem::floes::Floes;
use floe_dem::tessellation::{DiamondLattice, Rect, ThicknessDistribution};
use floe_dem::world::{stable_time_step, NoForcing, World};
use floe_dem::Vec2;

/// A channel of ~n diamonds of 1 km side, periodic along x, with a linear
/// shear velocity profile (0.1 m/s across the channel) and 20 warm-up steps
/// so that contacts have formed and slide.
pub fn sheared_channel(n: usize) -> World<NoForcing> {
    sheared_channel_with(n, ContactModel::default())
}

/// [`sheared_channel`] with a given contact model.
pub fn sheared_channel_with(n: usize, model: ContactModel) -> World<NoForcing> {
    let side = 1000.0;
    let cell_area = side * side * 60f64.to_radians().sin();
    let width = (n as f64 * cell_area / 4.0).sqrt();
    let domain = Rect {
        min: Vec2::new(0.0, 0.0),
        max: Vec2::new(4.0 * width, width),
    };
    let lattice = DiamondLattice {
        domain,
        side_m: side,
        acute_angle_deg: 60.0,
        orientation_deg: 0.0,
        thickness: ThicknessDistribution::Uniform { thickness_m: 1.0 },
        jitter_fraction: 0.0,
        seed: 1,
    };
    let t = lattice.build().expect("lattice");
    let mut floes = Floes::from_polygons(&t.polygons, &t.thickness_m, 917.0).expect("floes");
    for i in 0..floes.len() {
        let y = floes.position[i].y / width - 0.5;
        floes.velocity[i] = Vec2::new(0.1 * y, -0.001 * y);
    }
    let dt = 0.5 * stable_time_step(&floes, &model).0;
    let periodic = Periodicity {
        x: Some(Period {
            min_m: 0.0,
            length_m: 4.0 * width,
        }),
        y: None,
    };
    let mut w = World::new(floes, model, NoForcing, periodic, dt).expect("world");
    for _ in 0..20 {
        w.step();
    }
    w
}

fn full_step(c: &mut Criterion) {
    let mut g = c.benchmark_group("dem_step");
    g.sample_size(10);
    for n in [1_000usize, 10_000, 100_000] {
        for threads in [1usize, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut w = pool.install(|| sheared_channel(n));
            let contacts = w.contacts.len();
            // Throughput in contact updates per step.
            g.throughput(Throughput::Elements(contacts as u64));
            eprintln!(
                "n = {} floes, {} contacts, {} threads",
                w.floes.len(),
                contacts,
                threads
            );
            g.bench_with_input(
                BenchmarkId::new(format!("{threads}_threads"), n),
                &n,
                |b, _| b.iter(|| pool.install(|| w.step())),
            );
        }
    }
    g.finish();
}

criterion_group!(benches, full_step);
criterion_main!(benches);
