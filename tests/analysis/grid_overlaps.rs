//! Gridded fields of overlapping floes (floe_analysis::grid_fields): a
//! place under several floes is ice once in the concentration, while the
//! floes' volume and momentum are each floe's own. References: counting
//! the squares of a lattice every edge lies on, the staircase of shifted
//! squares, and the union by vertical slabs (tests/support/union.rs).

use crate::proptest_settings;
use crate::union_support;
use floe_analysis::grid_fields::{grid_fields, FloeSnapshot, Grid, GridFields, MAX_OVERLAP_ORDER};
use floe_analysis::AnalysisError;
use proptest::prelude::*;
use union_support::union_area_in_box;

/// An axis-aligned rectangle `[x0, x1] x [y0, y1]`, counter-clockwise.
fn rect(x0: f64, x1: f64, y0: f64, y1: f64) -> Vec<[f64; 2]> {
    vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
}

fn centroid(poly: &[[f64; 2]]) -> [f64; 2] {
    let n = poly.len() as f64;
    [0, 1].map(|a| poly.iter().map(|p| p[a]).sum::<f64>() / n)
}

/// Fields of floes `polys` drifting at `velocity` without spin, of
/// thicknesses `thickness`.
fn fields(
    grid: &Grid,
    polys: &[Vec<[f64; 2]>],
    velocity: &[[f64; 2]],
    thickness: &[f64],
) -> Result<GridFields, AnalysisError> {
    let position: Vec<[f64; 2]> = polys.iter().map(|p| centroid(p)).collect();
    grid_fields(
        grid,
        &FloeSnapshot {
            vertices: polys,
            position: &position,
            velocity,
            angular_velocity: &vec![0.0; polys.len()],
            thickness_m: thickness,
            stress_moment_n_m: None,
        },
    )
}

/// Four rectangles on a lattice of quarter metres, over cells of 1 m:
/// pairs, triples and one place under all four, across cell edges. On
/// each of the lattice's squares every rectangle is all in or all out, so
/// counting squares gives each cell's ice area, volume and momentum.
#[test]
fn overlapping_rectangles_are_ice_once_and_keep_each_floes_volume_and_momentum() {
    let grid = Grid {
        origin_m: [0.0, 0.0],
        cell_m: [1.0, 1.0],
        shape: [4, 4],
    };
    let polys = vec![
        rect(0.25, 2.25, 0.5, 2.5),
        rect(1.5, 3.5, 1.25, 3.25),
        rect(0.75, 2.75, 1.75, 3.75),
        rect(1.25, 2.0, 0.25, 3.0),
    ];
    let thickness = [1.0, 2.0, 0.5, 3.0];
    let velocity = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -2.0]];
    let f = fields(&grid, &polys, &velocity, &thickness).unwrap();
    let inside =
        |p: &[[f64; 2]], x: f64, y: f64| x > p[0][0] && x < p[1][0] && y > p[0][1] && y < p[2][1];
    let quarter = 1.0 / 16.0;
    let mut deepest = 0;
    for j in 0..4 {
        for i in 0..4 {
            let (mut ice, mut volume, mut momentum) = (0.0, 0.0, [0.0; 2]);
            for (a, b) in (0..4).flat_map(|a| (0..4).map(move |b| (a, b))) {
                let (x, y) = (
                    i as f64 + 0.125 + 0.25 * a as f64,
                    j as f64 + 0.125 + 0.25 * b as f64,
                );
                let over: Vec<usize> = (0..4).filter(|&p| inside(&polys[p], x, y)).collect();
                deepest = deepest.max(over.len());
                if !over.is_empty() {
                    ice += quarter;
                }
                for p in over {
                    volume += quarter * thickness[p];
                    momentum[0] += quarter * thickness[p] * velocity[p][0];
                    momentum[1] += quarter * thickness[p] * velocity[p][1];
                }
            }
            let k = grid.index(i, j);
            assert!(
                (f.concentration[k] - ice).abs() < 1e-14,
                "cell ({i}, {j}): {} against {ice}",
                f.concentration[k]
            );
            if ice > 0.0 {
                assert!((f.thickness_m[k] - volume / ice).abs() < 1e-14 * volume / ice);
                for (u, p) in f.velocity[k].iter().zip(momentum) {
                    assert!((u - p / volume).abs() < 1e-14, "cell ({i}, {j})");
                }
            } else {
                assert!(f.thickness_m[k].is_nan() && f.velocity[k][0].is_nan());
            }
        }
    }
    assert_eq!(deepest, 4, "a place lies under all four");
    // Every two overlap, and so do every three and all four.
    assert_eq!(f.overlap_sets, [6, 4, 1]);
}

