//! What lives while the app runs ([`UiState`]; what survives restarts is
//! [`Persisted`](super::Persisted), apart), and the read-only snapshot of it the
//! views get ([`Navigation`]). Nothing here depends on the views or the app.

use std::collections::BTreeMap;
use std::path::PathBuf;

use solscope_engine::{LocalTime, Profiles, format_local};

use super::axis::TimeAxis;
use super::document::OutcomeDiff;
use super::repair::Repair;

/// A file dialog the host is asked to show after the frame: the app never blocks
/// on one (headless, nobody shows it). Where no file dialog service exists, the
/// app asks for a typed path instead ([`PathPrompt`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dialog {
    /// Choose a plan to open.
    Open,
    /// Choose where to save the plan.
    SaveAs,
    /// Choose where to write the schedule JSON.
    ExportSchedule,
    /// Choose where to write the schedule CSV.
    ExportScheduleCsv,
    /// Choose where to write the view as PNG.
    ExportPng,
    /// Choose an actuals file to execute the plan with.
    OpenActuals,
}

impl Dialog {
    /// What the dialog is for (the typed-path prompt's heading).
    pub fn title(self) -> &'static str {
        match self {
            Self::Open => "Open a plan",
            Self::SaveAs => "Save the plan as",
            Self::ExportSchedule => "Export the schedule as JSON",
            Self::ExportScheduleCsv => "Export the schedule as CSV",
            Self::ExportPng => "Export the view as PNG",
            Self::OpenActuals => "Open an actuals file",
        }
    }

    /// The button that carries it out.
    pub fn action(self) -> &'static str {
        match self {
            Self::Open | Self::OpenActuals => "Open",
            Self::SaveAs => "Save",
            Self::ExportSchedule | Self::ExportScheduleCsv | Self::ExportPng => "Export",
        }
    }

    /// The file extension it writes or reads.
    pub fn extension(self) -> &'static str {
        match self {
            Self::ExportScheduleCsv => "csv",
            Self::ExportPng => "png",
            _ => "json",
        }
    }

    /// Whether it chooses a file to write (a save dialog).
    pub fn saves(self) -> bool {
        !matches!(self, Self::Open | Self::OpenActuals)
    }
}

/// No file dialog could be shown: the user types the path instead.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PathPrompt {
    /// What the path is for.
    pub dialog: Dialog,
    /// Why no dialog was shown.
    pub why: String,
}

/// An action waiting for "discard unsaved changes?".
#[derive(Clone, Debug, PartialEq)]
pub enum Pending {
    /// Open this file.
    Open(PathBuf),
    /// Open the bundled tutorial plan and start the guided tour.
    OpenTutorial,
    /// Quit.
    Quit,
}

/// Profiles as of one step (derived: rebuilt when the step or plan changes).
#[derive(Clone, Debug, Default)]
pub struct StepView {
    /// The step.
    pub step: usize,
    /// State of charge `[t, Wh]`.
    pub soc: Vec<[f64; 2]>,
    /// Peak power `[t, W]` (step function, given as pairs of points).
    pub peak: Vec<[f64; 2]>,
    /// Data volume `[t, Mbit]`.
    pub data: Vec<[f64; 2]>,
}

impl StepView {
    /// Plot points of `profiles` (the profiles as of `step`).
    pub fn from_profiles(step: usize, profiles: &Profiles) -> Self {
        let points = |series: &[(i64, f64)]| -> Vec<[f64; 2]> {
            series.iter().map(|&(t, v)| [t as f64, v]).collect()
        };
        // Peak power holds from each breakpoint to the next (the last one is the
        // horizon end): two points per segment draw it as steps.
        let peak = profiles
            .peak_power
            .windows(2)
            .flat_map(|w| [[w[0].0 as f64, w[0].1], [w[1].0 as f64, w[0].1]])
            .collect();
        Self {
            step,
            soc: points(&profiles.soc),
            peak,
            data: points(&profiles.data_volume),
        }
    }
}

/// Where the free slack of the flexible schedule shown stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FreeSlackProgress {
    /// Placed activities whose free slack is known.
    pub done: usize,
    /// Placed activities.
    pub total: usize,
    /// A worker is computing the rest.
    pub running: bool,
    /// How long the computation has run so far (seconds, all its runs).
    pub seconds: u64,
    /// The worker stopped without finishing (an internal error, shown): it is
    /// not started again for this revision.
    pub failed: bool,
    /// The activity whose free slack is being computed on its own, ahead of
    /// the rest (the selected one).
    pub computing: Option<usize>,
}

