//! Spatial decomposition of the floes into subdomains, one per process of
//! a distributed run: recursive coordinate bisection (RCB) weighted by each
//! floe's work (its contact count), as LAMMPS' `comm_style tiled` with
//! `balance rcb`.
//!
//! The box is cut across its longer side so that the weight on each side
//! is in proportion to the parts it will hold, then each side is cut again
//! until there is one part per box. Cuts lie halfway between the two floes
//! they separate, so every floe's owner is a function of its position
//! alone ([`Decomposition::owner_of`]); floes sort by (coordinate, index),
//! so the result is the same bits on every process and thread count.
//! [`Decomposition::imbalance`] measures how far the busiest part's work
//! exceeds the mean, what a rebalance is triggered on.
//!
//! floe-parallel cuts a distributed run's domain with it (docs/hpc.md).

use crate::tessellation::Rect;
use crate::{DemError, Vec2};

/// One cut of the bisection tree.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
enum Node {
    /// A leaf: the part's index.
    Part(usize),
    /// A cut at `at` along `axis` (0: x, 1: y); children in the tree.
    Cut {
        axis: usize,
        at: f64,
        below: usize,
        above: usize,
    },
}

/// Subdomains from recursive coordinate bisection.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Decomposition {
    nodes: Vec<Node>,
    boxes: Vec<Rect>,
}

impl Decomposition {
    /// Cuts `domain` into `parts` boxes holding about equal shares of
    /// `weights` (one per point of `points`, each `> 0` and finite).
    ///
    /// # Errors
    /// [`DemError::InvalidParameter`] for no parts, more parts than points
    /// (each process needs a floe), a weight that is not positive and
    /// finite, mismatched lengths, or a point outside `domain`.
    pub fn rcb(
        points: &[Vec2],
        weights: &[f64],
        domain: Rect,
        parts: usize,
    ) -> Result<Self, DemError> {
        let bad = crate::error::invalid_parameter;
        if parts == 0 {
            return bad("parts", 0.0, "needs at least one part");
        }
        if points.len() != weights.len() {
            return bad(
                "weights",
                weights.len() as f64,
                "needs one weight per point",
            );
        }
        if parts > points.len() {
            return bad(
                "parts",
                parts as f64,
                "more parts (processes) than floes: every part needs at least one floe",
            );
        }
        if let Some(&w) = weights.iter().find(|w| !(w.is_finite() && **w > 0.0)) {
            return bad("weights", w, "must be positive and finite");
        }
        let inside = |p: &Vec2| {
            p.x >= domain.min.x && p.x <= domain.max.x && p.y >= domain.min.y && p.y <= domain.max.y
        };
        if let Some(p) = points.iter().find(|p| !inside(p)) {
            return bad("points", p.x, "a point lies outside the domain");
        }
        let mut d = Decomposition {
            nodes: Vec::new(),
            boxes: vec![domain; parts],
        };
        let mut order: Vec<usize> = (0..points.len()).collect();
        d.split(points, weights, &mut order, domain, 0, parts)?;
        Ok(d)
    }

    /// Builds the subtree for `idx` (the points in `bx`) holding parts
    /// `first .. first + parts`; returns its node index.
    fn split(
        &mut self,
        points: &[Vec2],
        weights: &[f64],
        idx: &mut [usize],
        bx: Rect,
        first: usize,
        parts: usize,
    ) -> Result<usize, DemError> {
        if parts == 1 {
            self.boxes[first] = bx;
            self.nodes.push(Node::Part(first));
            return Ok(self.nodes.len() - 1);
        }
        let size = bx.max - bx.min;
        let longer = usize::from(size.y > size.x);
        let below_parts = parts / 2;
        // The longer side first; the other if floes there share one
        // coordinate too much to be cut between.
        let mut cut = None;
        for axis in [longer, 1 - longer] {
            let coord = |i: usize| if axis == 0 { points[i].x } else { points[i].y };
            idx.sort_by(|&a, &b| coord(a).total_cmp(&coord(b)).then(a.cmp(&b)));
            let c: Vec<f64> = idx.iter().map(|&i| coord(i)).collect();
            let w: Vec<f64> = idx.iter().map(|&i| weights[i]).collect();
            if let Some(k) = choose_cut(&c, &w, below_parts, parts) {
                cut = Some((axis, k, 0.5 * (c[k - 1] + c[k])));
                break;
            }
        }
        let Some((axis, k, at)) = cut else {
            return Err(DemError::InvalidParameter {
                name: "parts",
                value: parts as f64,
                reason: "floes at one position cannot be divided among the parts",
            });
        };
        if axis != longer {
            // Leave `idx` sorted along the cut's axis.
            let coord = |i: usize| if axis == 0 { points[i].x } else { points[i].y };
            idx.sort_by(|&a, &b| coord(a).total_cmp(&coord(b)).then(a.cmp(&b)));
        }
        let (mut lo, mut hi) = (bx, bx);
        if axis == 0 {
            lo.max.x = at;
            hi.min.x = at;
        } else {
            lo.max.y = at;
            hi.min.y = at;
        }
        let me = self.nodes.len();
        self.nodes.push(Node::Part(usize::MAX));
        let (left, right) = idx.split_at_mut(k);
        let below = self.split(points, weights, left, lo, first, below_parts)?;
        let above = self.split(
            points,
            weights,
            right,
            hi,
            first + below_parts,
            parts - below_parts,
        )?;
        self.nodes[me] = Node::Cut {
            axis,
            at,
            below,
            above,
        };
        Ok(me)
    }

