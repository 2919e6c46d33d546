//! What the state derives before each frame and reads back for the views:
//! the step's profiles, the selected activity's explanation, valid intervals
//! and suggestions, the execution, the campaign and the flexible schedule,
//! each for the plan revision (and actuals) shown.

use std::sync::Arc;
use std::time::Duration;

use solscope_engine::{CategoryIntervals, Explanation, Suggestion};

use super::derived::{CampaignCache, ExecKey, ExecutionCache, FlexResult, step_view};
use super::tune::TuneModel;
use super::{
    ActualsSource, Analysis, AppState, CampaignModel, CampaignResult, Command, CycleRun, Document,
    ExecModel, ExecutionRun, FLEX_LAYER_MAX_ACTIVITIES, FreeSlackProgress, Listed, Messages, Mode,
    Navigation, Persisted, Progress, SearchIndex, StepView, Stopped, TextBuffers, UiState,
    WouldCause, failed_steps,
};

/// The soonest redraw asked for while preparing a frame.
#[derive(Debug, Default)]
struct Repaint(Option<Duration>);

impl Repaint {
    /// Asks for a redraw within `ms` milliseconds.
    fn ask(&mut self, ms: u64) {
        let d = Duration::from_millis(ms);
        self.0 = Some(self.0.map_or(d, |e| e.min(d)));
    }
}

impl AppState {
    /// Before a frame is drawn: starts the guided tour offered with the
    /// tutorial plan (unless dismissed), takes what the workers finished,
    /// derives what the frame shows (the step's profiles, the execution or the
    /// flexible schedule, the selected activity's explanation and
    /// suggestions; on workers with `background`), gives the next step while
    /// playing (at `now`, seconds), and moves the time range to a selection
    /// made by a command given outside a frame. Says how soon the frame
    /// should be drawn again while something is still coming in.
    pub fn prepare(&mut self, now: f64, cmds: &mut Vec<Command>) -> Option<Duration> {
        let mut repaint = Repaint::default();
        if self.reap_opening() {
            // The progress line counts the seconds.
            repaint.ask(100);
        }
        // Take what the execution workers finished (in any mode, so they are
        // not polled for longer than they run).
        if let Err(e) = self.execution.reap(self.exec_key()) {
            self.ui.messages.error = Some(e);
        }
        // The campaign too: a campaign of an older plan revision stops here.
        if let Err(e) = self.campaign.reap(self.revision) {
            self.ui.messages.error = Some(e);
        }
        if let Err(e) = self.flex.reap(self.revision) {
            self.ui.messages.error = Some(e);
        }
        // A tuning search of an older plan revision stops here.
        if let Err(e) = self.tune.reap(self.revision) {
            self.ui.messages.error = Some(e);
        }
        self.derive_step_view();
        if self.ui.nav.mode == Mode::Execution {
            // The execution and the looked-at cycle's run, derived before
            // drawing (on a worker in the desktop app). The flexibility layer
            // is not drawn here: its free slack stops (what it found stays; it
            // goes on back in schedule mode).
            self.flex.stop_free_slack();
            self.derive_execution();
        } else {
            // The flexible schedule: the Gantt's layer and the inspector's
            // Flexibility section (on a worker in the desktop app).
            self.flex.request(
                &self.doc.plan,
                &self.analysis,
                self.revision,
                self.background,
            );
            if !self.flex_shown() {
                // Nobody looks at the shading: the worker stops (what it
                // found stays).
                self.flex.stop_free_slack();
            } else if self.background {
                let axis = self.ui.nav.axis;
                self.flex
                    .request_free_slack(self.revision, (axis.start + axis.end) / 2.0);
            } else {
                self.flex.fill_free_slack(self.revision);
            }
        }
        if self.ui.nav.playing {
            if now - self.last_tick > 0.15 {
                self.last_tick = now;
                let (k, n) = self.step_and_steps();
                cmds.push(if k < n {
                    self.set_step_command(k + 1)
                } else {
                    Command::Play(false)
                });
            }
            repaint.ask(150);
        }
        let scheduling = self.ui.nav.mode == Mode::Schedule;
        if let Some(a) = self.ui.nav.selected.filter(|_| scheduling) {
            // Derived data, computed before drawing (never mid-draw); execution
            // mode's inspector shows none of it.
            self.explanation_for(a);
            self.suggestions_for(a);
            self.derived.valid_for(&self.analysis, self.revision, a);
            let shown = self.ui.nav.overlay_reason_of(a);
            self.derived
                .would_cause_for(&self.doc.plan, &self.analysis, self.revision, (a, shown));
            // Its free slack ahead of the rest (the inspector shows it); on a
            // large plan only once the layer is on.
            if self.flex_shown() || self.doc.plan.activities.len() <= FLEX_LAYER_MAX_ACTIVITIES {
                self.flex.request_one(self.revision, a);
            }
        }
        self.reap_worker();
        // A selection made by a command given outside a frame.
        self.reveal_selection();
        if self.workers_busy_but_free_slack() {
            // Poll the worker until its result is in.
            repaint.ask(50);
        } else if self.flex.busy() {
            // The free slack fills in over minutes: a few repaints a second.
            repaint.ask(500);
        } else if self.campaign.progress().is_some() || self.tune.running().is_some() {
            // The progress bar moves while the campaign or the tuning runs.
            repaint.ask(100);
        }
        repaint.0
    }

