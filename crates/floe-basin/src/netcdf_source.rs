//! A gridded forcing field read from a CF NetCDF file: the engine's
//! [`SliceSource`] over one file (wind, current: two variables; sea-surface
//! height: one).
//!
//! The engine evaluates fields on a regular grid of the model plane
//! ([`PlaneGrid`]). For a file on projected x/y coordinates (the model
//! plane's own), that grid is the file's grid cut to the region the run
//! needs, and a slice is copied node for node. For a longitude-latitude
//! file, the plane grid covers the region at half the file's spacing (or
//! the spacing asked for); each plane node is projected back to longitude
//! and latitude once, and every slice is sampled there bilinearly in the
//! file's indices, east and north components turned onto the plane's axes
//! ([`MapProjection::east_north`]). A component on its own grid (the u and
//! v points of a staggered C grid) is sampled the same way.
//!
//! Vector components of an x/y file are taken along the grid's axes
//! (CF `x_wind`, `sea_water_x_velocity`), unless their `standard_name`
//! says eastward/northward, in which case they are turned with the
//! projection like those of a longitude-latitude file.

use std::ops::Range;
use std::path::Path;
use std::sync::Mutex;

use floe_dem::forcing::gridded::CellPosition;
use floe_dem::forcing::{ForcingFailure, PlaneGrid, SliceSource};
use floe_dem::Vec2;

use crate::cf_file::{AxisKind, CfFile, RegularAxis, VariableLayout};
use crate::error::BasinError;
use crate::projection::MapProjection;
use crate::value_limit::ValueLimit;

/// Mean Earth radius, m: only to pick a plane spacing like the file's.
const EARTH_RADIUS_M: f64 = 6.371e6;

/// What to read and where the run needs it.
#[derive(Debug, Clone, Copy)]
pub struct FieldRequest<'a> {
    /// The NetCDF file.
    pub path: &'a Path,
    /// One variable (a scalar) or two (the x or east, then the y or north
    /// component of a vector).
    pub variables: &'a [&'a str],
    /// The model plane's projection (needed for longitude-latitude files
    /// and eastward/northward components).
    pub projection: Option<&'a MapProjection>,
    /// The date of model time 0 (`"YYYY-MM-DD HH:MM:SS"`), needed when the
    /// file has a time axis.
    pub start_time: Option<&'a str>,
    /// The region of the plane the field must cover (lower-left and
    /// upper-right corners, m): the domain.
    pub region: (Vec2, Vec2),
    /// Plane grid spacing for a longitude-latitude file, m; `None`: half
    /// the file's spacing at the region's centre.
    pub plane_spacing_m: Option<f64>,
    /// How far beyond the region the plane grid reaches where the file has
    /// data, m (floes that stray out of an open domain stay on the grid).
    pub margin_m: f64,
    /// The largest magnitude a value may have; a slice holding a larger
    /// one is refused when read. `None`: any finite value.
    pub limit: Option<ValueLimit>,
}

/// Where plane node `k` samples one component: the file node `(i, j)` of
/// the window read and the fractions across the cell.
#[derive(Debug, Clone, Copy)]
struct Sample {
    i: u32,
    j: u32,
    fx: f64,
    fy: f64,
}

/// How one variable is sampled.
#[derive(Debug)]
struct Component {
    layout: VariableLayout,
    rows: Range<usize>,
    cols: Range<usize>,
    /// Whether columns wrap around (a global longitude axis).
    wrap: bool,
    samples: Vec<Sample>,
}

/// A file's variables as time slices on a plane grid. See the module docs.
pub struct NetcdfSource {
    describe: String,
    file: Mutex<CfFile>,
    grid: PlaneGrid,
    times: Vec<f64>,
    components: Vec<Component>,
    /// Per plane node, the plane directions of east and north (vectors
    /// given as east/north components), or empty.
    east_north: Vec<(Vec2, Vec2)>,
    /// For a source of one chosen record ([`NetcdfSource::open_record`]):
    /// the file's time index that slice 0 reads.
    record: Option<usize>,
    /// [`FieldRequest::limit`].
    limit: Option<ValueLimit>,
}

