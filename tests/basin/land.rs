//! Land from GeoJSON (floe-basin): the convex decomposition is exact (the
//! pieces are convex, their areas sum to the polygon's, and they do not
//! overlap), also after cutting the pieces to a floe's size; generated
//! coastlines of 1e4 vertices (straight runs, needles 1e-7 m wide, a long
//! shore closed far behind) are tiled exactly, edge for edge; the pieces do
//! not depend on where the ring starts or which way it turns; the piece
//! limit holds for thin pieces; a vertex moved onto another edge or vertex
//! is refused as a pairwise test says; a file with a byte-order mark reads
//! as one without; and a longitude-latitude file lands where the map
//! projection puts it.
//! `cargo test --release -p floe-basin --test basin land:: -- --nocapture`
//! prints the piece counts.

use crate::land_support;

use std::collections::HashMap;

use floe_basin::coastline::{parse_land, Coordinates, LandPolygon};
use floe_basin::convex_pieces::{
    convex_pieces, merge_hertel_mehlhorn, split_to_size, MAX_PIECE_VERTICES,
};
use floe_basin::planar::{bounds, centroid, convex_intersection_area, orient, signed_area};
use floe_basin::ring_crossing::segments_meet;
use floe_basin::ring_triangulation::triangulate;
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
    assert_areas_add_up(name, ring, pieces);
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
        assert_exact(name, &ring, &small);
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

/// Checks that the Hertel-Mehlhorn pieces of `ring` (indices into the
/// triangulation's points) tile it exactly, combinatorially: each piece is
/// convex, counter-clockwise and turns once round; every edge of the ring
/// is an edge of exactly one piece, in the ring's direction; every other
/// piece edge is matched by the same edge in the opposite direction in
/// another piece. Then the pieces' winding numbers add up to the ring's:
/// one inside, zero outside, so no gap and no overlap. Returns the count.
fn assert_tiles_exactly(name: &str, ring: &[Vec2]) -> usize {
    let t = triangulate(ring).unwrap();
    let pieces = merge_hertel_mehlhorn(&t);
    let at = |i: u32| t.points[i as usize];
    let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
    for (k, p) in pieces.iter().enumerate() {
        let n = p.len();
        assert!(
            (3..=MAX_PIECE_VERTICES).contains(&n),
            "{name}: piece {k} has {n} vertices"
        );
        let mut changes = 0;
        for i in 0..n {
            let (a, b, c) = (at(p[i]), at(p[(i + 1) % n]), at(p[(i + 2) % n]));
            assert!(orient(a, b, c) >= 0.0, "{name}: piece {k} turns right");
            let up = |u: Vec2, v: Vec2| v.y > u.y || (v.y == u.y && v.x > u.x);
            changes += usize::from(up(a, b) != up(b, c));
            *edges.entry((p[i], p[(i + 1) % n])).or_default() += 1;
        }
        assert_eq!(changes, 2, "{name}: piece {k} winds more than once");
    }
    // The ring's edges, in the triangulation's numbering.
    let index: HashMap<(u64, u64), u32> = t
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| ((p.x.to_bits(), p.y.to_bits()), i as u32))
        .collect();
    let id = |v: Vec2| index[&(v.x.to_bits(), v.y.to_bits())];
    let n = ring.len();
    for k in 0..n {
        let (a, b) = (id(ring[k]), id(ring[(k + 1) % n]));
        assert_eq!(
            edges.remove(&(a, b)),
            Some(1),
            "{name}: ring edge {k} is not one piece's edge"
        );
        assert_eq!(edges.get(&(b, a)), None, "{name}: a piece outside edge {k}");
    }
    for (&(a, b), &count) in &edges {
        assert_eq!(count, 1, "{name}: edge {a}-{b} in {count} pieces");
        assert_eq!(
            edges.get(&(b, a)),
            Some(&1),
            "{name}: edge {a}-{b} unmatched"
        );
    }
    pieces.len()
}

