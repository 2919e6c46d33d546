//! Where the user is: the step shown (of the plan's schedule, or of the
//! looked-at cycle's run), the step slider's span, the selection moved through
//! the list and the matches, links followed with their history (Back and
//! Forward), and the time range moved to reveal the selection.

use super::super::{
    AppState, Command, Extent, Mode, Place, STEP_ZOOM, StepWindow, UiCommand, extent,
};

impl AppState {
    /// The stepping, selection and history commands given by name.
    pub(super) fn run_steps(&mut self, cmd: UiCommand) {
        let (k, steps) = self.step_and_steps();
        match cmd {
            UiCommand::FirstStep => self.apply(self.set_step_command(0)),
            UiCommand::PreviousStep if k > 0 => self.apply(self.set_step_command(k - 1)),
            UiCommand::NextStep if k < steps => self.apply(self.set_step_command(k + 1)),
            UiCommand::LastStep => self.apply(self.set_step_command(steps)),
            UiCommand::NextFailure | UiCommand::PreviousFailure => {
                let failed = self.failed_steps();
                let next = if cmd == UiCommand::NextFailure {
                    failed.iter().find(|f| f.0 > k)
                } else {
                    failed.iter().rev().find(|f| f.0 < k)
                };
                if let Some(&(j, a)) = next {
                    self.follow(|app| {
                        app.apply(app.set_step_command(j));
                        if a.is_some() {
                            app.ui.nav.selected = a;
                        }
                    });
                }
            }
            UiCommand::SelectPrevious | UiCommand::SelectNext => {
                let listed = self.listed();
                let listed = &listed.shown;
                let at = self
                    .ui
                    .nav
                    .selected
                    .and_then(|a| listed.iter().position(|&b| b == a));
                let next = match (at, cmd == UiCommand::SelectNext) {
                    (Some(i), true) => listed.get(i + 1).or(listed.get(i)),
                    (Some(i), false) => listed.get(i.saturating_sub(1)),
                    // Nothing selected (or filtered out): from the top or the end.
                    (None, true) => listed.first(),
                    (None, false) => listed.last(),
                };
                if let Some(&a) = next.filter(|&&a| Some(a) != self.ui.nav.selected) {
                    // Moving through the list is not a link: Back skips it.
                    self.ui.nav.selected = Some(a);
                    self.reveal = true;
                }
            }
            UiCommand::NextMatch | UiCommand::PreviousMatch => {
                let listed = self.listed();
                let shown = &listed.shown;
                let n = shown.len();
                let at = self
                    .ui
                    .nav
                    .selected
                    .and_then(|a| shown.iter().position(|&b| b == a));
                // Round and round the matches.
                let next = match (at, cmd == UiCommand::NextMatch) {
                    _ if n == 0 => None,
                    (Some(i), true) => Some((i + 1) % n),
                    (Some(i), false) => Some((i + n - 1) % n),
                    (None, true) => Some(0),
                    (None, false) => Some(n - 1),
                };
                if let Some(&a) = next.and_then(|i| shown.get(i)) {
                    self.follow(|app| app.ui.nav.selected = Some(a));
                }
            }
            UiCommand::Back => {
                let place = self.ui.nav.history.back(self.ui.nav.place());
                self.go_to(place);
            }
            UiCommand::Forward => {
                let place = self.ui.nav.history.forward(self.ui.nav.place());
                self.go_to(place);
            }
            UiCommand::ZoomStepsIn | UiCommand::ZoomStepsOut => {
                let factor = if cmd == UiCommand::ZoomStepsIn {
                    STEP_ZOOM
                } else {
                    1.0 / STEP_ZOOM
                };
                self.ui.nav.steps_shown = self.ui.nav.steps_shown.zoomed(factor, k, steps);
            }
            UiCommand::AllSteps => self.ui.nav.steps_shown = StepWindow::ALL,
            // No step past either end; given by `run` for the stepping
            // commands only.
            _ => {}
        }
    }

