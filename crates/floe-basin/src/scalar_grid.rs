//! A scalar field of a CF NetCDF file at one time, on the plane grid over
//! a region (the initial ice: concentration, thickness), sampled at points.
//!
//! The slice comes from [`NetcdfSource`] (x/y files node for node,
//! longitude-latitude files through the projection): a chosen record, or
//! the file's value at model time 0 (linear between the two records about
//! the `start_time`). A point is sampled bilinearly in its grid cell,
//! exactly as the engine's gridded forcing does
//! ([`floe_dem::forcing::GriddedField`]) where the cell's four nodes have
//! values. Where some do not (land, a fill value), the node nearest the
//! point decides: missing, and the point has no value (it lies on land at
//! the grid's resolution); present, and the point gets the bilinear
//! weights of the nodes with values, renormalised. So ice reaches the
//! coast instead of stopping a whole grid cell short of it.

use std::path::Path;
use std::sync::Arc;

use floe_dem::forcing::{PlaneGrid, SliceSource};
use floe_dem::Vec2;

use crate::cf_file::CfFile;
use crate::error::BasinError;
use crate::netcdf_source::{FieldRequest, NetcdfSource};
use crate::projection::MapProjection;

/// Which scalar to read, when and where.
#[derive(Debug, Clone, Copy)]
pub struct ScalarRequest<'a> {
    /// The NetCDF file.
    pub path: &'a Path,
    /// The variable.
    pub variable: &'a str,
    /// The record (time index) to read; `None`: the only record, or the
    /// value at model time 0 given `start_time`.
    pub time_index: Option<usize>,
    /// The model plane's projection (for longitude-latitude files).
    pub projection: Option<&'a MapProjection>,
    /// The date of model time 0 (`"YYYY-MM-DD HH:MM:SS"`).
    pub start_time: Option<&'a str>,
    /// The region the field must cover (lower-left, upper-right), m.
    pub region: (Vec2, Vec2),
}

/// A scalar on a plane grid, NaN where the file has no value.
#[derive(Debug, Clone)]
pub struct ScalarGrid {
    describe: String,
    when: String,
    grid: PlaneGrid,
    values: Vec<f64>,
}

impl ScalarGrid {
    /// Reads `request.variable` at the time asked for onto the plane grid
    /// over `request.region`.
    ///
    /// # Errors
    /// [`BasinError`] naming the file and variable: as
    /// [`NetcdfSource::open`], a time index beyond the file's records, a
    /// file of several records without a time index or start time, a model
    /// time 0 outside the file's times.
    pub fn open(request: ScalarRequest<'_>) -> Result<Self, BasinError> {
        let field = FieldRequest {
            path: request.path,
            variables: &[request.variable],
            projection: request.projection,
            start_time: request.start_time,
            region: request.region,
            plane_spacing_m: None,
            margin_m: 0.0,
            // Concentration and thickness are checked against their own
            // ranges once read (crate::ice_fields).
            limit: None,
        };
        let err = |why: String| BasinError::File {
            path: request.path.to_path_buf(),
            why: format!("variable \"{}\": {why}", request.variable),
        };
        let record = match request.time_index {
            Some(k) => Some(k),
            None => {
                let file = CfFile::open(request.path)?;
                let records = file.records(&file.layout(request.variable)?)?;
                match (records, request.start_time) {
                    (1, _) => Some(0),
                    (_, Some(_)) => None,
                    (n, None) => {
                        return Err(err(format!(
                            "{n} time records: give the time index to read (0 to {})",
                            n - 1
                        )))
                    }
                }
            }
        };
        if let Some(k) = record {
            let source = NetcdfSource::open_record(field, k)?;
            let mut values = vec![f64::NAN; source.grid().nodes()];
            source.read_slice(0, &mut values).map_err(|e| err(e.0))?;
            return Ok(ScalarGrid {
                describe: source.describe().to_string(),
                when: format!("time index {k}"),
                grid: *source.grid(),
                values,
            });
        }
        // The value at model time 0, linear between two records.
        let source = Arc::new(NetcdfSource::open(field)?);
        let times = source.times_s();
        let last = times.len() - 1;
        if !(times[0] <= 0.0 && 0.0 <= times[last]) {
            return Err(err(format!(
                "its times run from {} s to {} s of model time, which does not hold the start \
                 (0 s); give a time index or a start time inside the file's",
                times[0], times[last]
            )));
        }
        let i = times
            .partition_point(|&t| t <= 0.0)
            .saturating_sub(1)
            .min(last.saturating_sub(1));
        let nodes = source.grid().nodes();
        let mut lower = vec![f64::NAN; nodes];
        source.read_slice(i, &mut lower).map_err(|e| err(e.0))?;
        let w = if last == 0 {
            0.0
        } else {
            (-times[i] / (times[i + 1] - times[i])).clamp(0.0, 1.0)
        };
        let when = if w == 0.0 {
            format!("time index {i} (model time 0)")
        } else {
            let mut upper = vec![f64::NAN; nodes];
            source.read_slice(i + 1, &mut upper).map_err(|e| err(e.0))?;
            for (a, b) in lower.iter_mut().zip(&upper) {
                *a = (1.0 - w) * *a + w * b;
            }
            format!(
                "model time 0, between time indices {i} and {} (weight {w:.4})",
                i + 1
            )
        };
        Ok(ScalarGrid {
            describe: source.describe().to_string(),
            when,
            grid: *source.grid(),
            values: lower,
        })
    }

