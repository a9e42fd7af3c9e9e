//! Builds a 1e6-floe diamond lattice (and a Voronoi field) once and prints
//! the wall-clock time and peak memory. Not a benchmark: one run, no
//! assertions.
//!
//! `cargo run --release -p floe-dem --example tessellation_timing [voronoi_count]`

use floe_dem::tessellation::{DiamondLattice, Rect, ThicknessDistribution, VoronoiFloes};
use floe_dem::Vec2;
use std::time::Instant;

fn peak_rss_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

fn main() {
    let voronoi_count: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(100_000);
    let thickness = ThicknessDistribution::LogNormal {
        mean_m: 1.0,
        std_m: 0.3,
    };
    // 1000 m x 866 m of 60-degree diamonds with 1 m sides: ~1.0e6 floes.
    let lattice = DiamondLattice {
        domain: Rect::from_size(Vec2::new(1e6, 1e6), 1000.0, 866.1),
        side_m: 1.0,
        acute_angle_deg: 60.0,
        orientation_deg: 17.0,
        thickness,
        jitter_fraction: 0.1,
        seed: 1,
    };
    let t0 = Instant::now();
    let (t, rep) = lattice.build_with_report().expect("lattice");
    let dt = t0.elapsed();
    let rel = (t.total_area_m2() - lattice.domain.area_m2()) / lattice.domain.area_m2();
    println!(
        "diamond lattice: {} floes in {:.3} s ({} candidates, {} clipped, {} slivers); area rel err {rel:.1e}; peak RSS {:.0} MB",
        t.len(),
        dt.as_secs_f64(),
        rep.candidate_cells,
        rep.clipped_floes,
        rep.dropped_slivers,
        peak_rss_mb().unwrap_or(f64::NAN)
    );
    drop(t);

    let side = (1e6 * voronoi_count as f64).sqrt() / 1e3;
    let gen = VoronoiFloes {
        domain: Rect::from_size(Vec2::new(1e6, 1e6), side, side),
        count: voronoi_count,
        seed: 1,
        thickness,
        relax_iterations: 0,
    };
    let t0 = Instant::now();
    let v = gen.build().expect("voronoi");
    println!(
        "voronoi: {} floes in {:.3} s; peak RSS {:.0} MB",
        v.len(),
        t0.elapsed().as_secs_f64(),
        peak_rss_mb().unwrap_or(f64::NAN)
    );
}
