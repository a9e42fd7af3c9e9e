//! The ice area flux through a gate across a strait, from run files (the
//! Nares Strait study, docs/studies/nares-strait.md).
//!
//! Run: `cargo run --release -p floe-study --example strait_flux -- \
//!        --gate-y-m Y --mouth-y-m Y2 --x-range-m X0,X1 [--scenario S] -o DIR RUN.h5...`
//!
//! For each run: the area of free ice past the gate `y < Y` (floes clipped
//! exactly to the half-plane, floe_analysis::gate_flux) at every snapshot,
//! its rate (the flux, km²/day), and the ice concentration in the mouth, the
//! band `Y2 − 5 km < y < Y2` over `X0 < x < X1` (the channel's width). The
//! strait is *blocked* (an arch holds) at a snapshot interval when ice
//! fills the mouth (concentration above 0.5) but less than 2 % of the
//! run's peak flux passes. With `--scenario`, the panel of winds: the
//! scenario's wind at the gate's centre, the component down the strait
//! (−y) and across it. Writes DIR/flux.csv, DIR/flux.png and prints a
//! summary table.

use std::path::PathBuf;

use floe_analysis::gate_flux::{area_past_gate, flux};
use floe_io::RunFile;
use floe_study::plot::{Axes, Line};

/// Depth of the mouth band, m.
const MOUTH_DEPTH_M: f64 = 5000.0;
/// Concentration above which the mouth is full of ice.
const FULL_MOUTH: f64 = 0.5;
/// Flux below this fraction of the peak counts as blocked.
const BLOCKED_FRACTION: f64 = 0.02;

struct Series {
    name: String,
    hours: Vec<f64>,
    past_km2: Vec<f64>,
    mouth_concentration: Vec<f64>,
}

fn parse_pair(s: &str) -> (f64, f64) {
    let mut it = s
        .split(',')
        .map(|x| x.trim().parse::<f64>().expect("a number"));
    (it.next().expect("X0"), it.next().expect("X1"))
}

fn read(path: &std::path::Path, gate: f64, mouth: f64, xr: (f64, f64)) -> Series {
    let run = RunFile::open(path).expect("run file");
    let n = run.snapshot_count().expect("snapshots");
    let mouth_area = MOUTH_DEPTH_M * (xr.1 - xr.0);
    let mut s = Series {
        name: path
            .file_stem()
            .map_or("run".into(), |x| x.to_string_lossy().into_owned()),
        hours: Vec::with_capacity(n),
        past_km2: Vec::with_capacity(n),
        mouth_concentration: Vec::with_capacity(n),
    };
    for k in 0..n {
        let snap = run.snapshot(k).expect("snapshot");
        let statics = run.floes_at(k).expect("floes");
        let free: Vec<bool> = statics.prescribed.iter().map(|p| !p).collect();
        let polys: Vec<Vec<[f64; 2]>> = (0..statics.len())
            .map(|i| snap.world_vertices(&statics, i))
            .collect();
        s.hours.push(snap.time_s / 3600.0);
        s.past_km2.push(area_past_gate(&polys, &free, gate) / 1e6);
        // Ice in the mouth band: the area past y = mouth − depth minus the
        // area past y = mouth, restricted to the channel's x range.
        let in_channel: Vec<bool> = (0..statics.len())
            .map(|i| free[i] && snap.position[i][0] > xr.0 && snap.position[i][0] < xr.1)
            .collect();
        let band = area_past_gate(&polys, &in_channel, mouth)
            - area_past_gate(&polys, &in_channel, mouth - MOUTH_DEPTH_M);
        s.mouth_concentration.push(band / mouth_area);
    }
    s
}

