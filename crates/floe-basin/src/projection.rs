//! The map projection that puts longitude and latitude onto floe's model
//! plane (metres, x east-ish, y north-ish), through the `proj4rs` crate.
//!
//! A scenario names it as `"EPSG:3413"` (NSIDC polar stereographic north,
//! the usual Arctic choice) or as a PROJ string
//! (`"+proj=stere +lat_0=90 +lat_ts=70 +lon_0=-45 +datum=WGS84 +units=m"`).
//! Vectors given as east and north components (winds, currents of a
//! longitude-latitude grid) are turned onto the plane's axes with the local
//! east and north directions of the projection, found by projecting two
//! points a small step east and north: exact for any projection to the
//! step's first order, and nothing to hand-derive per projection.

use floe_dem::Vec2;
use proj4rs::{adaptors::transform_xy, Proj};

use crate::error::BasinError;

/// Step for the local east and north directions, degrees (about 1 m at
/// the pole's distance of the equator; far below any grid spacing).
const DIRECTION_STEP_DEG: f64 = 1e-5;

/// A projection from WGS84 longitude and latitude (degrees) to the model
/// plane (metres).
pub struct MapProjection {
    definition: String,
    plane: Proj,
    geographic: Proj,
}

impl std::fmt::Debug for MapProjection {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "MapProjection({})", self.definition)
    }
}

impl Clone for MapProjection {
    fn clone(&self) -> Self {
        MapProjection::parse(&self.definition).expect("a projection that parsed parses again")
    }
}

impl MapProjection {
    /// Parses `"EPSG:NNNN"` or a PROJ string (starting with `+`). The plane
    /// must be projected (not longitude-latitude) with metres as unit.
    ///
    /// # Errors
    /// [`BasinError::Projection`] naming the definition and what was wrong.
    pub fn parse(definition: &str) -> Result<Self, BasinError> {
        let bad = |why: String| BasinError::Projection {
            definition: definition.to_string(),
            why,
        };
        let plane = Proj::from_user_string(definition).map_err(|e| {
            bad(format!(
                "{e}; accepted: \"EPSG:<code>\" (e.g. \"EPSG:3413\") or a PROJ string starting with '+'"
            ))
        })?;
        if plane.is_latlong() {
            return Err(bad(
                "it is longitude-latitude; the model plane needs a projection in metres (e.g. EPSG:3413)"
                    .to_string(),
            ));
        }
        let geographic = Proj::from_proj_string("+proj=longlat +datum=WGS84 +no_defs")
            .map_err(|e| bad(format!("WGS84 longitude-latitude: {e}")))?;
        Ok(MapProjection {
            definition: definition.trim().to_string(),
            plane,
            geographic,
        })
    }

    /// The definition as given.
    pub fn definition(&self) -> &str {
        &self.definition
    }

    /// The plane point (m) of longitude `lon_deg` and latitude `lat_deg`.
    ///
    /// # Errors
    /// [`BasinError::Projection`] where the projection is undefined.
    pub fn forward(&self, lon_deg: f64, lat_deg: f64) -> Result<Vec2, BasinError> {
        let (x, y) = transform_xy(
            &self.geographic,
            &self.plane,
            lon_deg.to_radians(),
            lat_deg.to_radians(),
        )
        .map_err(|e| self.undefined(format!("at lon {lon_deg}°, lat {lat_deg}°: {e}")))?;
        if !(x.is_finite() && y.is_finite()) {
            return Err(self.undefined(format!("at lon {lon_deg}°, lat {lat_deg}°")));
        }
        Ok(Vec2::new(x, y))
    }

    /// Longitude and latitude (degrees) of the plane point `p` (m).
    ///
    /// # Errors
    /// [`BasinError::Projection`] where the inverse is undefined.
    pub fn inverse(&self, p: Vec2) -> Result<(f64, f64), BasinError> {
        let (lon, lat) = transform_xy(&self.plane, &self.geographic, p.x, p.y)
            .map_err(|e| self.undefined(format!("inverse at ({}, {}) m: {e}", p.x, p.y)))?;
        Ok((lon.to_degrees(), lat.to_degrees()))
    }

