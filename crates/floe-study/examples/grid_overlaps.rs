//! How many floes overlap where, in a run's snapshots: per record, the
//! number of sets of 2, 3, ... free floes with a common overlap (the terms
//! of `floe grid`'s concentration, floe_analysis::grid_fields), how far the
//! largest concentration is above 1, and (floes of one thickness) the
//! largest sum of the floes' own areas in a cell over the cell's area,
//! which the concentration was before overlaps were counted once.
//! Periodic images are left out.
//!
//! `cargo run --release -p floe-study --example grid_overlaps -- RUN.h5 CELL_M`

use std::path::Path;

use floe_analysis::grid_fields::{grid_fields, FloeSnapshot, Grid};
use floe_io::RunFile;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let [_, path, cell] = &args[..] else {
        return Err("usage: grid_overlaps RUN.h5 CELL_M".into());
    };
    let cell: f64 = cell.parse()?;
    let run = RunFile::open(Path::new(path))?;
    let meta = run.metadata()?;
    let floes = run.static_floes()?;
    let count = run.snapshot_count()?;
    if count > 0 && run.floes_at(count - 1)?.id != floes.id {
        return Err(
            format!("{path}: its floes broke; this check reads a fixed set of floes").into(),
        );
    }
    let free: Vec<usize> = (0..floes.len()).filter(|&i| !floes.prescribed[i]).collect();
    let (min, size) = (meta.domain.min_m, meta.domain.size_m);
    let shape = [0, 1].map(|a| (size[a] / cell).ceil().max(1.0) as usize);
    let grid = Grid {
        origin_m: min,
        cell_m: [0, 1].map(|a| size[a] / shape[a] as f64),
        shape,
    };
    let thickness: Vec<f64> = free.iter().map(|&i| floes.thickness_m[i]).collect();
    println!("record  time_s  sets_of_2_3_..  max_c-1  max_own_area/cell");
    for k in 0..run.snapshot_count()? {
        let snap = run.snapshot(k)?;
        let of = |f: &dyn Fn(usize) -> [f64; 2]| free.iter().map(|&i| f(i)).collect::<Vec<_>>();
        let vertices: Vec<Vec<[f64; 2]>> = free
            .iter()
            .map(|&i| snap.world_vertices(&floes, i))
            .collect();
        let fields = grid_fields(
            &grid,
            &FloeSnapshot {
                vertices: &vertices,
                position: &of(&|i| snap.position[i]),
                velocity: &of(&|i| snap.velocity[i]),
                angular_velocity: &free
                    .iter()
                    .map(|&i| snap.angular_velocity[i])
                    .collect::<Vec<_>>(),
                thickness_m: &thickness,
                stress_moment_n_m: None,
            },
        )?;
        // Floes of one thickness h: their own area in a cell is c h / h.
        let one = thickness
            .iter()
            .all(|h| *h == thickness[0])
            .then(|| thickness[0]);
        let (c_max, own_max) = fields
            .concentration
            .iter()
            .zip(&fields.thickness_m)
            .filter(|(c, _)| **c > 0.0)
            .fold((0.0_f64, 0.0_f64), |(a, b), (c, h)| {
                (a.max(*c), b.max(one.map_or(f64::NAN, |t| c * h / t)))
            });
        println!(
            "{k:6}  {:6.0}  {:?}  {:.1e}  {:.4}",
            snap.time_s,
            fields.overlap_sets,
            c_max - 1.0,
            own_max
        );
    }
    Ok(())
}
