//! `floe render FIELDS.nc`: maps of the gridded fields `floe grid` wrote,
//! one PNG per field and record, or a movie of one field, cells coloured
//! by value (grey without ice).

use std::path::{Path, PathBuf};

use super::colour::ColourScale;
use super::floe_map::{self, FloeMap};
use super::grid_file::GridFile;
use super::movie::{self, Movie, MovieArgs, MovieWritten};
use super::{select, Snapshots};
use crate::grid_output::FIELDS;
use floe_dem::run::format_sim_time;
use floe_run::Error;

pub use super::grid_file::is_grid_file;

/// Most values a movie's colour scale is fitted to.
const SCALE_SAMPLE: usize = 4_000_000;

/// Draws every field of the selected records into `out_dir` as
/// `grid_<field>_<record>.png` (each map on a scale of its own); returns
/// the files written. `progress` hears (maps drawn, maps in all).
pub fn render_grid(
    file: &Path,
    which: Snapshots,
    out_dir: &Path,
    force: bool,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<PathBuf>, Error> {
    let grid = GridFile::open(file)?;
    let (cells, view) = grid.cells();
    let frames = select(which, grid.time.len())?;
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
    let prescribed = vec![false; cells.len()];
    let mut target = targets.iter();
    let mut drawn = 0;
    for &k in &frames {
        for (name, _, units, _) in FIELDS {
            let values = grid.field(name, k)?;
            let scale = ColourScale::fit(values.iter().flatten().copied(), diverging(name));
            let path = target.next().expect("one target per field and frame");
            floe_map::draw(
                path,
                &FloeMap {
                    title: &title(file, name, grid.time[k]),
                    polygons: &cells,
                    values: &values,
                    prescribed: &prescribed,
                    land: &prescribed,
                    scale,
                    label: &format!("{name} ({units})"),
                    view,
                },
            )?;
            drawn += 1;
            progress(drawn, targets.len());
        }
    }
    Ok(targets)
}

/// A movie of field `field` over the selected records, on one colour
/// scale for all of them.
pub fn render_grid_movie(
    file: &Path,
    which: Snapshots,
    field: &str,
    args: &MovieArgs,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<MovieWritten, Error> {
    let Some(&(name, _, units, _)) = FIELDS.iter().find(|f| f.0 == field) else {
        return Err(Error::Usage(format!(
            "--field {field}: one of {}",
            FIELDS.map(|f| f.0).join(", ")
        )));
    };
    let (target, encoding) = movie::plan(args, file)?;
    let grid = GridFile::open(file)?;
    let (cells, view) = grid.cells();
    let frames = select(which, grid.time.len())?;
    // The scale from every record (an even sample of each past
    // SCALE_SAMPLE values in all).
    let stride = (cells.len() * frames.len()).div_ceil(SCALE_SAMPLE).max(1);
    let mut sample = Vec::new();
    for &k in &frames {
        sample.extend(grid.field(name, k)?.into_iter().flatten().step_by(stride));
    }
    let scale = ColourScale::fit(sample.into_iter(), diverging(name));
    let size = encoding.frame_size(floe_map::frame_size(view));
    let mut out = Movie::create(&target, encoding, size, args.fps)?;
    let mut rgb = vec![0u8; size.0 as usize * size.1 as usize * 3];
    let prescribed = vec![false; cells.len()];
    for (i, &k) in frames.iter().enumerate() {
        let values = grid.field(name, k)?;
        let map = FloeMap {
            title: &title(file, name, grid.time[k]),
            polygons: &cells,
            values: &values,
            prescribed: &prescribed,
            land: &prescribed,
            scale,
            label: &format!("{name} ({units})"),
            view,
        };
        floe_map::draw_rgb(&map, size, &mut rgb, &target)?;
        out.push(&rgb)?;
        progress(i + 1, frames.len());
    }
    out.finish()
}

/// Signed fields get a scale centred on zero.
fn diverging(name: &str) -> bool {
    name.starts_with("stress") || name == "divergence" || name == "u" || name == "v"
}

fn title(file: &Path, name: &str, time_s: f64) -> String {
    let stem = file
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    format!("{stem}: {name}, t = {}", format_sim_time(time_s))
}
