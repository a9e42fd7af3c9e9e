//! Reading a gridded-fields file of `floe grid` (CF NetCDF) for
//! `floe render`: its coordinates, times and the fields of a record.

use std::io::Read;
use std::path::{Path, PathBuf};

use floe_io::RunFile;

use crate::grid_output::{FIELDS, FILL_VALUE};
use floe_run::Error;

/// Whether `file` is gridded fields rather than a run: a NetCDF-3 file
/// (the signature `CDF`, as floe wrote them before NetCDF-4), or an HDF5
/// file that is not a floe run file but a NetCDF file with the fields.
pub fn is_grid_file(file: &Path) -> bool {
    let mut magic = [0u8; 8];
    if std::fs::File::open(file)
        .and_then(|mut f| f.read_exact(&mut magic))
        .is_err()
    {
        return false;
    }
    if magic.starts_with(b"CDF") {
        return true;
    }
    // Run files are HDF5 too: ask floe-io first, so that a run file is
    // not opened by the NetCDF library. (floe-io fails on a NetCDF file
    // with "not a floe file", or, while the NetCDF library holds it open
    // with HDF5's file locks, with an HDF5 error.)
    magic == *b"\x89HDF\r\n\x1a\n"
        && RunFile::open(file).is_err()
        && netcdf::open(file).is_ok_and(|f| f.variable(FIELDS[0].0).is_some())
}

/// An open gridded-fields file.
pub(crate) struct GridFile {
    path: PathBuf,
    file: netcdf::File,
    /// Cell centres along x, m.
    pub(crate) x: Vec<f64>,
    /// Cell centres along y, m.
    pub(crate) y: Vec<f64>,
    /// The records' times, s.
    pub(crate) time: Vec<f64>,
}

impl GridFile {
    /// Opens `path` and reads its coordinates.
    pub(crate) fn open(path: &Path) -> Result<Self, Error> {
        let file = netcdf::open(path).map_err(|e| bad(path, e.to_string()))?;
        let mut grid = Self {
            path: path.to_path_buf(),
            file,
            x: Vec::new(),
            y: Vec::new(),
            time: Vec::new(),
        };
        grid.x = grid.read("x", None)?;
        grid.y = grid.read("y", None)?;
        grid.time = grid.read("time", None)?;
        if grid.x.len() < 2 || grid.y.len() < 2 {
            return Err(bad(path, "fewer than 2 cells along an axis".into()));
        }
        Ok(grid)
    }

    /// The cells, as outlines (row by row from the lowest y), and the
    /// region they cover, m.
    #[allow(clippy::type_complexity)]
    pub(crate) fn cells(&self) -> (Vec<Vec<(f64, f64)>>, ((f64, f64), (f64, f64))) {
        let (x, y) = (&self.x, &self.y);
        let (a, b) = (0.5 * (x[1] - x[0]), 0.5 * (y[1] - y[0]));
        let cells = y
            .iter()
            .flat_map(|&yc| {
                x.iter().map(move |&xc| {
                    vec![
                        (xc - a, yc - b),
                        (xc + a, yc - b),
                        (xc + a, yc + b),
                        (xc - a, yc + b),
                    ]
                })
            })
            .collect();
        let view = (
            (x[0] - a, x[x.len() - 1] + a),
            (y[0] - b, y[y.len() - 1] + b),
        );
        (cells, view)
    }

    /// Field `name` in record `k`, one value per cell (`None`: no ice).
    pub(crate) fn field(&self, name: &str, k: usize) -> Result<Vec<Option<f64>>, Error> {
        let values = self.read(name, Some(k))?;
        if values.len() != self.x.len() * self.y.len() {
            return Err(bad(
                &self.path,
                format!(
                    "{name} has {} values for {} x {} cells",
                    values.len(),
                    self.x.len(),
                    self.y.len()
                ),
            ));
        }
        Ok(values
            .into_iter()
            .map(|v| (v.is_finite() && v != FILL_VALUE).then_some(v))
            .collect())
    }

    /// Variable `name`, whole or (`Some(k)`) its record `k`.
    fn read(&self, name: &str, record: Option<usize>) -> Result<Vec<f64>, Error> {
        let var = self
            .file
            .variable(name)
            .ok_or_else(|| bad(&self.path, format!("no variable {name}")))?;
        match record {
            None => var.get_values::<f64, _>(..),
            Some(k) => var.get_values::<f64, _>([k..k + 1, 0..self.y.len(), 0..self.x.len()]),
        }
        .map_err(|e| bad(&self.path, format!("{name}: {e}")))
    }
}

/// A file that is not what `floe grid` writes: bad input.
fn bad(path: &Path, why: String) -> Error {
    Error::Usage(format!(
        "{}: not a gridded-fields file of `floe grid` ({why})",
        path.display()
    ))
}
