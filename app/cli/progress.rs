//! The progress bar of the long commands (`explain`, `montecarlo`): on standard
//! error, shown once the work has taken a second and only when standard error is
//! a terminal, so that a quick run or a redirected one shows nothing.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget};

/// A hidden progress bar that shows itself when the work turns out long.
#[derive(Debug)]
pub struct Progress {
    bar: ProgressBar,
    started: Instant,
    terminal: bool,
    shown: AtomicBool,
}

impl Progress {
    /// A bar of `total` units of work, hidden for now.
    pub fn new(total: u64) -> Self {
        Self {
            bar: ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::hidden()),
            started: Instant::now(),
            terminal: std::io::stderr().is_terminal(),
            shown: AtomicBool::new(false),
        }
    }

    /// One more unit done.
    pub fn inc(&self) {
        self.bar.inc(1);
        self.show_when_due();
    }

    /// `done` units done.
    pub fn set_position(&self, done: u64) {
        self.bar.set_position(done);
        self.show_when_due();
    }

    /// Draws the bar from now on once the work has taken a second (on a terminal).
    fn show_when_due(&self) {
        if self.terminal
            && self.started.elapsed() > Duration::from_secs(1)
            && !self.shown.swap(true, Ordering::Relaxed)
        {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
    }

    /// Takes the bar off the screen.
    pub fn finish(self) {
        self.bar.finish_and_clear();
    }
}

/// Runs `work` with a progress bar of `total` units, which `work` advances by
/// calling the tick it is given once per unit done.
pub fn with_progress<T>(total: u64, work: impl FnOnce(&(dyn Fn() + Sync)) -> T) -> T {
    let progress = Progress::new(total);
    let out = work(&|| progress.inc());
    progress.finish();
    out
}
