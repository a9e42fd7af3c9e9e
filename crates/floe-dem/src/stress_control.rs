//! A stress-controlled wall: the prescribed floes of a wall that moves
//! across itself so as to hold a set compressive normal stress while the
//! ice dilates or compacts (a constant-pressure shear cell).
//!
//! `sigma` is the compressive stress on the wall, N/m (vertically
//! integrated): minus the contact forces on its pieces along the inward
//! normal, over the wall's length `L`. Two laws move the wall:
//!
//! - [`ServoWall`] (the default of scenario files): the wall has a mass
//!   and obeys Newton's law under the stress error, as the walls of
//!   constant-pressure granular cells do (da Cruz et al. 2005), damped by
//!   the rate of change of the stress it feels:
//!   `M dv/dt = L (sigma_target - sigma) - D L dsigma_f/dt`, with
//!   `sigma_f` the stress low-passed over a time `T_f`
//!   (`dsigma_f/dt = (sigma - sigma_f) / T_f`). On a pack of stiffness `K`
//!   (`dsigma/dt = K v / L`) the last term is a dashpot of about `c = D K`
//!   on the wall's oscillation; unlike a dashpot on the wall's speed, it
//!   sums to `D L dsigma_f` over any window, so that
//!   `L <sigma_target - sigma> T = M dv + D L dsigma_f`: the mean stress
//!   over a window of `T` seconds equals the target to within
//!   `(M |dv| / L + D |dsigma_f|) / T` whenever the wall's speed stays
//!   bounded, also while the ice keeps dilating. The step's update holds
//!   this identity exactly up to rounding. The low pass keeps the
//!   contacts' dashpots, whose force follows the wall's speed at once, from
//!   closing a loop that flips the speed every step (`D c_contact / M > 1`
//!   without it).
//! - [`ControlLaw::Proportional`]: `v_n = G (sigma_target - sigma)`, a
//!   speed proportional to the error (integral control of the position):
//!   the mean stress is the target only once the wall's mean speed is zero.
//!
//! Stability: on a pack of normal stiffness `K` (N/m: `kappa` times the
//! contact length, `kappa = E h / sqrt(area)` the wall contact's stiffness
//! per unit area), the servo wall is an oscillator of `omega^2 = K / M`
//! and damping ratio `zeta = D K / (2 sqrt(K M))`, integrated by the
//! symplectic Euler of the step together with the stress filter and the
//! contacts' dashpots: stable when every eigenvalue of its step matrix
//! lies inside the unit circle ([`ServoWall::is_stable`],
//! [`ServoWall::stability_margin`]; undamped, `omega dt < 2`). The proportional law
//! is stable for `G dt kappa < 2` and `G c' < 1`, `c'` the contacts'
//! dashpot per unit length.

use crate::contact_kernel::force_and_torques;
use crate::contacts::ContactRecord;
use crate::error::DemError;
use crate::floes::Floes;
use crate::Vec2;

/// A wall (its pieces) holding a normal stress.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StressControl {
    /// Global ids of the wall's pieces (prescribed floes), increasing.
    pub floe_ids: Vec<u64>,
    /// Unit normal from the wall into the ice.
    pub inward_normal: Vec2,
    /// Length of the wall that carries the stress, m.
    pub length_m: f64,
    /// Compressive normal stress to hold, N/m (>= 0).
    pub target_stress_n_per_m: f64,
    /// How the wall moves, with its state.
    pub law: ControlLaw,
}

/// How a stress-controlled wall moves for a stress error.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum ControlLaw {
    /// Inward speed `G (sigma_target - sigma)`.
    Proportional {
        /// `G`: inward wall speed per unit stress deficit, (m/s)/(N/m).
        gain_m_per_s_per_n_per_m: f64,
    },
    /// A wall with mass and damping ([`ServoWall`]).
    Servo(ServoWall),
}

