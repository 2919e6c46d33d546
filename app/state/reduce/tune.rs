//! Priority tuning: the panel shown or hidden, a search started or
//! cancelled, its result applied as one undoable edit of the priorities or
//! dismissed, and the Gantt's overlay of the tuned schedule.

use super::super::tune::{TuneModel, TuneResult, TuneRunning, TuneSettings};
use super::super::{AppState, UiCommand};

impl AppState {
    /// The tuning commands given by name.
    pub(super) fn run_tune(&mut self, cmd: UiCommand) {
        match cmd {
            UiCommand::TunePriorities => self.tune.open = !self.tune.open,
            UiCommand::CancelTune => self.tune.cancel(),
            UiCommand::ApplyTuning => self.apply_tuning(),
            UiCommand::DismissTuning => self.tune.dismiss(),
            UiCommand::ToggleTuneOverlay => self.tune.overlay = !self.tune.overlay,
            // Given by `run` for the tuning commands only.
            _ => {}
        }
    }

    /// Starts tuning the plan as it is (the panel opens to show it).
    pub(super) fn start_tune(&mut self, settings: TuneSettings) {
        self.tune.open = true;
        self.tune
            .start(&self.doc.plan, self.revision, settings, self.background);
    }

    /// Gives the plan the tuned priorities through the edit path (validated,
    /// rescheduled, one undo step); the result is then retired with its
    /// overlay.
    fn apply_tuning(&mut self) {
        let Some(edit) = self.tune_result().and_then(|r| r.edit(&self.doc.plan)) else {
            return;
        };
        let (set, description) = edit;
        if self.edit_plan(set, description) {
            self.tune.dismiss();
        }
    }

    /// The last tuning of the plan as it is, when it succeeded.
    pub fn tune_result(&self) -> Option<&TuneResult> {
        self.tune
            .result(self.revision)
            .and_then(|r| r.as_ref().ok())
    }

    /// Why the last tuning of the plan as it is failed, if it did.
    pub fn tune_error(&self) -> Option<&str> {
        self.tune
            .result(self.revision)
            .and_then(|r| r.as_ref().err())
            .map(String::as_str)
    }

    /// The tuning search running, if any.
    pub fn tune_running(&self) -> Option<TuneRunning> {
        self.tune.running()
    }

    /// What the views read of tuning.
    pub fn tune_model(&self) -> TuneModel<'_> {
        self.tune.model(self.revision)
    }
}
