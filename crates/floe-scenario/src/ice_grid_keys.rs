//! `[ice] concentration_grid` and `thickness_grid`: which NetCDF file and
//! variable give the initial ice, checked where they are written. The
//! files are opened when the scenario is built (`ice_grid.rs`); a resumed
//! run takes its floes from the checkpoint.

use std::ops::Range;
use std::path::PathBuf;

use floe_basin::ConcentrationUnits;
use toml::Spanned;

use crate::error::ScenarioError;
use crate::source_file::SourceFile;
use crate::spec::{RawGridField, RawIce};

/// Most records a `time_index` may name (a decade of hourly fields).
pub const MAX_TIME_INDEX: u64 = 1_000_000;

/// One gridded field of the initial ice.
#[derive(Debug, Clone)]
pub(crate) struct GridField {
    /// The file, relative paths taken from the scenario file's directory.
    pub path: PathBuf,
    /// The path as written, for the report.
    pub written: String,
    pub variable: String,
    pub time_index: Option<usize>,
    /// Units stated in the scenario (concentration only).
    pub units: Option<ConcentrationUnits>,
    /// Where the table is, and its key (`ice.concentration_grid`).
    pub span: Range<usize>,
    pub key: &'static str,
}

/// The gridded fields of `[ice]`.
#[derive(Debug, Clone, Default)]
pub(crate) struct IceGrids {
    pub concentration: Option<GridField>,
    pub thickness: Option<GridField>,
}

impl IceGrids {
    /// Whether any field is given.
    pub(crate) fn any(&self) -> bool {
        self.concentration.is_some() || self.thickness.is_some()
    }

    /// The first field given (for messages about both).
    pub(crate) fn first(&self) -> Option<&GridField> {
        self.concentration.as_ref().or(self.thickness.as_ref())
    }
}

/// Reads `[ice]`'s grid keys.
pub(crate) fn resolve_ice_grids(
    f: &SourceFile,
    ice: Option<&Spanned<RawIce>>,
    base_dir: &std::path::Path,
) -> Result<IceGrids, ScenarioError> {
    let Some(ice) = ice else {
        return Ok(IceGrids::default());
    };
    let ice = ice.get_ref();
    Ok(IceGrids {
        concentration: ice
            .concentration_grid
            .as_ref()
            .map(|g| grid_field(f, g, "ice.concentration_grid", true, base_dir))
            .transpose()?,
        thickness: ice
            .thickness_grid
            .as_ref()
            .map(|g| grid_field(f, g, "ice.thickness_grid", false, base_dir))
            .transpose()?,
    })
}

fn grid_field(
    f: &SourceFile,
    raw: &Spanned<RawGridField>,
    key: &'static str,
    concentration: bool,
    base_dir: &std::path::Path,
) -> Result<GridField, ScenarioError> {
    let g = raw.get_ref();
    let text = |w: &Option<Spanned<String>>, name: &str| -> Result<String, ScenarioError> {
        let Some(w) = w else {
            return Err(f.error(
                raw.span(),
                format!("{key}.{name}"),
                format!(
                    "missing: a grid needs `file` (a NetCDF file) and `variable` (its name \
                     there), e.g. {{ file = \"{}.nc\", variable = \"{}\" }}",
                    if concentration { "siconc" } else { "sithick" },
                    if concentration { "siconc" } else { "sithick" }
                ),
            ));
        };
        let s = w.get_ref().trim();
        if s.is_empty() {
            return Err(f.error(w.span(), format!("{key}.{name}"), "must not be empty"));
        }
        Ok(s.to_string())
    };
    let written = text(&g.file, "file")?;
    let variable = text(&g.variable, "variable")?;
    let time_index = match &g.time_index {
        Some(t) => {
            let k = *t.get_ref();
            if !(0..=MAX_TIME_INDEX as i64).contains(&k) {
                return Err(f.error(
                    t.span(),
                    format!("{key}.time_index"),
                    format!("must be an integer from 0 to {MAX_TIME_INDEX} (0: the first record), got {k}"),
                ));
            }
            Some(k as usize)
        }
        None => None,
    };
    let units =
        match &g.units {
            Some(u) if !concentration => return Err(f.error(
                u.span(),
                format!("{key}.units"),
                "applies to concentration_grid only (a thickness is read in the file's m or cm)",
            )),
            Some(_) => Some(f.keyword(
                &g.units,
                &format!("{key}.units"),
                &[
                    ("fraction", ConcentrationUnits::Fraction),
                    ("percent", ConcentrationUnits::Percent),
                ],
                ConcentrationUnits::Fraction,
            )?),
            None => None,
        };
    let path = crate::gridded_inputs::input_path(base_dir, &written);
    Ok(GridField {
        path,
        written,
        variable,
        time_index,
        units,
        span: raw.span(),
        key,
    })
}
