//! Floe count, sizes, thickness and ridged volume against time in a box
//! under uniaxial compression, from run files, by variant (seeds averaged):
//! the SubZero compression study, docs/studies/uniaxial-compression.md.
//!
//! Run: `cargo run --release -p floe-study --example compression_box -- \
//!        -o DIR LABEL=RUN.h5,RUN.h5,... [LABEL=...]`
//!
//! Per variant and snapshot, over its runs (seeds): free floes, their median
//! size sqrt(A), their area-weighted mean and largest thickness, and the
//! ice volume ridging moved onto floes and lost to the coast (as fractions
//! of the start's free volume), as mean and standard deviation. Writes
//! DIR/compression.csv, DIR/compression.png and prints the end values.

use std::path::PathBuf;

use floe_io::RunFile;
use floe_study::plot::{Axes, Line};

/// One run's series, one entry per snapshot.
#[derive(Default)]
struct Run {
    hours: Vec<f64>,
    floes: Vec<f64>,
    median_m: Vec<f64>,
    mean_h: Vec<f64>,
    max_h: Vec<f64>,
    to_floes: Vec<f64>,
    to_coast: Vec<f64>,
    fractures: f64,
}

fn read(path: &std::path::Path) -> Run {
    let run = RunFile::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let n = run.snapshot_count().expect("snapshots");
    let ridged = run.observable("ridged_volume").ok();
    let mut r = Run::default();
    let mut v0 = None;
    for k in 0..n {
        let snap = run.snapshot(k).expect("snapshot");
        let s = run.floes_at(k).expect("floes");
        let free: Vec<usize> = (0..s.len()).filter(|&i| !s.prescribed[i]).collect();
        let area: f64 = free.iter().map(|&i| s.area_m2[i]).sum();
        let volume: f64 = free.iter().map(|&i| s.area_m2[i] * s.thickness_m[i]).sum();
        let v0 = *v0.get_or_insert(volume);
        let mut sizes: Vec<f64> = free.iter().map(|&i| s.area_m2[i].sqrt()).collect();
        sizes.sort_by(f64::total_cmp);
        r.hours.push(snap.time_s / 3600.0);
        r.floes.push(free.len() as f64);
        r.median_m
            .push(sizes.get(sizes.len() / 2).copied().unwrap_or(f64::NAN));
        r.mean_h.push(volume / area);
        r.max_h
            .push(free.iter().map(|&i| s.thickness_m[i]).fold(0.0, f64::max));
        let (to_floes, to_coast) = ridged
            .as_ref()
            .and_then(|o| {
                // The last sample at or before the snapshot (the cadences
                // need not meet: observables every 300 s are 589 steps at
                // one time step, 86 at another).
                let j = o
                    .step
                    .partition_point(|&st| st <= snap.step)
                    .checked_sub(1)?;
                Some((o.value[2 * j], o.value[2 * j + 1]))
            })
            .unwrap_or((0.0, 0.0));
        r.to_floes.push(to_floes / v0);
        r.to_coast.push(to_coast / v0);
    }
    r.fractures =
        run.fractures()
            .map_or(0, |f| f.iter().filter(|e| !e.piece_ids.is_empty()).count()) as f64;
    r
}

/// One of a run's series.
type Field = dyn Fn(&Run) -> &Vec<f64>;

/// Mean and sample standard deviation.
fn stats(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    let v = if x.len() > 1 {
        x.iter().map(|a| (a - m).powi(2)).sum::<f64>() / (n - 1.0)
    } else {
        0.0
    };
    (m, v.sqrt())
}

