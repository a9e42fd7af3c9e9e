//! Cost of a DEM step against the number of floes (docs/performance.md):
//! the benchmark's sheared channel of diamonds (`floe_fixtures::channel`,
//! regularised rate-and-state) at each size, stepped on one thread and on
//! two in alternation, best of the rounds; writes `step_scaling.csv` and
//! `step_scaling.png` into OUT_DIR.
//!
//! `cargo run --release -p floe-study --example step_scaling -- OUT_DIR [SIZES] [ROUNDS]`
//! with SIZES comma-separated (default 1000,3000,10000,30000,100000,300000,1000000)
//! and ROUNDS (default 3). A round times cycles of 50 steps from the
//! warmed-up pack, about 2e6 floe-steps in all.
use std::error::Error;
use std::path::PathBuf;
use std::time::Instant;

use floe_fixtures::channel::sheared_channel;
use floe_study::plot::{panels, Axes, Line};

/// Steps of a cycle: each starts from the same saved state, so every size
/// is timed on the pack the benchmark sets up, not on one that has sheared
/// for thousands of steps.
const CYCLE_STEPS: usize = 50;

/// Steps taken after the channel's warm-up before the state is saved.
const SETTLE: usize = 30;

/// Cycles timed per round at `n` floes: about two million floe-steps, at
/// least one.
fn cycles(n: usize) -> usize {
    (2_000_000 / (n.max(1) * CYCLE_STEPS)).clamp(1, 100)
}

/// One size's best times, and its mean contact count over the timed steps.
struct Row {
    floes: usize,
    contacts: usize,
    ms_one: f64,
    ms_two: f64,
}

fn main() -> Result<(), Box<dyn Error>> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(
        args.next()
            .ok_or("usage: step_scaling OUT_DIR [SIZES] [ROUNDS]")?,
    );
    let sizes: Vec<usize> = args
        .next()
        .unwrap_or_else(|| "1000,3000,10000,30000,100000,300000,1000000".into())
        .split(',')
        .map(|s| s.trim().parse())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("SIZES must be comma-separated floe counts: {e}"))?;
    let rounds: usize = match args.next() {
        Some(r) => r
            .parse()
            .map_err(|e| format!("ROUNDS must be a count: {e}"))?,
        None => 3,
    };
    std::fs::create_dir_all(&out)?;
    let pools = [1, 2].map(|t| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .expect("thread pool")
    });
    let mut rows = Vec::new();
    for &n in &sizes {
        let mut world = sheared_channel(n);
        // As the dem_step benchmark: the contact count still climbs over
        // the first steps after the warm-up.
        pools[1].install(|| (0..SETTLE).for_each(|_| world.step()));
        let cycles = cycles(n);
        let mut best = [f64::INFINITY; 2];
        let mut contacts = 0;
        // Each round steps copies of the same warmed-up world, one thread
        // then two, so both see the same pack and the machine's drift
        // falls on both alike.
        for _ in 0..rounds {
            for (pool, best) in pools.iter().zip(&mut best) {
                let (mut seconds, mut sum) = (0.0, 0);
                for _ in 0..cycles {
                    let mut w = floe_dem::world::World::resume(
                        world.state().clone(),
                        world.model().clone(),
                        floe_dem::forcing::NoForcing,
                        world.periodicity(),
                    )?;
                    // One untimed step: the pipeline's buffers and the
                    // candidate list are rebuilt after a resume.
                    pool.install(|| w.step());
                    let t = Instant::now();
                    pool.install(|| {
                        for _ in 0..CYCLE_STEPS {
                            w.step();
                            sum += w.contacts().len();
                        }
                    });
                    seconds += t.elapsed().as_secs_f64();
                }
                let steps = cycles * CYCLE_STEPS;
                *best = best.min(seconds * 1e3 / steps as f64);
                contacts = sum / steps;
            }
        }
        let row = Row {
            floes: world.floes().len(),
            contacts,
            ms_one: best[0],
            ms_two: best[1],
        };
        println!(
            "{} floes, {} contacts, {} steps: {:.3} ms/step on 1 thread ({:.0} ns per contact), {:.3} on 2 ({:.2}x)",
            row.floes,
            row.contacts,
            cycles * CYCLE_STEPS,
            row.ms_one,
            row.ms_one * 1e6 / row.contacts as f64,
            row.ms_two,
            row.ms_one / row.ms_two
        );
        rows.push(row);
    }
    let mut csv = String::from("floes,contacts,ms_per_step_1_thread,ms_per_step_2_threads\n");
    for r in &rows {
        csv += &format!("{},{},{},{}\n", r.floes, r.contacts, r.ms_one, r.ms_two);
    }
    std::fs::write(out.join("step_scaling.csv"), csv)?;
    let log_pts = |f: &dyn Fn(&Row) -> f64| {
        rows.iter()
            .map(|r| ((r.floes as f64).log10(), f(r)))
            .collect::<Vec<_>>()
    };
    panels(
        &out.join("step_scaling.png"),
        &[
            (
                Axes {
                    title: "time per step",
                    x: "log10 floes",
                    y: "log10 ms per step",
                },
                vec![
                    Line::markers("1 thread", log_pts(&|r| r.ms_one.log10())),
                    Line::markers("2 threads", log_pts(&|r| r.ms_two.log10())).coloured(1),
                ],
            ),
            (
                Axes {
                    title: "time per contact and step",
                    x: "log10 floes",
                    y: "ns per contact",
                },
                vec![
                    Line::markers("1 thread", log_pts(&|r| r.ms_one * 1e6 / r.contacts as f64)),
                    Line::markers(
                        "2 threads",
                        log_pts(&|r| r.ms_two * 1e6 / r.contacts as f64),
                    )
                    .coloured(1),
                ],
            ),
        ],
    )?;
    println!("wrote {}", out.join("step_scaling.png").display());
    Ok(())
}
