//! Ice from gridded fields (`[ice] concentration_grid`, `thickness_grid`,
//! `[tessellation] size_distribution`): NetCDF grids written here, read
//! through scenario files, the floes checked against them.
//!
//! `cargo test --release -p floe-scenario --test scenario ice_grid:: -- --nocapture`
//! prints the measured numbers (area fractions, per-cell deviations
//! against keeping each floe with probability c, build times).

use crate::grid_support;

use std::path::Path;
use std::time::Instant;

use floe_dem::floes::Floes;
use floe_dem::tessellation::{fit_power_law, Rect};
use floe_dem::Vec2;
use floe_scenario::{Scenario, Setup};
use grid_support::{axis, Grid};
use rand::{Rng, SeedableRng};

/// Builds the scenario `text` written as `dir/ice.toml` (grid files are
/// found beside it).
fn build(dir: &Path, text: &str) -> Setup {
    let path = dir.join("ice.toml");
    std::fs::write(&path, text).unwrap();
    let scenario = Scenario::load(&path).unwrap_or_else(|e| panic!("{e}"));
    scenario.build().unwrap_or_else(|e| panic!("{e}"))
}

/// A scenario of Voronoi floes of `scale` m over a `w` x `h` m domain,
/// with `ice` as the `[ice]` table's body.
fn voronoi(w: f64, h: f64, scale: f64, ice: &str) -> String {
    format!(
        "duration_s = 10.0\nseed = 5\n\n[domain]\nsize_m = [{w:.1}, {h:.1}]\n\n\
         [tessellation]\nkind = \"voronoi\"\nfloe_scale_m = {scale:.1}\n\n[ice]\n{ice}\n"
    )
}

/// A concentration grid of 1 km cells (nodes at cell centres, half a cell
/// beyond the domain on every side) with values `c(x, y)`.
fn concentration_file(dir: &Path, w: f64, h: f64, c: impl Fn(f64, f64) -> f64) {
    let nx = (w / 1000.0).round() as usize + 2;
    let ny = (h / 1000.0).round() as usize + 2;
    Grid {
        x: axis(-500.0, 1000.0, nx),
        y: axis(-500.0, 1000.0, ny),
        times: None,
        variable: "siconc",
        units: Some("1"),
    }
    .write(&dir.join("conc.nc"), |x, y, _| c(x, y));
}

const CONC: &str = "concentration_grid = { file = \"conc.nc\", variable = \"siconc\" }";

fn free_area(floes: &Floes) -> f64 {
    (0..floes.len())
        .filter(|&i| floes.is_free(i))
        .map(|i| floes.area_m2[i])
        .sum()
}

#[test]
fn ice_only_where_the_left_half_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (20_000.0, 10_000.0);
    concentration_file(dir.path(), w, h, |x, _| if x < w / 2.0 { 1.0 } else { 0.0 });
    let all = build(dir.path(), &voronoi(w, h, 300.0, ""));
    let placed = build(dir.path(), &voronoi(w, h, 300.0, CONC));
    let (a, p) = (all.world.floes(), placed.world.floes());
    // The grid's nodes bracket the middle at 9,500 and 10,500 m: between
    // them the bilinear concentration falls from 1 to 0.
    let right_of = |f: &Floes, x: f64| (0..f.len()).filter(|&i| f.position[i].x > x).count();
    assert_eq!(
        right_of(p, 10_500.0),
        0,
        "ice beyond the concentration's edge"
    );
    let full = |f: &Floes| (0..f.len()).filter(|&i| f.position[i].x < 9_500.0).count();
    assert_eq!(full(p), full(a), "every floe where the concentration is 1");
    let area = free_area(p);
    let half = 0.5 * free_area(a);
    println!(
        "left half: {} of {} floes, ice area {:.4e} m^2 against half the floes' {:.4e} ({:+.3} %)",
        p.len(),
        a.len(),
        area,
        half,
        100.0 * (area / half - 1.0)
    );
    // Within two mean floes of half the area.
    assert!((area - half).abs() < 2.0 * 300.0 * 300.0, "{area} {half}");
    for line in &placed.report {
        println!("{line}");
    }
    assert!(placed
        .report
        .iter()
        .any(|l| l.starts_with("ice from grids: ")));
}

