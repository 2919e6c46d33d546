//! solscope, on top of `solscope-engine`, in three wings: the command line
//! ([`cli`]), the app without a toolkit ([`state`]: the document, the commands,
//! the reducer, the derived values and their jobs) and its egui side ([`gui`]:
//! the frame, the views, the eframe host and the headless screenshot
//! renderer), and [`write`](mod@write), through which every file is written whole or
//! not at all. The binary (`main.rs`) parses the command line and hands over to
//! [`cli::run`], or opens the app.

pub mod cli;
pub mod gui;
pub mod state;
pub mod write;
