//! The paper's slide-hold-slide and velocity step through the DEM beside
//! the spring-slider: runs `scenarios/{tank,lab}_double_shear_protocol.toml`
//! (floe_study::double_shear_protocol), draws each hold and step with both
//! models into docs/validation/dem_protocol_{tank,lab}.png and prints the
//! table of docs/friction.md ("Through the DEM"). From the repository root:
//!
//!     cargo run --release -p floe-study --example double_shear_protocols
//!
//! (about two minutes: the lab's 1000 s hold is 26 million steps).

use std::path::Path;

use floe_scenario::Scenario;
use floe_study::double_shear_protocol::{run_protocol, ProtocolRun};
use floe_study::plot::{grid, Axes, Line};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    std::fs::create_dir_all("docs/validation")?;
    println!("| preset | event | steady mu before | peak: DEM, slider | delta mu: DEM, slider | DEM - slider: peak, delta mu |");
    println!("|---|---|---|---|---|---|");
    for preset in ["tank", "lab"] {
        let path = format!("scenarios/{preset}_double_shear_protocol.toml");
        let scenario = Scenario::load(Path::new(&path))?;
        // One thread: a world of four floes gains nothing from more, and a
        // step outside a pool hands each parallel loop to another thread.
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
        let run = pool.install(|| run_protocol(&scenario))?;
        for e in &run.events {
            let (dp, dd) = e.differences();
            let (d, s) = e.delta_mu();
            println!(
                "| {preset} | {} | {:.4} | {:.4}, {:.4} | {:.4}, {:.4} | {:+.2} %, {:+.2} % |",
                e.what,
                e.steady.1,
                e.peak.0,
                e.peak.1,
                d,
                s,
                100.0 * dp,
                100.0 * dd
            );
        }
        draw(preset, &run)?;
    }
    Ok(())
}

/// One panel per event, DEM and slider: a hold from 5 s before its end to
/// the middle of the reslide, a step from 2 s before it, time from the end
/// of the hold or the start of the step.
fn draw(preset: &str, run: &ProtocolRun) -> Result<(), Box<dyn std::error::Error>> {
    let titles: Vec<String> = run
        .events
        .iter()
        .map(|e| format!("{preset}: {}", e.what))
        .collect();
    let mut panels = Vec::new();
    for (e, title) in run.events.iter().zip(&titles) {
        let (w0, w1) = e.peak_window_s;
        let hold = w0 > e.start_s;
        let (origin, from) = if hold {
            (w0, w0 - 5.0)
        } else {
            (e.start_s, e.start_s - 2.0)
        };
        let to = w0 + 0.5 * (w1 - w0);
        let cut = |series: &[(f64, f64)]| -> Vec<(f64, f64)> {
            series
                .iter()
                .filter(|s| s.0 >= from && s.0 <= to)
                .map(|s| (s.0 - origin, s.1))
                .collect()
        };
        let x = if hold {
            "time from the end of the hold (s)"
        } else {
            "time from the step (s)"
        };
        panels.push((
            Axes { title, x, y: "mu" },
            vec![
                Line::new("DEM", cut(&run.dem)),
                Line::new("spring-slider", cut(&run.slider)),
            ],
        ));
    }
    let rows = panels.len().div_ceil(3);
    grid(
        Path::new(&format!("docs/validation/dem_protocol_{preset}.png")),
        rows,
        &panels,
    )?;
    Ok(())
}
