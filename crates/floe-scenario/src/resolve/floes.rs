//! Where the floes come from: explicit `[[floe]]` tables, or a
//! `[tessellation]` ([`crate::tessellation`]).

use std::ops::Range;

use floe_dem::motion_schedule::MotionSchedule;
use floe_dem::Vec2;
use toml::Spanned;

use super::limits::{at_most, thickness, travel_within, MAX_LENGTH_M};
use crate::error::ScenarioError;
use crate::extent::{Extent, MAX_ANGULAR_VELOCITY_RAD_PER_S};
use crate::motion_segments::resolve_schedule;
use crate::numbers::short_list;
use crate::source_file::SourceFile;
use crate::spec::{Exact, RawFloe, RawScenario};
use crate::tessellation::{self, Kind, Tessellated, KINDS};

/// A `[[floe]]`, checked.
#[derive(Debug, Clone)]
pub(crate) struct ExplicitFloe {
    pub vertices: Vec<Vec2>,
    pub thickness_m: Option<f64>,
    pub velocity: Option<Vec2>,
    pub angular_velocity_rad_per_s: f64,
    pub prescribed: bool,
    /// `[[floe.segment]]` of a prescribed floe.
    pub schedule: Option<MotionSchedule>,
    /// `[floe.load_point]` of a free floe: stiffness (N/m) and schedule.
    pub load_point: Option<(f64, MotionSchedule)>,
    pub span: Range<usize>,
}

/// Where the floes come from.
#[derive(Debug, Clone)]
pub(crate) enum FloeSource {
    /// A `[tessellation]` of one of [`KINDS`].
    Tessellation(Tessellated),
    Explicit(Vec<ExplicitFloe>),
}

impl FloeSource {
    /// The tessellation's kind, if the floes are generated.
    pub fn kind(&self) -> Option<&'static Kind> {
        match self {
            FloeSource::Tessellation(t) => Some(t.kind),
            FloeSource::Explicit(_) => None,
        }
    }
}

/// Accepted load-point spring stiffnesses, N/m (the paper's apparatus:
/// 2e7 lab, 2e6 tank).
pub const LOAD_POINT_STIFFNESS_RANGE_N_PER_M: (f64, f64) = (1e-3, 1e12);

pub(crate) fn resolve_floes(
    f: &SourceFile,
    raw: &RawScenario,
    extent: Extent,
) -> Result<(FloeSource, Range<usize>, f64), ScenarioError> {
    match (&raw.tessellation, &raw.floe) {
        (Some(t), Some(floes)) => {
            let span = floes.first().map_or(t.span(), |fl| fl.span());
            Err(f.error(
                span,
                "floe",
                "explicit [[floe]] tables and [tessellation] exclude each other: use one",
            ))
        }
        (None, None) => {
            let kinds: Vec<&str> = KINDS.iter().map(|k| k.name).collect();
            Err(f.error_in_file(format!(
                "no floes: add a [tessellation] ({}) or [[floe]] tables",
                kinds.join(", ")
            )))
        }
        (None, Some(floes)) => {
            let mut out = Vec::with_capacity(floes.len());
            for (i, fl) in floes.iter().enumerate() {
                out.push(resolve_explicit_floe(f, fl, i, extent)?);
            }
            let span = floes.first().map_or(0..0, |fl| fl.span());
            Ok((FloeSource::Explicit(out), span, 0.0))
        }
        (Some(t), None) => {
            let (t, span, min_area_fraction) = tessellation::resolve(f, t, extent)?;
            Ok((FloeSource::Tessellation(t), span, min_area_fraction))
        }
    }
}

