//! A 1e6-floe diamond tessellation builds and steps; prints time and memory
//! (docs/performance.md): `cargo run --release -p floe-dem --example million`
use floe_fixtures::channel as channel_pack;

/// A `/proc/self/status` memory line in MB: `VmRSS` (resident now) or
/// `VmHWM` (the peak).
fn status_mb(key: &str) -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let kb: f64 = status
        .lines()
        .find(|l| l.starts_with(key))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(0.0);
    kb / 1024.0
}

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let t0 = std::time::Instant::now();
    // The benchmark's sheared channel: build, world, 20 warm-up steps.
    let mut w = channel_pack::sheared_channel(n);
    let build_s = t0.elapsed().as_secs_f64();
    let t1 = std::time::Instant::now();
    let steps = 5;
    for _ in 0..steps {
        w.step();
    }
    let step_s = t1.elapsed().as_secs_f64() / steps as f64;
    let (rss, peak) = (status_mb("VmRSS:"), status_mb("VmHWM:"));
    let record = std::mem::size_of::<floe_dem::contacts::ContactRecord>();
    let per_floe = |bytes: f64| bytes / w.floes().len() as f64;
    println!(
        "{} floes, {} contacts: build + 20 steps {:.2} s, {:.2} s/step, RSS {:.0} MB = {:.0} B/floe, \
         peak RSS {:.0} MB = {:.0} B/floe \
         (floe arrays {:.0} B/floe, contact records {:.0} B/floe at {} B each)",
        w.floes().len(),
        w.contacts().len(),
        build_s,
        step_s,
        rss,
        per_floe(rss * 1048576.0),
        peak,
        per_floe(peak * 1048576.0),
        per_floe(w.floes().heap_bytes() as f64),
        per_floe((w.state().contacts.capacity() * record) as f64),
        record
    );
}
