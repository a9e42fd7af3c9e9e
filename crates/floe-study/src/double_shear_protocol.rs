//! A double-shear scenario whose pusher follows a schedule (the paper's
//! slide-hold-slide and velocity steps) run through the DEM and, beside
//! it, as a spring-slider with the same law, normal load, series stiffness
//! and protocol: friction in time for both, and per hold or step the steady
//! friction before it, the peak after it and delta mu. [`event_windows`]
//! says where those are measured without running anything, for the
//! scenario's `[[output.window]]` tables to cover.

use floe_dem::motion_schedule::ScheduledMotion;
use floe_friction::protocol::{Protocol, Segment};
use floe_friction::spring_slider::{Apparatus, SpringSlider};
use floe_scenario::Scenario;

use floe_run::Error;

/// Time step of the spring-slider, s (the paper's).
pub const SLIDER_DT_S: f64 = 1e-3;

/// A hold or a velocity step, and where it is measured.
#[derive(Debug, Clone, PartialEq)]
pub struct EventWindows {
    /// `hold 10 s`, `step to 0.08 m/s`.
    pub what: String,
    /// When the hold or the step starts, s.
    pub start_s: f64,
    /// The window of the steady friction before it (up to 2 s), s.
    pub steady_window_s: (f64, f64),
    /// The window searched for the peak, s.
    pub peak_window_s: (f64, f64),
}

/// A hold or a velocity step, and what both models make of it.
#[derive(Debug, Clone, PartialEq)]
pub struct ProtocolEvent {
    /// `hold 10 s`, `step to 0.08 m/s`.
    pub what: String,
    /// When the hold or the step starts, s.
    pub start_s: f64,
    /// The window of the steady friction before it (up to 2 s), s.
    pub steady_window_s: (f64, f64),
    /// The window searched for the peak, s.
    pub peak_window_s: (f64, f64),
    /// Steady friction before the event (mean over the steady window): DEM, slider.
    pub steady: (f64, f64),
    /// Peak friction after it: DEM, slider.
    pub peak: (f64, f64),
}

impl ProtocolEvent {
    /// `peak - steady`: DEM, slider.
    pub fn delta_mu(&self) -> (f64, f64) {
        (self.peak.0 - self.steady.0, self.peak.1 - self.steady.1)
    }

    /// The DEM's relative difference from the slider in the peak and in
    /// delta mu.
    pub fn differences(&self) -> (f64, f64) {
        let (d, s) = self.delta_mu();
        ((self.peak.0 - self.peak.1) / self.peak.1, (d - s) / s)
    }
}

/// Both runs of a protocol.
#[derive(Debug, Clone, PartialEq)]
pub struct ProtocolRun {
    /// DEM friction: the push force over the normal load on both faces,
    /// `(t, mu)` every step.
    pub dem: Vec<(f64, f64)>,
    /// The spring-slider's friction, `(t, mu)` every [`SLIDER_DT_S`].
    pub slider: Vec<(f64, f64)>,
    /// The pusher's segments, `(velocity along the block at the segment's
    /// start, duration)`.
    pub segments: Vec<(f64, f64)>,
    /// Every hold and every step up in velocity.
    pub events: Vec<ProtocolEvent>,
}

/// Runs `scenario` (a double shear with `[[tessellation.segment]]`) and its
/// spring-slider. Call it on a rayon pool of the threads wanted.
pub fn run_protocol(scenario: &Scenario) -> Result<ProtocolRun, Error> {
    let (load, geometry) = scenario.double_shear().ok_or_else(not_protocol)?;
    let mut world = scenario.build()?.world;
    let scheduled = world.schedules().first().ok_or_else(not_protocol)?;
    let segments = segments_of(scheduled);
    // The slider's load point does what the pusher does, ramps included.
    let protocol = Protocol::new(
        scheduled
            .schedule
            .segments()
            .iter()
            .map(|g| Segment::ramp(g.velocity_start.x, g.velocity_end.x, g.duration_s))
            .collect(),
    )?;
    let pusher = world
        .floes()
        .handle_of(scheduled.floe_id)
        .ok_or_else(not_protocol)? as u32;
    let steps = (scenario.duration_s() / world.dt_s()).round() as usize;
    let mut dem = Vec::with_capacity(steps);
    for _ in 0..steps {
        world.step();
        let push: f64 = world
            .contacts()
            .iter()
            .filter(|c| c.a == pusher || c.b == pusher)
            .map(|c| c.normal_force_n)
            .sum();
        dem.push((world.time_s(), push / (2.0 * load)));
    }
    let apparatus = Apparatus::new(geometry.series_stiffness_n_per_m, 2.0 * load, SLIDER_DT_S)?;
    let law = scenario.contact_model().law.clone();
    let mut slider = SpringSlider::new(law, apparatus, segments[0].0);
    let mut reference = Vec::new();
    slider.run(&protocol, |p| reference.push((p.t_s, p.mu)));
    let events = events(&segments, &dem, &reference);
    Ok(ProtocolRun {
        dem,
        slider: reference,
        segments,
        events,
    })
}

