//! Reading CF-convention NetCDF (ERA5, CMEMS, MOM6 output; NetCDF-3 and
//! NetCDF-4) through the `netcdf` crate: a variable's horizontal axes
//! (projected x/y in metres or kilometres, or longitude/latitude in
//! degrees), its time axis in seconds of model time, and 2-D slices with
//! `scale_factor`, `add_offset`, `_FillValue` and `missing_value` applied
//! (missing values become NaN). Every error names the file and variable.
//!
//! Axes are recognised by their coordinate variable (a variable named as
//! the dimension): `axis` = X/Y/T, or `standard_name` (longitude, latitude,
//! projection_x_coordinate, projection_y_coordinate, time), or `units`
//! (degrees_east, degrees_north, `<unit> since <date>`). Horizontal axes
//! must be regular (uniform spacing, either direction). Any other
//! dimension (a depth level) must have length one.
//!
//! A damaged file ends in an error naming it, never a crash: a NetCDF-3
//! file cut short is refused from its header ([`crate::classic_header`]),
//! and every call into the library is guarded ([`crate::native_guard`]:
//! the `netcdf` crate's panics on the library's errors are caught; a crash
//! or a hang of HDF5 prints the file's message and ends the process).

use std::ops::Range;
use std::path::{Path, PathBuf};

use crate::cf_time::offset_and_unit;
use crate::classic_header::{extent, Extent};
use crate::error::BasinError;
use crate::native_guard::{guarded, CrashReport};

/// Relative tolerance of a regular axis's spacing.
const REGULAR_TOLERANCE: f64 = 1e-6;

/// Values this large are NetCDF's default fill values (`NC_FILL_FLOAT`,
/// `NC_FILL_DOUBLE` are 9.969e36), never data.
const NETCDF_DEFAULT_FILL_FLOOR: f64 = 9.9e36;

/// What a horizontal axis measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisKind {
    /// Projected x, m.
    X,
    /// Projected y, m.
    Y,
    /// Longitude, degrees east.
    Longitude,
    /// Latitude, degrees north.
    Latitude,
}

/// A regular axis: value `start + k step`, `k < len` (`step` may be negative).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RegularAxis {
    /// What it measures.
    pub kind: AxisKind,
    /// The first value (m or degrees).
    pub start: f64,
    /// The spacing (m or degrees), nonzero.
    pub step: f64,
    /// Number of values, `≥ 2`.
    pub len: usize,
}

impl RegularAxis {
    /// The fractional index of `value` (may lie outside `[0, len − 1]`).
    pub fn index_of(&self, value: f64) -> f64 {
        (value - self.start) / self.step
    }

    /// The smallest and largest values.
    pub fn bounds(&self) -> (f64, f64) {
        let end = self.start + (self.len - 1) as f64 * self.step;
        (self.start.min(end), self.start.max(end))
    }
}

/// A variable's place in a file: the axes of its last two dimensions and
/// which dimension is time.
#[derive(Debug, Clone)]
pub struct VariableLayout {
    /// The variable's name.
    pub name: String,
    /// Along the last dimension.
    pub x: RegularAxis,
    /// Along the second-to-last dimension.
    pub y: RegularAxis,
    /// Position of the time dimension, if any.
    pub time_dim: Option<usize>,
    /// Number of dimensions.
    pub rank: usize,
    /// Multiplier and offset of packed values.
    pub scale: f64,
    /// Added after scaling.
    pub offset: f64,
    /// Raw values meaning "no value".
    pub missing: Vec<f64>,
}

/// Longest variable name of a NetCDF file, bytes (`NC_MAX_NAME`).
const MAX_NAME_BYTES: usize = 256;

/// An open CF NetCDF file.
pub struct CfFile {
    path: PathBuf,
    file: netcdf::File,
    /// What a crash or hang of the library prints while reading metadata
    /// (exit code 2: before the run) and slices (exit code 1: during it).
    metadata_crash: CrashReport,
    read_crash: CrashReport,
}

impl std::fmt::Debug for CfFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "CfFile({})", self.path.display())
    }
}

