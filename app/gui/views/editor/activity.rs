//! The activity form: id, name, priority, value, mandatory, awake, duration,
//! rates and engines, group; its windows, unit resources and thermal zones,
//! dependencies, state requirements and effects (`states`) and comm kinds,
//! each field committing one edit of the activity.

use eframe::egui::{self, RichText};
use serde_json::{Map, Value, json};
use solscope_engine::{Activity, AwakeMode, Duration, Plan, Window};

use super::kit::At::Top;
use super::kit::{Ed, FormRow, Kind, Name, Pick, list_value, name_list_ui, used_names};
use super::states;
use crate::gui::theme::{FIELD_WIDTH, NUMBER_FIELD_WIDTH, TIME_FIELD_WIDTH};
use crate::gui::views::{Model, command_button};
use crate::state::TextBuffers;
use crate::state::{Command, UiCommand};

/// The structured editor of activity `a`, with the buttons that add,
/// duplicate and delete activities.
pub(in crate::gui::views) fn activity_fields_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    st: &mut TextBuffers,
    a: usize,
    cmds: &mut Vec<Command>,
) {
    let plan = &m.doc.plan;
    let Some(act) = plan.activities.get(a) else {
        return;
    };
    ui.horizontal_wrapped(|ui| {
        command_button(ui, UiCommand::AddActivity, true, cmds);
        command_button(ui, UiCommand::DuplicateActivity, true, cmds);
        command_button(ui, UiCommand::DeleteActivity, true, cmds);
    });
    let obj = match serde_json::to_value(act) {
        Ok(v) => v,
        Err(e) => {
            ui.colored_label(
                m.theme.error,
                format!("This activity cannot be edited: {e}"),
            );
            return;
        }
    };
    let mut ed = Ed {
        m,
        st,
        cmds,
        target: format!("activity:{}", act.id),
        name: act.id.clone(),
    };
    egui::Grid::new("activity_fields")
        .num_columns(2)
        .show(ui, |ui| {
            identity_rows(ui, &mut ed, plan, a, act, &obj);
            duration_rows(ui, &mut ed, act, &obj);
            ed.rows(ui, &obj, RATES);
        });
    ui.separator();
    windows_ui(ui, &mut ed, act);
    ui.separator();
    names_ui(ui, &mut ed, act);
    ui.separator();
    dependencies_ui(ui, &mut ed, plan, act);
    ui.separator();
    states::states_ui(ui, &mut ed, plan, act);
    ui.separator();
    comm_ui(ui, &mut ed, plan, act);
}

/// Rates and peak power, engines and group.
const RATES: &[FormRow<'static>] = &[
    ("Energy rate", Top("energy_rate"), Kind::Number("W"), false),
    ("Peak power", Top("peak_power"), Kind::Number("W"), false),
    ("Data rate", Top("data_rate"), Kind::Number("Mbit/s"), false),
    (
        "Sequence engines",
        Top("sequence_engines"),
        Kind::Int,
        false,
    ),
    ("Group", Top("group"), Kind::Text, true),
];