impl FreeSlackProgress {
    /// Every activity's free slack is known.
    pub fn complete(&self) -> bool {
        self.done >= self.total
    }
}

/// Which plot a [`WouldCause`] overlay goes on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OverlayPlot {
    /// The state of charge (a `min_soc` or `handover_soc` failure).
    Soc,
    /// The peak power (a `max_peak_power` failure).
    Peak,
}

/// One energy or peak-power reason of a failed activity's explanation: the
/// start it was evaluated at and the limit it broke there.
#[derive(Clone, Debug, PartialEq)]
pub struct OverlayReason {
    /// Its index in the explanation's `reasons`.
    pub reason: usize,
    /// The plot it is drawn on.
    pub plot: OverlayPlot,
    /// The starts of its range (plan seconds).
    pub first: i64,
    /// The last start of its range (plan seconds).
    pub last: i64,
    /// The start its numbers were evaluated at (plan seconds).
    pub start: i64,
    /// The duration tried (seconds).
    pub duration: i64,
    /// The violation: time (plan seconds).
    pub at: i64,
    /// The value reached there (Wh or W).
    pub value: f64,
    /// "would reach 894.0 Wh < min_soc 900.0 Wh".
    pub label: String,
}

/// What an activity that failed in placement on energy or peak power would
/// have caused: every such reason of its explanation (each range of starts
/// with the limit it broke), and for the one shown the plot's profile with it
/// placed at that reason's start; the culprits to highlight.
#[derive(Clone, Debug, PartialEq)]
pub struct WouldCause {
    /// The failed activity.
    pub activity: usize,
    /// Its energy and peak-power reasons, in the order the inspector lists
    /// them (`reasons_in_reading_order`; never empty).
    pub reasons: Vec<OverlayReason>,
    /// The index in `reasons` of the one drawn with its profile.
    pub shown: usize,
    /// The profile with it placed at the shown reason's start `[t, Wh or W]`
    /// (peak power as pairs of points); empty when it could not be placed.
    pub points: Vec<[f64; 2]>,
    /// The culprits every view names (`solscope_engine::involved`), activity
    /// indices.
    pub culprits: Vec<usize>,
}

impl WouldCause {
    /// The reason drawn with its profile.
    pub fn shown(&self) -> Option<&OverlayReason> {
        self.reasons.get(self.shown)
    }
}

/// What the window shows: the plan's schedule, or its execution.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Mode {
    /// The scheduler's run over the plan, step by step.
    #[default]
    Schedule,
    /// The plan executed cycle by cycle with actual durations.
    Execution,
}

/// Editor text buffers: field key (`target/key`) → (text, error).
pub type EditorBuffers = BTreeMap<String, (String, Option<String>)>;

/// Session state of the UI (not persisted), in three parts that change in
/// different ways.
#[derive(Clone, Debug)]
pub struct UiState {
    /// Where the user is; changed only by commands.
    pub nav: Navigation,
    /// What the app tells the user; changed only by commands.
    pub messages: Messages,
    /// Widget state the views edit in place while drawing.
    pub text: TextBuffers,
}

impl UiState {
    /// The state of a freshly opened plan: its last step over `axis`, times
    /// shown on `clock`.
    pub fn new(step: usize, axis: TimeAxis, clock: &LocalTime) -> Self {
        let mut ui = Self {
            nav: Navigation {
                step,
                playing: false,
                selected: None,
                axis,
                probe: None,
                since_full: false,
                filter: ListFilter::default(),
                history: History::default(),
                mode: Mode::Schedule,
                cycle: 0,
                cycle_step: LAST_STEP,
                overlay_reason: None,
                steps_shown: StepWindow::ALL,
                flex_on_large: None,
            },
            messages: Messages::default(),
            text: TextBuffers::default(),
        };
        ui.sync_range_text(clock);
        ui
    }

    /// Puts the visible range into the range text fields, in sol and local time
    /// (`Sol 412 09:00:00`; the fields also read plan seconds).
    pub fn sync_range_text(&mut self, clock: &LocalTime) {
        self.text.range_text = [
            format_local(clock, self.nav.axis.start.round() as i64),
            format_local(clock, self.nav.axis.end.round() as i64),
        ];
    }
}