fn main() {
    let mut out = PathBuf::from("out/compression_box");
    let mut variants: Vec<(String, Vec<Run>)> = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        if a == "-o" {
            out = PathBuf::from(args.next().expect("DIR"));
        } else {
            let (label, files) = a.split_once('=').expect("LABEL=RUN.h5,...");
            let runs = files
                .split(',')
                .map(|f| read(std::path::Path::new(f)))
                .collect();
            variants.push((label.to_string(), runs));
        }
    }
    std::fs::create_dir_all(&out).expect("output directory");
    let names = [
        "free floes",
        "median sqrt(A) m",
        "mean h m",
        "max h m",
        "to floes",
        "to coast",
    ];
    let mut csv = String::from("variant,time_h");
    for n in names {
        csv.push_str(&format!(",{n} mean,{n} sd"));
    }
    csv.push('\n');
    let mut panels: Vec<Vec<Line>> = vec![Vec::new(); 4];
    println!("| variant | runs | free floes at the end | median sqrt(A), km | mean h, m | max h, m | volume ridged onto floes | lost to the coast | floes broken |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for (label, runs) in &variants {
        let n = runs.iter().map(|r| r.hours.len()).min().unwrap_or(0);
        let column = |k: usize, f: &Field| -> (f64, f64) {
            stats(&runs.iter().map(|r| f(r)[k]).collect::<Vec<_>>())
        };
        let fields: [&Field; 6] = [
            &|r| &r.floes,
            &|r| &r.median_m,
            &|r| &r.mean_h,
            &|r| &r.max_h,
            &|r| &r.to_floes,
            &|r| &r.to_coast,
        ];
        let mut lines: Vec<Vec<(f64, f64)>> = vec![Vec::new(); 6];
        for k in 0..n {
            let h = runs[0].hours[k];
            csv.push_str(&format!("{label},{h}"));
            for (j, f) in fields.iter().enumerate() {
                let (m, sd) = column(k, f);
                csv.push_str(&format!(",{m},{sd}"));
                lines[j].push((h, m));
            }
            csv.push('\n');
        }
        let end = |j: usize| column(n - 1, fields[j]);
        let (f, fs) = end(0);
        let (md, mds) = end(1);
        let (mh, mhs) = end(2);
        let (xh, xhs) = end(3);
        let (tf, tfs) = end(4);
        let (tc, tcs) = end(5);
        let (br, brs) = stats(&runs.iter().map(|r| r.fractures).collect::<Vec<_>>());
        println!(
            "| {label} | {} | {f:.0} ± {fs:.0} | {:.2} ± {:.2} | {mh:.3} ± {mhs:.3} | {xh:.2} ± {xhs:.2} | {:.1} ± {:.1} % | {:.1} ± {:.1} % | {br:.0} ± {brs:.0} |",
            runs.len(),
            md / 1e3,
            mds / 1e3,
            100.0 * tf,
            100.0 * tfs,
            100.0 * tc,
            100.0 * tcs
        );
        let [floes, median, mean_h, max_h, _, to_coast] =
            <[Vec<(f64, f64)>; 6]>::try_from(lines).expect("six");
        panels[0].push(Line::new(label.clone(), floes));
        panels[1].push(Line::new(
            label.clone(),
            median.into_iter().map(|(h, m)| (h, m / 1e3)).collect(),
        ));
        panels[2].push(Line::new(format!("{label} mean"), mean_h));
        panels[2].push(Line::new(format!("{label} max"), max_h));
        panels[3].push(Line::new(
            label.clone(),
            to_coast.into_iter().map(|(h, v)| (h, 100.0 * v)).collect(),
        ));
    }
    std::fs::write(out.join("compression.csv"), csv).expect("csv");
    let titles = [
        ("free floes", "floes"),
        ("median floe size sqrt(A)", "km"),
        ("free ice thickness (mean, largest)", "m"),
        (
            "ice lost to the coast by ridging",
            "% of the start's volume",
        ),
    ];
    let all: Vec<(Axes, Vec<Line>)> = titles
        .iter()
        .zip(panels)
        .map(|(&(title, y), lines)| {
            (
                Axes {
                    title,
                    x: "time (h)",
                    y,
                },
                lines,
            )
        })
        .collect();
    floe_study::plot::grid(&out.join("compression.png"), 2, &all).expect("plot");
    println!(
        "wrote {}/compression.csv and compression.png",
        out.display()
    );
}