/// Id (a rename updates the dependencies on it), name, priority, mandatory,
/// awake.
fn identity_rows(
    ui: &mut egui::Ui,
    ed: &mut Ed<'_, '_>,
    plan: &Plan,
    a: usize,
    act: &Activity,
    obj: &Value,
) {
    let label = ui.label("Id").id;
    let typed = ed.line_hint(ui, "id", Name::Label(label), (&act.id, ""), FIELD_WIDTH);
    ui.end_row();
    if let Some(new) = typed.map(|t| t.trim().to_string()) {
        // The edit format changes one target: a rename is an edit of the
        // plan's activities, the dependencies on it renamed too.
        let mut acts = plan.activities.clone();
        for x in &mut acts {
            for d in &mut x.after {
                if d.activity == act.id {
                    d.activity.clone_from(&new);
                }
            }
        }
        acts[a].id.clone_from(&new);
        let mut set = Map::new();
        set.insert(
            "activities".into(),
            serde_json::to_value(acts).unwrap_or(Value::Null),
        );
        ed.submit_to("plan", "id", set, format!("Rename {} to {new}", act.id));
    }
    ed.error_row(ui, "id");
    ed.field_row(ui, "Name", "name", Kind::Text, obj, true);
    ed.field_row(ui, "Priority", "priority", Kind::Int, obj, false);
    // What completing it is worth to the planners (only tuning reads it).
    ed.field_row(ui, "Value", "value", Kind::Number(""), obj, true);
    ui.label("");
    let mut mandatory = act.mandatory;
    if ui
        .checkbox(&mut mandatory, "Mandatory")
        .on_hover_text("Unticked: optional (handover limits bind only optional activities)")
        .changed()
    {
        ed.submit("mandatory", "mandatory", json!(mandatory), "mandatory");
    }
    ui.end_row();
    ed.error_row(ui, "mandatory");
    ui.label("Awake");
    let modes = [
        (AwakeMode::Required, "required", "awake required"),
        (AwakeMode::Forbidden, "forbidden", "asleep (manual sleep)"),
        (AwakeMode::Any, "any", "awake or asleep"),
    ];
    let shown = modes.iter().find(|m| m.0 == act.awake).map_or("", |m| m.2);
    let options: Vec<String> = modes.iter().map(|m| m.2.to_string()).collect();
    if let Some(choice) = ed.pick(ui, "awake", "Awake", shown, &options, Pick::List)
        && let Some(mode) = modes.iter().find(|m| m.2 == choice)
        && mode.0 != act.awake
    {
        ed.submit("awake", "awake", json!(mode.1), "awake");
    }
    ui.end_row();
    ed.error_row(ui, "awake");
}

/// Fixed or expanding, and its length(s).
fn duration_rows(ui: &mut egui::Ui, ed: &mut Ed<'_, '_>, act: &Activity, obj: &Value) {
    ui.label("Duration");
    let kinds = ["fixed".to_string(), "expanding (min to max)".to_string()];
    let expanding = matches!(act.duration, Duration::Expanding { .. });
    let shown = &kinds[usize::from(expanding)];
    if let Some(choice) = ed.pick(
        ui,
        "duration_kind",
        "Duration kind",
        shown,
        &kinds,
        Pick::List,
    ) {
        let value = match (choice == kinds[1], act.duration) {
            (true, Duration::Fixed(d)) => Some(json!({ "min": d, "max": d })),
            (false, Duration::Expanding { max, .. }) => Some(json!(max)),
            _ => None,
        };
        if let Some(v) = value {
            ed.submit("duration_kind", "duration", v, "duration");
        }
    }
    ui.end_row();
    ed.error_row(ui, "duration_kind");
    match act.duration {
        Duration::Fixed(_) => ed.field_row(ui, "Length", "duration", Kind::Seconds, obj, false),
        Duration::Expanding { .. } => {
            ed.section_row(
                ui,
                "Shortest",
                ("duration", "min"),
                Kind::Seconds,
                obj,
                false,
            );
            ed.section_row(
                ui,
                "Longest",
                ("duration", "max"),
                Kind::Seconds,
                obj,
                false,
            );
        }
    }
}

