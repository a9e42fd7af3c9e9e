//! A lattice made periodic over a domain's periodic axes: the lattice
//! vector nearest each period is found, the lattice is mapped so that it
//! equals the period exactly, and cells and nodes are identified modulo
//! those vectors, so that a floe straddling the seam stays whole and its
//! periodic image meets its neighbours across it.

use crate::error::DemError;
use crate::Vec2;

/// Largest stretch or squeeze of the lattice accepted to fit it to the
/// periods (singular values of the map within `[1/(1 + s), 1 + s]`): a
/// period that holds only a few cells cannot be fitted without changing
/// the floes' shape, and is refused.
pub const MAX_PERIOD_STRETCH: f64 = 0.2;

/// How a lattice was fitted to the periodic axes of a domain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PeriodFit {
    /// For x and y: the lattice vector, in steps along the edge vectors
    /// `(e1, e2)`, that spans the domain's period; `None` for an open axis.
    pub period_steps: [Option<[i64; 2]>; 2],
    /// The linear map applied to the edge vectors, row-major (`[[1, 0], [0,
    /// 1]]` when the lattice already fitted).
    pub map: [[f64; 2]; 2],
}

impl PeriodFit {
    /// The smallest and largest stretch of the map (its singular values):
    /// 1 and 1 when the lattice was left as it was.
    pub fn stretch_range(&self) -> (f64, f64) {
        let [[a, b], [c, d]] = self.map;
        // Singular values of a 2x2 matrix from its Frobenius norm and
        // determinant.
        let f = a * a + b * b + c * c + d * d;
        let det = (a * d - b * c).abs();
        let root = (f * f - 4.0 * det * det).max(0.0).sqrt();
        (
            (0.5 * (f - root)).max(0.0).sqrt(),
            (0.5 * (f + root)).sqrt(),
        )
    }

    /// How far the map turns the lattice, degrees counter-clockwise (its
    /// polar decomposition's rotation).
    pub fn rotation_deg(&self) -> f64 {
        let [[a, b], [c, d]] = self.map;
        (c - b).atan2(a + d).to_degrees()
    }

    /// Whether the lattice is used unchanged.
    pub fn is_identity(&self) -> bool {
        self.map == [[1.0, 0.0], [0.0, 1.0]]
    }

    /// Applies the map to a vector.
    pub fn apply(&self, v: Vec2) -> Vec2 {
        let [[a, b], [c, d]] = self.map;
        Vec2::new(a * v.x + b * v.y, c * v.x + d * v.y)
    }
}

/// The fit of the lattice with edge vectors `(e1, e2)` to the periods
/// `periods_m` (x, y; `None`: open axis).
///
/// One periodic axis: the lattice vector `w` nearest the period vector `P`
/// is scaled and turned onto it (`P / w` as complex numbers), which keeps the
/// cells' shape. Two: the linear map taking the two nearest lattice vectors
/// onto `(Lx, 0)` and `(0, Ly)` (a pure stretch along x and y when the
/// lattice's vectors already lie along the axes).
pub fn fit_periods(e1: Vec2, e2: Vec2, periods_m: [Option<f64>; 2]) -> Result<PeriodFit, DemError> {
    let targets = [
        periods_m[0].map(|l| Vec2::new(l, 0.0)),
        periods_m[1].map(|l| Vec2::new(0.0, l)),
    ];
    let steps = targets.map(|t| t.map(|t| nearest_lattice_vector(e1, e2, t)));
    let vector = |s: [i64; 2]| e1 * s[0] as f64 + e2 * s[1] as f64;
    let map = match (targets, steps) {
        ([None, None], _) => [[1.0, 0.0], [0.0, 1.0]],
        ([Some(t), None], [Some(s), None]) | ([None, Some(t)], [None, Some(s)]) => {
            // z = t / w, as complex numbers: a rotation and a scaling.
            let w = vector(s);
            let n = w.length_squared();
            let (re, im) = ((t.x * w.x + t.y * w.y) / n, (t.y * w.x - t.x * w.y) / n);
            [[re, -im], [im, re]]
        }
        ([Some(tx), Some(ty)], [Some(sx), Some(sy)]) => {
            let (wx, wy) = (vector(sx), vector(sy));
            let det = wx.perp_dot(wy);
            if det.abs() <= 1e-12 * wx.length() * wy.length() {
                return Err(too_few_cells());
            }
            // A = T W^-1, W = [wx wy] as columns, T = diag(Lx, Ly).
            let inv = [[wy.y / det, -wy.x / det], [-wx.y / det, wx.x / det]];
            [
                [tx.x * inv[0][0], tx.x * inv[0][1]],
                [ty.y * inv[1][0], ty.y * inv[1][1]],
            ]
        }
        _ => unreachable!("a step per periodic axis"),
    };
    let fit = PeriodFit {
        period_steps: steps,
        map,
    };
    let (lo, hi) = fit.stretch_range();
    if !(lo >= 1.0 / (1.0 + MAX_PERIOD_STRETCH) && hi <= 1.0 + MAX_PERIOD_STRETCH) {
        return Err(too_few_cells());
    }
    Ok(fit)
}

