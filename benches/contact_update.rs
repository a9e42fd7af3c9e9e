//! Cost of one per-contact update (`FrictionLaw::step`), the kernel the DEM
//! calls for every contact of every step.
//!
//! Run: `cargo bench -p floe-friction --bench contact_update`
//! Target (issue 2): median <= 50 ns for rate-and-state in steady sliding,
//! warm-started from the previous step. Results: docs/performance.md.

use criterion::{black_box, criterion_group, criterion_main, BatchSize, Criterion};
use floe_friction::*;

const DT: f64 = 1e-3;

fn lab(form: Form, state_law: StateLaw) -> Law {
    Law::RateState(RateState::new(
        RateStateParams::lishman_2011_lab(),
        form,
        state_law,
    ))
}

fn load(v: f64) -> ContactLoad {
    ContactLoad {
        load_point_velocity_m_per_s: v,
        stiffness_n_per_m: 20e6,
        normal_load_n: 2e3,
    }
}

/// The rate-and-state variants both groups measure.
fn rate_state_cases() -> [(&'static str, Law); 3] {
    [
        (
            "rate_state_published_slip",
            lab(Form::Published, StateLaw::Slip),
        ),
        (
            "rate_state_regularized_slip",
            lab(Form::Regularized, StateLaw::Slip),
        ),
        (
            "rate_state_regularized_aging",
            lab(Form::Regularized, StateLaw::Aging),
        ),
    ]
}

fn steady_sliding(c: &mut Criterion) {
    let mut g = c.benchmark_group("steady_sliding");
    let laws = rate_state_cases().into_iter().chain([
        (
            "rate_dependent",
            Law::RateDependent(RateDependent::lishman_2011(-0.072)),
        ),
        ("amontons", Law::Amontons(Amontons { mu: 0.5 })),
    ]);
    for (name, law) in laws {
        // Lab apparatus at 1 mm/s, already in steady state: each step starts
        // from the previous step's solution.
        let l = load(1e-3);
        let mut state = law.steady_state(1e-3, l.normal_load_n);
        for _ in 0..100 {
            law.step(&mut state, &l, DT);
        }
        g.bench_function(name, |b| {
            b.iter(|| law.step(black_box(&mut state), black_box(&l), black_box(DT)))
        });
    }
    g.finish();
}

fn transients(c: &mut Criterion) {
    let mut g = c.benchmark_group("transients");
    for (name, law) in [
        ("published_slip", lab(Form::Published, StateLaw::Slip)),
        ("regularized_slip", lab(Form::Regularized, StateLaw::Slip)),
    ] {
        // In a hold: the load point has stopped 10 s ago; the slider creeps.
        let hold = load(0.0);
        let mut in_hold = law.steady_state(1e-4, hold.normal_load_n);
        for _ in 0..10_000 {
            law.step(&mut in_hold, &hold, DT);
        }
        g.bench_function(format!("{name}/hold"), |b| {
            b.iter_batched_ref(
                || in_hold,
                |s| law.step(s, black_box(&hold), DT),
                BatchSize::SmallInput,
            )
        });
        // The first step after a 10x velocity step: the warm start is stale.
        let fast = load(1e-3);
        let before_step = law.steady_state(1e-4, fast.normal_load_n);
        g.bench_function(format!("{name}/first_step_after_velocity_step"), |b| {
            b.iter_batched_ref(
                || before_step,
                |s| law.step(s, black_box(&fast), DT),
                BatchSize::SmallInput,
            )
        });
    }
    g.finish();
}

/// Many independent contacts per call, as the DEM steps them: out-of-order
/// execution overlaps their dependency chains, so the cost per contact is
/// lower than one contact stepped after itself (`steady_sliding`).
fn batch_of_contacts(c: &mut Criterion) {
    let mut g = c.benchmark_group("batch_1024_contacts");
    g.throughput(criterion::Throughput::Elements(1024));
    for (name, law) in rate_state_cases() {
        // Contacts in steady sliding at speeds spread over two decades.
        let loads: Vec<ContactLoad> = (0..1024)
            .map(|i| load(1e-4 * 10f64.powf(2.0 * i as f64 / 1024.0)))
            .collect();
        let mut states: Vec<ContactState> = loads
            .iter()
            .map(|l| law.steady_state(l.load_point_velocity_m_per_s, l.normal_load_n))
            .collect();
        for _ in 0..10 {
            for (s, l) in states.iter_mut().zip(&loads) {
                law.step(s, l, DT);
            }
        }
        g.bench_function(name, |b| {
            b.iter(|| {
                let mut sum = 0.0;
                for (s, l) in states.iter_mut().zip(&loads) {
                    sum += law.step(s, l, DT).mu;
                }
                black_box(sum)
            })
        });
    }
    g.finish();
}

criterion_group!(benches, steady_sliding, transients, batch_of_contacts);
criterion_main!(benches);
