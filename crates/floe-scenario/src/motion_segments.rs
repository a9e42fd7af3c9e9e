//! `[[wall.segment]]` and `[[floe.segment]]`: a prescribed body's motion
//! schedule (floe-dem's `MotionSchedule`), checked and located.

use std::ops::Range;

use floe_dem::motion_schedule::{MotionSchedule, MotionSegment};
use floe_dem::Vec2;
use toml::Spanned;

use crate::error::ScenarioError;
use crate::extent::{Extent, MAX_ANGULAR_VELOCITY_RAD_PER_S, MAX_TRAVEL_DOMAINS};
use crate::numbers::sig;
use crate::source_file::SourceFile;
use crate::spec::RawSegment;

/// Most segments one schedule may have (checks of wall travel and meeting
/// look at every boundary).
pub(crate) const MAX_SEGMENTS: usize = 10_000;

/// The schedule of `segments` (keys named `{owner}.segment[k].…`), with
/// rotation allowed only when `rotation` is true. Refuses a schedule that
/// carries its body more than `MAX_TRAVEL_DOMAINS` domain sizes across the
/// domain's non-periodic axes within the run.
pub(crate) fn resolve_schedule(
    f: &SourceFile,
    (segments, owner_span): (&[toml::Spanned<RawSegment>], Range<usize>),
    owner: &str,
    rotation: bool,
    extent: Extent,
) -> Result<MotionSchedule, ScenarioError> {
    if segments.len() > MAX_SEGMENTS {
        return Err(f.error(
            segments[MAX_SEGMENTS].span(),
            format!("{owner}.segment[{MAX_SEGMENTS}]"),
            format!(
                "{} segments, more than the {MAX_SEGMENTS} a schedule may have",
                segments.len()
            ),
        ));
    }
    let mut out = Vec::with_capacity(segments.len());
    for (k, s) in segments.iter().enumerate() {
        let key = |name: &str| format!("{owner}.segment[{k}].{name}");
        let r = s.get_ref();
        let Some(d) = &r.duration_s else {
            return Err(f.error(
                s.span(),
                key("duration_s"),
                "missing: the segment's length in s",
            ));
        };
        let duration_s = f.positive(d, &key("duration_s"))?;
        let velocity = |v: &Option<Spanned<crate::spec::Exact<f64, 2>>>, name: &str| {
            v.as_ref().map(|v| f.pair(v, &key(name))).transpose()
        };
        let start = velocity(&r.velocity_m_per_s, "velocity_m_per_s")?.unwrap_or(Vec2::ZERO);
        let end = velocity(&r.end_velocity_m_per_s, "end_velocity_m_per_s")?.unwrap_or(start);
        let spin = |w: &Option<Spanned<f64>>, name: &str| -> Result<Option<f64>, ScenarioError> {
            let Some(w) = w else { return Ok(None) };
            if !rotation {
                return Err(f.error(
                    w.span(),
                    key(name),
                    "a wall translates only (its segments would turn about their own centres); \
                     a rotating boundary is a prescribed [[floe]]",
                ));
            }
            let most = MAX_ANGULAR_VELOCITY_RAD_PER_S;
            f.in_range(w, &key(name), (-most, most), "rad/s").map(Some)
        };
        let w0 = spin(&r.angular_velocity_rad_per_s, "angular_velocity_rad_per_s")?.unwrap_or(0.0);
        let w1 = spin(
            &r.end_angular_velocity_rad_per_s,
            "end_angular_velocity_rad_per_s",
        )?
        .unwrap_or(w0);
        out.push(MotionSegment {
            duration_s,
            velocity_start: start,
            velocity_end: end,
            angular_velocity_start: w0,
            angular_velocity_end: w1,
        });
    }
    if out.is_empty() {
        return Err(f.error(
            owner_span,
            format!("{owner}.segment"),
            "is empty: a schedule needs at least one segment table with duration_s",
        ));
    }
    let schedule = MotionSchedule::new(out).map_err(|e| {
        let span = segments.first().map_or(0..0, |s| s.span());
        f.error(span, format!("{owner}.segment"), e.to_string())
    })?;
    travel_bound(f, segments, owner, &schedule, extent)?;
    Ok(schedule)
}

/// Refuses a schedule whose travel across the non-periodic axes over the
/// run exceeds [`MAX_TRAVEL_DOMAINS`] domain sizes (walls are built as long
/// as their travel), blaming the segment where the bound is crossed.
fn travel_bound(
    f: &SourceFile,
    segments: &[toml::Spanned<RawSegment>],
    owner: &str,
    schedule: &MotionSchedule,
    extent: Extent,
) -> Result<(), ScenarioError> {
    let d = extent.domain;
    let mask = |v: Vec2| {
        Vec2::new(
            if d.periodic[0] { 0.0 } else { v.x },
            if d.periodic[1] { 0.0 } else { v.y },
        )
    };
    let most = MAX_TRAVEL_DOMAINS * d.size_m.x.max(d.size_m.y);
    let last = segments.len() - 1;
    let (mut start, mut travel) = (0.0, 0.0);
    for (k, s) in schedule.segments().iter().enumerate() {
        if start >= extent.duration_s {
            break;
        }
        let t = s.duration_s.min(extent.duration_s - start);
        let speed = mask(s.velocity_start)
            .length()
            .max(mask(s.velocity_end).length());
        travel += speed * t;
        // The last segment's end velocity continues to the end of the run.
        if k == last {
            travel += mask(s.velocity_end).length() * (extent.duration_s - start - t).max(0.0);
        }
        if travel > most {
            return Err(f.error(
                span_of(segments, k),
                format!("{owner}.segment[{k}]"),
                format!(
                    "the schedule moves the {owner} up to {} m across the domain's non-periodic \
                     axes by this segment, more than {MAX_TRAVEL_DOMAINS} domain sizes ({} m)",
                    sig(travel),
                    sig(most)
                ),
            ));
        }
        start += s.duration_s;
    }
    Ok(())
}

fn span_of(segments: &[toml::Spanned<RawSegment>], k: usize) -> Range<usize> {
    segments[k].span()
}

/// A schedule for the build report: its segments' velocities in order.
pub(crate) fn describe_schedule(s: &MotionSchedule) -> String {
    let parts: Vec<String> = s
        .segments()
        .iter()
        .map(|g| {
            let v = |v: Vec2| format!("[{}, {}]", sig(v.x), sig(v.y));
            if g.velocity_start == g.velocity_end {
                format!("{} for {} s", v(g.velocity_start), sig(g.duration_s))
            } else {
                format!(
                    "{} to {} over {} s",
                    v(g.velocity_start),
                    v(g.velocity_end),
                    sig(g.duration_s)
                )
            }
        })
        .collect();
    format!(
        "on a schedule of {} segments (m/s): {}, then the last velocity",
        parts.len(),
        parts.join(", ")
    )
}
