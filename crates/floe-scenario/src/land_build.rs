//! Land as floes: the `[[land]]` files read, cut into convex pieces no
//! larger than the largest free floe, and made fixed prescribed floes, as
//! walls are; and the generated ice that lies on land dropped.

use floe_basin::{read_land, Coordinates, Land};
use floe_dem::Vec2;

use crate::checks::OVERLAP_TOLERANCE;
use crate::error::ScenarioError;
use crate::length_limit::MAX_LENGTH_M;
use crate::numbers::{sig, thousands};
use crate::piece::Piece;
use crate::resolve::land::LandFile;
use crate::resolve::Resolved;
use crate::source_file::SourceFile;

/// The land of one `[[land]]` table.
pub(crate) struct LandOfFile {
    pub file: LandFile,
    pub land: Land,
}

/// Reads every `[[land]]` file and cuts its polygons into convex pieces of
/// radius at most `piece_radius_m`. Every problem is located at the
/// table's `file` key and names the GeoJSON file.
pub(crate) fn read_all(
    f: &SourceFile,
    r: &Resolved,
    piece_radius_m: f64,
) -> Result<Vec<LandOfFile>, ScenarioError> {
    let mut out = Vec::with_capacity(r.land.len());
    for lf in &r.land {
        let key = format!("land[{}].file", lf.index);
        let at = |why: String| f.error(lf.span.clone(), key.clone(), why);
        let polygons =
            read_land(&lf.path, lf.coordinates, r.map.as_ref()).map_err(|e| at(e.to_string()))?;
        if let Some((p, v)) = polygons.iter().find_map(|p| {
            p.ring
                .iter()
                .find(|v| v.x.abs().max(v.y.abs()) > MAX_LENGTH_M)
                .map(|v| (p, v))
        }) {
            return Err(at(format!(
                "{}: feature {}: vertex ({}, {}) m is beyond the largest accepted coordinate, {} m",
                lf.path.display(),
                p.feature,
                sig(v.x),
                sig(v.y),
                sig(MAX_LENGTH_M)
            )));
        }
        let land = Land::new(polygons, piece_radius_m)
            .map_err(|why| at(format!("{}: {why}", lf.path.display())))?;
        out.push(LandOfFile {
            file: lf.clone(),
            land,
        });
    }
    Ok(out)
}

/// Drops the free pieces that overlap land by more than
/// [`OVERLAP_TOLERANCE`] of their area; returns how many and their area.
pub(crate) fn drop_ice_on_land(pieces: &mut Vec<Piece>, land: &[LandOfFile]) -> (usize, f64) {
    if land.is_empty() {
        return (0, 0.0);
    }
    let (mut dropped, mut area) = (0, 0.0);
    pieces.retain(|p| {
        if p.prescribed {
            return true;
        }
        let a = floe_basin::planar::signed_area(&p.polygon).abs();
        let on_land: f64 = land
            .iter()
            .map(|l| l.land.overlap_area_m2(&p.polygon))
            .sum();
        let keep = on_land <= OVERLAP_TOLERANCE * a;
        if !keep {
            dropped += 1;
            area += a;
        }
        keep
    });
    (dropped, area)
}

/// The land pieces as fixed prescribed floes (after everything else), with
/// the report's lines.
pub(crate) fn land_pieces(
    land: &[LandOfFile],
    thickness_m: f64,
    map: Option<&floe_basin::MapProjection>,
    report: &mut Vec<String>,
) -> Vec<Piece> {
    let mut out = Vec::new();
    for l in land {
        let lf = &l.file;
        let how = match (lf.coordinates, map) {
            (Coordinates::LonLat, Some(m)) => format!("lon/lat through {}", m.definition()),
            _ => "x/y on the model plane".to_string(),
        };
        let before = out.len();
        let radius = l.land.piece_radius_m;
        for piece in &l.land.pieces {
            let a = floe_basin::planar::signed_area(&piece.vertices);
            // Slivers a cut can leave carry no force worth a floe.
            if a.partial_cmp(&(1e-12 * radius * radius)) != Some(std::cmp::Ordering::Greater) {
                continue;
            }
            let feature = l.land.polygons[piece.polygon].feature;
            out.push(Piece {
                polygon: piece.vertices.clone(),
                thickness_m,
                velocity: Vec2::ZERO,
                angular_velocity: 0.0,
                prescribed: true,
                schedule: None,
                load_point: None,
                label: Some(format!(
                    "land[{}] ({}, feature {feature})",
                    lf.index, lf.written
                )),
                span: Some(lf.span.clone()),
            });
        }
        report.push(format!(
            "land[{}]: {} ({how}): {} polygons, {} vertices, {} km^2; {} convex pieces, cut into {} fixed pieces of radius at most {} m",
            lf.index,
            lf.written,
            thousands(l.land.polygons.len()),
            thousands(l.land.vertex_count()),
            sig(l.land.area_m2() * 1e-6),
            thousands(l.land.convex_count),
            thousands(out.len() - before),
            sig(radius)
        ));
    }
    out
}
