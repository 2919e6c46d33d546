//! Commands: what the UI asks for. Views only read the model and push commands;
//! `SolscopeApp::apply` carries them out after the frame, so nothing changes
//! mid-draw.
//!
//! As in rerun's `UICommand`, the commands a user gives by name ([`UiCommand`]:
//! menu items, toolbar buttons, keys) carry no payload and own their label and
//! keyboard shortcut, so a button and its key cannot drift apart. Everything else
//! is a [`Command`] with its payload.

use std::path::PathBuf;

use eframe::egui::{Key, KeyboardShortcut, Modifiers};
use serde_json::{Map, Value};

use super::state::{Dialog, ListFilter, StepWindow};
use super::time_axis::TimeAxis;

/// A command the user gives by name: its label is the button's text (and
/// accessibility label), its shortcut the key that does the same.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UiCommand {
    /// Choose a plan file to open (guarded when there are unsaved changes).
    Open,
    /// Save to the current file (or ask where).
    Save,
    /// Save to a new file (asks where).
    SaveAs,
    /// Write the schedule JSON (asks where).
    ExportSchedule,
    /// Write the schedule as CSV, one row per activity (asks where).
    ExportScheduleCsv,
    /// Write the current view as PNG (asks where; the host renders it).
    ExportPng,
    /// Quit (guarded when there are unsaved changes).
    Quit,
    /// Undo the last edit.
    Undo,
    /// Redo the last undone edit.
    Redo,
    /// Add a new activity after the selected one (at the end when none is),
    /// and select it.
    AddActivity,
    /// Add a copy of the selected activity under a new id after it, and select
    /// it.
    DuplicateActivity,
    /// Delete the selected activity (and the dependencies on it).
    DeleteActivity,
    /// Repair view: check the plan text again; once it has no error it opens.
    RecheckRepair,
    /// Repair view: put the value typed for the error looked at in place of the
    /// text at its path, then check again.
    ReplaceAtError,
    /// Repair view: leave it; the plan open before stays.
    CancelRepair,
    /// Show the state before step 1.
    FirstStep,
    /// Show the previous step.
    PreviousStep,
    /// Show the next step.
    NextStep,
    /// Show the last step.
    LastStep,
    /// Show the next step at which an activity failed, and select it.
    NextFailure,
    /// Show the previous step at which an activity failed, and select it.
    PreviousFailure,
    /// Select the activity above the selected one in the activity list.
    SelectPrevious,
    /// Select the activity below the selected one in the activity list.
    SelectNext,
    /// Schedule mode: the scheduler's run over the plan.
    ShowSchedule,
    /// Execution mode: the plan executed cycle by cycle.
    ShowExecution,
    /// Choose an actuals file (`solscope.actuals/1`) to execute with.
    OpenActuals,
    /// Execute with every activity running its `duration`.
    NominalActuals,
    /// Show the previous scheduling cycle (execution mode).
    PreviousCycle,
    /// Show the next scheduling cycle (execution mode).
    NextCycle,
    /// Stop the Monte Carlo campaign running (its summary is not made).
    CancelCampaign,
    /// Show or hide the Gantt's flexibility layer (slack whiskers, free slack,
    /// dispatchable neighbours).
    ToggleFlex,
    /// Whether Run in the Monte Carlo panel compares the execution policies
    /// (replan, dispatch, fixed over the same runs) or runs the replanning
    /// executive alone.
    ToggleComparePolicies,
    /// Go back to the selection, step and time range before the last link
    /// followed.
    Back,
    /// Go forward again to where Back came from.
    Forward,
    /// Put the keyboard in the activity search field.
    Search,
    /// Select the next activity the search and filters list (wrapping).
    NextMatch,
    /// Select the previous activity the search and filters list (wrapping).
    PreviousMatch,
    /// Show every activity again: empty the search, clear the filters.
    ClearFilters,
    /// Start the guided tour of one failure on the tutorial plan (opening the
    /// bundled tutorial plan unless it is the plan open, guarded when there
    /// are unsaved changes).
    GuidedTour,
    /// End the guided tour; it no longer opens by itself with the tutorial
    /// plan.
    EndTour,
    /// Let the guided tour open by itself again with the tutorial plan.
    ResetTour,
    /// Zoom the step slider in about the step shown (fewer steps across the
    /// rail, so one step of a long run can be picked with the mouse).
    ZoomStepsIn,
    /// Zoom the step slider out about the step shown.
    ZoomStepsOut,
    /// The step slider spans every step of the run again.
    AllSteps,
}

