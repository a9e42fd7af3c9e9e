//! The paper's spring-slider experiments: apparatus presets, slide-hold-slide
//! tests (Figs. 6-7) and velocity steps.

use serde::{Deserialize, Serialize};

use crate::any_law::Law;
use crate::law::FrictionLaw;
pub use crate::params::Preset;
use crate::protocol::{Protocol, Segment};
use crate::spring_slider::{Apparatus, SpringSlider};

/// Default time step of the paper's spring-slider model (section 4), s.
pub const PAPER_DT_S: f64 = 1e-3;

impl Preset {
    /// Apparatus stiffness, N/m.
    pub fn stiffness_n_per_m(self) -> f64 {
        match self {
            Preset::Lab => 20e6,
            Preset::Tank => 2e6,
        }
    }

    /// Effective normal load (both sliding faces), N.
    pub fn normal_load_n(self) -> f64 {
        match self {
            Preset::Lab => 2e3,
            Preset::Tank => 10e3,
        }
    }

    /// Load-point speed of the hold tests, m/s.
    pub fn speed_m_per_s(self) -> f64 {
        match self {
            Preset::Lab => 1e-4,
            Preset::Tank => 8e-3,
        }
    }

    /// The apparatus with time step `dt_s`.
    pub fn apparatus(self, dt_s: f64) -> Apparatus {
        Apparatus {
            stiffness_n_per_m: self.stiffness_n_per_m(),
            normal_load_n: self.normal_load_n(),
            dt_s,
        }
    }

    /// Hold times of the paper (s): lab 1-1000 s, tank 10-1000 s.
    pub fn paper_hold_times_s(self) -> &'static [f64] {
        match self {
            Preset::Lab => &[1.0, 10.0, 100.0, 1000.0],
            Preset::Tank => &[10.0, 100.0, 1000.0],
        }
    }
}

/// Result of one slide-hold-slide test.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HoldResult {
    /// Hold time, s.
    pub hold_s: f64,
    /// Steady-state friction before the hold.
    pub mu_ss: f64,
    /// Peak friction on reslide.
    pub mu_peak: f64,
    /// `mu_peak - mu_ss`.
    pub delta_mu: f64,
    /// Lowest friction during the hold (negative when the spring pushes back,
    /// as it does in the published form).
    pub mu_min_hold: f64,
}

/// Slip distances (in units of `L`) used to settle before and after a transient.
const SETTLE_SLIPS: f64 = 20.0;

/// Characteristic slip distance of a law, m (the one that sets how long
/// transients last): `L` for rate-and-state, else 1 mm.
fn transient_slip_m(law: &Law) -> f64 {
    match law {
        Law::RateState(r) => r.params.critical_slip_m,
        _ => 1e-3,
    }
}

/// Most time steps a spring-slider command takes unless told otherwise
/// (about 2 minutes at 110 ns a step): far more than any of the paper's
/// experiments, and a guard against a hold or a speed that would run for
/// days.
pub const MAX_SLIDER_STEPS: f64 = 1e9;

/// Fastest load point a spring-slider command accepts, m/s: the paper's
/// speeds are 1e-6 to 1e-2 m/s; beyond this the numbers mean nothing.
pub const MAX_LOAD_POINT_SPEED_M_PER_S: f64 = 100.0;

/// Longest spring-slider time step accepted, s (the paper's is 1e-3 s).
pub const MAX_SLIDER_DT_S: f64 = 1.0;

/// Range of spring-slider stiffnesses accepted, N/m (the paper's are
/// 2 and 20 MN/m).
pub const SLIDER_STIFFNESS_RANGE_N_PER_M: (f64, f64) = (1e-3, 1e12);

/// Range of spring-slider normal loads accepted, N (the paper's are 2 kN
/// and 10 kN); below it friction forces underflow against the spring's.
pub const SLIDER_NORMAL_LOAD_RANGE_N: (f64, f64) = (1e-3, 1e12);

/// Simulated time of [`hold_test`], s: the slide to steady state, the hold
/// and the reslide (the part of it that reloads the spring taken at its
/// largest, `mu_ss N / k`).
pub fn hold_test_duration_s(
    law: &Law,
    apparatus: Apparatus,
    speed_m_per_s: f64,
    hold_s: f64,
) -> f64 {
    let l = transient_slip_m(law);
    let reload_m =
        law.mu_steady(speed_m_per_s).abs() * apparatus.normal_load_n / apparatus.stiffness_n_per_m;
    (2.0 * SETTLE_SLIPS * l + reload_m) / speed_m_per_s + hold_s
}

/// Simulated time of [`velocity_step`], s.
pub fn velocity_step_duration_s(law: &Law, from_m_per_s: f64, to_m_per_s: f64) -> f64 {
    let l = transient_slip_m(law);
    SETTLE_SLIPS * l / from_m_per_s.abs() + 2.0 * SETTLE_SLIPS * l / to_m_per_s.abs()
}