fn not_protocol() -> Error {
    Error::Usage(
        "a protocol comparison needs a double-shear scenario whose pusher follows \
         [[tessellation.segment]] tables"
            .into(),
    )
}

/// The pusher's segments: `(velocity along the block at the start, duration)`.
fn segments_of(scheduled: &ScheduledMotion) -> Vec<(f64, f64)> {
    scheduled
        .schedule
        .segments()
        .iter()
        .map(|g| (g.velocity_start.x, g.duration_s))
        .collect()
}

/// Where the holds and steps of `scenario` (as [`run_protocol`] takes it)
/// are measured, without running it: what its `[[output.window]]` tables
/// must cover for the run file to show the same.
pub fn event_windows(scenario: &Scenario) -> Result<Vec<EventWindows>, Error> {
    scenario.double_shear().ok_or_else(not_protocol)?;
    let world = scenario.build()?.world;
    let scheduled = world.schedules().first().ok_or_else(not_protocol)?;
    Ok(windows_of(&segments_of(scheduled)))
}

/// The holds (a stop after sliding) and steps up in velocity of
/// `segments`. A hold's peak is in the slide after it; a step's in the
/// step's own segment. The steady level is taken over up to 2 s before.
fn windows_of(segments: &[(f64, f64)]) -> Vec<EventWindows> {
    let mut out = Vec::new();
    let mut t = 0.0;
    for (k, &(v, d)) in segments.iter().enumerate() {
        let before = if k > 0 { segments[k - 1].0 } else { 0.0 };
        let event = if before > 0.0 && v == 0.0 {
            segments
                .get(k + 1)
                .map(|next| (format!("hold {d} s"), (t + d, t + d + next.1)))
        } else if before > 0.0 && v > before {
            Some((format!("step to {v} m/s"), (t, t + d)))
        } else {
            None
        };
        if let Some((what, window)) = event {
            let settle = 2.0f64.min(0.1 * t);
            out.push(EventWindows {
                what,
                start_s: t,
                steady_window_s: (t - settle, t),
                peak_window_s: window,
            });
        }
        t += d;
    }
    out
}

/// The events of `segments`, measured in both series.
fn events(
    segments: &[(f64, f64)],
    dem: &[(f64, f64)],
    slider: &[(f64, f64)],
) -> Vec<ProtocolEvent> {
    windows_of(segments)
        .into_iter()
        .map(|e| {
            let (t0, t1) = e.steady_window_s;
            let window = e.peak_window_s;
            ProtocolEvent {
                steady: (mean(dem, t0, t1), mean(slider, t0, t1)),
                peak: (peak(dem, window), peak(slider, window)),
                what: e.what,
                start_s: e.start_s,
                steady_window_s: e.steady_window_s,
                peak_window_s: window,
            }
        })
        .collect()
}

/// Mean of `series` over `[t0, t1)`.
fn mean(series: &[(f64, f64)], t0: f64, t1: f64) -> f64 {
    let (sum, n) = series
        .iter()
        .filter(|s| s.0 >= t0 && s.0 < t1)
        .fold((0.0, 0usize), |(sum, n), s| (sum + s.1, n + 1));
    sum / n as f64
}

/// Largest value of `series` over `[t0, t1)`.
fn peak(series: &[(f64, f64)], (t0, t1): (f64, f64)) -> f64 {
    series
        .iter()
        .filter(|s| s.0 >= t0 && s.0 < t1)
        .map(|s| s.1)
        .fold(f64::NEG_INFINITY, f64::max)
}
