//! Coastlines and islands from GeoJSON: the land polygons of a file on the
//! model plane.
//!
//! Every `Polygon` and `MultiPolygon` geometry of the file is land: a
//! `FeatureCollection`'s features, a single `Feature`, or a bare geometry.
//! Other geometry types (points, lines, collections) and features without
//! a geometry are refused, naming the feature. Coordinates are longitude
//! and latitude in degrees (WGS84, projected with the scenario's
//! [`MapProjection`]) or x and y in metres on the model plane; a third
//! value (altitude) is ignored. Edges are straight lines on the model
//! plane between the (projected) vertices, so a long edge given in
//! longitude and latitude should be densified in the file.
//!
//! The file is UTF-8, with or without a byte-order mark.
//!
//! Holes (interior rings: lakes, lagoons) are refused: water enclosed by
//! land could not exchange ice with the rest of the domain anyway; give
//! the land around it as separate polygons. Each outer ring must be simple
//! ([`crate::simple_ring`]).

use std::path::Path;

use floe_dem::Vec2;
use geojson::{GeoJson, Geometry, GeometryValue, PolygonType};

use crate::error::BasinError;
use crate::projection::MapProjection;
use crate::simple_ring::simple_ring;

/// Largest land file read, bytes.
pub const MAX_LAND_FILE_BYTES: u64 = 1 << 30;

/// How a land file gives its coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Coordinates {
    /// Longitude and latitude, degrees (WGS84), through the map projection.
    LonLat,
    /// x and y on the model plane, m.
    Xy,
}

/// One land polygon on the model plane.
#[derive(Debug, Clone, PartialEq)]
pub struct LandPolygon {
    /// Index of the feature it came from (0 for a bare geometry).
    pub feature: usize,
    /// Its outer ring: simple, counter-clockwise, without repeating the
    /// first vertex, m.
    pub ring: Vec<Vec2>,
}

/// Reads the land polygons of the GeoJSON file at `path`.
///
/// # Errors
/// [`BasinError::File`] naming the file (and the feature and polygon)
/// when it cannot be read, is not GeoJSON, holds other geometries than
/// polygons, a hole, a ring that is not simple, coordinates out of range,
/// or longitude and latitude without a projection.
pub fn read_land(
    path: &Path,
    coordinates: Coordinates,
    projection: Option<&MapProjection>,
) -> Result<Vec<LandPolygon>, BasinError> {
    let bad = |why: String| BasinError::File {
        path: path.to_path_buf(),
        why,
    };
    let meta = std::fs::metadata(path).map_err(|e| bad(format!("cannot read it: {e}")))?;
    if !meta.is_file() {
        return Err(bad("is not a regular file".into()));
    }
    if meta.len() > MAX_LAND_FILE_BYTES {
        return Err(bad(format!(
            "is {} bytes, above the limit of {MAX_LAND_FILE_BYTES} for a land file",
            meta.len()
        )));
    }
    let text = std::fs::read_to_string(path).map_err(|e| bad(format!("cannot read it: {e}")))?;
    parse_land(&text, coordinates, projection).map_err(bad)
}

