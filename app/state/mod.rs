//! The app's state, with no toolkit in it: the open plan and its analysis
//! ([`Document`], [`Analysis`]), the runtime state ([`UiState`]) apart from
//! what survives restarts ([`Persisted`]), the commands ([`UiCommand`] with
//! their labels and shortcuts as data, [`Command`]), the reducer
//! ([`AppState::apply`], by area in `reduce/`), and the values derived from
//! them on worker threads (each one `Job`, `job.rs`). Every change of state
//! can be driven and checked without a window; the gui (`crate::gui`) draws it
//! and turns input into commands.
//!
//! Modules, lowest first (each uses only those before it): `axis`, `job`
//! → `document`, `repair`, `tune` → `persisted`, `ui` → `commands`,
//! `status`, `execution` → `extent`, `list`, `tour`, `montecarlo` →
//! `exec_model`, `derived` → this module (`AppState`), `frame`, `opening`,
//! `reduce`.

mod axis;
pub mod commands;
mod derived;
pub mod document;
mod exec_model;
pub mod execution;
mod extent;
mod frame;
mod job;
mod list;
pub mod montecarlo;
mod opening;
mod persisted;
mod reduce;
pub mod repair;
mod status;
pub mod tour;
pub mod tune;
mod ui;

#[cfg(test)]
mod tests;

use std::path::{Path, PathBuf};

pub use axis::TimeAxis;
pub use commands::{Command, Key, Modifiers, Shortcut, UiCommand};
pub use derived::FlexResult;
pub use document::{Analysis, Document, OutcomeDiff};
pub use exec_model::{CampaignModel, ExecModel};
pub use execution::{ActualsSource, CycleRun, ExecutionRun};
pub use extent::{Extent, extent, window_spans};
pub use frame::FrameReads;
pub use list::{Listed, SearchIndex};
pub use montecarlo::{CampaignResult, Progress, StopReason, Stopped};
pub use persisted::Persisted;
pub use status::{Status, failed_steps, status_at};
pub use ui::{
    DEFAULT_CAMPAIGN_RUNS, Dialog, EditorBuffers, FLEX_LAYER_MAX_ACTIVITIES, FreeSlackProgress,
    HISTORY_LIMIT, History, LAST_STEP, ListFilter, MIN_STEPS_SHOWN, Messages, Mode, Navigation,
    OverlayPlot, OverlayReason, PathPrompt, Pending, PinOffer, Place, STEP_ZOOM, StatusFilter,
    StepView, StepWindow, TextBuffers, Tour, UiState, WouldCause,
};

use derived::{CampaignCache, DerivedCache, ExecutionCache, FlexCache, StepViewCache, step_view};
use list::ListCache;

/// The plan the app opens without arguments.
pub const DEFAULT_PLAN: &str = include_str!("../../assets/default-plan.json");

/// The app's state: document, derived analysis, UI state, and the command
/// queue; changed only by [`AppState::apply`].
pub struct AppState {
    /// The open plan.
    pub doc: Document,
    /// Its schedule and explanations.
    pub analysis: Analysis,
    /// UI state (not persisted).
    pub ui: UiState,
    /// Persisted settings.
    pub persisted: Persisted,
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
    /// Priority tuning: its panel, search and result.
    tune: tune::TuneCache,
    /// What the activity list's search and filters select.
    list: ListCache,
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
    /// A plan file being opened on a worker (the plan above stays until it
    /// is in).
    opening: Option<opening::Opening>,
    /// Opens started (each worker's key).
    opens: u64,
}

impl std::fmt::Debug for AppState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AppState")
            .field("plan", &self.doc.title())
            .field("step", &self.ui.nav.step)
            .finish()
    }
}

impl AppState {
    /// Opens a plan from JSON text.
    pub fn from_text(text: &str, path: Option<PathBuf>) -> Result<Self, solscope_engine::Error> {
        Self::from_text_limited(text, path, solscope_engine::MAX_PLAN_BYTES)
    }

    /// [`AppState::from_text`] with another size limit (`screenshot
    /// --max-input-mib`).
    pub fn from_text_limited(
        text: &str,
        path: Option<PathBuf>,
        limit: usize,
    ) -> Result<Self, solscope_engine::Error> {
        let doc = Document::from_text_limited(text, path, limit)?;
        let analysis = Analysis::of(&doc.plan)?;
        Ok(Self::from_analysis(doc, analysis))
    }

    /// The app on a validated plan and its schedule.
    fn from_analysis(doc: Document, analysis: Analysis) -> Self {
        let axis = TimeAxis::new(doc.plan.horizon.start as f64, doc.plan.horizon.end as f64);
        let steps = analysis.steps();
        let step_view = step_view(&analysis, steps);
        let ui = UiState::new(steps, axis, &doc.plan.local_time);
        Self {
            doc,
            analysis,
            ui,
            persisted: Persisted::default(),
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
            tune: tune::TuneCache::default(),
            list: ListCache::default(),
            last_tick: 0.0,
            dialog: None,
            quit_now: false,
            png_to: None,
            reveal: false,
            offer_tour: false,
            commands: Vec::new(),
            opening: None,
            opens: 0,
        }
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

    /// The commands queued since the last frame, to be carried out after it.
    pub fn take_commands(&mut self) -> Vec<Command> {
        std::mem::take(&mut self.commands)
    }

    /// The file dialog asked for since the last call, for the host to show.
    pub fn take_dialog(&mut self) -> Option<Dialog> {
        self.dialog.take()
    }

    /// Quit was asked for (and confirmed if there were unsaved changes).
    pub fn quit_confirmed(&self) -> bool {
        self.quit_now
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

    /// Plan bounds as `f64`.
    pub fn bounds(&self) -> (f64, f64) {
        (
            self.doc.plan.horizon.start as f64,
            self.doc.plan.horizon.end as f64,
        )
    }
}
