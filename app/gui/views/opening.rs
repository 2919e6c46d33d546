//! The progress line of a plan file being opened on a worker: what is opened,
//! how far it has come, and Cancel (the plan shown stays meanwhile).

use eframe::egui::{self, RichText};

use super::{Model, command_button};
use crate::state::{Command, UiCommand};

/// The line, while a plan file is being opened.
pub fn opening_ui(ui: &mut egui::Ui, m: &Model<'_>, cmds: &mut Vec<Command>) {
    let Some(line) = &m.messages.opening else {
        return;
    };
    ui.horizontal(|ui| {
        ui.spinner();
        ui.label(RichText::new(line).strong());
        command_button(ui, UiCommand::CancelOpen, true, cmds);
    });
}
