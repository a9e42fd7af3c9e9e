//! `[tessellation]`: the generated floes' kind and parameters.

use std::ops::Range;

use floe_dem::tessellation::{max_jitter_fraction, MAX_FLOES};
use toml::Spanned;

use super::floes::FloeSource;
use super::limits::{
    at_most, count, distance, length, refuse_given, span_of, within, MAX_LENGTH_M,
};
use crate::error::ScenarioError;
use crate::extent::Extent;
use crate::motion_segments::resolve_schedule;
use crate::numbers::{short, short_list, sig, thousands};
use crate::size_distribution::resolve_size_distribution;
use crate::source_file::SourceFile;
use crate::spec::{Pair, RawTessellation};

/// Fraction of the nominal floe area below which generated floes (pieces
/// clipped at the domain edges) are dropped, unless the file says otherwise.
pub const DEFAULT_MIN_AREA_FRACTION: f64 = 0.1;
/// Most Lloyd iterations of a Voronoi tessellation (it converges in tens).
pub const MAX_RELAX_ITERATIONS: u64 = 10_000;
/// Most Voronoi work, sites x (Lloyd iterations + 1): one pass over 1e6
/// sites takes about 5 s, so the limit is about 8 minutes.
pub const MAX_VORONOI_WORK: f64 = 1e8;

/// Refuses a tessellation of `sites` Voronoi sites relaxed `iterations`
/// times whose work is above [`MAX_VORONOI_WORK`], blaming `key` at `span`.
pub(crate) fn voronoi_work(
    f: &SourceFile,
    span: Range<usize>,
    key: &str,
    sites: usize,
    iterations: usize,
) -> Result<(), ScenarioError> {
    let work = sites as f64 * (iterations as f64 + 1.0);
    if work <= MAX_VORONOI_WORK {
        return Ok(());
    }
    Err(f.error(
        span,
        key,
        format!(
            "{} sites x ({iterations} + 1) Lloyd passes is {} site-passes, above the limit of \
             {} (about 8 minutes); use fewer iterations (Lloyd converges in tens) or fewer floes",
            thousands(sites),
            sig(work),
            sig(MAX_VORONOI_WORK)
        ),
    ))
}

