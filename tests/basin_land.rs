//! Land from GeoJSON (floe-basin): the convex decomposition is exact (the
//! pieces are convex, their areas sum to the polygon's, and they do not
//! overlap), also after cutting the pieces to a floe's size; and a
//! longitude-latitude file lands where the map projection puts it; a
//! vertex of a long coast moved onto another edge or vertex is refused as
//! a pairwise test says.
//! `cargo test --release -p floe-basin --test basin_land -- --nocapture`
//! prints the piece counts.

#[path = "land_support/mod.rs"]
mod land_support;

use floe_basin::coastline::{parse_land, Coordinates};
use floe_basin::convex_pieces::{convex_pieces, split_to_size, MAX_PIECE_VERTICES};
use floe_basin::planar::{centroid, convex_intersection_area, orient, signed_area};
use floe_basin::ring_crossing::segments_meet;
use floe_basin::simple_ring::simple_ring;
use floe_basin::{Land, MapProjection};
use floe_dem::Vec2;
use land_support::{coast_ring, CoastStyle, Shape};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn pts(p: &[(f64, f64)]) -> Vec<Vec2> {
    p.iter().map(|&(x, y)| Vec2::new(x, y)).collect()
}

/// An L, 10 km on a side and 3 km thick, far from the origin.
fn l_shape() -> Vec<Vec2> {
    let o = (7.0e5, -1.2e6);
    pts(&[
        (0.0, 0.0),
        (10e3, 0.0),
        (10e3, 3e3),
        (3e3, 3e3),
        (3e3, 10e3),
        (0.0, 10e3),
    ])
    .into_iter()
    .map(|v| v + Vec2::new(o.0, o.1))
    .collect()
}

/// A comb: a 20 km spine with eight 6 km teeth 1 km wide.
fn comb() -> Vec<Vec2> {
    let mut p = vec![(0.0, 0.0), (20e3, 0.0), (20e3, 2e3)];
    for k in (0..8).rev() {
        let x = 1e3 + 2.5e3 * k as f64;
        p.extend([(x + 1e3, 2e3), (x + 1e3, 8e3), (x, 8e3), (x, 2e3)]);
    }
    p.push((0.0, 2e3));
    pts(&p)
}

/// A zigzag coast: a flat back, a front of sharp teeth (20 degree tips and
/// bays).
fn zigzag() -> Vec<Vec2> {
    let mut p = vec![(0.0, -5e3), (30e3, -5e3)];
    for k in (0..=30).rev() {
        let x = 1e3 * k as f64;
        let y = if k % 2 == 0 { 0.0 } else { 2.8e3 };
        p.push((x, y));
    }
    pts(&p)
}

/// A random star-shaped polygon of `n` vertices about `c`.
fn star(n: usize, seed: u64) -> Vec<Vec2> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let c = Vec2::new(-2.0e6, 3.0e5);
    (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * (k as f64 + rng.gen_range(-0.4..0.4)) / n as f64;
            let r = rng.gen_range(2e3..20e3);
            c + Vec2::new(r * a.cos(), r * a.sin())
        })
        .collect()
}

/// The checks of an exact decomposition of `ring` into `pieces`.
fn assert_exact(name: &str, ring: &[Vec2], pieces: &[Vec<Vec2>]) {
    let area = signed_area(ring);
    assert!(area > 0.0, "{name}: ring counter-clockwise");
    for (k, p) in pieces.iter().enumerate() {
        let n = p.len();
        assert!(
            (3..=MAX_PIECE_VERTICES).contains(&n),
            "{name}: piece {k} has {n} vertices"
        );
        for i in 0..n {
            let turn = orient(p[i], p[(i + 1) % n], p[(i + 2) % n]);
            assert!(turn >= 0.0, "{name}: piece {k} turns right at {i}");
        }
        assert!(signed_area(p) > 0.0, "{name}: piece {k} has no area");
    }
    let sum: f64 = pieces.iter().map(|p| signed_area(p)).sum();
    assert!(
        (sum - area).abs() <= 1e-9 * area,
        "{name}: pieces sum to {sum} m^2, polygon {area} m^2"
    );
    let mut worst: f64 = 0.0;
    for i in 0..pieces.len() {
        for j in i + 1..pieces.len() {
            worst = worst.max(convex_intersection_area(&pieces[i], &pieces[j]));
        }
    }
    assert!(
        worst <= 1e-9 * area,
        "{name}: two pieces overlap by {worst} m^2"
    );
}

