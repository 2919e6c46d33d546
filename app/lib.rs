//! solscope: the command line (`cli`), the desktop app (eframe) and the headless
//! screenshot renderer, on top of `solscope-engine`. The binary (`main.rs`) parses
//! the command line and hands over to `cli::run`, or opens the app.

pub mod cli;
pub mod gui;
pub mod screenshot;
