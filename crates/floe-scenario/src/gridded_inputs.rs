//! The scenario's basin inputs: `[map] projection`, `start_time`, and wind,
//! current and sea-surface height read from CF NetCDF files (`file` and
//! `variables` in `[wind]` and `[ocean]`). Files are opened here, so a
//! missing variable or a grid that misses the domain is reported at the
//! key, with the file's own message. Each field keeps its key
//! (`GriddedOrigin`): times that do not cover the run are refused at it
//! once the time step is known, and a field's failures at the start or
//! during the run are located at it too (as is the message printed if the
//! NetCDF library crashes on the file).

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use floe_basin::{FieldRequest, MapProjection, NetcdfSource, ValueLimit};
use floe_dem::forcing::{GriddedField, VelocityField};

use crate::domain::Domain;
use crate::error::ScenarioError;
use crate::source_file::SourceFile;
use crate::spec::RawFluid;

/// How far beyond the domain, as a fraction of its larger side, gridded
/// fields reach where their files have data: floes that stray out of an
/// open domain stay on the grid.
pub const PLANE_MARGIN_FRACTION: f64 = 0.25;

/// A file the run reads besides the scenario: what it is for and where it is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InputFile {
    /// What it gives (`wind`, `ocean`, `ocean.sea_surface_height`...).
    pub role: String,
    /// Its path (relative ones resolved against the scenario's directory).
    pub path: PathBuf,
}

/// Longest input path (`file` value) accepted, bytes: messages quote it.
pub const MAX_INPUT_PATH_BYTES: usize = 512;

/// What the gridded fields of a scenario need to know.
pub(crate) struct GridContext<'a> {
    pub projection: Option<&'a MapProjection>,
    pub start_time: Option<String>,
    pub region: Domain,
    /// Where relative paths start.
    pub base_dir: PathBuf,
    /// The files opened so far.
    pub inputs: Vec<InputFile>,
    /// The fields opened so far, with their keys.
    pub origins: Vec<GriddedOrigin>,
}

/// Where a gridded field came from, to locate its failures at its key.
#[derive(Debug, Clone)]
pub(crate) struct GriddedOrigin {
    /// The field's description, which begins each of its failures.
    pub describe: String,
    /// The key naming its file, and where it is.
    pub key: String,
    pub span: Range<usize>,
    /// The field's times, s of model time (one for a steady field).
    pub times_s: Vec<f64>,
}

/// A path as written, relative to `base_dir` (the scenario's directory).
pub(crate) fn input_path(base_dir: &Path, written: &str) -> PathBuf {
    let p = Path::new(written);
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        base_dir.join(p)
    }
}

/// A `file` value (`kind`: "NetCDF", "GeoJSON") that can name a file:
/// not blank, without a NUL, at most [`MAX_INPUT_PATH_BYTES`] long.
pub(crate) fn check_file_value(
    f: &SourceFile,
    written: &str,
    span: Range<usize>,
    key: &str,
    kind: &str,
) -> Result<(), ScenarioError> {
    let why = if written.trim().is_empty() {
        format!("is empty: name a {kind} file")
    } else if written.contains('\0') {
        "holds a NUL character, which no file name can".to_string()
    } else if written.len() > MAX_INPUT_PATH_BYTES {
        format!(
            "is a path of {} bytes; input paths may have at most {MAX_INPUT_PATH_BYTES}",
            written.len()
        )
    } else {
        return Ok(());
    };
    Err(f.error(span, key, why))
}

/// The end of a located message for `key` at `span`
/// (`scenario.toml:12:8: \`wind.file\`: `), to begin another with.
fn location(f: &SourceFile, span: Range<usize>, key: &str) -> String {
    f.error(span, key, "").to_string()
}

/// Refuses fields whose times do not cover the run, from model time 0 to
/// `end_s`, at their keys (the run would stop when it got there).
pub(crate) fn check_times_cover_run(
    f: &SourceFile,
    origins: &[GriddedOrigin],
    end_s: f64,
) -> Result<(), ScenarioError> {
    for o in origins {
        let (Some(&first), Some(&last)) = (o.times_s.first(), o.times_s.last()) else {
            continue;
        };
        if o.times_s.len() < 2 || (first <= 0.0 && end_s <= last) {
            continue;
        }
        // Whole seconds once they are long (a date decades from start_time).
        let s = |t: f64| {
            if t.abs() >= 1e4 {
                format!("{t:.0}")
            } else {
                crate::numbers::sig(t)
            }
        };
        return Err(f.error(
            o.span.clone(),
            &o.key,
            format!(
                "{}: the run goes from 0 to {} s of model time (seconds after start_time) but \
                 the file's times cover {} s to {} s; give a file that covers the run, or a \
                 shorter duration_s",
                o.describe,
                s(end_s),
                s(first),
                s(last)
            ),
        ));
    }
    Ok(())
}