impl UiCommand {
    /// Commands whose shortcut is taken also while a text field has focus
    /// (with Ctrl/Cmd, or a function key), in the order the keyboard handling
    /// checks them (Redo before Undo: Cmd+Shift+Z also matches Cmd+Z
    /// logically; so does Shift+F3 F3).
    pub const WITH_MODIFIERS: [Self; 9] = [
        Self::Redo,
        Self::Undo,
        Self::Save,
        Self::Open,
        Self::ShowSchedule,
        Self::ShowExecution,
        Self::Search,
        Self::PreviousMatch,
        Self::NextMatch,
    ];

    /// Commands on keys without Ctrl/Cmd (stepping, the list, Back and Forward
    /// on Alt+arrows, which a text field uses to move by words), taken only
    /// when no text field has focus; each press counts, also several in one
    /// frame.
    pub const PLAIN_KEYS: [Self; 13] = [
        Self::PreviousStep,
        Self::NextStep,
        Self::PreviousFailure,
        Self::NextFailure,
        Self::SelectPrevious,
        Self::SelectNext,
        Self::FirstStep,
        Self::LastStep,
        Self::PreviousCycle,
        Self::NextCycle,
        Self::ToggleFlex,
        Self::Back,
        Self::Forward,
    ];

    /// The text of its button or menu item (also its accessibility label).
    pub fn label(self) -> &'static str {
        match self {
            Self::Open => "Open…",
            Self::Save => "Save",
            Self::SaveAs => "Save as…",
            Self::ExportSchedule => "Export schedule JSON…",
            Self::ExportScheduleCsv => "Export schedule CSV…",
            Self::ExportPng => "Export view as PNG…",
            Self::Quit => "Quit",
            Self::Undo => "Undo",
            Self::Redo => "Redo",
            Self::AddActivity => "Add activity",
            Self::DuplicateActivity => "Duplicate activity",
            Self::DeleteActivity => "Delete activity",
            Self::RecheckRepair => "Re-check",
            Self::ReplaceAtError => "Replace and re-check",
            Self::CancelRepair => "Back to the open plan",
            Self::FirstStep => "|< First",
            Self::PreviousStep => "< Previous",
            Self::NextStep => "Next >",
            Self::LastStep => "Last >|",
            Self::NextFailure => "Next failure >>",
            Self::PreviousFailure => "<< Previous failure",
            Self::SelectPrevious => "Previous activity",
            Self::SelectNext => "Next activity",
            Self::ShowSchedule => "Schedule",
            Self::ShowExecution => "Execution",
            Self::OpenActuals => "Open actuals…",
            Self::NominalActuals => "Nominal",
            Self::PreviousCycle => "< Cycle",
            Self::NextCycle => "Cycle >",
            Self::CancelCampaign => "Cancel",
            Self::ToggleFlex => "Flexibility layer",
            Self::ToggleComparePolicies => "Compare policies",
            Self::Back => "Back",
            Self::Forward => "Forward",
            Self::Search => "Search",
            Self::NextMatch => "Next match",
            Self::PreviousMatch => "Previous match",
            Self::ClearFilters => "Clear filters",
            Self::GuidedTour => "Guided tour",
            Self::EndTour => "End tour",
            Self::ResetTour => "Reset guided tour",
            Self::ZoomStepsIn => "Zoom steps in",
            Self::ZoomStepsOut => "Zoom steps out",
            Self::AllSteps => "All steps",
        }
    }

    /// Its keyboard shortcut, if any.
    pub fn kb_shortcut(self) -> Option<KeyboardShortcut> {
        let cmd = |key| Some(KeyboardShortcut::new(Modifiers::COMMAND, key));
        let plain = |key| Some(KeyboardShortcut::new(Modifiers::NONE, key));
        match self {
            Self::Open => cmd(Key::O),
            Self::Save => cmd(Key::S),
            Self::Undo => cmd(Key::Z),
            Self::Redo => Some(KeyboardShortcut::new(
                Modifiers {
                    shift: true,
                    ..Modifiers::COMMAND
                },
                Key::Z,
            )),
            Self::FirstStep => plain(Key::Home),
            Self::PreviousStep => plain(Key::ArrowLeft),
            Self::NextStep => plain(Key::ArrowRight),
            Self::LastStep => plain(Key::End),
            Self::NextFailure => Some(KeyboardShortcut::new(Modifiers::SHIFT, Key::ArrowRight)),
            Self::PreviousFailure => Some(KeyboardShortcut::new(Modifiers::SHIFT, Key::ArrowLeft)),
            Self::SelectPrevious => plain(Key::ArrowUp),
            Self::SelectNext => plain(Key::ArrowDown),
            Self::ShowSchedule => cmd(Key::Num1),
            Self::ShowExecution => cmd(Key::Num2),
            Self::PreviousCycle => plain(Key::PageUp),
            Self::NextCycle => plain(Key::PageDown),
            Self::ToggleFlex => plain(Key::F),
            Self::AddActivity
            | Self::DuplicateActivity
            | Self::DeleteActivity
            | Self::RecheckRepair
            | Self::ReplaceAtError
            | Self::CancelRepair => None,
            Self::Back => Some(KeyboardShortcut::new(Modifiers::ALT, Key::ArrowLeft)),
            Self::Forward => Some(KeyboardShortcut::new(Modifiers::ALT, Key::ArrowRight)),
            Self::Search => cmd(Key::F),
            Self::NextMatch => plain(Key::F3),
            Self::PreviousMatch => Some(KeyboardShortcut::new(Modifiers::SHIFT, Key::F3)),
            Self::SaveAs
            | Self::ExportSchedule
            | Self::ExportScheduleCsv
            | Self::ExportPng
            | Self::Quit
            | Self::OpenActuals
            | Self::NominalActuals
            | Self::CancelCampaign
            | Self::ToggleComparePolicies
            | Self::ClearFilters
            | Self::GuidedTour
            | Self::EndTour
            | Self::ResetTour
            | Self::ZoomStepsIn
            | Self::ZoomStepsOut
            | Self::AllSteps => None,
        }
    }
}

