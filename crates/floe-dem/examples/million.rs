//! A 1e6-floe diamond tessellation builds and steps; prints time and memory
//! (docs/performance.md): `cargo run --release -p floe-dem --example million`
use floe_dem::broad_phase::Periodicity;
use floe_dem::contacts::ContactModel;
use floe_dem::floes::Floes;
use floe_dem::tessellation::{DiamondLattice, Rect, ThicknessDistribution};
use floe_dem::world::{stable_time_step, NoForcing, World};
use floe_dem::Vec2;

fn rss_mb() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let kb: f64 = status
        .lines()
        .find(|l| l.starts_with("VmRSS:"))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(0.0);
    kb / 1024.0
}

fn main() {
    let n: f64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1e6);
    let side = 1000.0;
    let width = (n * side * side * 60f64.to_radians().sin() / 4.0).sqrt();
    let t0 = std::time::Instant::now();
    let lattice = DiamondLattice {
        domain: Rect {
            min: Vec2::new(0.0, 0.0),
            max: Vec2::new(4.0 * width, width),
        },
        side_m: side,
        acute_angle_deg: 60.0,
        orientation_deg: 0.0,
        thickness: ThicknessDistribution::Uniform { thickness_m: 1.0 },
        jitter_fraction: 0.0,
        seed: 1,
    };
    let t = lattice.build().expect("lattice");
    let mut floes = Floes::from_polygons(&t.polygons, &t.thickness_m, 917.0).expect("floes");
    drop(t);
    for i in 0..floes.len() {
        let y = floes.position[i].y / width - 0.5;
        floes.velocity[i] = Vec2::new(0.1 * y, -0.001 * y);
    }
    let model = ContactModel::default();
    let dt = 0.5 * stable_time_step(&floes, &model).0;
    let build_s = t0.elapsed().as_secs_f64();
    let mut w = World::new(floes, model, NoForcing, Periodicity::default(), dt).expect("world");
    let t1 = std::time::Instant::now();
    let steps = 5;
    for _ in 0..steps {
        w.step();
    }
    let step_s = t1.elapsed().as_secs_f64() / steps as f64;
    let rss = rss_mb();
    let contact_bytes =
        w.contacts.capacity() * std::mem::size_of::<floe_dem::contacts::ContactRecord>();
    println!(
        "{} floes, {} contacts: build {:.2} s, {:.2} s/step, RSS {:.0} MB = {:.0} B/floe (floe arrays {:.0} B/floe, contact records {:.0} B/floe at {} B each)",
        w.floes.len(),
        w.contacts.len(),
        build_s,
        step_s,
        rss,
        rss * 1048576.0 / w.floes.len() as f64,
        w.floes.heap_bytes() as f64 / w.floes.len() as f64,
        contact_bytes as f64 / w.floes.len() as f64,
        std::mem::size_of::<floe_dem::contacts::ContactRecord>()
    );
}
