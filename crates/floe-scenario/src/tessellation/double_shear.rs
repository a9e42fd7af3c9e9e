//! `kind = "double-shear"`: the double-shear set-up of Lishman et al.
//! (2011): a free block between two fixed blocks that overlap it by the
//! depth giving the normal load, pushed along x by a prescribed plate
//! whose contact is the loading spring.

use std::sync::Arc;

use floe_dem::motion_schedule::MotionSchedule;
use floe_dem::Vec2;
use floe_friction::FrictionLaw;

use super::double_shear_geometry::double_shear_geometry;
use super::{rect_polygon, Generate, Generation, Keys, Kind};
use crate::error::ScenarioError;
use crate::motion_segments::{describe_schedule, resolve_schedule};
use crate::numbers::{short_list, sig};
use crate::piece::Piece;
use crate::resolve::limits::{at_most, MAX_LENGTH_M};
use crate::spec::Pair;

/// Its line of [`super::KINDS`].
pub(super) const KIND: Kind = Kind {
    name: "double-shear",
    keys: &[
        "block_m",
        "side_block_m",
        "pusher_m",
        "normal_load_per_face_n",
        "push_velocity_m_per_s",
        "segment",
    ],
    resolve,
    sea_ice: false,
};

/// The double-shear set-up, checked.
#[derive(Debug, Clone)]
pub(crate) struct DoubleShear {
    pub block_m: [f64; 2],
    pub side_block_m: [f64; 2],
    pub pusher_m: [f64; 2],
    pub normal_load_per_face_n: f64,
    /// The pusher's velocity at the start.
    pub push_velocity_m_per_s: f64,
    /// `[[tessellation.segment]]`, when the pusher follows a schedule.
    pub push_schedule: Option<MotionSchedule>,
}

fn resolve(k: &Keys<'_>) -> Result<Arc<dyn Generate>, ScenarioError> {
    let (f, t) = (k.f, k.t);
    let size = |v: &Pair, key: &str| -> Result<[f64; 2], ScenarioError> {
        let Some(v) = v else {
            return Err(k.need(key));
        };
        let p = f.pair(v, &format!("tessellation.{key}"))?;
        if !(p.x > 0.0 && p.y > 0.0) {
            return Err(f.error(
                v.span(),
                format!("tessellation.{key}"),
                format!("lengths must be > 0, got {}", short_list(&[p.x, p.y])),
            ));
        }
        at_most(
            f,
            v.span(),
            &format!("tessellation.{key}"),
            &[p.x, p.y],
            MAX_LENGTH_M,
            "m",
        )?;
        Ok([p.x, p.y])
    };
    let block_m = size(&t.block_m, "block_m")?;
    let side_block_m = size(&t.side_block_m, "side_block_m")?;
    let pusher_m = match &t.pusher_m {
        Some(_) => size(&t.pusher_m, "pusher_m")?,
        None => [0.25 * block_m[0], block_m[1]],
    };
    let Some(load) = &t.normal_load_per_face_n else {
        return Err(k.need("normal_load_per_face_n"));
    };
    let (push_velocity_m_per_s, push_schedule) = match (&t.push_velocity_m_per_s, &t.segment) {
        (Some(push), None) => (
            f.non_negative(push, "tessellation.push_velocity_m_per_s")?,
            None,
        ),
        (None, Some(segments)) => {
            let s = resolve_schedule(
                f,
                (segments, k.span.clone()),
                "tessellation",
                false,
                k.extent,
            )?;
            (s.velocity_at(0.0).0.x, Some(s))
        }
        (Some(push), Some(_)) => {
            return Err(f.error(
                push.span(),
                "tessellation.push_velocity_m_per_s",
                "give the pusher's motion either as push_velocity_m_per_s or as \
                 [[tessellation.segment]] tables, not both",
            ))
        }
        (None, None) => return Err(k.need("push_velocity_m_per_s")),
    };
    if let Some(s) = &push_schedule {
        // The pusher pushes along +x: a segment across is refused.
        if let Some(k) = s
            .segments()
            .iter()
            .position(|g| g.velocity_start.y != 0.0 || g.velocity_end.y != 0.0)
        {
            let segments = t.segment.as_deref().unwrap_or(&[]);
            return Err(f.error(
                segments[k].span(),
                format!("tessellation.segment[{k}]"),
                "the pusher moves along the block (x) only: give velocities [v, 0.0]",
            ));
        }
    }
    Ok(Arc::new(DoubleShear {
        block_m,
        side_block_m,
        pusher_m,
        normal_load_per_face_n: f.positive(load, "tessellation.normal_load_per_face_n")?,
        push_velocity_m_per_s,
        push_schedule,
    }))
}

