//! The toolbar: the File and Help menus, Back and Forward, Undo and Redo, the
//! theme, the Gantt's layers, the plan's title and counts, and the mode switch.

use eframe::egui::{self, RichText};

use super::Model;
use super::controls::{command_button, menu_item, mode_button, shortcut_button};
use crate::gui::shortcuts::kb_shortcut;
use crate::state::{Command, Mode, UiCommand};

/// File actions, back/forward, undo/redo, theme, layers.
pub(super) fn toolbar_ui(ui: &mut egui::Ui, m: &Model<'_>, cmds: &mut Vec<Command>) {
    ui.horizontal_wrapped(|ui| {
        ui.menu_button("File", |ui| {
            for cmd in [
                UiCommand::Open,
                UiCommand::Save,
                UiCommand::SaveAs,
                UiCommand::ExportSchedule,
                UiCommand::ExportScheduleCsv,
                UiCommand::ExportPng,
            ] {
                menu_item(ui, cmd, cmds);
            }
            ui.separator();
            // The panel under the Gantt (also Ctrl+T).
            menu_item(ui, UiCommand::TunePriorities, cmds);
            if !m.persisted.recent.is_empty() {
                ui.separator();
                ui.label("Recent");
                for p in &m.persisted.recent {
                    if ui.button(p.display().to_string()).clicked() {
                        cmds.push(Command::Open(p.clone()));
                    }
                }
            }
            ui.separator();
            menu_item(ui, UiCommand::Quit, cmds);
        });
        ui.menu_button("Help", |ui| {
            let tour = UiCommand::GuidedTour;
            if ui
                .button(tour.label())
                .on_hover_text(
                    "A short tour of one failure on the tutorial plan: steps, why it failed, \
                     what took its place, a checked fix and undo",
                )
                .clicked()
            {
                cmds.push(tour.into());
            }
            let reset = UiCommand::ResetTour;
            if ui
                .add_enabled(m.persisted.tour_dismissed, egui::Button::new(reset.label()))
                .on_hover_text(
                    "The tour opens by itself again the next time the tutorial plan is opened",
                )
                .on_disabled_hover_text("The tour opens by itself with the tutorial plan")
                .clicked()
            {
                cmds.push(reset.into());
            }
        });
        shortcut_button(ui, UiCommand::Back, m.nav.history.can_back(), cmds);
        shortcut_button(ui, UiCommand::Forward, m.nav.history.can_forward(), cmds);
        command_button(ui, UiCommand::Undo, m.doc.can_undo(), cmds);
        command_button(ui, UiCommand::Redo, m.doc.can_redo(), cmds);
        let dark = !m.persisted.light;
        if ui
            .button(if dark { "Light theme" } else { "Dark theme" })
            .clicked()
        {
            cmds.push(Command::SetDark(!dark));
        }
        if m.nav.mode == Mode::Schedule {
            let cmd = UiCommand::ToggleFlex;
            let mut shown = m.flex_shown();
            let mut resp = ui.checkbox(&mut shown, cmd.label());
            if let Some(shortcut) = kb_shortcut(cmd) {
                resp = resp.on_hover_text(format!(
                    "Gantt: slack whiskers [lb, ub], free slack shaded (green: every check \
                     passes; amber: temporal only), the selected activity's dispatchable \
                     neighbours outlined, and drag a bar to try another start ({})",
                    ui.ctx().format_shortcut(&shortcut)
                ));
            }
            if resp.changed() {
                cmds.push(cmd.into());
            }
        }
        let mut by_resource = m.persisted.by_resource;
        if ui
            .checkbox(&mut by_resource, "Group by resource")
            .on_hover_text("Gantt: one row per unit resource instead of packed lanes")
            .changed()
        {
            cmds.push(Command::GroupByResource(by_resource));
        }
        ui.separator();
        let dirty = if m.doc.dirty { " (unsaved)" } else { "" };
        // Whole, never wrapped inside the row (a wrapped label spans the
        // row's width, under the mode switch): one that does not fit goes to
        // the next row.
        ui.add(
            egui::Label::new(RichText::new(format!("{}{dirty}", m.doc.title())).strong()).extend(),
        );
        let failed = m.analysis.failed();
        let n = m.doc.plan.activities.len();
        let counts = ui.add(
            egui::Label::new(format!("{} of {n} scheduled, {failed} not", n - failed)).extend(),
        );
        // The mode switch, at the right end (the other tools keep their place),
        // on a row of its own when the rest leaves it no room (it would be
        // drawn over the counts).
        let modes = [
            (UiCommand::ShowSchedule, Mode::Schedule),
            (UiCommand::ShowExecution, Mode::Execution),
        ];
        // (From the counts' own rect: the row's cursor may stand past it.)
        if ui.max_rect().right() - counts.rect.right() < mode_switch_width(ui) {
            // A layout of its own would start on this row whatever: the
            // next row, from the left.
            ui.end_row();
            ui.label("View");
            for (cmd, mode) in modes {
                mode_button(ui, cmd, m.nav.mode == mode, cmds);
            }
            return;
        }
        ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
            for (cmd, mode) in modes.into_iter().rev() {
                mode_button(ui, cmd, m.nav.mode == mode, cmds);
            }
            ui.label("View");
        });
    });
}

/// The width the mode switch ("View", "Schedule", "Execution") takes, with
/// a gap on its left.
fn mode_switch_width(ui: &egui::Ui) -> f32 {
    let spacing = ui.spacing();
    let text = |t: &str, style: egui::TextStyle| {
        ui.painter()
            .layout_no_wrap(
                t.to_string(),
                style.resolve(ui.style()),
                egui::Color32::WHITE,
            )
            .size()
            .x
    };
    let buttons: f32 = [UiCommand::ShowSchedule, UiCommand::ShowExecution]
        .into_iter()
        .map(|c| text(c.label(), egui::TextStyle::Button) + 2.0 * spacing.button_padding.x)
        .sum();
    // "View" is a label (body text); two spacings inside, one before it.
    text("View", egui::TextStyle::Body) + buttons + 3.0 * spacing.item_spacing.x
}
