//! `floe render FIELDS.nc`: maps of the gridded fields `floe grid` wrote,
//! one PNG per field and record, cells coloured by value (grey without ice).

use std::path::{Path, PathBuf};

use netcdf3::{DataVector, FileReader, NC_FILL_F64};

use super::colour::ColourScale;
use super::floe_map::{self, FloeMap};
use super::{select, Snapshots};
use crate::error::Error;
use crate::grid_output::FIELDS;
use floe_dem::run::format_sim_time;

/// Whether `file` starts with the NetCDF-3 signature.
pub fn is_netcdf(file: &Path) -> bool {
    use std::io::Read;
    let mut magic = [0u8; 3];
    std::fs::File::open(file)
        .and_then(|mut f| f.read_exact(&mut magic))
        .is_ok()
        && &magic == b"CDF"
}

/// Draws every field of the selected records into `out_dir` as
/// `grid_<field>_<record>.png`; returns the files written.
pub fn render_grid(
    file: &Path,
    which: Snapshots,
    out_dir: &Path,
    force: bool,
) -> Result<Vec<PathBuf>, Error> {
    let bad = |why: String| {
        Error::Usage(format!(
            "{}: not a gridded-fields file of `floe grid` ({why})",
            file.display()
        ))
    };
    let mut reader = FileReader::open(file).map_err(|e| bad(format!("{e:?}")))?;
    let mut f64s = |name: &str, record: Option<usize>| -> Result<Vec<f64>, Error> {
        let data = match record {
            Some(k) => reader.read_record(name, k),
            None => reader.read_var(name),
        }
        .map_err(|e| bad(format!("{name}: {e:?}")))?;
        match data {
            DataVector::F64(v) => Ok(v),
            _ => Err(bad(format!("{name} is not f64"))),
        }
    };
    let (x, y, time) = (f64s("x", None)?, f64s("y", None)?, f64s("time", None)?);
    if x.len() < 2 || y.len() < 2 {
        return Err(bad("fewer than 2 cells along an axis".into()));
    }
    let (dx, dy) = (x[1] - x[0], y[1] - y[0]);
    let cells: Vec<Vec<(f64, f64)>> = y
        .iter()
        .flat_map(|&yc| {
            x.iter().map(move |&xc| {
                let (a, b) = (0.5 * dx, 0.5 * dy);
                vec![
                    (xc - a, yc - b),
                    (xc + a, yc - b),
                    (xc + a, yc + b),
                    (xc - a, yc + b),
                ]
            })
        })
        .collect();
    let frames = select(which, time.len())?;
    let mut targets = Vec::new();
    for &k in &frames {
        for (name, ..) in FIELDS {
            targets.push(out_dir.join(format!("grid_{name}_{k:04}.png")));
        }
    }
    if !force {
        if let Some(existing) = targets.iter().find(|p| p.exists()) {
            return Err(Error::WouldOverwrite(existing.clone()));
        }
    }
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    let view = (
        (x[0] - 0.5 * dx, x[x.len() - 1] + 0.5 * dx),
        (y[0] - 0.5 * dy, y[y.len() - 1] + 0.5 * dy),
    );
    let stem = file
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let prescribed = vec![false; cells.len()];
    let mut target = targets.iter();
    for &k in &frames {
        for (name, _, units, _) in FIELDS {
            let values: Vec<Option<f64>> = f64s(name, Some(k))?
                .into_iter()
                .map(|v| (v.is_finite() && v != NC_FILL_F64).then_some(v))
                .collect();
            if values.len() != cells.len() {
                return Err(bad(format!(
                    "{name} has {} values for {} cells",
                    values.len(),
                    cells.len()
                )));
            }
            let diverging =
                name.starts_with("stress") || name == "divergence" || name == "u" || name == "v";
            let scale = ColourScale::fit(values.iter().flatten().copied(), diverging);
            let title = format!("{stem}: {name}, t = {}", format_sim_time(time[k]));
            let label = format!("{name} ({units})");
            let path = target.next().expect("one target per field and frame");
            floe_map::draw(
                path,
                &FloeMap {
                    title: &title,
                    polygons: &cells,
                    values: &values,
                    prescribed: &prescribed,
                    land: &prescribed,
                    scale,
                    label: &label,
                    view,
                },
            )?;
        }
    }
    Ok(targets)
}
