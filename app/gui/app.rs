//! The app: the open plan, its analysis, the UI state and the command queue; the
//! frame loop ([`SolscopeApp::frame_ui`]) and the one place that changes any of it
//! ([`SolscopeApp::apply`]).

use std::path::{Path, PathBuf};

use eframe::egui;
use solscope_engine::{Plan, Suggestion};

use super::commands::{Command, UiCommand};
use super::derived::{
    CampaignCache, DerivedCache, ExecKey, ExecutionCache, FlexCache, FlexResult, StepViewCache,
    step_view,
};
use super::document::{
    ActivitiesEdit, Analysis, Document, OutcomeDiff, add_activity, delete_activity,
    duplicate_activity, pin_window,
};
use super::execution::{ActualsSource, CycleRun, ExecutionRun};
use super::montecarlo::{CampaignResult, MAX_RUNS, Progress, Stopped};
use super::repair::{self, Repair};
pub use super::state::Dialog;
use super::state::{
    FreeSlackProgress, LAST_STEP, Mode, Navigation, PathPrompt, Pending, Persisted, PinOffer,
    STEP_ZOOM, StepView, StepWindow, Tour, UiState, WouldCause,
};
use super::theme::Theme;
use super::time_axis::TimeAxis;
use super::tour;
use super::views::{self, CampaignModel, ExecModel, Model, ViewCache, Widgets};

/// The plan the app opens without arguments.
pub const DEFAULT_PLAN: &str = include_str!("../../assets/default-plan.json");

/// The app: document, derived analysis, UI state, and the command queue.
pub struct SolscopeApp {
    /// The open plan.
    pub doc: Document,
    /// Its schedule and explanations.
    pub analysis: Analysis,
    /// UI state (not persisted).
    pub ui: UiState,
    /// Persisted settings.
    pub persisted: Persisted,
    /// The palette.
    pub theme: Theme,
    /// Profiles as of the current step: derived once per frame for the step
    /// shown (on a worker in the desktop app while the step moves within one
    /// plan revision, so it may be of an earlier step for a few frames; never
    /// of another revision).
    pub step_view: StepView,
    /// The plan revision `step_view` was derived at.
    step_view_rev: u64,
    /// The worker deriving the step profiles.
    step_views: StepViewCache,
    /// Verify suggestions on a worker thread (the desktop app); headless renders
    /// and tests compute them in the frame so that what they draw is settled.
    pub background: bool,
    /// Bumped on every accepted change of the plan.
    pub revision: u64,
    /// Where the execution's actual durations come from.
    pub actuals: ActualsSource,
    /// Bumped whenever `actuals` changes.
    actuals_rev: u64,
    /// Explanation, valid intervals and suggestions of the selected activity.
    derived: DerivedCache,
    /// The execution of the plan and its cycles' scheduler runs (execution mode).
    execution: ExecutionCache,
    /// The Monte Carlo campaign (execution mode).
    campaign: CampaignCache,
    /// The flexible form of the schedule (schedule mode).
    flex: FlexCache,
    /// What the views keep between frames (built rows, the plots' x range).
    pub(crate) view_cache: ViewCache,
    /// Time of the last automatic step.
    last_tick: f64,
    /// A file dialog for the host to show.
    dialog: Option<Dialog>,
    /// Quit was confirmed.
    quit_now: bool,
    /// A PNG export asked for, for the host to render.
    png_to: Option<PathBuf>,
    /// The selection changed by a link or key: the time range is moved to
    /// show it before the next frame is drawn.
    reveal: bool,
    /// The tutorial plan was just opened: the guided tour starts with the next
    /// frame unless it was dismissed (known only once the host has restored
    /// the persisted settings).
    offer_tour: bool,
    commands: Vec<Command>,
}

impl std::fmt::Debug for SolscopeApp {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SolscopeApp")
            .field("plan", &self.doc.title())
            .field("step", &self.ui.nav.step)
            .finish()
    }
}

impl SolscopeApp {
    /// Opens a plan from JSON text.
    pub fn from_text(text: &str, path: Option<PathBuf>) -> Result<Self, solscope_engine::Error> {
        let doc = Document::from_text(text, path)?;
        let analysis = Analysis::of(&doc.plan)?;
        let axis = TimeAxis::new(doc.plan.horizon.start as f64, doc.plan.horizon.end as f64);
        let steps = analysis.steps();
        let step_view = step_view(&analysis, steps);
        let ui = UiState::new(steps, axis, &doc.plan.local_time);
        Ok(Self {
            doc,
            analysis,
            ui,
            persisted: Persisted::default(),
            theme: Theme::new(true),
            step_view,
            step_view_rev: 0,
            step_views: StepViewCache::default(),
            background: false,
            revision: 0,
            actuals: ActualsSource::Nominal,
            actuals_rev: 0,
            derived: DerivedCache::default(),
            execution: ExecutionCache::default(),
            campaign: CampaignCache::default(),
            flex: FlexCache::default(),
            view_cache: ViewCache::default(),
            last_tick: 0.0,
            dialog: None,
            quit_now: false,
            png_to: None,
            reveal: false,
            offer_tour: false,
            commands: Vec::new(),
        })
    }

    /// The app on the bundled default plan.
    pub fn with_default_plan() -> Result<Self, solscope_engine::Error> {
        Self::from_text(DEFAULT_PLAN, None)
    }