    /// Unit vectors on the plane of the local east and north at
    /// (`lon_deg`, `lat_deg`): a vector of east and north components
    /// `(u, v)` is `u east + v north` on the plane.
    ///
    /// # Errors
    /// As [`MapProjection::forward`] (the poles themselves have no east).
    pub fn east_north(&self, lon_deg: f64, lat_deg: f64) -> Result<(Vec2, Vec2), BasinError> {
        let h = DIRECTION_STEP_DEG;
        // Centred differences; north steps stay below the pole.
        let (lat_lo, lat_hi) = if lat_deg + h > 90.0 {
            (lat_deg - 2.0 * h, lat_deg)
        } else if lat_deg - h < -90.0 {
            (lat_deg, lat_deg + 2.0 * h)
        } else {
            (lat_deg - h, lat_deg + h)
        };
        let east = self.forward(lon_deg + h, lat_deg)? - self.forward(lon_deg - h, lat_deg)?;
        let north = self.forward(lon_deg, lat_hi)? - self.forward(lon_deg, lat_lo)?;
        let (le, ln) = (east.length(), north.length());
        if !(le > 0.0 && ln > 0.0) {
            return Err(self.undefined(format!(
                "no east or north direction at lon {lon_deg}°, lat {lat_deg}° (a pole?)"
            )));
        }
        Ok((east / le, north / ln))
    }

    fn undefined(&self, why: String) -> BasinError {
        BasinError::Projection {
            definition: self.definition.clone(),
            why: format!("undefined {why}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// EPSG:3413 by Snyder (1987, eqs. 14-15, 21-33, 21-34, 21-36, 21-37):
    /// the ellipsoidal polar stereographic with standard parallel 70° N,
    /// central meridian −45°, WGS84.
    fn snyder_3413(lon_deg: f64, lat_deg: f64) -> Vec2 {
        let a = 6378137.0_f64;
        let f = 1.0_f64 / 298.257223563;
        let e: f64 = (f * (2.0 - f)).sqrt();
        let t = |phi: f64| {
            ((std::f64::consts::FRAC_PI_4 - phi / 2.0).tan())
                / ((1.0 - e * phi.sin()) / (1.0 + e * phi.sin())).powf(e / 2.0)
        };
        let m = |phi: f64| phi.cos() / (1.0 - (e * phi.sin()).powi(2)).sqrt();
        let phi_c = 70f64.to_radians();
        let rho = a * m(phi_c) * t(lat_deg.to_radians()) / t(phi_c);
        let dl = (lon_deg + 45.0).to_radians();
        Vec2::new(rho * dl.sin(), -rho * dl.cos())
    }

    #[test]
    fn epsg_3413_matches_snyder_to_a_millimetre() {
        let p = MapProjection::parse("EPSG:3413").unwrap();
        for &(lon, lat) in &[
            (-45.0, 90.0),
            (-60.0, 80.0),
            (-70.0, 81.5),
            (10.0, 70.0),
            (135.0, 61.0),
        ] {
            let got = p.forward(lon, lat).unwrap();
            let want = snyder_3413(lon, lat);
            assert!(
                (got - want).length() < 1e-3,
                "{lon} {lat}: {got:?} vs {want:?}"
            );
            let (lo, la) = p.inverse(got).unwrap();
            if lat < 90.0 {
                assert!(
                    (lo - lon).abs() < 1e-9 && (la - lat).abs() < 1e-9,
                    "{lo} {la}"
                );
            }
        }
    }

    #[test]
    fn east_and_north_follow_the_meridians_of_a_polar_plane() {
        // On EPSG:3413 north points to the pole (the origin) from every point.
        let p = MapProjection::parse("EPSG:3413").unwrap();
        for &(lon, lat) in &[(-45.0, 75.0), (-70.0, 81.0), (100.0, 66.0)] {
            let (east, north) = p.east_north(lon, lat).unwrap();
            let to_pole = -p.forward(lon, lat).unwrap().normalize();
            assert!((north - to_pole).length() < 1e-6, "{north:?} {to_pole:?}");
            // Conformal: east is north turned clockwise by 90°.
            assert!((east - Vec2::new(north.y, -north.x)).length() < 1e-6);
        }
    }

    #[test]
    fn geographic_or_unknown_planes_are_refused_with_what_is_accepted() {
        for bad in ["EPSG:4326", "EPSG:99999", "polar", "+proj=nonsense"] {
            let e = MapProjection::parse(bad).unwrap_err().to_string();
            assert!(e.contains(bad.trim()), "{e}");
        }
        let e = MapProjection::parse("mercator").unwrap_err().to_string();
        assert!(e.contains("EPSG:3413"), "{e}");
    }
}
