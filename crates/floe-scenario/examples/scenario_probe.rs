//! Builds a scenario file and runs it without output files, timing the
//! steps: `cargo run --release -p floe-scenario --example scenario_probe --
//! scenarios/demo.toml [max_steps] [threads]` (default one thread). The
//! steps run inside a rayon pool, as in `floe run`: stepping from outside
//! the pool costs a thread hand-off per parallel loop (~0.1 ms per step).

use floe_friction::FrictionLaw;
use std::path::PathBuf;
use std::time::Instant;

use floe_scenario::Scenario;

fn main() {
    let mut args = std::env::args().skip(1);
    let path = PathBuf::from(args.next().expect("usage: scenario_probe FILE [max_steps]"));
    let max_steps: Option<u64> = args
        .next()
        .map(|s| s.parse().expect("max_steps"))
        .filter(|&n| n > 0);
    let threads: usize = args.next().map_or(1, |s| s.parse().expect("threads"));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    pool.install(|| probe(&path, max_steps));
}

fn probe(path: &std::path::Path, max_steps: Option<u64>) {
    let scenario = match Scenario::load(path) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let started = Instant::now();
    let setup = match scenario.build() {
        Ok(s) => s,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let build_s = started.elapsed().as_secs_f64();
    for line in &setup.report {
        println!("{line}");
    }
    let mut world = setup.world;
    let total = ((scenario.duration_s() / world.dt_s()).round() as u64).max(1);
    let steps = max_steps.map_or(total, |m| m.min(total));
    let area = scenario.domain().area_m2();
    let report_every = (steps / 10).max(1);
    let started = Instant::now();
    for k in 1..=steps {
        world.step();
        if k % report_every == 0 || k == steps {
            let o = world.observables(area);
            let vmax = world
                .floes()
                .velocity
                .iter()
                .zip(&world.floes().motion)
                .filter(|(_, m)| matches!(m, floe_dem::floes::Motion::Free))
                .map(|(v, _)| v.length())
                .fold(0.0, f64::max);
            println!(
                "t = {:.1} s: KE {:.3e} J, {} contacts, sliding {:.2}, mean mu {:.3}, max speed {:.3e} m/s, stress xx {:.3e} yy {:.3e} N/m",
                world.time_s(),
                o.kinetic_translational_j + o.kinetic_rotational_j,
                o.contacts,
                o.sliding_fraction,
                o.mean_mu,
                vmax,
                o.mean_stress_n_per_m[0],
                o.mean_stress_n_per_m[3]
            );
        }
    }
    let run_s = started.elapsed().as_secs_f64();
    if std::env::var_os("PROBE_CONTACTS").is_some() {
        for c in world.contacts() {
            println!(
                "contact {}-{}: overlap {:.4e} m^2, length {:.4} m, normal [{:.3}, {:.3}], F_n {:.4e} N, F_t {:.4e} N, slip {:.4e} m/s, theta {:.4}",
                c.a, c.b, c.overlap_m2, c.length_m, c.normal.x, c.normal.y, c.normal_force_n, c.tangential_force_n(), c.slip_rate_m_per_s, world.model().law.theta(&c.friction)
            );
        }
        let f = &world.floes();
        for i in 0..f.len() {
            println!(
                "floe {i}: x [{:.6}, {:.6}] v [{:.4e}, {:.4e}] angle {:.3e} omega {:.3e}",
                f.position[i].x,
                f.position[i].y,
                f.velocity[i].x,
                f.velocity[i].y,
                f.angle[i],
                f.angular_velocity[i]
            );
        }
    }
    println!(
        "build {build_s:.2} s; {steps} of {total} steps in {run_s:.2} s ({:.3} ms/step); full run estimate {:.1} s",
        1e3 * run_s / steps as f64,
        run_s / steps as f64 * total as f64
    );
}