/// Kept minus wanted ice area per 1 km cell (the cell of a floe's
/// centroid), relative to the cell: (rms, largest).
fn per_cell(
    centroids: &[Vec2],
    areas: &[f64],
    kept: &[bool],
    c: impl Fn(f64, f64) -> f64,
    w: f64,
    h: f64,
) -> (f64, f64) {
    let (nx, ny) = ((w / 1000.0) as usize, (h / 1000.0) as usize);
    let mut diff = vec![0.0; nx * ny];
    for ((p, a), k) in centroids.iter().zip(areas).zip(kept) {
        let (i, j) = (
            ((p.x / 1000.0) as usize).min(nx - 1),
            ((p.y / 1000.0) as usize).min(ny - 1),
        );
        diff[j * nx + i] += (if *k { *a } else { 0.0 }) - c(p.x, p.y) * a;
    }
    let rms = (diff.iter().map(|d| d * d).sum::<f64>() / diff.len() as f64).sqrt() / 1e6;
    let largest = diff.iter().map(|d| d.abs()).fold(0.0, f64::max) / 1e6;
    (rms, largest)
}

#[test]
fn a_uniform_concentration_gives_its_area_fraction_and_a_ramp_its_bands() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (40_000.0, 40_000.0);
    // Uniform 0.6: about 25,600 floes of 250 m.
    concentration_file(dir.path(), w, h, |_, _| 0.6);
    let all = build(dir.path(), &voronoi(w, h, 250.0, ""));
    let start = Instant::now();
    let placed = build(dir.path(), &voronoi(w, h, 250.0, CONC));
    let took = start.elapsed().as_secs_f64();
    let (a, p) = (all.world.floes(), placed.world.floes());
    let fraction = free_area(p) / (w * h);
    let of_floes = free_area(p) / free_area(a);
    println!(
        "uniform 0.6: {} of {} floes placed, ice area fraction {fraction:.5} of the domain, \
         {of_floes:.5} of the tessellated area ({took:.2} s to build)",
        p.len(),
        a.len()
    );
    // The tessellation covers the domain but for slivers dropped at its
    // edges (below 0.1 of the mean floe); the selection holds c x area to
    // within twice the largest floe.
    let largest = a.area_m2.iter().copied().fold(0.0, f64::max);
    assert!(
        (of_floes - 0.6).abs() < 2.0 * largest / free_area(a),
        "{of_floes}"
    );
    assert!((fraction - 0.6).abs() < 0.005, "{fraction}");

    // Per 1 km cell (16 floes): error diffusion against independent
    // draws with probability 0.6 (what keeping each floe at random gives).
    let centroids: Vec<Vec2> = a.position.clone();
    let areas: Vec<f64> = a.area_m2.clone();
    // A floe is known by its centroid, bitwise the same in both builds.
    let key = |v: &Vec2| (v.x.to_bits(), v.y.to_bits());
    let placed_at: std::collections::HashSet<(u64, u64)> = p.position.iter().map(key).collect();
    let kept: Vec<bool> = a
        .position
        .iter()
        .map(|v| placed_at.contains(&key(v)))
        .collect();
    assert_eq!(kept.iter().filter(|&&k| k).count(), p.len());
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    let drawn: Vec<bool> = (0..a.len()).map(|_| rng.gen::<f64>() < 0.6).collect();
    let c = |_: f64, _: f64| 0.6;
    let (rms, largest) = per_cell(&centroids, &areas, &kept, c, w, h);
    let (rms_b, largest_b) = per_cell(&centroids, &areas, &drawn, c, w, h);
    println!(
        "per 1 km cell: kept minus wanted area rms {:.2} % (largest {:.2} %) of the cell; \
         independent draws: rms {:.2} % (largest {:.2} %)",
        100.0 * rms,
        100.0 * largest,
        100.0 * rms_b,
        100.0 * largest_b
    );
    assert!(rms < 0.5 * rms_b, "{rms} {rms_b}");
    for line in &placed.report {
        println!("{line}");
    }

    // A ramp: c = x / w, so band [x0, x1] wants (x1² − x0²) / (2 w) x h.
    let dir = tempfile::tempdir().unwrap();
    concentration_file(dir.path(), w, h, |x, _| (x / w).clamp(0.0, 1.0));
    let ramp = build(dir.path(), &voronoi(w, h, 250.0, CONC));
    let r = ramp.world.floes();
    let bands = 8;
    let band = w / bands as f64;
    let mut worst = 0.0f64;
    for b in 0..bands {
        let (x0, x1) = (b as f64 * band, (b + 1) as f64 * band);
        let kept: f64 = (0..r.len())
            .filter(|&i| r.position[i].x >= x0 && r.position[i].x < x1)
            .map(|i| r.area_m2[i])
            .sum();
        // Wanted over the floes of the band: Σ c(centroid) a (the
        // tessellation's floes, slivers at the edges dropped).
        let wanted: f64 = (0..a.len())
            .filter(|&i| a.position[i].x >= x0 && a.position[i].x < x1)
            .map(|i| (a.position[i].x / w).clamp(0.0, 1.0) * a.area_m2[i])
            .sum();
        let exact = (x1 * x1 - x0 * x0) / (2.0 * w) * h;
        println!(
            "ramp band {b}: kept {:.4e} m^2, wanted {:.4e}, integral {:.4e} ({:+.3} %)",
            kept,
            wanted,
            exact,
            100.0 * (kept / exact - 1.0)
        );
        // A band of 5 km x 40 km (200 cells) is visited in many runs of
        // the curve through the cells, each holding its area to twice the
        // largest floe: a few floes over the band.
        assert!((kept - wanted).abs() < 0.005 * band * h, "band {b}");
        worst = worst.max((kept - exact).abs() / (band * h));
    }
    println!(
        "ramp: largest band deviation from the integral {:.3} % of the band",
        100.0 * worst
    );
    assert!(worst < 0.005);
}

