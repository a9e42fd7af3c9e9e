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
    /// `e`, for the dashpot as the contact kernel applies it: clipped at
    /// zero force (no adhesion), so that a collision ends when the force
    /// vanishes, before the overlap does ([`clipped_restitution`], Schwager &
    /// Poschel 2008). The textbook `zeta = -ln e / sqrt(pi^2 + ln^2 e)`
    /// assumes the dashpot may pull until the overlap ends: with the clip it
    /// gives restitution 0.214 for `e = 0.05` and 0.550 for 0.5.
    /// A bisection in `ln zeta` (70 evaluations): the world computes it once.
    pub fn damping_ratio(&self) -> f64 {
        damping_ratio_for_restitution(self.restitution)
    }

    /// The model with another friction law.
    pub fn with_law(self, law: Law) -> Self {
        Self { law, ..self }
    }
}

/// Coefficient of restitution of a head-on collision through a linear
/// spring-dashpot of damping ratio `zeta` whose force is clipped at zero:
/// the collision ends when `k x + c x' = 0` (Schwager & Poschel 2008,
/// Phys. Rev. E 78, 051304), and `e = -x'/v0` there, `= omega0 x / (2 zeta
/// v0)`. Decreases from 1 at `zeta = 0` to 0 as `zeta -> inf` (`~1/(4
/// zeta^2)`); exactly `e^-2` at critical damping.
pub fn clipped_restitution(zeta: f64) -> f64 {
    if zeta <= 0.0 {
        return 1.0;
    }
    // Units omega0 = 1, v0 = 1: x(0) = 0, x'(0) = 1; e = x(t_end) / (2 zeta).
    let x_end = if zeta < 1.0 {
        let wd = (1.0 - zeta * zeta).sqrt();
        // sin(wd t) (1 - 2 zeta^2) + 2 zeta wd cos(wd t) = 0, first root in (0, pi).
        let phase = (2.0 * zeta * wd).atan2(-(1.0 - 2.0 * zeta * zeta));
        (-zeta * phase / wd).exp() * phase.sin() / wd
    } else if zeta == 1.0 {
        // x = t e^-t, force (2 - t) e^-t: ends at t = 2.
        2.0 * (-2.0f64).exp()
    } else {
        // Roots r1 = -zeta + s, r2 = -zeta - s, written without cancellation
        // (r1 r2 = 1): 1 + 2 zeta r1 = -1/(zeta + s)^2.
        let s = (zeta * zeta - 1.0).sqrt();
        let (r1, r2) = (-1.0 / (zeta + s), -zeta - s);
        // (1 + 2 zeta r1) e^(r1 t) = (1 + 2 zeta r2) e^(r2 t).
        let t = ((2.0 * zeta * (zeta + s) - 1.0) * (zeta + s).powi(2)).ln() / (r1 - r2);
        ((r1 * t).exp() - (r2 * t).exp()) / (r1 - r2)
    };
    x_end / (2.0 * zeta)
}

/// The damping ratio whose [`clipped_restitution`] is `e` (clamped to
/// `[1e-12, 1]`): 0 for `e = 1`.
pub fn damping_ratio_for_restitution(e: f64) -> f64 {
    let e = e.clamp(1e-12, 1.0);
    if e >= 1.0 {
        return 0.0;
    }
    // e(1e-17) = 1 - 3e-17 rounds to 1 > e; e(1e7) ~ 2.5e-15 < 1e-12.
    let (mut lo, mut hi) = ((1e-17f64).ln(), (1e7f64).ln());
    for _ in 0..70 {
        let mid = 0.5 * (lo + hi);
        if clipped_restitution(mid.exp()) > e {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (0.5 * (lo + hi)).exp()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Head-on collision of the clipped linear spring-dashpot, integrated
    /// by velocity Verlet with a fine step: the restitution it ends with.
    fn integrated_restitution(zeta: f64) -> f64 {
        let dt = 1e-5;
        let (mut x, mut v) = (0.0f64, 1.0f64);
        let force = |x: f64, v: f64| (-(x + 2.0 * zeta * v)).min(0.0);
        loop {
            let vh = v + 0.5 * dt * force(x, v);
            x += dt * vh;
            v = vh + 0.5 * dt * force(x, vh);
            if x > 0.0 && x + 2.0 * zeta * v <= 0.0 {
                return -v;
            }
        }
    }

    #[test]
    fn clipped_restitution_matches_an_integrated_collision_in_every_regime() {
        for zeta in [0.01, 0.2, 0.69, 0.707, 0.99, 1.0, 1.01, 2.0, 5.0] {
            let (e, num) = (clipped_restitution(zeta), integrated_restitution(zeta));
            assert!((e - num).abs() < 1e-4, "zeta {zeta}: {e} vs {num}");
        }
        assert!((clipped_restitution(1.0) - (-2.0f64).exp()).abs() < 1e-15);
    }

    #[test]
    fn the_damping_ratio_gives_the_restitution_asked_for() {
        for e in [1e-12, 1e-3, 0.05, 0.1, 0.5, 0.9, 0.999_999] {
            let zeta = damping_ratio_for_restitution(e);
            assert!((clipped_restitution(zeta) / e - 1.0).abs() < 1e-12, "e {e}");
        }
        assert_eq!(damping_ratio_for_restitution(1.0), 0.0);
        // Near critical damping both closed forms lose digits (sqrt(1 - zeta^2)).
        assert!((damping_ratio_for_restitution((-2.0f64).exp()) - 1.0).abs() < 1e-6);
    }
}
