//! Progress of long work, one phase at a time: a bar on stderr when it is
//! a terminal, nothing when it is not (a log or a pipe would fill with
//! redraws), and with `STRATA_PROGRESS=lines` plain lines instead (a
//! line as a phase starts, one at each tenth of it, one when it ends), for
//! logs of batch jobs and for tests. `STRATA_PROGRESS=off` hides even the
//! bar.
//!
//! A phase counts units of work (pixels, or pixel samples) from any
//! thread; every phase of a command that can take more than a second has
//! one, so no long wait is silent.

use std::io::IsTerminal;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};

/// The environment variable that chooses how progress is shown: `lines`,
/// `off`, or (unset or anything else) a bar on a terminal only.
pub const PROGRESS_VAR: &str = "STRATA_PROGRESS";

/// How progress is shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// A bar on stderr (a terminal).
    Bar,
    /// Plain lines on stderr.
    Lines,
    /// Nothing.
    Off,
}

impl Mode {
    /// The mode [`PROGRESS_VAR`] and stderr ask for.
    #[must_use]
    pub fn from_env() -> Mode {
        match std::env::var(PROGRESS_VAR).as_deref() {
            Ok("lines") => Mode::Lines,
            Ok("off") => Mode::Off,
            _ if std::io::stderr().is_terminal() => Mode::Bar,
            _ => Mode::Off,
        }
    }
}

/// One phase of long work: `total` units, counted by [`Phase::inc`] from
/// any thread, ended by [`Phase::finish`] (or when dropped).
pub struct Phase {
    name: String,
    total: u64,
    done: AtomicU64,
    /// The last tenth reported as a line.
    tenth: Mutex<u64>,
    bar: Option<ProgressBar>,
    lines: bool,
    start: Instant,
    finished: bool,
}

impl Phase {
    /// Starts a phase of `total` units, shown as [`Mode::from_env`] asks.
    #[must_use]
    pub fn start(name: &str, total: u64) -> Phase {
        Phase::with_mode(name, total, Mode::from_env())
    }

    /// Starts a phase shown in `mode`.
    #[must_use]
    pub fn with_mode(name: &str, total: u64, mode: Mode) -> Phase {
        let bar = (mode == Mode::Bar).then(|| {
            let bar = ProgressBar::new(total.max(1));
            bar.set_style(
                ProgressStyle::with_template(
                    "{msg} [{elapsed_precise}] {wide_bar} {percent}% ETA {eta}",
                )
                .expect("a valid template"),
            );
            bar.set_message(name.to_string());
            bar
        });
        let lines = mode == Mode::Lines;
        if lines {
            eprintln!("{name}: 0 %");
        }
        Phase {
            name: name.to_string(),
            total,
            done: AtomicU64::new(0),
            tenth: Mutex::new(0),
            bar,
            lines,
            start: Instant::now(),
            finished: false,
        }
    }

    /// Counts `n` more units done.
    pub fn inc(&self, n: u64) {
        let done = self.done.fetch_add(n, Ordering::Relaxed) + n;
        if let Some(bar) = &self.bar {
            bar.inc(n);
        }
        if self.lines && self.total > 0 {
            let tenth = (done.min(self.total) * 10 / self.total).min(9);
            let mut last = self.tenth.lock().unwrap_or_else(|e| e.into_inner());
            if tenth > *last {
                *last = tenth;
                eprintln!("{}: {} %", self.name, tenth * 10);
            }
        }
    }

    /// Prints `line` to stderr without breaking the bar (drawn again
    /// under it).
    pub fn println(&self, line: &str) {
        match &self.bar {
            Some(bar) => bar.suspend(|| eprintln!("{line}")),
            None => eprintln!("{line}"),
        }
    }

    /// Units counted so far.
    #[must_use]
    pub fn done(&self) -> u64 {
        self.done.load(Ordering::Relaxed)
    }

    /// Ends the phase: the bar is cleared; a line says how far it got
    /// (`100 %` when every unit was counted) and how long it took.
    pub fn finish(mut self) {
        self.end();
    }

    fn end(&mut self) {
        if self.finished {
            return;
        }
        self.finished = true;
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
        if self.lines {
            let done = self.done();
            let share = match self.total {
                0 => 100,
                t => done.min(t) * 100 / t,
            };
            eprintln!(
                "{}: {share} %, done in {:.1} s",
                self.name,
                self.start.elapsed().as_secs_f64()
            );
        }
    }
}

impl Drop for Phase {
    fn drop(&mut self) {
        self.end();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_phase_counts_from_any_thread() {
        let p = Phase::with_mode("work", 1000, Mode::Off);
        std::thread::scope(|s| {
            for _ in 0..4 {
                s.spawn(|| {
                    for _ in 0..250 {
                        p.inc(1);
                    }
                });
            }
        });
        assert_eq!(p.done(), 1000);
        p.finish();
    }
}