/// `n` squares of side `side`, each shifted by `(d, d)` from the one
/// before: their union is a staircase, `side^2 + (n - 1) (2 side d - d^2)`,
/// with places under up to `n` of them (2^n - 1 overlap terms).
fn staircase(n: usize, side: f64, d: f64) -> Vec<Vec<[f64; 2]>> {
    (0..n)
        .map(|k| {
            let o = 0.3 + k as f64 * d;
            rect(o, o + side, o, o + side)
        })
        .collect()
}

#[test]
fn a_stack_of_squares_is_counted_to_every_order_and_a_deeper_one_is_refused() {
    // One cell holding the whole stack, and cells cutting through it.
    for (cell, shape) in [(10.0, 1), (0.7, 15)] {
        let grid = Grid {
            origin_m: [0.0, 0.0],
            cell_m: [cell, cell],
            shape: [shape, shape],
        };
        let (n, side, d) = (MAX_OVERLAP_ORDER, 5.0, 0.25);
        let polys = staircase(n, side, d);
        let f = fields(&grid, &polys, &vec![[0.1, 0.0]; n], &vec![1.0; n]).unwrap();
        let ice: f64 = f.concentration.iter().sum::<f64>() * cell * cell;
        let exact = side * side + (n - 1) as f64 * (2.0 * side * d - d * d);
        assert!((ice - exact).abs() < 1e-12 * exact, "{ice} against {exact}");
        assert!(f.concentration.iter().all(|c| *c <= 1.0 + 1e-12));
        // The volume is every square's own.
        let volume: f64 = (0..grid.len())
            .filter(|&k| f.concentration[k] > 0.0)
            .map(|k| f.concentration[k] * f.thickness_m[k] * cell * cell)
            .sum();
        assert!((volume - n as f64 * side * side).abs() < 1e-12 * volume);
        // Every set of two or more squares has a common overlap.
        let binomial = |k: usize| (0..k).fold(1, |c, i| c * (n - i) / (i + 1));
        assert_eq!(f.overlap_sets, (2..=n).map(binomial).collect::<Vec<_>>());
    }
    let grid = Grid {
        origin_m: [0.0, 0.0],
        cell_m: [10.0, 10.0],
        shape: [1, 1],
    };
    let n = MAX_OVERLAP_ORDER + 1;
    let e = fields(
        &grid,
        &staircase(n, 5.0, 0.25),
        &vec![[0.0; 2]; n],
        &vec![1.0; n],
    )
    .unwrap_err();
    assert!(
        matches!(e, AnalysisError::TooManyOverlaps { count, .. } if count == n),
        "{e}"
    );
    assert!(e.to_string().contains(&format!("{n} floes overlap")), "{e}");
}

/// A convex polygon: a rectangle of `w` x `h` turned by `turn`, or (when
/// `tri`) the triangle of three of its corners, centred at `c`.
fn shape(c: [f64; 2], w: f64, h: f64, turn: f64, tri: bool) -> Vec<[f64; 2]> {
    let (s, co) = turn.sin_cos();
    let corners = [[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]];
    let take = if tri { 3 } else { 4 };
    corners[..take]
        .iter()
        .map(|[a, b]| {
            let (x, y) = (a * w, b * h);
            [c[0] + co * x - s * y, c[1] + s * x + co * y]
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..proptest_settings::default() })]
    /// Turned rectangles and triangles, overlapping at random across a
    /// grid that leaves some of them partly outside: each cell's ice area
    /// is the union's area by slabs, to round-off.
    #[test]
    fn each_cells_ice_is_the_union_of_the_floes_in_it(
        raw in prop::collection::vec(
            ((0.0f64..30.0, 0.0f64..20.0), (2.0f64..12.0, 2.0f64..12.0), 0.0f64..6.3, any::<bool>()),
            1..12),
    ) {
        let grid = Grid { origin_m: [1.0, -2.0], cell_m: [5.0, 4.0], shape: [6, 5] };
        let polys: Vec<Vec<[f64; 2]>> = raw
            .iter()
            .map(|&((x, y), (w, h), turn, tri)| shape([x, y], w, h, turn, tri))
            .collect();
        let n = polys.len();
        let f = fields(&grid, &polys, &vec![[0.0; 2]; n], &vec![1.0; n]).unwrap();
        for j in 0..5 {
            for i in 0..6 {
                let lo = [1.0 + 5.0 * i as f64, -2.0 + 4.0 * j as f64];
                let hi = [lo[0] + 5.0, lo[1] + 4.0];
                let expected = union_area_in_box(&polys, lo, hi) / 20.0;
                let c = f.concentration[grid.index(i, j)];
                prop_assert!((c - expected).abs() < 1e-12, "cell ({}, {}): {} against {}", i, j, c, expected);
            }
        }
    }
}
