//! The halo of a scenario's decomposition into K subdomains: floes per
//! process, ghosts, neighbours and bytes per step, for the weak-scaling
//! projection of docs/hpc.md. Threads stand in for the processes (the
//! decomposition is the one `mpirun -np K` makes).
//!
//! `cargo run --release -p floe-parallel --example halo_census -- SCENARIO K...`

use floe_parallel::{DistributedWorld, Settings, ThreadComm};
use floe_scenario::Scenario;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some((path, ks)) = args.split_first() else {
        eprintln!("usage: halo_census SCENARIO K...");
        std::process::exit(2);
    };
    let scenario = Scenario::load(std::path::Path::new(path)).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(2)
    });
    let setup = scenario.build().expect("the scenario builds");
    let (state, model, forcing, periodicity) = setup.world.into_parts();
    println!("| processes | free floes per process | ghosts per process (mean, max) | ghost fraction | walls and land on every process | neighbours (max) | halo bytes per step (max) |");
    println!("|---|---|---|---|---|---|---|");
    for k in ks {
        let k: usize = k.parse().expect("a process count");
        let stats = ThreadComm::run(k, |comm| {
            let d = DistributedWorld::from_whole(
                state.clone(),
                model.clone(),
                forcing.clone(),
                periodicity,
                comm,
                Settings::default(),
            )
            .expect("the decomposition");
            d.stats()
        });
        let owned = stats.iter().map(|s| s.owned).sum::<usize>() as f64 / k as f64;
        let ghosts = stats.iter().map(|s| s.ghosts).sum::<usize>() as f64 / k as f64;
        let max_ghosts = stats.iter().map(|s| s.ghosts).max().unwrap_or(0);
        let neighbours = stats.iter().map(|s| s.neighbours).max().unwrap_or(0);
        let bytes = stats.iter().map(|s| s.halo_bytes).max().unwrap_or(0);
        println!(
            "| {k} | {owned:.0} | {ghosts:.0}, {max_ghosts} | {:.3} | {} | {neighbours} | {bytes} |",
            ghosts / owned,
            stats[0].prescribed
        );
    }
}