fn attr_f64(v: &netcdf::Variable<'_>, name: &str) -> Option<f64> {
    let value = v.attribute_value(name)?.ok()?;
    use netcdf::AttributeValue as A;
    Some(match value {
        A::Double(x) => x,
        A::Float(x) => x as f64,
        A::Doubles(x) => *x.first()?,
        A::Floats(x) => *x.first()? as f64,
        A::Short(x) => x as f64,
        A::Int(x) => x as f64,
        A::Schar(x) => x as f64,
        A::Uchar(x) => x as f64,
        A::Ushort(x) => x as f64,
        A::Uint(x) => x as f64,
        A::Longlong(x) => x as f64,
        A::Ulonglong(x) => x as f64,
        _ => return None,
    })
}

fn attr_str(v: &netcdf::Variable<'_>, name: &str) -> Option<String> {
    match v.attribute_value(name)?.ok()? {
        netcdf::AttributeValue::Str(s) => Some(s.trim().to_string()),
        _ => None,
    }
}

impl CfFile {
    /// Opens `path`.
    ///
    /// # Errors
    /// [`BasinError::File`] when it is missing, not a regular file, cut
    /// short or not NetCDF.
    pub fn open(path: &Path) -> Result<Self, BasinError> {
        Self::open_located(path, "")
    }

    /// Opens `path`; `context` (`scenario.toml:12:8: \`wind.file\`: `)
    /// begins the message printed if the library crashes or hangs on the
    /// file, which names the file after it.
    ///
    /// # Errors
    /// As [`CfFile::open`].
    pub fn open_located(path: &Path, context: &str) -> Result<Self, BasinError> {
        let error = |why: String| BasinError::File {
            path: path.to_path_buf(),
            why,
        };
        match std::fs::metadata(path) {
            Ok(m) if m.is_file() => {
                let len = m.len();
                match extent(path) {
                    Ok(Extent::HeaderCut) => {
                        return Err(error(
                            "is cut short: its NetCDF-3 header ends before it is complete \
                             (an interrupted copy or download?)"
                                .to_string(),
                        ))
                    }
                    Ok(Extent::AtLeast(need)) if need > len => {
                        return Err(error(format!(
                            "is cut short: its NetCDF-3 header places data up to byte {need}, \
                             but the file has {len} bytes (an interrupted copy or download?)"
                        )))
                    }
                    Ok(_) => {}
                    Err(e) => return Err(error(format!("cannot read it: {e}"))),
                }
            }
            Ok(_) => {
                return Err(error(
                    "is not a regular file (a directory or a device); name a NetCDF file"
                        .to_string(),
                ))
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                return Err(error("no such file".to_string()))
            }
            Err(e) => return Err(error(format!("cannot read it: {e}"))),
        }
        let head = format!("error: {context}{}: the NetCDF library", path.display());
        let metadata_crash = CrashReport {
            head: head.clone(),
            exit_code: 2,
        };
        // NetCDF-4 files are HDF5: the library's own failed probes (an
        // attribute that is not there) must not print HDF5 diagnostics.
        hdf5::silence_errors(true);
        let file = guarded(&metadata_crash, || netcdf::open(path))
            .map_err(|panic| error(library_failure(&panic)))?
            .map_err(|e| error(format!("not a NetCDF file that can be read ({e})")))?;
        Ok(CfFile {
            path: path.to_path_buf(),
            file,
            metadata_crash,
            read_crash: CrashReport { head, exit_code: 1 },
        })
    }

    /// Runs `f` (calls into the library) guarded: a panic of the `netcdf`
    /// crate becomes an error naming the file.
    fn guard<R>(
        &self,
        crash: &CrashReport,
        f: impl FnOnce() -> Result<R, BasinError>,
    ) -> Result<R, BasinError> {
        guarded(crash, f).map_err(|panic| self.error(library_failure(&panic)))?
    }

