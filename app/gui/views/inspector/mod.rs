//! The inspector (the right-hand panel). In schedule mode the selected
//! activity: outcome, its flexibility when placed, valid intervals per
//! category on the time axis, why it did not schedule and the verified
//! suggestions (`why`); in execution mode its execution (`execution`, with
//! the Monte Carlo campaign's view of it, `montecarlo`). Then the structured
//! editor of the activity and of the plan limits, with their JSON under
//! "Advanced" (`json`). The sections are called from here and never call
//! back.

mod execution;
mod json;
mod montecarlo;
mod why;

use eframe::egui::{self, RichText};
use solscope_engine::{Duration, format_span};

use crate::gui::help;
use crate::gui::views::{Model, Status, TourAnchors, command_button, editor, flex, widgets};
use crate::state::{Command, UiCommand};
use crate::state::{Mode, TextBuffers};

/// The right-hand panel.
pub fn inspector_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    st: &mut TextBuffers,
    anchors: &mut TourAnchors,
    cmds: &mut Vec<Command>,
) {
    ui.heading("Inspector");
    match (m.nav.mode, m.nav.selected) {
        (Mode::Execution, selected) => {
            execution::inspector_ui(ui, m, selected, cmds);
            if let Some(a) = selected {
                ui.separator();
                egui::CollapsingHeader::new("Edit activity")
                    .default_open(false)
                    .show(ui, |ui| {
                        activity_edit_ui(ui, m, st, a, cmds);
                    });
            }
        }
        (Mode::Schedule, None) => {
            ui.label("Select an activity in the list or on the Gantt chart.");
            command_button(ui, UiCommand::AddActivity, true, cmds);
        }
        (Mode::Schedule, Some(a)) => activity_ui(ui, m, st, a, anchors, cmds),
    }
    ui.separator();
    egui::CollapsingHeader::new("Plan limits")
        .default_open(false)
        .show(ui, |ui| {
            if m.nav.selected.is_none() {
                json::reset_buffers_if_stale(st, (None, m.revision));
            }
            editor::plan_fields_ui(ui, m, st, cmds);
            egui::CollapsingHeader::new("Advanced (JSON)")
                .id_salt("plan_json")
                .default_open(false)
                .show(ui, |ui| {
                    json::plan_editor_ui(ui, m, st, cmds);
                });
        });
}

/// The selected activity's editor: its fields, and its JSON under Advanced.
fn activity_edit_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    st: &mut TextBuffers,
    a: usize,
    cmds: &mut Vec<Command>,
) {
    json::reset_buffers_if_stale(st, (Some(a), m.revision));
    editor::activity_fields_ui(ui, m, st, a, cmds);
    ui.separator();
    egui::CollapsingHeader::new("Advanced (JSON)")
        .id_salt("activity_json")
        .default_open(false)
        .show(ui, |ui| {
            json::activity_editor_ui(ui, m, st, a, cmds);
        });
}

fn activity_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    st: &mut TextBuffers,
    a: usize,
    anchors: &mut TourAnchors,
    cmds: &mut Vec<Command>,
) {
    let act = &m.doc.plan.activities[a];
    let step = m.analysis.schedule.step_of(a);
    ui.label(RichText::new(m.label(a)).strong());
    let own_step = step.map_or(0, |s| s.step);
    let status = match m.status(a, m.nav.step) {
        Status::Scheduled(s, e) => format!("scheduled {} – {}", m.time(s), m.time(e)),
        Status::Failed => "failed".into(),
        Status::Skipped => "skipped".into(),
        Status::Pending => format!("pending (its step is {own_step})"),
    };
    ui.label(format!(
        "Step {own_step}, priority {}, {}: {status}",
        act.priority,
        if act.mandatory {
            "mandatory"
        } else {
            "optional"
        }
    ));
    if ui.button("Show its step").clicked() {
        cmds.push(Command::SetStep(own_step));
    }
    if m.analysis.placement(a).is_some() {
        // The flexible form of the final schedule (whatever step is shown:
        // a placement never moves).
        ui.separator();
        flex::flex_section_ui(ui, m, a, cmds);
        ui.separator();
    }

    // Valid intervals per category, drawn on the shared time axis.
    let (cats, seen_at) = match m.explanation {
        Some(ex) => (ex.categories.clone(), ex.failure_step.unwrap_or(0)),
        None => (
            m.valid.map(<[_]>::to_vec).unwrap_or_default(),
            own_step.saturating_sub(1),
        ),
    };
    // An expanding activity's intervals are for one of its durations: the
    // explanation's (the shortest when it failed), else its step's.
    let shown = m
        .explanation
        .map(|ex| ex.duration)
        .or(step.map(|s| s.duration));
    let for_duration = match (shown, &act.duration) {
        (Some(d), Duration::Expanding { .. }) => format!(", for {}", format_span(d)),
        _ => String::new(),
    };
    if !cats.is_empty() {
        ui.label(
            RichText::new(format!(
                "Valid starts per constraint (as seen after step {seen_at}{for_duration})"
            ))
            .strong(),
        )
        .on_hover_text(help::VALID_STARTS);
        widgets::intervals_ui(ui, m, &cats);
    }

    if let Some(e) = m.explanation_error {
        ui.separator();
        ui.colored_label(m.theme.error, format!("Could not explain it: {e}"));
    }
    if let Some(ex) = m.explanation {
        ui.separator();
        why::why_ui(ui, m, a, ex, anchors, cmds);
        why::suggestions_ui(ui, m, anchors, cmds);
    }
    ui.separator();
    egui::CollapsingHeader::new("Edit activity")
        .default_open(true)
        .show(ui, |ui| {
            activity_edit_ui(ui, m, st, a, cmds);
        });
}