/// A wall with mass `M`, damped by `D` times the rate of change of the
/// stress it feels low-passed over `T_f` (module docs), and its state.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ServoWall {
    /// `M`, the whole wall's mass in the control law, kg.
    pub mass_kg: f64,
    /// `D`, the damping per unit rate of stress, s.
    pub stress_damping_s: f64,
    /// `T_f`, the time over which the stress is low-passed, s.
    pub stress_filter_s: f64,
    /// `v`, the inward normal speed of the step just taken, m/s.
    pub speed_m_per_s: f64,
    /// `sigma_f`, N/m; NaN before the first step.
    pub filtered_stress_n_per_m: f64,
}

impl ServoWall {
    /// A servo wall at rest; its mass and filter time must be finite and
    /// > 0, its damping finite and >= 0.
    pub fn new(
        mass_kg: f64,
        stress_damping_s: f64,
        stress_filter_s: f64,
    ) -> Result<Self, DemError> {
        if !(mass_kg.is_finite() && mass_kg > 0.0) {
            return invalid("mass_kg", mass_kg, "must be a finite number > 0");
        }
        if !(stress_damping_s.is_finite() && stress_damping_s >= 0.0) {
            return invalid(
                "stress_damping_s",
                stress_damping_s,
                "must be a finite number >= 0",
            );
        }
        if !(stress_filter_s.is_finite() && stress_filter_s > 0.0) {
            return invalid(
                "stress_filter_s",
                stress_filter_s,
                "must be a finite number > 0",
            );
        }
        Ok(ServoWall {
            mass_kg,
            stress_damping_s,
            stress_filter_s,
            speed_m_per_s: 0.0,
            filtered_stress_n_per_m: f64::NAN,
        })
    }

    /// The wall after a step of `dt_s` that began under the stress
    /// `stress_n_per_m` (N/m), for a target `target_n_per_m` over the
    /// length `length_m`: the filtered stress moves towards the stress
    /// (exactly for a stress constant over the step; it starts at the first
    /// stress), and the speed for the coming drift is the last one plus
    /// `dt / M` times the push `L (target - sigma) - D L (sigma_f_new -
    /// sigma_f) / dt`.
    pub fn advanced(
        &self,
        stress_n_per_m: f64,
        target_n_per_m: f64,
        length_m: f64,
        dt_s: f64,
    ) -> ServoWall {
        let before = if self.filtered_stress_n_per_m.is_nan() {
            stress_n_per_m
        } else {
            self.filtered_stress_n_per_m
        };
        let after =
            stress_n_per_m + (before - stress_n_per_m) * (-dt_s / self.stress_filter_s).exp();
        let push = length_m * (target_n_per_m - stress_n_per_m)
            - self.stress_damping_s * length_m * (after - before) / dt_s;
        ServoWall {
            speed_m_per_s: self.speed_m_per_s + dt_s / self.mass_kg * push,
            filtered_stress_n_per_m: after,
            ..*self
        }
    }

    /// The step's update matrix for the wall on a linear pack of normal
    /// stiffness `stiffness_n_per_m` and dashpot `dashpot_n_s_per_m` (the
    /// stress at the start of a step is `(K x + C v) / L`, `v` the speed of
    /// the step just taken) at time step `dt_s`, acting on the departures
    /// `(x, v, y)` from equilibrium of the wall's position, its speed and
    /// the filtered stress expressed as a position (`y = L sigma_f / K`),
    /// rows for `(x', v', y')`.
    pub fn step_matrix(
        &self,
        (stiffness_n_per_m, dashpot_n_s_per_m): (f64, f64),
        dt_s: f64,
    ) -> [[f64; 3]; 3] {
        let h = dt_s;
        let (k, c) = (
            stiffness_n_per_m / self.mass_kg,
            dashpot_n_s_per_m / self.mass_kg,
        );
        let lag = dashpot_n_s_per_m / stiffness_n_per_m;
        let e = (-dt_s / self.stress_filter_s).exp();
        let g = self.stress_damping_s * k * (1.0 - e);
        let v_row = [-(h * k + g), 1.0 - h * c - g * lag, g];
        [
            [1.0 + h * v_row[0], h * v_row[1], h * v_row[2]],
            v_row,
            [1.0 - e, (1.0 - e) * lag, e],
        ]
    }

