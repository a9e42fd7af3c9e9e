//! Splitting a floe's polygon: Voronoi cells of sites inside it tile it
//! (areas, first and second moments add up to the parent's, every point in
//! exactly one piece), each piece convex; the sites depend only on (seed,
//! floe id, step, attempt); too-small pieces are drawn again, and a floe
//! that cannot be split stays whole.

use floe_dem::fracture::split::{
    clip_half_plane, random_sites, split_polygon, voronoi_cells, SplitKey, SplitRule,
};
use floe_dem::geometry::shape::{area_and_centroid, polar_moment, FloeShape};
use floe_dem::geometry::{cross, MAX_VERTICES};
use floe_dem::Vec2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A random convex polygon of `n` vertices about its centroid, a few km
/// across: points on an ellipse at sorted random angles.
fn convex(rng: &mut ChaCha8Rng, n: usize) -> Vec<Vec2> {
    let (a, b) = (rng.gen_range(500.0..3000.0), rng.gen_range(500.0..3000.0));
    let turn = rng.gen_range(0.0..std::f64::consts::PI);
    let mut angles: Vec<f64> = (0..n)
        .map(|_| rng.gen_range(0.0..std::f64::consts::TAU))
        .collect();
    angles.sort_by(f64::total_cmp);
    let (s, c) = turn.sin_cos();
    let world: Vec<Vec2> = angles
        .iter()
        .map(|t| {
            let p = Vec2::new(a * t.cos(), b * t.sin());
            Vec2::new(c * p.x - s * p.y, s * p.x + c * p.y)
        })
        .collect();
    let (shape, _) = FloeShape::from_world(0, &world).expect("convex");
    shape.vertices
}

fn inside(p: &[Vec2], q: Vec2) -> bool {
    let n = p.len();
    (0..n).all(|i| cross(p[(i + 1) % n] - p[i], q - p[i]) >= 0.0)
}

#[test]
fn two_symmetric_sites_cut_a_square_in_half() {
    let sq = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(x, y)| Vec2::new(x, y));
    let cells = voronoi_cells(&sq, &[Vec2::new(-0.5, 0.2), Vec2::new(0.5, 0.2)]);
    for (cell, side) in cells.iter().zip([-1.0, 1.0]) {
        let (area, c) = area_and_centroid(cell);
        assert_eq!(cell.len(), 4, "{cell:?}");
        assert!((area - 2.0).abs() < 1e-15, "{area}");
        assert!((c - Vec2::new(0.5 * side, 0.0)).length() < 1e-15, "{c}");
    }
    // A half-plane that misses the polygon leaves it whole; one beyond it
    // leaves nothing.
    assert_eq!(clip_half_plane(&sq, Vec2::new(1.0, 0.0), 5.0), sq.to_vec());
    assert!(clip_half_plane(&sq, Vec2::new(1.0, 0.0), -5.0).is_empty());
}

#[test]
fn pieces_tile_the_parent_and_keep_its_moments() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for case in 0..200 {
        let n = rng.gen_range(3..=12);
        let parent = convex(&mut rng, n);
        let k = rng.gen_range(2..=6);
        let sites = random_sites(&parent, k, &mut rng);
        assert_eq!(sites.len(), k);
        let cells = voronoi_cells(&parent, &sites);
        let (area, _) = area_and_centroid(&parent);
        let size = parent.iter().map(|v| v.length()).fold(0.0, f64::max);
        let (mut a_sum, mut first, mut second) = (0.0, Vec2::ZERO, 0.0);
        for (cell, site) in cells.iter().zip(&sites) {
            assert!(cell.len() >= 3 && cell.len() <= parent.len() + k, "{case}");
            let (shape, c) = FloeShape::from_world(0, cell).expect("a convex piece");
            assert!(inside(cell, *site), "{case}: the site is in its cell");
            a_sum += shape.area_m2;
            first += shape.area_m2 * c;
            // Parallel axes: about the parent's centroid.
            second += shape.polar_moment_m4 + shape.area_m2 * c.length_squared();
        }
        assert!(
            (a_sum - area).abs() < 1e-12 * area,
            "{case}: area {a_sum} {area}"
        );
        assert!(
            first.length() < 1e-12 * area * size,
            "{case}: centroid {first}"
        );
        let j = polar_moment(&parent);
        assert!(
            (second - j).abs() < 1e-11 * j,
            "{case}: moment {second} {j}"
        );
        // Every point of the parent is in one piece: sample a grid.
        for ix in 0..20 {
            for iy in 0..20 {
                let q = Vec2::new(
                    size * (ix as f64 / 9.5 - 1.0),
                    size * (iy as f64 / 9.5 - 1.0),
                );
                let holders = cells.iter().filter(|c| inside(c, q)).count();
                if inside(&parent, q) {
                    assert!(holders >= 1, "{case}: {q} in no piece");
                    let nearest = (0..k)
                        .min_by(|&i, &j| {
                            (sites[i] - q).length().total_cmp(&(sites[j] - q).length())
                        })
                        .unwrap();
                    assert!(
                        inside(&cells[nearest], q),
                        "{case}: {q} not in its site's cell"
                    );
                } else {
                    assert_eq!(holders, 0, "{case}: {q} outside the parent");
                }
            }
        }
    }
}

#[test]
fn a_split_depends_on_its_key_alone() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let parent = convex(&mut rng, 9);
    let rule = SplitRule::default();
    let key = SplitKey {
        seed: 3,
        floe_id: 1041,
        step: 777_000,
    };
    let (a, attempt) = split_polygon(&parent, &rule, key).expect("splits");
    assert_eq!(attempt, 0, "no smallest piece: the first attempt fits");
    assert_eq!(a.len(), 3);
    // The same key, in another thread: the same bits.
    let again = std::thread::spawn({
        let parent = parent.clone();
        move || split_polygon(&parent, &SplitRule::default(), key)
    })
    .join()
    .unwrap();
    assert_eq!(Some((a.clone(), 0)), again);
    for other in [
        SplitKey { seed: 4, ..key },
        SplitKey {
            floe_id: 1042,
            ..key
        },
        SplitKey {
            step: 777_001,
            ..key
        },
    ] {
        assert_ne!(split_polygon(&parent, &rule, other).unwrap().0, a);
    }
}

#[test]
fn small_pieces_are_drawn_again_and_an_unsplittable_floe_stays_whole() {
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let (mut redrawn, mut whole) = (0, 0);
    for case in 0..100 {
        let parent = convex(&mut rng, 8);
        let (area, _) = area_and_centroid(&parent);
        let rule = SplitRule {
            pieces: 4,
            min_piece_area_m2: 0.15 * area,
            attempts: 20,
        };
        let key = SplitKey {
            seed: 1,
            floe_id: case,
            step: 10,
        };
        match split_polygon(&parent, &rule, key) {
            Some((pieces, attempt)) => {
                redrawn += usize::from(attempt > 0);
                let total: f64 = pieces.iter().map(|p| area_and_centroid(p).0).sum();
                assert!((total - area).abs() < 1e-12 * area);
                for p in &pieces {
                    assert!(area_and_centroid(p).0 >= rule.min_piece_area_m2);
                    assert!(p.len() <= MAX_VERTICES);
                }
            }
            None => whole += 1,
        }
        // Four pieces of more than a quarter each cannot be.
        let impossible = SplitRule {
            min_piece_area_m2: 0.26 * area,
            ..rule
        };
        assert!(split_polygon(&parent, &impossible, key).is_none());
    }
    assert!(redrawn > 10, "attempts were redrawn ({redrawn})");
    assert!(whole < 50, "most floes split ({whole} whole)");
}
