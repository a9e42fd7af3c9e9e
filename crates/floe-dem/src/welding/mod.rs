//! Welding: two floes frozen together long enough become one floe, the
//! convex hull of the pair. A formed bond ([`crate::cohesion`]) older than
//! [`Welding::after_s`] welds its floes when the hull adds little open
//! water to the ice ([`Welding::max_added_area_fraction`]), the welded
//! floe is not too large ([`Welding::max_area_m2`]) and its centre of mass
//! moves little ([`Welding::max_centre_shift_fraction`]).
//!
//! The welded floe keeps the pair's mass and ice volume exactly (the
//! volume spread evenly over the hull as thickness), their linear momentum
//! and their angular momentum about every point; the kinetic energy of the
//! pair's relative motion is lost in the merge and booked in the
//! [`WeldingLedger`]. One thickness per floe moves the centre of mass
//! from the pair's to the hull's centroid (the shift is logged and bounded);
//! the spin is chosen so that angular momentum is still conserved.
//!
//! Subzero.jl welds pairs drawn at random (an unseeded generator) with a
//! probability growing with their overlap; here the rule is a deterministic
//! inequality on the bond's age, so runs repeat to the bit.
//!
//! Defaults, stated so they can be argued with:
//! * two days of bond age: the bond's strength is then 86 % of its
//!   maximum (growth time 1 d), the refrozen lead about 20-30 cm thick
//!   (Stefan's law at -20 C), a plate that carries bending, not a seam;
//! * the hull adds at most 5 % of the pair's area as new ice (the pair's
//!   outline, not a floe swollen over open water);
//! * at most 2e9 m^2, Subzero.jl's largest welded floe;
//! * the centre of mass moves at most 5 % of the welded floe's radius;
//! * checked every hour: a bond needs days to weld, and each check
//!   computes the hull of every bond old enough (about 8,000 instructions
//!   a bond at 1e4 floes, `life_cycle_cost 10000 N weld-watch`), more than
//!   a step costs when the pack is frozen.

pub mod ledger;

pub use ledger::WeldingLedger;

use crate::error::{invalid_parameter, DemError};

/// When bonded floes weld into one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Welding {
    /// A bond this old welds its floes, s.
    pub after_s: f64,
    /// The hull may add at most this fraction of the pair's area.
    pub max_added_area_fraction: f64,
    /// No welded floe is larger, m^2.
    pub max_area_m2: f64,
    /// The centre of mass may move at most this fraction of the welded
    /// floe's radius.
    pub max_centre_shift_fraction: f64,
    /// Welds are looked for every this many seconds (at the steps whose
    /// count is a multiple of it in steps, at least 1), s (0: every step).
    pub check_every_s: f64,
}

impl Default for Welding {
    fn default() -> Self {
        Welding {
            after_s: 172_800.0,
            max_added_area_fraction: 0.05,
            max_area_m2: 2e9,
            max_centre_shift_fraction: 0.05,
            check_every_s: 3600.0,
        }
    }
}

impl Welding {
    /// Checks every parameter: finite and >= 0, the largest area > 0.
    pub fn check(&self) -> Result<(), DemError> {
        let Welding {
            after_s,
            max_added_area_fraction,
            max_area_m2,
            max_centre_shift_fraction,
            check_every_s,
        } = *self;
        for (name, value) in [
            ("after_s", after_s),
            ("check_every_s", check_every_s),
            ("max_added_area_fraction", max_added_area_fraction),
            ("max_centre_shift_fraction", max_centre_shift_fraction),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return invalid_parameter(name, value, "must be finite and >= 0");
            }
        }
        if !(max_area_m2.is_finite() && max_area_m2 > 0.0) {
            return invalid_parameter("max_area_m2", max_area_m2, "must be finite and > 0");
        }
        Ok(())
    }

    /// Whether welds are looked for after step `step` of `dt_s`.
    pub fn due(&self, step: u64, dt_s: f64) -> bool {
        step.is_multiple_of(crate::run::cadence::whole_steps(self.check_every_s, dt_s))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn welds_are_looked_for_at_multiples_of_the_check_interval() {
        let w = Welding {
            check_every_s: 10.0,
            ..Welding::default()
        };
        let due: Vec<u64> = (1..=45).filter(|&s| w.due(s, 0.5)).collect();
        assert_eq!(due, vec![20, 40]);
        let every = Welding {
            check_every_s: 0.0,
            ..w
        };
        assert!((1..=5).all(|s| every.due(s, 0.5)));
    }

    #[test]
    fn bad_parameters_are_refused_by_name() {
        let d = Welding::default();
        assert!(d.check().is_ok());
        for (bad, name) in [
            (Welding { after_s: -1.0, ..d }, "after_s"),
            (
                Welding {
                    max_added_area_fraction: f64::NAN,
                    ..d
                },
                "max_added_area_fraction",
            ),
            (
                Welding {
                    max_area_m2: 0.0,
                    ..d
                },
                "max_area_m2",
            ),
            (
                Welding {
                    check_every_s: -1.0,
                    ..d
                },
                "check_every_s",
            ),
            (
                Welding {
                    max_centre_shift_fraction: f64::INFINITY,
                    ..d
                },
                "max_centre_shift_fraction",
            ),
        ] {
            match bad.check() {
                Err(DemError::InvalidParameter { name: got, .. }) => assert_eq!(got, name),
                other => panic!("{name}: {other:?}"),
            }
        }
    }
}
