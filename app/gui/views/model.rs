//! What the views read and write for one frame: the read-only [`Model`] of
//! the state, the widget state they may write ([`Widgets`]), and what they
//! keep between frames ([`ViewCache`]).

use eframe::egui;
use solscope_engine::Suggestion;

use super::gantt::{BarDrag, GanttRows};
use super::tour::TourAnchors;
use crate::gui::theme::Theme;
use crate::state::tune::TuneModel;
use crate::state::{
    Analysis, Document, ExecModel, FreeSlackProgress, Listed, Messages, Mode, Navigation,
    Persisted, SearchIndex, Status, StepView, TextBuffers, WouldCause, status_at,
};

/// Read-only view of the app for one frame.
pub struct Model<'a> {
    /// The open plan.
    pub doc: &'a Document,
    /// Its schedule and explanations.
    pub analysis: &'a Analysis,
    /// The palette.
    pub theme: Theme,
    /// Profiles as of the current step.
    pub step_view: &'a StepView,
    /// Persisted settings.
    pub persisted: &'a Persisted,
    /// Verified suggestions of the selected activity, when computed.
    pub suggestions: Option<&'a [Suggestion]>,
    /// Bumped on every accepted change of the plan.
    pub revision: u64,
    /// Explanation of the selected activity, when it did not schedule.
    pub explanation: Option<&'a solscope_engine::Explanation>,
    /// Why the selected activity could not be explained, if that happened.
    pub explanation_error: Option<&'a str>,
    /// Valid intervals of the selected activity at its own step (full horizon).
    pub valid: Option<&'a [solscope_engine::CategoryIntervals]>,
    /// What the selected activity, failed on energy or peak power, would have
    /// caused at its explanation's start (drawn over the plots, its culprits
    /// highlighted on the Gantt).
    pub would_cause: Option<&'a WouldCause>,
    /// The flexible schedule of this revision, or why there is none, once
    /// derived (`None` meanwhile).
    pub flex: Option<&'a Result<std::sync::Arc<solscope_engine::Flex>, String>>,
    /// Where its free slack stands (computed on a worker, filled in as it
    /// goes), once the flexible schedule is derived.
    pub free_slack: Option<FreeSlackProgress>,
    /// Where the user is: step, selection, visible range, probe.
    pub nav: &'a Navigation,
    /// The outcome banner, the error and the unsaved-changes question.
    pub messages: &'a Messages,
    /// What execution mode draws.
    pub exec: ExecModel<'a>,
    /// Priority tuning: the panel, the search and its result.
    pub tune: TuneModel<'a>,
}

/// What the views keep between frames (their own, not the app's).
#[derive(Clone, Debug, Default)]
pub struct ViewCache {
    /// Screen x range of the plots' data area last frame: the Gantt's timeline
    /// uses the same, so one time maps to one x everywhere.
    pub plot_x: Option<(f32, f32)>,
    /// The Gantt rows last built, with what they were built for.
    pub gantt: Option<GanttRows>,
    /// Where each placed activity's bar was drawn last frame (schedule mode,
    /// visible bars only): what a drag picks up.
    pub bars: Vec<(usize, egui::Rect)>,
    /// The bar being dragged, if any.
    pub drag: Option<BarDrag>,
    /// The activity list's rows wholly in view last frame.
    pub list_rows: std::ops::Range<usize>,
    /// The selection the activity list last scrolled to, and the
    /// [`Listed::generation`] it was in.
    pub list_selected: Option<(Option<usize>, u64)>,
    /// The [`Listed::opened`] of the plan the activity list showed last
    /// frame.
    pub list_opened: u64,
    /// What the search and filters select this frame (set by the frame
    /// before drawing, from the state), for the list and the Gantt alike.
    pub listed: Option<std::sync::Arc<Listed>>,
    /// Lower-case ids and names, resources and sols of the plan as it is (set
    /// with `listed`), for the list's menus.
    pub search: Option<std::sync::Arc<SearchIndex>>,
    /// The selection the Gantt last scrolled its row into view for.
    pub gantt_revealed: Option<Option<usize>>,
    /// The Gantt gives every failed or skipped activity its own row however
    /// many there are (else more than a few are folded into one row).
    pub failed_unfolded: bool,
    /// How each activity bar drawn last frame looked with the search and
    /// filters (every bar plain without them).
    pub looks: Vec<(usize, Look)>,
    /// Where the parts the guided tour points at were drawn this frame.
    pub tour_anchors: TourAnchors,
}

/// How the Gantt draws an activity's bar against the search and filters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Look {
    /// Nothing is filtered.
    Plain,
    /// It matches: outlined.
    Highlighted,
    /// It does not: faded.
    Dimmed,
}

impl ViewCache {
    /// Where activity `a`'s placement bar was drawn last frame.
    pub fn gantt_bar(&self, a: usize) -> Option<egui::Rect> {
        self.bars.iter().find(|(b, _)| *b == a).map(|(_, r)| *r)
    }
}

/// The state the views write while drawing, for one frame.
#[derive(Debug)]
pub struct Widgets<'a> {
    /// Text buffers of the range fields and the editor.
    pub text: &'a mut TextBuffers,
    /// What the views keep between frames.
    pub cache: &'a mut ViewCache,
}

impl Model<'_> {
    /// Status of activity `a` after step `k`.
    pub fn status(&self, a: usize, k: usize) -> Status {
        status_at(self.analysis, a, k)
    }

    /// The activity of step `k` (1-based).
    pub fn activity_of_step(&self, k: usize) -> Option<usize> {
        k.checked_sub(1)
            .and_then(|i| self.analysis.schedule.steps.get(i))
            .map(|s| s.activity)
    }

    /// `id — name` of activity `a`.
    pub fn label(&self, a: usize) -> String {
        let act = &self.doc.plan.activities[a];
        match &act.name {
            Some(n) => format!("{} — {n}", act.id),
            None => act.id.clone(),
        }
    }

    /// The flexible schedule, when derived without error.
    pub fn flex_ready(&self) -> Option<&'_ solscope_engine::Flex> {
        self.flex.and_then(|r| r.as_ref().ok()).map(AsRef::as_ref)
    }

    /// Whether the flexibility layer is on (see [`Navigation::flex_shown`]).
    pub fn flex_shown(&self) -> bool {
        self.nav
            .flex_shown(self.persisted.hide_flex, self.doc.plan.activities.len())
    }

    /// The flexible schedule when the Gantt shows its layer (schedule mode,
    /// not hidden, derived).
    pub fn flex_layer(&self) -> Option<&'_ solscope_engine::Flex> {
        let shown = self.nav.mode == Mode::Schedule && self.flex_shown();
        self.flex_ready().filter(|_| shown)
    }

    /// Plan time as `Sol 413 14:15:00 (t=600)`.
    pub fn time(&self, t: i64) -> String {
        solscope_engine::format_plan_time(&self.doc.plan.local_time, t)
    }
}
