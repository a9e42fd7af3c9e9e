//! Output size and write cost on a ~1000-floe sheared channel of jittered
//! diamonds: bytes per snapshot per floe (floe arrays and contacts), and
//! the time of each kind of write. The figures are in docs/output.md.
//!
//! Run: `cargo run --release -p floe-io --example io_size`

use std::time::Instant;

use floe_dem::contact_model::ContactModel;
use floe_dem::forcing::NoForcing;
use floe_dem::world::World;
use floe_io::{DomainBox, OutputOptions, RunMetadata, RunWriter};

fn channel(n: usize) -> (World<NoForcing>, DomainBox) {
    let c = floe_fixtures::channel::channel(n, 0.1);
    let model = ContactModel::default();
    let dt = c.dt_s(&model);
    let domain = DomainBox {
        min_m: [c.domain.min.x, c.domain.min.y],
        size_m: [
            c.domain.max.x - c.domain.min.x,
            c.domain.max.y - c.domain.min.y,
        ],
        periodic: [true, false],
    };
    let world = World::new(c.floes, model, NoForcing, c.periodicity, dt).expect("world");
    (world, domain)
}

fn main() {
    let dir = std::env::temp_dir().join(format!("floe_io_size_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    for opts in [
        OutputOptions::default(),
        OutputOptions {
            deflate_level: 0,
            shuffle: false,
            ..OutputOptions::default()
        },
    ] {
        let (mut world, domain) = channel(1000);
        for _ in 0..20 {
            world.step();
        }
        let n = world.floes().len();
        let meta = RunMetadata {
            scenario_toml: String::new(),
            scenario_path: "io_size".into(),
            floe_version: env!("CARGO_PKG_VERSION").into(),
            git_commit: "n/a".into(),
            command_line: std::env::args().collect(),
            threads: 1,
            processes: 1,
            author: "io_size".into(),
            domain,
            inputs: Vec::new(),
        };
        let path = dir.join(format!("deflate{}.h5", opts.deflate_level));
        let _ = std::fs::remove_file(&path);
        let mut w = RunWriter::create(&path, &meta, world.floes(), &opts).expect("create");
        let area = domain.size_m[0] * domain.size_m[1];
        let (snapshots, steps_between) = (40, 10);
        let (mut t_snap, mut t_obs, mut t_ckpt, mut contacts) = (0.0, 0.0, 0.0, 0);
        w.write_snapshot(&world).expect("snapshot");
        w.flush().expect("flush");
        let size0 = std::fs::metadata(&path).expect("size").len();
        for _ in 0..snapshots {
            for _ in 0..steps_between {
                world.step();
                let o = world.observables(area);
                let t = Instant::now();
                w.write_observables(world.steps(), &o).expect("observables");
                t_obs += t.elapsed().as_secs_f64();
            }
            contacts += world.contacts().len();
            let t = Instant::now();
            w.write_snapshot(&world).expect("snapshot");
            t_snap += t.elapsed().as_secs_f64();
        }
        let size1 = std::fs::metadata(&path).expect("size").len();
        let state = world.state();
        let t = Instant::now();
        w.write_checkpoint(state, 3).expect("checkpoint");
        t_ckpt += t.elapsed().as_secs_f64();
        drop(w);
        let f = hdf5::File::open(&path).expect("open");
        let stored = |names: &[&str]| -> u64 {
            names
                .iter()
                .map(|n| f.dataset(n).map_or(0, |d| d.storage_size()))
                .sum()
        };
        let floe_bytes = stored(&[
            "particles/floes/position/value",
            "particles/floes/velocity/value",
            "particles/floes/angle/value",
            "particles/floes/angular_velocity/value",
        ]);
        let contact_bytes = stored(&[
            "contacts/pair",
            "contacts/theta",
            "contacts/mu",
            "contacts/normal_force",
            "contacts/tangential_force",
            "contacts/slip_rate",
            "contacts/overlap_area",
            "contacts/point",
            "contacts/normal",
        ]);
        let per = |b: u64| b as f64 / (snapshots + 1) as f64 / n as f64;
        println!(
            "deflate {} shuffle {}: {n} floes, {:.1} contacts per floe; per snapshot per floe: \
             {:.1} B floe arrays + {:.1} B contacts = {:.1} B stored, file growth {:.1} B",
            opts.deflate_level,
            opts.shuffle,
            contacts as f64 / snapshots as f64 / n as f64,
            per(floe_bytes),
            per(contact_bytes),
            per(floe_bytes + contact_bytes),
            (size1 - size0) as f64 / snapshots as f64 / n as f64,
        );
        println!(
            "  write_snapshot {:.2} ms, write_observables {:.3} ms, write_checkpoint {:.2} ms ({} B)",
            1e3 * t_snap / snapshots as f64,
            1e3 * t_obs / (snapshots * steps_between) as f64,
            1e3 * t_ckpt,
            floe_io::checkpoint::encode(state, &Default::default(), 3).len()
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
