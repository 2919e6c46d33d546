//! Commands: what the UI asks for. Views only read the model and push commands;
//! [`AppState::apply`](super::AppState::apply) carries them out after the frame,
//! so nothing changes mid-draw.
//!
//! As in rerun's `UICommand`, the commands a user gives by name ([`UiCommand`]:
//! menu items, toolbar buttons, keys) carry no payload and own their label and
//! keyboard shortcut ([`Shortcut`]: a key and its modifiers, as data; the gui
//! maps it to its toolkit's), so a button and its key cannot drift apart, and
//! the keyboard handling goes through [`UiCommand::ALL`]. Everything else is a
//! [`Command`] with its payload.

use std::path::PathBuf;

use serde_json::{Map, Value};

use super::axis::TimeAxis;
use super::tune::TuneSettings;
use super::ui::{Dialog, ListFilter, StepWindow};

/// Declares [`UiCommand`] and [`UiCommand::ALL`] from one list, so that no
/// command can be left out of what the keyboard handling and the shortcut
/// checks go through.
macro_rules! ui_commands {
    ($($(#[$doc:meta])* $name:ident,)*) => {
        /// A command the user gives by name: its label is the button's text (and
        /// accessibility label), its shortcut the key that does the same.
        ///
        /// Declared in the order the keyboard handling checks the shortcuts:
        /// one whose key is also another's with fewer modifiers comes first
        /// (Redo before Undo: Cmd+Shift+Z also matches Cmd+Z logically; so does
        /// Shift+F3 F3), and within a frame the commands of the keys pressed
        /// are given in this order.
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum UiCommand {
            $($(#[$doc])* $name,)*
        }

        impl UiCommand {
            /// Every command, in declaration order.
            pub const ALL: &[Self] = &[$(Self::$name,)*];
        }
    };
}

ui_commands! {
    /// Save to the current file (or ask where).
    Save,
    /// Choose a plan file to open (guarded when there are unsaved changes).
    Open,
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
    /// Redo the last undone edit.
    Redo,
    /// Undo the last edit.
    Undo,
    /// Add a new activity after the selected one (at the end when none is),
    /// and select it.
    AddActivity,
    /// Add a copy of the selected activity under a new id after it, and select
    /// it.
    DuplicateActivity,
    /// Delete the selected activity (and the dependencies on it).
    DeleteActivity,
    /// Stop opening the plan file being opened; the plan open before stays.
    CancelOpen,
    /// Repair view: check the plan text again; once it has no error it opens.
    RecheckRepair,
    /// Repair view: put the value typed for the error looked at in place of the
    /// text at its path, then check again.
    ReplaceAtError,
    /// Repair view: put the plan text back as it was before the last
    /// replacement (a value typed or an id picked), then check again.
    UndoRepair,
    /// Repair view: leave it; the plan open before stays.
    CancelRepair,
    /// Show the previous step.
    PreviousStep,
    /// Show the next step.
    NextStep,
    /// Show the previous step at which an activity failed, and select it.
    PreviousFailure,
    /// Show the next step at which an activity failed, and select it.
    NextFailure,
    /// Select the activity above the selected one in the activity list.
    SelectPrevious,
    /// Select the activity below the selected one in the activity list.
    SelectNext,
    /// Show the state before step 1.
    FirstStep,
    /// Show the last step.
    LastStep,
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
    /// Select the previous activity the search and filters list (wrapping).
    PreviousMatch,
    /// Select the next activity the search and filters list (wrapping).
    NextMatch,
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
    /// Show or hide the panel that tunes the priorities.
    TunePriorities,
    /// Stop the tuning search: the best order found so far is confirmed and
    /// shown, marked as stopped early.
    CancelTune,
    /// Give the plan the tuned priorities (one edit: one undo restores every
    /// priority).
    ApplyTuning,
    /// Forget the tuning shown (and its overlay on the Gantt).
    DismissTuning,
    /// Show the tuned predicted schedule over the original one on the Gantt,
    /// or not.
    ToggleTuneOverlay,
}

impl UiCommand {
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
            Self::CancelOpen => "Cancel opening",
            Self::RecheckRepair => "Re-check",
            Self::ReplaceAtError => "Replace and re-check",
            Self::UndoRepair => "Undo replace",
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
            Self::TunePriorities => "Tune priorities",
            Self::CancelTune => "Cancel tuning",
            Self::ApplyTuning => "Apply tuned priorities",
            Self::DismissTuning => "Dismiss tuning",
            Self::ToggleTuneOverlay => "Tuned schedule on the Gantt",
        }
    }

    /// Its keyboard shortcut, if any.
    pub fn shortcut(self) -> Option<Shortcut> {
        let cmd = |key| Some(Shortcut::new(Modifiers::COMMAND, key));
        let plain = |key| Some(Shortcut::new(Modifiers::NONE, key));
        match self {
            Self::Open => cmd(Key::O),
            Self::Save => cmd(Key::S),
            Self::Undo => cmd(Key::Z),
            Self::Redo => Some(Shortcut::new(
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
            Self::NextFailure => Some(Shortcut::new(Modifiers::SHIFT, Key::ArrowRight)),
            Self::PreviousFailure => Some(Shortcut::new(Modifiers::SHIFT, Key::ArrowLeft)),
            Self::SelectPrevious => plain(Key::ArrowUp),
            Self::SelectNext => plain(Key::ArrowDown),
            Self::ShowSchedule => cmd(Key::Num1),
            Self::ShowExecution => cmd(Key::Num2),
            Self::PreviousCycle => plain(Key::PageUp),
            Self::NextCycle => plain(Key::PageDown),
            Self::ToggleFlex => plain(Key::F),
            Self::TunePriorities => cmd(Key::T),
            Self::AddActivity
            | Self::DuplicateActivity
            | Self::DeleteActivity
            | Self::CancelOpen
            | Self::RecheckRepair
            | Self::ReplaceAtError
            | Self::UndoRepair
            | Self::CancelRepair => None,
            Self::Back => Some(Shortcut::new(Modifiers::ALT, Key::ArrowLeft)),
            Self::Forward => Some(Shortcut::new(Modifiers::ALT, Key::ArrowRight)),
            Self::Search => cmd(Key::F),
            Self::NextMatch => plain(Key::F3),
            Self::PreviousMatch => Some(Shortcut::new(Modifiers::SHIFT, Key::F3)),
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
            | Self::AllSteps
            | Self::CancelTune
            | Self::ApplyTuning
            | Self::DismissTuning
            | Self::ToggleTuneOverlay => None,
        }
    }
}

/// A key a shortcut is on (the ones the commands use), as data: the gui maps
/// it to its toolkit's key.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Key {
    /// The letter O.
    O,
    /// The letter S.
    S,
    /// The letter Z.
    Z,
    /// The letter F.
    F,
    /// The letter T.
    T,
    /// The digit 1.
    Num1,
    /// The digit 2.
    Num2,
    /// Home.
    Home,
    /// End.
    End,
    /// Page Up.
    PageUp,
    /// Page Down.
    PageDown,
    /// Left arrow.
    ArrowLeft,
    /// Right arrow.
    ArrowRight,
    /// Up arrow.
    ArrowUp,
    /// Down arrow.
    ArrowDown,
    /// The function key F3.
    F3,
}

impl Key {
    /// A function key (taken also while a text field has focus).
    pub fn is_function_key(self) -> bool {
        matches!(self, Self::F3)
    }
}

/// The modifiers held with a shortcut's key. `command` is Ctrl, or Cmd on a
/// Mac.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Modifiers {
    /// Ctrl (Cmd on a Mac).
    pub command: bool,
    /// Shift.
    pub shift: bool,
    /// Alt (Option on a Mac).
    pub alt: bool,
}

impl Modifiers {
    /// No modifier.
    pub const NONE: Self = Self {
        command: false,
        shift: false,
        alt: false,
    };
    /// Ctrl (Cmd on a Mac).
    pub const COMMAND: Self = Self {
        command: true,
        ..Self::NONE
    };
    /// Shift.
    pub const SHIFT: Self = Self {
        shift: true,
        ..Self::NONE
    };
    /// Alt.
    pub const ALT: Self = Self {
        alt: true,
        ..Self::NONE
    };

    /// Whether every modifier of `other` is held in `self` too.
    pub fn contains(self, other: Self) -> bool {
        (self.command || !other.command) && (self.shift || !other.shift) && (self.alt || !other.alt)
    }
}

/// A keyboard shortcut: a key with its modifiers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shortcut {
    /// The modifiers held.
    pub modifiers: Modifiers,
    /// The key pressed.
    pub key: Key,
}

impl Shortcut {
    /// `key` with `modifiers`.
    pub const fn new(modifiers: Modifiers, key: Key) -> Self {
        Self { modifiers, key }
    }

    /// Taken also while a text field has focus: with Ctrl/Cmd, or on a
    /// function key (once per frame). The others (stepping, the list, Back and
    /// Forward on Alt+arrows, which a text field uses to move by words) are
    /// taken only when no text field has focus, each press counting, also
    /// several in one frame, with exactly their modifiers (Shift+Right is the
    /// next failure, not also the next step).
    pub fn while_typing(self) -> bool {
        self.modifiers.command || self.key.is_function_key()
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
    /// The side panels' widths as dragged: the activity list's and the
    /// inspector's (points; kept across restarts).
    SetPanelWidths([f32; 2]),
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
    /// Repair view: put this activity id (picked from the plan's) in place of
    /// the unknown one at the error looked at, then check again (undoable
    /// with [`UiCommand::UndoRepair`]).
    RepairPickId(String),
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
    /// Tune the priorities of the plan as it is with these settings (on a
    /// worker in the desktop app); a search running is stopped first.
    RunTune(TuneSettings),
}

impl From<UiCommand> for Command {
    fn from(cmd: UiCommand) -> Self {
        Self::Ui(cmd)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_command_has_its_own_label_and_shortcut() {
        for (i, a) in UiCommand::ALL.iter().enumerate() {
            assert!(!a.label().is_empty(), "{a:?}");
            for b in &UiCommand::ALL[i + 1..] {
                assert_ne!(a, b, "listed twice");
                assert_ne!(a.label(), b.label(), "{a:?} and {b:?}");
                if let (Some(sa), Some(sb)) = (a.shortcut(), b.shortcut()) {
                    assert_ne!(sa, sb, "{a:?} and {b:?} share a shortcut");
                }
            }
        }
    }

    #[test]
    fn a_shortcut_taken_while_typing_is_checked_before_one_it_also_matches() {
        // Such a shortcut matches a key pressed with more modifiers than its
        // own (Cmd+Z matches Cmd+Shift+Z): the one with more is checked first,
        // or it would never be given.
        let typing: Vec<(UiCommand, Shortcut)> = UiCommand::ALL
            .iter()
            .filter_map(|&c| c.shortcut().filter(|s| s.while_typing()).map(|s| (c, s)))
            .collect();
        assert!(typing.len() >= 5, "{typing:?}");
        for (i, (a, sa)) in typing.iter().enumerate() {
            for (b, sb) in &typing[i + 1..] {
                let shadowed = sa.key == sb.key && sb.modifiers.contains(sa.modifiers);
                assert!(
                    !shadowed,
                    "{b:?} ({sb:?}) is also {a:?} ({sa:?}), checked first"
                );
            }
        }
    }

    #[test]
    fn shortcuts_taken_while_typing_have_ctrl_or_a_function_key() {
        let typing = |c: UiCommand| c.shortcut().is_some_and(Shortcut::while_typing);
        for c in [
            UiCommand::Undo,
            UiCommand::Redo,
            UiCommand::Search,
            UiCommand::NextMatch,
        ] {
            assert!(typing(c), "{c:?}");
        }
        for c in [UiCommand::NextStep, UiCommand::Back, UiCommand::ToggleFlex] {
            assert!(!typing(c), "{c:?}");
        }
    }
}
