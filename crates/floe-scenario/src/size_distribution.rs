//! `[tessellation] size_distribution`: floe sizes from a power law,
//! checked where they are written, and the checks that need the ice
//! region (the largest floe fits; not too many floes).

use std::ops::Range;

use floe_dem::tessellation::{PowerLawSizes, Rect, MAX_POWER_LAW_EXPONENT, MAX_POWER_LAW_FLOES};
use toml::Spanned;

use crate::error::ScenarioError;
use crate::length_limit::MAX_LENGTH_M;
use crate::numbers::{sig, thousands};
use crate::source_file::SourceFile;
use crate::spec::RawSizeDistribution;

const KEY: &str = "tessellation.size_distribution";

/// A resolved `size_distribution`, with where its bounds are written.
#[derive(Debug, Clone)]
pub(crate) struct SizeDistribution {
    pub law: PowerLawSizes,
    pub min_span: Range<usize>,
    pub max_span: Range<usize>,
}

/// Reads `size_distribution = { kind = "power_law", exponent, min_m, max_m }`.
pub(crate) fn resolve_size_distribution(
    f: &SourceFile,
    raw: &Spanned<RawSizeDistribution>,
) -> Result<SizeDistribution, ScenarioError> {
    let d = raw.get_ref();
    let missing = |name: &str, what: &str| {
        f.error(
            raw.span(),
            format!("{KEY}.{name}"),
            format!(
                "missing: {what}; e.g. size_distribution = {{ kind = \"power_law\", exponent = 2.0, \
                 min_m = 100.0, max_m = 2000.0 }}"
            ),
        )
    };
    match &d.kind {
        None => return Err(missing("kind", "`power_law` (the only kind)")),
        Some(k) if k.get_ref() != "power_law" => {
            return Err(f.error(
                k.span(),
                format!("{KEY}.kind"),
                format!("unknown kind `{}`, expected `power_law`", k.get_ref()),
            ))
        }
        Some(_) => {}
    }
    let Some(e) = &d.exponent else {
        return Err(missing(
            "exponent",
            "the exponent alpha of N(>d) ~ d^-alpha",
        ));
    };
    let exponent = *e.get_ref();
    if !(exponent.is_finite() && exponent > 0.0 && exponent <= MAX_POWER_LAW_EXPONENT) {
        return Err(f.error(
            e.span(),
            format!("{KEY}.exponent"),
            format!(
                "must be in (0, {MAX_POWER_LAW_EXPONENT}], got {exponent} (sea-ice floe sizes give \
                 about 1.5 to 3)"
            ),
        ));
    }
    let length =
        |v: &Option<Spanned<f64>>, name: &str| -> Result<(f64, Range<usize>), ScenarioError> {
            let Some(v) = v else {
                return Err(missing(
                    name,
                    "the smallest and largest floe sizes, sqrt(area) in m",
                ));
            };
            let key = format!("{KEY}.{name}");
            let x = f.positive(v, &key)?;
            if x > MAX_LENGTH_M {
                return Err(f.error(
                    v.span(),
                    key,
                    format!(
                        "{} m is beyond the largest accepted length, {} m",
                        sig(x),
                        sig(MAX_LENGTH_M)
                    ),
                ));
            }
            Ok((x, v.span()))
        };
    let (min_m, min_span) = length(&d.min_m, "min_m")?;
    let (max_m, max_span) = length(&d.max_m, "max_m")?;
    if max_m <= min_m {
        return Err(f.error(
            max_span,
            format!("{KEY}.max_m"),
            format!(
                "must be above min_m ({} m), got {} m",
                sig(min_m),
                sig(max_m)
            ),
        ));
    }
    Ok(SizeDistribution {
        law: PowerLawSizes {
            exponent,
            min_m,
            max_m,
        },
        min_span,
        max_span,
    })
}

/// Most floe-fits of a size distribution: floes × (Lloyd iterations + 1),
/// each a Newton fit of the cells' areas (10 iterations of 200,000 floes,
/// about half an hour on two cores).
pub const MAX_POWER_LAW_WORK: f64 = 2e6;

/// Refuses a largest floe wider than the ice region's shorter side, a
/// smallest floe so small that the region would hold more than
/// [`MAX_POWER_LAW_FLOES`] floes (naming the smallest `min_m` it allows),
/// and more Lloyd iterations (`relax`, and where it is written) than
/// [`MAX_POWER_LAW_WORK`] allows for that many floes.
pub(crate) fn check_fits(
    f: &SourceFile,
    d: &SizeDistribution,
    region: Rect,
    (relax, relax_span): (usize, Option<Range<usize>>),
) -> Result<(), ScenarioError> {
    let side = region.width_m().min(region.height_m());
    let law = d.law;
    if law.max_m > side {
        return Err(f.error(
            d.max_span.clone(),
            format!("{KEY}.max_m"),
            format!(
                "{} m is wider than the ice region's shorter side, {} m: the largest floe must fit",
                sig(law.max_m),
                sig(side)
            ),
        ));
    }
    let area = region.area_m2();
    let count = law.expected_count(area);
    if count <= MAX_POWER_LAW_FLOES as f64 {
        let work = count * (relax as f64 + 1.0);
        if work > MAX_POWER_LAW_WORK {
            return Err(f.error(
                relax_span.unwrap_or_else(|| d.min_span.clone()),
                "tessellation.relax_iterations",
                format!(
                    "about {} floes x ({relax} + 1) fits is {}, above the limit of {} for a size \
                     distribution (each Lloyd iteration refits every floe's area); use at most {} \
                     iterations",
                    sig(count),
                    sig(work),
                    sig(MAX_POWER_LAW_WORK),
                    ((MAX_POWER_LAW_WORK / count).floor() - 1.0).max(0.0)
                ),
            ));
        }
        return Ok(());
    }
    // The count falls as min_m rises: bisect for the smallest min_m allowed.
    let (mut lo, mut hi) = (law.min_m, law.max_m);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        let n = PowerLawSizes { min_m: mid, ..law }.expected_count(area);
        if n > MAX_POWER_LAW_FLOES as f64 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Err(f.error(
        d.min_span.clone(),
        format!("{KEY}.min_m"),
        format!(
            "{} m makes about {} floes in the {} x {} m ice region, above the limit of {} for a \
             size distribution; the region allows min_m of at least {} m (or a smaller exponent, \
             or a smaller region)",
            sig(law.min_m),
            sig(count),
            sig(region.width_m()),
            sig(region.height_m()),
            thousands(MAX_POWER_LAW_FLOES),
            sig(hi)
        ),
    ))
}
