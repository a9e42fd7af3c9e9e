//! When and how floes break: the criterion, how often it is checked, the
//! smallest floe that breaks, the pieces made.

use crate::error::DemError;

use super::criteria::FractureCriterion;
use super::split::SplitRule;

/// Which thickness and concentration set Hibler's strength `P`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StrengthThickness {
    /// Each floe's own thickness, concentration 1.
    Own,
    /// The pack's mean thickness (free floes, by area) and its
    /// concentration in the domain, as Subzero.jl's `update_criteria!`.
    Pack,
}

/// How floes break.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FractureRule {
    /// The criterion on a floe's averaged principal stresses.
    pub criterion: FractureCriterion,
    /// The criterion is checked at steps that are multiples of this.
    pub check_every_steps: u64,
    /// Floes smaller than this never break, m^2.
    pub min_floe_area_m2: f64,
    /// Pieces per split and attempts (its smallest piece is
    /// `min_floe_area_m2`).
    pub split: SplitRule,
    /// Hibler's thickness and concentration (unused by Mohr-Coulomb).
    pub strength_thickness: StrengthThickness,
    /// The run's seed, which keys every split.
    pub seed: u64,
}

impl FractureRule {
    /// Checks the rule: a valid criterion, a check every step or more, a
    /// smallest floe area finite and >= 0, two or more pieces per split,
    /// at least one attempt.
    pub fn check(&self) -> Result<(), DemError> {
        let bad = |reason: String| Err(DemError::InvalidModel { reason });
        let criterion = match &self.criterion {
            FractureCriterion::MohrCoulomb(m) => m.check(),
            FractureCriterion::Hibler(h) => h.check(),
        };
        if let Err(why) = criterion {
            return bad(format!("fracture criterion: {why}"));
        }
        if self.check_every_steps == 0 {
            return bad("fracture is checked every 1 step or more".into());
        }
        if !(self.min_floe_area_m2.is_finite() && self.min_floe_area_m2 >= 0.0) {
            return bad(format!(
                "smallest floe area {} m^2: must be finite and >= 0",
                self.min_floe_area_m2
            ));
        }
        let piece = self.split.min_piece_area_m2;
        if !(piece.is_finite() && piece >= 0.0) {
            return bad(format!(
                "smallest piece area {piece} m^2: must be finite and >= 0"
            ));
        }
        if self.split.pieces < 2 || self.split.attempts == 0 {
            return bad(format!(
                "a split makes {} pieces in {} attempts: two or more pieces, one attempt or more",
                self.split.pieces, self.split.attempts
            ));
        }
        Ok(())
    }

    /// Whether the criterion is checked after step `step`.
    pub fn due(&self, step: u64) -> bool {
        step.is_multiple_of(self.check_every_steps)
    }
}

/// Fracture as a run applies it after every step: the rule and the area
/// of the domain (for the pack's concentration).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fracturing {
    /// When and how floes break.
    pub rule: FractureRule,
    /// The domain's area, m^2.
    pub domain_area_m2: f64,
}
