//! `kind = "voronoi"` with `size_distribution`: Laguerre cells whose sizes
//! `sqrt(area)` are drawn from a power law ([`crate::size_distribution`]),
//! with the fitted exponent of what was made in the report.

use std::ops::Range;
use std::sync::Arc;

use floe_dem::tessellation::{fit_sizes, PowerLawFit, PowerLawFloes, PowerLawSizes, Tessellation};
use floe_dem::Vec2;

use super::{Generate, Generation, Keys, MAX_RELAX_ITERATIONS};
use crate::error::ScenarioError;
use crate::numbers::{sig, thousands};
use crate::piece::Piece;
use crate::resolve::limits::{count, span_of};
use crate::size_distribution::{check_fits, resolve_size_distribution, SizeDistribution};

/// Power-law floes, checked.
#[derive(Debug, Clone)]
struct PowerLaw {
    sizes: SizeDistribution,
    relax_iterations: usize,
    relax_span: Option<Range<usize>>,
    fill_fraction: f64,
}

/// The keys of a Voronoi tessellation with `size_distribution`.
pub(super) fn resolve(k: &Keys<'_>) -> Result<Arc<dyn Generate>, ScenarioError> {
    let (f, t) = (k.f, k.t);
    let sizes = t.size_distribution.as_ref().expect("called when given");
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
    Ok(Arc::new(PowerLaw {
        sizes: resolve_size_distribution(f, sizes)?,
        relax_iterations,
        relax_span: span_of(&t.relax_iterations),
        fill_fraction: super::fill::fill_fraction(k)?,
    }))
}

impl Generate for PowerLaw {
    fn generate(
        &self,
        g: &Generation<'_>,
        report: &mut Vec<String>,
    ) -> Result<Vec<Piece>, ScenarioError> {
        let (region, sizes, relax_iterations) = (g.region, &self.sizes, self.relax_iterations);
        check_fits(
            g.f,
            sizes,
            region,
            (relax_iterations, self.relax_span.clone()),
        )?;
        let (mut t, pr) = PowerLawFloes {
            domain: region,
            sizes: sizes.law,
            seed: g.seed,
            thickness: g.thickness,
            relax_iterations,
        }
        .build()
        .map_err(|e| g.dem(e))?;
        let law = sizes.law;
        let drop = t.drop_floes_smaller_than(g.min_area_fraction * law.min_m * law.min_m);
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
                g.min_area_fraction,
                sig(drop.dropped_area_m2)
            ));
        }
        super::fill::fill(&mut t, self.fill_fraction, report);
        let placed = (g.place)(t, report)?;
        if g.concentration_grid {
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
