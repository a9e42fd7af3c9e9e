//! Physical consistency of a scenario: checks that involve several values
//! together (walls against the domain and each other, explicit floes
//! against each other); the contact geometry of the double-shear set-up
//! is [`double_shear_geometry`].

use floe_dem::geometry::{overlap, ClipScratch};

use crate::built_floes::BuiltFloes;
use crate::error::ScenarioError;
use crate::numbers::sig;
use crate::resolve::{Resolved, Side, Wall};
use crate::source_file::SourceFile;
pub use crate::tessellation::double_shear_geometry::{double_shear_geometry, DoubleShearGeometry};

/// Overlap area, as a fraction of the smaller floe, above which explicit
/// floes are refused as overlapping at the start.
pub const OVERLAP_TOLERANCE: f64 = 1e-6;

/// Walls: not across a periodic axis, inside the domain, and not meeting
/// (or crossing the domain) before the end of the run.
pub(crate) fn walls_fit(f: &SourceFile, r: &Resolved) -> Result<(), ScenarioError> {
    let d = &r.domain;
    let axis_name = ["x", "y"];
    for w in &r.walls {
        let axis = w.side.axis();
        if d.periodic[axis] {
            return Err(f.error(
                w.span.clone(),
                format!("wall[{}].side", w.index),
                format!(
                    "the domain is periodic along {}: a {} wall would cut the period (set domain.periodic to false along {} or remove the wall)",
                    axis_name[axis],
                    w.side.name(),
                    axis_name[axis]
                ),
            ));
        }
    }
    for (axis, axis_label) in axis_name.iter().enumerate() {
        let (lo_side, hi_side) = if axis == 0 {
            (Side::Left, Side::Right)
        } else {
            (Side::Bottom, Side::Top)
        };
        let lo = r.walls.iter().find(|w| w.side == lo_side);
        let hi = r.walls.iter().find(|w| w.side == hi_side);
        let insets = lo.map_or(0.0, |w| w.inset_m) + hi.map_or(0.0, |w| w.inset_m);
        let extent = d.size_m[axis];
        if insets >= extent {
            let w = hi.or(lo).expect("an inset comes from a wall");
            return Err(f.error(
                w.inset_span.clone(),
                format!("wall[{}].inset_m", w.index),
                format!(
                    "the wall lies outside the domain: insets of {} m leave nothing of its {} m {}",
                    sig(insets),
                    sig(extent),
                    if axis == 0 { "width" } else { "height" }
                ),
            ));
        }
        let gap = extent - insets;
        if let Some(meet_s) = walls_meet_s(lo, hi, axis, gap, r.duration_s) {
            let moves_in = |w: &&Wall| w.schedule.is_some() || w.velocity[axis] != 0.0;
            let w = hi.filter(moves_in).or(lo).expect("a closing wall exists");
            let key = if w.schedule.is_some() {
                "segment"
            } else {
                "velocity_m_per_s"
            };
            return Err(f.error(
                w.velocity_span.clone(),
                format!("wall[{}].{key}", w.index),
                format!(
                    "the walls across {} close {} m in {} s, before duration_s = {} s: {}",
                    axis_label,
                    sig(gap),
                    sig(meet_s),
                    sig(r.duration_s),
                    if lo.is_some() && hi.is_some() {
                        "they would cross each other"
                    } else {
                        "the wall would cross the whole domain"
                    }
                ),
            ));
        }
    }
    Ok(())
}

/// No two floes (at least one of them free) overlap by more than
/// [`OVERLAP_TOLERANCE`] of the smaller one.
pub(crate) fn no_initial_overlap(
    f: &SourceFile,
    r: &Resolved,
    built: &BuiltFloes,
) -> Result<(), ScenarioError> {
    let fl = &built.floes;
    let periodicity = r.domain.periodicity();
    let mut scratch = ClipScratch::default();
    let placed = |i: usize, offset| fl.placed(i, offset, fl.angle[i].sin_cos());
    let name = |i: usize| {
        built.labels[i]
            .clone()
            .unwrap_or_else(|| format!("floe {i}"))
    };
    for i in 0..fl.len() {
        for j in (i + 1)..fl.len() {
            if !fl.is_free(i) && !fl.is_free(j) {
                continue;
            }
            let offset = periodicity.nearest_image(fl.position[i], fl.position[j]);
            let reach = fl.radius_m[i] + fl.radius_m[j];
            if (fl.position[j] + offset - fl.position[i]).length_squared() > reach * reach {
                continue;
            }
            let Some(ov) = overlap(
                placed(i, floe_dem::Vec2::ZERO),
                placed(j, offset),
                &mut scratch,
            ) else {
                continue;
            };
            let smaller = fl.area_m2[i].min(fl.area_m2[j]);
            if ov.area_m2 > OVERLAP_TOLERANCE * smaller {
                let span = built.pieces_span[j]
                    .clone()
                    .or_else(|| built.pieces_span[i].clone())
                    .unwrap_or_else(|| r.floes_span.clone());
                return Err(f.error(
                    span,
                    name(j),
                    format!(
                        "overlaps {} by {} m^2 ({} % of the smaller floe) at the start; floes may touch but not overlap",
                        name(i),
                        sig(ov.area_m2),
                        sig(100.0 * ov.area_m2 / smaller)
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// When the walls `lo` and `hi` across `axis` (either may be absent) first
/// close a gap of `gap` m within `duration_s`, if they do. The closing is
/// piecewise quadratic in time (linear velocities per segment): it is
/// largest at a segment boundary or where the walls' relative velocity
/// along the axis is zero, and those are the times tested.
fn walls_meet_s(
    lo: Option<&Wall>,
    hi: Option<&Wall>,
    axis: usize,
    gap: f64,
    duration_s: f64,
) -> Option<f64> {
    let closing = |t: f64| {
        lo.map_or(0.0, |w| w.travel_to(t)[axis]) - hi.map_or(0.0, |w| w.travel_to(t)[axis])
    };
    let mut times = vec![0.0, duration_s];
    for w in [lo, hi].into_iter().flatten() {
        if let Some(s) = &w.schedule {
            let mut t = 0.0;
            for g in s.segments() {
                t += g.duration_s;
                if t < duration_s {
                    times.push(t);
                }
            }
        }
    }
    times.sort_by(f64::total_cmp);
    times.dedup();
    let mut candidates = times.clone();
    for pair in times.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        // Relative velocity is linear on (a, b): its root from two points.
        let velocity = |t: f64| {
            lo.map_or(0.0, |w| w.velocity_at(t)[axis]) - hi.map_or(0.0, |w| w.velocity_at(t)[axis])
        };
        let (p, q) = (a + 0.25 * (b - a), a + 0.75 * (b - a));
        let (vp, vq) = (velocity(p), velocity(q));
        if vp != vq {
            let root = p + vp * (q - p) / (vp - vq);
            if root > a && root < b {
                candidates.push(root);
            }
        }
    }
    candidates.sort_by(f64::total_cmp);
    let k = candidates.iter().position(|&t| closing(t) >= gap)?;
    if k == 0 {
        return Some(0.0);
    }
    // Between two candidates the closing is monotone: bisect for the time.
    let (mut a, mut b) = (candidates[k - 1], candidates[k]);
    for _ in 0..64 {
        let m = 0.5 * (a + b);
        if closing(m) >= gap {
            b = m;
        } else {
            a = m;
        }
    }
    Some(b)
}
