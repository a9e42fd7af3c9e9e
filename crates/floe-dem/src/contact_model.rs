//! The contact model: the parameters of the floe-floe contact (elastic
//! overlap force, dashpot, tangential spring) and the friction law.

use floe_friction::{Law, RateState, RateStateParams};

/// Parameters of the floe-floe contact.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactModel {
    /// Young's modulus `E` of the elastic overlap force, Pa. Default 6e6 Pa,
    /// Subzero.jl's (Manucharyan & Montemuro 2022). This is a contact
    /// stiffness parameter, orders below the ~6e9 Pa of intact ice, chosen so
    /// that dt of seconds is stable.
    pub youngs_modulus_pa: f64,
    /// Poisson's ratio, setting the tangential stiffness `k_t = k_n / (2 (1 + nu))`. Default 0.3.
    pub poisson_ratio: f64,
    /// Coefficient of restitution of the normal dashpot, in (0, 1]. 1: no damping. Default 0.5.
    pub restitution: f64,
    /// Friction law of every contact.
    pub law: Law,
    /// Slip rate whose steady state a new contact starts in, m/s. Default 1e-3 m/s.
    pub new_contact_slip_rate_m_per_s: f64,
    /// A contact slips (for the sliding fraction) when its slip rate exceeds this, m/s. Default 1e-6 m/s.
    pub sliding_threshold_m_per_s: f64,
    /// How long a broken contact's state is remembered, s. Default 0: forgotten at once.
    pub memory_s: f64,
}

impl Default for ContactModel {
    fn default() -> Self {
        Self {
            youngs_modulus_pa: 6e6,
            poisson_ratio: 0.3,
            restitution: 0.5,
            law: Law::RateState(RateState::new(
                RateStateParams::lishman_2011_tank(),
                floe_friction::Form::Regularized,
                floe_friction::StateLaw::Slip,
            )),
            new_contact_slip_rate_m_per_s: 1e-3,
            sliding_threshold_m_per_s: 1e-6,
            memory_s: 0.0,
        }
    }
}

impl ContactModel {
    /// Damping ratio of the normal dashpot for the coefficient of restitution
    /// `e` of a linear spring-dashpot: `zeta = -ln e / sqrt(pi^2 + ln^2 e)`.
    pub fn damping_ratio(&self) -> f64 {
        let e = self.restitution.clamp(1e-12, 1.0);
        let l = e.ln();
        -l / (std::f64::consts::PI.powi(2) + l * l).sqrt()
    }

    /// The model with another friction law.
    pub fn with_law(self, law: Law) -> Self {
        Self { law, ..self }
    }
}