#[test]
fn thickness_linear_in_x_is_reproduced_at_the_centroids() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (12_000.0, 8_000.0);
    // Thickness 0.5 m + 0.2 m per km along x, 0.05 m per km along y, on
    // an irregular-looking 700 m grid covering the domain.
    let thick = |x: f64, y: f64| 0.5 + 2e-4 * x + 5e-5 * y;
    Grid {
        x: axis(-350.0, 700.0, 20),
        y: axis(-350.0, 700.0, 14),
        times: Some(3),
        variable: "sithick",
        units: Some("m"),
    }
    .write(&dir.path().join("thick.nc"), |x, y, t| {
        thick(x, y) + t as f64
    });
    let text = voronoi(
        w,
        h,
        400.0,
        "thickness_grid = { file = \"thick.nc\", variable = \"sithick\", time_index = 1 }",
    );
    let setup = build(dir.path(), &text);
    let f = setup.world.floes();
    let mut worst = 0.0f64;
    for i in (0..f.len()).filter(|&i| f.is_free(i)) {
        let p = f.position[i];
        worst = worst.max((f.thickness_m[i] - (thick(p.x, p.y) + 1.0)).abs());
    }
    println!(
        "thickness from a grid linear in x and y: largest error {worst:.2e} m at the centroids"
    );
    assert!(worst < 1e-9, "{worst}");
    assert!(setup
        .report
        .iter()
        .any(|l| l.contains("thickness of the placed floes")));
}

#[test]
fn the_same_seed_gives_bitwise_the_same_floes() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (10_000.0, 10_000.0);
    concentration_file(dir.path(), w, h, |x, y| 0.3 + 0.6 * (x * y / (w * h)));
    let text = voronoi(w, h, 300.0, CONC);
    let a = build(dir.path(), &text);
    let b = build(dir.path(), &text);
    let (fa, fb) = (a.world.floes(), b.world.floes());
    assert_eq!(fa.columns(), fb.columns());
    let bits = |f: &Floes| -> Vec<u64> {
        f.position
            .iter()
            .flat_map(|p| [p.x.to_bits(), p.y.to_bits()])
            .chain(
                f.vertices
                    .iter()
                    .flat_map(|v| [v.x.to_bits(), v.y.to_bits()]),
            )
            .chain(f.thickness_m.iter().map(|h| h.to_bits()))
            .collect()
    };
    assert_eq!(bits(fa), bits(fb));
    // Another seed selects other floes.
    let other = build(dir.path(), &text.replace("seed = 5", "seed = 6"));
    assert_ne!(fa.columns(), other.world.floes().columns());
}