/// Sum of the pieces' areas against the ring's, and no two pieces
/// overlapping (pairs whose bounding boxes meet tested).
fn assert_areas_add_up(name: &str, ring: &[Vec2], pieces: &[Vec<Vec2>]) {
    let area = signed_area(ring);
    let sum: f64 = pieces.iter().map(|p| signed_area(p)).sum();
    assert!(
        (sum - area).abs() <= 1e-9 * area,
        "{name}: pieces sum to {sum} m^2, polygon {area} m^2"
    );
    let boxes: Vec<(Vec2, Vec2)> = pieces.iter().map(|p| bounds(p)).collect();
    let mut order: Vec<usize> = (0..pieces.len()).collect();
    order.sort_by(|&a, &b| boxes[a].0.x.total_cmp(&boxes[b].0.x));
    let mut worst: f64 = 0.0;
    for (s, &i) in order.iter().enumerate() {
        for &j in &order[s + 1..] {
            if boxes[j].0.x > boxes[i].1.x {
                break;
            }
            if boxes[j].0.y <= boxes[i].1.y && boxes[i].0.y <= boxes[j].1.y {
                worst = worst.max(convex_intersection_area(&pieces[i], &pieces[j]));
            }
        }
    }
    assert!(
        worst <= 1e-9 * area,
        "{name}: two pieces overlap by {worst} m^2"
    );
}

#[test]
fn generated_coasts_of_ten_thousand_vertices_are_tiled_exactly() {
    let natural = ("natural", CoastStyle::NATURAL);
    let degenerate = ("straight runs and needles", CoastStyle::DEGENERATE);
    for (shape, styles, cut_m) in [
        (Shape::Island, vec![natural, degenerate], 150.0),
        (Shape::Mainland, vec![natural, degenerate], 150.0),
        (Shape::Shore, vec![natural], 3000.0),
    ] {
        for (style_name, style) in styles {
            let name = format!("{shape:?}, {style_name}");
            let raw = coast_ring(10_000, 5, shape, style);
            let ring = simple_ring(&raw).unwrap();
            let count = assert_tiles_exactly(&name, &ring);
            let pieces = convex_pieces(&ring).unwrap();
            assert_eq!(pieces.len(), count);
            // The ring reaches every piece's vertices and nothing else.
            let vertices: std::collections::HashSet<(u64, u64)> = ring
                .iter()
                .map(|v| (v.x.to_bits(), v.y.to_bits()))
                .collect();
            assert!(pieces
                .iter()
                .flatten()
                .all(|v| vertices.contains(&(v.x.to_bits(), v.y.to_bits()))));
            assert_areas_add_up(&name, &ring, &pieces);
            let small = split_to_size(pieces, cut_m);
            assert_areas_add_up(&format!("{name}, cut to {cut_m} m"), &ring, &small);
            // The degenerate rings hold what they are meant to: exactly
            // straight vertices (dropped) and needles 1e-7 m wide.
            let needles = ring
                .iter()
                .enumerate()
                .filter(|&(k, &v)| {
                    let n = ring.len();
                    (ring[(k + n - 1) % n] - ring[(k + 1) % n]).length() < 1e-6
                        && (v - ring[(k + 1) % n]).length() > 1.0
                })
                .count();
            println!(
                "{name}: {} vertices given, {} kept, {needles} needles, {count} convex pieces, {} cut to {cut_m} m",
                raw.len(),
                ring.len(),
                small.len()
            );
            if style.needle_chance > 0.0 {
                assert!(ring.len() + 1000 < raw.len() && needles >= 5, "{name}");
            } else {
                assert_eq!(needles, 0, "{name}");
            }
        }
    }
}