/// The windows, one block each: start and end, preferred and cutoff.
fn windows_ui(ui: &mut egui::Ui, ed: &mut Ed<'_, '_>, act: &Activity) {
    ui.label(RichText::new("Windows (allowed starts)").strong());
    let horizon = ed.m.doc.plan.horizon;
    let whole = Window {
        start: horizon.start,
        end: horizon.end,
        preferred: None,
        cutoff: None,
    };
    let Some(windows) = &act.windows else {
        ui.label("None given: any start in the horizon.");
        if ui.button("Add window").clicked() {
            ed.submit(
                "windows",
                "windows",
                list_value(&[whole], |_| {}),
                "windows",
            );
        }
        ed.error_ui(ui, "windows");
        return;
    };
    if windows.is_empty() {
        ui.colored_label(ed.m.theme.error, "No window: it can never be scheduled.");
    }
    for (i, w) in windows.iter().enumerate() {
        let n = i + 1;
        ui.horizontal(|ui| {
            ui.label(format!("Window {n}"));
            let what = format!("windows (window {n} removed)");
            let name = format!("Remove window {n}");
            ed.remove_item(ui, &name, ("windows", windows, i), &what);
        });
        let parts = [
            ("start", Some(w.start), false),
            ("end", Some(w.end), false),
            ("preferred", w.preferred, true),
            ("cutoff", w.cutoff, true),
        ];
        let mut changed = None;
        egui::Grid::new(("window", i))
            .num_columns(2)
            .show(ui, |ui| {
                for (part, value, optional) in &parts {
                    ui.label(*part);
                    let field = format!("windows[{i}].{part}");
                    let current = value.map(|t| json!(t));
                    let shown = Kind::Time.show(ed.clock(), current.as_ref());
                    let name = format!("Window {n} {part}");
                    let hint = match *part {
                        "preferred" => "its start",
                        "cutoff" => "none",
                        _ => "",
                    };
                    let typed = ed.line_hint(
                        ui,
                        &field,
                        Name::Text(&name),
                        (&shown, hint),
                        TIME_FIELD_WIDTH,
                    );
                    ui.end_row();
                    if let Some(text) = typed {
                        let near = current.clone().or(Some(json!(w.start)));
                        if let Some(v) =
                            ed.read(&field, Kind::Time, &text, near.as_ref(), *optional)
                        {
                            changed = Some((field, *part, v.and_then(|v| v.as_i64())));
                        }
                    }
                }
            });
        for part in ["start", "end", "preferred", "cutoff"] {
            ed.error_ui(ui, &format!("windows[{i}].{part}"));
        }
        if let Some((field, part, t)) = changed {
            let mut new = *w;
            match (part, t) {
                ("start", Some(t)) => new.start = t,
                ("end", Some(t)) => new.end = t,
                ("preferred", t) => new.preferred = t,
                ("cutoff", t) => new.cutoff = t,
                _ => {}
            }
            let v = list_value(windows, |l| l[i] = new);
            ed.submit(&field, "windows", v, &format!("window {n} {part}"));
        }
    }
    ui.horizontal_wrapped(|ui| {
        if ui.button("Add window").clicked() {
            let next = windows.last().copied().unwrap_or(whole);
            let v = list_value(windows, |l| l.push(next));
            ed.submit("windows", "windows", v, "windows (window added)");
        }
        if ui
            .button("Any start")
            .on_hover_text("Leave out the windows: any start in the horizon")
            .clicked()
        {
            ed.submit("windows", "windows", Value::Null, "windows (any start)");
        }
    });
    ed.error_ui(ui, "windows");
}

/// Unit resources and thermal zones.
fn names_ui(ui: &mut egui::Ui, ed: &mut Ed<'_, '_>, act: &Activity) {
    let plan = &ed.m.doc.plan;
    let resources = used_names(plan, |a| a.resources.iter().collect());
    let zones: Vec<String> = plan.thermal_zones.keys().cloned().collect();
    ui.label(RichText::new("Unit resources").strong());
    name_list_ui(
        ui,
        ed,
        "resources",
        "resource",
        &act.resources,
        &resources,
        true,
    );
    ui.label(RichText::new("Thermal zones").strong());
    name_list_ui(
        ui,
        ed,
        "thermal_zones",
        "zone",
        &act.thermal_zones,
        &zones,
        false,
    );
}