/// Where the user is: step, selection, visible range, probe, filters, and the
/// way back.
#[derive(Clone, Debug, PartialEq)]
pub struct Navigation {
    /// The step shown (0..=N).
    pub step: usize,
    /// Stepping automatically.
    pub playing: bool,
    /// The selected activity.
    pub selected: Option<usize>,
    /// The visible time range.
    pub axis: TimeAxis,
    /// Where the plots were clicked.
    pub probe: Option<i64>,
    /// Energy consumers since the last full battery.
    pub since_full: bool,
    /// What the activity list shows and the Gantt highlights: search text,
    /// status, unit resource, sol.
    pub filter: ListFilter,
    /// Where Back and Forward go.
    pub history: History,
    /// Schedule or execution.
    pub mode: Mode,
    /// Execution mode: the scheduling cycle looked at (clamped to the cycles of
    /// the current execution when read).
    pub cycle: usize,
    /// Execution mode: the step shown inside that cycle's scheduler run (clamped
    /// to its steps when read; [`LAST_STEP`] shows its last).
    pub cycle_step: usize,
    /// The failed activity and the index of its energy or peak-power reason
    /// whose profile the plots draw (the first when none was picked for it).
    pub overlay_reason: Option<(usize, usize)>,
    /// The steps the step slider spans (zoomed in on a long run), in the run
    /// it moves through (the schedule's, or the looked-at cycle's).
    pub steps_shown: StepWindow,
    /// The flexibility layer on a plan of more than
    /// [`FLEX_LAYER_MAX_ACTIVITIES`] activities as toggled while it is open
    /// (`None`: not toggled, so off); smaller plans follow
    /// [`Persisted::hide_flex`](super::Persisted::hide_flex).
    pub flex_on_large: Option<bool>,
}

/// The most activities of a plan whose flexibility layer is shown when it
/// opens (unless hidden in the settings): on a larger plan it starts off, and
/// its free slack (minutes to hours of CPU at 10,000 activities) is not
/// computed until the layer is turned on.
pub const FLEX_LAYER_MAX_ACTIVITIES: usize = 2_000;

/// How much one press of "Zoom steps in" narrows the step slider's span.
pub const STEP_ZOOM: f64 = 4.0;

/// The fewest steps the step slider spans when zoomed in.
pub const MIN_STEPS_SHOWN: usize = 10;

/// The steps the step slider spans: `first..=last` of a run's steps `0..=n`,
/// clamped to the run when read (so one window serves whichever run the
/// slider moves through). Runtime state, never persisted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StepWindow {
    /// The first step spanned.
    pub first: usize,
    /// The last step spanned (`usize::MAX`: the run's last).
    pub last: usize,
}

impl StepWindow {
    /// Every step of the run.
    pub const ALL: Self = Self {
        first: 0,
        last: usize::MAX,
    };

    /// The window on a run of steps `0..=n`: `(first, last)` inside it, at
    /// least [`MIN_STEPS_SHOWN`] steps wide when the run has that many.
    pub fn span(self, n: usize) -> (usize, usize) {
        let last = self.last.min(n);
        let first = self.first.min(last);
        let width = MIN_STEPS_SHOWN.min(n);
        if last - first >= width {
            (first, last)
        } else {
            let first = first.min(n - width);
            (first, first + width)
        }
    }

    /// Whether it spans all of a run of `n` steps.
    pub fn is_all(self, n: usize) -> bool {
        self.span(n) == (0, n)
    }

    /// The window `width` steps wide (at least [`MIN_STEPS_SHOWN`], at most
    /// the run) placed so that step `at` stays where it is on the rail: at
    /// the same fraction of the window (`frac`, 0 to 1).
    fn sized(width: usize, at: usize, frac: f64, n: usize) -> Self {
        let width = width.clamp(MIN_STEPS_SHOWN.min(n), n);
        let before = (width as f64 * frac.clamp(0.0, 1.0)).round() as usize;
        let first = at.saturating_sub(before).min(n - width);
        Self {
            first,
            last: first + width,
        }
    }

    /// Zoomed by `factor` (above 1: fewer steps) about step `at`, which keeps
    /// its place on the rail; on a run of `n` steps.
    pub fn zoomed(self, factor: f64, at: usize, n: usize) -> Self {
        let (first, last) = self.span(n);
        let width = ((last - first) as f64 / factor.max(f64::MIN_POSITIVE)).round() as usize;
        let at = at.clamp(first, last);
        let frac = if last > first {
            (at - first) as f64 / (last - first) as f64
        } else {
            0.5
        };
        let z = Self::sized(width, at, frac, n);
        if z.is_all(n) { Self::ALL } else { z }
    }