#[test]
fn the_pieces_do_not_depend_on_where_the_ring_starts_or_which_way_it_turns() {
    for shape in [Shape::Island, Shape::Mainland, Shape::Shore] {
        let raw = coast_ring(10_000, 9, shape, CoastStyle::DEGENERATE);
        let want = convex_pieces(&simple_ring(&raw).unwrap()).unwrap();
        for start in [1, 17, raw.len() / 3, raw.len() - 1] {
            let mut moved = raw.clone();
            moved.rotate_left(start);
            let got = convex_pieces(&simple_ring(&moved).unwrap()).unwrap();
            assert!(got == want, "{shape:?}: starting at vertex {start}");
            moved.reverse();
            let got = convex_pieces(&simple_ring(&moved).unwrap()).unwrap();
            assert!(got == want, "{shape:?}: reversed, from vertex {start}");
        }
        let land = |ring: Vec<Vec2>| {
            let polygon = LandPolygon {
                feature: 0,
                ring: simple_ring(&ring).unwrap(),
            };
            Land::new(vec![polygon], 300.0).unwrap().pieces
        };
        let mut moved = raw.clone();
        moved.rotate_left(raw.len() / 2);
        assert!(land(moved) == land(raw), "{shape:?}: land pieces");
    }
}

#[test]
fn the_piece_limit_holds_for_thin_pieces() {
    // A long shore closed far behind: triangles from the shore far along
    // it or to the corners, long and thin, are cut into about their length
    // over the radius each, not their area over its square.
    const R: f64 = 1000.0;
    let ring = simple_ring(&coast_ring(3_000, 2, Shape::Shore, CoastStyle::NATURAL)).unwrap();
    let polygon = || LandPolygon {
        feature: 0,
        ring: ring.clone(),
    };
    let free = Land::with_piece_limit(vec![polygon()], R, usize::MAX).unwrap();
    // A limit that area / r^2 pieces of radius r would keep at r = R, but
    // the pieces cut to R break.
    let area = signed_area(&ring);
    let by_area = area / (R * R);
    let limit = ((by_area + free.pieces.len() as f64) / 2.0) as usize;
    println!(
        "{} convex pieces; area / ({R} m)^2 = {by_area:.0}; cut to {R} m: {}",
        free.convex_count,
        free.pieces.len(),
    );
    assert!(by_area < limit as f64 && limit < free.pieces.len());
    let held = Land::with_piece_limit(vec![polygon()], R, limit).unwrap();
    println!(
        "limited to {limit}: {} of radius {:.1} m",
        held.pieces.len(),
        held.piece_radius_m
    );
    assert!(held.pieces.len() <= limit);
    let pieces: Vec<Vec<Vec2>> = held.pieces.into_iter().map(|p| p.vertices).collect();
    assert_areas_add_up("limited", &ring, &pieces);
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
fn a_land_file_with_a_byte_order_mark_reads_as_one_without() {
    let text = r#"{"type": "FeatureCollection", "features": [
  {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon",
   "coordinates": [[[0, 0], [4000, 0], [4000, 3000], [2000, 1000], [0, 3000], [0, 0]]]}}]}
"#;
    // A comma missing on line 3, after the second vertex.
    let broken = text.replace("[4000, 0], [4000, 3000]", "[4000, 0] [4000, 3000]");
    let dir = tempfile::tempdir().unwrap();
    let read = |name: &str, body: &str| {
        let path = dir.path().join(name);
        std::fs::write(&path, body).unwrap();
        floe_basin::read_land(&path, Coordinates::Xy, None)
    };
    let plain = read("plain.geojson", text).unwrap();
    let marked = read("marked.geojson", &format!("\u{feff}{text}")).unwrap();
    assert_eq!(plain, marked);
    let pieces = |p| Land::new(p, 500.0).unwrap().pieces;
    assert!(pieces(plain) == pieces(marked));
    let why = |e: floe_basin::BasinError| match e {
        floe_basin::BasinError::File { why, .. } => why,
        other => panic!("{other}"),
    };
    let plain = why(read("plain.geojson", &broken).unwrap_err());
    let marked = why(read("marked.geojson", &format!("\u{feff}{broken}")).unwrap_err());
    // serde_json counts columns in bytes from 1, at the character where
    // the comma should be.
    let line = broken.lines().nth(2).unwrap();
    let column = line.find("[4000, 3000]").unwrap() + 1;
    println!("{marked}");
    assert!(
        plain.contains(&format!("at line 3 column {column}")),
        "{plain}"
    );
    assert_eq!(plain, marked);
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