#[test]
fn a_size_distribution_with_a_concentration_reports_both_fits() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (15_000.0, 15_000.0);
    concentration_file(dir.path(), w, h, |_, _| 0.7);
    let text = format!(
        "duration_s = 10.0\nseed = 2\n\n[domain]\nsize_m = [{w:.1}, {h:.1}]\n\n\
         [tessellation]\nkind = \"voronoi\"\n\
         size_distribution = {{ kind = \"power_law\", exponent = 2.0, min_m = 100.0, max_m = 1500.0 }}\n\n\
         [ice]\n{CONC}\n"
    );
    let start = Instant::now();
    let setup = build(dir.path(), &text);
    println!("built in {:.2} s", start.elapsed().as_secs_f64());
    for line in &setup.report {
        println!("{line}");
    }
    let fits: Vec<&String> = setup
        .report
        .iter()
        .filter(|l| l.contains("fitted exponent"))
        .collect();
    assert_eq!(fits.len(), 2, "{:?}", setup.report);
    // The placed floes' exponent, fitted here.
    let f = setup.world.floes();
    let sizes: Vec<f64> = (0..f.len()).map(|i| f.area_m2[i].sqrt()).collect();
    let lo = sizes.iter().copied().fold(100.0, f64::min);
    let fit = fit_power_law(&sizes, lo, 1500.0).unwrap();
    println!(
        "placed floes: fitted exponent {:.3} +- {:.3}",
        fit.exponent, fit.std_error
    );
    assert!((fit.exponent - 2.0).abs() < 4.0 * fit.std_error, "{fit:?}");
    let fraction = free_area(f) / Rect::new(Vec2::ZERO, Vec2::new(w, h)).area_m2();
    assert!((fraction - 0.7).abs() < 0.01, "{fraction}");
}

#[test]
fn ten_thousand_floes_from_a_grid_build_in_seconds() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (25_000.0, 25_000.0);
    concentration_file(dir.path(), w, h, |x, y| {
        // An ice edge along a diagonal, land in one corner.
        if x + y < 4_000.0 {
            f64::NAN
        } else {
            (0.4 + (x + y) / (2.0 * w)).min(1.0)
        }
    });
    Grid {
        x: axis(-500.0, 1000.0, 27),
        y: axis(-500.0, 1000.0, 27),
        times: None,
        variable: "sithick",
        units: Some("cm"),
    }
    .write(&dir.path().join("thick.nc"), |x, _, _| 50.0 + x / 250.0);
    let ice = format!("{CONC}\nthickness_grid = {{ file = \"thick.nc\", variable = \"sithick\" }}");
    let start = Instant::now();
    let without = build(dir.path(), &voronoi(w, h, 200.0, ""));
    let plain = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let with = build(dir.path(), &voronoi(w, h, 200.0, &ice));
    let gridded = start.elapsed().as_secs_f64();
    println!(
        "{} floes tessellated, {} placed from the grids: build {plain:.2} s without the grids, {gridded:.2} s with",
        without.world.floes().len(),
        with.world.floes().len()
    );
    for line in &with.report {
        println!("{line}");
    }
    let f = with.world.floes();
    // Nothing on land; thickness from cm.
    for i in 0..f.len() {
        let p = f.position[i];
        assert!(p.x + p.y > 3_000.0, "floe on land at {p:?}");
        let want = (50.0 + p.x / 250.0) / 100.0;
        assert!((f.thickness_m[i] - want).abs() < 1e-9);
    }
    assert!(with.world.floes().len() > 10_000);
}