impl Generate for DoubleShear {
    fn generate(
        &self,
        g: &Generation<'_>,
        report: &mut Vec<String>,
    ) -> Result<Vec<Piece>, ScenarioError> {
        let DoubleShear {
            block_m: block,
            side_block_m: side,
            pusher_m: pusher,
            normal_load_per_face_n: load,
            push_velocity_m_per_s: v,
            ..
        } = *self;
        let schedule = self.push_schedule.as_ref();
        let (f, span) = (g.f, g.span.clone());
        let h = g.thickness.mean_m();
        let geometry = double_shear_geometry(g.model, h, block, pusher, load);
        if geometry.depth_m >= 0.25 * block[1] {
            return Err(f.error(
                span,
                "tessellation.normal_load_per_face_n",
                format!(
                    "{load} N per face needs an overlap {} m deep, over a quarter of the block's width {} m: raise contact.youngs_modulus_pa or lower the load",
                    sig(geometry.depth_m),
                    block[1]
                ),
            ));
        }
        let travel = match schedule {
            Some(s) => s.most_travel_m(g.duration_s),
            None => v * g.duration_s,
        };
        if side[0] < block[0] + travel {
            return Err(f.error(
                span,
                "tessellation.side_block_m",
                format!(
                    "side blocks {} m long are too short: the {} m block travels {} m in duration_s, so they must be at least {} m long",
                    sig(side[0]),
                    sig(block[0]),
                    sig(travel),
                    sig(block[0] + travel)
                ),
            ));
        }
        let d = &g.domain;
        let c = d.min_m + 0.5 * d.size_m;
        let depth = geometry.depth_m;
        let side_y = 0.5 * block[1] + 0.5 * side[1] - depth;
        let side_x = c.x + 0.5 * travel;
        let pusher_c = Vec2::new(c.x - 0.5 * block[0] - 0.5 * pusher[0], c.y);
        // A fixed side block centred at height `y`.
        let side_block = |y: f64, label: &str| Piece {
            polygon: rect_polygon(Vec2::new(side_x, y), side),
            thickness_m: h,
            velocity: Vec2::ZERO,
            angular_velocity: 0.0,
            prescribed: true,
            schedule: None,
            load_point: None,
            label: Some(label.into()),
            span: None,
        };
        let pieces = vec![
            Piece {
                polygon: rect_polygon(c, block),
                thickness_m: h,
                velocity: Vec2::new(v, 0.0),
                angular_velocity: 0.0,
                prescribed: false,
                schedule: None,
                load_point: None,
                label: Some("block".into()),
                span: None,
            },
            side_block(c.y + side_y, "upper side block"),
            side_block(c.y - side_y, "lower side block"),
            Piece {
                polygon: rect_polygon(pusher_c, pusher),
                thickness_m: h,
                velocity: Vec2::new(v, 0.0),
                angular_velocity: 0.0,
                prescribed: true,
                schedule: schedule.cloned(),
                load_point: None,
                label: Some("pusher".into()),
                span: None,
            },
        ];
        // Everything, with its travel, must lie in the domain.
        let (lo, hi) = (d.min_m, d.min_m + d.size_m);
        for p in &pieces {
            let moves = if p.velocity.x != 0.0 || p.schedule.is_some() || !p.prescribed {
                travel
            } else {
                0.0
            };
            for q in &p.polygon {
                if q.x < lo.x || q.x + moves > hi.x || q.y < lo.y || q.y > hi.y {
                    return Err(f.error(
                        span,
                        "domain.size_m",
                        format!(
                            "the double-shear set-up ({}, with {} m of travel) does not fit in the domain [{}, {}] x [{}, {}] m",
                            p.label.as_deref().unwrap_or("a block"),
                            sig(travel),
                            lo.x, hi.x, lo.y, hi.y
                        ),
                    ));
                }
            }
        }
        let pushed = match schedule {
            Some(s) => format!("pushed {}", describe_schedule(s)),
            None => format!("pushed at {} m/s", sig(v)),
        };
        report.push(format!(
            "floes: double shear: block {} x {} x {} m {pushed} between fixed side blocks {} x {} m",
            block[0],
            block[1],
            sig(h),
            side[0],
            side[1]
        ));
        report.push(format!(
            "  normal load {} N per face ({} N on both) from an overlap {} m deep; contact kappa = E h / sqrt(A) = {} Pa",
            sig(load),
            sig(2.0 * load),
            sig(depth),
            sig(geometry.kappa_pa)
        ));
        report.push(format!(
            "  loading spring (pusher contact, {} m wide) k = {} N/m; side contacts k_t = {} N/m each; in series {} N/m",
            sig(pusher[1].min(block[1])),
            sig(geometry.pusher_stiffness_n_per_m),
            sig(geometry.side_tangential_stiffness_n_per_m),
            sig(geometry.series_stiffness_n_per_m)
        ));
        // Under both faces' load; none when the law strengthens with speed.
        if let Some(kc) = g
            .model
            .law
            .critical_stiffness_n_per_m(2.0 * load)
            .filter(|&kc| kc > 0.0)
        {
            report.push(format!(
                "  critical stiffness N (B - A) / L = {} N/m: steady sliding is {} at this stiffness",
                sig(kc),
                if geometry.series_stiffness_n_per_m > kc {
                    "stable"
                } else {
                    "unstable (stick-slip expected)"
                }
            ));
        }
        Ok(pieces)
    }

    fn double_shear(&self) -> Option<&DoubleShear> {
        Some(self)
    }
}
