//! solscope: the desktop app (eframe) and the headless screenshot renderer, on
//! top of `solscope-engine`. The binary (`main.rs`) is the command line.

pub mod gui;
pub mod screenshot;