#[test]
fn concave_polygons_are_cut_exactly_into_convex_pieces() {
    let cases = [
        ("L", l_shape(), 2..=3),
        ("comb", comb(), 9..=20),
        ("zigzag", zigzag(), 15..=40),
        ("star 60", star(60, 7), 10..=60),
        ("star 400", star(400, 11), 60..=400),
    ];
    for (name, raw, expected) in cases {
        let ring = simple_ring(&raw).unwrap();
        let pieces = convex_pieces(&ring).unwrap();
        println!(
            "{name}: {} vertices, {} triangles, {} convex pieces",
            ring.len(),
            ring.len() - 2,
            pieces.len()
        );
        assert!(
            expected.contains(&pieces.len()),
            "{name}: {} pieces",
            pieces.len()
        );
        assert_exact(name, &ring, &pieces);
        // Cut to 1 km pieces: still exact, and each within the radius.
        let small = split_to_size(pieces, 1e3);
        for p in &small {
            let c = centroid(p);
            let r = p.iter().map(|&v| (v - c).length()).fold(0.0, f64::max);
            assert!(r <= 1e3 * (1.0 + 1e-12), "{name}: a piece of radius {r} m");
        }
        println!("  cut to radius 1 km: {} pieces", small.len());
        if small.len() <= 3000 {
            assert_exact(name, &ring, &small);
        }
    }
}

#[test]
fn a_clockwise_ring_and_a_ring_given_closed_decompose_alike() {
    let mut ring = l_shape();
    ring.reverse();
    ring.push(ring[0]);
    let clean = simple_ring(&ring).unwrap();
    assert_eq!(clean.len(), 6);
    assert_exact("L reversed", &clean, &convex_pieces(&clean).unwrap());
}

#[test]
fn a_large_coast_decomposes_quickly() {
    let ring = simple_ring(&star(20_000, 3)).unwrap();
    let t = std::time::Instant::now();
    let pieces = convex_pieces(&ring).unwrap();
    let s = t.elapsed().as_secs_f64();
    let sum: f64 = pieces.iter().map(|p| signed_area(p)).sum();
    let area = signed_area(&ring);
    println!("star 20000: {} pieces in {s:.3} s", pieces.len());
    assert!((sum - area).abs() <= 1e-9 * area);
    assert!(s < 20.0, "{s} s");
}

