//! Where a ridging floe is cut: the line parallel to the contact chord
//! behind which the loser's ice goes to the ridge, placed so that the
//! overlap left carries exactly the capped force.

use crate::geometry::{overlap, ClipScratch, Placed};
use crate::Vec2;

/// A ridging contact seen from the loser: polygons in world orientation,
/// the loser's about its centroid.
#[derive(Debug, Clone, Copy)]
pub struct RidgingContact<'a> {
    /// The loser's vertices about its centroid, counter-clockwise, m.
    pub loser: &'a [Vec2],
    /// The gainer's vertices about its own centroid, counter-clockwise, m.
    pub gainer: &'a [Vec2],
    /// The gainer's centroid from the loser's (its touching image), m.
    pub gainer_offset: Vec2,
    /// Unit normal from the loser towards the gainer.
    pub normal: Vec2,
    /// The ridging strength, N per m of contact.
    pub strength_n_per_m: f64,
}

/// The loser cut in two.
#[derive(Debug, Clone, PartialEq)]
pub struct Cut {
    /// The part kept, about the loser's centroid, counter-clockwise, m.
    pub kept: Vec<Vec2>,
    /// The part that goes to the ridge, same frame.
    pub removed: Vec<Vec2>,
    /// The elastic force the overlap left carries, N (at most the cap).
    pub elastic_after_n: f64,
    /// The elastic energy it holds as a strip of its mean depth, `F d / 2`
    /// (`d` its area over the contact length), J.
    pub stored_after_j: f64,
    /// The overlap left, m^2.
    pub overlap_after_m2: f64,
}

/// Most evaluations of the cut: Newton steps, each kept inside the bracket
/// (halving it when a step would leave it).
const MOST_STEPS: usize = 60;

/// The force left below the cap by at most this fraction ends the search.
const FORCE_TOLERANCE: f64 = 1e-9;

/// The loser kept behind the line at `s`, and its contact then.
struct Trial {
    kept: Vec<Vec2>,
    /// Elastic force over the cap (strength times contact length), N;
    /// `-inf` without an overlap.
    excess_n: f64,
    elastic_n: f64,
    /// `F d / 2` of the overlap, J.
    stored_j: f64,
    /// The overlap's area, m^2.
    overlap_m2: f64,
    /// The cap, N.
    cap_n: f64,
    /// d(elastic)/ds for a strip, `kappa l`, N/m.
    slope_n_per_m: f64,
}

/// The cut that brings the contact's elastic force `stiffness(kept area) x
/// overlap area` down to the strength times the contact length, or `None`
/// when it is not above that. `stiffness` is the contact's overlap
/// stiffness with the loser's area changed to the one given (Pa). The line
/// is found by Newton steps on the force (for an edge-on strip the force
/// falls by `kappa l` per metre the line moves back: one step), each
/// safeguarded by the bracket, to `FORCE_TOLERANCE` of the cap below it.
pub fn ridge_cut(c: &RidgingContact, stiffness: impl Fn(f64) -> f64) -> Option<Cut> {
    let n = c.normal;
    let mut scratch = ClipScratch::default();
    let gainer = Placed {
        vertices: c.gainer,
        position: c.gainer_offset,
        cos: 1.0,
        sin: 0.0,
        radius_m: radius(c.gainer),
    };
    let mut trial = |s: f64| -> Trial {
        let kept = clip_half_plane(c.loser, n, s);
        let none = |kept| Trial {
            kept,
            excess_n: f64::NEG_INFINITY,
            elastic_n: 0.0,
            stored_j: 0.0,
            overlap_m2: 0.0,
            cap_n: 0.0,
            slope_n_per_m: 0.0,
        };
        if kept.len() < 3 {
            return none(kept);
        }
        let placed = Placed {
            vertices: &kept,
            position: Vec2::ZERO,
            cos: 1.0,
            sin: 0.0,
            radius_m: radius(&kept),
        };
        match overlap(placed, gainer, &mut scratch) {
            None => none(kept),
            Some(ov) => {
                let kappa = stiffness(crate::geometry::shape::area_and_centroid(&kept).0);
                let elastic_n = kappa * ov.area_m2;
                let cap_n = c.strength_n_per_m * ov.length_m;
                Trial {
                    kept,
                    excess_n: elastic_n - cap_n,
                    elastic_n,
                    stored_j: 0.5 * elastic_n * ov.area_m2 / ov.length_m.max(f64::MIN_POSITIVE),
                    overlap_m2: ov.area_m2,
                    cap_n,
                    slope_n_per_m: kappa * ov.length_m,
                }
            }
        }
    };
    let mut hi = c
        .loser
        .iter()
        .map(|v| v.dot(n))
        .fold(f64::NEG_INFINITY, f64::max);
    let mut lo = c
        .gainer
        .iter()
        .map(|&v| (v + c.gainer_offset).dot(n))
        .fold(f64::INFINITY, f64::min);
    let start = trial(hi);
    // NaN-safe: a NaN excess or bound makes no cut.
    let over = |t: &Trial| t.excess_n.partial_cmp(&0.0) == Some(std::cmp::Ordering::Greater);
    if !over(&start) || lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) {
        return None;
    }
    let width = hi - lo;
    let (mut s, mut at) = (hi, start);
    // The kept part and its force at `lo`, once a trial has landed there.
    let mut below: Option<(Vec<Vec2>, f64, f64, f64)> = None;
    for _ in 0..MOST_STEPS {
        let newton = s - at.excess_n / at.slope_n_per_m;
        let next = if at.slope_n_per_m > 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        let t = trial(next);
        s = next;
        if over(&t) {
            hi = next;
        } else {
            lo = next;
            below = Some((t.kept.clone(), t.elastic_n, t.stored_j, t.overlap_m2));
            if t.excess_n >= -FORCE_TOLERANCE * t.cap_n {
                break;
            }
        }
        at = t;
        if hi - lo <= 1e-12 * width {
            break;
        }
    }
    let (kept, elastic_after_n, stored_after_j, overlap_after_m2) = match below {
        Some(b) => b,
        None => {
            let t = trial(lo);
            (t.kept, t.elastic_n, t.stored_j, t.overlap_m2)
        }
    };
    let removed = clip_half_plane(c.loser, -n, -lo);
    Some(Cut {
        kept,
        removed,
        elastic_after_n,
        stored_after_j,
        overlap_after_m2,
    })
}