    /// Whether the step integrates the wall stably on a linear pack of
    /// stiffness and dashpot `pack` (N/m, N s/m) at `dt_s`: every eigenvalue
    /// of [`ServoWall::step_matrix`] inside the unit circle (Jury's test on
    /// its characteristic cubic; without any damping, `omega dt < 2`).
    pub fn is_stable(&self, pack: (f64, f64), dt_s: f64) -> bool {
        if self.stress_damping_s == 0.0 && pack.1 == 0.0 {
            // Undamped: the symplectic Euler's eigenvalues lie on the unit
            // circle (bounded) up to omega dt = 2.
            return self.omega_dt(pack.0, dt_s) < 2.0;
        }
        let m = self.step_matrix(pack, dt_s);
        // p(z) = z^3 + a2 z^2 + a1 z + a0 = det(z I - m).
        let trace = m[0][0] + m[1][1] + m[2][2];
        let minors = m[0][0] * m[1][1] - m[0][1] * m[1][0] + m[0][0] * m[2][2] - m[0][2] * m[2][0]
            + m[1][1] * m[2][2]
            - m[1][2] * m[2][1];
        let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        let (a2, a1, a0) = (-trace, minors, -det);
        let p = |z: f64| ((z + a2) * z + a1) * z + a0;
        p(1.0) > 0.0
            && -p(-1.0) > 0.0
            && a0.abs() < 1.0
            && (a0 * a0 - 1.0).abs() > (a0 * a2 - a1).abs()
    }

    /// How many times stiffer than `pack` (stiffness and dashpot scaled
    /// together, N/m and N s/m) a pack may be for the step to stay stable
    /// at `dt_s` (bisection on [`ServoWall::is_stable`] to 1e-6).
    pub fn stability_margin(&self, pack: (f64, f64), dt_s: f64) -> f64 {
        let scaled = |f: f64| (f * pack.0, f * pack.1);
        let mut hi = 1.0;
        while self.is_stable(scaled(hi), dt_s) {
            hi *= 2.0;
            if hi > 1e12 {
                return hi;
            }
        }
        let mut lo = 0.0;
        while hi - lo > 1e-6 * hi {
            let mid = 0.5 * (lo + hi);
            if self.is_stable(scaled(mid), dt_s) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    }

    /// The damping ratio `zeta = D K / (2 sqrt(K M))` on a pack of normal
    /// stiffness `stiffness_n_per_m` (for a filter much faster than the
    /// wall's oscillation).
    pub fn damping_ratio(&self, stiffness_n_per_m: f64) -> f64 {
        self.stress_damping_s * stiffness_n_per_m
            / (2.0 * (stiffness_n_per_m * self.mass_kg).sqrt())
    }

    /// `omega dt` on a pack of normal stiffness `stiffness_n_per_m` at time
    /// step `dt_s`, `omega = sqrt(K / M)`.
    pub fn omega_dt(&self, stiffness_n_per_m: f64, dt_s: f64) -> f64 {
        (stiffness_n_per_m / self.mass_kg).sqrt() * dt_s
    }
}

/// A parameter refused: `name` is `value`, and should be what `reason`
/// says.
fn invalid<T>(name: &'static str, value: f64, reason: &'static str) -> Result<T, DemError> {
    Err(DemError::InvalidParameter {
        name,
        value,
        reason,
    })
}

impl StressControl {
    /// Checks the parts: pieces given in increasing id order, a unit
    /// normal, a length > 0, a target >= 0, a gain > 0, all finite.
    pub fn new(
        floe_ids: Vec<u64>,
        inward_normal: Vec2,
        length_m: f64,
        target_stress_n_per_m: f64,
        law: ControlLaw,
    ) -> Result<Self, DemError> {
        if floe_ids.is_empty() || floe_ids.windows(2).any(|w| w[0] >= w[1]) {
            return invalid(
                "floe_ids",
                floe_ids.len() as f64,
                "must be increasing, at least one",
            );
        }
        let unit = (inward_normal.length() - 1.0).abs() < 1e-9;
        if !unit {
            return invalid(
                "inward_normal",
                inward_normal.length(),
                "must be a unit vector",
            );
        }
        if !(length_m.is_finite() && length_m > 0.0) {
            return invalid("length_m", length_m, "must be a finite number > 0");
        }
        if !(target_stress_n_per_m.is_finite() && target_stress_n_per_m >= 0.0) {
            return invalid(
                "target_stress_n_per_m",
                target_stress_n_per_m,
                "must be a finite number >= 0",
            );
        }
        match law {
            ControlLaw::Proportional {
                gain_m_per_s_per_n_per_m: g,
            } if !(g.is_finite() && g > 0.0) => {
                return invalid("gain_m_per_s_per_n_per_m", g, "must be a finite number > 0");
            }
            ControlLaw::Servo(s) => {
                ServoWall::new(s.mass_kg, s.stress_damping_s, s.stress_filter_s)?;
                if !s.speed_m_per_s.is_finite() || s.filtered_stress_n_per_m.is_infinite() {
                    return invalid("speed_m_per_s", s.speed_m_per_s, "must be finite");
                }
            }
            _ => {}
        }
        Ok(StressControl {
            floe_ids,
            inward_normal,
            length_m,
            target_stress_n_per_m,
            law,
        })
    }

