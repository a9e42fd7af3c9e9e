//! `[map]` and `[[land]]`: the map projection and the coastline files,
//! checked one value at a time (the files themselves are read when the
//! floes are built, [`crate::land_build`], so that a resumed run, which
//! takes its land from the checkpoint, does not need them).

use std::ops::Range;
use std::path::PathBuf;

use floe_basin::{Coordinates, MapProjection};
use toml::Spanned;

use crate::error::ScenarioError;
use crate::source_file::SourceFile;
use crate::spec::{RawLand, RawMap};

/// A `[[land]]` table, checked.
#[derive(Debug, Clone)]
pub(crate) struct LandFile {
    /// `land[index]` in the file.
    pub index: usize,
    /// The GeoJSON file, relative paths taken from the scenario's directory.
    pub path: PathBuf,
    /// As written, for messages.
    pub written: String,
    pub coordinates: Coordinates,
    /// Location of `file`.
    pub span: Range<usize>,
}

/// `[map]`: the projection, if the table is there.
pub(crate) fn resolve_map(
    f: &SourceFile,
    raw: Option<&Spanned<RawMap>>,
) -> Result<Option<MapProjection>, ScenarioError> {
    let Some(raw) = raw else {
        return Ok(None);
    };
    let Some(definition) = &raw.get_ref().projection else {
        return Err(f.error(
            raw.span(),
            "map.projection",
            "missing: the projection of longitude and latitude onto the model plane, \
             e.g. \"EPSG:3413\"",
        ));
    };
    MapProjection::parse(definition.get_ref())
        .map(Some)
        .map_err(|e| f.error(definition.span(), "map.projection", e.to_string()))
}

/// `[[land]]` tables.
pub(crate) fn resolve_land(
    f: &SourceFile,
    raw: &[Spanned<RawLand>],
    map: Option<&MapProjection>,
    base_dir: &std::path::Path,
) -> Result<Vec<LandFile>, ScenarioError> {
    let mut out = Vec::with_capacity(raw.len());
    for (i, t) in raw.iter().enumerate() {
        let r = t.get_ref();
        let key = |k: &str| format!("land[{i}].{k}");
        let Some(file) = &r.file else {
            return Err(f.error(
                t.span(),
                key("file"),
                "missing: the GeoJSON file of the land polygons (relative to the scenario's directory)",
            ));
        };
        crate::gridded_inputs::check_file_value(
            f,
            file.get_ref(),
            file.span(),
            &key("file"),
            "GeoJSON",
        )?;
        let coordinates = f.keyword(
            &r.coordinates,
            &key("coordinates"),
            &[("lonlat", Coordinates::LonLat), ("xy", Coordinates::Xy)],
            Coordinates::LonLat,
        )?;
        if coordinates == Coordinates::LonLat && map.is_none() {
            let span = r.coordinates.as_ref().map_or(t.span(), |c| c.span());
            return Err(f.error(
                span,
                key("coordinates"),
                "the land is in longitude and latitude (the default) but the scenario has no \
                 [map] table to project them: add [map] with projection = \"EPSG:3413\" (say), \
                 or give coordinates = \"xy\" for metres on the model plane",
            ));
        }
        out.push(LandFile {
            index: i,
            path: crate::gridded_inputs::input_path(base_dir, file.get_ref()),
            written: file.get_ref().clone(),
            coordinates,
            span: file.span(),
        });
    }
    Ok(out)
}