fn main() {
    let mut gate = None;
    let mut mouth = None;
    let mut xr = None;
    let mut out = PathBuf::from("out/strait_flux");
    let mut runs = Vec::new();
    let mut scenario = None;
    // `--key=value` as well as `--key value` (values may be negative).
    let mut args = std::env::args()
        .skip(1)
        .flat_map(|a| match a.split_once('=') {
            Some((k, v)) if k.starts_with("--") => vec![k.to_string(), v.to_string()],
            _ => vec![a],
        });
    while let Some(a) = args.next() {
        match a.as_str() {
            "--gate-y-m" => gate = args.next().map(|v| v.parse::<f64>().expect("Y")),
            "--mouth-y-m" => mouth = args.next().map(|v| v.parse::<f64>().expect("Y2")),
            "--x-range-m" => xr = args.next().map(|v| parse_pair(&v)),
            "-o" => out = PathBuf::from(args.next().expect("DIR")),
            "--scenario" => scenario = args.next().map(PathBuf::from),
            _ => runs.push(PathBuf::from(a)),
        }
    }
    let (gate, mouth, xr) = (
        gate.expect("--gate-y-m"),
        mouth.expect("--mouth-y-m"),
        xr.expect("--x-range-m"),
    );
    std::fs::create_dir_all(&out).expect("output directory");
    let series: Vec<Series> = runs.iter().map(|r| read(r, gate, mouth, xr)).collect();
    let mut csv =
        String::from("run,time_h,area_past_gate_km2,flux_km2_per_day,mouth_concentration\n");
    let mut flux_lines = Vec::new();
    let mut area_lines = Vec::new();
    let mut mouth_lines = Vec::new();
    println!("| run | ice through the gate, km² | peak flux, km²/day (at h) | hours blocked (mouth full, flux < 2 % of peak) | first blocked, h | longest block, h |");
    println!("|---|---|---|---|---|---|");
    for s in &series {
        let times_s: Vec<f64> = s.hours.iter().map(|h| h * 3600.0).collect();
        let q = flux(&times_s, &s.past_km2).expect("flux");
        let per_day: Vec<(f64, f64)> = q.iter().map(|&(t, f)| (t / 3600.0, f * 86400.0)).collect();
        for (k, &h) in s.hours.iter().enumerate() {
            let f = if k == 0 { f64::NAN } else { per_day[k - 1].1 };
            csv.push_str(&format!(
                "{},{h},{},{f},{}\n",
                s.name, s.past_km2[k], s.mouth_concentration[k]
            ));
        }
        let (t_peak, peak) = per_day
            .iter()
            .fold((0.0, 0.0), |a, &(t, f)| if f > a.1 { (t, f) } else { a });
        let mut blocked_h = 0.0;
        let mut first = None;
        let (mut run_h, mut longest) = (0.0f64, 0.0f64);
        for (k, &(t, f)) in per_day.iter().enumerate() {
            let dt = s.hours[k + 1] - s.hours[k];
            let full =
                s.mouth_concentration[k] > FULL_MOUTH && s.mouth_concentration[k + 1] > FULL_MOUTH;
            if full && f < BLOCKED_FRACTION * peak {
                blocked_h += dt;
                first.get_or_insert(t);
                run_h += dt;
                longest = longest.max(run_h);
            } else {
                run_h = 0.0;
            }
        }
        println!(
            "| {} | {:.0} | {:.0} ({:.1}) | {:.1} | {} | {:.1} |",
            s.name,
            s.past_km2.last().copied().unwrap_or(0.0) - s.past_km2[0],
            peak,
            t_peak,
            blocked_h,
            first.map_or("never".to_string(), |t| format!("{t:.1}")),
            longest
        );
        flux_lines.push(Line::new(s.name.clone(), per_day));
        area_lines.push(Line::new(
            s.name.clone(),
            s.hours
                .iter()
                .zip(&s.past_km2)
                .map(|(&h, &a)| (h, a - s.past_km2[0]))
                .collect(),
        ));
        mouth_lines.push(Line::new(
            s.name.clone(),
            s.hours
                .iter()
                .copied()
                .zip(s.mouth_concentration.iter().copied())
                .collect(),
        ));
    }
    std::fs::write(out.join("flux.csv"), csv).expect("csv");
    let mut wind_panel = Vec::new();
    if let Some(path) = &scenario {
        let sc = floe_scenario::Scenario::load(path).expect("scenario");
        let mut forcing = sc.forcing().clone();
        let at = floe_dem::Vec2::new(0.5 * (xr.0 + xr.1), gate);
        let none = floe_dem::floes::FloeColumns::default();
        let hours = series.first().map_or(vec![], |s| s.hours.clone());
        let (mut down, mut across) = (Vec::new(), Vec::new());
        for &h in &hours {
            forcing.prepare(h * 3600.0, &none).expect("wind");
            let w = forcing.wind.velocity(at, h * 3600.0);
            down.push((h, -w.y));
            across.push((h, w.x));
        }
        wind_panel.push((
            Axes {
                title: "wind at the gate",
                x: "time (h)",
                y: "wind (m/s)",
            },
            vec![
                Line::new("down the strait (-y)", down),
                Line::new("across (+x)", across),
            ],
        ));
    }
    let mut all = wind_panel;
    all.extend([
        (
            Axes {
                title: "ice area through the gate",
                x: "time (h)",
                y: "area (km²)",
            },
            area_lines,
        ),
        (
            Axes {
                title: "area flux through the gate",
                x: "time (h)",
                y: "flux (km²/day)",
            },
            flux_lines,
        ),
        (
            Axes {
                title: "ice concentration in the strait's mouth",
                x: "time (h)",
                y: "concentration",
            },
            mouth_lines,
        ),
    ]);
    floe_study::plot::grid(&out.join("flux.png"), 2, &all).expect("plot");
    println!("wrote {}/flux.csv and flux.png", out.display());
}