    /// The compressive stress on the wall, N/m, from the total forces on
    /// its pieces (`force_of(id)`, N).
    pub fn stress(&self, force_of: impl Fn(u64) -> Vec2) -> f64 {
        let total = self
            .floe_ids
            .iter()
            .fold(Vec2::ZERO, |sum, &id| sum + force_of(id));
        -total.dot(self.inward_normal) / self.length_m
    }

    /// The compressive stress on the wall, N/m, summed from the contact
    /// records between its pieces and other floes (each contact's force as
    /// [`force_and_torques`] gives it): the stress measured independently of
    /// the gathered forces the control reads.
    pub fn stress_from_contacts(&self, floes: &Floes, contacts: &[ContactRecord]) -> f64 {
        let on_wall = |h: u32| self.floe_ids.binary_search(&floes.id[h as usize]).is_ok();
        let mut push = 0.0;
        for c in contacts {
            let (a_on, b_on) = (on_wall(c.a), on_wall(c.b));
            if a_on == b_on {
                continue;
            }
            let pb = floes.position[c.b as usize] + c.image_offset;
            let (force_on_b, _, _) = force_and_torques(c, floes.position[c.a as usize], pb);
            let on_wall = if b_on { force_on_b } else { -force_on_b };
            push -= on_wall.dot(self.inward_normal);
        }
        push / self.length_m
    }

    /// The wall's inward normal speed over the coming step of `dt_s`, for
    /// the stress `stress_n_per_m` measured at its start, without changing
    /// the control's state.
    pub fn next_speed(&self, stress_n_per_m: f64, dt_s: f64) -> f64 {
        match &self.law {
            ControlLaw::Proportional {
                gain_m_per_s_per_n_per_m,
            } => gain_m_per_s_per_n_per_m * (self.target_stress_n_per_m - stress_n_per_m),
            ControlLaw::Servo(s) => {
                s.advanced(
                    stress_n_per_m,
                    self.target_stress_n_per_m,
                    self.length_m,
                    dt_s,
                )
                .speed_m_per_s
            }
        }
    }