    /// Starts the guided tour when the tutorial plan was just opened, unless
    /// it was dismissed (known only once the host restored the persisted
    /// settings, so asked at the start of a frame).
    pub fn start_offered_tour(&mut self) {
        if std::mem::take(&mut self.offer_tour) && !self.persisted.tour_dismissed {
            self.start_tour();
        }
    }

    /// What the search and filters list now, in step order.
    pub fn listed(&mut self) -> Arc<Listed> {
        self.list
            .listed(&self.doc.plan, &self.analysis, &self.ui.nav, self.revision)
    }

    /// The search index of the plan as it is (lower-case ids and names, the
    /// unit resources, the sols).
    pub fn search_index(&mut self) -> Arc<SearchIndex> {
        self.list.search_index(&self.doc.plan, self.revision)
    }

    /// The execution of the current plan revision with the current actuals, once
    /// derived (and when it could be run).
    pub fn execution_run(&self) -> Option<&ExecutionRun> {
        self.execution
            .run(self.exec_key())
            .and_then(|r| r.as_ref().ok())
            .map(AsRef::as_ref)
    }

    /// The last Monte Carlo campaign's result, when it ran on the plan as it
    /// is.
    pub fn campaign_result(&self) -> Option<&CampaignResult> {
        self.campaign
            .result(self.revision)
            .and_then(|r| r.as_ref().ok())
    }

    /// The flexible schedule of the plan as it is, once derived (and when it
    /// could be).
    pub fn flex(&self) -> Option<&solscope_engine::Flex> {
        self.flex
            .get(self.revision)
            .and_then(|r: &FlexResult| r.as_ref().ok())
            .map(AsRef::as_ref)
    }

    /// The activities the list shows with the search and filters as they are,
    /// in step order.
    pub fn list_shown(&mut self) -> Vec<usize> {
        self.listed().shown.clone()
    }

    /// The Monte Carlo campaign running, if any.
    pub fn campaign_progress(&self) -> Option<Progress> {
        self.campaign.progress()
    }

    /// The last campaign that stopped before its summary was made.
    pub fn campaign_stopped(&self) -> Option<Stopped> {
        self.campaign.stopped().copied()
    }

    /// The looked-at cycle's scheduler run, once derived.
    pub fn cycle_run(&self) -> Option<&CycleRun> {
        let (k, _) = self.cycle_and_cycles()?;
        self.execution.cycle(self.exec_key(), k)
    }

    /// The plan revision and actuals the execution is derived for.
    pub(super) fn exec_key(&self) -> ExecKey {
        ExecKey {
            revision: self.revision,
            actuals: self.actuals_rev,
        }
    }

