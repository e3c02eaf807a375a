//! The progress of `foamgrain run`: a bar on a terminal, plain lines in a log, both with the
//! estimated time left of the coupled loop.
//!
//! The estimate is the mean time per coupling step since the loop started (not since the run
//! started: reading and locating 10⁶ particles takes as long as a coupling step) times the
//! steps left, less the time since the last step closed, so that it counts down between steps
//! (a coupling step of 10⁶ particles takes tens of seconds; the bar redraws every second).

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// When the coupled loop started and when its last step closed.
#[derive(Clone, Copy, Debug)]
pub struct LoopClock {
    /// The loop's start (until the loop announces it: when the clock was made).
    start: Instant,
    /// Whether the loop has announced its start.
    started: bool,
    /// When the last step closed.
    last: Option<Instant>,
    /// Steps done and in total.
    done: u64,
    total: u64,
}

impl LoopClock {
    /// A clock made at `now`, before the loop starts.
    pub fn new(now: Instant) -> LoopClock {
        LoopClock {
            start: now,
            started: false,
            last: None,
            done: 0,
            total: 0,
        }
    }

    /// The loop starts at `now` with `total` steps.
    pub fn start(&mut self, now: Instant, total: u64) {
        *self = LoopClock {
            started: true,
            total,
            ..LoopClock::new(now)
        };
    }

    /// Step `done` of `total` closed at `now`.
    pub fn step(&mut self, now: Instant, done: u64, total: u64) {
        self.last = Some(now);
        self.done = done;
        self.total = total;
    }

    /// Time left at `now`: (last − start) / done × (total − done) − (now − last), at least 0;
    /// `None` before a step has closed.
    pub fn left(&self, now: Instant) -> Option<Duration> {
        let last = self.last?;
        if self.done == 0 {
            return None;
        }
        let per_step = last.duration_since(self.start).as_secs_f64() / self.done as f64;
        let left = per_step * self.total.saturating_sub(self.done) as f64
            - now.duration_since(last).as_secs_f64();
        Some(Duration::from_secs_f64(left.max(0.0)))
    }

    /// `k/n steps` once the loop has started, `setting up` before.
    fn steps(&self) -> String {
        if self.started || self.last.is_some() {
            format!("{}/{} steps", self.done, self.total)
        } else {
            "setting up".to_owned()
        }
    }
}

/// A duration as `1h 05m`, `2m 07s` or `9s`; `—` for none (not yet estimated).
pub fn human(d: Option<Duration>) -> String {
    let Some(d) = d else {
        return "—".to_owned();
    };
    let s = d.as_secs_f64().round() as u64;
    match s {
        0..=59 => format!("{s}s"),
        60..=3599 => format!("{}m {:02}s", s / 60, s % 60),
        _ => format!("{}h {:02}m", s / 3600, s % 3600 / 60),
    }
}

/// The run's progress: a bar redrawn every second on a terminal, else a plain line at most
/// every 5 s (and at the last step).
pub struct Progress {
    bar: Option<indicatif::ProgressBar>,
    clock: Arc<Mutex<LoopClock>>,
    last_log: Instant,
}

impl Progress {
    /// A bar when stderr is a terminal, plain lines otherwise.
    pub fn new() -> Progress {
        let clock = Arc::new(Mutex::new(LoopClock::new(Instant::now())));
        let read = |c: &Arc<Mutex<LoopClock>>| *c.lock().unwrap_or_else(|e| e.into_inner());
        let bar = crate::args::progress_bar(
            0,
            "{spinner} [{elapsed_precise}] {bar:30} {steps}, t = {msg} (ETA {left})",
        );
        let bar = bar.inspect(|b| {
            let (c1, c2) = (clock.clone(), clock.clone());
            let style = b
                .style()
                .with_key(
                    "steps",
                    move |_: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                        let _ = w.write_str(&read(&c1).steps());
                    },
                )
                .with_key(
                    "left",
                    move |_: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                        let _ = w.write_str(&human(read(&c2).left(Instant::now())));
                    },
                );
            b.set_style(style);
            b.set_message("—");
            b.enable_steady_tick(Duration::from_secs(1));
        });
        Progress {
            bar,
            clock,
            last_log: Instant::now(),
        }
    }

    fn clock(&self) -> std::sync::MutexGuard<'_, LoopClock> {
        self.clock.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// A log line, above the bar when there is one.
    pub fn message(&self, m: &str) {
        match &self.bar {
            Some(b) => b.println(m),
            None => eprintln!("{m}"),
        }
    }

    /// The coupled loop starts with `steps` steps.
    pub fn started(&mut self, steps: u64) {
        self.clock().start(Instant::now(), steps);
        if let Some(b) = &self.bar {
            b.set_length(steps);
            b.set_position(0);
        }
    }

    /// Step `step` of `steps` closed; `bar` is the bar's message, `line` the log line's text
    /// (both made only when shown).
    pub fn step(
        &mut self,
        step: u64,
        steps: u64,
        bar: impl FnOnce() -> String,
        line: impl FnOnce() -> String,
    ) {
        let now = Instant::now();
        self.clock().step(now, step, steps);
        if let Some(b) = &self.bar {
            b.set_length(steps);
            b.set_position(step);
            b.set_message(bar());
        } else if step == steps || self.last_log.elapsed().as_secs_f64() >= 5.0 {
            self.last_log = now;
            let left = human(self.clock().left(now));
            eprintln!("step {step}/{steps}: {}, ETA {left}", line());
        }
    }

    /// Clears the bar.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_left_is_the_mean_step_times_the_steps_left_counting_down() {
        let t0 = Instant::now();
        let at = |s: f64| t0 + Duration::from_secs_f64(s);
        // 20 s of setup before the loop: not part of the estimate
        let mut c = LoopClock::new(t0);
        assert_eq!(c.steps(), "setting up");
        c.start(at(20.0), 10);
        assert_eq!(c.left(at(25.0)), None);
        assert_eq!(c.steps(), "0/10 steps");
        // 3 steps in 30 s: 10 s a step, 7 left
        c.step(at(50.0), 3, 10);
        assert_eq!(c.left(at(50.0)), Some(Duration::from_secs(70)));
        // 4 s later, still within step 4
        assert_eq!(c.left(at(54.0)), Some(Duration::from_secs(66)));
        // a slow step: never below zero
        assert_eq!(c.left(at(200.0)), Some(Duration::ZERO));
        c.step(at(220.0), 10, 10);
        assert_eq!(c.left(at(220.0)), Some(Duration::ZERO));
        assert_eq!(c.steps(), "10/10 steps");
    }

    #[test]
    fn durations_read_as_hours_minutes_seconds() {
        assert_eq!(human(None), "—");
        assert_eq!(human(Some(Duration::from_secs_f64(8.6))), "9s");
        assert_eq!(human(Some(Duration::from_secs(127))), "2m 07s");
        assert_eq!(human(Some(Duration::from_secs(3900))), "1h 05m");
    }
}
