//! The inspector (selected activity: outcome, its flexibility when placed, valid
//! intervals per category on the time axis, explanation, suggestions) and the
//! constraint editor.

use eframe::egui::{self, Pos2, Rect, RichText, Sense, Stroke};
use serde_json::{Map, Value};
use solscope_engine::{
    CategoryIntervals, Duration, Phase, explanation_notes_and_lead, format_span, reason_line,
    reasons_in_reading_order, suggestion_line,
};

use super::{Model, Status, TourAnchors, command_button, editor, execution, flex};
use crate::gui::help;
use crate::gui::theme::{
    FIELD_WIDTH, LABEL_WIDTH, TRACK_FONT_SIZE, TRACK_LINE_STROKE, TRACK_ROW_GAP, TRACK_ROW_HEIGHT,
};
use crate::state::{Command, Mode, TextBuffers, UiCommand};

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
                reset_buffers_if_stale(st, (None, m.revision));
            }
            editor::plan_fields_ui(ui, m, st, cmds);
            egui::CollapsingHeader::new("Advanced (JSON)")
                .id_salt("plan_json")
                .default_open(false)
                .show(ui, |ui| {
                    plan_editor_ui(ui, m, st, cmds);
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
    reset_buffers_if_stale(st, (Some(a), m.revision));
    editor::activity_fields_ui(ui, m, st, a, cmds);
    ui.separator();
    egui::CollapsingHeader::new("Advanced (JSON)")
        .id_salt("activity_json")
        .default_open(false)
        .show(ui, |ui| {
            activity_editor_ui(ui, m, st, a, cmds);
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
        intervals_ui(ui, m, &cats);
    }

    if let Some(e) = m.explanation_error {
        ui.separator();
        ui.colored_label(m.theme.error, format!("Could not explain it: {e}"));
    }
    if let Some(ex) = m.explanation {
        ui.separator();
        let why = ui
            .label(RichText::new("Why it did not schedule").strong())
            .on_hover_text(help::WHY);
        anchors.why = Some(why.rect);
        if let Some(k) = ex.failure_step {
            if ui
                .button(format!("Go to failure step {k}"))
                .on_hover_text(help::FAILURE_STEP)
                .clicked()
            {
                cmds.push(Command::GoToFailureStep(a));
            }
        }
        // Why, in a sentence (and the duration the rest is for), above the
        // conflicts and reasons; the notes that go through them one by one below.
        let problem = &m.analysis.schedule.problem;
        let (notes, lead) = explanation_notes_and_lead(&m.doc.plan, problem, ex);
        let lead = lead.min(notes.len());
        for note in &notes[..lead] {
            ui.label(note);
        }
        if ex.phase == Some(Phase::ValidIntervals) {
            for c in &ex.conflicts {
                let names: Vec<&str> = c.iter().map(|x| x.name()).collect();
                ui.label(format!("Conflict: {}", names.join(" + ")));
            }
        }
        for (i, r) in reasons_in_reading_order(ex)
            .into_iter()
            .take(4)
            .map(|i| (i, &ex.reasons[i]))
        {
            let line = reason_line(&m.doc.plan, &m.analysis.schedule.problem, r, ex.duration);
            // An energy or peak-power reason can be drawn over its plot (when
            // there is more than one to choose from).
            let overlay = m.would_cause.filter(|w| w.reasons.len() > 1).and_then(|w| {
                let j = w.reasons.iter().position(|o| o.reason == i)?;
                Some((w, j))
            });
            match overlay {
                Some((w, j)) => {
                    ui.horizontal_wrapped(|ui| {
                        ui.label(line);
                        if ui
                            .selectable_label(w.shown == j, "Show on plot")
                            .on_hover_text(help::OVERLAY_REASONS)
                            .clicked()
                        {
                            cmds.push(Command::ShowReason {
                                activity: a,
                                index: j,
                            });
                        }
                    });
                }
                None => {
                    ui.label(line);
                }
            }
        }
        if ex.reasons.len() > 4 {
            let more = ex.reasons.len() - 4;
            let text = if m.would_cause.is_some() {
                format!(
                    "and {more} more range(s) of starts (Next reason on the plots goes \
                     through the energy and peak-power ones)"
                )
            } else {
                format!("and {more} more range(s) of starts")
            };
            ui.label(RichText::new(text).color(m.theme.muted));
        }
        for note in &notes[lead..] {
            ui.label(note);
        }
        if !ex.culprits.is_empty() {
            let involved = ui
                .label(RichText::new("Involved (click to select and jump to its step)").strong())
                .on_hover_text(help::INVOLVED);
            anchors.involved = Some(involved.rect);
            for c in solscope_engine::involved(ex) {
                let text = format!(
                    "{} (step {}, {})",
                    m.doc.plan.activities[c.activity].id,
                    c.step,
                    c.blame.name()
                );
                if ui.link(text).clicked() {
                    cmds.push(Command::Select(Some(c.activity)));
                    cmds.push(Command::SetStep(c.step));
                }
            }
        }
        let suggestions = ui
            .label(RichText::new("Suggestions (verified by rescheduling)").strong())
            .on_hover_text(help::SUGGESTIONS);
        anchors.suggestions = Some(suggestions.rect);
        match m.suggestions {
            None => {
                ui.horizontal(|ui| {
                    ui.spinner();
                    ui.label("verifying candidate edits by rescheduling…");
                });
            }
            Some([]) => {
                ui.label("No single edit found that makes it schedule.");
            }
            Some(list) => {
                for s in list {
                    ui.horizontal_wrapped(|ui| {
                        ui.label(suggestion_line(&m.doc.plan, s));
                        if ui.button(format!("Apply: {}", s.description)).clicked() {
                            cmds.push(Command::Edit {
                                target: s.target.clone(),
                                set: s.set.clone(),
                                description: s.description.clone(),
                            });
                        }
                    });
                }
            }
        }
    }
    ui.separator();
    egui::CollapsingHeader::new("Edit activity")
        .default_open(true)
        .show(ui, |ui| {
            activity_edit_ui(ui, m, st, a, cmds);
        });
}

/// One row per category with its valid starts, then their intersection.
pub(super) fn intervals_ui(ui: &mut egui::Ui, m: &Model<'_>, cats: &[CategoryIntervals]) {
    let row_h = TRACK_ROW_HEIGHT;
    let n = cats.len() + 1;
    let (rect, resp) = ui.allocate_exact_size(
        egui::vec2(ui.available_width(), n as f32 * (row_h + TRACK_ROW_GAP)),
        Sense::hover(),
    );
    // The row under the pointer says what its rule is.
    if let Some(pos) = resp.hover_pos() {
        let row = ((pos.y - rect.top()) / (row_h + TRACK_ROW_GAP)).max(0.0) as usize;
        let text = cats
            .get(row)
            .map_or(help::ALL_TOGETHER, |c| help::category(c.category));
        resp.on_hover_text(text);
    }
    let painter = ui.painter_at(rect);
    let label_w = LABEL_WIDTH.min(rect.width() / 3.0);
    let track = Rect::from_min_max(Pos2::new(rect.left() + label_w, rect.top()), rect.max);
    let axis = m.nav.axis;
    let font = egui::FontId::proportional(TRACK_FONT_SIZE);
    let mut inter =
        solscope_engine::IntervalSet::single(m.doc.plan.horizon.start, m.doc.plan.horizon.end);
    let draw = |i: usize, name: &str, set: &solscope_engine::IntervalSet, color: egui::Color32| {
        let y = rect.top() + i as f32 * (row_h + TRACK_ROW_GAP);
        painter.text(
            Pos2::new(rect.left(), y + row_h / 2.0),
            egui::Align2::LEFT_CENTER,
            name,
            font.clone(),
            m.theme.muted,
        );
        painter.line_segment(
            [
                Pos2::new(track.left(), y + row_h / 2.0),
                Pos2::new(track.right(), y + row_h / 2.0),
            ],
            Stroke::new(TRACK_LINE_STROKE, m.theme.muted),
        );
        for iv in set.intervals() {
            let x0 = axis.x(iv.lo as f64, track).max(f64::from(track.left())) as f32;
            let x1 = axis
                .x(iv.hi as f64 + 1.0, track)
                .min(f64::from(track.right())) as f32;
            if x1 >= x0 {
                painter.rect_filled(
                    Rect::from_min_max(Pos2::new(x0, y), Pos2::new(x1.max(x0 + 1.0), y + row_h)),
                    1.0,
                    color,
                );
            }
        }
    };
    for (i, c) in cats.iter().enumerate() {
        inter = inter.intersect(&c.valid);
        draw(i, c.category.name(), &c.valid, m.theme.valid);
    }
    draw(cats.len(), "all together", &inter, m.theme.current);
}

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

fn reset_buffers_if_stale(st: &mut TextBuffers, key: (Option<usize>, u64)) {
    if st.editor_for != Some(key) {
        st.editor.clear();
        st.editor_for = Some(key);
    }
}

fn activity_editor_ui(
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

fn plan_editor_ui(ui: &mut egui::Ui, m: &Model<'_>, st: &mut TextBuffers, cmds: &mut Vec<Command>) {
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
