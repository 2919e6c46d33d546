//! The desktop app: a step-through schedule inspector hosting the engine in-process.
//!
//! Data flow per frame: the views (`views/*`, functions named `*_ui`) read a
//! read-only `views::Model` of the [`Document`], its [`Analysis`] and the UI
//! state, and push [`Command`]s; after the frame [`SolscopeApp::apply`] carries
//! them out (edit → reschedule → explain → diff), so the model never changes
//! mid-draw. The only state the views write is their widget state (text buffers,
//! built rows). What survives restarts (recent files, theme) is [`Persisted`],
//! saved by the eframe host ([`SolscopeHost`]).
//!
//! Modules, lowest first (each uses only those before it):
//! `time_axis`, `theme`, `help` → `document`, `repair` → `state`, `commands` → `tour`,
//! `execution` → `montecarlo` → `derived` → `views` → `app` → `host`.

pub mod app;
pub mod commands;
mod derived;
pub mod document;
pub mod execution;
pub mod help;
pub mod host;
pub mod montecarlo;
pub mod repair;
pub mod state;
pub mod theme;
pub mod time_axis;
pub mod tour;
mod views;

pub use app::{DEFAULT_PLAN, Dialog, SolscopeApp};
pub use commands::{Command, UiCommand};
pub use document::{Analysis, Document, OutcomeDiff};
pub use execution::{ActualsSource, CycleRun, ExecutionRun};
pub use host::{SolscopeHost, run, save_color_image};
pub use montecarlo::{CampaignResult, Progress, StopReason, Stopped};
pub use state::{
    History, LAST_STEP, ListFilter, Mode, OverlayPlot, OverlayReason, PathPrompt, Pending,
    Persisted, Place, StatusFilter, StepView, StepWindow, Tour, UiState, WouldCause,
};
pub use theme::Theme;
pub use time_axis::TimeAxis;
pub use views::Look;
