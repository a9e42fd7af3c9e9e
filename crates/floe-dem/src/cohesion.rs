//! Cohesion: floes frozen together. A contact held at a small relative
//! speed for long enough forms a bond whose tensile and shear strength
//! grow with its age towards a maximum; the bond breaks when its load per
//! unit length exceeds the strength of its age.
//!
//! This is the memory that holds ice arches and landfast ice: unlike the
//! friction law's healing (`theta`, which raises the friction coefficient
//! of a contact held still but never lets it pull), a bond carries tension
//! and holds the floes together after the overlap is gone.
//!
//! Defaults, order-of-magnitude choices stated so they can be argued with:
//! * strengths 10 kN/m of bond length: the 5-10 kN/m^2 cohesion Plante et
//!   al. (2020) infer for the Nares Strait ice bridges, times 1 m of ice;
//! * a bond forms after 1 h below 0.1 mm/s of relative speed (about 9 m a
//!   day: floes that have stopped against each other; the water between
//!   them skims over with ice within hours in winter);
//! * strength grows as `1 - exp(-age / 1 d)`: refrozen leads thicken over
//!   days (Stefan's law, about 15 cm in a day at -20 C).

use crate::error::DemError;

/// When bonds form and how strong they grow.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cohesion {
    /// A contact is quiet while the relative speed of its floes at the
    /// contact point is below this, m/s.
    pub quiet_speed_m_per_s: f64,
    /// A contact quiet for this long forms a bond, s (0: at once).
    pub bond_after_s: f64,
    /// The largest tensile strength a bond reaches, N per m of its length.
    pub tensile_strength_n_per_m: f64,
    /// The largest shear strength a bond reaches, N per m of its length.
    pub shear_strength_n_per_m: f64,
    /// The e-folding time of the strengths' growth with age, s (0: full
    /// strength at once).
    pub growth_time_s: f64,
}

impl Default for Cohesion {
    fn default() -> Self {
        Cohesion {
            quiet_speed_m_per_s: 1e-4,
            bond_after_s: 3600.0,
            tensile_strength_n_per_m: 1e4,
            shear_strength_n_per_m: 1e4,
            growth_time_s: 86_400.0,
        }
    }
}

impl Cohesion {
    /// Checks every parameter: finite and >= 0, the quiet speed > 0.
    pub fn check(&self) -> Result<(), DemError> {
        let Cohesion {
            quiet_speed_m_per_s,
            bond_after_s,
            tensile_strength_n_per_m,
            shear_strength_n_per_m,
            growth_time_s,
        } = *self;
        let bad = |name: &'static str, value: f64, reason: &'static str| {
            Err(DemError::InvalidParameter {
                name,
                value,
                reason,
            })
        };
        if !(quiet_speed_m_per_s.is_finite() && quiet_speed_m_per_s > 0.0) {
            return bad(
                "quiet_speed_m_per_s",
                quiet_speed_m_per_s,
                "must be finite and > 0",
            );
        }
        for (name, value) in [
            ("bond_after_s", bond_after_s),
            ("tensile_strength_n_per_m", tensile_strength_n_per_m),
            ("shear_strength_n_per_m", shear_strength_n_per_m),
            ("growth_time_s", growth_time_s),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return bad(name, value, "must be finite and >= 0");
            }
        }
        Ok(())
    }

    /// The fraction of the largest strengths a bond of `age_s` has:
    /// `1 - exp(-age / growth_time)`, 1 without growth time.
    #[inline]
    pub fn strength_fraction(&self, age_s: f64) -> f64 {
        if self.growth_time_s > 0.0 {
            -(-age_s.max(0.0) / self.growth_time_s).exp_m1()
        } else {
            1.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strength_grows_to_its_maximum_with_the_growth_time() {
        let c = Cohesion::default();
        assert_eq!(c.strength_fraction(0.0), 0.0);
        let e = 1.0 - (-1.0f64).exp();
        assert!((c.strength_fraction(86_400.0) - e).abs() < 1e-15);
        assert!((c.strength_fraction(1e9) - 1.0).abs() < 1e-15);
        // A small age: the linear start, age / growth time.
        assert!((c.strength_fraction(1.0) * 86_400.0 - 1.0).abs() < 1e-5);
        let at_once = Cohesion {
            growth_time_s: 0.0,
            ..c
        };
        assert_eq!(at_once.strength_fraction(0.0), 1.0);
    }

    #[test]
    fn bad_parameters_are_refused_by_name() {
        let c = Cohesion::default();
        assert!(c.check().is_ok());
        for (bad, name) in [
            (
                Cohesion {
                    quiet_speed_m_per_s: 0.0,
                    ..c
                },
                "quiet_speed_m_per_s",
            ),
            (
                Cohesion {
                    bond_after_s: -1.0,
                    ..c
                },
                "bond_after_s",
            ),
            (
                Cohesion {
                    tensile_strength_n_per_m: f64::NAN,
                    ..c
                },
                "tensile_strength_n_per_m",
            ),
            (
                Cohesion {
                    shear_strength_n_per_m: f64::INFINITY,
                    ..c
                },
                "shear_strength_n_per_m",
            ),
            (
                Cohesion {
                    growth_time_s: -2.0,
                    ..c
                },
                "growth_time_s",
            ),
        ] {
            match bad.check() {
                Err(DemError::InvalidParameter { name: got, .. }) => assert_eq!(got, name),
                other => panic!("{name}: {other:?}"),
            }
        }
    }
}
