//! Land build time and peak memory against the number of vertices: a
//! synthetic coastline ring (tests/basin/land_support.rs: an island, mainland
//! closed behind by three long straight edges, and a 200 km shore closed
//! 100 km behind by two corners) written as a GeoJSON file,
//! then read ([`floe_basin::read_land`]: parse, project, check simple) and
//! cut into convex pieces of radius at most 1 km ([`floe_basin::Land`]).
//!
//! Run: `cargo run --release -p floe-basin --example land_scaling [-- N...]`
//! (default sizes 10000 100000 300000 1000000). Each size runs in a child
//! process (this program with `--child FILE`), whose peak resident memory
//! (`VmHWM` of /proc/self/status) is the figure given; times are wall
//! clock. The last column, the time over `n log2 n`, stays about constant
//! when the time grows as `n log n`, and so does memory over `n` for
//! memory that grows as `n`.

#[path = "../../../tests/basin/land_support.rs"]
mod land_support;

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

use floe_basin::{read_land, Coordinates, Land};
use land_support::{coast_ring, CoastStyle, Shape};

/// Largest radius of a land piece, m.
const PIECE_RADIUS_M: f64 = 1000.0;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("--child") {
        child(Path::new(&args[1]));
        return;
    }
    let sizes: Vec<usize> = if args.is_empty() {
        vec![10_000, 100_000, 300_000, 1_000_000]
    } else {
        args.iter()
            .map(|a| a.parse().expect("sizes are whole numbers"))
            .collect()
    };
    let dir = std::env::temp_dir().join(format!("land_scaling_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    println!(
        "{:<9} {:>9} {:>8} {:>8} {:>8} {:>8} {:>9} {:>9} {:>10} {:>9}",
        "shape",
        "vertices",
        "read s",
        "build s",
        "total s",
        "peak MB",
        "convex",
        "pieces",
        "ns/nlog2n",
        "bytes/n"
    );
    for shape in [Shape::Island, Shape::Mainland, Shape::Shore] {
        for &n in &sizes {
            let ring = coast_ring(n, 1, shape, CoastStyle::NATURAL);
            let file = dir.join(format!("{shape:?}_{n}.geojson"));
            std::fs::write(&file, geojson(&ring)).expect("the GeoJSON file written");
            let out = Command::new(std::env::current_exe().expect("this program"))
                .arg("--child")
                .arg(&file)
                .output()
                .expect("the child runs");
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            let text = String::from_utf8_lossy(&out.stdout);
            let f: Vec<f64> = text
                .split_whitespace()
                .map(|w| w.parse().expect("numbers"))
                .collect();
            let (read, build, convex, pieces, peak_kb) = (f[0], f[1], f[2], f[3], f[4]);
            let m = ring.len() as f64;
            println!(
                "{:<9} {:>9} {:>8.2} {:>8.2} {:>8.2} {:>8.0} {:>9} {:>9} {:>10.1} {:>9.0}",
                format!("{shape:?}").to_lowercase(),
                ring.len(),
                read,
                build,
                read + build,
                peak_kb / 1024.0,
                convex,
                pieces,
                (read + build) * 1e9 / (m * m.log2()),
                peak_kb * 1024.0 / m
            );
            std::fs::remove_file(&file).ok();
        }
    }
    std::fs::remove_dir(&dir).ok();
}

/// The ring as a GeoJSON polygon in x and y (m), every coordinate written
/// so that it reads back exactly.
fn geojson(ring: &[floe_dem::Vec2]) -> String {
    let mut s = String::with_capacity(ring.len() * 44 + 64);
    s.push_str(r#"{"type": "Polygon", "coordinates": [["#);
    for (k, v) in ring.iter().chain(&ring[..1]).enumerate() {
        if k > 0 {
            s.push_str(", ");
        }
        write!(s, "[{:?}, {:?}]", v.x, v.y).expect("a string takes it");
    }
    s.push_str("]]}\n");
    s
}

/// Reads and builds the land of `file`; prints the seconds to read and to
/// build, the convex and final piece counts, and the peak memory (kB).
fn child(file: &Path) {
    let t = Instant::now();
    let polygons = read_land(file, Coordinates::Xy, None).expect("the land reads");
    let read = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let land = Land::new(polygons, PIECE_RADIUS_M).expect("the land builds");
    let build = t.elapsed().as_secs_f64();
    let status = std::fs::read_to_string("/proc/self/status").expect("/proc/self/status");
    let peak_kb: f64 = status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .expect("VmHWM in /proc/self/status");
    println!(
        "{read} {build} {} {} {peak_kb}",
        land.convex_count,
        land.pieces.len()
    );
}
