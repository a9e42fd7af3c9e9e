//! The narrow phase alone: the overlap of every touching pair of a sheared
//! 1e4-floe diamond channel (the pairs, positions and angles of
//! the DEM step benchmark's channel, `floe_fixtures::channel`, after its warm-up), clipped one after the other.
//!
//! Run: `cargo bench -p floe-dem --bench narrow_phase`
//! Figures in docs/performance.md.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use floe_dem::geometry::{overlap, ClipScratch};
use floe_dem::Vec2;
use floe_fixtures::channel::sheared_channel;

/// One pair as the contact update places it.
struct Pair {
    a: usize,
    b: usize,
    offset: Vec2,
}

fn narrow_phase(c: &mut Criterion) {
    let mut w = sheared_channel(10_000);
    for _ in 0..30 {
        w.step();
    }
    let f = &w.floes();
    let pairs: Vec<Pair> = w
        .contacts()
        .iter()
        .map(|c| Pair {
            a: c.a as usize,
            b: c.b as usize,
            offset: c.image_offset,
        })
        .collect();
    let trig: Vec<(f64, f64)> = f.angle.iter().map(|a| a.sin_cos()).collect();
    let placed = |i: usize, offset: Vec2| f.placed(i, offset, trig[i]);
    let mut g = c.benchmark_group("narrow_phase");
    g.throughput(Throughput::Elements(pairs.len() as u64));
    g.bench_function(
        format!("overlap_of_{}_contact_pairs", pairs.len()),
        |bench| {
            let mut scratch = ClipScratch::default();
            bench.iter(|| {
                let mut area = 0.0;
                for p in &pairs {
                    if let Some(ov) =
                        overlap(placed(p.a, Vec2::ZERO), placed(p.b, p.offset), &mut scratch)
                    {
                        area += ov.area_m2;
                    }
                }
                area
            })
        },
    );
    g.finish();
}

criterion_group!(benches, narrow_phase);
criterion_main!(benches);
