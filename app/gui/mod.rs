//! The desktop app's egui side: the frame around the state, the eframe host,
//! the keyboard shortcuts, the palette, the time↔pixel mapping, the hover
//! help, the headless screenshot harness, and the views.
//!
//! Data flow per frame ([`SolscopeApp::frame_ui`]): the state prepares what
//! the frame shows ([`AppState::prepare`](crate::state::AppState::prepare)),
//! the keys become commands ([`shortcuts`]), the views (`views/*`, functions
//! named `*_ui`) read a read-only `views::Model` of the state and push
//! [`Command`](crate::state::Command)s, and after the frame
//! [`AppState::apply`](crate::state::AppState::apply) carries them out, so the
//! model never changes mid-draw. The only state the views write is their
//! widget state (text buffers, built rows). What survives restarts is
//! [`Persisted`](crate::state::Persisted), saved by the eframe host
//! ([`SolscopeHost`]).
//!
//! Modules, lowest first (each uses only those before it, and `crate::state`):
//! `time_axis`, `theme`, `help`, `shortcuts` → `views` → `app` → `host`, `screenshot`.

pub mod app;
pub mod help;
pub mod host;
pub mod screenshot;
pub mod shortcuts;
pub mod theme;
pub mod time_axis;
mod views;

pub use app::SolscopeApp;
pub use host::{SolscopeHost, dialog_start, run, save_color_image};
pub use theme::Theme;
pub use views::Look;