/// The land polygons of GeoJSON `text`; errors are the reason alone (the
/// caller names the file).
pub fn parse_land(
    text: &str,
    coordinates: Coordinates,
    projection: Option<&MapProjection>,
) -> Result<Vec<LandPolygon>, String> {
    let projection = match (coordinates, projection) {
        (Coordinates::LonLat, None) => {
            return Err(
                "coordinates are longitude and latitude, but no map projection was given \
                 (a [map] table with projection = \"EPSG:3413\", say)"
                    .into(),
            )
        }
        (Coordinates::LonLat, Some(p)) => Some(p),
        (Coordinates::Xy, _) => None,
    };
    // A UTF-8 byte-order mark (some Windows tools write one) is not JSON;
    // dropped, lines and columns in messages are those an editor shows.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let json: GeoJson = text.parse().map_err(|e| format!("not GeoJSON: {e}"))?;
    let geometries: Vec<(usize, Option<Geometry>)> = match json {
        GeoJson::FeatureCollection(c) => c
            .features
            .into_iter()
            .enumerate()
            .map(|(i, f)| (i, f.geometry))
            .collect(),
        GeoJson::Feature(f) => vec![(0, f.geometry)],
        GeoJson::Geometry(g) => vec![(0, Some(g))],
    };
    if geometries.is_empty() {
        return Err("holds no features: no land".into());
    }
    let mut out = Vec::new();
    for (feature, geometry) in geometries {
        let at = |what: String| format!("feature {feature}: {what}");
        let Some(geometry) = geometry else {
            return Err(at("has no geometry; land is Polygon or MultiPolygon".into()));
        };
        let polygons: Vec<(Option<usize>, PolygonType)> = match geometry.value {
            GeometryValue::Polygon { coordinates } => vec![(None, coordinates)],
            GeometryValue::MultiPolygon { coordinates } => coordinates
                .into_iter()
                .enumerate()
                .map(|(k, p)| (Some(k), p))
                .collect(),
            other => {
                return Err(at(format!(
                    "is a {}; land is Polygon or MultiPolygon",
                    other.type_name()
                )))
            }
        };
        for (k, rings) in polygons {
            let at = |what: String| match k {
                Some(k) => at(format!("polygon {k} of its MultiPolygon {what}")),
                None => at(format!("polygon {what}")),
            };
            match rings.len() {
                0 => return Err(at("has no ring".into())),
                1 => {}
                n => {
                    return Err(at(format!(
                        "has {} holes (interior rings); holes in land are not supported: \
                         give the land around a lake or lagoon as separate polygons",
                        n - 1
                    )))
                }
            }
            let mut plane = Vec::with_capacity(rings[0].len());
            for (v, position) in rings[0].iter().enumerate() {
                let c = position.as_slice();
                if c.len() < 2 {
                    return Err(at(format!(
                        "has vertex {v} with fewer than two coordinates"
                    )));
                }
                let (a, b) = (c[0], c[1]);
                if !(a.is_finite() && b.is_finite()) {
                    return Err(at(format!(
                        "has vertex {v} at ({}, {}), not finite",
                        number(a),
                        number(b)
                    )));
                }
                let p = match projection {
                    Some(proj) => {
                        if !((-180.0..=360.0).contains(&a) && (-90.0..=90.0).contains(&b)) {
                            return Err(at(format!(
                                "has vertex {v} at longitude {}, latitude {}: not a longitude \
                                 and latitude in degrees (are the coordinates x and y? then \
                                 coordinates = \"xy\")",
                                number(a),
                                number(b)
                            )));
                        }
                        proj.forward(a, b)
                            .map_err(|e| at(format!("has vertex {v} off the map: {e}")))?
                    }
                    None => Vec2::new(a, b),
                };
                plane.push(p);
            }
            let ring = simple_ring(&plane).map_err(|why| at(format!("outer ring {why}")))?;
            out.push(LandPolygon { feature, ring });
        }
    }
    Ok(out)
}

/// A coordinate as written in a message: as is, or in exponent form when
/// plain digits would run long (`1e300`, not three hundred digits).
fn number(x: f64) -> String {
    let plain = format!("{x}");
    if plain.len() > 24 {
        format!("{x:e}")
    } else {
        plain
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn features_of_other_types_and_holes_are_named() {
        let point = r#"{"type":"FeatureCollection","features":[
            {"type":"Feature","properties":{},"geometry":{"type":"Polygon","coordinates":[[[0,0],[1,0],[1,1],[0,0]]]}},
            {"type":"Feature","properties":{},"geometry":{"type":"Point","coordinates":[0,0]}}]}"#;
        let e = parse_land(point, Coordinates::Xy, None).unwrap_err();
        assert!(e.contains("feature 1") && e.contains("Point"), "{e}");
        let hole = r#"{"type":"Polygon","coordinates":[[[0,0],[10,0],[10,10],[0,10],[0,0]],[[2,2],[3,2],[3,3],[2,2]]]}"#;
        let e = parse_land(hole, Coordinates::Xy, None).unwrap_err();
        assert!(e.contains("1 holes"), "{e}");
        let e = parse_land("{nope", Coordinates::Xy, None).unwrap_err();
        assert!(e.contains("not GeoJSON"), "{e}");
        let e = parse_land(hole, Coordinates::LonLat, None).unwrap_err();
        assert!(e.contains("projection"), "{e}");
        let ok = r#"{"type":"MultiPolygon","coordinates":[[[[0,0],[1,0],[1,1],[0,0]]],[[[5,5],[6,5],[6,6],[5,5]]]]}"#;
        assert_eq!(parse_land(ok, Coordinates::Xy, None).unwrap().len(), 2);
    }
}