/// `message` (a forcing failure) located at the key of the field it is
/// about, when it begins with one's description.
pub(crate) fn locate_failure(
    f: &SourceFile,
    origins: &[GriddedOrigin],
    message: &str,
) -> Option<ScenarioError> {
    let o = origins
        .iter()
        .find(|o| message.starts_with(&format!("{}: ", o.describe)))?;
    Some(f.error(o.span.clone(), &o.key, message))
}

fn open_field(
    f: &SourceFile,
    ctx: &mut GridContext<'_>,
    (path, span, key): (PathBuf, Range<usize>, String),
    variables: &[&str],
    plane_spacing_m: Option<f64>,
    limit: ValueLimit,
) -> Result<GriddedField, ScenarioError> {
    let d = ctx.region;
    let request = FieldRequest {
        path: &path,
        variables,
        projection: ctx.projection,
        start_time: ctx.start_time.as_deref(),
        region: (d.min_m, d.min_m + d.size_m),
        plane_spacing_m,
        margin_m: PLANE_MARGIN_FRACTION * d.size_m.x.max(d.size_m.y),
        limit: Some(limit),
    };
    let context = location(f, span.clone(), &key);
    let source = NetcdfSource::open_located(request, &context)
        .map_err(|e| f.error(span.clone(), &key, e.to_string()))?;
    let field = GriddedField::new(Arc::new(source))
        .map_err(|e| f.error(span.clone(), &key, e.to_string()))?;
    ctx.inputs.push(InputFile {
        role: key.trim_end_matches(".file").to_string(),
        path,
    });
    ctx.origins.push(GriddedOrigin {
        describe: field.describe().to_string(),
        key,
        span,
        times_s: field.times_s().to_vec(),
    });
    Ok(field)
}

/// The gridded velocity of `[table]` if it names a `file`.
pub(crate) fn resolve_gridded_velocity(
    f: &SourceFile,
    raw: &RawFluid,
    table: &str,
    ctx: &mut GridContext<'_>,
) -> Result<Option<VelocityField>, ScenarioError> {
    let Some(file) = &raw.file else {
        if let Some(v) = &raw.variables {
            return Err(f.error(
                v.span(),
                format!("{table}.variables"),
                "needs `file`, the NetCDF file they are in",
            ));
        }
        return Ok(None);
    };
    let Some(vars) = &raw.variables else {
        return Err(f.error(
            file.span(),
            format!("{table}.file"),
            "needs `variables = [\"u\", \"v\"]`: the x (or eastward) and y (or northward) \
             components in the file, m/s",
        ));
    };
    if vars.get_ref().len() != 2 {
        return Err(f.error(
            vars.span(),
            format!("{table}.variables"),
            format!(
                "give two variables (x or east, y or north), got {}",
                vars.get_ref().len()
            ),
        ));
    }
    let spacing = match &raw.plane_spacing_m {
        Some(s) => Some(f.positive(s, &format!("{table}.plane_spacing_m"))?),
        None => None,
    };
    let names: Vec<&str> = vars.get_ref().iter().map(String::as_str).collect();
    check_file_value(
        f,
        file.get_ref(),
        file.span(),
        &format!("{table}.file"),
        "NetCDF",
    )?;
    let path = input_path(&ctx.base_dir, file.get_ref());
    let field = open_field(
        f,
        ctx,
        (path, file.span(), format!("{table}.file")),
        &names,
        spacing,
        if table == "wind" {
            ValueLimit::WIND
        } else {
            ValueLimit::CURRENT
        },
    )?;
    Ok(Some(VelocityField::Gridded(Box::new(field))))
}

/// `[ocean] sea_surface_height = { variable, file }`.
pub(crate) fn resolve_sea_surface_height(
    f: &SourceFile,
    raw: &RawFluid,
    ctx: &mut GridContext<'_>,
) -> Result<Option<GriddedField>, ScenarioError> {
    let Some(eta) = &raw.sea_surface_height else {
        return Ok(None);
    };
    let r = eta.get_ref();
    let written =
        match (&r.file, &raw.file) {
            (Some(p), _) => p.clone(),
            (None, Some(p)) => p.get_ref().clone(),
            (None, None) => return Err(f.error(
                eta.span(),
                "ocean.sea_surface_height",
                "needs `file` (or the [ocean] table's `file`): the NetCDF file of the height, m",
            )),
        };
    let spacing = match &raw.plane_spacing_m {
        Some(s) => Some(f.positive(s, "ocean.plane_spacing_m")?),
        None => None,
    };
    check_file_value(
        f,
        &written,
        eta.span(),
        "ocean.sea_surface_height",
        "NetCDF",
    )?;
    let path = input_path(&ctx.base_dir, &written);
    open_field(
        f,
        ctx,
        (path, eta.span(), "ocean.sea_surface_height".to_string()),
        &[r.variable.as_str()],
        spacing,
        ValueLimit::SEA_SURFACE_HEIGHT,
    )
    .map(Some)
}