    /// Moved by `by` steps (negative: earlier), its width kept.
    pub fn panned(self, by: i64, n: usize) -> Self {
        let (first, last) = self.span(n);
        let width = last - first;
        let first = if by < 0 {
            first.saturating_sub(by.unsigned_abs() as usize)
        } else {
            first.saturating_add(by as usize).min(n - width)
        };
        if width == n {
            return Self::ALL;
        }
        Self {
            first,
            last: first + width,
        }
    }

    /// The smallest move that brings step `k` into the window (its width
    /// kept): the window follows the step shown.
    pub fn following(self, k: usize, n: usize) -> Self {
        let (first, last) = self.span(n);
        if self.is_all(n) || (first..=last).contains(&k) {
            return self;
        }
        if k < first {
            self.panned(-((first - k) as i64), n)
        } else {
            self.panned((k - last) as i64, n)
        }
    }
}

impl Navigation {
    /// Whether the flexibility layer is shown on a plan of `activities`
    /// activities, with the setting `hide_flex` (in either mode; execution
    /// mode draws no layer).
    pub fn flex_shown(&self, hide_flex: bool, activities: usize) -> bool {
        if activities > FLEX_LAYER_MAX_ACTIVITIES {
            self.flex_on_large.unwrap_or(false)
        } else {
            !hide_flex
        }
    }

    /// The index of the energy or peak-power reason of activity `a` whose
    /// profile the plots draw.
    pub fn overlay_reason_of(&self, a: usize) -> usize {
        self.overlay_reason
            .filter(|&(b, _)| b == a)
            .map_or(0, |(_, i)| i)
    }

    /// Where the user is, as Back and Forward restore it.
    pub fn place(&self) -> Place {
        Place {
            selected: self.selected,
            step: self.step,
            axis: self.axis,
        }
    }
}

/// An activity status the list can be filtered to, as of the step shown
/// (schedule mode).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StatusFilter {
    /// Placed by a step up to the one shown.
    Scheduled,
    /// Failed by a step up to the one shown.
    Failed,
    /// Skipped (another member of its group was placed).
    Skipped,
    /// Its step is after the one shown: not yet run.
    Pending,
}

impl StatusFilter {
    /// Every status, in the order the list's menu offers them.
    pub const ALL: [Self; 4] = [Self::Scheduled, Self::Failed, Self::Skipped, Self::Pending];

    /// Its menu entry (also its accessibility label).
    pub fn label(self) -> &'static str {
        match self {
            Self::Scheduled => "Scheduled",
            Self::Failed => "Failed",
            Self::Skipped => "Skipped",
            Self::Pending => "Pending (not yet run)",
        }
    }
}

/// What the activity list shows (and the Gantt highlights, dimming the rest):
/// every condition set must hold. Runtime state, never persisted.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ListFilter {
    /// Part of the id or name, ignoring case (empty: any).
    pub search: String,
    /// Its status as of the step shown (schedule mode only).
    pub status: Option<StatusFilter>,
    /// A unit resource it holds.
    pub resource: Option<String>,
    /// A sol its bar is in (placed as of the step shown) or its windows touch
    /// (not placed).
    pub sol: Option<i64>,
}

impl ListFilter {
    /// Whether anything is filtered out.
    pub fn active(&self) -> bool {
        !self.search.trim().is_empty()
            || self.status.is_some()
            || self.resource.is_some()
            || self.sol.is_some()
    }
}

/// A place to go back to: the selection, the step shown and the time range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Place {
    /// The selected activity.
    pub selected: Option<usize>,
    /// The step shown.
    pub step: usize,
    /// The visible time range.
    pub axis: TimeAxis,
}

/// How many places Back remembers.
pub const HISTORY_LIMIT: usize = 100;

/// Back and Forward, as in a browser: following a link remembers where the
/// user was (and forgets what was forward of it).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct History {
    back: std::collections::VecDeque<Place>,
    forward: Vec<Place>,
}

impl History {
    /// The user left `from` by following a link: Back returns there; what was
    /// forward is forgotten. At most [`HISTORY_LIMIT`] places are kept (the
    /// oldest go first).
    pub fn visit(&mut self, from: Place) {
        self.forward.clear();
        if self.back.back() != Some(&from) {
            self.back.push_back(from);
            while self.back.len() > HISTORY_LIMIT {
                self.back.pop_front();
            }
        }
    }

