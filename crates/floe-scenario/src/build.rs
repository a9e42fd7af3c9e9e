//! From resolved values to floe-dem objects: the floes (generated or
//! explicit), the walls as strings of prescribed floes, and the time step.
//!
//! Floe order (and id): the free floes of the tessellation, or the
//! `[[floe]]` tables in file order; then the prescribed blocks of a
//! double-shear set-up; then the wall segments, wall by wall in file order;
//! then the land pieces, `[[land]]` table by table.

use std::ops::Not;

use floe_dem::floes::{Floe, Floes};
use floe_dem::geometry::FloeShape;
use floe_dem::motion_schedule::MotionSchedule;
use floe_dem::pipeline::integrator::{damping_step_factor, STABILITY_SAFETY};
use floe_dem::tessellation::{
    fit_sizes, DiamondLattice, PeriodFit, PowerLawFit, PowerLawFloes, PowerLawSizes, Rect,
    Tessellation, VoronoiFloes, MAX_FLOES,
};
use floe_dem::world::stable_time_step;
use floe_dem::Vec2;
use floe_friction::FrictionLaw;

use crate::built_floes::{BuiltFloes, StressWall};
use crate::checks;
use crate::error::ScenarioError;
use crate::ice_grid::{place_from_grids, GridFrame};
use crate::land_build;
use crate::numbers::{parameter, short, sig, thousands};
pub(crate) use crate::piece::Piece;
use crate::resolve::{
    dem_error, voronoi_work, DtChoice, FloeSource, Resolved, Side, Wall, AUTO_DT_FRACTION,
};
use crate::size_distribution::check_fits;
use crate::source_file::SourceFile;

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

fn rect_polygon(center: Vec2, size: [f64; 2]) -> Vec<Vec2> {
    let h = Vec2::new(0.5 * size[0], 0.5 * size[1]);
    vec![
        center - h,
        center + Vec2::new(h.x, -h.y),
        center + h,
        center + Vec2::new(-h.x, h.y),
    ]
}

/// The report line of a lattice fitted to the domain's periods: how many
/// cells span each period and how much the lattice was changed for it.
fn describe_period_fit(lattice: &DiamondLattice, fit: &PeriodFit) -> String {
    let (e1, e2) = lattice.edge_vectors_m();
    let spans: Vec<String> = fit
        .period_steps
        .iter()
        .zip(["x", "y"])
        .filter_map(|(steps, axis)| {
            steps.map(|[m, n]| format!("{m} e1 + {n} e2 span the period along {axis}"))
        })
        .collect();
    let change = if fit.is_identity() {
        "the lattice is unchanged".to_string()
    } else {
        let (lo, hi) = fit.stretch_range();
        let (d1, d2) = (fit.apply(e1 + e2).length(), fit.apply(e2 - e1).length());
        let stretch = if hi - lo <= 1e-9 * hi {
            format!("scaled by {}", sig(lo))
        } else {
            format!("stretched by {} to {}", sig(lo), sig(hi))
        };
        let turn = fit.rotation_deg();
        let turn = if turn.abs() < 1e-9 {
            String::new()
        } else {
            format!(" and turned by {} deg", sig(turn))
        };
        format!(
            "the lattice is {stretch}{turn} to fit (diagonals now {} x {} m)",
            sig(d1),
            sig(d2)
        )
    };
    format!(
        "  periodic: {}; {change}; floes straddling the seam are whole",
        spans.join(", ")
    )
}