/// The dependencies (`after`), each with its delays, and the picker that adds
/// one.
fn dependencies_ui(ui: &mut egui::Ui, ed: &mut Ed<'_, '_>, plan: &Plan, act: &Activity) {
    ui.label(RichText::new("After (dependencies)").strong());
    let deps = &act.after;
    for (j, d) in deps.iter().enumerate() {
        let other = &d.activity;
        ui.horizontal_wrapped(|ui| {
            ui.label(format!("after {other}"));
            let mut meets = d.meets;
            if ui
                .checkbox(&mut meets, "meets")
                .on_hover_text("Starts exactly when it ends")
                .changed()
            {
                let v = list_value(deps, |l| {
                    l[j].meets = meets;
                    if meets {
                        l[j].min_delay = None;
                        l[j].max_delay = None;
                    }
                });
                ed.submit("after", "after", v, &format!("after {other}"));
            }
            let what = format!("after (no longer after {other})");
            let name = format!("Remove dependency on {other}");
            ed.remove_item(ui, &name, ("after", deps, j), &what);
        });
        ui.horizontal_wrapped(|ui| {
            if !d.meets {
                for (part, value) in [("min delay", d.min_delay), ("max delay", d.max_delay)] {
                    ui.label(part);
                    let field = format!("after[{j}].{part}");
                    let current = value.map(|x| json!(x));
                    let shown = Kind::Seconds.show(ed.clock(), current.as_ref());
                    let name = format!("Dependency on {other} {part}");
                    if let Some(text) = ed.line(ui, &field, &name, &shown, NUMBER_FIELD_WIDTH / 1.5)
                        && let Some(v) = ed.read(&field, Kind::Seconds, &text, None, true)
                    {
                        let x = v.and_then(|v| v.as_i64());
                        let v = list_value(deps, |l| {
                            if part == "min delay" {
                                l[j].min_delay = x;
                            } else {
                                l[j].max_delay = x;
                            }
                        });
                        ed.submit(&field, "after", v, &format!("{part} after {other}"));
                    }
                    ui.label("s");
                }
            }
        });
        for part in ["min delay", "max delay"] {
            ed.error_ui(ui, &format!("after[{j}].{part}"));
        }
    }
    let options: Vec<String> = plan
        .activities
        .iter()
        .map(|x| &x.id)
        .filter(|id| **id != act.id && !deps.iter().any(|d| &d.activity == *id))
        .cloned()
        .collect();
    if let Some(id) = ed.add_pick(ui, "after", "Add dependency", &options, Pick::Search) {
        let v = list_value(deps, |l| {
            l.push(solscope_engine::Dependency {
                activity: id.clone(),
                meets: false,
                min_delay: None,
                max_delay: None,
            });
        });
        ed.submit("after", "after", v, &format!("after (after {id})"));
    }
    ed.error_ui(ui, "after");
}

/// Comm kind and the kinds it may run alongside.
fn comm_ui(ui: &mut egui::Ui, ed: &mut Ed<'_, '_>, plan: &Plan, act: &Activity) {
    let kinds = used_names(plan, |a| {
        a.comm_kind
            .iter()
            .chain(a.uhf_interactions.iter().flatten())
            .collect()
    });
    ui.label(RichText::new("Communication").strong());
    ui.horizontal_wrapped(|ui| {
        ui.label("Comm kind");
        const NONE: &str = "none (not a comm activity)";
        let mut options = vec![NONE.to_string()];
        options.extend(kinds.iter().cloned());
        let shown = act.comm_kind.as_deref().unwrap_or(NONE);
        if let Some(k) = ed.pick(ui, "comm_kind", "Comm kind", shown, &options, Pick::New)
            && Some(k.as_str()) != act.comm_kind.as_deref()
        {
            let v = if k == NONE { Value::Null } else { json!(k) };
            ed.submit("comm_kind", "comm_kind", v, "comm_kind");
        }
    });
    ed.error_ui(ui, "comm_kind");
    let mut any = act.uhf_interactions.is_none();
    if ui
        .checkbox(&mut any, "Runs alongside any comm kind")
        .on_hover_text("Unticked: only alongside the kinds listed")
        .changed()
    {
        let v = if any { Value::Null } else { json!([]) };
        ed.submit(
            "uhf_interactions",
            "uhf_interactions",
            v,
            "uhf_interactions",
        );
    }
    if let Some(list) = &act.uhf_interactions {
        ui.label("Only alongside:");
        name_list_ui(ui, ed, "uhf_interactions", "comm kind", list, &kinds, true);
    } else {
        ed.error_ui(ui, "uhf_interactions");
    }
}
