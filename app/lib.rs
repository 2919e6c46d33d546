//! solscope: the desktop app (eframe) and the headless screenshot renderer, on
//! top of `solscope-engine`. The binary (`main.rs`) is the command line.
//!
//! [`state`] is the app without a toolkit (the document, the commands, the
//! reducer, the derived values); [`gui`] draws it with egui.

pub mod gui;
pub mod state;

pub use gui::screenshot;
