//! How well a stress-controlled wall holds its stress in a real pack: a
//! shear cell of about 250 Voronoi floes (350 m) between rough walls,
//! periodic along x, the top wall sliding at 0.3 m/s and holding 3000 N/m.
//! Prints the wall's stress measured from the contact forces at every step
//! (not from the forces the controller reads): its mean over the second
//! half with a block-averaged standard error, its rms, and the transient.
//!
//! ```text
//! cargo run --release -p floe-scenario --example servo_wall_cell -- LAW E CONTROL [DURATION_S] [SEED] [DT_FACTOR]
//!   LAW: amontons (mu 0.5) | rate-state (tank);  E: Young's modulus, Pa
//!   CONTROL: servo | proportional;  DURATION_S: 24000 (6.7 h)
//!   DT_FACTOR: dt as a fraction of the automatic one (1)
//! ```

use std::path::Path;

use floe_scenario::Scenario;

/// The cell (tests/data/servo_wall_cell.toml).
const CELL: &str = include_str!("../../../tests/data/servo_wall_cell.toml");

/// The cell's scenario text under `law` (`amontons`: mu 0.5;
/// `rate-state`: the tank parameters), with Young's modulus `youngs_pa`,
/// the control `control`, lasting `duration_s`, from `seed`, at
/// `dt_factor` times the automatic time step.
pub fn cell(
    law: &str,
    youngs_pa: f64,
    control: &str,
    duration_s: f64,
    seed: u64,
    dt_factor: f64,
) -> String {
    let law = match law {
        "amontons" => "law = \"amontons\"\nmu = 0.5",
        "rate-state" => "law = \"rate-state\"",
        other => panic!("law {other}: amontons or rate-state"),
    };
    CELL.replace("law = \"amontons\"\nmu = 0.5", law)
        .replace(
            "youngs_modulus_pa = 6.0e6",
            &format!("youngs_modulus_pa = {youngs_pa:e}"),
        )
        .replace(
            "stress_control = \"servo\"",
            &format!("stress_control = \"{control}\""),
        )
        .replace("24000.0", &format!("{duration_s:.1}"))
        .replace("seed = 1", &format!("seed = {seed}"))
        .replace(
            "dt_fraction = 0.5",
            &format!("dt_fraction = {}", 0.5 * dt_factor),
        )
}

/// The compressive stress on the wall of control 0 at each step, N/m,
/// summed from the contact records, and the step's time.
pub fn wall_stress_history(text: &str) -> (Vec<(f64, f64)>, Vec<String>) {
    let s = Scenario::from_text(text, Path::new("cell.toml")).unwrap();
    let setup = s.build().unwrap();
    let mut w = setup.world;
    let control = w.stress_controls()[0].clone();
    let steps = (s.duration_s() / w.dt_s()).round() as usize;
    let mut out = Vec::with_capacity(steps);
    for _ in 0..steps {
        w.step();
        out.push((
            w.time_s(),
            control.stress_from_contacts(w.floes(), w.contacts()),
        ));
    }
    (out, setup.report)
}

/// Mean, block-averaged standard error (the largest over block lengths
/// from 1 to n/8 samples, doubling) and rms of `x`.
pub fn mean_error_rms(x: &[f64]) -> (f64, f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let rms = (x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt();
    let mut error: f64 = 0.0;
    let mut block = 1;
    while x.len() / block >= 8 {
        let means: Vec<f64> = x
            .chunks_exact(block)
            .map(|c| c.iter().sum::<f64>() / block as f64)
            .collect();
        let m = means.iter().sum::<f64>() / means.len() as f64;
        let var = means.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (means.len() - 1) as f64;
        error = error.max((var / means.len() as f64).sqrt());
        block *= 2;
    }
    (mean, error, rms)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 3 {
        eprintln!("usage: servo_wall_cell LAW E CONTROL [DURATION_S] [SEED] [DT_FACTOR]");
        std::process::exit(2);
    }
    let youngs: f64 = args[1].parse().expect("E, Pa");
    let duration: f64 = args
        .get(3)
        .map_or(24000.0, |d| d.parse().expect("duration, s"));
    let seed: u64 = args.get(4).map_or(1, |d| d.parse().expect("seed"));
    let dt_factor: f64 = args.get(5).map_or(1.0, |d| d.parse().expect("dt factor"));
    let text = cell(&args[0], youngs, &args[2], duration, seed, dt_factor);
    let started = std::time::Instant::now();
    let (history, report) = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| wall_stress_history(&text));
    for line in report
        .iter()
        .filter(|l| l.contains("wall[1]") || l.starts_with("dt") || l.starts_with("floes"))
    {
        eprintln!("{line}");
    }
    let target = 3000.0;
    let second: Vec<f64> = history[history.len() / 2..]
        .iter()
        .map(|&(_, s)| s)
        .collect();
    let (mean, error, rms) = mean_error_rms(&second);
    // Transient: the first time the stress averaged over 10 min comes
    // within 10 % of the target; then the share of the second half's
    // 10-min windows outside 10 %.
    let window = history
        .len()
        .min((600.0 / (history[1].0 - history[0].0)).round().max(1.0) as usize);
    let averages: Vec<(f64, f64)> = history
        .chunks(window)
        .map(|w| {
            (
                w[w.len() - 1].0,
                w.iter().map(|&(_, s)| s).sum::<f64>() / w.len() as f64,
            )
        })
        .collect();
    let near = |s: f64| (s - target).abs() <= 0.1 * target;
    let reached = averages.iter().find(|&&(_, s)| near(s)).map(|a| a.0);
    let late = &averages[averages.len() / 2..];
    let outside = late.iter().filter(|&&(_, s)| !near(s)).count();
    println!(
        "{} E={:e} {} seed {} dt x{}: mean {:.1} +- {:.1} N/m ({:+.2} % of target), rms/mean {:.3}, 10-min mean within 10 % from {}, {} of {} later 10-min means outside, {} steps, {:.0} s",
        args[0],
        youngs,
        args[2],
        seed,
        dt_factor,
        mean,
        error,
        100.0 * (mean / target - 1.0),
        rms / mean,
        reached.map_or("never".to_string(), |t| format!("{t:.0} s")),
        outside,
        late.len(),
        history.len(),
        started.elapsed().as_secs_f64()
    );
}
