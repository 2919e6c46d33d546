//! Commands: what the UI asks for. Views only read the model and push commands;
//! `SolscopeApp::apply` carries them out after the frame, so nothing changes
//! mid-draw.

use std::path::PathBuf;

use serde_json::{Map, Value};

use super::time_axis::TimeAxis;

/// A request from the UI.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Show the state after this step.
    SetStep(usize),
    /// Start or stop stepping automatically.
    Play(bool),
    /// Select an activity (or nothing).
    Select(Option<usize>),
    /// Select an activity and jump to its failure step.
    GoToFailureStep(usize),
    /// Change the visible time range.
    SetAxis(TimeAxis),
    /// Probe the plots at a time (or clear).
    ProbePlot(Option<i64>),
    /// Energy consumers since the last full battery instead of since the start.
    SetSinceFull(bool),
    /// Apply an edit in the spec's format, rerun and show the outcome diff.
    Edit {
        /// `plan` or `activity:ID`.
        target: String,
        /// Replacement top-level fields.
        set: Map<String, Value>,
        /// For the banner and undo.
        description: String,
    },
    /// Undo the last edit.
    Undo,
    /// Redo the last undone edit.
    Redo,
    /// Open a plan file (guarded when there are unsaved changes).
    Open(PathBuf),
    /// Choose a plan file to open.
    OpenDialog,
    /// Save to the current file (or ask where).
    Save,
    /// Save to a new file (`None`: ask where).
    SaveAs(Option<PathBuf>),
    /// Write the schedule JSON (`None`: ask where).
    ExportSchedule(Option<PathBuf>),
    /// Write the current view as PNG (`None`: ask where).
    ExportPng(Option<PathBuf>),
    /// Dark (true) or light theme.
    SetDark(bool),
    /// Gantt rows per unit resource (true) or packed lanes.
    GroupByResource(bool),
    /// Filter activities by id or name.
    SetFilter(String),
    /// Hide the outcome banner.
    DismissBanner,
    /// Hide the error message.
    DismissError,
    /// Answer the unsaved-changes question (true: discard and go on).
    ConfirmDiscard(bool),
    /// Quit (guarded when there are unsaved changes).
    Quit,
}