/// The part of the convex polygon `p` where `x . n <= s`: convex, with at
/// most one vertex more than `p`.
pub fn clip_half_plane(p: &[Vec2], n: Vec2, s: f64) -> Vec<Vec2> {
    let mut out = Vec::with_capacity(p.len() + 1);
    for (i, &u) in p.iter().enumerate() {
        let v = p[(i + 1) % p.len()];
        let (du, dv) = (u.dot(n) - s, v.dot(n) - s);
        if du <= 0.0 {
            out.push(u);
        }
        if (du < 0.0 && dv > 0.0) || (du > 0.0 && dv < 0.0) {
            out.push(u + (v - u) * (du / (du - dv)));
        }
    }
    out
}

fn radius(p: &[Vec2]) -> f64 {
    p.iter().map(|v| v.length()).fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::shape::area_and_centroid;

    fn square(half: f64) -> Vec<Vec2> {
        vec![
            Vec2::new(-half, -half),
            Vec2::new(half, -half),
            Vec2::new(half, half),
            Vec2::new(-half, half),
        ]
    }

    #[test]
    fn a_half_plane_cut_tiles_the_polygon() {
        let p = vec![
            Vec2::new(0.0, -2.0),
            Vec2::new(3.0, 0.0),
            Vec2::new(0.0, 2.0),
            Vec2::new(-3.0, 0.0),
        ];
        let n = Vec2::new(0.6, 0.8);
        let (a, b) = (clip_half_plane(&p, n, 0.7), clip_half_plane(&p, -n, -0.7));
        let (whole, _) = area_and_centroid(&p);
        let (ka, ca) = area_and_centroid(&a);
        let (kb, cb) = area_and_centroid(&b);
        assert!((ka + kb - whole).abs() < 1e-12 * whole);
        // The pieces' first moments add up to the whole's (about 0).
        assert!((ca * ka + cb * kb).length() < 1e-12 * whole);
        assert!(a.iter().all(|v| v.dot(n) <= 0.7 + 1e-12));
    }

    #[test]
    fn an_edge_on_overlap_is_cut_to_the_strength_over_the_stiffness() {
        // Two 100 m squares, the gainer 2 m into the loser along x: the
        // overlap is a 100 m x 2 m strip, the chord 100 m long. With
        // kappa = 1e6 Pa and strength 5e4 N/m the capped penetration is
        // strength / kappa = 0.05 m: the loser loses 1.95 m x 100 m.
        let (loser, gainer) = (square(50.0), square(50.0));
        let c = RidgingContact {
            loser: &loser,
            gainer: &gainer,
            gainer_offset: Vec2::new(98.0, 0.0),
            normal: Vec2::X,
            strength_n_per_m: 5e4,
        };
        let cut = ridge_cut(&c, |_| 1e6).expect("over the cap");
        let (kept, _) = area_and_centroid(&cut.kept);
        let (removed, _) = area_and_centroid(&cut.removed);
        assert!((removed - 195.0).abs() < 1e-9, "{removed}");
        assert!((kept + removed - 1e4).abs() < 1e-9);
        assert!((cut.elastic_after_n - 5e4 * 100.0).abs() < 1e-6 * 5e6);
        // Under the cap nothing is cut.
        let weak = RidgingContact {
            strength_n_per_m: 3e6,
            ..c
        };
        assert!(ridge_cut(&weak, |_| 1e6).is_none());
    }
}