impl std::fmt::Debug for NetcdfSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "NetcdfSource({})", self.describe)
    }
}

impl NetcdfSource {
    /// Opens `request.path` and prepares the sampling of its variables on
    /// the plane grid over `request.region`.
    ///
    /// # Errors
    /// [`BasinError::File`] naming the file and variable: a missing file or
    /// variable, axes that are not regular x/y or longitude/latitude,
    /// components on different kinds of grid, a region the grid does not
    /// cover, a longitude-latitude file without a projection, bad times.
    pub fn open(request: FieldRequest<'_>) -> Result<Self, BasinError> {
        Self::open_located(request, "")
    }

    /// [`NetcdfSource::open`], with `context` (`scenario.toml:12:8:
    /// \`wind.file\`: `) beginning the message printed if the NetCDF
    /// library crashes or hangs on the file ([`CfFile::open_located`]).
    ///
    /// # Errors
    /// As [`NetcdfSource::open`].
    pub fn open_located(request: FieldRequest<'_>, context: &str) -> Result<Self, BasinError> {
        Self::open_with(request, None, context)
    }

    /// Like [`NetcdfSource::open`], but one slice only, at time 0: the
    /// file's record `record` (its time index; 0 for a variable without a
    /// time dimension). The file's dates are not read, so no
    /// `start_time` is needed.
    ///
    /// # Errors
    /// As [`NetcdfSource::open`], and a record beyond the file's.
    pub fn open_record(request: FieldRequest<'_>, record: usize) -> Result<Self, BasinError> {
        Self::open_with(request, Some(record), "")
    }