pub(crate) fn resolve_tessellation(
    f: &SourceFile,
    raw: &Spanned<RawTessellation>,
    extent: Extent,
) -> Result<(FloeSource, Range<usize>, f64), ScenarioError> {
    let t = raw.get_ref();
    let span = raw.span();
    let Some(kind_word) = &t.kind else {
        return Err(f.error(
            span,
            "tessellation.kind",
            "missing: `diamond`, `voronoi`, `grid` or `double-shear`",
        ));
    };
    let kind = kind_word.get_ref().as_str();
    let given = [
        (span_of(&t.min_area_fraction), "min_area_fraction"),
        (span_of(&t.side_m), "side_m"),
        (span_of(&t.diagonals_m), "diagonals_m"),
        (span_of(&t.acute_angle_deg), "acute_angle_deg"),
        (span_of(&t.orientation_deg), "orientation_deg"),
        (span_of(&t.jitter_fraction), "jitter_fraction"),
        (span_of(&t.floe_scale_m), "floe_scale_m"),
        (span_of(&t.count), "count"),
        (span_of(&t.relax_iterations), "relax_iterations"),
        (span_of(&t.columns), "columns"),
        (span_of(&t.rows), "rows"),
        (span_of(&t.gap_m), "gap_m"),
        (span_of(&t.block_m), "block_m"),
        (span_of(&t.side_block_m), "side_block_m"),
        (span_of(&t.pusher_m), "pusher_m"),
        (span_of(&t.normal_load_per_face_n), "normal_load_per_face_n"),
        (span_of(&t.push_velocity_m_per_s), "push_velocity_m_per_s"),
        (
            t.segment.as_ref().and_then(|s| s.first()).map(|s| s.span()),
            "segment",
        ),
        (span_of(&t.size_distribution), "size_distribution"),
    ];
    let allowed: &[&str] = match kind {
        "diamond" => &[
            "min_area_fraction",
            "side_m",
            "diagonals_m",
            "acute_angle_deg",
            "orientation_deg",
            "jitter_fraction",
        ],
        "voronoi" => &[
            "min_area_fraction",
            "floe_scale_m",
            "count",
            "relax_iterations",
            "size_distribution",
        ],
        "grid" => &["columns", "rows", "gap_m"],
        "double-shear" => &[
            "block_m",
            "side_block_m",
            "pusher_m",
            "normal_load_per_face_n",
            "push_velocity_m_per_s",
            "segment",
        ],
        other => {
            return Err(f.error(
                kind_word.span(),
                "tessellation.kind",
                format!(
                "unknown kind `{other}`, expected `diamond`, `voronoi`, `grid` or `double-shear`"
            ),
            ))
        }
    };
    refuse_given(
        f,
        "tessellation",
        &format!("kind `{kind}`"),
        &given,
        allowed,
    )?;
    let min_area_fraction = match &t.min_area_fraction {
        Some(v) => within(f, v, "tessellation.min_area_fraction", 0.0, 1.0, true)?,
        None => DEFAULT_MIN_AREA_FRACTION,
    };
    let need = |what: &str| {
        f.error(
            span.clone(),
            format!("tessellation.{what}"),
            format!("missing: kind `{kind}` needs it"),
        )
    };
    let source = match kind {
        "diamond" => {
            let orientation_deg = match &t.orientation_deg {
                Some(v) => f.finite(v, "tessellation.orientation_deg")?,
                None => 0.0,
            };
            let (side_m, acute_angle_deg, diagonals_m) = match (&t.side_m, &t.diagonals_m) {
                (Some(s), None) => {
                    let side = length(f, s, "tessellation.side_m")?;
                    let angle = match &t.acute_angle_deg {
                        Some(a) => {
                            let a_deg = *a.get_ref();
                            if !(a_deg.is_finite() && a_deg > 0.0 && a_deg < 180.0) {
                                return Err(f.error(
                                    a.span(),
                                    "tessellation.acute_angle_deg",
                                    format!(
                                        "must lie strictly between 0 and 180, got {}",
                                        short(a_deg)
                                    ),
                                ));
                            }
                            a_deg
                        }
                        None => 60.0,
                    };
                    (side, angle, None)
                }
                (None, Some(d)) => {
                    if let Some(a) = &t.acute_angle_deg {
                        return Err(f.error(
                            a.span(),
                            "tessellation.acute_angle_deg",
                            "does not apply with `diagonals_m` (the diagonals set the angle)",
                        ));
                    }
                    let [along, across] = d.get_ref().0;
                    if !(along.is_finite() && across.is_finite() && along > 0.0 && across > 0.0) {
                        return Err(f.error(
                            d.span(),
                            "tessellation.diagonals_m",
                            format!(
                                "must be [along, across] > 0, got {}",
                                short_list(&[along, across])
                            ),
                        ));
                    }
                    at_most(
                        f,
                        d.span(),
                        "tessellation.diagonals_m",
                        &[along, across],
                        MAX_LENGTH_M,
                        "m",
                    )?;
                    let angle = 2.0 * across.atan2(along).to_degrees();
                    (0.5 * along.hypot(across), angle, Some((along, across)))
                }
                (Some(s), Some(_)) => {
                    return Err(f.error(
                        s.span(),
                        "tessellation.side_m",
                        "give `side_m` (with `acute_angle_deg`) or `diagonals_m`, not both",
                    ))
                }
                (None, None) => return Err(need("side_m` or `diagonals_m")),
            };
            let jitter_fraction = match &t.jitter_fraction {
                Some(v) => {
                    let max = max_jitter_fraction(acute_angle_deg);
                    within(f, v, "tessellation.jitter_fraction", 0.0, max, false)?
                }
                None => 0.0,
            };
            FloeSource::Diamond {
                side_m,
                acute_angle_deg,
                orientation_deg,
                diagonals_m,
                jitter_fraction,
            }
        }
        "voronoi" if t.size_distribution.is_some() => {
            let sizes = t.size_distribution.as_ref().expect("checked by the guard");
            if let Some((span, name)) = [
                (span_of(&t.count), "count"),
                (span_of(&t.floe_scale_m), "floe_scale_m"),
            ]
            .into_iter()
            .find_map(|(s, n)| s.map(|s| (s, n)))
            {
                return Err(f.error(
                    span,
                    format!("tessellation.{name}"),
                    "give `size_distribution` or the floes' count or scale, not both \
                     (the distribution sets how many floes fill the region)",
                ));
            }
            let relax_iterations = match &t.relax_iterations {
                Some(r) => count(
                    f,
                    r,
                    "tessellation.relax_iterations",
                    0,
                    MAX_RELAX_ITERATIONS,
                )?,
                None => 1,
            };
            FloeSource::PowerLaw {
                sizes: resolve_size_distribution(f, sizes)?,
                relax_iterations,
                relax_span: span_of(&t.relax_iterations),
            }
        }
        "voronoi" => {
            let (count_n, scale) = match (&t.count, &t.floe_scale_m) {
                (Some(c), None) => (
                    Some(count(f, c, "tessellation.count", 1, MAX_FLOES as u64)?),
                    None,
                ),
                (None, Some(s)) => (None, Some(length(f, s, "tessellation.floe_scale_m")?)),
                (Some(c), Some(_)) => {
                    return Err(f.error(
                        c.span(),
                        "tessellation.count",
                        "give `count` or `floe_scale_m`, not both",
                    ))
                }
                (None, None) => return Err(need("count` or `floe_scale_m")),
            };
            let relax_iterations = match &t.relax_iterations {
                Some(r) => {
                    let key = "tessellation.relax_iterations";
                    let n = count(f, r, key, 0, MAX_RELAX_ITERATIONS)?;
                    if let Some(sites) = count_n {
                        voronoi_work(f, r.span(), key, sites, n)?;
                    }
                    n
                }
                None => 1,
            };
            FloeSource::Voronoi {
                count: count_n,
                floe_scale_m: scale,
                relax_iterations,
            }
        }
        "grid" => {
            let (Some(c), Some(r)) = (&t.columns, &t.rows) else {
                return Err(need(if t.columns.is_none() {
                    "columns"
                } else {
                    "rows"
                }));
            };
            let most = MAX_FLOES as u64;
            let columns = count(f, c, "tessellation.columns", 1, most)?;
            let rows = count(f, r, "tessellation.rows", 1, most)?;
            if columns.saturating_mul(rows) > MAX_FLOES {
                let (v, key) = if columns >= rows {
                    (c, "tessellation.columns")
                } else {
                    (r, "tessellation.rows")
                };
                return Err(f.error(
                    v.span(),
                    key,
                    format!("{columns} x {rows} floes is above the cap of {MAX_FLOES}"),
                ));
            }
            FloeSource::Grid {
                columns,
                rows,
                gap_m: match &t.gap_m {
                    Some(g) => distance(f, g, "tessellation.gap_m")?,
                    None => 0.0,
                },
            }
        }
        _ => {
            // "double-shear", the only kind left.
            let size = |v: &Pair, key: &str| -> Result<[f64; 2], ScenarioError> {
                let Some(v) = v else {
                    return Err(need(key));
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
                return Err(need("normal_load_per_face_n"));
            };
            let (push_velocity_m_per_s, push_schedule) =
                match (&t.push_velocity_m_per_s, &t.segment) {
                    (Some(push), None) => (
                        f.non_negative(push, "tessellation.push_velocity_m_per_s")?,
                        None,
                    ),
                    (None, Some(segments)) => {
                        let s = resolve_schedule(
                            f,
                            (segments, span.clone()),
                            "tessellation",
                            false,
                            extent,
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
                    (None, None) => return Err(need("push_velocity_m_per_s")),
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
            FloeSource::DoubleShear {
                block_m,
                side_block_m,
                pusher_m,
                normal_load_per_face_n: f.positive(load, "tessellation.normal_load_per_face_n")?,
                push_velocity_m_per_s,
                push_schedule,
            }
        }
    };
    Ok((source, span, min_area_fraction))
}