    /// [`StressControl::next_speed`], taking the step: a servo wall's state
    /// moves on.
    pub fn advance(&mut self, stress_n_per_m: f64, dt_s: f64) -> f64 {
        let speed = self.next_speed(stress_n_per_m, dt_s);
        if let ControlLaw::Servo(s) = &mut self.law {
            *s = s.advanced(
                stress_n_per_m,
                self.target_stress_n_per_m,
                self.length_m,
                dt_s,
            );
        }
        speed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn servo(mass: f64, damping_s: f64) -> StressControl {
        let law =
            ControlLaw::Servo(ServoWall::new(mass, damping_s, 0.25 * damping_s.max(1e-3)).unwrap());
        StressControl::new(vec![1], Vec2::Y, 2.0, 100.0, law).unwrap()
    }

    /// The wall at inward position `x` on a pack of stiffness `k` (N/m):
    /// the stress is `k x / L` once it presses (x > 0).
    fn spring_run(c: &mut StressControl, k: f64, dt: f64, steps: usize) -> Vec<(f64, f64)> {
        let mut x = 0.0;
        (0..steps)
            .map(|_| {
                let stress = (k * x / c.length_m).max(0.0);
                let v = c.advance(stress, dt);
                x += v * dt;
                (x, stress)
            })
            .collect()
    }

    #[test]
    fn the_mean_stress_error_is_exactly_the_walls_change_of_momentum_and_stress() {
        // Any stress history (here a noisy stick-slip saw-tooth).
        let mut c = servo(3.0e4, 7.0);
        let dt = 0.37;
        let mut error_sum = 0.0;
        let mut state = 0.123_f64;
        let mut first = None;
        for n in 0..20_000 {
            state = (state * 3.9 * (1.0 - state)).clamp(1e-3, 1.0 - 1e-3);
            let stress =
                100.0 * (1.0 + 0.5 * ((n % 97) as f64 / 97.0 - 0.5)) + 30.0 * (state - 0.5);
            c.advance(stress, dt);
            error_sum += dt * c.length_m * (c.target_stress_n_per_m - stress);
            first.get_or_insert(stress);
        }
        let ControlLaw::Servo(s) = c.law else {
            unreachable!()
        };
        let change = s.mass_kg * s.speed_m_per_s
            + s.stress_damping_s * c.length_m * (s.filtered_stress_n_per_m - first.unwrap());
        assert!(
            (error_sum - change).abs() <= 1e-9 * error_sum.abs().max(change.abs()).max(1.0),
            "{error_sum} vs {change}"
        );
    }

    #[test]
    fn on_a_spring_the_wall_settles_at_the_target_with_the_analytic_period() {
        // Undamped: the wall oscillates about x = L sigma / k with omega =
        // sqrt(k / M) (symplectic Euler: 2 asin(omega dt / 2) per step).
        let (k, m, dt): (f64, f64, f64) = (5.0e4, 2.0e3, 0.05);
        let mut c = servo(m, 0.0);
        let run = spring_run(&mut c, k, dt, 40_000);
        let crossings: Vec<usize> = run
            .windows(2)
            .enumerate()
            .filter(|(_, w)| (w[0].1 - 100.0) < 0.0 && (w[1].1 - 100.0) >= 0.0)
            .map(|(n, _)| n)
            .collect();
        let period_steps =
            (crossings[crossings.len() - 1] - crossings[1]) as f64 / (crossings.len() - 2) as f64;
        let omega_dt = 2.0 * (0.5 * (k / m).sqrt() * dt).asin();
        let expected = std::f64::consts::TAU / omega_dt;
        assert!(
            (period_steps - expected).abs() < 0.01 * expected,
            "{period_steps} vs {expected}"
        );
        // Critically damped (D K = 2 sqrt(K M)): settles at the target
        // within a few periods, without overshoot beyond round-off.
        let mut c = servo(m, 2.0 * (m / k).sqrt());
        let run = spring_run(&mut c, k, dt, 4000);
        let last = run.last().unwrap().1;
        assert!((last - 100.0).abs() < 1e-6 * 100.0, "{last}");
        let peak = run.iter().map(|r| r.1).fold(0.0, f64::max);
        assert!(peak < 100.0 * (1.0 + 0.05), "overshoot {peak}");
    }

    #[test]
    fn the_stated_stability_limit_separates_bounded_from_growing() {
        // Stepping the wall on a linear spring and dashpot just below and
        // just above the stiffest stable pack that Jury's test on the step
        // matrix gives: bounded, then growing.
        let (m, dt): (f64, f64) = (2.0e3, 0.1);
        for (damping_s, filter_s, dashpot) in [
            (0.0, 1.0, 0.0),
            (0.5, 0.1, 0.0),
            (2.0, 0.5, 0.0),
            (8.0, 0.05, 0.0),
            (0.0, 1.0, 0.2),
            (4.0, 0.02, 0.1),
            (4.0, 1.0, 0.1),
        ] {
            let wall = ServoWall::new(m, damping_s, filter_s).unwrap();
            // A pack of 1e5 N/m and a dashpot of `dashpot` times critical
            // for the wall's mass, scaled together.
            let pack = (1e5, dashpot * 2.0 * (1e5 * m).sqrt());
            let f = wall.stability_margin(pack, dt);
            assert!(
                f > 0.0 && f * pack.0 <= 4.0 * m / (dt * dt) * (1.0 + 1e-9),
                "{f}"
            );
            let grows = |f: f64| {
                let law = ControlLaw::Servo(wall);
                let mut c = StressControl::new(vec![1], Vec2::Y, 2.0, 100.0, law).unwrap();
                let (k, dash) = (f * pack.0, f * pack.1);
                let (mut x, mut v) = (1e-3, 0.0);
                let (mut early, mut late): (f64, f64) = (0.0, 0.0);
                for n in 0..40_000 {
                    let stress = (k * x + dash * v) / c.length_m;
                    v = c.advance(stress, dt);
                    x += v * dt;
                    if !x.is_finite() {
                        return true;
                    }
                    let departure = (k * x / c.length_m - 100.0).abs();
                    if (1000..2000).contains(&n) {
                        early = early.max(departure);
                    } else if n >= 38_000 {
                        late = late.max(departure);
                    }
                }
                late > 10.0 * early
            };
            let case = format!("D {damping_s} T_f {filter_s} dashpot {dashpot}");
            assert!(!grows(0.97 * f), "{case}: below the margin {f}");
            assert!(grows(1.03 * f), "{case}: above the margin {f}");
        }
        // Undamped, the limit is the symplectic Euler's omega dt = 2.
        let wall = ServoWall::new(m, 0.0, 1.0).unwrap();
        let f = wall.stability_margin((1e5, 0.0), dt);
        assert!((wall.omega_dt(f * 1e5, dt) - 2.0).abs() < 1e-5);
    }

    #[test]
    fn the_proportional_law_is_the_speed_of_the_error() {
        let law = ControlLaw::Proportional {
            gain_m_per_s_per_n_per_m: 1e-4,
        };
        let mut c = StressControl::new(vec![3, 5], -Vec2::X, 10.0, 50.0, law).unwrap();
        assert_eq!(c.advance(30.0, 1.0), 2e-3);
        assert_eq!(c.law, law, "no state");
        let stress = c.stress(|id| Vec2::new(id as f64, 0.0));
        assert_eq!(stress, 0.8);
    }

    #[test]
    fn bad_parts_are_refused() {
        assert!(ServoWall::new(0.0, 1.0, 1.0).is_err());
        assert!(ServoWall::new(1.0, -1.0, 1.0).is_err());
        assert!(ServoWall::new(1.0, f64::INFINITY, 1.0).is_err());
        assert!(ServoWall::new(1.0, 1.0, 0.0).is_err());
        let law = ControlLaw::Proportional {
            gain_m_per_s_per_n_per_m: -1.0,
        };
        assert!(StressControl::new(vec![1], Vec2::Y, 1.0, 1.0, law).is_err());
    }
}
