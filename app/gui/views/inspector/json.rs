//! The inspector's "Advanced (JSON)" editors: every field of the selected
//! activity and the plan-wide limits as JSON text, each checked with
//! `apply_edit` before it is sent (a bad value stays in its field with the
//! reason).

use eframe::egui::{self, RichText};
use serde_json::{Map, Value};

use crate::gui::theme::FIELD_WIDTH;
use crate::gui::views::Model;
use crate::state::Command;
use crate::state::TextBuffers;

/// Text field for one JSON value; validated before it is sent.
fn json_field_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    st: &mut TextBuffers,
    target: &str,
    key: &str,
    current: Option<&Value>,
    cmds: &mut Vec<Command>,
) {
    let buf_key = format!("{target}/{key}");
    let shown = current.map_or(String::new(), |v| v.to_string());
    let entry = st
        .editor
        .entry(buf_key)
        .or_insert_with(|| (shown.clone(), None));
    let lbl = ui.label(key);
    let resp = ui
        .add(egui::TextEdit::singleline(&mut entry.0).desired_width(FIELD_WIDTH))
        .labelled_by(lbl.id);
    let resp = resp.on_hover_text(format!("{key} as JSON; Enter applies (empty removes it)"));
    let commit = resp.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
    if commit && entry.0 != shown {
        let text = entry.0.trim();
        let parsed = if text.is_empty() {
            Ok(Value::Null)
        } else {
            serde_json::from_str::<Value>(text)
        };
        match parsed {
            Err(e) => entry.1 = Some(format!("not JSON: {e}")),
            Ok(value) => {
                let mut set = Map::new();
                set.insert(key.to_string(), value);
                // Validate now, so a bad value is shown here and never applied.
                match solscope_engine::apply_edit(&m.doc.plan, target, &set) {
                    Err(e) => entry.1 = Some(e.to_string()),
                    Ok(_) => {
                        entry.1 = None;
                        cmds.push(Command::Edit {
                            target: target.to_string(),
                            set,
                            description: format!("Set {key} of {target}"),
                        });
                    }
                }
            }
        }
    }
    ui.end_row();
    if let Some(err) = &entry.1 {
        ui.label("");
        // Wrapped at the field's width: a long message never widens the panel.
        ui.vertical(|ui| {
            ui.set_max_width(FIELD_WIDTH);
            ui.add(egui::Label::new(RichText::new(err).color(m.theme.error)).wrap());
        });
        ui.end_row();
    }
}

const ACTIVITY_FIELDS: [&str; 18] = [
    "name",
    "priority",
    "mandatory",
    "duration",
    "windows",
    "resources",
    "sequence_engines",
    "energy_rate",
    "peak_power",
    "data_rate",
    "awake",
    "thermal_zones",
    "after",
    "requires",
    "effects",
    "uhf_interactions",
    "comm_kind",
    "group",
];

/// Clears the editor's text buffers when they were typed for another
/// selection or plan revision (`key`).
pub(super) fn reset_buffers_if_stale(st: &mut TextBuffers, key: (Option<usize>, u64)) {
    if st.editor_for != Some(key) {
        st.editor.clear();
        st.editor_for = Some(key);
    }
}

pub(super) fn activity_editor_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    st: &mut TextBuffers,
    a: usize,
    cmds: &mut Vec<Command>,
) {
    reset_buffers_if_stale(st, (Some(a), m.revision));
    let act = &m.doc.plan.activities[a];
    let value = match serde_json::to_value(act) {
        Ok(value) => value,
        Err(e) => {
            ui.colored_label(
                m.theme.error,
                format!("This activity cannot be edited: {e}"),
            );
            return;
        }
    };
    let target = format!("activity:{}", act.id);
    egui::Grid::new("activity_editor")
        .num_columns(2)
        .show(ui, |ui| {
            for key in ACTIVITY_FIELDS {
                json_field_ui(ui, m, st, &target, key, value.get(key), cmds);
            }
        });
}

pub(super) fn plan_editor_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    st: &mut TextBuffers,
    cmds: &mut Vec<Command>,
) {
    if m.nav.selected.is_none() {
        reset_buffers_if_stale(st, (None, m.revision));
    }
    let value = match serde_json::to_value(&m.doc.plan) {
        Ok(value) => value,
        Err(e) => {
            ui.colored_label(
                m.theme.error,
                format!("The plan limits cannot be edited: {e}"),
            );
            return;
        }
    };
    egui::Grid::new("plan_editor")
        .num_columns(2)
        .show(ui, |ui| {
            for key in [
                "battery",
                "power",
                "sleep",
                "sequence_engines",
                "data",
                "handover",
                "horizon",
                "local_time",
            ] {
                json_field_ui(ui, m, st, "plan", key, value.get(key), cmds);
            }
        });
}