    /// A field given node by node (`values[j nx + i]`, NaN where missing).
    ///
    /// # Panics
    /// If there is not one value per node.
    pub fn from_values(describe: &str, grid: PlaneGrid, values: Vec<f64>) -> Self {
        assert_eq!(values.len(), grid.nodes(), "one value per node");
        ScalarGrid {
            describe: describe.to_string(),
            when: String::new(),
            grid,
            values,
        }
    }

    /// The file and variable.
    pub fn describe(&self) -> &str {
        &self.describe
    }

    /// Which time was read (`time index 3`, or the records about model
    /// time 0).
    pub fn when(&self) -> &str {
        &self.when
    }

    /// The plane grid.
    pub fn grid(&self) -> &PlaneGrid {
        &self.grid
    }

    /// The values, node `j nx + i` at `[j nx + i]`, NaN where missing.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Applies `f` to every value (a change of units).
    pub fn map_values(&mut self, f: impl Fn(f64) -> f64) {
        for v in &mut self.values {
            *v = f(*v);
        }
    }

    /// The plane position of node `k`, m.
    pub fn node_position(&self, k: usize) -> Vec2 {
        self.grid.node_position(k)
    }

    /// The node nearest `p`, or `None` off the grid.
    pub fn nearest_node(&self, p: Vec2) -> Option<usize> {
        let c = self.grid.cell(p)?;
        Some(c.node + usize::from(c.fx >= 0.5) + self.grid.nx * usize::from(c.fy >= 0.5))
    }

    /// The value at `p` (see the module docs): bilinear where the cell's
    /// nodes have values, `None` off the grid or where the nearest node
    /// has none.
    pub fn at(&self, p: Vec2) -> Option<f64> {
        let c = self.grid.cell(p)?;
        let (k, nx) = (c.node, self.grid.nx);
        let v = [
            self.values[k],
            self.values[k + 1],
            self.values[k + nx],
            self.values[k + nx + 1],
        ];
        if v.iter().all(|x| x.is_finite()) {
            // The engine's bilinear form (GriddedField).
            return Some(c.interpolate(&v));
        }
        let nearest = usize::from(c.fx >= 0.5) + 2 * usize::from(c.fy >= 0.5);
        if !v[nearest].is_finite() {
            return None;
        }
        let (mut sum, mut weight) = (0.0, 0.0);
        for (x, w) in v.iter().zip(c.weights()) {
            if x.is_finite() {
                sum += w * x;
                weight += w;
            }
        }
        Some(sum / weight)
    }

    /// The smallest and largest values with the nodes where they are, or
    /// `None` if every value is missing.
    pub fn extremes(&self) -> Option<((f64, usize), (f64, usize))> {
        let mut out: Option<((f64, usize), (f64, usize))> = None;
        for (k, &v) in self.values.iter().enumerate() {
            if !v.is_finite() {
                continue;
            }
            out = Some(match out {
                None => ((v, k), (v, k)),
                Some((lo, hi)) => (
                    if v < lo.0 { (v, k) } else { lo },
                    if v > hi.0 { (v, k) } else { hi },
                ),
            });
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field(values: Vec<f64>) -> ScalarGrid {
        let grid = PlaneGrid {
            origin_m: Vec2::new(0.0, 0.0),
            spacing_m: Vec2::new(10.0, 10.0),
            nx: 3,
            ny: 2,
        };
        ScalarGrid::from_values("test", grid, values)
    }

    #[test]
    fn bilinear_where_the_cell_is_complete_and_the_nearest_node_decides_elsewhere() {
        // x + 2y at the nodes.
        let f = field(vec![0.0, 10.0, 20.0, 20.0, 30.0, 40.0]);
        assert!((f.at(Vec2::new(13.0, 4.0)).unwrap() - 21.0).abs() < 1e-12);
        assert_eq!(f.at(Vec2::new(-1.0, 4.0)), None);
        // Node (2, 1) is land.
        let f = field(vec![0.0, 10.0, 20.0, 20.0, 30.0, f64::NAN]);
        // Nearest (1, 0): the three nodes with values, renormalised.
        let v = f.at(Vec2::new(14.0, 2.0)).unwrap();
        let (w00, w10, w01) = (0.6 * 0.8, 0.4 * 0.8, 0.6 * 0.2);
        let want = (w00 * 10.0 + w10 * 20.0 + w01 * 30.0) / (w00 + w10 + w01);
        assert!((v - want).abs() < 1e-12, "{v} {want}");
        // Nearest (2, 1): on land.
        assert_eq!(f.at(Vec2::new(17.0, 6.0)), None);
        // The other cell is complete.
        assert_eq!(f.at(Vec2::new(5.0, 5.0)), Some(15.0));
        assert_eq!(f.nearest_node(Vec2::new(17.0, 6.0)), Some(5));
        assert_eq!(f.extremes(), Some(((0.0, 0), (30.0, 4))));
    }
}
