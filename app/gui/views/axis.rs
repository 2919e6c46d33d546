//! The time range's controls above the Gantt: zoom and pan, the whole plan,
//! and the exact range typed in local time or plan seconds.

use eframe::egui;
use solscope_engine::parse_local;

use super::Model;
use crate::gui::theme::RANGE_FIELD_WIDTH;
use crate::gui::time_axis::TimeAxis;
use crate::state::Command;

/// Zoom/pan controls and the exact range.
pub(super) fn axis_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    range_text: &mut [String; 2],
    cmds: &mut Vec<Command>,
) {
    let axis = m.nav.axis;
    let bounds = (
        m.doc.plan.horizon.start as f64,
        m.doc.plan.horizon.end as f64,
    );
    ui.horizontal_wrapped(|ui| {
        // Every sol time in the app reads in LMST: said once, here.
        ui.label("Time range (LMST)")
            .on_hover_text(crate::gui::help::LMST);
        let l0 = ui.label("from");
        // The plan seconds of the range shown, on hover (the fields read either).
        let r0 = ui
            .add(egui::TextEdit::singleline(&mut range_text[0]).desired_width(RANGE_FIELD_WIDTH))
            .labelled_by(l0.id)
            .on_hover_text(format!("t={:.0} s", axis.start.round()));
        let l1 = ui.label("to");
        let r1 = ui
            .add(egui::TextEdit::singleline(&mut range_text[1]).desired_width(RANGE_FIELD_WIDTH))
            .labelled_by(l1.id)
            .on_hover_text(format!("t={:.0} s", axis.end.round()));
        let enter = ui.input(|i| i.key_pressed(egui::Key::Enter));
        if (r0.lost_focus() || r1.lost_focus()) && enter || ui.button("Apply range").clicked() {
            // "Sol 413 08:00" to "12:00": the end's sol defaults to the start's.
            let clock = &m.doc.plan.local_time;
            let from = parse_local(clock, &range_text[0], None);
            let to = parse_local(clock, &range_text[1], from.map(|t| clock.sol(t)));
            match (from, to) {
                (Some(a), Some(b)) if a < b => {
                    cmds.push(Command::SetAxis(TimeAxis::new(a as f64, b as f64)))
                }
                _ => cmds.push(Command::ShowError(
                    "Time range: enter a start before an end, each as a sol and local time \
                     (Sol 413 08:00, or 12:00 for the end in the start's sol) or in plan \
                     seconds"
                        .into(),
                )),
            }
        }
        if ui.button("Zoom in").clicked() {
            let mut axis = axis;
            axis.zoom_about((axis.start + axis.end) / 2.0, 2.0, bounds);
            cmds.push(Command::SetAxis(axis));
        }
        if ui.button("Zoom out").clicked() {
            let mut axis = axis;
            axis.zoom_about((axis.start + axis.end) / 2.0, 0.5, bounds);
            cmds.push(Command::SetAxis(axis));
        }
        if ui.button("Whole plan").clicked() {
            cmds.push(Command::SetAxis(TimeAxis::new(bounds.0, bounds.1)));
        }
    });
}
