//! `[[wall]]`: which side each wall closes, how it moves, and the stress
//! it may hold.

use std::ops::Range;

use floe_dem::motion_schedule::MotionSchedule;
use floe_dem::Vec2;
use toml::Spanned;

use super::limits::{distance, travel_within};
use crate::error::ScenarioError;
use crate::extent::Extent;
use crate::motion_segments::resolve_schedule;
use crate::numbers::{short, sig};
use crate::source_file::SourceFile;
use crate::spec::RawWall;
use crate::stress_wall::{resolve_control_keys, ControlKeys};

/// Which side of the domain a wall closes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Side {
    Left,
    Right,
    Bottom,
    Top,
}

impl Side {
    pub fn name(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
            Side::Bottom => "bottom",
            Side::Top => "top",
        }
    }

    /// 0 for walls across x (left, right), 1 for walls across y.
    pub fn axis(self) -> usize {
        match self {
            Side::Left | Side::Right => 0,
            Side::Bottom | Side::Top => 1,
        }
    }
}

/// A `[[wall]]`, checked.
#[derive(Debug, Clone)]
pub(crate) struct Wall {
    pub index: usize,
    pub side: Side,
    /// The velocity at the start (the schedule's, when it has one).
    pub velocity: Vec2,
    /// `[[wall.segment]]`, when given.
    pub schedule: Option<MotionSchedule>,
    /// `normal_stress_n_per_m` and the control's keys, when the wall holds
    /// a stress.
    pub stress: Option<(f64, ControlKeys)>,
    /// Floes whose centroid lies within this distance of the wall's face
    /// move with it (a rough wall), m; 0: none.
    pub glue_depth_m: f64,
    pub inset_m: f64,
    pub thickness_m: Option<f64>,
    pub span: Range<usize>,
    pub velocity_span: Range<usize>,
    pub inset_span: Range<usize>,
}

impl Wall {
    /// The most the wall can be from where it started over `duration_s`, m.
    pub(crate) fn most_travel_m(&self, duration_s: f64) -> f64 {
        match &self.schedule {
            Some(s) => s.most_travel_m(duration_s),
            None => self.velocity.length() * duration_s,
        }
    }

    /// Its velocity at time `t_s`, m/s.
    pub(crate) fn velocity_at(&self, t_s: f64) -> Vec2 {
        match &self.schedule {
            Some(s) => s.velocity_at(t_s).0,
            None => self.velocity,
        }
    }

    /// Its displacement from the start at time `t_s`, m.
    pub(crate) fn travel_to(&self, t_s: f64) -> Vec2 {
        match &self.schedule {
            Some(s) => s.travel_to(t_s).0,
            None => self.velocity * t_s,
        }
    }
}
/// Largest normal stress a wall may hold, N/m (vertically integrated; the
/// pack's strength is tens of kN/m).
pub const MAX_WALL_STRESS_N_PER_M: f64 = 1e9;

pub(crate) fn resolve_walls(
    f: &SourceFile,
    raw: &[Spanned<RawWall>],
    extent: Extent,
) -> Result<Vec<Wall>, ScenarioError> {
    let mut walls: Vec<Wall> = Vec::with_capacity(raw.len());
    for (i, w) in raw.iter().enumerate() {
        let r = w.get_ref();
        let key = |k: &str| format!("wall[{i}].{k}");
        let Some(side_word) = &r.side else {
            return Err(f.error(
                w.span(),
                key("side"),
                "missing: `left`, `right`, `bottom` or `top`",
            ));
        };
        let side = f.keyword(
            &r.side,
            &key("side"),
            &[
                ("left", Side::Left),
                ("right", Side::Right),
                ("bottom", Side::Bottom),
                ("top", Side::Top),
            ],
            Side::Left,
        )?;
        if let Some(other) = walls.iter().find(|o| o.side == side) {
            return Err(f.error(
                side_word.span(),
                key("side"),
                format!(
                    "wall[{}] is already on the {} side",
                    other.index,
                    side.name()
                ),
            ));
        }
        let schedule = match (&r.segment, &r.velocity_m_per_s) {
            (Some(_), Some(v)) => {
                return Err(f.error(
                    v.span(),
                    key("velocity_m_per_s"),
                    "give the wall's motion either as velocity_m_per_s or as [[wall.segment]] \
                     tables, not both",
                ))
            }
            (Some(segments), None) => Some(resolve_schedule(
                f,
                (segments, w.span()),
                &format!("wall[{i}]"),
                false,
                extent,
            )?),
            (None, _) => None,
        };
        let velocity = match (&schedule, &r.velocity_m_per_s) {
            (Some(s), _) => s.velocity_at(0.0).0,
            (None, Some(v)) => {
                let velocity = f.pair(v, &key("velocity_m_per_s"))?;
                // The wall is built as long as its travel: bound that.
                travel_within(f, v, &key("velocity_m_per_s"), velocity, extent, "wall")?;
                velocity
            }
            (None, None) => Vec2::ZERO,
        };
        let control = resolve_control_keys(f, r, i)?;
        let stress = match (&r.normal_stress_n_per_m, control) {
            (None, _) | (_, None) => None,
            (Some(target), Some(control)) => {
                let target = f.in_range(
                    target,
                    &key("normal_stress_n_per_m"),
                    (0.0, MAX_WALL_STRESS_N_PER_M),
                    "N/m",
                )?;
                // The servo sets the normal velocity: none may be given.
                let axis = side.axis();
                let across = |v: Vec2| v[axis] != 0.0;
                let normal_given = match (&schedule, &r.velocity_m_per_s) {
                    (Some(s), _) => s
                        .segments()
                        .iter()
                        .any(|g| across(g.velocity_start) || across(g.velocity_end)),
                    (None, Some(_)) => across(velocity),
                    (None, None) => false,
                };
                if normal_given {
                    let span = r.velocity_m_per_s.as_ref().map_or(w.span(), |v| v.span());
                    return Err(f.error(
                        span,
                        key("velocity_m_per_s"),
                        "a wall holding normal_stress_n_per_m moves across itself as the \
                         stress asks: give its velocity along the wall only",
                    ));
                }
                Some((target, control))
            }
        };
        walls.push(Wall {
            index: i,
            side,
            velocity,
            schedule,
            stress,
            inset_m: match &r.inset_m {
                Some(v) => distance(f, v, &key("inset_m"))?,
                None => 0.0,
            },
            glue_depth_m: match &r.glue_depth_m {
                Some(v) => distance(f, v, &key("glue_depth_m"))?,
                None => 0.0,
            },
            thickness_m: r
                .thickness_m
                .as_ref()
                .map(|v| {
                    // Thicker than the domain adds nothing but segments.
                    let t = f.positive(v, &key("thickness_m"))?;
                    let most = extent.domain.size_m.x.max(extent.domain.size_m.y);
                    if t <= most {
                        return Ok(t);
                    }
                    Err(f.error(
                        v.span(),
                        key("thickness_m"),
                        format!(
                            "{} m is thicker than the domain's larger side, {} m",
                            short(t),
                            sig(most)
                        ),
                    ))
                })
                .transpose()?,
            span: side_word.span(),
            velocity_span: r.velocity_m_per_s.as_ref().map_or(w.span(), |v| v.span()),
            inset_span: r.inset_m.as_ref().map_or(w.span(), |v| v.span()),
        });
    }
    Ok(walls)
}