    /// Where Back goes from `current` (which Forward then returns to).
    pub fn back(&mut self, current: Place) -> Option<Place> {
        let to = self.back.pop_back()?;
        self.forward.push(current);
        Some(to)
    }

    /// Where Forward goes from `current` (which Back then returns to).
    pub fn forward(&mut self, current: Place) -> Option<Place> {
        let to = self.forward.pop()?;
        self.back.push_back(current);
        Some(to)
    }

    /// Whether Back has somewhere to go.
    pub fn can_back(&self) -> bool {
        !self.back.is_empty()
    }

    /// Whether Forward has somewhere to go.
    pub fn can_forward(&self) -> bool {
        !self.forward.is_empty()
    }

    /// The number of places behind and ahead.
    pub fn depth(&self) -> (usize, usize) {
        (self.back.len(), self.forward.len())
    }
}

/// The value of [`Navigation::cycle_step`] that shows a cycle's last step
/// whatever its number of steps.
pub const LAST_STEP: usize = usize::MAX;

/// The messages shown (dismissed through commands).
#[derive(Clone, Debug, Default)]
pub struct Messages {
    /// The outcome of the last edit.
    pub banner: Option<OutcomeDiff>,
    /// The last error (bad file, bad edit, failed write).
    pub error: Option<String>,
    /// Waiting for "discard unsaved changes?".
    pub confirm: Option<Pending>,
    /// A bar dropped outside its slack: waiting for "pin it there and
    /// reschedule?".
    pub pin: Option<PinOffer>,
    /// No file dialog could be shown: waiting for a typed path.
    pub path_prompt: Option<PathPrompt>,
    /// What to do once the plan is saved ("Save and open", "Save and quit" on
    /// a plan without a file: after the save dialog).
    pub after_save: Option<Pending>,
    /// A plan file that did not load, being repaired (its text is
    /// [`TextBuffers::repair_text`]); the plan open stays until it loads.
    pub repair: Option<Repair>,
    /// The guided tour, while it is shown.
    pub tour: Option<Tour>,
    /// The progress line of a plan file being opened on a worker.
    pub opening: Option<String>,
}

/// Where the guided tour is (see `gui::tour`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Tour {
    /// The page shown (0-based).
    pub page: usize,
    /// The id of the failed activity it follows (picked when it started: the
    /// first failure of the schedule), none when the plan had no failure.
    pub target: Option<String>,
}

/// An activity dragged on the Gantt to a start outside its slack, offered to be
/// pinned there (an edit of its windows, then a reschedule).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PinOffer {
    /// The activity.
    pub activity: usize,
    /// The start it was dropped at (plan seconds).
    pub start: i64,
}

/// The number of runs the Monte Carlo panel proposes.
pub const DEFAULT_CAMPAIGN_RUNS: u64 = 200;

/// The text buffers: the only UI state the views write.
#[derive(Clone, Debug)]
pub struct TextBuffers {
    /// Range text fields (start, end).
    pub range_text: [String; 2],
    /// Editor text buffers.
    pub editor: EditorBuffers,
    /// The activity and plan revision the editor buffers belong to.
    pub editor_for: Option<(Option<usize>, u64)>,
    /// The seed field of "Sample" (execution mode).
    pub seed_text: String,
    /// The runs field of the Monte Carlo panel.
    pub campaign_runs_text: String,
    /// The seed field of the Monte Carlo panel.
    pub campaign_seed_text: String,
    /// The fields of the tuning panel.
    pub tune: super::tune::TuneText,
    /// The typed path when no file dialog could be shown.
    pub path_text: String,
    /// Repair view: the plan text being repaired.
    pub repair_text: String,
    /// Repair view: the value at the path of the error looked at, as edited.
    pub repair_value: String,
    /// Repair view: what the list of ids to pick for an unknown `after`
    /// target is narrowed to.
    pub repair_pick: String,
    /// Repair view: the chars of the plan text to select and scroll to (set
    /// by a jump to an error, taken by the text view).
    pub repair_cursor: Option<std::ops::Range<usize>>,
    /// Ctrl+F was pressed: the search field takes the keyboard (and selects
    /// its text) when next drawn.
    pub focus_search: bool,
}