/// The free (and double-shear prescribed) pieces and report lines.
fn generate(
    f: &SourceFile,
    r: &Resolved,
    region: Rect,
    report: &mut Vec<String>,
) -> Result<Vec<Piece>, ScenarioError> {
    let span = r.floes_span.clone();
    let dem = |e| dem_error(f, span.clone(), "tessellation", e);
    // The floes of a tessellation, placed from the ice grids if any.
    let frame = GridFrame {
        projection: r.map.as_ref(),
        start_time: r.start_time.as_deref(),
    };
    let free = |mut t: Tessellation,
                v: Vec2,
                report: &mut Vec<String>|
     -> Result<Vec<Piece>, ScenarioError> {
        place_from_grids(f, r, region, &mut t, frame, report)?;
        Ok(t.polygons
            .into_iter()
            .zip(t.thickness_m)
            .map(|(polygon, thickness_m)| Piece {
                polygon,
                thickness_m,
                velocity: v,
                angular_velocity: 0.0,
                prescribed: false,
                schedule: None,
                load_point: None,
                label: None,
                span: None,
            })
            .collect())
    };
    let v0 = r.initial_velocity;
    let dropped_line = |what: &str, dropped: usize, area: f64| {
        format!(
            "  {} {what} below {} of the nominal floe area dropped ({} m^2, {} % of the ice region)",
            thousands(dropped),
            r.min_area_fraction,
            sig(area),
            sig(100.0 * area / region.area_m2())
        )
    };
    match &r.floes {
        FloeSource::Diamond {
            side_m,
            acute_angle_deg,
            orientation_deg,
            diagonals_m,
            jitter_fraction,
        } => {
            let lattice = match diagonals_m {
                Some((along, across)) => DiamondLattice::from_diagonals(
                    region,
                    *along,
                    *across,
                    *orientation_deg,
                    r.thickness,
                    *jitter_fraction,
                    r.seed,
                )
                .map_err(dem)?,
                None => DiamondLattice {
                    domain: region,
                    side_m: *side_m,
                    acute_angle_deg: *acute_angle_deg,
                    orientation_deg: *orientation_deg,
                    thickness: r.thickness,
                    jitter_fraction: *jitter_fraction,
                    seed: r.seed,
                },
            };
            let periodic = r.domain.periodic;
            let (mut t, lr, fit) = if periodic.contains(&true) {
                let (t, lr, fit) = lattice.build_periodic(periodic).map_err(dem)?;
                (t, lr, Some(fit))
            } else {
                let (t, lr) = lattice.build_with_report().map_err(dem)?;
                (t, lr, None)
            };
            let cell = lattice.cell_area_m2();
            let drop = t.drop_floes_smaller_than(r.min_area_fraction * cell);
            let (d_along, d_across) = lattice.diagonals_m();
            report.push(format!(
                "floes: {} diamonds, side {} m, acute angle {} deg, diagonals {} x {} m, orientation {} deg, jitter {}",
                thousands(t.len()),
                sig(lattice.side_m),
                sig(lattice.acute_angle_deg),
                sig(d_along),
                sig(d_across),
                sig(lattice.orientation_deg),
                lattice.jitter_fraction
            ));
            if let Some(fit) = fit {
                report.push(describe_period_fit(&lattice, &fit));
            }
            report.push(format!(
                "  {} clipped at the edges of the ice region; {} slivers dropped by the lattice",
                thousands(lr.clipped_floes),
                lr.dropped_slivers
            ));
            report.push(dropped_line(
                "clipped pieces",
                drop.dropped,
                drop.dropped_area_m2,
            ));
            free(t, v0, report)
        }
        FloeSource::Voronoi {
            count,
            floe_scale_m,
            relax_iterations,
        } => {
            let n = match (count, floe_scale_m) {
                (Some(n), _) => *n,
                (None, Some(scale)) => {
                    let n = (region.area_m2() / (scale * scale)).round().max(1.0);
                    if n > MAX_FLOES as f64 {
                        return Err(f.error(
                            span,
                            "tessellation.floe_scale_m",
                            format!("would make about {n:.3e} floes, above the cap of {MAX_FLOES}"),
                        ));
                    }
                    let n = n as usize;
                    let key = "tessellation.floe_scale_m";
                    voronoi_work(f, span.clone(), key, n, *relax_iterations)?;
                    n
                }
                (None, None) => unreachable!("resolve requires count or floe_scale_m"),
            };
            let v = VoronoiFloes {
                domain: region,
                count: n,
                seed: r.seed,
                thickness: r.thickness,
                relax_iterations: *relax_iterations,
            };
            let mut t = v.build().map_err(dem)?;
            let mean = region.area_m2() / n as f64;
            let drop = t.drop_floes_smaller_than(r.min_area_fraction * mean);
            report.push(format!(
                "floes: {} Voronoi cells (mean area {} m^2, {} Lloyd iterations)",
                thousands(t.len()),
                sig(mean),
                relax_iterations
            ));
            report.push(dropped_line("cells", drop.dropped, drop.dropped_area_m2));
            free(t, v0, report)
        }
        FloeSource::PowerLaw {
            sizes,
            relax_iterations,
            relax_span,
        } => {
            check_fits(f, sizes, region, (*relax_iterations, relax_span.clone()))?;
            let (mut t, pr) = PowerLawFloes {
                domain: region,
                sizes: sizes.law,
                seed: r.seed,
                thickness: r.thickness,
                relax_iterations: *relax_iterations,
            }
            .build()
            .map_err(dem)?;
            let law = sizes.law;
            let drop = t.drop_floes_smaller_than(r.min_area_fraction * law.min_m * law.min_m);
            report.push(format!(
                "floes: {} Laguerre cells, sizes sqrt(area) from a power law N(>d) ~ d^-{} between {} and {} m ({} Lloyd iterations)",
                thousands(t.len()),
                sig(law.exponent),
                sig(law.min_m),
                sig(law.max_m),
                relax_iterations
            ));
            report.push(format!(
                "  cell areas within {} % of the drawn sizes' (rms {} %) after {} power diagrams; sizes scaled by {:.6} to fill the region; {} disks placed overlapping",
                sig(100.0 * pr.max_area_error),
                sig(100.0 * pr.rms_area_error),
                pr.passes,
                pr.size_scale,
                pr.forced_placements
            ));
            report.push(describe_fit("  fitted exponent", fit_sizes(&t, law), law));
            if pr.simplified > 0 {
                report.push(format!(
                    "  {} large floes among many small ones cut down to {} vertices ({} m^2 of open water, {} % of the region)",
                    thousands(pr.simplified),
                    floe_dem::geometry::MAX_VERTICES,
                    sig(pr.simplified_area_m2),
                    sig(100.0 * pr.simplified_area_m2 / region.area_m2())
                ));
            }
            if pr.empty_cells + drop.dropped > 0 {
                report.push(format!(
                    "  {} empty cells and {} cells below {} of min_m^2 dropped ({} m^2)",
                    pr.empty_cells,
                    drop.dropped,
                    r.min_area_fraction,
                    sig(drop.dropped_area_m2)
                ));
            }
            let placed = free(t, v0, report)?;
            if r.ice_grids.concentration.is_some() {
                let polygons: Vec<Vec<Vec2>> = placed.iter().map(|p| p.polygon.clone()).collect();
                let t = Tessellation {
                    thickness_m: vec![1.0; polygons.len()],
                    polygons,
                };
                report.push(describe_fit(
                    "  fitted exponent of the placed floes",
                    fit_sizes(&t, law),
                    law,
                ));
            }
            Ok(placed)
        }
        FloeSource::Grid {
            columns,
            rows,
            gap_m,
        } => {
            let (cw, ch) = (
                region.width_m() / *columns as f64,
                region.height_m() / *rows as f64,
            );
            if !(*gap_m < cw && *gap_m < ch) {
                return Err(f.error(
                    span,
                    "tessellation.gap_m",
                    format!(
                        "gap {gap_m} m leaves nothing of the {} x {} m cells",
                        sig(cw),
                        sig(ch)
                    ),
                ));
            }
            let n = columns.saturating_mul(*rows);
            if n > MAX_FLOES {
                return Err(f.error(
                    span,
                    "tessellation.columns",
                    format!("{columns} x {rows} floes is above the cap of {MAX_FLOES}"),
                ));
            }
            let thickness = r.thickness.sample(n, r.seed).map_err(dem)?;
            let mut polygons = Vec::with_capacity(n);
            for j in 0..*rows {
                for i in 0..*columns {
                    let c = region.min + Vec2::new((i as f64 + 0.5) * cw, (j as f64 + 0.5) * ch);
                    polygons.push(rect_polygon(c, [cw - gap_m, ch - gap_m]));
                }
            }
            report.push(format!(
                "floes: {} rectangles ({columns} x {rows}), {} x {} m, gap {} m",
                thousands(n),
                sig(cw - gap_m),
                sig(ch - gap_m),
                sig(*gap_m)
            ));
            free(
                Tessellation {
                    polygons,
                    thickness_m: thickness,
                },
                v0,
                report,
            )
        }
        FloeSource::Explicit(list) => {
            let thickness = r.thickness.sample(list.len(), r.seed).map_err(dem)?;
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
                        None => e
                            .velocity
                            .unwrap_or(if e.prescribed { Vec2::ZERO } else { v0 }),
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
        FloeSource::DoubleShear {
            block_m,
            side_block_m,
            pusher_m,
            normal_load_per_face_n,
            push_velocity_m_per_s,
            push_schedule,
        } => double_shear(
            f,
            r,
            *block_m,
            *side_block_m,
            *pusher_m,
            *normal_load_per_face_n,
            (*push_velocity_m_per_s, push_schedule.as_ref()),
            report,
        ),
    }
}

/// A report line of a fitted size exponent.
fn describe_fit(what: &str, fit: Option<PowerLawFit>, law: PowerLawSizes) -> String {
    match fit {
        Some(fit) => format!(
            "{what} {} +- {} (maximum likelihood over {} floes; requested {})",
            sig(fit.exponent),
            sig(fit.std_error),
            thousands(fit.used),
            sig(law.exponent)
        ),
        None => format!("{what}: none (too few floes, or sizes weighted to the large end)"),
    }
}

/// The double-shear set-up of Lishman et al. (2011): a free block between
/// two fixed blocks that overlap it by the depth giving the normal load,
/// pushed along x by a prescribed plate whose contact is the loading spring.
#[allow(clippy::too_many_arguments)]
fn double_shear(
    f: &SourceFile,
    r: &Resolved,
    block: [f64; 2],
    side: [f64; 2],
    pusher: [f64; 2],
    load: f64,
    (v, schedule): (f64, Option<&MotionSchedule>),
    report: &mut Vec<String>,
) -> Result<Vec<Piece>, ScenarioError> {
    let span = r.floes_span.clone();
    let h = r.thickness.mean_m();
    let geometry = checks::double_shear_geometry(&r.model, h, block, pusher, load);
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
        Some(s) => s.most_travel_m(r.duration_s),
        None => v * r.duration_s,
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
    let d = &r.domain;
    let c = d.min_m + 0.5 * d.size_m;
    let depth = geometry.depth_m;
    let side_y = 0.5 * block[1] + 0.5 * side[1] - depth;
    let side_x = c.x + 0.5 * travel;
    let pusher_c = Vec2::new(c.x - 0.5 * block[0] - 0.5 * pusher[0], c.y);
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
        Piece {
            polygon: rect_polygon(Vec2::new(side_x, c.y + side_y), side),
            thickness_m: h,
            velocity: Vec2::ZERO,
            angular_velocity: 0.0,
            prescribed: true,
            schedule: None,
            load_point: None,
            label: Some("upper side block".into()),
            span: None,
        },
        Piece {
            polygon: rect_polygon(Vec2::new(side_x, c.y - side_y), side),
            thickness_m: h,
            velocity: Vec2::ZERO,
            angular_velocity: 0.0,
            prescribed: true,
            schedule: None,
            load_point: None,
            label: Some("lower side block".into()),
            span: None,
        },
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
    if let Some(kc) = r
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

/// A wall's schedule for the report: its segments' velocities in order.
fn describe_schedule(s: &MotionSchedule) -> String {
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
