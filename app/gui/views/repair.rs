//! The repair view: a plan file that does not load, with every error it has
//! (JSON path and reason), the value at the path of the error looked at to
//! edit in place, and the whole text. Re-check opens it once no error is
//! left; the plan open before stays until then (Back to the open plan).

use eframe::egui::{self, RichText};
use egui::text::CCursor;

use super::{Model, command_button};
use crate::gui::theme::{REPAIR_LIST_WIDTH, REPAIR_PICK_SHOWN, REPAIR_VALUE_HEIGHT};
use crate::state::repair::{Repair, char_range, locate};
use crate::state::{Command, TextBuffers, UiCommand};

/// The whole window while a plan file is being repaired.
pub fn repair_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    repair: &Repair,
    st: &mut TextBuffers,
    cmds: &mut Vec<Command>,
) {
    let file = repair.file_name();
    let n = repair.errors.len();
    egui::Panel::top("repair_top").show(ui, |ui| {
        ui.heading(format!("Repair {file}"));
        ui.add(
            egui::Label::new(format!(
                "{file} does not load: {n} error{} (every one is listed, each with its JSON \
                 path). Fix them here and re-check: it opens once none is left. {} stays open \
                 until then.",
                if n == 1 { "" } else { "s" },
                m.doc.title()
            ))
            .wrap(),
        );
        ui.horizontal(|ui| {
            command_button(ui, UiCommand::RecheckRepair, true, cmds);
            command_button(ui, UiCommand::UndoRepair, !repair.undo.is_empty(), cmds);
            command_button(ui, UiCommand::CancelRepair, true, cmds);
            if repair.checks > 1 {
                ui.label(
                    RichText::new(format!("checked {} times", repair.checks)).color(m.theme.muted),
                );
            }
        });
    });
    egui::Panel::left("repair_errors")
        .resizable(true)
        .default_size(REPAIR_LIST_WIDTH)
        .show(ui, |ui| {
            ui.heading(format!("Errors ({n})"));
            ui.label(RichText::new("Click a path to jump to it.").color(m.theme.muted));
            egui::ScrollArea::vertical()
                .auto_shrink([false; 2])
                .show(ui, |ui| {
                    for (i, e) in repair.errors.iter().enumerate() {
                        ui.separator();
                        let text = RichText::new(&e.path).monospace();
                        if ui
                            .selectable_label(repair.selected == Some(i), text)
                            .on_hover_text("Show the text at this path")
                            .clicked()
                        {
                            cmds.push(Command::RepairJump(i));
                        }
                        ui.add(
                            egui::Label::new(RichText::new(&e.reason).color(m.theme.error)).wrap(),
                        );
                    }
                });
        });
    egui::CentralPanel::default().show(ui, |ui| {
        if let Some(e) = repair.selected.and_then(|i| repair.errors.get(i)) {
            ui.label(RichText::new(format!("At {}", e.path)).strong());
            ui.add(egui::Label::new(RichText::new(&e.reason).color(m.theme.error)).wrap());
            let label = ui.label("Value at this path");
            egui::ScrollArea::vertical()
                .id_salt("repair_value")
                .max_height(REPAIR_VALUE_HEIGHT)
                .show(ui, |ui| {
                    ui.add(
                        egui::TextEdit::multiline(&mut st.repair_value)
                            .code_editor()
                            .desired_rows(1)
                            .desired_width(f32::INFINITY),
                    )
                    .labelled_by(label.id);
                });
            command_button(ui, UiCommand::ReplaceAtError, true, cmds);
            if e.is_unknown_activity() {
                pick_id_ui(ui, m, repair, st, cmds);
            }
            ui.separator();
        }
        let label = ui.label("Plan text");
        // The text at the path of the error looked at, marked behind the text.
        let marked = repair
            .selected
            .and_then(|i| repair.errors.get(i))
            .and_then(|e| locate(&st.repair_text, &e.path))
            .map(|span| char_range(&st.repair_text, &span));
        egui::ScrollArea::both()
            .id_salt("repair_text")
            .auto_shrink([false; 2])
            .show(ui, |ui| {
                let out = egui::TextEdit::multiline(&mut st.repair_text)
                    .code_editor()
                    .desired_width(f32::INFINITY)
                    .show(ui);
                out.response.response.labelled_by(label.id);
                let Some(span) = marked else {
                    return;
                };
                let offset = out.galley_pos.to_vec2();
                let at = |c: usize| {
                    out.galley
                        .pos_from_cursor(CCursor::new(c))
                        .translate(offset)
                };
                let (from, to) = (at(span.start), at(span.end));
                let right = out.galley.rect.translate(offset).right();
                let left = out.galley_pos.x;
                let row = from.height();
                // Row by row from the start of the value to its end.
                let mut y = from.top();
                while y < to.bottom() - row / 2.0 {
                    let x0 = if y == from.top() { from.left() } else { left };
                    let x1 = if y + row >= to.bottom() - row / 2.0 {
                        to.left()
                    } else {
                        right
                    };
                    let rect = egui::Rect::from_min_max(egui::pos2(x0, y), egui::pos2(x1, y + row));
                    ui.painter().rect_filled(rect, 0.0, m.theme.error_mark);
                    y += row;
                }
                if st.repair_cursor.take().is_some() {
                    // Just jumped here.
                    ui.scroll_to_rect(from, Some(egui::Align::Center));
                }
            });
    });
}

/// The plan's activity ids to put in place of an unknown `after` target:
/// narrowed by what is typed, one click each.
fn pick_id_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    repair: &Repair,
    st: &mut TextBuffers,
    cmds: &mut Vec<Command>,
) {
    ui.horizontal(|ui| {
        let label = ui.label("Or pick one of the plan's activities:");
        ui.add(
            egui::TextEdit::singleline(&mut st.repair_pick)
                .hint_text("type to narrow")
                .desired_width(180.0),
        )
        .labelled_by(label.id);
    });
    let needle = st.repair_pick.to_lowercase();
    let matching: Vec<&String> = repair
        .ids
        .iter()
        .filter(|id| id.to_lowercase().contains(&needle))
        .collect();
    if matching.is_empty() {
        ui.label(RichText::new("No activity id contains this.").color(m.theme.muted));
        return;
    }
    egui::ScrollArea::vertical()
        .id_salt("repair_pick")
        .max_height(REPAIR_VALUE_HEIGHT)
        .show(ui, |ui| {
            ui.horizontal_wrapped(|ui| {
                for id in matching.iter().take(REPAIR_PICK_SHOWN) {
                    if ui
                        .button(RichText::new(id.as_str()).monospace())
                        .on_hover_text("Put this id here and re-check (Undo replace takes it back)")
                        .clicked()
                    {
                        cmds.push(Command::RepairPickId((*id).clone()));
                    }
                }
            });
        });
    if matching.len() > REPAIR_PICK_SHOWN {
        ui.label(
            RichText::new(format!(
                "{} more: type to narrow them.",
                matching.len() - REPAIR_PICK_SHOWN
            ))
            .color(m.theme.muted),
        );
    }
}