fn too_few_cells() -> DemError {
    DemError::InvalidParameter {
        name: "side_m",
        value: f64::NAN,
        reason: "the domain's period holds too few lattice cells to fit the lattice to it \
                 without changing the floes' shape by more than 20 %: make the cells smaller \
                 or the periodic side longer",
    }
}

/// The nonzero lattice vector `m e1 + n e2` nearest `target`, as `[m, n]`
/// (ties: the first of the rounded candidates in the order tried).
fn nearest_lattice_vector(e1: Vec2, e2: Vec2, target: Vec2) -> [i64; 2] {
    let det = e1.perp_dot(e2);
    let u = target.perp_dot(e2) / det;
    let v = e1.perp_dot(target) / det;
    let mut best = [0, 0];
    let mut best_d = f64::INFINITY;
    for m in [u.floor(), u.ceil()] {
        for n in [v.floor(), v.ceil()] {
            let (m, n) = (m as i64, n as i64);
            if (m, n) == (0, 0) {
                continue;
            }
            let d = (e1 * m as f64 + e2 * n as f64 - target).length();
            if d < best_d {
                best_d = d;
                best = [m, n];
            }
        }
    }
    best
}

/// Lattice indices identified modulo the period vectors.
#[derive(Debug, Clone, Copy)]
pub(crate) struct IndexPeriods {
    steps: [Option<[i64; 2]>; 2],
}

impl IndexPeriods {
    pub(crate) fn new(fit: &PeriodFit) -> Self {
        Self {
            steps: fit.period_steps,
        }
    }

    /// The representative of `(i, j)` modulo the periods: the same for every
    /// index the periods map onto each other.
    pub(crate) fn canonical(&self, i: i64, j: i64) -> (i64, i64) {
        match self.steps {
            [None, None] => (i, j),
            [Some(p), None] | [None, Some(p)] => {
                let [m, n] = if p[1] < 0 || (p[1] == 0 && p[0] < 0) {
                    [-p[0], -p[1]]
                } else {
                    p
                };
                if n == 0 {
                    (i.rem_euclid(m), j)
                } else {
                    let t = j.div_euclid(n);
                    (i - t * m, j - t * n)
                }
            }
            [Some([m1, n1]), Some([m2, n2])] => {
                // (i, j) = a P1 + b P2 with a = (i n2 - j m2) / D and
                // b = (m1 j - n1 i) / D; subtract floor(a) P1 + floor(b) P2.
                let det = m1 * n2 - m2 * n1;
                let floor_div = |x: i64| {
                    if det > 0 {
                        x.div_euclid(det)
                    } else {
                        (-x).div_euclid(-det)
                    }
                };
                let a = floor_div(i * n2 - j * m2);
                let b = floor_div(m1 * j - n1 * i);
                (i - a * m1 - b * m2, j - a * n1 - b * n2)
            }
        }
    }