    /// Starts or stops stepping automatically (from the first step when the
    /// last is shown).
    pub(super) fn play(&mut self, on: bool) {
        let (k, n) = self.step_and_steps();
        if on && k >= n {
            let first = self.set_step_command(0);
            self.apply(first);
        }
        self.ui.nav.playing = on;
    }

    /// Selects `a` and shows its failure step (a link followed).
    pub(super) fn go_to_failure_step(&mut self, a: usize) {
        self.follow(|app| {
            app.ui.nav.selected = Some(a);
            if let Some(k) = app.explanation_for(a).and_then(|e| e.failure_step) {
                app.set_step(k);
            }
        });
    }

    /// Follows a link: `go` changes the selection or step; when they changed,
    /// Back returns to where the user was (selection, step, time range) and
    /// the time range moves to show the selection.
    pub(super) fn follow(&mut self, go: impl FnOnce(&mut Self)) {
        let before = self.ui.nav.place();
        go(self);
        let after = self.ui.nav.place();
        if (after.selected, after.step) != (before.selected, before.step) {
            self.ui.nav.history.visit(before);
            self.reveal = true;
        }
    }

    /// Goes back (or forward) to a place: its selection, step and time range
    /// exactly as they were.
    fn go_to(&mut self, place: Option<Place>) {
        let Some(p) = place else {
            return;
        };
        let n = self.doc.plan.activities.len();
        self.ui.nav.selected = p.selected.filter(|&a| a < n);
        self.set_step(p.step);
        self.apply(Command::SetAxis(p.axis));
        self.reveal = false;
    }

    /// When asked for (a link or key changed the selection), moves the time
    /// range as little as it can to show the selected activity: its bar
    /// whole, or, not placed, one of its windows (the nearest; nothing moves
    /// while one is partly in view). In execution mode it waits for the
    /// execution.
    pub fn reveal_selection(&mut self) {
        if !std::mem::take(&mut self.reveal) {
            return;
        }
        let Some(a) = self.ui.nav.selected else {
            return;
        };
        let run = match self.ui.nav.mode {
            Mode::Schedule => None,
            Mode::Execution => match self.execution_run() {
                Some(run) => Some(run),
                None => {
                    // Not derived yet: once it is.
                    self.reveal = self.execution.run(self.exec_key()).is_none();
                    return;
                }
            },
        };
        let Some(extent) = extent(&self.doc.plan, &self.analysis, run, self.ui.nav.step, a) else {
            return;
        };
        let bounds = self.bounds();
        let mut axis = self.ui.nav.axis;
        match extent {
            Extent::Bar(s, e) => axis.reveal((s as f64, e as f64), bounds),
            Extent::Windows(spans) => {
                let (lo, hi) = (axis.start, axis.end);
                let seen = spans
                    .iter()
                    .any(|&(s, e)| (e as f64) > lo && (s as f64) < hi);
                let centre = (lo + hi) / 2.0;
                let distance = |&&(s, e): &&(i64, i64)| {
                    let (s, e) = (s as f64, e as f64);
                    if centre < s {
                        s - centre
                    } else {
                        (centre - e).max(0.0)
                    }
                };
                let nearest = spans
                    .iter()
                    .min_by(|x, y| distance(x).total_cmp(&distance(y)));
                if let Some(&(s, e)) = nearest.filter(|_| !seen) {
                    axis.reveal((s as f64, e as f64), bounds);
                }
            }
        }
        if axis != self.ui.nav.axis {
            self.apply(Command::SetAxis(axis));
        }
    }

    /// Shows step `k`. Its profiles are derived before the next frame is
    /// drawn ([`Self::derive_step_view`]): however many steps are given
    /// between two frames, only the last one costs.
    pub(super) fn set_step(&mut self, k: usize) {
        self.ui.nav.step = k.min(self.analysis.steps());
        self.follow_step();
    }

    /// The step slider's zoomed span follows the step shown (the least move
    /// that keeps it in view).
    pub(super) fn follow_step(&mut self) {
        let (k, n) = self.step_and_steps();
        self.ui.nav.steps_shown = self.ui.nav.steps_shown.following(k, n);
    }
}