    /// The parts' boxes, by part index.
    pub fn boxes(&self) -> &[Rect] {
        &self.boxes
    }

    /// The part owning position `p`: below a cut (`<`) or at and above it.
    pub fn owner_of(&self, p: Vec2) -> usize {
        let mut n = 0;
        loop {
            match self.nodes[n] {
                Node::Part(k) => return k,
                Node::Cut {
                    axis,
                    at,
                    below,
                    above,
                } => {
                    let c = if axis == 0 { p.x } else { p.y };
                    n = if c < at { below } else { above };
                }
            }
        }
    }

    /// The busiest part's work over the mean, minus one (0: perfectly even),
    /// for `weights` at `points` now.
    pub fn imbalance(&self, points: &[Vec2], weights: &[f64]) -> f64 {
        let mut work = vec![0.0; self.boxes.len()];
        for (p, w) in points.iter().zip(weights) {
            work[self.owner_of(*p)] += w;
        }
        let mean = work.iter().sum::<f64>() / work.len() as f64;
        let max = work.iter().copied().fold(0.0, f64::max);
        if mean > 0.0 {
            max / mean - 1.0
        } else {
            0.0
        }
    }

    /// Whether a floe at `p` of circumradius `reach` (radius plus skin)
    /// reaches into part `k`'s box (a ghost there, or owned).
    pub fn reaches(&self, k: usize, p: Vec2, reach: f64) -> bool {
        let b = self.boxes[k];
        let dx = (b.min.x - p.x).max(0.0).max(p.x - b.max.x);
        let dy = (b.min.y - p.y).max(0.0).max(p.y - b.max.y);
        dx * dx + dy * dy <= reach * reach
    }
}