    /// Derives the execution, the looked-at cycle's run and the profiles of its
    /// step shown (each once per key; on workers with `background`).
    fn derive_execution(&mut self) {
        let key = self.exec_key();
        self.execution
            .request(&self.doc.plan, &self.actuals, key, self.background);
        let cycle = match self.execution.run(key) {
            Some(Ok(run)) => run.cycle_index(self.ui.nav.cycle),
            _ => return,
        };
        self.execution.request_cycle(key, cycle, self.background);
        if let Some(a) = self.ui.nav.selected {
            self.execution.request_loss(key, a, self.background);
        }
        if let Some(n) = self.execution.cycle(key, cycle).map(|c| c.steps()) {
            self.execution
                .derive_view(key, cycle, self.ui.nav.cycle_step.min(n));
        }
    }

    /// Whether the flexibility layer is on for the open plan (see
    /// [`Navigation::flex_shown`]).
    pub fn flex_shown(&self) -> bool {
        self.ui
            .nav
            .flex_shown(self.persisted.hide_flex, self.doc.plan.activities.len())
    }

    /// Turns the flexibility layer on or off: on a plan of more than
    /// [`FLEX_LAYER_MAX_ACTIVITIES`] activities for as long as it is open, on
    /// a smaller one in the settings.
    pub(super) fn toggle_flex(&mut self) {
        if self.doc.plan.activities.len() > FLEX_LAYER_MAX_ACTIVITIES {
            self.ui.nav.flex_on_large = Some(!self.flex_shown());
        } else {
            self.persisted.hide_flex = !self.persisted.hide_flex;
        }
    }

    /// The step shown and the number of steps of the run the step slider moves
    /// through: the plan's schedule, or in execution mode the looked-at cycle's
    /// run (no steps while it is derived).
    pub(super) fn step_and_steps(&self) -> (usize, usize) {
        match self.ui.nav.mode {
            Mode::Schedule => (self.ui.nav.step, self.analysis.steps()),
            Mode::Execution => {
                let m = self.exec_model();
                (m.step, m.cycle_run.map_or(0, |c| c.steps()))
            }
        }
    }

    /// The steps (1-based) at which an activity failed in the run the step
    /// slider moves through, each with the plan activity that failed.
    pub(super) fn failed_steps(&self) -> Vec<(usize, Option<usize>)> {
        match self.ui.nav.mode {
            Mode::Schedule => failed_steps(&self.analysis.schedule.steps)
                .map(|(k, a)| (k, Some(a)))
                .collect(),
            Mode::Execution => match self.cycle_run() {
                Some(CycleRun {
                    schedule: Ok(s), ..
                }) => failed_steps(&s.steps)
                    .filter_map(|(k, i)| self.cycle_run().map(|c| (k, c.plan_activity(i))))
                    .collect(),
                _ => Vec::new(),
            },
        }
    }

    /// The command that shows step `k` of the run the step slider moves through.
    pub(super) fn set_step_command(&self, k: usize) -> Command {
        match self.ui.nav.mode {
            Mode::Schedule => Command::SetStep(k),
            Mode::Execution => Command::SetCycleStep(k),
        }
    }

    /// The cycle looked at (clamped to the current execution's) and how many
    /// cycles it has, once the execution is derived.
    pub(super) fn cycle_and_cycles(&self) -> Option<(usize, usize)> {
        match self.execution.run(self.exec_key()) {
            Some(Ok(run)) => Some((
                run.cycle_index(self.ui.nav.cycle),
                run.execution.cycles.len(),
            )),
            _ => None,
        }
    }

    /// Verified suggestions for activity `a`, computed once per plan revision from
    /// its explanation: in the frame, or with `background` on a worker thread (then
    /// `None` until they arrive; a result for an older revision is dropped).
    pub fn suggestions_for(&mut self, a: usize) -> Option<&[Suggestion]> {
        if self.background {
            self.reap_worker();
        }
        self.derived.request_suggestions(
            &self.doc.plan,
            &self.analysis,
            self.revision,
            a,
            self.background,
        );
        self.derived.suggestions(a, self.revision)
    }

    /// Takes a finished worker's result; a worker lost without one is shown as an
    /// error.
    pub(super) fn reap_worker(&mut self) {
        if let Err(e) = self.derived.reap_worker(self.revision) {
            self.ui.messages.error = Some(e);
        }
    }

