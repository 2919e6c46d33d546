//! Execution mode: the mode switch, the actual durations (a file, a Monte
//! Carlo run, or nominal), the looked-at cycle, and the Monte Carlo campaign.

use std::path::PathBuf;

use super::super::montecarlo::MAX_RUNS;
use super::super::{ActualsSource, AppState, Command, LAST_STEP, Mode, StepWindow, UiCommand};

impl AppState {
    /// The mode switch, the actuals, the cycles and the campaign commands
    /// given by name.
    pub(super) fn run_execution(&mut self, cmd: UiCommand) {
        match cmd {
            UiCommand::ShowSchedule | UiCommand::ShowExecution => {
                let mode = match cmd {
                    UiCommand::ShowSchedule => Mode::Schedule,
                    _ => Mode::Execution,
                };
                if mode != self.ui.nav.mode {
                    // Another run under the step slider: all of its steps.
                    self.ui.nav.steps_shown = StepWindow::ALL;
                }
                self.ui.nav.mode = mode;
            }
            UiCommand::CancelCampaign => self.campaign.cancel(),
            UiCommand::NominalActuals => self.use_actuals(ActualsSource::Nominal, "Nominal"),
            UiCommand::PreviousCycle | UiCommand::NextCycle => {
                let shown = self.ui.nav.mode == Mode::Execution;
                if let Some((c, n)) = self.cycle_and_cycles().filter(|_| shown) {
                    let next = if cmd == UiCommand::PreviousCycle {
                        c.saturating_sub(1)
                    } else {
                        (c + 1).min(n.saturating_sub(1))
                    };
                    if next != c {
                        self.apply(Command::SetCycle(next));
                    }
                }
            }
            // Given by `run` for the execution commands only.
            _ => {}
        }
    }

    /// Looks at scheduling cycle `k` (clamped to the execution's), at its last
    /// step, its steps all spanned.
    pub(super) fn set_cycle(&mut self, k: usize) {
        self.ui.nav.cycle = match self.cycle_and_cycles() {
            Some((_, n)) => k.min(n.saturating_sub(1)),
            None => k,
        };
        self.ui.nav.cycle_step = LAST_STEP;
        self.ui.nav.steps_shown = StepWindow::ALL;
    }

    /// Executes with the actual durations of the file at `path`; one that
    /// cannot be read or does not fit the plan changes nothing and is shown.
    pub(super) fn open_actuals(&mut self, path: PathBuf) {
        let what = format!("Could not open actuals {}", path.display());
        match solscope_engine::read_plan_text(&path, solscope_engine::MAX_PLAN_BYTES) {
            Ok(text) => self.use_actuals(ActualsSource::File { path, text }, &what),
            Err(e) => self.ui.messages.error = Some(format!("{what}: {e}")),
        }
    }

    /// Starts a Monte Carlo campaign of `runs` runs seeded with `seed` (under
    /// each policy with `compare`); a number of runs out of range is shown.
    pub(super) fn run_campaign(&mut self, runs: u64, seed: u64, compare: bool) {
        if (1..=MAX_RUNS).contains(&runs) {
            self.campaign.start(
                &self.doc.plan,
                self.revision,
                (seed, runs, compare),
                self.background,
            );
        } else {
            self.ui.messages.error =
                Some(format!("Runs: enter a whole number from 1 to {MAX_RUNS}"));
        }
    }

    /// Uses `source` for the actual durations if it fits the plan; otherwise
    /// nothing changes and `what` is shown with the path-named error.
    pub(super) fn use_actuals(&mut self, source: ActualsSource, what: &str) {
        match source.actuals(&self.doc.plan) {
            // The same actuals again: the execution shown stays.
            Ok(_) if source == self.actuals => self.ui.messages.error = None,
            Ok(_) => {
                self.actuals = source;
                self.actuals_rev += 1;
                self.ui.messages.error = None;
            }
            Err(e) => self.ui.messages.error = Some(format!("{what}: {e}")),
        }
    }
}