    /// Opens `path`, or the default plan when it cannot be read; the error, if any,
    /// is shown in the app.
    pub fn open_or_default(path: Option<&Path>) -> Result<Self, solscope_engine::Error> {
        let mut app = Self::with_default_plan()?;
        if let Some(p) = path {
            // The same path as File > Open: a bad file keeps the default plan and
            // shows its path-named error.
            app.open_now(p);
        }
        Ok(app)
    }

    /// Queues a command, carried out after the next frame.
    pub fn push(&mut self, cmd: Command) {
        self.commands.push(cmd);
    }

    /// Draws one frame and applies the commands it produced.
    pub fn frame_ui(&mut self, ui: &mut egui::Ui) {
        // Plan files may hold any text: draw a box for a missing glyph, never panic.
        ui.ctx()
            .set_missing_glyph_policy(egui::epaint::text::MissingGlyphPolicy::Tofu);
        let fonts_set = egui::Id::unique("solscope_fonts_set");
        if !ui
            .ctx()
            .data(|d| d.get_temp::<bool>(fonts_set).unwrap_or(false))
        {
            // Once per context (comparing font definitions each frame is costly).
            ui.ctx().set_fonts(super::theme::fonts());
            ui.ctx().data_mut(|d| d.insert_temp(fonts_set, true));
        }
        ui.ctx().set_theme(if self.persisted.light {
            egui::Theme::Light
        } else {
            egui::Theme::Dark
        });
        self.theme = Theme::new(!self.persisted.light);
        if std::mem::take(&mut self.offer_tour) && !self.persisted.tour_dismissed {
            self.start_tour();
        }
        let mut cmds = std::mem::take(&mut self.commands);
        if self.ui.messages.repair.is_none() {
            // The repair view edits text: no undo, stepping or saving of the
            // plan behind it.
            views::shortcuts(ui, &mut cmds);
        }
        views::dropped_files(ui, &mut cmds);
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
            if self.persisted.hide_flex {
                // Nobody looks at the shading: the worker stops (what it
                // found stays).
                self.flex.stop_free_slack();
            } else {
                let axis = self.ui.nav.axis;
                self.flex
                    .request_free_slack(self.revision, (axis.start + axis.end) / 2.0);
            }
        }
        if self.ui.nav.playing {
            let now = ui.input(|i| i.time);
            if now - self.last_tick > 0.15 {
                self.last_tick = now;
                let (k, n) = self.step_and_steps();
                cmds.push(if k < n {
                    self.set_step_command(k + 1)
                } else {
                    Command::Play(false)
                });
            }
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(150));
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
            // Its free slack ahead of the rest (the inspector shows it).
            self.flex.request_one(self.revision, a);
        }
        self.reap_worker();
        // A selection made by a command given outside a frame.
        self.reveal_selection();
        if self.workers_busy_but_free_slack() {
            // Poll the worker until its result is in.
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(50));
        } else if self.flex.busy() {
            // The free slack fills in over minutes: a few repaints a second.
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(500));
        } else if self.campaign.progress().is_some() {
            // The progress bar moves while the campaign runs.
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(100));
        }
        let (m, mut w) = self.model_and_widgets();
        views::layout_ui(ui, &m, &mut w, &mut cmds);
        if !cmds.is_empty() {
            // What the commands change is drawn next frame, even when no input
            // comes (a drop that offers a popup).
            ui.ctx().request_repaint();
        }
        for cmd in cmds {
            self.apply(cmd);
        }
        self.reveal_selection();
    }

    /// Follows a link: `go` changes the selection or step; when they changed,
    /// Back returns to where the user was (selection, step, time range) and
    /// the time range moves to show the selection.
    fn follow(&mut self, go: impl FnOnce(&mut Self)) {
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
    fn go_to(&mut self, place: Option<super::state::Place>) {
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
    fn reveal_selection(&mut self) {
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
        let Some(extent) = views::extent(&self.doc.plan, &self.analysis, run, self.ui.nav.step, a)
        else {
            return;
        };
        let bounds = self.bounds();
        let mut axis = self.ui.nav.axis;
        match extent {
            views::Extent::Bar(s, e) => axis.reveal((s as f64, e as f64), bounds),
            views::Extent::Windows(spans) => {
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

    /// What the search and filters list now, in step order.
    fn listed(&mut self) -> std::sync::Arc<views::Listed> {
        self.view_cache
            .listed(&self.doc.plan, &self.analysis, &self.ui.nav, self.revision)
    }

    /// The read-only model the views draw and the widget state they may write,
    /// for one frame (only what was derived for the selected activity at this
    /// revision).
    pub(crate) fn model_and_widgets(&mut self) -> (Model<'_>, Widgets<'_>) {
        let (selected, revision) = (self.ui.nav.selected, self.revision);
        let derived = &self.derived;
        let m = Model {
            doc: &self.doc,
            analysis: &self.analysis,
            theme: self.theme,
            step_view: &self.step_view,
            persisted: &self.persisted,
            suggestions: selected.and_then(|a| derived.suggestions(a, revision)),
            revision,
            explanation: selected.and_then(|a| derived.explanation(a, revision)),
            explanation_error: selected.and_then(|a| derived.explanation_error(a, revision)),
            valid: selected.and_then(|a| derived.valid(a, revision)),
            // Execution mode explains nothing.
            would_cause: selected
                .filter(|_| self.ui.nav.mode == Mode::Schedule)
                .and_then(|a| derived.would_cause(a, revision)),
            flex: self.flex.get(revision),
            free_slack: self.flex.free_slack_progress(revision),
            nav: &self.ui.nav,
            messages: &self.ui.messages,
            exec: ExecModel {
                campaign: campaign_model(&self.campaign, revision),
                ..exec_model(
                    &self.execution,
                    &self.actuals,
                    &self.ui.nav,
                    self.exec_key(),
                )
            },
        };
        let w = Widgets {
            text: &mut self.ui.text,
            cache: &mut self.view_cache,
        };
        (m, w)
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

    /// Where activity `a`'s bar was drawn on the Gantt in the last frame (its
    /// placement's bar, in schedule mode), if it was.
    pub fn gantt_bar(&self, a: usize) -> Option<egui::Rect> {
        self.view_cache.gantt_bar(a)
    }

    /// The activities the list shows with the search and filters as they are,
    /// in step order.
    pub fn list_shown(&mut self) -> Vec<usize> {
        self.listed().shown.clone()
    }

    /// How each activity bar the Gantt drew last frame looked against the
    /// search and filters (an activity with several bars appears once per
    /// bar).
    pub fn gantt_looks(&self) -> &[(usize, views::Look)] {
        &self.view_cache.looks
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
    fn exec_key(&self) -> ExecKey {
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
            self.execution
                .request_loss(&self.doc.plan, key, a, self.background);
        }
        if let Some(n) = self.execution.cycle(key, cycle).map(|c| c.steps()) {
            self.execution
                .derive_view(key, cycle, self.ui.nav.cycle_step.min(n));
        }
    }

    /// The step shown and the number of steps of the run the step slider moves
    /// through: the plan's schedule, or in execution mode the looked-at cycle's
    /// run (no steps while it is derived).
    fn step_and_steps(&self) -> (usize, usize) {
        match self.ui.nav.mode {
            Mode::Schedule => (self.ui.nav.step, self.analysis.steps()),
            Mode::Execution => {
                let m = exec_model(
                    &self.execution,
                    &self.actuals,
                    &self.ui.nav,
                    self.exec_key(),
                );
                (m.step, m.cycle_run.map_or(0, |c| c.steps()))
            }
        }
    }

    /// The steps (1-based) at which an activity failed in the run the step
    /// slider moves through, each with the plan activity that failed.
    fn failed_steps(&self) -> Vec<(usize, Option<usize>)> {
        match self.ui.nav.mode {
            Mode::Schedule => views::failed_steps(&self.analysis.schedule.steps)
                .map(|(k, a)| (k, Some(a)))
                .collect(),
            Mode::Execution => match self.cycle_run() {
                Some(CycleRun {
                    schedule: Ok(s), ..
                }) => views::failed_steps(&s.steps)
                    .filter_map(|(k, i)| self.cycle_run().map(|c| (k, c.plan_activity(i))))
                    .collect(),
                _ => Vec::new(),
            },
        }
    }

    /// The command that shows step `k` of the run the step slider moves through.
    fn set_step_command(&self, k: usize) -> Command {
        match self.ui.nav.mode {
            Mode::Schedule => Command::SetStep(k),
            Mode::Execution => Command::SetCycleStep(k),
        }
    }

    /// The cycle looked at (clamped to the current execution's) and how many
    /// cycles it has, once the execution is derived.
    fn cycle_and_cycles(&self) -> Option<(usize, usize)> {
        match self.execution.run(self.exec_key()) {
            Some(Ok(run)) => Some((
                run.cycle_index(self.ui.nav.cycle),
                run.execution.cycles.len(),
            )),
            _ => None,
        }
    }

    /// Uses `source` for the actual durations if it fits the plan; otherwise
    /// nothing changes and `what` is shown with the path-named error.
    fn use_actuals(&mut self, source: ActualsSource, what: &str) {
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

    /// Carries out one command.
    pub fn apply(&mut self, cmd: Command) {
        match cmd {
            Command::Ui(cmd) => self.run(cmd),
            Command::SetStep(k) => self.set_step(k),
            Command::Play(on) => {
                let (k, n) = self.step_and_steps();
                if on && k >= n {
                    let first = self.set_step_command(0);
                    self.apply(first);
                }
                self.ui.nav.playing = on;
            }
            Command::SetCycle(k) => {
                self.ui.nav.cycle = match self.cycle_and_cycles() {
                    Some((_, n)) => k.min(n.saturating_sub(1)),
                    None => k,
                };
                self.ui.nav.cycle_step = LAST_STEP;
                self.ui.nav.steps_shown = StepWindow::ALL;
            }
            Command::SetCycleStep(k) => {
                self.ui.nav.cycle_step = k;
                self.follow_step();
            }
            Command::SetStepsShown(w) => self.ui.nav.steps_shown = w,
            Command::OpenActuals(path) => {
                let what = format!("Could not open actuals {}", path.display());
                match solscope_engine::read_plan_text(&path, solscope_engine::MAX_PLAN_BYTES) {
                    Ok(text) => self.use_actuals(ActualsSource::File { path, text }, &what),
                    Err(e) => self.ui.messages.error = Some(format!("{what}: {e}")),
                }
            }
            Command::SampleActuals { seed, run } => {
                let source = ActualsSource::Sampled { seed, run };
                self.use_actuals(source, "Could not sample actuals");
            }
            Command::RunCampaign { runs, seed } | Command::ComparePolicies { runs, seed } => {
                if (1..=MAX_RUNS).contains(&runs) {
                    let compare = matches!(cmd, Command::ComparePolicies { .. });
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
            Command::Select(a) => self.follow(|app| app.ui.nav.selected = a),
            Command::GoToFailureStep(a) => self.follow(|app| {
                app.ui.nav.selected = Some(a);
                if let Some(k) = app.explanation_for(a).and_then(|e| e.failure_step) {
                    app.set_step(k);
                }
            }),
            Command::SetAxis(axis) => {
                self.ui.nav.axis = axis;
                self.ui.nav.axis.clamp(self.bounds());
                self.ui.sync_range_text(&self.doc.plan.local_time);
            }
            Command::ProbePlot(t) => self.ui.nav.probe = t,
            Command::SetSinceFull(on) => self.ui.nav.since_full = on,
            Command::ShowReason { activity, index } => {
                self.ui.nav.overlay_reason = Some((activity, index));
            }
            Command::Edit {
                target,
                set,
                description,
            } => match solscope_engine::apply_edit(&self.doc.plan, &target, &set) {
                Ok(plan) => self.accept_plan(plan, &description),
                Err(e) => self.ui.messages.error = Some(format!("{description}: not applied: {e}")),
            },
            Command::Open(path) => {
                if self.doc.dirty {
                    self.ui.messages.confirm = Some(Pending::Open(path));
                } else {
                    self.open_now(&path);
                }
            }
            Command::SaveTo(path) => self.save_to(&path),
            Command::Chosen { dialog, path } => self.chosen(dialog, path),
            Command::DialogCancelled => {
                self.ui.messages.path_prompt = None;
                self.ui.messages.after_save = None;
            }
            Command::AskPath { dialog, why } => {
                self.ui.text.path_text = self.suggested_path(dialog).display().to_string();
                self.ui.messages.path_prompt = Some(PathPrompt { dialog, why });
            }
            Command::SaveAndContinue => {
                let pending = self.ui.messages.confirm.take();
                match self.doc.path.clone() {
                    Some(p) => {
                        self.save_to(&p);
                        if !self.doc.dirty {
                            self.go_on(pending);
                        }
                    }
                    None => {
                        self.ui.messages.after_save = pending;
                        self.dialog = Some(Dialog::SaveAs);
                    }
                }
            }
            Command::ExportScheduleTo(path) => self.export_schedule_to(&path),
            Command::SetDark(dark) => self.persisted.light = !dark,
            Command::GroupByResource(on) => self.persisted.by_resource = on,
            Command::SetFilter(f) => self.ui.nav.filter.search = f,
            Command::SetListFilter(f) => self.ui.nav.filter = f,
            Command::RepairJump(i) => self.repair_jump(i),
            Command::ShowError(e) => self.ui.messages.error = Some(e),
            Command::OfferPin { activity, start } => {
                self.ui.messages.pin = Some(PinOffer { activity, start });
            }
            Command::DismissPin => self.ui.messages.pin = None,
            Command::Pin { activity, start } => self.pin(activity, start),
            Command::DismissBanner => self.ui.messages.banner = None,
            Command::DismissError => self.ui.messages.error = None,
            Command::ConfirmDiscard(yes) => {
                let pending = self.ui.messages.confirm.take();
                if yes {
                    self.go_on(pending);
                }
            }
            Command::TourPage(k) => self.tour_page(k),
        }
    }

    /// Starts the guided tour on the plan open, following its first failure.
    fn start_tour(&mut self) {
        let target = tour::first_failure(&self.analysis)
            .and_then(|a| self.doc.plan.activities.get(a))
            .map(|a| a.id.clone());
        self.ui.messages.tour = Some(Tour { page: 0, target });
        self.tour_page(0);
    }

    /// Shows page `k` of the guided tour (when it is shown) and gives the
    /// commands of that page.
    fn tour_page(&mut self, k: usize) {
        let Some(t) = self.ui.messages.tour.as_mut() else {
            return;
        };
        t.page = k.min(tour::Page::ALL.len() - 1);
        let page = tour::Page::at(t.page);
        let target = t
            .target
            .as_ref()
            .and_then(|id| self.doc.plan.activities.iter().position(|a| &a.id == id));
        for cmd in tour::enter(page, &self.analysis, target) {
            self.apply(cmd);
        }
    }

    /// Opens the bundled tutorial plan (without a file: saving asks where)
    /// and starts the guided tour.
    fn open_tutorial(&mut self) {
        match Self::from_text(tour::TUTORIAL_PLAN, None) {
            Ok(fresh) => {
                self.become_(fresh);
                self.start_tour();
            }
            Err(e) => {
                self.ui.messages.error = Some(format!("Could not open the tutorial plan: {e}"));
            }
        }
    }

    /// Carries out what waited for the unsaved-changes question.
    fn go_on(&mut self, pending: Option<Pending>) {
        match pending {
            Some(Pending::Open(p)) => self.open_now(&p),
            Some(Pending::OpenTutorial) => self.open_tutorial(),
            Some(Pending::Quit) => self.quit_now = true,
            None => {}
        }
    }

    /// Opens, saves or exports at `path`, chosen for `dialog`.
    fn chosen(&mut self, dialog: Dialog, path: PathBuf) {
        self.ui.messages.path_prompt = None;
        let path = if dialog.saves() && path.extension().is_none() {
            path.with_extension(dialog.extension())
        } else {
            path
        };
        match dialog {
            Dialog::Open => self.apply(Command::Open(path)),
            Dialog::OpenActuals => self.apply(Command::OpenActuals(path)),
            Dialog::SaveAs => {
                self.save_to(&path);
                let after = self.ui.messages.after_save.take();
                if !self.doc.dirty {
                    self.go_on(after);
                }
            }
            Dialog::ExportSchedule => self.export_schedule_to(&path),
            Dialog::ExportScheduleCsv => self.export_csv_to(&path),
            Dialog::ExportPng => self.png_to = Some(path),
        }
    }

    /// Where a file chosen for `dialog` is proposed: beside the plan (or in the
    /// working directory), named after it (`plan.json`, `plan-schedule.csv`,
    /// `plan.png`); a directory for the dialogs that open a file.
    pub fn suggested_path(&self, dialog: Dialog) -> PathBuf {
        let dir = self
            .doc
            .path
            .as_deref()
            .and_then(Path::parent)
            .map(Path::to_path_buf)
            .or_else(|| std::env::current_dir().ok())
            .unwrap_or_default();
        let stem = self.doc.file_stem();
        let name = match dialog {
            Dialog::Open | Dialog::OpenActuals => return dir.join(""),
            Dialog::SaveAs => format!("{stem}.json"),
            Dialog::ExportSchedule => format!("{stem}-schedule.json"),
            Dialog::ExportScheduleCsv => format!("{stem}-schedule.csv"),
            Dialog::ExportPng => format!("{stem}.png"),
        };
        dir.join(name)
    }

    /// The file a PNG export was asked for since the last call, for the host to
    /// render the view into.
    pub fn take_png_request(&mut self) -> Option<PathBuf> {
        self.png_to.take()
    }

    /// Takes persisted settings restored by the host; the plan open (from the
    /// command line) goes first in the recent files.
    pub fn restore_persisted(&mut self, persisted: Persisted) {
        self.persisted = persisted;
        if let Some(p) = self.doc.path.clone() {
            self.persisted.remember(&p);
        }
    }

    /// Carries out a command given by name.
    fn run(&mut self, cmd: UiCommand) {
        let (k, steps) = self.step_and_steps();
        match cmd {
            UiCommand::Open => self.dialog = Some(Dialog::Open),
            UiCommand::Save => match self.doc.path.clone() {
                Some(p) => self.save_to(&p),
                None => self.dialog = Some(Dialog::SaveAs),
            },
            UiCommand::SaveAs => self.dialog = Some(Dialog::SaveAs),
            UiCommand::ExportSchedule => self.dialog = Some(Dialog::ExportSchedule),
            UiCommand::ExportScheduleCsv => self.dialog = Some(Dialog::ExportScheduleCsv),
            UiCommand::ExportPng => self.dialog = Some(Dialog::ExportPng),
            UiCommand::Quit => {
                if self.doc.dirty {
                    self.ui.messages.confirm = Some(Pending::Quit);
                } else {
                    self.quit_now = true;
                }
            }
            UiCommand::Undo => {
                let before = self.doc.plan.clone();
                if self.doc.undo() {
                    self.reanalyse(before, "Undo");
                }
            }
            UiCommand::Redo => {
                let before = self.doc.plan.clone();
                if self.doc.redo() {
                    self.reanalyse(before, "Redo");
                }
            }
            UiCommand::AddActivity => match add_activity(&self.doc.plan, self.ui.nav.selected) {
                Ok(edit) => self.edit_activities(edit),
                Err(e) => self.ui.messages.error = Some(e),
            },
            UiCommand::DuplicateActivity => {
                if let Some(edit) = self
                    .ui
                    .nav
                    .selected
                    .and_then(|a| duplicate_activity(&self.doc.plan, a))
                {
                    self.edit_activities(edit);
                }
            }
            UiCommand::DeleteActivity => {
                if let Some(edit) = self
                    .ui
                    .nav
                    .selected
                    .and_then(|a| delete_activity(&self.doc.plan, a))
                {
                    self.edit_activities(edit);
                }
            }
            UiCommand::RecheckRepair => self.recheck_repair(),
            UiCommand::ReplaceAtError => {
                let text = &mut self.ui.text.repair_text;
                let at = self
                    .ui
                    .messages
                    .repair
                    .as_ref()
                    .and_then(|r| r.errors.get(r.selected?))
                    .and_then(|e| repair::locate(text, &e.path));
                if let Some(span) = at {
                    text.replace_range(span, &self.ui.text.repair_value);
                }
                self.recheck_repair();
            }
            UiCommand::CancelRepair => {
                self.ui.messages.repair = None;
                self.ui.text.repair_text.clear();
                self.ui.text.repair_value.clear();
                self.ui.text.repair_cursor = None;
            }
            UiCommand::FirstStep => self.apply(self.set_step_command(0)),
            UiCommand::PreviousStep => {
                if k > 0 {
                    self.apply(self.set_step_command(k - 1));
                }
            }
            UiCommand::NextStep => {
                if k < steps {
                    self.apply(self.set_step_command(k + 1));
                }
            }
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
            UiCommand::Search => self.ui.text.focus_search = true,
            UiCommand::ClearFilters => self.ui.nav.filter = Default::default(),
            UiCommand::GuidedTour => {
                if tour::is_tutorial(&self.doc.plan) {
                    self.start_tour();
                } else if self.doc.dirty {
                    self.ui.messages.confirm = Some(Pending::OpenTutorial);
                } else {
                    self.open_tutorial();
                }
            }
            UiCommand::EndTour => {
                self.ui.messages.tour = None;
                self.persisted.tour_dismissed = true;
            }
            UiCommand::ResetTour => self.persisted.tour_dismissed = false,
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
            UiCommand::ZoomStepsIn | UiCommand::ZoomStepsOut => {
                let factor = if cmd == UiCommand::ZoomStepsIn {
                    STEP_ZOOM
                } else {
                    1.0 / STEP_ZOOM
                };
                self.ui.nav.steps_shown = self.ui.nav.steps_shown.zoomed(factor, k, steps);
            }
            UiCommand::AllSteps => self.ui.nav.steps_shown = StepWindow::ALL,
            UiCommand::OpenActuals => self.dialog = Some(Dialog::OpenActuals),
            UiCommand::CancelCampaign => self.campaign.cancel(),
            UiCommand::ToggleFlex => self.persisted.hide_flex = !self.persisted.hide_flex,
            UiCommand::ToggleComparePolicies => {
                self.persisted.compare_policies = !self.persisted.compare_policies;
            }
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
        }
    }

    /// The file dialog asked for since the last call, for the host to show.
    pub fn take_dialog(&mut self) -> Option<Dialog> {
        self.dialog.take()
    }

    /// Quit was asked for (and confirmed if there were unsaved changes).
    pub fn quit_confirmed(&self) -> bool {
        self.quit_now
    }

    /// Plan bounds as `f64`.
    pub fn bounds(&self) -> (f64, f64) {
        (
            self.doc.plan.horizon.start as f64,
            self.doc.plan.horizon.end as f64,
        )
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
    fn reap_worker(&mut self) {
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

    /// Pins activity `a` at `start` (one window `[start, start]`) through the
    /// edit path, so the plan is validated, rescheduled and undoable.
    fn pin(&mut self, a: usize, start: i64) {
        self.ui.messages.pin = None;
        let Some(act) = self.doc.plan.activities.get(a) else {
            return;
        };
        let placed = self.analysis.placement(a).map(|p| p.0);
        let (window, dropped) = pin_window(act, placed, start);
        let mut description = format!(
            "Pin {} at {}",
            act.id,
            solscope_engine::format_plan_time(&self.doc.plan.local_time, start)
        );
        if let Some(c) = dropped {
            description.push_str(&format!(" (dropping its cutoff {c})"));
        }
        let windows = match serde_json::to_value([window]) {
            Ok(v) => v,
            Err(e) => {
                self.ui.messages.error = Some(format!("{description}: not applied: {e}"));
                return;
            }
        };
        let mut set = serde_json::Map::new();
        set.insert("windows".into(), windows);
        let target = format!("activity:{}", act.id);
        self.apply(Command::Edit {
            target,
            set,
            description,
        });
    }

    /// Shows step `k`. Its profiles are derived before the next frame is
    /// drawn ([`Self::derive_step_view`]): however many steps are given
    /// between two frames, only the last one costs.
    fn set_step(&mut self, k: usize) {
        self.ui.nav.step = k.min(self.analysis.steps());
        self.follow_step();
    }

    /// The step slider's zoomed span follows the step shown (the least move
    /// that keeps it in view).
    fn follow_step(&mut self) {
        let (k, n) = self.step_and_steps();
        self.ui.nav.steps_shown = self.ui.nav.steps_shown.following(k, n);
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

    fn accept_plan(&mut self, plan: Plan, description: &str) {
        let before = self.doc.plan.clone();
        if self.doc.replace(plan) {
            self.reanalyse(before, description);
        } else {
            // Nothing to reschedule or undo; the editor shows the plan again.
            self.ui.messages.banner = Some(OutcomeDiff::unchanged(description));
            self.ui.messages.error = None;
            self.ui.text.editor.clear();
        }
    }

    /// Reschedules the current plan and shows the outcome diff against `before`.
    fn reanalyse(&mut self, before: Plan, description: &str) {
        match self.analysis.rerun(&self.doc.plan) {
            Ok(analysis) => {
                self.ui.nav.selected = self.ui.nav.selected.and_then(|a| {
                    // The same activity by id (an activity added, deleted or
                    // undone moves the others); by place when its id changed.
                    let acts = &self.doc.plan.activities;
                    let id = &before.activities.get(a)?.id;
                    acts.iter()
                        .position(|x| &x.id == id)
                        .or_else(|| (acts.len() == before.activities.len()).then_some(a))
                });
                let old = std::mem::replace(&mut self.analysis, analysis);
                self.ui.messages.banner = Some(OutcomeDiff::between(
                    description,
                    (&before, &old),
                    (&self.doc.plan, &self.analysis),
                ));
                self.ui.messages.error = None;
                // An offer to pin was for the plan as it was.
                self.ui.messages.pin = None;
                self.revision += 1;
                let mut k = self.ui.nav.step.min(self.analysis.steps());
                if k == old.steps() {
                    k = self.analysis.steps();
                }
                self.set_step(k);
            }
            Err(e) => self.ui.messages.error = Some(format!("{description}: {e}")),
        }
    }

    fn open_now(&mut self, path: &Path) {
        let text = match solscope_engine::read_plan_text(path, solscope_engine::MAX_PLAN_BYTES) {
            Ok(t) => t,
            Err(e) => {
                self.ui.messages.error = Some(format!("Could not open {}: {e}", path.display()));
                return;
            }
        };
        match Self::from_text(&text, Some(path.to_path_buf())) {
            Ok(fresh) => {
                self.become_(fresh);
                // The guided tour opens with the tutorial plan.
                self.offer_tour = tour::is_tutorial(&self.doc.plan);
            }
            Err(e) => {
                // Keep the current plan; repair the file's text in the repair
                // view (every error listed), or say what is wrong when there
                // is nothing to repair in it.
                let repair = Repair::new(Some(path.to_path_buf()), &text);
                if repair.errors.is_empty() {
                    self.ui.messages.error =
                        Some(format!("Could not open {}: {e}", path.display()));
                    return;
                }
                self.ui.messages.repair = Some(repair);
                self.ui.messages.error = None;
                self.ui.text.repair_text = text;
                self.repair_jump(0);
            }
        }
    }

    /// Takes `fresh` (a plan just opened) as the app, keeping the settings,
    /// the mode and how derived values are computed; its file goes first in
    /// Recent.
    fn become_(&mut self, mut fresh: Self) {
        fresh.persisted = std::mem::take(&mut self.persisted);
        fresh.background = self.background;
        // The mode stays; the actuals were for the other plan.
        fresh.ui.nav.mode = self.ui.nav.mode;
        if let Some(p) = fresh.doc.path.clone() {
            fresh.persisted.remember(&p);
        }
        *self = fresh;
    }

    /// Repair view: checks the text again; with no error left it opens as the
    /// plan (unsaved: its file still holds the broken text), else the first
    /// error is looked at.
    fn recheck_repair(&mut self) {
        let Some(repair) = self.ui.messages.repair.as_mut() else {
            return;
        };
        repair.errors = repair::check(&self.ui.text.repair_text);
        repair.checks += 1;
        repair.selected = None;
        if !repair.errors.is_empty() {
            self.repair_jump(0);
            return;
        }
        let path = repair.path.clone();
        match Self::from_text(&self.ui.text.repair_text, path) {
            Ok(mut fresh) => {
                fresh.doc.mark_unsaved();
                self.become_(fresh);
            }
            // It validates, yet does not schedule: said in the repair view.
            Err(e) => {
                if let Some(repair) = self.ui.messages.repair.as_mut() {
                    repair.errors = vec![repair::PlanError {
                        path: "$".into(),
                        reason: e.to_string(),
                    }];
                }
            }
        }
    }

    /// Repair view: looks at error `i`, its value put in the value field and
    /// selected in the text.
    fn repair_jump(&mut self, i: usize) {
        let Some(repair) = self.ui.messages.repair.as_mut() else {
            return;
        };
        let Some(err) = repair.errors.get(i) else {
            return;
        };
        repair.selected = Some(i);
        let text = &self.ui.text.repair_text;
        let span = repair::locate(text, &err.path);
        self.ui.text.repair_value = span
            .as_ref()
            .and_then(|s| text.get(s.clone()))
            .unwrap_or("")
            .to_string();
        self.ui.text.repair_cursor = span.map(|s| repair::char_range(text, &s));
    }

    /// Applies a change of the list of activities as a plan edit (validated,
    /// rescheduled, undoable) and selects what it names.
    fn edit_activities(&mut self, edit: ActivitiesEdit) {
        let ActivitiesEdit {
            activities,
            select,
            description,
        } = edit;
        let value = match serde_json::to_value(&activities) {
            Ok(v) => v,
            Err(e) => {
                self.ui.messages.error = Some(format!("{description}: not applied: {e}"));
                return;
            }
        };
        let mut set = serde_json::Map::new();
        set.insert("activities".into(), value);
        let revision = self.revision;
        self.apply(Command::Edit {
            target: "plan".into(),
            set,
            description,
        });
        if self.revision != revision {
            self.ui.nav.selected =
                select.and_then(|id| self.doc.plan.activities.iter().position(|a| a.id == id));
        }
    }

    fn save_to(&mut self, path: &Path) {
        match write_json(&self.doc.plan, path) {
            Ok(()) => {
                self.doc.mark_saved(path.to_path_buf());
                self.persisted.remember(path);
            }
            Err(e) => {
                self.ui.messages.error = Some(format!("Could not save {}: {e}", path.display()))
            }
        }
    }

    fn export_schedule_to(&mut self, path: &Path) {
        let loaded = solscope_engine::LoadedPlan {
            plan: self.doc.plan.clone(),
            warnings: self.doc.warnings.clone(),
        };
        let doc =
            solscope_engine::schedule_document(&loaded, &self.analysis.schedule, &self.doc.title());
        if let Err(e) = write_json(&doc, path) {
            self.ui.messages.error = Some(format!("Could not write {}: {e}", path.display()));
        }
    }
}

impl SolscopeApp {
    fn export_csv_to(&mut self, path: &Path) {
        let csv = solscope_engine::schedule_csv(&self.doc.plan, &self.analysis.schedule);
        if let Err(e) = std::fs::write(path, csv) {
            self.ui.messages.error = Some(format!("Could not write {}: {e}", path.display()));
        }
    }
}

/// What execution mode draws, as far as it is derived at `key` (the current plan
/// revision and actuals).
fn exec_model<'a>(
    execution: &'a ExecutionCache,
    source: &'a ActualsSource,
    nav: &Navigation,
    key: ExecKey,
) -> ExecModel<'a> {
    let run = execution.run(key);
    let cycle = match run {
        Some(Ok(r)) => r.cycle_index(nav.cycle),
        _ => nav.cycle,
    };
    let cycle_run = execution.cycle(key, cycle);
    let step = cycle_run.map_or(0, |c| nav.cycle_step.min(c.steps()));
    ExecModel {
        source,
        actuals_rev: key.actuals,
        run,
        cycle,
        cycle_run,
        step,
        view: execution.view(key, cycle, step),
        loss: nav.selected.and_then(|a| execution.loss(key, a)),
        campaign: CampaignModel::default(),
    }
}

/// What the Monte Carlo panel draws at plan revision `revision`.
fn campaign_model(campaign: &CampaignCache, revision: u64) -> CampaignModel<'_> {
    CampaignModel {
        result: campaign.result(revision),
        running: campaign.progress(),
        stale: campaign.stale(revision),
        stopped: campaign.stopped(),
    }
}

/// Writes `value` as pretty JSON (with a final newline) to `path`. Nothing is
/// written when it cannot be serialised.
fn write_json<T: serde::Serialize>(value: &T, path: &Path) -> Result<(), String> {
    let text =
        serde_json::to_string_pretty(value).map_err(|e| format!("cannot serialise it: {e}"))?;
    std::fs::write(path, text + "\n").map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn opening_at_start_up_falls_back_to_the_default_plan_and_repairs_the_file() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let good = root.join("assets/examples/pitfall.json");
        let app = SolscopeApp::open_or_default(Some(&good)).expect("app");
        assert_eq!(app.doc.plan.activities.len(), 2);
        assert_eq!(app.doc.path.as_deref(), Some(good.as_path()));
        assert!(app.ui.messages.error.is_none());
        let bad = root.join("tests/malformed/window-end-before-start.json");
        let app = SolscopeApp::open_or_default(Some(&bad)).expect("app");
        assert_eq!(
            app.doc.plan,
            SolscopeApp::with_default_plan().expect("default").doc.plan
        );
        // The file is in the repair view, with its error.
        let repair = app.ui.messages.repair.expect("repair view");
        assert_eq!(repair.path.as_deref(), Some(bad.as_path()));
        assert!(
            repair.errors[0].path.ends_with("windows[0].end"),
            "{repair:?}"
        );
        assert!(app.ui.text.repair_text.contains("\"end\""));
        // A file that cannot be read has no text to repair: the error.
        let app = SolscopeApp::open_or_default(Some(&root.join("no-such-plan.json"))).expect("app");
        assert!(app.ui.messages.repair.is_none());
        let err = app.ui.messages.error.expect("error shown");
        assert!(err.starts_with("Could not open"), "{err}");
    }

    #[test]
    fn step_view_series_are_monotone_in_time() {
        let app = SolscopeApp::with_default_plan().expect("default plan");
        for series in [&app.step_view.soc, &app.step_view.peak, &app.step_view.data] {
            assert!(
                series.windows(2).all(|w| w[0][0] <= w[1][0]),
                "time goes backwards"
            );
        }
        // A step function: consecutive pairs share x or y.
        assert!(
            app.step_view
                .peak
                .windows(2)
                .all(|w| w[0][0] == w[1][0] || w[0][1] == w[1][1])
        );
    }

    /// A directory that does not exist, in a fresh temporary directory.
    fn missing_dir(name: &str) -> PathBuf {
        std::env::temp_dir()
            .join(format!("solscope-{name}-{}", std::process::id()))
            .join("missing")
    }

    #[test]
    fn a_failed_schedule_export_is_shown_and_writes_nothing() {
        let mut app = SolscopeApp::with_default_plan().expect("default plan");
        let path = missing_dir("export").join("schedule.json");
        app.apply(Command::ExportScheduleTo(path.clone()));
        let err = app.ui.messages.error.clone().expect("error shown");
        assert!(err.starts_with("Could not write "), "{err}");
        assert!(err.contains("schedule.json"), "{err}");
        assert!(!path.exists());
    }

    #[test]
    fn a_failed_save_is_shown_and_keeps_the_plan_unsaved() {
        let mut app = SolscopeApp::with_default_plan().expect("default plan");
        app.doc.dirty = true;
        let path = missing_dir("save").join("plan.json");
        app.apply(Command::SaveTo(path.clone()));
        let err = app.ui.messages.error.clone().expect("error shown");
        assert!(err.starts_with("Could not save "), "{err}");
        assert!(app.doc.dirty);
        assert!(app.doc.path.is_none());
        assert!(!path.exists());
    }

    #[test]
    fn what_cannot_be_serialised_is_an_error_and_no_file() {
        // JSON object keys must be strings: serialising this map fails.
        let value: std::collections::BTreeMap<(u8, u8), u8> = [((1, 2), 3)].into();
        let dir = std::env::temp_dir().join(format!("solscope-ser-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let path = dir.join("out.json");
        let err = write_json(&value, &path).expect_err("not serialisable");
        assert!(err.starts_with("cannot serialise it"), "{err}");
        assert!(!path.exists(), "no empty file");
        std::fs::remove_dir_all(&dir).expect("clean up");
    }

    #[test]
    fn an_error_from_a_view_is_a_command() {
        let mut app = SolscopeApp::with_default_plan().expect("default plan");
        app.apply(Command::ShowError("Time range: bad".into()));
        assert_eq!(app.ui.messages.error.as_deref(), Some("Time range: bad"));
        app.apply(Command::DismissError);
        assert!(app.ui.messages.error.is_none());
    }
}