    /// The activity whose suggestions a worker is verifying, if any.
    pub fn verifying(&self) -> Option<usize> {
        self.derived.verifying()
    }

    /// Whether a worker (suggestions, execution, flexible schedule) is still
    /// running: the frame loop polls until none is.
    pub fn workers_busy(&self) -> bool {
        self.workers_busy_but_free_slack() || self.flex.busy()
    }

    /// Whether a worker other than the free slack one (which may run for
    /// minutes) is still running.
    fn workers_busy_but_free_slack(&self) -> bool {
        self.verifying().is_some()
            || self.execution.busy()
            || self.flex.busy_first_stage()
            || self.step_views.busy()
    }

    /// Where the free slack of the plan as it is stands, once the flexible
    /// schedule's first stage is in.
    pub fn free_slack_progress(&self) -> Option<FreeSlackProgress> {
        self.flex.free_slack_progress(self.revision)
    }

    /// The explanation of activity `a` if it did not schedule (computed once per
    /// plan revision).
    pub fn explanation_for(&mut self, a: usize) -> Option<&solscope_engine::Explanation> {
        self.derived
            .explanation_for(&self.doc.plan, &self.analysis, self.revision, a)
    }

    /// What the selected activity, failed on energy or peak power, would have
    /// caused, as the plots draw it this frame (derived before drawing, once
    /// per selection and plan revision; none in execution mode).
    pub fn would_cause(&self) -> Option<&WouldCause> {
        self.ui
            .nav
            .selected
            .filter(|_| self.ui.nav.mode == Mode::Schedule)
            .and_then(|a| self.derived.would_cause(a, self.revision))
    }

    /// Cached suggestions, if computed for this revision (views read these).
    pub fn cached_suggestions(&self, a: usize) -> Option<&[Suggestion]> {
        self.derived.suggestions(a, self.revision)
    }

    /// The profiles of the step shown, once per frame for the latest step.
    /// Within a plan revision the desktop app derives them on a worker (one
    /// at a time, each for the step shown when it starts) and draws the last
    /// ones in until they catch up; after an edit, or headless, in place (the
    /// profiles of another revision are never drawn).
    fn derive_step_view(&mut self) {
        match self.step_views.reap(self.revision) {
            Ok(Some(view)) => {
                self.step_view = view;
                self.step_view_rev = self.revision;
            }
            Ok(None) => {}
            Err(e) => self.ui.messages.error = Some(e),
        }
        let k = self.ui.nav.step;
        if (self.step_view_rev, self.step_view.step) == (self.revision, k) {
            return;
        }
        if self.background && self.step_view_rev == self.revision {
            self.step_views.request(&self.analysis, self.revision, k);
        } else {
            self.step_view = step_view(&self.analysis, k);
            self.step_view_rev = self.revision;
        }
    }

    /// The explanation of activity `a` at this revision, once derived.
    pub fn explanation(&self, a: usize) -> Option<&Explanation> {
        self.derived.explanation(a, self.revision)
    }

    /// Why activity `a` could not be explained, if that happened.
    pub fn explanation_error(&self, a: usize) -> Option<&str> {
        self.derived.explanation_error(a, self.revision)
    }

    /// Activity `a`'s valid intervals at its own step (full horizon), once
    /// derived.
    pub fn valid(&self, a: usize) -> Option<&[CategoryIntervals]> {
        self.derived.valid(a, self.revision)
    }

    /// The flexible schedule of the plan as it is, or why there is none, once
    /// derived.
    pub fn flex_result(&self) -> Option<&FlexResult> {
        self.flex.get(self.revision)
    }