pub(crate) fn resolve_explicit_floe(
    f: &SourceFile,
    raw: &Spanned<RawFloe>,
    i: usize,
    extent: Extent,
) -> Result<ExplicitFloe, ScenarioError> {
    let fl = raw.get_ref();
    let key = |k: &str| format!("floe[{i}].{k}");
    let vertices = match (&fl.vertices_m, &fl.box_m) {
        (Some(v), None) => {
            let pts: Vec<Vec2> = v
                .get_ref()
                .iter()
                .map(|&Exact([x, y])| Vec2::new(x, y))
                .collect();
            if pts.iter().any(|p| !(p.x.is_finite() && p.y.is_finite())) {
                return Err(f.error(v.span(), key("vertices_m"), "coordinates must be finite"));
            }
            let coords: Vec<f64> = pts.iter().flat_map(|p| [p.x, p.y]).collect();
            at_most(f, v.span(), &key("vertices_m"), &coords, MAX_LENGTH_M, "m")?;
            pts
        }
        (None, Some(b)) => {
            let [x0, y0, x1, y1] = b.get_ref().0;
            if !([x0, y0, x1, y1].iter().all(|v| v.is_finite()) && x1 > x0 && y1 > y0) {
                return Err(f.error(
                    b.span(),
                    key("box_m"),
                    format!(
                        "must be [x_min, y_min, x_max, y_max] with max > min, got {}",
                        short_list(&[x0, y0, x1, y1])
                    ),
                ));
            }
            at_most(f, b.span(), &key("box_m"), &[x0, y0, x1, y1], MAX_LENGTH_M, "m")?;
            vec![
                Vec2::new(x0, y0),
                Vec2::new(x1, y0),
                Vec2::new(x1, y1),
                Vec2::new(x0, y1),
            ]
        }
        _ => {
            return Err(f.error(
                raw.span(),
                format!("floe[{i}]"),
                "give exactly one of `vertices_m = [[x, y], ...]` (convex outline) or `box_m = [x_min, y_min, x_max, y_max]`",
            ))
        }
    };
    let prescribed = fl.prescribed.as_ref().is_some_and(|p| *p.get_ref());
    let schedule = match &fl.segment {
        None => None,
        Some(segments) => {
            let first = segments.first().map_or(raw.span(), |s| s.span());
            if !prescribed {
                return Err(f.error(
                    first,
                    key("segment"),
                    "only a prescribed floe (prescribed = true) follows a motion schedule",
                ));
            }
            for (given, name) in [
                (
                    fl.velocity_m_per_s.as_ref().map(|v| v.span()),
                    "velocity_m_per_s",
                ),
                (
                    fl.angular_velocity_rad_per_s.as_ref().map(|v| v.span()),
                    "angular_velocity_rad_per_s",
                ),
            ] {
                if let Some(span) = given {
                    return Err(f.error(
                        span,
                        key(name),
                        "give the floe's motion either as velocities or as [[floe.segment]] \
                         tables, not both",
                    ));
                }
            }
            Some(resolve_schedule(
                f,
                (segments, raw.span()),
                &format!("floe[{i}]"),
                true,
                extent,
            )?)
        }
    };
    let load_point = match &fl.load_point {
        None => None,
        Some(lp) => {
            let owner = format!("floe[{i}].load_point");
            if prescribed {
                return Err(f.error(
                    lp.span(),
                    key("load_point"),
                    "a load point drives a free floe through its spring; a prescribed floe \
                     ignores forces (drop prescribed = true, or give it [[floe.segment]])",
                ));
            }
            let r = lp.get_ref();
            let Some(k) = &r.stiffness_n_per_m else {
                return Err(f.error(
                    lp.span(),
                    format!("{owner}.stiffness_n_per_m"),
                    "missing: the spring's stiffness in N/m (the paper's apparatus: 2e7 lab, \
                     2e6 tank)",
                ));
            };
            let k = f.in_range(
                k,
                &format!("{owner}.stiffness_n_per_m"),
                LOAD_POINT_STIFFNESS_RANGE_N_PER_M,
                "N/m",
            )?;
            let Some(segments) = &r.segment else {
                return Err(f.error(
                    lp.span(),
                    format!("{owner}.segment"),
                    "missing: [[floe.load_point.segment]] tables saying how the load point moves",
                ));
            };
            Some((
                k,
                resolve_schedule(f, (segments, lp.span()), &owner, false, extent)?,
            ))
        }
    };
    Ok(ExplicitFloe {
        vertices,
        thickness_m: fl
            .thickness_m
            .as_ref()
            .map(|h| thickness(f, h, &key("thickness_m"), false))
            .transpose()?,
        velocity: fl
            .velocity_m_per_s
            .as_ref()
            .map(|v| {
                let velocity = f.pair(v, &key("velocity_m_per_s"))?;
                // A prescribed floe keeps its velocity: bound its travel.
                if fl.prescribed.as_ref().is_some_and(|p| *p.get_ref()) {
                    travel_within(f, v, &key("velocity_m_per_s"), velocity, extent, "floe")?;
                }
                Ok::<_, ScenarioError>(velocity)
            })
            .transpose()?,
        angular_velocity_rad_per_s: fl
            .angular_velocity_rad_per_s
            .as_ref()
            .map(|w| {
                let most = MAX_ANGULAR_VELOCITY_RAD_PER_S;
                f.in_range(
                    w,
                    &key("angular_velocity_rad_per_s"),
                    (-most, most),
                    "rad/s",
                )
            })
            .transpose()?
            .unwrap_or(0.0),
        prescribed: fl.prescribed.as_ref().is_some_and(|p| *p.get_ref()),
        schedule,
        load_point,
        span: raw.span(),
    })
}
