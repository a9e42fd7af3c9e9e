//! Ice from gridded fields: the floes of a tessellation kept where a
//! concentration grid says there is ice, in the amount it says
//! ([`floe_dem::tessellation::select_by_concentration`]), with the
//! thickness of a thickness grid at their centroids. Floes on land (no
//! concentration at the nearest grid node), where the concentration is 0,
//! or where the thickness is missing, not positive or below the thinnest
//! accepted ice are dropped before the selection; the build report counts
//! each, and gives the ice area kept against concentration × area, overall
//! and per grid cell.

use floe_basin::{open_concentration, open_thickness, MapProjection, ScalarGrid, ScalarRequest};
use floe_dem::tessellation::{select_by_concentration, Rect, Tessellation};
use floe_dem::Vec2;

use crate::error::ScenarioError;
use crate::ice_grid_keys::GridField;
use crate::numbers::{sig, thousands};
use crate::resolve::{Resolved, MAX_THICKNESS_M, MIN_THICKNESS_M};
use crate::source_file::SourceFile;

/// The time and place of the grids: `projection` puts longitude-latitude
/// files on the plane, `start_time` is the date of model time 0.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct GridFrame<'a> {
    pub projection: Option<&'a MapProjection>,
    pub start_time: Option<&'a str>,
}

fn request<'a>(g: &'a GridField, region: Rect, frame: GridFrame<'a>) -> ScalarRequest<'a> {
    ScalarRequest {
        path: &g.path,
        variable: &g.variable,
        time_index: g.time_index,
        projection: frame.projection,
        start_time: frame.start_time,
        region: (region.min, region.max),
    }
}

/// Why a floe is not placed.
#[derive(Default)]
struct Dropped {
    thickness_missing: usize,
    too_thin: usize,
}

