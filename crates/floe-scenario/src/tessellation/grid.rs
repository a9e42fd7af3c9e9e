//! `kind = "grid"`: `columns` x `rows` rectangles filling the ice region,
//! `gap_m` apart.

use std::sync::Arc;

use floe_dem::tessellation::{Tessellation, MAX_FLOES};
use floe_dem::Vec2;

use super::{rect_polygon, Generate, Generation, Keys, Kind};
use crate::error::ScenarioError;
use crate::numbers::{sig, thousands};
use crate::piece::Piece;
use crate::resolve::limits::{count, distance};

/// Its line of [`super::KINDS`].
pub(super) const KIND: Kind = Kind {
    name: "grid",
    keys: &["columns", "rows", "gap_m"],
    resolve,
    sea_ice: true,
};

/// A grid of rectangles, checked.
#[derive(Debug, Clone)]
struct Grid {
    columns: usize,
    rows: usize,
    gap_m: f64,
}

fn resolve(k: &Keys<'_>) -> Result<Arc<dyn Generate>, ScenarioError> {
    let (f, t) = (k.f, k.t);
    let (Some(c), Some(r)) = (&t.columns, &t.rows) else {
        return Err(k.need(if t.columns.is_none() {
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
    Ok(Arc::new(Grid {
        columns,
        rows,
        gap_m: match &t.gap_m {
            Some(g) => distance(f, g, "tessellation.gap_m")?,
            None => 0.0,
        },
    }))
}

impl Generate for Grid {
    fn generate(
        &self,
        g: &Generation<'_>,
        report: &mut Vec<String>,
    ) -> Result<Vec<Piece>, ScenarioError> {
        let (f, span, region) = (g.f, g.span.clone(), g.region);
        let Grid {
            columns,
            rows,
            gap_m,
        } = self;
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
        let thickness = g.thickness.sample(n, g.seed).map_err(|e| g.dem(e))?;
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
        (g.place)(
            Tessellation {
                polygons,
                thickness_m: thickness,
            },
            report,
        )
    }
}