/// A request from the UI.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// A command given by name (button, menu item or key).
    Ui(UiCommand),
    /// Show the state after this step.
    SetStep(usize),
    /// Start or stop stepping automatically.
    Play(bool),
    /// Select an activity (or nothing): a link followed (a click in the list,
    /// on the Gantt, in the inspector), so Back returns to the selection, step
    /// and time range before it; the Gantt's time range moves to show the
    /// activity when it is out of view.
    Select(Option<usize>),
    /// Select an activity and jump to its failure step (a link followed).
    GoToFailureStep(usize),
    /// Change the visible time range.
    SetAxis(TimeAxis),
    /// Probe the plots at a time (or clear).
    ProbePlot(Option<i64>),
    /// Energy consumers since the last full battery instead of since the start.
    SetSinceFull(bool),
    /// Draw the profile of energy or peak-power reason `index` of `activity`'s
    /// explanation (what it would have caused at that reason's start) over the
    /// plots.
    ShowReason {
        /// The failed activity.
        activity: usize,
        /// The index among its energy and peak-power reasons.
        index: usize,
    },
    /// Apply an edit in the spec's format, rerun and show the outcome diff.
    Edit {
        /// `plan` or `activity:ID`.
        target: String,
        /// Replacement top-level fields.
        set: Map<String, Value>,
        /// For the banner and undo.
        description: String,
    },
    /// Repair view: look at error `i` (its value at its path is shown to be
    /// edited, and selected in the plan text).
    RepairJump(usize),
    /// Open a plan file (guarded when there are unsaved changes).
    Open(PathBuf),
    /// Save the plan to this file (the host sends it once a file is chosen).
    SaveTo(PathBuf),
    /// Write the schedule JSON to this file (the host sends it once a file is
    /// chosen).
    ExportScheduleTo(PathBuf),
    /// A file was chosen (in the host's dialog, or typed when there is none)
    /// for `dialog`: open, save, or export there.
    Chosen {
        /// What it was chosen for.
        dialog: Dialog,
        /// The file (an extension is added when it has none).
        path: PathBuf,
    },
    /// The file dialog was closed without a choice.
    DialogCancelled,
    /// No file dialog could be shown for `dialog`: ask for a typed path.
    AskPath {
        /// What the path is for.
        dialog: Dialog,
        /// Why there is no dialog (shown to the user).
        why: String,
    },
    /// Answer the unsaved-changes question with "Save and open" / "Save and
    /// quit": save (asking where when the plan has no file), then go on.
    SaveAndContinue,
    /// Dark (true) or light theme.
    SetDark(bool),
    /// Gantt rows per unit resource (true) or packed lanes.
    GroupByResource(bool),
    /// Search the activities by id or name (the list shows the matches, the
    /// Gantt highlights them).
    SetFilter(String),
    /// Filter the activity list (and the Gantt's highlight) by search text,
    /// status, unit resource and sol.
    SetListFilter(ListFilter),
    /// Show an error message (bad input in a view, a failed write in the host).
    ShowError(String),
    /// Execution mode: look at scheduling cycle k (its last step).
    SetCycle(usize),
    /// Execution mode: show the state after this step of the cycle's run.
    SetCycleStep(usize),
    /// The steps the step slider spans (Ctrl+wheel over it zooms, the wheel
    /// pans).
    SetStepsShown(StepWindow),
    /// Execute with the actual durations of this file (the host sends it once a
    /// file is chosen); an invalid file changes nothing and shows its error.
    OpenActuals(PathBuf),
    /// Execute with the durations of Monte Carlo run `run` of a campaign
    /// seeded with `seed`, drawn from the duration models (run 0 is what
    /// "Sample" draws with that seed).
    SampleActuals {
        /// The campaign seed.
        seed: u64,
        /// The run index.
        run: u64,
    },
    /// Run a Monte Carlo campaign of `runs` runs seeded with `seed` (on a
    /// worker in the desktop app); a campaign running is cancelled first.
    RunCampaign {
        /// Number of runs.
        runs: u64,
        /// The campaign seed.
        seed: u64,
    },
    /// Run the same Monte Carlo campaign (`runs` runs seeded with `seed`)
    /// under each execution policy, replan, dispatch and fixed, one after the
    /// other (on a worker in the desktop app), to compare them run by run; a
    /// campaign running is cancelled first.
    ComparePolicies {
        /// Number of runs per policy.
        runs: u64,
        /// The campaign seed.
        seed: u64,
    },
    /// Offer to pin `activity` at `start` (a bar dropped outside its slack).
    OfferPin {
        /// The activity.
        activity: usize,
        /// The start it was dropped at.
        start: i64,
    },
    /// Pin `activity` at `start` and reschedule: its windows become the one
    /// window `[start, start]` (preferred `start`; the cutoff of the window it
    /// was placed in is kept when the activity still fits before it), applied
    /// as an edit (undo restores the plan).
    Pin {
        /// The activity.
        activity: usize,
        /// The new start.
        start: i64,
    },
    /// Forget the offer to pin.
    DismissPin,
    /// Hide the outcome banner.
    DismissBanner,
    /// Hide the error message.
    DismissError,
    /// Answer the unsaved-changes question (true: discard and go on).
    ConfirmDiscard(bool),
    /// Show page `k` of the guided tour, and give the commands that page gives
    /// (select its failure, move the step slider).
    TourPage(usize),
}

impl From<UiCommand> for Command {
    fn from(cmd: UiCommand) -> Self {
        Self::Ui(cmd)
    }
}
