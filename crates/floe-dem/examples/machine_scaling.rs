//! How far this machine scales an ideal parallel loop from one thread to
//! two: independent `exp`, `ln_1p` and `sqrt` over 1e7 numbers with rayon,
//! no shared data, alternating one and two threads. The speed-up of the DEM
//! step (docs/performance.md) is to be read against it. Then the same work
//! cut into short parallel regions (1e4 numbers, about 0.1 ms on one
//! thread, a thousand in a row), as a small DEM step is: their speed-up
//! also pays for waking the pool's threads at every region.
//!
//! Run: `cargo run --release -p floe-dem --example machine_scaling -- [n] [pairs]`

use rayon::prelude::*;
use std::time::Instant;

fn work(n: usize) -> f64 {
    (0..n)
        .into_par_iter()
        .with_min_len(1024)
        .map(|i| {
            let x = i as f64 * 1e-6;
            (x.exp() + x.ln_1p()).sqrt()
        })
        .sum()
}

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args
        .next()
        .and_then(|a| a.parse().ok())
        .unwrap_or(10_000_000);
    let pairs: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(6);
    let pools: Vec<rayon::ThreadPool> = [1, 2]
        .iter()
        .map(|&t| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .expect("thread pool")
        })
        .collect();
    let time = |pool: &rayon::ThreadPool| {
        let t = Instant::now();
        let sum = pool.install(|| work(n));
        (t.elapsed().as_secs_f64() * 1e3, sum)
    };
    let mut ratios = Vec::new();
    for _ in 0..pairs {
        let (one, s1) = time(&pools[0]);
        let (two, s2) = time(&pools[1]);
        let ratio = one / two;
        ratios.push(ratio);
        println!(
            "1 thread {one:.1} ms, 2 threads {two:.1} ms: {ratio:.2}x (sums {s1:.6e} {s2:.6e})"
        );
    }
    summary("one long region", &mut ratios);
    let short = |pool: &rayon::ThreadPool| {
        let t = Instant::now();
        let sum: f64 = pool.install(|| (0..1000).map(|_| work(10_000)).sum());
        (t.elapsed().as_secs_f64() * 1e3, sum)
    };
    let mut ratios = Vec::new();
    for _ in 0..pairs {
        let (one, _) = short(&pools[0]);
        let (two, _) = short(&pools[1]);
        ratios.push(one / two);
        println!(
            "1,000 short regions: 1 thread {one:.1} ms, 2 threads {two:.1} ms: {:.2}x",
            one / two
        );
    }
    summary("short regions", &mut ratios);
}

/// Prints the range and median of the speed-ups.
fn summary(what: &str, ratios: &mut [f64]) {
    ratios.sort_by(f64::total_cmp);
    let n = ratios.len();
    println!(
        "speed-up over {n} pairs, {what}: {:.2}-{:.2}x, median {:.2}x",
        ratios[0],
        ratios[n - 1],
        ratios[n / 2]
    );
}
