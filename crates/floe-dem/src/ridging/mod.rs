//! Ridging and rafting as a plastic normal contact (Hopkins 1998; DEMSI):
//! a contact's normal force is capped by a ridging strength that grows
//! with the thinner floe's thickness, and the overlap beyond the cap turns
//! into thickness. After every step, a floe pressed past the cap by a
//! thicker floe (or a wall) loses the part of it behind a line parallel
//! to the contact chord, placed so that the overlap left carries exactly
//! the capped force ([`cut`]); that part's volume, momentum and angular
//! momentum go to the thicker floe (spread over its area as thickness),
//! or to the coast's ledger when the other side is a wall
//! ([`RidgingLedger`]). The loser stays convex and keeps its id.
//!
//! Rafting (thin ice sliding over thin ice) moves volume the same way in
//! a two-dimensional model and is not told apart.
//!
//! Defaults, stated so they can be argued with:
//! * strength `C h^p` per metre of contact, `C` = 1e5 N/m at 1 m,
//!   `p` = 1.5: Hopkins' ridge-building simulations give a ridging force
//!   per unit width rising as `h^(3/2)`, and 1e5 N/m at 1 m matches
//!   Hibler's `P* h` with the `P*` of the Nares-strait anchors; `p` = 1
//!   gives Hibler's linear law;
//! * floes thicker than 5 m do not ridge (Subzero.jl's limit);
//! * a floe whose kept part would be under 100 m^2 stays whole (its
//!   contact then stays elastic above the cap).

pub mod cut;
pub mod ledger;

pub use ledger::RidgingLedger;

use crate::error::{invalid_parameter, DemError};

/// Where a free floe's ridged ice goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Rubble {
    /// All of it onto the thicker floe (the gainer), as Subzero.jl.
    #[default]
    Gainer,
    /// Shared between the gainer and the loser's kept part in proportion
    /// to their areas, so that both thicken by the same amount: a small
    /// thick floe no longer collects its large neighbours' ridges over its
    /// small area. Against a wall all of it goes to the coast as with
    /// [`Rubble::Gainer`].
    Both,
}

/// The ridging strength and who ridges.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ridging {
    /// `C` in the strength `C h^p`, N/m (the strength per metre of contact
    /// of 1 m ice).
    pub strength_n_per_m: f64,
    /// `p` in the strength `C h^p`.
    pub thickness_exponent: f64,
    /// A floe thicker than this does not lose ice to ridging, m.
    pub max_thickness_m: f64,
    /// A floe whose kept part would be smaller than this stays whole, m^2.
    pub min_floe_area_m2: f64,
    /// Where the ridged ice goes between two free floes.
    pub rubble: Rubble,
}

impl Default for Ridging {
    fn default() -> Self {
        Ridging {
            strength_n_per_m: 1e5,
            thickness_exponent: 1.5,
            max_thickness_m: 5.0,
            min_floe_area_m2: 100.0,
            rubble: Rubble::Gainer,
        }
    }
}

impl Ridging {
    /// Checks every parameter: finite, the strength and the areas > 0, the
    /// exponent >= 0.
    pub fn check(&self) -> Result<(), DemError> {
        let Ridging {
            strength_n_per_m,
            thickness_exponent,
            max_thickness_m,
            min_floe_area_m2,
            rubble: _,
        } = *self;
        for (name, value) in [
            ("strength_n_per_m", strength_n_per_m),
            ("max_thickness_m", max_thickness_m),
            ("min_floe_area_m2", min_floe_area_m2),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return invalid_parameter(name, value, "must be finite and > 0");
            }
        }
        if !(thickness_exponent.is_finite() && thickness_exponent >= 0.0) {
            return invalid_parameter(
                "thickness_exponent",
                thickness_exponent,
                "must be finite and >= 0",
            );
        }
        Ok(())
    }

    /// The largest normal force per metre of contact a floe of
    /// `thickness_m` bears before it ridges, N/m.
    #[inline]
    pub fn strength_at(&self, thickness_m: f64) -> f64 {
        self.strength_n_per_m * thickness_m.powf(self.thickness_exponent)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_strength_follows_the_power_law() {
        let r = Ridging::default();
        assert_eq!(r.strength_at(1.0), 1e5);
        assert!((r.strength_at(4.0) - 8e5).abs() < 1e-9);
        let hibler = Ridging {
            thickness_exponent: 1.0,
            ..r
        };
        assert!((hibler.strength_at(0.25) - 2.5e4).abs() < 1e-9);
    }

    #[test]
    fn bad_parameters_are_refused_by_name() {
        let r = Ridging::default();
        assert!(r.check().is_ok());
        for (bad, name) in [
            (
                Ridging {
                    strength_n_per_m: 0.0,
                    ..r
                },
                "strength_n_per_m",
            ),
            (
                Ridging {
                    thickness_exponent: -1.0,
                    ..r
                },
                "thickness_exponent",
            ),
            (
                Ridging {
                    max_thickness_m: f64::NAN,
                    ..r
                },
                "max_thickness_m",
            ),
            (
                Ridging {
                    min_floe_area_m2: f64::INFINITY,
                    ..r
                },
                "min_floe_area_m2",
            ),
        ] {
            match bad.check() {
                Err(DemError::InvalidParameter { name: n, .. }) => assert_eq!(n, name),
                other => panic!("{name}: {other:?}"),
            }
        }
    }
}