    /// The file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn error(&self, why: String) -> BasinError {
        BasinError::File {
            path: self.path.clone(),
            why,
        }
    }

    fn variable(&self, name: &str) -> Result<netcdf::Variable<'_>, BasinError> {
        // The `netcdf` crate panics on such names.
        if name.contains('\0') || name.len() > MAX_NAME_BYTES {
            return Err(self.error(format!(
                "no variable \"{}\" (a NetCDF name has at most {MAX_NAME_BYTES} bytes and no NUL)",
                crate::error::shown(name)
            )));
        }
        self.file.variable(name).ok_or_else(|| {
            let mut names: Vec<String> = self.file.variables().map(|v| v.name()).collect();
            names.sort();
            self.error(format!(
                "no variable \"{}\"; the file has: {}",
                crate::error::shown(name),
                crate::error::shown(&names.join(", "))
            ))
        })
    }

    /// The coordinate values of dimension `dim` (its coordinate variable),
    /// with the variable for its attributes.
    fn coordinate(
        &self,
        var: &str,
        dim: &str,
    ) -> Result<(Vec<f64>, netcdf::Variable<'_>), BasinError> {
        let c = self.file.variable(dim).ok_or_else(|| {
            self.error(format!(
                "variable \"{var}\": its dimension \"{dim}\" has no coordinate variable \
                 (a variable named \"{dim}\" giving its values)"
            ))
        })?;
        let values: Vec<f64> = c
            .get_values::<f64, _>(..)
            .map_err(|e| self.error(format!("coordinate \"{dim}\": {e}")))?;
        Ok((values, c))
    }

    /// The layout of variable `name`: horizontal axes, time dimension,
    /// packing and missing values.
    ///
    /// # Errors
    /// A missing variable, fewer than two dimensions, an unrecognised or
    /// irregular horizontal axis, two time dimensions, another dimension
    /// longer than one.
    pub fn layout(&self, name: &str) -> Result<VariableLayout, BasinError> {
        self.guard(&self.metadata_crash, || self.layout_unguarded(name))
    }

    fn layout_unguarded(&self, name: &str) -> Result<VariableLayout, BasinError> {
        let v = self.variable(name)?;
        let dims: Vec<(String, usize)> =
            v.dimensions().iter().map(|d| (d.name(), d.len())).collect();
        let rank = dims.len();
        if rank < 2 {
            return Err(self.error(format!(
                "variable \"{name}\" has {rank} dimension(s); a field needs (y, x) or (time, y, x)"
            )));
        }
        let mut time_dim = None;
        for (k, (dim, len)) in dims[..rank - 2].iter().enumerate() {
            let is_time = match self.file.variable(dim) {
                Some(c) => is_time_coordinate(&c),
                None => false,
            };
            if is_time && time_dim.is_none() {
                time_dim = Some(k);
            } else if *len != 1 {
                return Err(self.error(format!(
                    "variable \"{name}\": dimension \"{dim}\" has {len} values; floe reads one \
                     level only (select it first, e.g. `ncks -d {dim},0`)"
                )));
            }
        }
        let x = self.horizontal_axis(name, &dims[rank - 1].0, true)?;
        let y = self.horizontal_axis(name, &dims[rank - 2].0, false)?;
        let geographic = |k: AxisKind| matches!(k, AxisKind::Longitude | AxisKind::Latitude);
        if geographic(x.kind) != geographic(y.kind) || x.kind == y.kind {
            return Err(self.error(format!(
                "variable \"{name}\": its last two dimensions are {:?} and {:?}; floe needs \
                 (latitude, longitude) or (y, x)",
                y.kind, x.kind
            )));
        }
        let mut missing = Vec::new();
        for key in ["_FillValue", "missing_value"] {
            if let Some(m) = attr_f64(&v, key) {
                missing.push(m);
            }
        }
        Ok(VariableLayout {
            name: name.to_string(),
            x,
            y,
            time_dim,
            rank,
            scale: attr_f64(&v, "scale_factor").unwrap_or(1.0),
            offset: attr_f64(&v, "add_offset").unwrap_or(0.0),
            missing,
        })
    }

    fn horizontal_axis(&self, var: &str, dim: &str, last: bool) -> Result<RegularAxis, BasinError> {
        let (values, c) = self.coordinate(var, dim)?;
        let axis = attr_str(&c, "axis").unwrap_or_default().to_uppercase();
        let standard = attr_str(&c, "standard_name").unwrap_or_default();
        let units = attr_str(&c, "units").unwrap_or_default();
        let (kind, to_si) = if standard == "longitude"
            || units.starts_with("degrees_east")
            || units == "degree_east"
        {
            (AxisKind::Longitude, Some(1.0))
        } else if standard == "latitude"
            || units.starts_with("degrees_north")
            || units == "degree_north"
        {
            (AxisKind::Latitude, Some(1.0))
        } else if standard == "projection_x_coordinate"
            || axis == "X"
            || (last && is_length(&units))
        {
            (AxisKind::X, length_to_m(&units))
        } else if standard == "projection_y_coordinate"
            || axis == "Y"
            || (!last && is_length(&units))
        {
            (AxisKind::Y, length_to_m(&units))
        } else {
            return Err(self.error(format!(
                "variable \"{var}\": cannot tell what its dimension \"{dim}\" measures \
                 (units \"{units}\", standard_name \"{standard}\"); floe reads longitude/latitude \
                 (degrees_east/degrees_north) or projected x/y (units m or km)"
            )));
        };
        let to_si = to_si.ok_or_else(|| {
            self.error(format!(
                "coordinate \"{dim}\": units \"{units}\"; projected coordinates must be in m or km"
            ))
        })?;
        let values: Vec<f64> = values.iter().map(|v| v * to_si).collect();
        regular(&values)
            .ok_or_else(|| {
                self.error(format!(
                    "coordinate \"{dim}\" is not regularly spaced (or has fewer than two values); \
                 floe reads regular grids (regrid first, e.g. with cdo remapbil)"
                ))
            })
            .map(|(start, step)| RegularAxis {
                kind,
                start,
                step,
                len: values.len(),
            })
    }

    /// The times of the time dimension of the variable laid out as
    /// `layout` ([`CfFile::layout`]) as seconds after
    /// `start` (`"YYYY-MM-DD HH:MM:SS"`, read in the file's calendar), or
    /// `None` for a variable without time.
    ///
    /// # Errors
    /// Time units that are not `<unit> since <date>`, an unknown calendar,
    /// a missing `start` for a file with dates, times not increasing.
    pub fn times_s(
        &self,
        layout: &VariableLayout,
        start: Option<&str>,
    ) -> Result<Option<Vec<f64>>, BasinError> {
        self.guard(&self.metadata_crash, || self.times_unguarded(layout, start))
    }

    fn times_unguarded(
        &self,
        layout: &VariableLayout,
        start: Option<&str>,
    ) -> Result<Option<Vec<f64>>, BasinError> {
        let name = layout.name.as_str();
        let Some(k) = layout.time_dim else {
            return Ok(None);
        };
        let v = self.variable(name)?;
        let dim = v.dimensions()[k].name();
        let (values, c) = self.coordinate(name, &dim)?;
        let units = attr_str(&c, "units").unwrap_or_default();
        let calendar = attr_str(&c, "calendar").unwrap_or_else(|| "standard".to_string());
        let start = start.ok_or_else(|| {
            self.error(format!(
                "time \"{dim}\" is in \"{units}\": give the scenario's `start_time` \
                 (e.g. start_time = \"2024-03-01 00:00:00\"), the date of model time 0"
            ))
        })?;
        let (offset, unit) = offset_and_unit(&units, &calendar, start)
            .map_err(|e| self.error(format!("time \"{dim}\": {e}")))?;
        let out: Vec<f64> = values.iter().map(|&t| offset + t * unit).collect();
        if out.windows(2).any(|w| w[1] <= w[0]) {
            return Err(self.error(format!("time \"{dim}\" does not increase strictly")));
        }
        Ok(Some(out))
    }

    /// The number of time records of the variable laid out as `layout`:
    /// the length of its time dimension, 1 without one.
    ///
    /// # Errors
    /// The variable no longer readable.
    pub fn records(&self, layout: &VariableLayout) -> Result<usize, BasinError> {
        let Some(k) = layout.time_dim else {
            return Ok(1);
        };
        Ok(self.variable(&layout.name)?.dimensions()[k].len())
    }

    /// The values of `layout` at time index `time` (ignored without a time
    /// dimension) over rows `rows` (y) and columns `cols` (x), row-major,
    /// unpacked, NaN where missing.
    ///
    /// # Errors
    /// A failed read, naming the file and variable.
    pub fn read(
        &self,
        layout: &VariableLayout,
        time: usize,
        rows: Range<usize>,
        cols: Range<usize>,
    ) -> Result<Vec<f64>, BasinError> {
        self.guard(&self.read_crash, || {
            self.read_unguarded(layout, time, rows, cols)
        })
    }

    fn read_unguarded(
        &self,
        layout: &VariableLayout,
        time: usize,
        rows: Range<usize>,
        cols: Range<usize>,
    ) -> Result<Vec<f64>, BasinError> {
        let v = self.variable(&layout.name)?;
        let mut extents: Vec<Range<usize>> = Vec::with_capacity(layout.rank);
        for k in 0..layout.rank - 2 {
            extents.push(if Some(k) == layout.time_dim {
                time..time + 1
            } else {
                0..1
            });
        }
        extents.push(rows);
        extents.push(cols);
        let raw: Vec<f64> = v.get_values::<f64, _>(extents).map_err(|e| {
            self.error(format!(
                "variable \"{}\": reading time index {time}: {e}",
                layout.name
            ))
        })?;
        Ok(raw
            .into_iter()
            .map(|r| {
                // NetCDF's default fills (9.97e36) count as missing too.
                let filled = r.abs() >= NETCDF_DEFAULT_FILL_FLOOR
                    || layout
                        .missing
                        .iter()
                        .any(|&m| r == m || (r as f32) == (m as f32));
                if !r.is_finite() || filled {
                    f64::NAN
                } else {
                    r * layout.scale + layout.offset
                }
            })
            .collect())
    }

    /// A text attribute of variable `name` (`standard_name`, `units`);
    /// `None` also when the library cannot give it back.
    pub fn text_attribute(&self, name: &str, attribute: &str) -> Option<String> {
        self.guard(&self.metadata_crash, || {
            Ok(self
                .variable(name)
                .ok()
                .and_then(|v| attr_str(&v, attribute)))
        })
        .ok()
        .flatten()
    }
}