    fn open_with(
        request: FieldRequest<'_>,
        record: Option<usize>,
        context: &str,
    ) -> Result<Self, BasinError> {
        let file = CfFile::open_located(request.path, context)?;
        let err = |why: String| BasinError::File {
            path: request.path.to_path_buf(),
            why,
        };
        let layouts = request
            .variables
            .iter()
            .map(|v| file.layout(v))
            .collect::<Result<Vec<_>, _>>()?;
        let geographic = layouts[0].x.kind == AxisKind::Longitude;
        if layouts
            .iter()
            .any(|l| (l.x.kind == AxisKind::Longitude) != geographic)
        {
            return Err(err(format!(
                "variables {} are on different kinds of grid (x/y and longitude/latitude)",
                request.variables.join(", ")
            )));
        }
        if let Some(k) = record {
            for l in &layouts {
                let records = file.records(l)?;
                if k >= records {
                    return Err(err(format!(
                        "variable \"{}\" has {records} time record(s): time index {k} is \
                         beyond the last, {}",
                        l.name,
                        records - 1
                    )));
                }
            }
        }
        let times = match record {
            Some(_) => vec![0.0],
            None => {
                let times = file
                    .times_s(&layouts[0], request.start_time)?
                    .unwrap_or_else(|| vec![0.0]);
                for l in &layouts[1..] {
                    let other = file
                        .times_s(l, request.start_time)?
                        .unwrap_or_else(|| vec![0.0]);
                    if other != times {
                        return Err(err(format!(
                            "variables {} and {} have different times",
                            request.variables[0], l.name
                        )));
                    }
                }
                times
            }
        };
        let eastward = request.variables.len() == 2
            && file
                .text_attribute(request.variables[0], "standard_name")
                .is_some_and(|s| s.starts_with("eastward"));
        let rotate = request.variables.len() == 2 && (geographic || eastward);
        let projection = match (geographic || rotate, request.projection) {
            (true, None) => {
                return Err(err(format!(
                    "variable \"{}\" is {}: give the scenario's [map] projection \
                     (e.g. projection = \"EPSG:3413\") to put it on the model plane",
                    request.variables[0],
                    if geographic {
                        "on a longitude-latitude grid"
                    } else {
                        "an eastward component"
                    }
                )))
            }
            (_, p) => p,
        };
        let grid = if geographic {
            geographic_plane_grid(&layouts[0], request, projection.expect("checked above"))
                .map_err(err)?
        } else {
            projected_plane_grid(&layouts[0], request.region, request.margin_m).map_err(err)?
        };
        let mut plane_lonlat = Vec::new();
        let mut east_north = Vec::new();
        if geographic || rotate {
            let p = projection.expect("checked above");
            for k in 0..grid.nodes() {
                let node = grid.node_position(k);
                let (lon, lat) = p.inverse(node)?;
                plane_lonlat.push((lon, lat));
                if rotate {
                    east_north.push(p.east_north(lon, lat)?);
                }
            }
        }
        let components = layouts
            .into_iter()
            .map(|layout| {
                let at = |k: usize| -> (f64, f64) {
                    if geographic {
                        plane_lonlat[k]
                    } else {
                        let n = grid.node_position(k);
                        (n.x, n.y)
                    }
                };
                component(layout, &grid, at, request).map_err(err)
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(NetcdfSource {
            describe: format!(
                "{}: {}",
                request.path.display(),
                request.variables.join(", ")
            ),
            file: Mutex::new(file),
            grid,
            times,
            components,
            east_north,
            record,
            limit: request.limit,
        })
    }
}

/// The file's own x/y grid cut to the region and its margin (as far as
/// the file reaches), ascending.
fn projected_plane_grid(
    layout: &VariableLayout,
    (lo, hi): (Vec2, Vec2),
    margin: f64,
) -> Result<PlaneGrid, String> {
    let cut = |a: &RegularAxis, lo: f64, hi: f64, name: &str| -> Result<(f64, usize), String> {
        let (min, max) = a.bounds();
        if lo < min || hi > max {
            return Err(format!(
                "variable \"{}\": the grid spans {name} {min} to {max} m but the domain spans \
                 {lo} to {hi} m; give a file that covers the domain",
                layout.name
            ));
        }
        let (lo, hi) = ((lo - margin).max(min), (hi + margin).min(max));
        let step = a.step.abs();
        let first = ((lo - min) / step).floor().max(0.0) as usize;
        let n_all = a.len;
        let last = (((hi - min) / step).ceil() as usize)
            .min(n_all - 1)
            .max(first + 1);
        Ok((min + first as f64 * step, last - first + 1))
    };
    let (x0, nx) = cut(&layout.x, lo.x, hi.x, "x")?;
    let (y0, ny) = cut(&layout.y, lo.y, hi.y, "y")?;
    Ok(PlaneGrid {
        origin_m: Vec2::new(x0, y0),
        spacing_m: Vec2::new(layout.x.step.abs(), layout.y.step.abs()),
        nx,
        ny,
    })
}

/// A plane grid over the region and its margin, at the requested spacing
/// or half the file's, with one node more on each side (nodes the file
/// does not reach have no values).
fn geographic_plane_grid(
    layout: &VariableLayout,
    request: FieldRequest<'_>,
    projection: &MapProjection,
) -> Result<PlaneGrid, String> {
    let (lo, hi) = request.region;
    let spacing = match request.plane_spacing_m {
        Some(s) => s,
        None => {
            let centre = 0.5 * (lo + hi);
            let (_, lat) = projection.inverse(centre).map_err(|e| e.to_string())?;
            let dlat = layout.y.step.abs().to_radians() * EARTH_RADIUS_M;
            let dlon = layout.x.step.abs().to_radians() * EARTH_RADIUS_M * lat.to_radians().cos();
            0.5 * dlat.min(dlon.max(1.0))
        }
    };
    if !(spacing.is_finite() && spacing > 0.0) {
        return Err(format!("plane grid spacing {spacing} m must be > 0"));
    }
    let (lo, hi) = (
        lo - Vec2::splat(request.margin_m),
        hi + Vec2::splat(request.margin_m),
    );
    let n = |span: f64| ((span / spacing).ceil() as usize + 3).max(2);
    let (nx, ny) = (n(hi.x - lo.x), n(hi.y - lo.y));
    let nodes = nx as u64 * ny as u64;
    if nodes > 50_000_000 {
        return Err(format!(
            "the plane grid over the domain at {spacing} m would have {nodes} nodes; \
             give a coarser plane_spacing_m"
        ));
    }
    Ok(PlaneGrid {
        origin_m: lo - Vec2::splat(spacing),
        spacing_m: Vec2::splat(spacing),
        nx,
        ny,
    })
}

/// Where each plane node samples `layout`'s grid, and the window to read.
fn component(
    layout: VariableLayout,
    grid: &PlaneGrid,
    at: impl Fn(usize) -> (f64, f64),
    request: FieldRequest<'_>,
) -> Result<Component, String> {
    let (x, y) = (layout.x, layout.y);
    let wrap = x.kind == AxisKind::Longitude
        && ((x.len as f64) * x.step.abs() - 360.0).abs() < 1e-6 * 360.0;
    let (lo, hi) = request.region;
    let mut fractional = Vec::with_capacity(grid.nodes());
    for k in 0..grid.nodes() {
        let (mut a, b) = at(k);
        if x.kind == AxisKind::Longitude {
            // Into the axis's own 360° range.
            let (min, _) = x.bounds();
            a = min + (a - min).rem_euclid(360.0);
        }
        // Nodes that are file nodes up to rounding sample them exactly.
        let snap = |f: f64| {
            if (f - f.round()).abs() < 1e-9 {
                f.round()
            } else {
                f
            }
        };
        let (fi, fj) = (snap(x.index_of(a)), snap(y.index_of(b)));
        let last_i = if wrap {
            x.len as f64
        } else {
            (x.len - 1) as f64
        };
        let inside = fi >= 0.0 && fi <= last_i && fj >= 0.0 && fj <= (y.len - 1) as f64;
        let node = grid.node_position(k);
        let in_region = node.x >= lo.x && node.x <= hi.x && node.y >= lo.y && node.y <= hi.y;
        if !inside && in_region {
            let (xmin, xmax) = x.bounds();
            let (ymin, ymax) = y.bounds();
            return Err(format!(
                "variable \"{}\": the domain's point ({:.0}, {:.0}) m lies at {a:.4}, {b:.4} \
                 outside the file's grid ({xmin} to {xmax}, {ymin} to {ymax}); give a file \
                 that covers the domain",
                layout.name, node.x, node.y
            ));
        }
        fractional.push(inside.then_some((fi, fj)));
    }
    let (mut imin, mut imax, mut jmin, mut jmax) = (usize::MAX, 0, usize::MAX, 0);
    for &(fi, fj) in fractional.iter().flatten() {
        imin = imin.min(fi.floor() as usize);
        imax = imax.max((fi.ceil() as usize).min(if wrap { x.len } else { x.len - 1 }));
        jmin = jmin.min(fj.floor() as usize);
        jmax = jmax.max((fj.ceil() as usize).min(y.len - 1));
    }
    if imin == usize::MAX {
        return Err(format!(
            "variable \"{}\": no plane node falls on the file's grid",
            layout.name
        ));
    }
    let cols = if wrap && imax >= x.len {
        0..x.len
    } else {
        imin..imax + 1
    };
    let rows = jmin..jmax + 1;
    let samples = fractional
        .iter()
        .map(|f| match f {
            // Outside the file: a cell the engine refuses floes on.
            None => Sample {
                i: u32::MAX,
                j: u32::MAX,
                fx: 0.0,
                fy: 0.0,
            },
            Some((fi, fj)) => {
                let (i, j) = (fi.floor(), fj.floor());
                Sample {
                    i: (i as usize - cols.start) as u32,
                    j: (j as usize - rows.start) as u32,
                    fx: fi - i,
                    fy: fj - j,
                }
            }
        })
        .collect();
    Ok(Component {
        layout,
        rows,
        cols,
        wrap,
        samples,
    })
}

impl Component {
    /// Reads the window at time index `t` and samples it at every node.
    /// Values beyond `limit` are refused, naming the first one found.
    fn sample(
        &self,
        file: &CfFile,
        t: usize,
        limit: Option<ValueLimit>,
        out: &mut [f64],
        stride: usize,
        offset: usize,
    ) -> Result<(), BasinError> {
        let window = file.read(&self.layout, t, self.rows.clone(), self.cols.clone())?;
        let width = self.cols.len();
        if let Some(limit) = limit {
            self.check(&window, t, limit)
                .map_err(|why| BasinError::File {
                    path: file.path().to_path_buf(),
                    why,
                })?;
        }
        let height = self.rows.len();
        let value = |i: usize, j: usize| -> f64 {
            let i = if self.wrap { i % width } else { i };
            if i >= width || j >= height {
                return f64::NAN;
            }
            window[j * width + i]
        };
        for (k, s) in self.samples.iter().enumerate() {
            out[k * stride + offset] = if s.i == u32::MAX {
                f64::NAN
            } else {
                let (i, j) = (s.i as usize, s.j as usize);
                // Only corners with weight: a node on a file node copies it
                // exactly, and a missing neighbour does not leak into it.
                let mut sum = 0.0;
                let at = CellPosition {
                    node: 0,
                    fx: s.fx,
                    fy: s.fy,
                };
                for ((di, dj), w) in [(0, 0), (1, 0), (0, 1), (1, 1)]
                    .into_iter()
                    .zip(at.weights())
                {
                    if w != 0.0 {
                        sum += w * value(i + di, j + dj);
                    }
                }
                sum
            };
        }
        Ok(())
    }
}

impl Component {
    /// The first value of the window read at time index `t` beyond `limit`,
    /// located at its file node and coordinates.
    fn check(&self, window: &[f64], t: usize, limit: ValueLimit) -> Result<(), String> {
        let Some(k) = window.iter().position(|&v| !limit.admits(v)) else {
            return Ok(());
        };
        let width = self.cols.len();
        let i = (self.cols.start + k % width) % self.layout.x.len;
        let j = self.rows.start + k / width;
        let (x, y) = (self.layout.x, self.layout.y);
        Err(format!(
            "variable \"{}\": the value {} {} at time index {t}, node ({i}, {j}) ({}, {}), is \
             beyond what {} can be on Earth (|value| <= {} {}): check the variable, its units, \
             scale_factor and _FillValue",
            self.layout.name,
            ValueLimit::shown(window[k]),
            limit.units,
            x.start + i as f64 * x.step,
            y.start + j as f64 * y.step,
            limit.what,
            limit.max_abs,
            limit.units
        ))
    }
}

impl SliceSource for NetcdfSource {
    fn describe(&self) -> &str {
        &self.describe
    }

    fn grid(&self) -> &PlaneGrid {
        &self.grid
    }

    fn components(&self) -> usize {
        self.components.len()
    }

    fn times_s(&self) -> &[f64] {
        &self.times
    }

    fn read_slice(&self, index: usize, out: &mut [f64]) -> Result<(), ForcingFailure> {
        let file = self
            .file
            .lock()
            .map_err(|_| ForcingFailure(format!("{}: reader poisoned", self.describe)))?;
        let c = self.components.len();
        let index = self.record.unwrap_or(index);
        for (k, comp) in self.components.iter().enumerate() {
            comp.sample(&file, index, self.limit, out, c, k)
                .map_err(|e| match e {
                    // Named as the field's other failures are.
                    BasinError::File { why, .. } => {
                        ForcingFailure(format!("{}: {why}", self.describe))
                    }
                    e => ForcingFailure(e.to_string()),
                })?;
        }
        if !self.east_north.is_empty() {
            for (k, (east, north)) in self.east_north.iter().enumerate() {
                let v = out[2 * k] * *east + out[2 * k + 1] * *north;
                out[2 * k] = v.x;
                out[2 * k + 1] = v.y;
            }
        }
        Ok(())
    }
}
