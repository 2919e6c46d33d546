//! The controls that give a [`UiCommand`]: buttons, menu items and the mode
//! switch, labelled with the command's label, its shortcut as the tooltip.

use eframe::egui;

use crate::gui::shortcuts::kb_shortcut;
use crate::state::{Command, UiCommand};

/// A button that gives `cmd` (its label is the command's).
pub(super) fn command_button(
    ui: &mut egui::Ui,
    cmd: UiCommand,
    enabled: bool,
    cmds: &mut Vec<Command>,
) {
    if ui
        .add_enabled(enabled, egui::Button::new(cmd.label()))
        .clicked()
    {
        cmds.push(cmd.into());
    }
}

/// A File menu item that gives `cmd`; its shortcut, if any, is its tooltip (the
/// label stays the command's alone).
pub(super) fn menu_item(ui: &mut egui::Ui, cmd: UiCommand, cmds: &mut Vec<Command>) {
    let mut resp = ui.button(cmd.label());
    if let Some(shortcut) = kb_shortcut(cmd) {
        resp = resp.on_hover_text(ui.ctx().format_shortcut(&shortcut));
    }
    if resp.clicked() {
        cmds.push(cmd.into());
    }
}

/// A button that gives `cmd`, its shortcut as its tooltip.
pub(super) fn shortcut_button(
    ui: &mut egui::Ui,
    cmd: UiCommand,
    enabled: bool,
    cmds: &mut Vec<Command>,
) {
    let mut resp = ui.add_enabled(enabled, egui::Button::new(cmd.label()));
    if let Some(shortcut) = kb_shortcut(cmd) {
        resp = resp.on_hover_text(ui.ctx().format_shortcut(&shortcut));
        resp = resp.on_disabled_hover_text(ui.ctx().format_shortcut(&shortcut));
    }
    if resp.clicked() {
        cmds.push(cmd.into());
    }
}

/// One side of the mode switch: selected when its mode is shown; its shortcut
/// is its tooltip.
pub(super) fn mode_button(
    ui: &mut egui::Ui,
    cmd: UiCommand,
    selected: bool,
    cmds: &mut Vec<Command>,
) {
    let mut resp = ui.selectable_label(selected, cmd.label());
    if let Some(shortcut) = kb_shortcut(cmd) {
        resp = resp.on_hover_text(ui.ctx().format_shortcut(&shortcut));
    }
    if resp.clicked() && !selected {
        cmds.push(cmd.into());
    }
}