/// Why the library failed, from the `netcdf` crate's panic (which unwraps
/// the library's error code).
fn library_failure(panic: &str) -> String {
    let code = panic
        .find("Netcdf(")
        .and_then(|i| panic[i + "Netcdf(".len()..].split(')').next())
        .and_then(|c| c.trim().parse::<i32>().ok());
    let detail = match code {
        Some(c) => netcdf::Error::Netcdf(c).to_string(),
        None => crate::error::shown(panic),
    };
    format!("the NetCDF library failed reading it ({detail}): the file is damaged")
}

fn is_time_coordinate(c: &netcdf::Variable<'_>) -> bool {
    attr_str(c, "axis").is_some_and(|a| a.eq_ignore_ascii_case("T"))
        || attr_str(c, "standard_name").is_some_and(|s| s == "time")
        || attr_str(c, "units").is_some_and(|u| u.contains(" since "))
}

fn is_length(units: &str) -> bool {
    length_to_m(units).is_some()
}

fn length_to_m(units: &str) -> Option<f64> {
    match units {
        "m" | "meter" | "meters" | "metre" | "metres" => Some(1.0),
        "km" | "kilometer" | "kilometers" | "kilometre" | "kilometres" => Some(1000.0),
        _ => None,
    }
}

/// `(start, step)` of evenly spaced `values`, or `None`.
fn regular(values: &[f64]) -> Option<(f64, f64)> {
    let n = values.len();
    if n < 2 || values.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let step = (values[n - 1] - values[0]) / (n - 1) as f64;
    if step == 0.0 {
        return None;
    }
    let ok = values.iter().enumerate().all(|(k, &v)| {
        (v - (values[0] + k as f64 * step)).abs() <= REGULAR_TOLERANCE * step.abs() * (n as f64)
    });
    ok.then_some((values[0], step))
}

#[cfg(test)]
mod tests {
    use super::regular;

    #[test]
    fn regular_axes_are_told_from_irregular_ones() {
        assert_eq!(regular(&[0.0, 0.25, 0.5, 0.75]), Some((0.0, 0.25)));
        assert_eq!(regular(&[90.0, 89.75, 89.5]), Some((90.0, -0.25)));
        assert_eq!(regular(&[0.0, 1.0, 3.0]), None);
        assert_eq!(regular(&[1.0]), None);
    }
}