/// Where to cut sorted coordinates `c` (weights `w`): the first `k` go
/// below, `k` leaving at least `below_parts` points below and the rest
/// of the `parts` their point each above, with `c[k - 1] < c[k]` (a cut
/// strictly between two floes), as near as can be to the weight share
/// `below_parts / parts`. `None` if no strict gap is allowed.
fn choose_cut(c: &[f64], w: &[f64], below_parts: usize, parts: usize) -> Option<usize> {
    let n = c.len();
    let (lo, hi) = (below_parts, n - (parts - below_parts));
    if lo > hi {
        return None;
    }
    let target = w.iter().sum::<f64>() * below_parts as f64 / parts as f64;
    let mut k = lo;
    let mut acc: f64 = w[..k].iter().sum();
    while k < hi && acc + 0.5 * w[k] < target {
        acc += w[k];
        k += 1;
    }
    // The nearest strict gap to k within [lo, hi].
    (0..=n)
        .flat_map(|d| [k.checked_add(d), k.checked_sub(d)])
        .flatten()
        .filter(|&j| j >= lo.max(1) && j <= hi && j < n)
        .find(|&j| c[j - 1] < c[j])
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn cloud(n: usize, seed: u64) -> (Vec<Vec2>, Vec<f64>, Rect) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let domain = Rect {
            min: Vec2::new(-5000.0, 0.0),
            max: Vec2::new(15000.0, 4000.0),
        };
        // A dense cluster and a sparse background, contact counts 1 to 6.
        let points = (0..n)
            .map(|i| {
                if i % 3 == 0 {
                    Vec2::new(rng.gen_range(-5000.0..15000.0), rng.gen_range(0.0..4000.0))
                } else {
                    Vec2::new(
                        rng.gen_range(8000.0..10000.0),
                        rng.gen_range(1000.0..2000.0),
                    )
                }
            })
            .collect();
        let weights = (0..n).map(|_| rng.gen_range(1..=6) as f64).collect();
        (points, weights, domain)
    }

    #[test]
    fn every_floe_has_one_owner_inside_its_box_and_the_work_is_even() {
        let (points, weights, domain) = cloud(3000, 7);
        for parts in 1..=9 {
            let d = Decomposition::rcb(&points, &weights, domain, parts).unwrap();
            assert_eq!(d.boxes().len(), parts);
            let mut work = vec![0.0; parts];
            for (p, w) in points.iter().zip(&weights) {
                let k = d.owner_of(*p);
                let b = d.boxes()[k];
                assert!(p.x >= b.min.x && p.x <= b.max.x && p.y >= b.min.y && p.y <= b.max.y);
                work[k] += w;
            }
            // Each cut misses its target by at most one point's weight (6)
            // per level: within 4 levels x 6 of the mean.
            let mean = work.iter().sum::<f64>() / parts as f64;
            for w in &work {
                assert!((w - mean).abs() <= 6.0 * 4.0, "{parts}: {work:?}");
            }
            assert!(d.imbalance(&points, &weights) <= 24.0 / mean);
            // The boxes tile the domain.
            let area: f64 = d
                .boxes()
                .iter()
                .map(|b| (b.max - b.min).x * (b.max - b.min).y)
                .sum();
            assert!((area - 20000.0 * 4000.0).abs() < 1e-6 * area);
        }
    }

    #[test]
    fn the_same_input_in_another_order_gives_the_same_cuts() {
        let (points, weights, domain) = cloud(500, 3);
        let d = Decomposition::rcb(&points, &weights, domain, 4).unwrap();
        // Owners are positions' functions: the same whichever order.
        let rev_p: Vec<Vec2> = points.iter().rev().copied().collect();
        let rev_w: Vec<f64> = weights.iter().rev().copied().collect();
        let e = Decomposition::rcb(&rev_p, &rev_w, domain, 4).unwrap();
        for p in &points {
            assert_eq!(d.owner_of(*p), e.owner_of(*p));
        }
    }

    #[test]
    fn more_parts_than_floes_and_bad_weights_are_refused() {
        let (points, weights, domain) = cloud(5, 1);
        assert!(Decomposition::rcb(&points, &weights, domain, 6).is_err());
        assert!(Decomposition::rcb(&points, &weights, domain, 0).is_err());
        let mut w = weights.clone();
        w[2] = 0.0;
        assert!(Decomposition::rcb(&points, &w, domain, 2).is_err());
        let d = Decomposition::rcb(&points, &weights, domain, 5).unwrap();
        // Five parts for five floes: one each.
        let mut owners: Vec<usize> = points.iter().map(|p| d.owner_of(*p)).collect();
        owners.sort();
        assert_eq!(owners, vec![0, 1, 2, 3, 4]);
    }

    #[test]
    fn a_lattice_with_shared_coordinates_is_cut_between_floes() {
        // 40 x 10 points on a lattice: whole columns share x.
        let points: Vec<Vec2> = (0..400)
            .map(|i| {
                Vec2::new(
                    100.0 * (i % 40) as f64 + 50.0,
                    100.0 * (i / 40) as f64 + 50.0,
                )
            })
            .collect();
        let weights = vec![1.0; 400];
        let domain = Rect {
            min: Vec2::ZERO,
            max: Vec2::new(4000.0, 1000.0),
        };
        for parts in [2, 3, 5, 7] {
            let d = Decomposition::rcb(&points, &weights, domain, parts).unwrap();
            for p in &points {
                let b = d.boxes()[d.owner_of(*p)];
                assert!(p.x > b.min.x && p.x < b.max.x, "{parts}: {p:?} {b:?}");
            }
            assert!(d.imbalance(&points, &weights) < 0.35, "{parts}");
        }
        // All floes at one place cannot be split.
        let same = vec![Vec2::new(1.0, 1.0); 4];
        assert!(Decomposition::rcb(&same, &[1.0; 4], domain, 2).is_err());
    }

    #[test]
    fn a_floe_reaches_a_box_within_its_radius_and_skin() {
        let (points, weights, domain) = cloud(100, 2);
        let d = Decomposition::rcb(&points, &weights, domain, 2).unwrap();
        let b = d.boxes()[0];
        let outside = Vec2::new(b.max.x + 10.0, 0.5 * (b.min.y + b.max.y));
        if b.max.x < domain.max.x {
            assert!(d.reaches(0, outside, 10.0));
            assert!(!d.reaches(0, outside, 9.9));
        }
    }
}