impl Default for TextBuffers {
    fn default() -> Self {
        Self {
            range_text: Default::default(),
            editor: EditorBuffers::new(),
            editor_for: None,
            seed_text: "1".into(),
            campaign_runs_text: DEFAULT_CAMPAIGN_RUNS.to_string(),
            campaign_seed_text: "1".into(),
            tune: super::tune::TuneText::default(),
            path_text: String::new(),
            repair_text: String::new(),
            repair_value: String::new(),
            repair_pick: String::new(),
            repair_cursor: None,
            focus_search: false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(selected: usize, step: usize) -> Place {
        Place {
            selected: Some(selected),
            step,
            axis: TimeAxis::new(0.0, 100.0),
        }
    }

    #[test]
    fn back_and_forward_walk_the_places_visited_and_a_visit_forgets_forward() {
        let mut h = History::default();
        assert!(!h.can_back() && !h.can_forward());
        assert_eq!(h.back(at(0, 0)), None, "nowhere to go");
        // At 1, follow to 2, then to 3.
        h.visit(at(1, 10));
        h.visit(at(2, 20));
        assert_eq!(h.back(at(3, 30)), Some(at(2, 20)));
        assert_eq!(h.back(at(2, 20)), Some(at(1, 10)));
        assert!(!h.can_back());
        assert_eq!(h.forward(at(1, 10)), Some(at(2, 20)));
        assert_eq!(h.forward(at(2, 20)), Some(at(3, 30)));
        assert!(!h.can_forward());
        // Back to 2, then a new link: 3 is forgotten.
        assert_eq!(h.back(at(3, 30)), Some(at(2, 20)));
        h.visit(at(2, 20));
        assert!(!h.can_forward());
        assert_eq!(h.depth(), (2, 0));
        // The same place twice in a row is one entry.
        h.visit(at(2, 20));
        assert_eq!(h.depth(), (2, 0));
    }

    #[test]
    fn history_is_bounded_and_forgets_the_oldest() {
        let mut h = History::default();
        for i in 0..HISTORY_LIMIT + 50 {
            h.visit(at(i, i));
        }
        assert_eq!(h.depth(), (HISTORY_LIMIT, 0));
        let mut current = at(9999, 0);
        let mut last = None;
        while let Some(p) = h.back(current) {
            last = Some(p);
            current = p;
        }
        assert_eq!(last, Some(at(50, 50)), "the oldest 50 are gone");
    }

    #[test]
    fn the_step_window_zooms_about_a_step_pans_and_follows() {
        let n = 10_000;
        let all = StepWindow::ALL;
        assert_eq!(all.span(n), (0, n));
        assert_eq!(all.span(4), (0, 4), "a short run is spanned whole");
        // Zoomed 4x about step 5,000 in the middle: it stays in the middle.
        let z = all.zoomed(4.0, 5_000, n);
        assert_eq!(z.span(n), (3_750, 6_250));
        // About step 9,000: it keeps its place (90 % along the rail).
        let z9 = all.zoomed(4.0, 9_000, n);
        assert_eq!(z9.span(n), (6_750, 9_250));
        // Zoomed in as far as it goes: ten steps, step 1,234 inside.
        let tight = all.zoomed(1e9, 1_234, n);
        let (a, b) = tight.span(n);
        assert_eq!(b - a, MIN_STEPS_SHOWN);
        assert!((a..=b).contains(&1_234));
        // Out again past the whole run: all steps.
        assert_eq!(z.zoomed(0.1, 5_000, n), StepWindow::ALL);
        // Panned: clamped at both ends, the width kept.
        assert_eq!(z.panned(-10_000, n).span(n), (0, 2_500));
        assert_eq!(z.panned(10_000, n).span(n), (7_500, n));
        // The window follows a step outside it by the least move.
        assert_eq!(z.following(7_000, n).span(n), (4_500, 7_000));
        assert_eq!(z.following(100, n).span(n), (100, 2_600));
        assert_eq!(z.following(4_000, n), z, "inside: no move");
        // A window of a longer run on a shorter one.
        assert_eq!(z.span(3_000), (3_000 - MIN_STEPS_SHOWN, 3_000));
    }

    #[test]
    fn a_filter_is_active_when_any_condition_is_set() {
        let mut f = ListFilter::default();
        assert!(!f.active());
        f.search = "  ".into();
        assert!(!f.active(), "blank search text filters nothing");
        f.search = "mast".into();
        assert!(f.active());
        let f = ListFilter {
            sol: Some(412),
            ..ListFilter::default()
        };
        assert!(f.active());
    }
}
