//! From resolved values to floe-dem objects: the floes (generated or
//! explicit), the walls as strings of prescribed floes, and the time step.
//!
//! Floe order (and id): the free floes of the tessellation, or the
//! `[[floe]]` tables in file order; then the prescribed blocks of a
//! double-shear set-up; then the wall segments, wall by wall in file order;
//! then the land pieces, `[[land]]` table by table.

use std::ops::Not;

use floe_dem::floes::{Floe, Floes};
use floe_dem::geometry::shape::area_and_centroid;
use floe_dem::geometry::FloeShape;
use floe_dem::pipeline::integrator::{damping_step_factor, STABILITY_SAFETY};
use floe_dem::tessellation::{Rect, Tessellation};
use floe_dem::world::stable_time_step;
use floe_dem::Vec2;

use crate::built_floes::{BuiltFloes, StressWall};
use crate::checks;
use crate::error::ScenarioError;
use crate::ice_grid::{place_from_grids, GridFrame};
use crate::land_build;
use crate::motion_segments::describe_schedule;
use crate::numbers::{parameter, short, sig, thousands};
pub(crate) use crate::piece::Piece;
use crate::resolve::{dem_error, DtChoice, FloeSource, Resolved, Side, Wall, AUTO_DT_FRACTION};
use crate::source_file::SourceFile;
use crate::tessellation::Generation;

/// Most segments one wall is made of (a wall much longer than the floes are
/// wide gets longer segments rather than millions of them).
const MAX_WALL_SEGMENTS: usize = 100_000;

/// The ice region: the domain minus the wall insets.
pub(crate) fn ice_region(r: &Resolved) -> Rect {
    let d = &r.domain;
    let mut min = d.min_m;
    let mut max = d.min_m + d.size_m;
    for w in &r.walls {
        match w.side {
            Side::Left => min.x += w.inset_m,
            Side::Right => max.x -= w.inset_m,
            Side::Bottom => min.y += w.inset_m,
            Side::Top => max.y -= w.inset_m,
        }
    }
    Rect::new(min, max)
}

/// The free (and a set-up's prescribed) pieces and report lines.
fn generate(
    f: &SourceFile,
    r: &Resolved,
    region: Rect,
    report: &mut Vec<String>,
) -> Result<Vec<Piece>, ScenarioError> {
    let v0 = r.initial_velocity;
    match &r.floes {
        FloeSource::Tessellation(t) => {
            // The floes of a tessellation, placed from the ice grids if any.
            let frame = GridFrame {
                projection: r.map.as_ref(),
                start_time: r.start_time.as_deref(),
            };
            let place = |mut t: Tessellation,
                         report: &mut Vec<String>|
             -> Result<Vec<Piece>, ScenarioError> {
                place_from_grids(f, r, region, &mut t, frame, report)?;
                let heights: Vec<f64> = (0..t.len())
                    .map(|i| t.centroid_m(i).y - region.min.y)
                    .collect();
                Ok(t.polygons
                    .into_iter()
                    .zip(t.thickness_m)
                    .zip(heights)
                    .map(|((polygon, thickness_m), height)| Piece {
                        polygon,
                        thickness_m,
                        velocity: v0.at(height),
                        angular_velocity: 0.0,
                        prescribed: false,
                        schedule: None,
                        load_point: None,
                        label: None,
                        span: None,
                    })
                    .collect())
            };
            let g = Generation {
                f,
                span: r.floes_span.clone(),
                region,
                domain: r.domain,
                seed: r.seed,
                thickness: r.thickness,
                min_area_fraction: r.min_area_fraction,
                duration_s: r.duration_s,
                model: &r.model,
                concentration_grid: r.ice_grids.concentration.is_some(),
                place: &place,
            };
            t.floes.generate(&g, report)
        }
        FloeSource::Explicit(list) => {
            let thickness = r
                .thickness
                .sample(list.len(), r.seed)
                .map_err(|e| dem_error(f, r.floes_span.clone(), "tessellation", e))?;
            let prescribed = list.iter().filter(|e| e.prescribed).count();
            report.push(format!(
                "floes: {} from [[floe]] tables ({} free, {} prescribed)",
                list.len(),
                list.len() - prescribed,
                prescribed
            ));
            Ok(list
                .iter()
                .zip(thickness)
                .enumerate()
                .map(|(i, (e, h))| Piece {
                    polygon: e.vertices.clone(),
                    thickness_m: e.thickness_m.unwrap_or(h),
                    velocity: match &e.schedule {
                        Some(s) => s.velocity_at(0.0).0,
                        None => e.velocity.unwrap_or(if e.prescribed {
                            Vec2::ZERO
                        } else {
                            v0.at(centroid_height(&e.vertices, region))
                        }),
                    },
                    angular_velocity: match &e.schedule {
                        Some(s) => s.velocity_at(0.0).1,
                        None => e.angular_velocity_rad_per_s,
                    },
                    prescribed: e.prescribed,
                    schedule: e.schedule.clone(),
                    load_point: e.load_point.clone(),
                    label: Some(format!("floe[{i}]")),
                    span: Some(e.span.clone()),
                })
                .collect())
        }
    }
}

