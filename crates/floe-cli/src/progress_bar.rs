//! Progress of a long run: an indicatif bar on a terminal (simulated time,
//! steps per second, ETA), plain log lines every 10 % otherwise (batch jobs
//! whose standard error goes to a file); likewise for the frames of a
//! render ([`CountProgress`]).

use std::io::IsTerminal;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use floe_dem::run::{format_sim_time, Progress};

/// Progress on standard error.
pub struct RunProgress {
    bar: Option<ProgressBar>,
    started: Instant,
    first_step: u64,
    last_message: Instant,
    next_log_fraction: f64,
    end_time_s: f64,
}

impl RunProgress {
    /// Progress from `first_step` to `total_steps` (simulated end `end_time_s`);
    /// a bar if standard error is a terminal and `show` is set, log lines if
    /// it is not, nothing if `show` is false.
    pub fn new(first_step: u64, total_steps: u64, end_time_s: f64, show: bool) -> Self {
        let bar = (show && std::io::stderr().is_terminal()).then(|| {
            let bar = ProgressBar::with_draw_target(
                Some(total_steps),
                ProgressDrawTarget::stderr_with_hz(4),
            );
            bar.set_style(
                ProgressStyle::with_template(
                    "{bar:30} {pos}/{len} steps  t = {msg}  {per_sec}  ETA {eta}",
                )
                .expect("constant template")
                .progress_chars("=> "),
            );
            bar.set_position(first_step);
            bar.reset_eta();
            bar
        });
        Self {
            bar,
            started: Instant::now(),
            first_step,
            last_message: Instant::now() - Duration::from_secs(1),
            next_log_fraction: if show { 0.1 } else { f64::INFINITY },
            end_time_s,
        }
    }
}

impl Progress for RunProgress {
    fn update(&mut self, step: u64, total_steps: u64, time_s: f64) {
        if let Some(bar) = &self.bar {
            bar.set_position(step);
            // Formatting allocates: only a few times a second.
            if self.last_message.elapsed() >= Duration::from_millis(250) {
                bar.set_message(format!(
                    "{} / {}",
                    format_sim_time(time_s),
                    format_sim_time(self.end_time_s)
                ));
                self.last_message = Instant::now();
            }
            return;
        }
        let fraction = step as f64 / total_steps.max(1) as f64;
        if fraction >= self.next_log_fraction {
            let rate = (step - self.first_step) as f64 / self.started.elapsed().as_secs_f64();
            crate::stderr::line(&format!(
                "step {step}/{total_steps} ({:.0} %), t = {}, {rate:.1} steps/s",
                100.0 * fraction,
                format_sim_time(time_s)
            ));
            while self.next_log_fraction <= fraction {
                self.next_log_fraction += 0.1;
            }
        }
    }

    fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.abandon();
        }
    }
}

/// Progress through a count of items (the frames of a render): a bar on a
/// terminal; otherwise log lines every 10 %, once the work has taken more
/// than a few seconds (short renders stay quiet).
pub struct CountProgress {
    what: &'static str,
    bar: Option<ProgressBar>,
    terminal: bool,
    started: Instant,
    next_log_fraction: f64,
}

impl CountProgress {
    /// Seconds before log lines start.
    const QUIET_S: f64 = 5.0;

    /// Progress through `what` (a plural noun: "frames").
    pub fn new(what: &'static str) -> Self {
        Self {
            what,
            bar: None,
            terminal: std::io::stderr().is_terminal(),
            started: Instant::now(),
            next_log_fraction: 0.1,
        }
    }

    /// `done` of `total` items are done.
    pub fn update(&mut self, done: usize, total: usize) {
        if self.terminal {
            let bar = self.bar.get_or_insert_with(|| {
                let bar = ProgressBar::with_draw_target(
                    Some(total as u64),
                    ProgressDrawTarget::stderr_with_hz(4),
                );
                let template = format!("{{bar:30}} {{pos}}/{{len}} {}  ETA {{eta}}", self.what);
                if let Ok(style) = ProgressStyle::with_template(&template) {
                    bar.set_style(style.progress_chars("=> "));
                }
                bar
            });
            bar.set_position(done as u64);
            if done >= total {
                bar.finish_and_clear();
            }
            return;
        }
        let fraction = done as f64 / total.max(1) as f64;
        let elapsed = self.started.elapsed().as_secs_f64();
        if fraction >= self.next_log_fraction && elapsed > Self::QUIET_S {
            crate::stderr::line(&format!(
                "{done}/{total} {} ({:.0} %), {:.1} s",
                self.what,
                100.0 * fraction,
                elapsed
            ));
        }
        while self.next_log_fraction <= fraction {
            self.next_log_fraction += 0.1;
        }
    }
}