    /// The steps `[m, n]` of the period along axis `axis` (0: x, 1: y).
    pub(crate) fn along(&self, axis: usize) -> Option<[i64; 2]> {
        self.steps[axis]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lattice_that_already_fits_is_left_bitwise_as_it_was() {
        let (e1, e2) = (Vec2::new(800.0, 0.0), Vec2::new(400.0, 692.820323));
        let fit = fit_periods(e1, e2, [Some(20_000.0), None]).unwrap();
        assert_eq!(fit.period_steps, [Some([25, 0]), None]);
        assert!(fit.is_identity(), "{:?}", fit.map);
    }

    #[test]
    fn one_period_scales_and_turns_the_lattice_onto_it() {
        let (e1, e2) = (Vec2::new(850.0, -500.0), Vec2::new(850.0, 500.0));
        let fit = fit_periods(e1, e2, [Some(100_000.0), None]).unwrap();
        assert_eq!(fit.period_steps, [Some([59, 59]), None]);
        let w = fit.apply(e1 * 59.0 + e2 * 59.0);
        assert!((w - Vec2::new(100_000.0, 0.0)).length() < 1e-9, "{w:?}");
        let (lo, hi) = fit.stretch_range();
        assert!((lo - 100_000.0 / 100_300.0).abs() < 1e-12 && (hi - lo).abs() < 1e-12);
        // A lattice turned by less than a cell over the period is turned
        // back onto the axis.
        let turn = 0.1f64.to_radians();
        let r = |v: Vec2| {
            Vec2::new(
                v.x * turn.cos() - v.y * turn.sin(),
                v.x * turn.sin() + v.y * turn.cos(),
            )
        };
        let fit = fit_periods(r(e1), r(e2), [Some(100_000.0), None]).unwrap();
        assert_eq!(fit.period_steps, [Some([59, 59]), None]);
        assert!(
            (fit.rotation_deg() + 0.1).abs() < 1e-9,
            "{}",
            fit.rotation_deg()
        );
    }

    #[test]
    fn two_periods_map_both_lattice_vectors_onto_the_axes() {
        let (e1, e2) = (Vec2::new(800.0, 0.0), Vec2::new(400.0, 692.8));
        let fit = fit_periods(e1, e2, [Some(20_000.0), Some(10_000.0)]).unwrap();
        let [sx, sy] = fit.period_steps.map(Option::unwrap);
        let vector = |s: [i64; 2]| fit.apply(e1 * s[0] as f64 + e2 * s[1] as f64);
        assert!((vector(sx) - Vec2::new(20_000.0, 0.0)).length() < 1e-9);
        assert!((vector(sy) - Vec2::new(0.0, 10_000.0)).length() < 1e-9);
    }

    #[test]
    fn a_period_of_a_cell_and_a_half_is_refused() {
        let (e1, e2) = (Vec2::new(800.0, 0.0), Vec2::new(400.0, 692.8));
        assert!(fit_periods(e1, e2, [Some(1_200.0), None]).is_err());
    }

    #[test]
    fn canonical_indices_are_one_per_class() {
        for steps in [
            [Some([25, 0]), None],
            [Some([7, 7]), None],
            [None, Some([-3, 5])],
            [Some([25, 0]), Some([-7, 14])],
            [Some([6, 6]), Some([-4, 4])],
        ] {
            let p = IndexPeriods { steps };
            let periods: Vec<[i64; 2]> = steps.iter().flatten().copied().collect();
            for i in -40..40 {
                for j in -40..40 {
                    let c = p.canonical(i, j);
                    assert_eq!(p.canonical(c.0, c.1), c, "{steps:?} ({i}, {j})");
                    for [m, n] in &periods {
                        for k in [-2, -1, 1, 3] {
                            assert_eq!(p.canonical(i + k * m, j + k * n), c, "{steps:?}");
                        }
                    }
                }
            }
            // Classes in a big window: as many as the periods' cells (the
            // determinant; one vector: the window's rows times |m| per row).
            if let [Some([m1, n1]), Some([m2, n2])] = steps {
                let mut seen = std::collections::HashSet::new();
                for i in -200..200 {
                    for j in -200..200 {
                        seen.insert(p.canonical(i, j));
                    }
                }
                assert_eq!(seen.len() as i64, (m1 * n2 - m2 * n1).abs(), "{steps:?}");
            }
        }
    }
}
