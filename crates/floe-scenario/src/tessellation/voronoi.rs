//! `kind = "voronoi"`: Voronoi cells of random sites, relaxed by Lloyd
//! iterations, as many as `count` or as `floe_scale_m` makes; with
//! `size_distribution` the cells are Laguerre cells of drawn sizes
//! ([`super::power_law`]).

use std::ops::Range;
use std::sync::Arc;

use floe_dem::tessellation::{VoronoiFloes, MAX_FLOES};

use super::{fill, power_law, Generate, Generation, Keys, Kind, MAX_RELAX_ITERATIONS};
use crate::error::ScenarioError;
use crate::numbers::{sig, thousands};
use crate::piece::Piece;
use crate::resolve::limits::{count, length};
use crate::source_file::SourceFile;

/// Its line of [`super::KINDS`].
pub(super) const KIND: Kind = Kind {
    name: "voronoi",
    keys: &[
        "min_area_fraction",
        "floe_scale_m",
        "count",
        "relax_iterations",
        "size_distribution",
        "fill_fraction",
    ],
    resolve,
    sea_ice: true,
};

/// Most Voronoi work, sites x (Lloyd iterations + 1): one pass over 1e6
/// sites takes about 5 s, so the limit is about 8 minutes.
pub const MAX_VORONOI_WORK: f64 = 1e8;

/// How many sites: given, or from the floe scale and the ice region.
#[derive(Debug, Clone)]
enum Sites {
    Count(usize),
    Scale(f64),
}

/// A Voronoi tessellation, checked.
#[derive(Debug, Clone)]
struct Voronoi {
    sites: Sites,
    relax_iterations: usize,
    fill_fraction: f64,
}

/// Refuses a tessellation of `sites` Voronoi sites relaxed `iterations`
/// times whose work is above [`MAX_VORONOI_WORK`], blaming `key` at `span`.
fn voronoi_work(
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

fn resolve(k: &Keys<'_>) -> Result<Arc<dyn Generate>, ScenarioError> {
    let (f, t) = (k.f, k.t);
    if t.size_distribution.is_some() {
        return power_law::resolve(k);
    }
    let sites = match (&t.count, &t.floe_scale_m) {
        (Some(c), None) => Sites::Count(count(f, c, "tessellation.count", 1, MAX_FLOES as u64)?),
        (None, Some(s)) => Sites::Scale(length(f, s, "tessellation.floe_scale_m")?),
        (Some(c), Some(_)) => {
            return Err(f.error(
                c.span(),
                "tessellation.count",
                "give `count` or `floe_scale_m`, not both",
            ))
        }
        (None, None) => return Err(k.need("count` or `floe_scale_m")),
    };
    let relax_iterations = match &t.relax_iterations {
        Some(r) => {
            let key = "tessellation.relax_iterations";
            let n = count(f, r, key, 0, MAX_RELAX_ITERATIONS)?;
            if let Sites::Count(sites) = sites {
                voronoi_work(f, r.span(), key, sites, n)?;
            }
            n
        }
        None => 1,
    };
    Ok(Arc::new(Voronoi {
        sites,
        relax_iterations,
        fill_fraction: fill::fill_fraction(k)?,
    }))
}

impl Generate for Voronoi {
    fn generate(
        &self,
        g: &Generation<'_>,
        report: &mut Vec<String>,
    ) -> Result<Vec<Piece>, ScenarioError> {
        let (f, span, region) = (g.f, g.span.clone(), g.region);
        let relax_iterations = self.relax_iterations;
        let n = match self.sites {
            Sites::Count(n) => n,
            Sites::Scale(scale) => {
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
                voronoi_work(f, span.clone(), key, n, relax_iterations)?;
                n
            }
        };
        let v = VoronoiFloes {
            domain: region,
            count: n,
            seed: g.seed,
            thickness: g.thickness,
            relax_iterations,
        };
        let mut t = v.build().map_err(|e| g.dem(e))?;
        let mean = region.area_m2() / n as f64;
        let drop = t.drop_floes_smaller_than(g.min_area_fraction * mean);
        report.push(format!(
            "floes: {} Voronoi cells (mean area {} m^2, {} Lloyd iterations)",
            thousands(t.len()),
            sig(mean),
            relax_iterations
        ));
        report.push(g.dropped_line("cells", drop.dropped, drop.dropped_area_m2));
        fill::fill(&mut t, self.fill_fraction, report);
        (g.place)(t, report)
    }
}
