//! The spring-slider of Lishman et al. (2011), eqs. 4a-4c: a slider on a
//! frictional interface, pulled through a spring by a load point.
//!
//! It is exactly one contact of the DEM: [`SpringSlider::advance`] calls the
//! same [`FrictionLaw::step`] as the engine.

use serde::{Deserialize, Serialize};

use crate::any_law::Law;
use crate::error::{positive, FrictionError};
use crate::law::{ContactLoad, ContactState, FrictionLaw};
use crate::protocol::Protocol;

/// The loading apparatus: spring, normal load and time step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Apparatus {
    /// Spring stiffness `k`, N/m.
    pub stiffness_n_per_m: f64,
    /// Effective normal load `N`, N (for double shear: twice the side load).
    pub normal_load_n: f64,
    /// Time step, s.
    pub dt_s: f64,
}

impl Apparatus {
    /// Checks stiffness, normal load and time step: finite and > 0.
    pub fn new(
        stiffness_n_per_m: f64,
        normal_load_n: f64,
        dt_s: f64,
    ) -> Result<Self, FrictionError> {
        Ok(Self {
            stiffness_n_per_m: positive("stiffness_n_per_m", stiffness_n_per_m)?,
            normal_load_n: positive("normal_load_n", normal_load_n)?,
            dt_s: positive("dt_s", dt_s)?,
        })
    }
}

/// One recorded instant of a spring-slider run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    /// Time, s.
    pub t_s: f64,
    /// Load-point displacement, m.
    pub load_point_m: f64,
    /// Slider displacement, m.
    pub slider_m: f64,
    /// Slider slip rate over the last step, m/s.
    pub slip_rate_m_per_s: f64,
    /// State variable `theta` (0 for laws without one).
    pub theta: f64,
    /// Friction coefficient `F / N`.
    pub mu: f64,
}

/// A spring-slider in motion.
#[derive(Debug, Clone)]
pub struct SpringSlider {
    law: Law,
    apparatus: Apparatus,
    state: ContactState,
    sample: Sample,
}

impl SpringSlider {
    /// A slider in steady sliding at `initial_velocity_m_per_s` (the load point
    /// and slider move together; spring force `mu_ss N`). At zero initial
    /// velocity, see [`FrictionLaw::steady_state`].
    pub fn new(law: Law, apparatus: Apparatus, initial_velocity_m_per_s: f64) -> Self {
        let state = law.steady_state(initial_velocity_m_per_s, apparatus.normal_load_n);
        let sample = Sample {
            t_s: 0.0,
            load_point_m: 0.0,
            slider_m: -state.tangential_force_n / apparatus.stiffness_n_per_m,
            slip_rate_m_per_s: initial_velocity_m_per_s,
            theta: law.theta(&state),
            mu: state.tangential_force_n / apparatus.normal_load_n,
        };
        Self {
            law,
            apparatus,
            state,
            sample,
        }
    }

    /// The law in use.
    pub fn law(&self) -> &Law {
        &self.law
    }

    /// The apparatus.
    pub fn apparatus(&self) -> &Apparatus {
        &self.apparatus
    }

    /// The latest sample.
    pub fn sample(&self) -> Sample {
        self.sample
    }

    /// The contact state (spring force, theta).
    pub fn contact(&self) -> ContactState {
        self.state
    }

    /// Advances one step of length `dt` during which the load point moves by
    /// `load_point_displacement_m`.
    #[inline]
    pub fn advance(&mut self, load_point_displacement_m: f64, dt: f64) -> Sample {
        let a = &self.apparatus;
        let load = ContactLoad {
            load_point_velocity_m_per_s: load_point_displacement_m / dt,
            stiffness_n_per_m: a.stiffness_n_per_m,
            normal_load_n: a.normal_load_n,
        };
        let out = self.law.step(&mut self.state, &load, dt);
        let s = &mut self.sample;
        s.t_s += dt;
        s.load_point_m += load_point_displacement_m;
        s.slider_m += out.slip_rate_m_per_s * dt;
        s.slip_rate_m_per_s = out.slip_rate_m_per_s;
        s.theta = self.law.theta(&self.state);
        s.mu = out.mu;
        *s
    }

    /// Runs a protocol with the apparatus time step, calling `observe` after
    /// every step (segment ends fall exactly on step ends: the last step of a
    /// segment is shortened if needed).
    pub fn run(&mut self, protocol: &Protocol, mut observe: impl FnMut(&Sample)) {
        let dt = self.apparatus.dt_s;
        for seg in protocol.segments() {
            let start = self.sample.t_s;
            let steps = ((seg.duration_s / dt) - 1e-9).ceil().max(1.0) as u64;
            for i in 0..steps {
                let t0 = i as f64 * dt;
                let t1 = if i + 1 == steps {
                    seg.duration_s
                } else {
                    t0 + dt
                };
                self.advance(seg.displacement_m(t0, t1), t1 - t0);
                // Times from step counts, not running sums, so that segment
                // ends and output times land on round numbers.
                self.sample.t_s = start + t1;
                observe(&self.sample);
            }
        }
    }

    /// Runs a protocol and returns samples spaced by at least `every_s`
    /// seconds (plus the first and the last).
    pub fn record(&mut self, protocol: &Protocol, every_s: f64) -> Vec<Sample> {
        let mut out = vec![self.sample];
        let mut thinning = OutputThinning::new(self.sample.t_s, every_s);
        self.run(protocol, |s| {
            if thinning.keep(s.t_s) {
                out.push(*s);
            }
        });
        if out.last().map(|s| s.t_s) != Some(self.sample.t_s) {
            out.push(self.sample);
        }
        out
    }
}

/// Which steps of a run to keep when output is wanted every `every_s`
/// seconds: the first step in each interval of that length after `t0_s`.
/// Step times come from step counts, so the small allowance absorbs their
/// rounding at interval boundaries.
#[derive(Debug, Clone, Copy)]
pub struct OutputThinning {
    t0_s: f64,
    every_s: f64,
    last_slot: f64,
}

impl OutputThinning {
    /// Thinning from time `t0_s` (already recorded) every `every_s` seconds.
    pub fn new(t0_s: f64, every_s: f64) -> Self {
        Self {
            t0_s,
            every_s,
            last_slot: 0.0,
        }
    }

    /// Whether the step ending at `t_s` should be kept.
    pub fn keep(&mut self, t_s: f64) -> bool {
        let slot = ((t_s - self.t0_s) / self.every_s + 1e-6).floor();
        let keep = slot > self.last_slot;
        if keep {
            self.last_slot = slot;
        }
        keep
    }
}