/// The height of a polygon's area centroid above the bottom of `region`.
fn centroid_height(polygon: &[Vec2], region: Rect) -> f64 {
    area_and_centroid(polygon).1.y - region.min.y
}

/// Builds the floes (free, prescribed, walls) and checks their layout.
pub(crate) fn build_floes(f: &SourceFile, r: &Resolved) -> Result<BuiltFloes, ScenarioError> {
    checks::walls_fit(f, r)?;
    let region = ice_region(r);
    let mut report = Vec::new();
    if let Some(t) = &r.title {
        report.push(format!("scenario: {t}"));
    }
    let mut pieces = generate(f, r, region, &mut report)?;
    // Land pieces no larger than the largest free floe (the broad phase's
    // cells are as wide as the largest body).
    let land = if r.land.is_empty() {
        Vec::new()
    } else {
        land_build::read_all(f, r, free_radius(&pieces).max(f64::MIN_POSITIVE))?
    };
    if !matches!(r.floes, FloeSource::Explicit(_)) && !land.is_empty() {
        let (dropped, area) = land_build::drop_ice_on_land(&mut pieces, &land);
        report.push(format!(
            "  {} floes on land dropped ({} m^2)",
            thousands(dropped),
            sig(area)
        ));
    }
    let glued = glue_to_walls(r, region, &mut pieces, &mut report);
    let free = pieces.iter().filter(|p| !p.prescribed).count();
    if free == 0 {
        return Err(f.error(
            r.floes_span.clone(),
            "tessellation",
            "no free floes: the tessellation is empty (cells larger than the ice region?), every [[floe]] is prescribed, every floe is glued to a wall (glue_depth_m), or every floe lies on land",
        ));
    }
    let r_max = pieces
        .iter()
        .filter(|p| !p.prescribed)
        .map(|p| {
            let c = p.vertex_mean();
            p.polygon
                .iter()
                .map(|&q| (q - c).length())
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max);
    // The walls' thickness: the mean floe's.
    let mean_h = if r.ice_grids.thickness.is_some() {
        let free: Vec<f64> = pieces
            .iter()
            .filter(|p| !p.prescribed)
            .map(|p| p.thickness_m)
            .collect();
        free.iter().sum::<f64>() / free.len() as f64
    } else {
        r.thickness.mean_m()
    };
    let mut stress_walls = Vec::new();
    for w in &r.walls {
        let first_piece = pieces.len();
        let segments = wall_segments(r, w, r_max);
        report.push(format!(
            "wall[{}]: {} side, {}, {} segments {} m long, {} m thick",
            w.index,
            w.side.name(),
            match &w.schedule {
                Some(s) => describe_schedule(s),
                None if w.velocity == Vec2::ZERO => "fixed".to_string(),
                None => format!(
                    "moving at [{}, {}] m/s",
                    parameter(w.velocity.x),
                    parameter(w.velocity.y)
                ),
            },
            segments.len(),
            sig(segments.first().map_or(0.0, |s| {
                let e = s[2] - s[0];
                if w.side.axis() == 0 {
                    e.y
                } else {
                    e.x
                }
            })),
            sig(w.thickness_m.unwrap_or(r_max))
        ));
        for polygon in segments {
            pieces.push(Piece {
                polygon,
                thickness_m: mean_h,
                velocity: w.velocity,
                angular_velocity: 0.0,
                prescribed: true,
                schedule: w.schedule.clone(),
                load_point: None,
                label: Some(format!("wall[{}] ({})", w.index, w.side.name())),
                span: Some(w.span.clone()),
            });
        }
        if let Some((target, control)) = w.stress {
            let along = 1 - w.side.axis();
            let inward = match w.side {
                Side::Left => Vec2::X,
                Side::Right => -Vec2::X,
                Side::Bottom => Vec2::Y,
                Side::Top => -Vec2::Y,
            };
            // The floes glued to the wall are part of it (their indices
            // come before the wall's own pieces).
            let glued_here = glued
                .iter()
                .filter(|(index, _)| *index == w.index)
                .flat_map(|(_, k)| k.iter().copied());
            stress_walls.push(StressWall {
                index: w.index,
                floe_ids: glued_here
                    .chain(first_piece..pieces.len())
                    .map(|i| i as u64)
                    .collect(),
                inward_normal: inward,
                length_m: region.max[along] - region.min[along],
                target_n_per_m: target,
                control,
                span: w.span.clone(),
            });
        }
    }
    let first_land = pieces.len();
    pieces.extend(land_build::land_pieces(
        &land,
        mean_h,
        r.map.as_ref(),
        &mut report,
    ));
    let land_ids: Vec<u64> = (first_land..pieces.len()).map(|i| i as u64).collect();
    let periodicity = r.domain.periodicity();
    let mut floes = Floes::default();
    let mut schedules = Vec::new();
    let mut load_points = Vec::new();
    let mut spans = Vec::with_capacity(pieces.len());
    let mut labels = Vec::with_capacity(pieces.len());
    for (i, p) in pieces.into_iter().enumerate() {
        let (shape, centroid) = FloeShape::from_world(i, &p.polygon).map_err(|e| {
            let reason = match e {
                floe_dem::DemError::InvalidFloe { reason, .. } => reason,
                other => other.to_string(),
            };
            match (&p.span, &p.label) {
                (Some(s), Some(l)) => f.error(s.clone(), l.clone(), reason),
                _ => f.error(r.floes_span.clone(), "tessellation", reason),
            }
        })?;
        let floe = Floe::new(
            i as u64,
            &shape,
            periodicity.wrap(centroid),
            p.thickness_m,
            r.density_kg_per_m3,
        );
        let floe = if p.prescribed {
            floe.prescribed(p.velocity)
        } else {
            floe
        };
        floes
            .insert(floe.with_velocity(p.velocity, p.angular_velocity))
            .map_err(|e| match (&p.span, &p.label) {
                (Some(s), Some(l)) => f.error(s.clone(), l.clone(), e.to_string()),
                _ => f.error(r.floes_span.clone(), "tessellation", e.to_string()),
            })?;
        if let Some(schedule) = p.schedule {
            schedules.push((i as u64, schedule));
        }
        if let Some((k, schedule)) = p.load_point {
            report.push(format!(
                "{}: driven through a {} N/m spring from a load point {}",
                p.label.as_deref().unwrap_or("floe"),
                sig(k),
                describe_schedule(&schedule)
            ));
            load_points.push((i as u64, (k, schedule)));
        }
        spans.push(p.span);
        labels.push(p.label);
    }
    let built = BuiltFloes {
        floes,
        schedules,
        load_points,
        stress_walls,
        pieces_span: spans,
        labels,
        report,
        free,
        land_ids,
    };
    if matches!(r.floes, FloeSource::Explicit(_)) {
        checks::no_initial_overlap(f, r, &built)?;
    }
    Ok(built)
}

/// The largest bounding radius (about the vertex mean) of the free pieces, m.
fn free_radius(pieces: &[Piece]) -> f64 {
    pieces
        .iter()
        .filter(|p| !p.prescribed)
        .map(|p| {
            let c = p.vertex_mean();
            p.polygon
                .iter()
                .map(|&q| (q - c).length())
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

/// The outlines of a wall's segments: rectangles about one floe diameter
/// long, so that the broad phase's cells stay floe-sized.
fn wall_segments(r: &Resolved, w: &Wall, r_max: f64) -> Vec<Vec<Vec2>> {
    let region = ice_region(r);
    let d = &r.domain;
    let t = w.thickness_m.unwrap_or(r_max);
    let along = 1 - w.side.axis();
    let reach = t + r
        .walls
        .iter()
        .map(|w| w.most_travel_m(r.duration_s))
        .fold(0.0, f64::max);
    let (lo, hi) = if d.periodic[along] {
        (d.min_m[along], d.min_m[along] + d.size_m[along])
    } else {
        (region.min[along] - reach, region.max[along] + reach)
    };
    // Segments of one floe diameter, but at most MAX_WALL_SEGMENTS of them.
    let target = (2.0 * r_max).max((hi - lo) / MAX_WALL_SEGMENTS as f64);
    let n = ((hi - lo) / target)
        .ceil()
        .clamp(1.0, MAX_WALL_SEGMENTS as f64) as usize;
    let step = (hi - lo) / n as f64;
    let (a, b) = match w.side {
        Side::Left => (region.min.x - t, region.min.x),
        Side::Right => (region.max.x, region.max.x + t),
        Side::Bottom => (region.min.y - t, region.min.y),
        Side::Top => (region.max.y, region.max.y + t),
    };
    (0..n)
        .map(|k| {
            let (s0, s1) = (lo + k as f64 * step, lo + (k + 1) as f64 * step);
            let (x0, x1, y0, y1) = if w.side.axis() == 0 {
                (a, b, s0, s1)
            } else {
                (s0, s1, a, b)
            };
            vec![
                Vec2::new(x0, y0),
                Vec2::new(x1, y0),
                Vec2::new(x1, y1),
                Vec2::new(x0, y1),
            ]
        })
        .collect()
}

/// The time step: automatic, or the file's if stable.
pub(crate) fn time_step(
    f: &SourceFile,
    r: &Resolved,
    built: &BuiltFloes,
    max_steps: f64,
) -> Result<(f64, f64, String), ScenarioError> {
    let (mut limit, mut culprit) = stable_time_step(&built.floes, &r.model);
    // A load point's spring is one more stiffness on its floe.
    let mut spring_sets_it = false;
    for (id, (k, _)) in &built.load_points {
        let h = built.floes.handle_of(*id).expect("built with the floes");
        let spring = STABILITY_SAFETY * 2.0 * (built.floes.mass_kg[h] / k).sqrt();
        if spring < limit {
            (limit, culprit, spring_sets_it) = (spring, h, true);
        }
    }
    let culprit_name = built.labels[culprit]
        .clone()
        .unwrap_or_else(|| format!("floe {culprit}"));
    let culprit_name = if spring_sets_it {
        format!("{culprit_name}'s load-point spring")
    } else {
        culprit_name
    };
    if !(limit.is_finite() && limit > 0.0) {
        let span = built.pieces_span[culprit]
            .clone()
            .unwrap_or_else(|| r.floes_span.clone());
        return Err(f.error(
            span,
            built.labels[culprit]
                .clone()
                .unwrap_or_else(|| "tessellation".into()),
            format!(
                "the stable time step of {culprit_name} is {limit} s: its mass or the contact \
                 stiffness (E = {} Pa) is out of range; check the thickness, density and \
                 contact.youngs_modulus_pa",
                parameter(r.model.youngs_modulus_pa)
            ),
        ));
    }
    // A step longer than the run would be the whole run.
    let limit = limit.min(r.duration_s / AUTO_DT_FRACTION);
    let steps = |dt: f64| ((r.duration_s / dt).round() as u64).max(1);
    // What sets the limit, for messages: the contact stiffness and, when a
    // strong dashpot shortens the step, the restitution.
    let damping = damping_step_factor(&r.model);
    let (stiffness, soften) = if damping < 1.0 {
        (
            format!(
                "E = {} Pa, restitution {} (which shortens the step {} times)",
                parameter(r.model.youngs_modulus_pa),
                short(r.model.restitution),
                sig(1.0 / damping)
            ),
            "soften contact.youngs_modulus_pa, raise contact.restitution",
        )
    } else {
        (
            format!("E = {} Pa", parameter(r.model.youngs_modulus_pa)),
            "soften contact.youngs_modulus_pa",
        )
    };
    let too_many = |dt: f64| ((r.duration_s / dt).round() <= max_steps).not();
    let above = |dt: f64| {
        format!(
            "{} s / dt {} s is {} steps, above the limit of {}",
            sig(r.duration_s),
            sig(dt),
            sig((r.duration_s / dt).round()),
            sig(max_steps)
        )
    };
    match &r.dt {
        DtChoice::Auto | DtChoice::Fraction(..) => {
            let (fraction, given) = match &r.dt {
                DtChoice::Fraction(x, span) => (*x, Some(span)),
                _ => (AUTO_DT_FRACTION, None),
            };
            let dt = fraction * limit;
            // How dt was chosen, `auto` introducing the automatic fraction.
            let how = |auto: &str| match given {
                Some(_) => format!("dt_fraction {} x", short(fraction)),
                None => format!("{auto}{AUTO_DT_FRACTION} x"),
            };
            if too_many(dt) {
                // Blamed on dt_fraction when given, as dt_s would be.
                let (span, key, fix) = match given {
                    Some(span) => (
                        span.clone(),
                        "dt_fraction",
                        "raise dt_fraction, shorten duration_s",
                    ),
                    None => (r.duration_span.clone(), "duration_s", "shorten duration_s"),
                };
                let how = how("dt is automatic: ");
                return Err(f.error(
                    span,
                    key,
                    format!(
                        "{} ({how} the stable limit, set by {culprit_name} \
                         with {stiffness}); {fix}, {soften}, \
                         or raise the limit with --step-limit N",
                        above(dt),
                    ),
                ));
            }
            let how = how("auto: ");
            Ok((
                dt,
                limit,
                format!(
                    "dt: {} s ({how} the stable limit {} s, set by {culprit_name}); {} steps for {} s",
                    sig(dt),
                    sig(limit),
                    thousands(steps(dt) as usize),
                    sig(r.duration_s)
                ),
            ))
        }
        DtChoice::Given(dt, span) => {
            if *dt > limit {
                return Err(f.error(
                    span.clone(),
                    "dt_s",
                    format!(
                        "{dt} s is above the stable limit {} s (set by {culprit_name}, {stiffness}); use at most that, or omit dt_s for {} s",
                        sig(limit),
                        sig(AUTO_DT_FRACTION * limit)
                    ),
                ));
            }
            if too_many(*dt) {
                return Err(f.error(
                    span.clone(),
                    "dt_s",
                    format!(
                        "{}; lengthen dt_s (the stable limit is {} s), shorten duration_s, \
                         or raise the limit with --step-limit N",
                        above(*dt),
                        sig(limit)
                    ),
                ));
            }
            Ok((
                *dt,
                limit,
                format!(
                    "dt: {} s (given; stable limit {} s, set by {culprit_name}); {} steps for {} s",
                    sig(*dt),
                    sig(limit),
                    thousands(steps(*dt) as usize),
                    sig(r.duration_s)
                ),
            ))
        }
    }
}

/// Refuses `[[output.window]]` tables that ask for more outputs, summed
/// over the windows (where they overlap, counted in each), than the run may
/// take steps: the bound of the base cadence too, which writes at most once
/// a step. Returns the report's line when there are windows.
pub(crate) fn output_windows(
    f: &SourceFile,
    r: &Resolved,
    dt_s: f64,
    max_steps: f64,
) -> Result<Option<String>, ScenarioError> {
    if r.output.windows.is_empty() {
        return Ok(None);
    }
    let cadence = r.output.in_steps(dt_s);
    let (mut snapshots, mut samples) = (0u64, 0u64);
    for (i, (w, span)) in cadence.windows.iter().zip(&r.window_spans).enumerate() {
        // Multiples of `every` from `from_step` to `to_step`.
        let count = |every: Option<u64>| {
            every.map_or(0, |e| {
                (w.to_step / e + 1).saturating_sub(w.from_step.div_ceil(e))
            })
        };
        snapshots = snapshots.saturating_add(count(w.snapshot));
        samples = samples.saturating_add(count(w.observables));
        let total = snapshots.saturating_add(samples) as f64;
        if (total <= max_steps).not() {
            return Err(f.error(
                span.clone(),
                format!("output.window[{i}]"),
                format!(
                    "the windows up to this one write {} snapshots and {} observable samples \
                     at dt = {} s, {} outputs in all, above the limit of {} (the most steps \
                     a run may take); use sparser cadences or fewer windows, or raise the \
                     limit with --step-limit N",
                    thousands(snapshots as usize),
                    thousands(samples as usize),
                    sig(dt_s),
                    sig(total),
                    sig(max_steps)
                ),
            ));
        }
    }
    let n = cadence.windows.len();
    Ok(Some(format!(
        "output: {n} {} of denser output, in which {} snapshots and {} observable samples fall due",
        if n == 1 { "window" } else { "windows" },
        thousands(snapshots as usize),
        thousands(samples as usize)
    )))
}

/// Rough walls: the free pieces whose centroid lies within a wall's
/// `glue_depth_m` of its face become prescribed and move with the wall
/// (its velocity or schedule). Returns, per wall index, the indices of the
/// pieces glued to it.
fn glue_to_walls(
    r: &Resolved,
    region: Rect,
    pieces: &mut [Piece],
    report: &mut Vec<String>,
) -> Vec<(usize, Vec<usize>)> {
    let mut out = Vec::new();
    for w in r.walls.iter().filter(|w| w.glue_depth_m > 0.0) {
        let mut glued = Vec::new();
        for (k, p) in pieces.iter_mut().enumerate() {
            if p.prescribed {
                continue;
            }
            let c = p.vertex_mean();
            let from_face = match w.side {
                Side::Left => c.x - region.min.x,
                Side::Right => region.max.x - c.x,
                Side::Bottom => c.y - region.min.y,
                Side::Top => region.max.y - c.y,
            };
            if from_face <= w.glue_depth_m {
                p.prescribed = true;
                p.velocity = w.velocity;
                p.angular_velocity = 0.0;
                p.schedule = w.schedule.clone();
                p.label = Some(format!("wall[{}] (glued floe)", w.index));
                glued.push(k);
            }
        }
        report.push(format!(
            "wall[{}]: {} floes within {} m of its face glued to it (a rough wall)",
            w.index,
            glued.len(),
            sig(w.glue_depth_m)
        ));
        out.push((w.index, glued));
    }
    out
}