/// Applies `[ice] concentration_grid` and `thickness_grid` to the floes
/// of `t` (filling `region`), writing what was done to `report`.
pub(crate) fn place_from_grids(
    f: &SourceFile,
    r: &Resolved,
    region: Rect,
    t: &mut Tessellation,
    frame: GridFrame<'_>,
    report: &mut Vec<String>,
) -> Result<(), ScenarioError> {
    let grids = &r.ice_grids;
    if !grids.any() {
        return Ok(());
    }
    let located =
        |g: &GridField, e: floe_basin::BasinError| f.error(g.span.clone(), g.key, e.to_string());
    let concentration = match &grids.concentration {
        Some(g) => Some(
            open_concentration(request(g, region, frame), g.units).map_err(|e| located(g, e))?,
        ),
        None => None,
    };
    let thickness = match &grids.thickness {
        Some(g) => {
            let field = open_thickness(request(g, region, frame)).map_err(|e| located(g, e))?;
            if let Some((_, (hi, k))) = field.extremes() {
                if hi > MAX_THICKNESS_M {
                    let p = field.node_position(k);
                    return Err(f.error(
                        g.span.clone(),
                        g.key,
                        format!(
                            "{}: thickness {} m at ({:.1}, {:.1}) m is above the thickest accepted \
                             ice, {} m",
                            field.describe(),
                            sig(hi),
                            p.x,
                            p.y,
                            sig(MAX_THICKNESS_M)
                        ),
                    ));
                }
            }
            Some(field)
        }
        None => None,
    };

    let n = t.len();
    let centroids: Vec<Vec2> = (0..n).map(|k| t.centroid_m(k)).collect();
    let areas: Vec<f64> = (0..n).map(|k| t.area_m2(k)).collect();
    let mut c: Vec<f64> = match &concentration {
        Some(g) => centroids
            .iter()
            .map(|&p| g.field.at(p).unwrap_or(f64::NAN))
            .collect(),
        None => vec![1.0; n],
    };
    let mut dropped = Dropped::default();
    if let Some(h) = &thickness {
        for k in 0..n {
            let value = h.at(centroids[k]);
            match value {
                Some(v) if v >= MIN_THICKNESS_M => t.thickness_m[k] = v,
                _ if c[k].is_nan() || c[k] <= 0.0 => {}
                Some(v) if v > 0.0 => {
                    dropped.too_thin += 1;
                    c[k] = f64::NAN;
                }
                _ => {
                    dropped.thickness_missing += 1;
                    c[k] = f64::NAN;
                }
            }
        }
    }
    // Cell by cell of the concentration's grid: the cell of the nearest node.
    let cells: Option<Vec<(u32, u32)>> = concentration.as_ref().map(|g| {
        let nx = g.field.grid().nx;
        centroids
            .iter()
            .map(|&p| {
                g.field
                    .nearest_node(p)
                    .map_or((u32::MAX, u32::MAX), |k| ((k % nx) as u32, (k / nx) as u32))
            })
            .collect()
    });
    let (keep, selection) =
        select_by_concentration(&areas, &centroids, &c, cells.as_deref(), region, r.seed);

    // Kept against wanted area per cell of the concentration grid.
    let cells = concentration
        .as_ref()
        .map(|g| per_cell(&g.field, &centroids, &areas, &c, &keep));
    t.retain(&keep);
    if t.is_empty() && n > 0 {
        let g = grids.first().expect("a grid is given");
        return Err(f.error(
            g.span.clone(),
            g.key,
            format!(
                "leaves no floe: none of the {} floes has its centroid where the grids give ice \
                 (a concentration above 0 and, with a thickness grid, a thickness of at least \
                 {MIN_THICKNESS_M} m); check that the grid is the one for this domain and time",
                thousands(n)
            ),
        ));
    }

    let region_area = region.area_m2();
    let mut line = format!(
        "ice from grids: {} of {} floes placed",
        thousands(selection.kept),
        thousands(n)
    );
    if let (Some(g), Some(conc)) = (&grids.concentration, &concentration) {
        line += &format!(
            " by the concentration `{}` of {} ({}; {})",
            g.variable,
            g.written,
            conc.field.when(),
            conc.units_reason,
        );
    }
    if let (Some(g), Some(h)) = (&grids.thickness, &thickness) {
        line += &format!(
            "{} the thickness `{}` of {} ({})",
            if concentration.is_some() {
                ", with"
            } else {
                " with"
            },
            g.variable,
            g.written,
            h.when(),
        );
    }
    report.push(line);
    if concentration.is_some() {
        let ratio = selection.kept_area_m2 / selection.wanted_area_m2;
        report.push(format!(
            "  ice area {} m^2 against concentration x area {} m^2 ({}): {} of the ice region against {}",
            sig(selection.kept_area_m2),
            sig(selection.wanted_area_m2),
            if ratio.is_finite() {
                format!("{} %", sig(100.0 * ratio))
            } else {
                "no ice wanted".to_string()
            },
            sig(selection.kept_area_m2 / region_area),
            sig(selection.wanted_area_m2 / region_area)
        ));
    }
    if let Some(s) = cells {
        report.push(format!(
            "  per grid cell ({} cells of {} x {} m with ice): kept minus wanted area rms {} %, largest {} % of the cell",
            thousands(s.cells),
            sig(s.cell_size.x),
            sig(s.cell_size.y),
            sig(100.0 * s.rms),
            sig(100.0 * s.largest)
        ));
    }
    let mut why = Vec::new();
    if concentration.is_some() {
        why.push(format!(
            "{} on land, off the data or where the concentration is 0",
            thousands(selection.no_ice - dropped.thickness_missing - dropped.too_thin)
        ));
        why.push(format!(
            "{} left as open water by the selection",
            thousands(selection.thinned)
        ));
    }
    if thickness.is_some() {
        why.push(format!(
            "{} where the thickness is missing or <= 0",
            thousands(dropped.thickness_missing)
        ));
        why.push(format!(
            "{} thinner than {MIN_THICKNESS_M} m (the thinnest accepted ice)",
            thousands(dropped.too_thin)
        ));
    }
    report.push(format!("  dropped: {}", why.join(", ")));
    if thickness.is_some() && !t.is_empty() {
        let (lo, hi, sum) = t
            .thickness_m
            .iter()
            .fold((f64::INFINITY, 0.0f64, 0.0), |(lo, hi, s), &h| {
                (lo.min(h), hi.max(h), s + h)
            });
        report.push(format!(
            "  thickness of the placed floes: mean {} m, from {} to {} m",
            sig(sum / t.len() as f64),
            sig(lo),
            sig(hi)
        ));
    }
    Ok(())
}

/// Kept minus wanted ice area per cell of a grid, relative to the cell.
struct CellDeviation {
    cells: usize,
    cell_size: Vec2,
    rms: f64,
    largest: f64,
}

/// Floes are counted in the cell of their centroid's nearest node (the
/// cell a node's value stands for); cells with ice wanted or kept count.
fn per_cell(
    field: &ScalarGrid,
    centroids: &[Vec2],
    areas: &[f64],
    c: &[f64],
    keep: &[bool],
) -> CellDeviation {
    let grid = field.grid();
    let mut wanted = vec![0.0; grid.nodes()];
    let mut kept = vec![0.0; grid.nodes()];
    for k in 0..centroids.len() {
        let Some(node) = field.nearest_node(centroids[k]) else {
            continue;
        };
        if c[k] > 0.0 {
            wanted[node] += c[k].min(1.0) * areas[k];
        }
        if keep[k] {
            kept[node] += areas[k];
        }
    }
    let cell = grid.spacing_m.x * grid.spacing_m.y;
    let (mut n, mut sum, mut largest) = (0usize, 0.0, 0.0f64);
    for (w, k) in wanted.iter().zip(&kept) {
        if *w > 0.0 || *k > 0.0 {
            let e = (k - w) / cell;
            n += 1;
            sum += e * e;
            largest = largest.max(e.abs());
        }
    }
    CellDeviation {
        cells: n,
        cell_size: grid.spacing_m,
        rms: if n > 0 { (sum / n as f64).sqrt() } else { 0.0 },
        largest,
    }
}