    /// What execution mode draws, as far as it is derived for the current plan
    /// revision and actuals.
    pub fn exec_model(&self) -> ExecModel<'_> {
        let key = self.exec_key();
        exec_model(
            &self.ui.nav,
            &self.execution,
            &self.campaign,
            &self.actuals,
            key,
        )
    }

    /// What the views read of the state for one frame, and the text buffers,
    /// the only state they write while drawing.
    pub fn frame_reads(&mut self) -> (FrameReads<'_>, &mut TextBuffers) {
        let key = self.exec_key();
        let AppState {
            doc,
            analysis,
            step_view,
            persisted,
            revision,
            derived,
            flex,
            execution,
            campaign,
            actuals,
            tune,
            ui,
            ..
        } = self;
        let UiState {
            nav,
            messages,
            text,
        } = ui;
        let (selected, revision) = (nav.selected, *revision);
        let reads = FrameReads {
            doc,
            analysis,
            step_view,
            persisted,
            suggestions: selected.and_then(|a| derived.suggestions(a, revision)),
            revision,
            explanation: selected.and_then(|a| derived.explanation(a, revision)),
            explanation_error: selected.and_then(|a| derived.explanation_error(a, revision)),
            valid: selected.and_then(|a| derived.valid(a, revision)),
            // Execution mode explains nothing.
            would_cause: selected
                .filter(|_| nav.mode == Mode::Schedule)
                .and_then(|a| derived.would_cause(a, revision)),
            flex: flex.get(revision),
            free_slack: flex.free_slack_progress(revision),
            nav,
            messages,
            exec: exec_model(nav, execution, campaign, actuals, key),
            tune: tune.model(revision),
        };
        (reads, text)
    }
}

/// What execution mode draws, as far as it is derived at `key` (the current
/// plan revision and actuals); from the fields it reads, so that the text
/// buffers can be lent out beside it.
fn exec_model<'a>(
    nav: &Navigation,
    execution: &'a ExecutionCache,
    campaign: &'a CampaignCache,
    actuals: &'a ActualsSource,
    key: ExecKey,
) -> ExecModel<'a> {
    let revision = key.revision;
    let run = execution.run(key);
    let cycle = match run {
        Some(Ok(r)) => r.cycle_index(nav.cycle),
        _ => nav.cycle,
    };
    let cycle_run = execution.cycle(key, cycle);
    let step = cycle_run.map_or(0, |c| nav.cycle_step.min(c.steps()));
    ExecModel {
        source: actuals,
        actuals_rev: key.actuals,
        run,
        cycle,
        cycle_run,
        step,
        view: execution.view(key, cycle, step),
        loss: nav.selected.and_then(|a| execution.loss(key, a)),
        campaign: CampaignModel {
            result: campaign.result(revision),
            running: campaign.progress(),
            stale: campaign.stale(revision),
            stopped: campaign.stopped(),
        },
    }
}

/// What the views read of the state for one frame (only what was derived for
/// the selected activity at this revision).
#[derive(Debug)]
pub struct FrameReads<'a> {
    /// The open plan.
    pub doc: &'a Document,
    /// Its schedule and explanations.
    pub analysis: &'a Analysis,
    /// Profiles as of the current step.
    pub step_view: &'a StepView,
    /// Persisted settings.
    pub persisted: &'a Persisted,
    /// Verified suggestions of the selected activity, when computed.
    pub suggestions: Option<&'a [Suggestion]>,
    /// Bumped on every accepted change of the plan.
    pub revision: u64,
    /// Explanation of the selected activity, when it did not schedule.
    pub explanation: Option<&'a Explanation>,
    /// Why the selected activity could not be explained, if that happened.
    pub explanation_error: Option<&'a str>,
    /// Valid intervals of the selected activity at its own step.
    pub valid: Option<&'a [CategoryIntervals]>,
    /// What the selected activity, failed on energy or peak power, would have
    /// caused (schedule mode).
    pub would_cause: Option<&'a WouldCause>,
    /// The flexible schedule of this revision, or why there is none, once
    /// derived.
    pub flex: Option<&'a FlexResult>,
    /// Where its free slack stands.
    pub free_slack: Option<FreeSlackProgress>,
    /// Where the user is.
    pub nav: &'a Navigation,
    /// The banner, the error and the questions.
    pub messages: &'a Messages,
    /// What execution mode draws.
    pub exec: ExecModel<'a>,
    /// Priority tuning: the panel, the search and its result.
    pub tune: TuneModel<'a>,
}