#[test]
fn longitude_latitude_land_is_where_the_projection_puts_it() {
    let corners = [
        (-60.0, 80.0),
        (-50.0, 80.0),
        (-50.0, 82.0),
        (-55.0, 81.0),
        (-60.0, 82.0),
    ];
    let coords: Vec<String> = corners
        .iter()
        .chain(std::iter::once(&corners[0]))
        .map(|(lon, lat)| format!("[{lon}, {lat}]"))
        .collect();
    let text = format!(
        r#"{{"type": "FeatureCollection", "features": [{{"type": "Feature", "properties": {{}},
           "geometry": {{"type": "Polygon", "coordinates": [[{}]]}}}}]}}"#,
        coords.join(", ")
    );
    let map = MapProjection::parse("EPSG:3413").unwrap();
    let land = parse_land(&text, Coordinates::LonLat, Some(&map)).unwrap();
    assert_eq!(land.len(), 1);
    let ring = &land[0].ring;
    assert_eq!(ring.len(), corners.len());
    for &(lon, lat) in &corners {
        let want = map.forward(lon, lat).unwrap();
        assert!(
            ring.contains(&want),
            "({lon}, {lat}) should be at {want:?}, ring {ring:?}"
        );
    }
    // The same land given in x and y (m) is the same land.
    let xy: Vec<String> = corners
        .iter()
        .chain(std::iter::once(&corners[0]))
        .map(|&(lon, lat)| {
            let p = map.forward(lon, lat).unwrap();
            format!("[{:?}, {:?}]", p.x, p.y)
        })
        .collect();
    let text = format!(
        r#"{{"type": "Polygon", "coordinates": [[{}]]}}"#,
        xy.join(", ")
    );
    // (serde_json reads decimals to within an ulp, not always exactly.)
    let again = parse_land(&text, Coordinates::Xy, None).unwrap();
    for (a, b) in again[0].ring.iter().zip(ring) {
        assert!((*a - *b).length() < 1e-6, "{a:?} {b:?}");
    }
    // And the land knows its inside: the middle of the 80-81 N band is land.
    let l = Land::new(land, 5e3).unwrap();
    assert!(l.contains(map.forward(-52.0, 80.5).unwrap()));
    assert!(!l.contains(map.forward(-55.0, 81.8).unwrap()));
    let a: f64 = l.pieces.iter().map(|p| signed_area(&p.vertices)).sum();
    assert!((a - l.area_m2()).abs() <= 1e-9 * a);
}

#[test]
fn one_vertex_moved_onto_an_edge_or_a_vertex_of_a_long_coast_is_refused() {
    // Every pair of edges tested: the reference for the sweep line.
    let meets_any = |ring: &[Vec2]| {
        let n = ring.len();
        let v = |i: usize| ring[i % n];
        (0..n).any(|i| {
            orient(v(i), v(i + 1), v(i + 2)) == 0.0
                && (v(i + 1) - v(i)).dot(v(i + 2) - v(i + 1)) < 0.0
        }) || (0..n).any(|i| {
            (i + 2..n)
                .any(|j| !(i == 0 && j == n - 1) && segments_meet(v(i), v(i + 1), v(j), v(j + 1)))
        })
    };
    let ring = simple_ring(&coast_ring(1_500, 4, Shape::Island, CoastStyle::DEGENERATE)).unwrap();
    let n = ring.len();
    assert!(!meets_any(&ring));
    // Grid-aligned edges: a point on one is exactly on it.
    let straight: Vec<usize> = (0..n)
        .filter(|&k| ring[k].y == ring[(k + 1) % n].y)
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let (mut refused, mut kept) = (0, 0);
    for trial in 0..150 {
        let k = rng.gen_range(0..n);
        let mut moved = ring.clone();
        moved[k] = match trial % 3 {
            // Onto the middle of a grid-aligned edge.
            0 => {
                let e = straight[rng.gen_range(0..straight.len())];
                let (a, b) = (ring[e], ring[(e + 1) % n]);
                Vec2::new(0.5 * (a.x + b.x), a.y)
            }
            // Onto another vertex.
            1 => ring[rng.gen_range(0..n)],
            // Somewhere near: it crosses an edge or not.
            _ => ring[k] + Vec2::new(rng.gen_range(-150.0..150.0), rng.gen_range(-150.0..150.0)),
        };
        let neighbour = |p: Vec2| p == moved[(k + 1) % n] || p == moved[(k + n - 1) % n];
        if neighbour(moved[k]) {
            continue;
        }
        let want = meets_any(&moved);
        let got = simple_ring(&moved);
        assert_eq!(got.is_err(), want, "vertex {k} to {:?}: {got:?}", moved[k]);
        if let Err(why) = got {
            assert!(why.contains("not simple"), "{why}");
            refused += 1;
        } else {
            kept += 1;
        }
    }
    println!("{refused} refused, {kept} still simple");
    assert!(refused > 60 && kept > 10);
}