/// Slide at `speed` to steady state, hold for `hold_s`, reslide at `speed`.
///
/// The slider starts in steady state and slides a further 20 `L` before the
/// hold; the reslide lasts long enough to reload the spring and slide 20 `L`.
pub fn hold_test(law: Law, apparatus: Apparatus, speed_m_per_s: f64, hold_s: f64) -> HoldResult {
    let l = transient_slip_m(&law);
    let settle_s = SETTLE_SLIPS * l / speed_m_per_s;
    let mut slider = SpringSlider::new(law, apparatus, speed_m_per_s);
    let pre =
        Protocol::new(vec![Segment::constant(speed_m_per_s, settle_s)]).expect("valid pre-slide");
    slider.run(&pre, |_| {});
    let mu_ss = slider.sample().mu;

    let mut mu_min_hold = mu_ss;
    let hold = Protocol::new(vec![Segment::hold(hold_s)]).expect("valid hold");
    slider.run(&hold, |s| mu_min_hold = mu_min_hold.min(s.mu));

    let reload_m = (mu_ss - slider.sample().mu).max(0.0) * apparatus.normal_load_n
        / apparatus.stiffness_n_per_m;
    let reslide_s = (SETTLE_SLIPS * l + reload_m) / speed_m_per_s;
    let mut mu_peak = f64::NEG_INFINITY;
    let reslide =
        Protocol::new(vec![Segment::constant(speed_m_per_s, reslide_s)]).expect("valid reslide");
    slider.run(&reslide, |s| mu_peak = mu_peak.max(s.mu));
    HoldResult {
        hold_s,
        mu_ss,
        mu_peak,
        delta_mu: mu_peak - mu_ss,
        mu_min_hold,
    }
}

/// Result of a velocity step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StepResult {
    /// Steady-state friction at the first speed.
    pub mu_ss_before: f64,
    /// Extreme friction of the transient: the maximum after a step up, the
    /// minimum after a step down.
    pub mu_peak: f64,
    /// Friction at the end of the run at the second speed (steady state if the
    /// system is stable; see `RateStateParams::critical_stiffness_n_per_m`).
    pub mu_ss_after: f64,
    /// Analytic steady state at the second speed, for comparison.
    pub mu_ss_after_analytic: f64,
}

/// Steady sliding at `from`, then a step of the load point to `to` (m/s), run
/// for 40 `L` of slip at the new speed.
pub fn velocity_step(
    law: Law,
    apparatus: Apparatus,
    from_m_per_s: f64,
    to_m_per_s: f64,
) -> StepResult {
    let l = transient_slip_m(&law);
    let mut slider = SpringSlider::new(law.clone(), apparatus, from_m_per_s);
    let pre = Protocol::new(vec![Segment::constant(
        from_m_per_s,
        SETTLE_SLIPS * l / from_m_per_s,
    )])
    .expect("valid pre-slide");
    slider.run(&pre, |_| {});
    let mu_ss_before = slider.sample().mu;
    let up = to_m_per_s.abs() >= from_m_per_s.abs();
    let mut mu_peak = mu_ss_before;
    let post = Protocol::new(vec![Segment::constant(
        to_m_per_s,
        2.0 * SETTLE_SLIPS * l / to_m_per_s.abs(),
    )])
    .expect("valid step");
    slider.run(&post, |s| {
        mu_peak = if up {
            mu_peak.max(s.mu)
        } else {
            mu_peak.min(s.mu)
        }
    });
    StepResult {
        mu_ss_before,
        mu_peak,
        mu_ss_after: slider.sample().mu,
        mu_ss_after_analytic: law.mu_steady(to_m_per_s),
    }
}

/// Peak-to-peak amplitude of `mu` over the last quarter of a long run at
/// constant load-point speed, started from steady state perturbed by a 1 %
/// kick in spring force. Near zero for stable sliding; order `0.1` in
/// stick-slip.
pub fn late_oscillation_amplitude(
    law: Law,
    apparatus: Apparatus,
    speed_m_per_s: f64,
    slips: f64,
) -> f64 {
    let l = transient_slip_m(&law);
    let mut slider = SpringSlider::new(law, apparatus, speed_m_per_s);
    // Kick: a short 10x speed-up of the load point, 1 % of L.
    let kick = Protocol::new(vec![Segment::constant(
        10.0 * speed_m_per_s,
        0.01 * l / (10.0 * speed_m_per_s),
    )])
    .expect("valid kick");
    slider.run(&kick, |_| {});
    let total_s = slips * l / speed_m_per_s;
    let t_start_window = slider.sample().t_s + 0.75 * total_s;
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let run = Protocol::new(vec![Segment::constant(speed_m_per_s, total_s)]).expect("valid run");
    slider.run(&run, |s| {
        if s.t_s >= t_start_window {
            lo = lo.min(s.mu);
            hi = hi.max(s.mu);
        }
    });
    hi - lo
}
