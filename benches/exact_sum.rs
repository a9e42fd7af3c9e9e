//! Cost of an exact, order-independent sum (`floe_dem::exact_sum`) against
//! the naive `+=` loop, over 1e6 random terms of random sign with exponents
//! spread over 2^-60..2^60. Divide the time per iteration by 1e6 for the
//! cost per add (criterion's throughput line gives the adds per second).
//!
//! Run: `cargo bench -p floe-dem --bench exact_sum`

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use floe_dem::exact_sum::ExactSum;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const TERMS: usize = 1_000_000;

fn terms() -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(2015);
    (0..TERMS)
        .map(|_| {
            let x = (1.0 + rng.gen::<f64>()) * 2f64.powi(rng.gen_range(-60..60));
            if rng.gen() {
                x
            } else {
                -x
            }
        })
        .collect()
}

fn exact_sum(c: &mut Criterion) {
    let terms = terms();
    let mut g = c.benchmark_group("sum_of_1e6_random_terms");
    g.throughput(Throughput::Elements(TERMS as u64));
    g.bench_function("naive", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for &x in black_box(&terms) {
                s += x;
            }
            s
        })
    });
    g.bench_function("exact_sum_add", |b| {
        b.iter(|| {
            let mut s = ExactSum::new();
            for &x in black_box(&terms) {
                s.add(x);
            }
            s.value()
        })
    });
    g.finish();
}

criterion_group!(benches, exact_sum);
criterion_main!(benches);
