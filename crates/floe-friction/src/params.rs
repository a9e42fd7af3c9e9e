//! Parameter sets of the friction laws, with units in their names, and the
//! published presets.

use serde::{Deserialize, Serialize};

use crate::error::{finite, positive, FrictionError};

/// Parameters of the Lishman et al. (2011) rate-and-state law, eqs. 3a/3b:
/// `mu = mu0 + theta + a ln(V/V*)`, `dtheta/dt = -(V/L)(theta + b ln(V/V*))`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RateStateParams {
    /// Reference friction coefficient `mu0` at `V = V*` in steady state (dimensionless).
    pub mu0: f64,
    /// Direct-effect coefficient `A` (dimensionless).
    pub a: f64,
    /// State-evolution coefficient `B` (dimensionless); `B > A` is velocity weakening.
    pub b: f64,
    /// Reference slip rate `V*` in m/s.
    pub v_star_m_per_s: f64,
    /// Characteristic slip distance `L` in m over which state evolves.
    pub critical_slip_m: f64,
}

/// `mu0` of Table 2.
pub const LISHMAN_MU0: f64 = 0.872;
/// `A` of Table 2.
pub const LISHMAN_A: f64 = 0.310;
/// `B` of Table 2.
pub const LISHMAN_B: f64 = 0.382;
/// `V*` of eq. 2, m/s.
pub const LISHMAN_V_STAR_M_PER_S: f64 = 1e-5;
/// Laboratory critical slip distance (section 4), m.
pub const LISHMAN_LAB_L_M: f64 = 0.2e-3;
/// Ice-tank critical slip distance (section 4), m.
pub const LISHMAN_TANK_L_M: f64 = 5e-3;

impl RateStateParams {
    /// Lishman et al. (2011) Table 2 with a given critical slip distance `L` (m).
    pub fn lishman_2011(critical_slip_m: f64) -> Self {
        Self {
            mu0: LISHMAN_MU0,
            a: LISHMAN_A,
            b: LISHMAN_B,
            v_star_m_per_s: LISHMAN_V_STAR_M_PER_S,
            critical_slip_m,
        }
    }

    /// Lishman et al. (2011), laboratory scale (`L` = 0.2 mm).
    pub fn lishman_2011_lab() -> Self {
        Self::lishman_2011(LISHMAN_LAB_L_M)
    }

    /// Lishman et al. (2011), ice-tank scale (`L` = 5 mm).
    pub fn lishman_2011_tank() -> Self {
        Self::lishman_2011(LISHMAN_TANK_L_M)
    }

    /// Checks every parameter: `a`, `v_star_m_per_s`, `critical_slip_m` > 0, `b` >= 0,
    /// all finite.
    pub fn validate(&self) -> Result<(), FrictionError> {
        finite("mu0", self.mu0)?;
        positive("a", self.a)?;
        finite("b", self.b)?;
        if self.b < 0.0 {
            return Err(FrictionError::InvalidParameter {
                name: "b",
                value: self.b,
                reason: "must be >= 0",
            });
        }
        positive("v_star_m_per_s", self.v_star_m_per_s)?;
        positive("critical_slip_m", self.critical_slip_m)?;
        Ok(())
    }

    /// Steady-state state variable `theta_ss = -b ln(V/V*)` at slip rate `|v|` (m/s).
    pub fn theta_steady(&self, v_m_per_s: f64) -> f64 {
        -self.b * (v_m_per_s.abs() / self.v_star_m_per_s).ln()
    }

    /// Steady-state friction of the published form, `mu0 + (a - b) ln(V/V*)`.
    pub fn mu_steady_published(&self, v_m_per_s: f64) -> f64 {
        self.mu0 + (self.a - self.b) * (v_m_per_s.abs() / self.v_star_m_per_s).ln()
    }

    /// Critical spring stiffness `k_c = N (b - a) / L` (N/m) below which steady
    /// sliding of a spring-slider under normal load `N` is unstable (Ruina 1983,
    /// Gu et al. 1984). Zero or negative for velocity-strengthening parameters.
    pub fn critical_stiffness_n_per_m(&self, normal_load_n: f64) -> f64 {
        normal_load_n * (self.b - self.a) / self.critical_slip_m
    }
}

/// Fortt & Schulson (2009) rate coefficients `C1` (substituted for `A - B`, as the
/// paper suggests in section 3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ForttSchulsonC1 {
    /// Accelerating slip, `C1 = -0.10`.
    Acceleration,
    /// Constant-velocity slip, `C1 = -0.12`.
    ConstantVelocity,
    /// Decelerating slip, `C1 = -0.16`.
    Deceleration,
}

impl ForttSchulsonC1 {
    /// The value of `C1` (dimensionless).
    pub fn c1(self) -> f64 {
        match self {
            Self::Acceleration => -0.10,
            Self::ConstantVelocity => -0.12,
            Self::Deceleration => -0.16,
        }
    }
}

/// The paper's two experimental set-ups.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Preset {
    /// UCL laboratory double shear: k = 20 MN/m, 0.1 mm/s, L = 0.2 mm, 1 kN
    /// side load on two faces (effective normal load 2 kN).
    Lab,
    /// HSVA ice tank: k = 2 MN/m, 8 mm/s, L = 5 mm, 5 kN side load on two faces
    /// (effective normal load 10 kN).
    Tank,
}

impl Preset {
    /// Lishman et al. (2011) parameters at this scale.
    pub fn params(self) -> RateStateParams {
        match self {
            Preset::Lab => RateStateParams::lishman_2011_lab(),
            Preset::Tank => RateStateParams::lishman_2011_tank(),
        }
    }
}

/// How the friction coefficient relates to the slip rate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Form {
    /// Eq. 4b as published: `V = V* exp((mu - mu0 - theta)/A)`. The slip rate is
    /// always positive, so the slider creeps forward even at zero or negative
    /// spring force; it cannot slide backwards.
    Published,
    /// Sign-consistent form `V = 2 V* exp(-(mu0 + theta)/A) sinh(mu/A)`: slip and
    /// friction share their sign and vanish together. Equal to the published form
    /// to relative order `exp(-2 mu/A)`, which for ice (`A = 0.31`) is not
    /// negligible: about 5 % in `mu` at 8 mm/s. Needed wherever force can vanish
    /// or reverse, as on every DEM contact.
    #[default]
    Regularized,
}
