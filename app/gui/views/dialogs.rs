//! The messages and questions over the views: the outcome banner and the
//! error, the offer to pin a dropped bar, the unsaved-changes question, and the
//! typed-path prompt when no file dialog can be shown.

use eframe::egui::{self, RichText};

use super::Model;
use crate::gui::theme::{BANNER_MAX_SHARE, MESSAGE_MARGIN, PROMPT_WIDTH};
use crate::state::{Command, Pending};

/// The outcome of the last edit, and the last error: drawn over the foot of
/// `area` (the Gantt and plots), so that neither moves the layout when it
/// comes or goes.
pub(super) fn banner_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    area: egui::Rect,
    cmds: &mut Vec<Command>,
) {
    if m.messages.banner.is_none() && m.messages.error.is_none() {
        return;
    }
    egui::Area::new(egui::Id::unique("change_banner"))
        .order(egui::Order::Foreground)
        .pivot(egui::Align2::LEFT_BOTTOM)
        .fixed_pos(area.left_bottom())
        .constrain_to(area)
        .show(ui.ctx(), |ui| {
            egui::Frame::new()
                .fill(m.theme.banner)
                .inner_margin(MESSAGE_MARGIN)
                .show(ui, |ui| {
                    ui.set_width(area.width() - 2.0 * MESSAGE_MARGIN);
                    if let Some(diff) = &m.messages.banner {
                        // A rerun that moves hundreds of activities has a
                        // long summary: it scrolls in a quarter of the area,
                        // and Dismiss stays in reach below it.
                        egui::ScrollArea::vertical()
                            .id_salt("change_banner_text")
                            .max_height(area.height() * BANNER_MAX_SHARE)
                            .show(ui, |ui| ui.label(diff.summary()));
                        if ui.button("Dismiss").clicked() {
                            cmds.push(Command::DismissBanner);
                        }
                    }
                    if let Some(err) = &m.messages.error {
                        ui.horizontal_wrapped(|ui| {
                            ui.label(RichText::new(err).color(m.theme.error));
                            if ui.button("Dismiss error").clicked() {
                                cmds.push(Command::DismissError);
                            }
                        });
                    }
                });
        });
}

/// "Pin it at this start and reschedule?" after a bar was dropped outside its
/// slack.
pub(super) fn pin_ui(ui: &mut egui::Ui, m: &Model<'_>, cmds: &mut Vec<Command>) {
    let Some(offer) = m.messages.pin else {
        return;
    };
    let Some(act) = m.doc.plan.activities.get(offer.activity) else {
        return;
    };
    let placed = m.analysis.placement(offer.activity);
    let (_, dropped) = crate::state::document::pin_window(act, placed.map(|p| p.0), offer.start);
    let modal = egui::Modal::new(egui::Id::unique("pin_offer")).show(ui.ctx(), |ui| {
        ui.heading("Move outside its slack");
        let now = placed.map_or("not placed".to_string(), |p| {
            format!("scheduled at {}", m.time(p.0))
        });
        ui.label(format!(
            "{} is {now}. A start at {} is outside its slack: only an edit of the plan \
             gets it there.",
            act.id,
            m.time(offer.start),
        ));
        ui.label(format!(
            "Pin it at {} and reschedule? Its windows become the one window [{t}, {t}].",
            m.time(offer.start),
            t = offer.start
        ));
        if let Some(c) = dropped {
            ui.colored_label(
                m.theme.error,
                format!(
                    "It would end after its window's cutoff {}: the cutoff is dropped.",
                    m.time(c)
                ),
            );
        }
        ui.label(RichText::new("Undo restores the plan.").color(m.theme.muted));
        ui.horizontal(|ui| {
            if ui.button("Pin and reschedule").clicked() {
                cmds.push(Command::Pin {
                    activity: offer.activity,
                    start: offer.start,
                });
            }
            if ui.button("Keep the schedule").clicked() {
                cmds.push(Command::DismissPin);
            }
        });
    });
    if modal.should_close() {
        cmds.push(Command::DismissPin);
    }
}

/// "Discard unsaved changes?", or save them first.
pub(super) fn confirm_ui(ui: &mut egui::Ui, m: &Model<'_>, cmds: &mut Vec<Command>) {
    let Some(pending) = &m.messages.confirm else {
        return;
    };
    let (what, save_and) = match pending {
        Pending::Open(p) => (format!("open {}", p.display()), "Save and open"),
        Pending::OpenTutorial => (
            "open the tutorial plan for the guided tour".to_string(),
            "Save and open",
        ),
        Pending::Quit => ("quit".to_string(), "Save and quit"),
    };
    egui::Modal::new(egui::Id::unique("confirm_discard")).show(ui.ctx(), |ui| {
        ui.heading("Unsaved changes");
        ui.label(format!(
            "The plan has unsaved edits. Save them, or discard them and {what}?"
        ));
        if m.doc.path.is_none() {
            ui.label(RichText::new("It has no file yet: saving asks where.").color(m.theme.muted));
        }
        ui.horizontal(|ui| {
            if ui.button(save_and).clicked() {
                cmds.push(Command::SaveAndContinue);
            }
            if ui.button("Discard changes").clicked() {
                cmds.push(Command::ConfirmDiscard(true));
            }
            if ui.button("Keep editing").clicked() {
                cmds.push(Command::ConfirmDiscard(false));
            }
        });
    });
}

/// No file dialog could be shown: say why and take a typed path.
pub(super) fn path_prompt_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    path: &mut String,
    cmds: &mut Vec<Command>,
) {
    let Some(prompt) = &m.messages.path_prompt else {
        return;
    };
    let dialog = prompt.dialog;
    let modal = egui::Modal::new(egui::Id::unique("path_prompt")).show(ui.ctx(), |ui| {
        ui.set_max_width(PROMPT_WIDTH);
        ui.heading(dialog.title());
        ui.add(egui::Label::new(prompt.why.as_str()).wrap());
        ui.label("Type the path of the file instead:");
        let label = ui.label("Path");
        let field = ui
            .add(egui::TextEdit::singleline(path).desired_width(PROMPT_WIDTH))
            .labelled_by(label.id);
        let enter = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        ui.horizontal(|ui| {
            let go = ui.button(dialog.action()).clicked() || enter;
            if go {
                if path.trim().is_empty() {
                    cmds.push(Command::ShowError(format!(
                        "{}: type a path",
                        dialog.title()
                    )));
                } else {
                    cmds.push(Command::Chosen {
                        dialog,
                        path: path.trim().into(),
                    });
                }
            }
            if ui.button("Cancel").clicked() {
                cmds.push(Command::DialogCancelled);
            }
        });
    });
    if modal.should_close() {
        cmds.push(Command::DialogCancelled);
    }
}
