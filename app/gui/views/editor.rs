//! The structured editor in the inspector: every field of the selected
//! activity and of the plan-wide limits as a widget of its kind (times in sol
//! and local time, numbers with their units, checkboxes, names picked from
//! what the plan has), each committing one edit when the user finishes it
//! (Enter, or focus lost; Escape puts the value back). An edit is checked
//! with `apply_edit` first: a bad one stays in its field, in red with the
//! reason, and is never applied. An edit that changes nothing is not
//! recorded (the app says so).

use std::collections::BTreeSet;

use eframe::egui::{self, RichText};
use serde_json::{Map, Value, json};
use solscope_engine::{
    Activity, AwakeMode, Duration, EffectAt, LocalTime, Plan, Window, format_local, format_span,
    format_time_of_day, parse_local,
};

use super::{Model, command_button};
use crate::gui::theme::{
    COMBO_WIDTH, FIELD_WIDTH, NUMBER_FIELD_WIDTH, PICKER_HEIGHT, PICKER_WIDTH, TIME_FIELD_WIDTH,
};
use crate::state::{Command, TextBuffers, UiCommand};

/// Most options a picker lists (the search narrows them).
const PICK_LIMIT: usize = 60;

/// How a field reads and shows its value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// A whole number.
    Int,
    /// A length of time in seconds (shown with its span).
    Seconds,
    /// A decimal number in this unit.
    Number(&'static str),
    /// A plan time, in sol and local time (or plan seconds).
    Time,
    /// A local time of day.
    TimeOfDay,
    /// Free text.
    Text,
}

impl Kind {
    fn width(self) -> f32 {
        match self {
            Kind::Time => TIME_FIELD_WIDTH,
            Kind::Text => FIELD_WIDTH,
            _ => NUMBER_FIELD_WIDTH,
        }
    }

    /// `v` as the field shows it.
    fn show(self, clock: &LocalTime, v: Option<&Value>) -> String {
        match (self, v) {
            (_, None | Some(Value::Null)) => String::new(),
            (Kind::Time, Some(v)) => v
                .as_i64()
                .map_or_else(|| v.to_string(), |t| format_local(clock, t)),
            (Kind::TimeOfDay, Some(v)) => {
                v.as_i64().map_or_else(|| v.to_string(), format_time_of_day)
            }
            (Kind::Text, Some(Value::String(s))) => s.clone(),
            (_, Some(v)) => v.to_string(),
        }
    }

    /// The value of `text` (`None` when empty); `near`, the value it had,
    /// gives a time without a sol its sol.
    fn read(
        self,
        clock: &LocalTime,
        text: &str,
        near: Option<&Value>,
    ) -> Result<Option<Value>, String> {
        let text = text.trim();
        if text.is_empty() {
            return Ok(None);
        }
        let int = || {
            text.parse::<i64>()
                .map_err(|_| format!("\"{text}\" is not a whole number"))
        };
        Ok(Some(match self {
            Kind::Int => json!(int()?),
            Kind::Seconds => json!(int().map_err(|e| format!("{e} of seconds"))?),
            Kind::Number(unit) => match text.parse::<f64>() {
                Ok(x) if x.is_finite() => json!(x),
                _ => return Err(format!("\"{text}\" is not a number of {unit}")),
            },
            Kind::Time => {
                let sol = near.and_then(Value::as_i64).map(|t| clock.sol(t));
                match parse_local(clock, text, sol) {
                    Some(t) => json!(t),
                    None => {
                        return Err(format!(
                            "\"{text}\" is not a time: write a sol and local time \
                             (Sol {} 08:00), a local time in the same sol (08:00), or plan \
                             seconds",
                            sol.unwrap_or(0)
                        ));
                    }
                }
            }
            Kind::TimeOfDay => {
                // Seconds after midnight, or hh:mm[:ss] read as a time in the
                // first sol of a clock without offset.
                let day = LocalTime {
                    sol_length: clock.sol_length,
                    offset: 0,
                    first_sol: None,
                };
                match text
                    .parse::<i64>()
                    .ok()
                    .or_else(|| parse_local(&day, text, Some(0)))
                {
                    Some(t) => json!(t),
                    None => {
                        return Err(format!(
                            "\"{text}\" is not a local time of day: write 08:30 or seconds \
                             after midnight"
                        ));
                    }
                }
            }
            Kind::Text => json!(text),
        }))
    }

    /// What the field says beside its value (unit, length of time).
    fn note(self, v: Option<&Value>) -> Option<String> {
        match self {
            Kind::Number(unit) => Some(unit.to_string()),
            Kind::Seconds => Some(match v.and_then(Value::as_i64) {
                Some(s) if s >= 60 => format!("s ({})", format_span(s)),
                _ => "s".into(),
            }),
            _ => None,
        }
    }
}

/// How a field is named for assistive technology (and the tests).
#[derive(Clone, Copy, Debug)]
enum Name<'s> {
    /// By this text (nothing visible says all of it).
    Text(&'s str),
    /// By the visible label beside it.
    Label(egui::Id),
}

/// How a picker offers its options.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Pick {
    /// A plain list.
    List,
    /// A search field in its popup narrows the list.
    Search,
    /// The search field's text can also be chosen as a new name.
    New,
}

/// What the fields of one target (an activity, or the plan) draw with.
struct Ed<'a, 'm> {
    m: &'a Model<'m>,
    st: &'a mut TextBuffers,
    cmds: &'a mut Vec<Command>,
    /// `plan` or `activity:ID`.
    target: String,
    /// How the banner names the target: its id, or `the plan`.
    name: String,
}

impl Ed<'_, '_> {
    fn clock(&self) -> &LocalTime {
        &self.m.doc.plan.local_time
    }

    /// The text buffer of `field`.
    fn key(&self, field: &str) -> String {
        format!("s/{}/{field}", self.target)
    }

    /// A one-line field named `name` (its accessibility label) showing
    /// `shown` until typed in: the text when the user finishes (Enter or
    /// focus lost) and it differs from `shown`; Escape puts `shown` back.
    fn line(
        &mut self,
        ui: &mut egui::Ui,
        field: &str,
        name: &str,
        shown: &str,
        width: f32,
    ) -> Option<String> {
        self.line_hint(ui, field, Name::Text(name), (shown, ""), width)
    }

    /// [`Ed::line`] with `hint` shown in the field while it is empty.
    fn line_hint(
        &mut self,
        ui: &mut egui::Ui,
        field: &str,
        name: Name<'_>,
        (shown, hint): (&str, &str),
        width: f32,
    ) -> Option<String> {
        let key = self.key(field);
        let entry = self
            .st
            .editor
            .entry(key)
            .or_insert_with(|| (shown.to_string(), None));
        let mut edit = egui::TextEdit::singleline(&mut entry.0)
            .desired_width(width)
            .hint_text(hint);
        if entry.1.is_some() {
            edit = edit.text_color(self.m.theme.error);
        }
        let resp = match name {
            Name::Text(name) => ui.add(edit).accessible_name(name),
            Name::Label(id) => ui.add(edit).labelled_by(id),
        };
        if !resp.lost_focus() {
            return None;
        }
        if ui.input(|i| i.key_pressed(egui::Key::Escape)) {
            *entry = (shown.to_string(), None);
            return None;
        }
        (entry.0 != shown).then(|| entry.0.clone())
    }

    /// Keeps `msg` as the error of `field` (shown under it; nothing applied).
    fn fail(&mut self, field: &str, msg: String) {
        let key = self.key(field);
        if let Some(entry) = self.st.editor.get_mut(&key) {
            entry.1 = Some(msg);
        } else {
            self.st.editor.insert(key, (String::new(), Some(msg)));
        }
    }

    /// The error of `field`, wrapped to the width there is.
    fn error_ui(&self, ui: &mut egui::Ui, field: &str) {
        if let Some((_, Some(err))) = self.st.editor.get(&self.key(field)) {
            ui.add(egui::Label::new(RichText::new(err).color(self.m.theme.error)).wrap());
        }
    }

    /// In a two-column grid: the error of `field` under its value.
    fn error_row(&self, ui: &mut egui::Ui, field: &str) {
        if matches!(self.st.editor.get(&self.key(field)), Some((_, Some(_)))) {
            ui.label("");
            ui.vertical(|ui| {
                ui.set_max_width(FIELD_WIDTH + NUMBER_FIELD_WIDTH);
                self.error_ui(ui, field);
            });
            ui.end_row();
        }
    }

    /// Checks the edit setting `set` on `target` and pushes it, or keeps its
    /// error at `field`.
    fn submit_to(
        &mut self,
        target: &str,
        field: &str,
        set: Map<String, Value>,
        description: String,
    ) {
        match solscope_engine::apply_edit(&self.m.doc.plan, target, &set) {
            Ok(_) => self.cmds.push(Command::Edit {
                target: target.to_string(),
                set,
                description,
            }),
            Err(e) => self.fail(field, e.to_string()),
        }
    }

    /// [`Ed::submit_to`] this target, setting `key` to `value` (null removes it).
    fn submit(&mut self, field: &str, key: &str, value: Value, what: &str) {
        let mut set = Map::new();
        set.insert(key.to_string(), value);
        let target = self.target.clone();
        let description = format!("Set {what} of {}", self.name);
        self.submit_to(&target, field, set, description);
    }

    /// A field of `kind` in a grid row labelled `label`: the new value (`None`:
    /// emptied, only when `optional`) once the user finishes typing one that
    /// reads.
    fn value_row(
        &mut self,
        ui: &mut egui::Ui,
        label: &str,
        field: &str,
        kind: Kind,
        current: Option<&Value>,
        optional: bool,
    ) -> Option<Option<Value>> {
        let label = ui.label(label).id;
        let shown = kind.show(self.clock(), current);
        let typed = ui
            .horizontal(|ui| {
                let hint = if optional { "none" } else { "" };
                let typed =
                    self.line_hint(ui, field, Name::Label(label), (&shown, hint), kind.width());
                if let Some(note) = kind.note(current) {
                    ui.label(RichText::new(note).color(self.m.theme.muted));
                }
                typed
            })
            .inner;
        ui.end_row();
        let out = typed.and_then(|text| self.read(field, kind, &text, current, optional));
        self.error_row(ui, field);
        out
    }

    /// `text` read as `kind`, or the error kept at `field`.
    fn read(
        &mut self,
        field: &str,
        kind: Kind,
        text: &str,
        current: Option<&Value>,
        optional: bool,
    ) -> Option<Option<Value>> {
        match kind.read(self.clock(), text, current) {
            Ok(None) if !optional => {
                self.fail(field, "enter a value (it cannot be left out)".into());
                None
            }
            Ok(v) => Some(v),
            Err(e) => {
                self.fail(field, e);
                None
            }
        }
    }

    /// A row setting one top-level field `key` of the target.
    fn field_row(
        &mut self,
        ui: &mut egui::Ui,
        label: &str,
        key: &str,
        kind: Kind,
        obj: &Value,
        optional: bool,
    ) {
        if let Some(v) = self.value_row(ui, label, key, kind, obj.get(key), optional) {
            self.submit(key, key, v.unwrap_or(Value::Null), key);
        }
    }

    /// A row setting field `key` of the object `section` of the target (the
    /// whole object is the edit, as the edit format wants).
    fn section_row(
        &mut self,
        ui: &mut egui::Ui,
        label: &str,
        (section, key): (&str, &str),
        kind: Kind,
        obj: &Value,
        optional: bool,
    ) {
        let current = obj.get(section).and_then(|s| s.get(key));
        let field = format!("{section}.{key}");
        if let Some(v) = self.value_row(ui, label, &field, kind, current, optional) {
            let mut whole = obj
                .get(section)
                .and_then(Value::as_object)
                .cloned()
                .unwrap_or_default();
            match v {
                Some(v) => whole.insert(key.to_string(), v),
                None => whole.remove(key),
            };
            self.submit(&field, section, Value::Object(whole), &field);
        }
    }

    /// A combo box named `name` showing `shown`: the option chosen (see
    /// [`Pick`]).
    fn pick(
        &mut self,
        ui: &mut egui::Ui,
        field: &str,
        name: &str,
        shown: &str,
        options: &[String],
        how: Pick,
    ) -> Option<String> {
        let (search, new) = (how != Pick::List, how == Pick::New);
        let search_key = self.key(&format!("{field}/search"));
        let mut chosen = None;
        let st = &mut *self.st;
        let resp = egui::ComboBox::from_id_salt(&search_key)
            .selected_text(shown)
            .close_behavior(if search || new {
                egui::PopupCloseBehavior::CloseOnClickOutside
            } else {
                egui::PopupCloseBehavior::CloseOnClick
            })
            .show_ui(ui, |ui| {
                let mut needle = String::new();
                if search || new {
                    let entry = st
                        .editor
                        .entry(search_key.clone())
                        .or_insert_with(|| (String::new(), None));
                    let hint = if new {
                        "search or type a new name"
                    } else {
                        "search"
                    };
                    ui.add(
                        egui::TextEdit::singleline(&mut entry.0)
                            .hint_text(hint)
                            .desired_width(PICKER_WIDTH),
                    )
                    .accessible_name(format!("Search {name}"));
                    needle = entry.0.trim().to_string();
                }
                let lower = needle.to_lowercase();
                let matching: Vec<&String> = options
                    .iter()
                    .filter(|o| lower.is_empty() || o.to_lowercase().contains(&lower))
                    .collect();
                egui::ScrollArea::vertical()
                    .max_height(PICKER_HEIGHT)
                    .show(ui, |ui| {
                        for o in matching.iter().take(PICK_LIMIT) {
                            if ui.selectable_label(false, o.as_str()).clicked() {
                                chosen = Some((*o).clone());
                            }
                        }
                        if matching.len() > PICK_LIMIT {
                            ui.label(format!("… {} more: search", matching.len() - PICK_LIMIT));
                        }
                        if matching.is_empty() && !new {
                            ui.label("none");
                        }
                    });
                if new
                    && !needle.is_empty()
                    && !options.contains(&needle)
                    && ui.button(format!("New: {needle}")).clicked()
                {
                    chosen = Some(needle.clone());
                }
                if chosen.is_some() {
                    ui.close();
                }
            });
        resp.response.accessible_name(name);
        if chosen.is_some() {
            self.st.editor.remove(&search_key);
        }
        chosen
    }

    /// A small remove button named `name` (its hover text too).
    fn remove_button(ui: &mut egui::Ui, name: &str) -> bool {
        ui.small_button("×")
            .accessible_name(name)
            .on_hover_text(name)
            .clicked()
    }
}

/// A list field of the activity after `change`, as a JSON value.
fn list_value<T: serde::Serialize + Clone>(list: &[T], change: impl FnOnce(&mut Vec<T>)) -> Value {
    let mut list = list.to_vec();
    change(&mut list);
    serde_json::to_value(list).unwrap_or(Value::Null)
}

/// Every name the plan's activities use in `names` (sorted, once each).
fn used_names<'p>(plan: &'p Plan, names: impl Fn(&'p Activity) -> Vec<&'p String>) -> Vec<String> {
    let set: BTreeSet<&String> = plan.activities.iter().flat_map(names).collect();
    set.into_iter().cloned().collect()
}

/// The structured editor of activity `a`, with the buttons that add,
/// duplicate and delete activities.
pub(super) fn activity_fields_ui(
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
            ed.field_row(
                ui,
                "Energy rate",
                "energy_rate",
                Kind::Number("W"),
                &obj,
                false,
            );
            ed.field_row(
                ui,
                "Peak power",
                "peak_power",
                Kind::Number("W"),
                &obj,
                false,
            );
            ed.field_row(
                ui,
                "Data rate",
                "data_rate",
                Kind::Number("Mbit/s"),
                &obj,
                false,
            );
            ed.field_row(
                ui,
                "Sequence engines",
                "sequence_engines",
                Kind::Int,
                &obj,
                false,
            );
            ed.field_row(ui, "Group", "group", Kind::Text, &obj, true);
        });
    ui.separator();
    windows_ui(ui, &mut ed, act);
    ui.separator();
    names_ui(ui, &mut ed, act);
    ui.separator();
    dependencies_ui(ui, &mut ed, plan, act);
    ui.separator();
    states_ui(ui, &mut ed, plan, act);
    ui.separator();
    comm_ui(ui, &mut ed, plan, act);
}

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
            if Ed::remove_button(ui, &format!("Remove window {n}")) {
                let v = list_value(windows, |l| {
                    l.remove(i);
                });
                ed.submit(
                    "windows",
                    "windows",
                    v,
                    &format!("windows (window {n} removed)"),
                );
            }
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

/// A list of names with a remove button each and a picker to add one.
fn name_list_ui(
    ui: &mut egui::Ui,
    ed: &mut Ed<'_, '_>,
    key: &str,
    what: &str,
    names: &[String],
    options: &[String],
    new: bool,
) {
    ui.horizontal_wrapped(|ui| {
        if names.is_empty() {
            ui.label(RichText::new("none").color(ed.m.theme.muted));
        }
        for (i, name) in names.iter().enumerate() {
            ui.label(name);
            if Ed::remove_button(ui, &format!("Remove {what} {name}")) {
                let v = list_value(names, |l| {
                    l.remove(i);
                });
                ed.submit(key, key, v, key);
            }
        }
        let free: Vec<String> = options
            .iter()
            .filter(|o| !names.contains(o))
            .cloned()
            .collect();
        let how = match (new, free.len() > 8) {
            (true, _) => Pick::New,
            (false, true) => Pick::Search,
            (false, false) => Pick::List,
        };
        let label = format!("Add {what}");
        if let Some(name) = ed.pick(
            ui,
            &format!("{key}/add"),
            &label,
            &format!("{label}…"),
            &free,
            how,
        ) {
            let v = list_value(names, |l| l.push(name));
            ed.submit(key, key, v, key);
        }
    });
    ed.error_ui(ui, key);
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
            if Ed::remove_button(ui, &format!("Remove dependency on {other}")) {
                let v = list_value(deps, |l| {
                    l.remove(j);
                });
                ed.submit(
                    "after",
                    "after",
                    v,
                    &format!("after (no longer after {other})"),
                );
            }
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
    if let Some(id) = ed.pick(
        ui,
        "after/add",
        "Add dependency",
        "Add dependency…",
        &options,
        Pick::Search,
    ) {
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

/// State requirements and effects, states and values picked from the plan's.
fn states_ui(ui: &mut egui::Ui, ed: &mut Ed<'_, '_>, plan: &Plan, act: &Activity) {
    let states: Vec<String> = plan.states.keys().cloned().collect();
    let values = |state: &str| -> Vec<String> {
        plan.states
            .get(state)
            .map(|d| d.values.clone())
            .unwrap_or_default()
    };
    let initial = |state: &str| plan.states.get(state).map(|d| d.initial.clone());
    ui.label(RichText::new("Requires (state holds over the whole activity)").strong());
    let reqs = &act.requires;
    for (j, r) in reqs.iter().enumerate() {
        ui.horizontal_wrapped(|ui| {
            ui.spacing_mut().combo_width = COMBO_WIDTH;
            let n = j + 1;
            let name = format!("Requirement {n} state");
            if let Some(s) = ed.pick(
                ui,
                &format!("requires[{j}].state"),
                &name,
                &r.state,
                &states,
                Pick::List,
            ) && s != r.state
            {
                let v = initial(&s).unwrap_or_default();
                let v = list_value(reqs, |l| {
                    l[j] = solscope_engine::StateRequirement { state: s, value: v }
                });
                ed.submit("requires", "requires", v, "requires");
            }
            ui.label("=");
            let name = format!("Requirement {n} value");
            if let Some(x) = ed.pick(
                ui,
                &format!("requires[{j}].value"),
                &name,
                &r.value,
                &values(&r.state),
                Pick::List,
            ) {
                let v = list_value(reqs, |l| l[j].value = x);
                ed.submit("requires", "requires", v, "requires");
            }
            if Ed::remove_button(ui, &format!("Remove requirement {n}")) {
                let v = list_value(reqs, |l| {
                    l.remove(j);
                });
                ed.submit("requires", "requires", v, "requires");
            }
        });
    }
    if let Some(s) = ed.pick(
        ui,
        "requires/add",
        "Add requirement",
        "Add requirement…",
        &states,
        Pick::List,
    ) {
        let value = initial(&s).unwrap_or_default();
        let v = list_value(reqs, |l| {
            l.push(solscope_engine::StateRequirement { state: s, value })
        });
        ed.submit("requires", "requires", v, "requires");
    }
    ed.error_ui(ui, "requires");

    ui.label(RichText::new("Effects (state set at its start or end)").strong());
    let effs = &act.effects;
    let ats = ["at start".to_string(), "at end".to_string()];
    for (j, e) in effs.iter().enumerate() {
        ui.horizontal_wrapped(|ui| {
            ui.spacing_mut().combo_width = COMBO_WIDTH;
            let n = j + 1;
            let name = format!("Effect {n} state");
            if let Some(s) = ed.pick(
                ui,
                &format!("effects[{j}].state"),
                &name,
                &e.state,
                &states,
                Pick::List,
            ) && s != e.state
            {
                let v = initial(&s).unwrap_or_default();
                let v = list_value(effs, |l| {
                    l[j].state = s;
                    l[j].value = v;
                });
                ed.submit("effects", "effects", v, "effects");
            }
            ui.label("→");
            let name = format!("Effect {n} value");
            if let Some(x) = ed.pick(
                ui,
                &format!("effects[{j}].value"),
                &name,
                &e.value,
                &values(&e.state),
                Pick::List,
            ) {
                let v = list_value(effs, |l| l[j].value = x);
                ed.submit("effects", "effects", v, "effects");
            }
            let at = usize::from(e.at == EffectAt::End);
            let name = format!("Effect {n} when");
            if let Some(x) = ed.pick(
                ui,
                &format!("effects[{j}].at"),
                &name,
                &ats[at],
                &ats,
                Pick::List,
            ) {
                let at = if x == ats[0] {
                    EffectAt::Start
                } else {
                    EffectAt::End
                };
                let v = list_value(effs, |l| l[j].at = at);
                ed.submit("effects", "effects", v, "effects");
            }
            if Ed::remove_button(ui, &format!("Remove effect {n}")) {
                let v = list_value(effs, |l| {
                    l.remove(j);
                });
                ed.submit("effects", "effects", v, "effects");
            }
        });
    }
    if let Some(s) = ed.pick(
        ui,
        "effects/add",
        "Add effect",
        "Add effect…",
        &states,
        Pick::List,
    ) {
        // The first value other than the initial one: an effect that changes
        // something.
        let init = initial(&s).unwrap_or_default();
        let value = values(&s).into_iter().find(|v| *v != init).unwrap_or(init);
        let v = list_value(effs, |l| {
            l.push(solscope_engine::StateEffect {
                state: s,
                value,
                at: EffectAt::End,
            });
        });
        ed.submit("effects", "effects", v, "effects");
    }
    ed.error_ui(ui, "effects");
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

/// The structured editor of the plan-wide fields: limits, horizon and clock,
/// states and thermal zones.
pub(super) fn plan_fields_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    st: &mut TextBuffers,
    cmds: &mut Vec<Command>,
) {
    let plan = &m.doc.plan;
    let obj = match serde_json::to_value(plan.without_activities()) {
        Ok(v) => v,
        Err(e) => {
            ui.colored_label(m.theme.error, format!("The plan cannot be edited: {e}"));
            return;
        }
    };
    let mut ed = Ed {
        m,
        st,
        cmds,
        target: "plan".into(),
        name: "the plan".into(),
    };
    let energy = Kind::Number("Wh");
    let power = Kind::Number("W");
    let volume = Kind::Number("Mbit");
    egui::Grid::new("plan_fields")
        .num_columns(2)
        .show(ui, |ui| {
            heading_row(ui, "Battery");
            ed.section_row(ui, "Capacity", ("battery", "capacity"), energy, &obj, false);
            ed.section_row(
                ui,
                "Initial charge",
                ("battery", "initial"),
                energy,
                &obj,
                false,
            );
            ed.section_row(
                ui,
                "Minimum charge",
                ("battery", "min_soc"),
                energy,
                &obj,
                false,
            );
            heading_row(ui, "Power");
            ed.section_row(ui, "RTG output", ("power", "rtg"), power, &obj, false);
            ed.section_row(ui, "Draw asleep", ("power", "asleep"), power, &obj, false);
            ed.section_row(ui, "Draw awake", ("power", "awake"), power, &obj, false);
            ed.section_row(
                ui,
                "Peak power limit",
                ("power", "max_peak"),
                power,
                &obj,
                true,
            );
            heading_row(ui, "Sleep");
            ed.section_row(
                ui,
                "Wakeup",
                ("sleep", "wakeup_duration"),
                Kind::Seconds,
                &obj,
                false,
            );
            ed.section_row(
                ui,
                "Shutdown",
                ("sleep", "shutdown_duration"),
                Kind::Seconds,
                &obj,
                false,
            );
            ed.section_row(
                ui,
                "Shortest awake",
                ("sleep", "min_awake"),
                Kind::Seconds,
                &obj,
                false,
            );
            ed.section_row(
                ui,
                "Shortest sleep",
                ("sleep", "min_sleep"),
                Kind::Seconds,
                &obj,
                false,
            );
            heading_row(ui, "Data and engines");
            ed.section_row(
                ui,
                "Storage capacity",
                ("data", "capacity"),
                volume,
                &obj,
                true,
            );
            ed.section_row(ui, "Initial data", ("data", "initial"), volume, &obj, false);
            ed.field_row(
                ui,
                "Sequence engines",
                "sequence_engines",
                Kind::Int,
                &obj,
                true,
            );
            heading_row(ui, "Handover");
            ui.label("");
            let mut on = plan.handover.is_some();
            if ui
                .checkbox(&mut on, "Handover limits")
                .on_hover_text("Limits at the handover to the next plan (optional activities only)")
                .changed()
            {
                let v = if on {
                    json!({ "time": plan.horizon.end })
                } else {
                    Value::Null
                };
                ed.submit("handover", "handover", v, "handover");
            }
            ui.end_row();
            ed.error_row(ui, "handover");
            if plan.handover.is_some() {
                ed.section_row(
                    ui,
                    "Handover time",
                    ("handover", "time"),
                    Kind::Time,
                    &obj,
                    false,
                );
                ed.section_row(
                    ui,
                    "Handover charge",
                    ("handover", "min_soc"),
                    energy,
                    &obj,
                    true,
                );
                ed.section_row(
                    ui,
                    "Data produced by then",
                    ("handover", "max_data_volume"),
                    volume,
                    &obj,
                    true,
                );
            }
            heading_row(ui, "Horizon and clock");
            ed.section_row(
                ui,
                "Plan start",
                ("horizon", "start"),
                Kind::Time,
                &obj,
                false,
            );
            ed.section_row(ui, "Plan end", ("horizon", "end"), Kind::Time, &obj, false);
            ed.section_row(
                ui,
                "Sol length",
                ("local_time", "sol_length"),
                Kind::Seconds,
                &obj,
                false,
            );
            ed.section_row(
                ui,
                "Local time at t=0",
                ("local_time", "offset"),
                Kind::Seconds,
                &obj,
                false,
            );
            ed.section_row(
                ui,
                "Sol at t=0",
                ("local_time", "first_sol"),
                Kind::Int,
                &obj,
                true,
            );
        });
    ui.separator();
    plan_states_ui(ui, &mut ed, plan);
    ui.separator();
    zones_ui(ui, &mut ed, plan);
}

fn heading_row(ui: &mut egui::Ui, text: &str) {
    ui.label(RichText::new(text).strong());
    ui.end_row();
}

/// The plan's states: values (comma-separated) and initial value; add one,
/// remove one.
fn plan_states_ui(ui: &mut egui::Ui, ed: &mut Ed<'_, '_>, plan: &Plan) {
    ui.label(RichText::new("States").strong());
    let states = serde_json::to_value(&plan.states).unwrap_or(Value::Null);
    let set_states =
        |ed: &mut Ed<'_, '_>, field: &str, change: &dyn Fn(&mut Map<String, Value>), what: &str| {
            let mut all = states.as_object().cloned().unwrap_or_default();
            change(&mut all);
            ed.submit(field, "states", Value::Object(all), what);
        };
    for (name, def) in &plan.states {
        ui.horizontal_wrapped(|ui| {
            ui.label(RichText::new(name).monospace());
            if Ed::remove_button(ui, &format!("Remove state {name}")) {
                set_states(
                    ed,
                    "states",
                    &|all| {
                        all.remove(name);
                    },
                    &format!("states ({name} removed)"),
                );
            }
        });
        egui::Grid::new(("state", name))
            .num_columns(2)
            .show(ui, |ui| {
                ui.label("values");
                let field = format!("states.{name}.values");
                let shown = def.values.join(", ");
                let typed = ed.line(
                    ui,
                    &field,
                    &format!("State {name} values"),
                    &shown,
                    FIELD_WIDTH,
                );
                ui.end_row();
                if let Some(text) = typed {
                    let values: Vec<String> = text
                        .split(',')
                        .map(|v| v.trim().to_string())
                        .filter(|v| !v.is_empty())
                        .collect();
                    set_states(
                        ed,
                        &field,
                        &|all| {
                            if let Some(d) = all.get_mut(name) {
                                d["values"] = json!(values);
                            }
                        },
                        &format!("the values of state {name}"),
                    );
                }
                ed.error_row(ui, &field);
                ui.label("initial");
                let field = format!("states.{name}.initial");
                let picked = ed.pick(
                    ui,
                    &field,
                    &format!("State {name} initial"),
                    &def.initial,
                    &def.values,
                    Pick::List,
                );
                ui.end_row();
                if let Some(v) = picked.filter(|v| *v != def.initial) {
                    set_states(
                        ed,
                        &field,
                        &|all| {
                            if let Some(d) = all.get_mut(name) {
                                d["initial"] = json!(v);
                            }
                        },
                        &format!("the initial value of state {name}"),
                    );
                }
                ed.error_row(ui, &field);
            });
    }
    ui.horizontal(|ui| {
        ui.label("New state");
        if let Some(name) = ed.line(ui, "states/new", "New state", "", FIELD_WIDTH / 1.5) {
            let name = name.trim().to_string();
            if !name.is_empty() {
                set_states(
                    ed,
                    "states/new",
                    &|all| {
                        all.insert(
                            name.clone(),
                            json!({ "values": ["off", "on"], "initial": "off" }),
                        );
                    },
                    &format!("states ({name} added)"),
                );
            }
        }
    });
    ed.error_ui(ui, "states/new");
    ed.error_ui(ui, "states");
}

/// The plan's thermal zones: heater powers, preheat table and operable
/// periods (local times of day); add one, remove one.
fn zones_ui(ui: &mut egui::Ui, ed: &mut Ed<'_, '_>, plan: &Plan) {
    ui.label(RichText::new("Thermal zones").strong());
    let zones = serde_json::to_value(&plan.thermal_zones).unwrap_or(Value::Null);
    let set_zones =
        |ed: &mut Ed<'_, '_>, field: &str, change: &dyn Fn(&mut Map<String, Value>), what: &str| {
            let mut all = zones.as_object().cloned().unwrap_or_default();
            change(&mut all);
            ed.submit(field, "thermal_zones", Value::Object(all), what);
        };
    for (name, zone) in &plan.thermal_zones {
        let z = zones.get(name).cloned().unwrap_or(Value::Null);
        ui.horizontal_wrapped(|ui| {
            ui.label(RichText::new(name).monospace());
            if Ed::remove_button(ui, &format!("Remove zone {name}")) {
                set_zones(
                    ed,
                    "thermal_zones",
                    &|all| {
                        all.remove(name);
                    },
                    &format!("thermal zones ({name} removed)"),
                );
            }
        });
        // The edit made in this zone, if any: (field, the zone's fields it
        // replaces, what it was).
        let mut edit: Option<(String, Value, String)> = None;
        egui::Grid::new(("zone", name))
            .num_columns(2)
            .show(ui, |ui| {
                for (label, key) in [
                    ("Preheat power", "preheat_power"),
                    ("Maintenance power", "maintenance_power"),
                ] {
                    let field = format!("thermal_zones.{name}.{key}");
                    if let Some(Some(v)) =
                        ed.value_row(ui, label, &field, Kind::Number("W"), z.get(key), false)
                    {
                        edit = Some((field, json!({ key: v }), format!("{key} of zone {name}")));
                    }
                }
            });
        for (table, cols) in [
            ("preheat", ["from", "duration"]),
            ("operable", ["from", "to"]),
        ] {
            let rows = z.get(table).and_then(Value::as_array).cloned();
            let heading = if table == "preheat" {
                "Preheat (from a local time: its length)"
            } else {
                "Operable (a preheat may start)"
            };
            ui.label(heading);
            if table == "operable" && rows.is_none() {
                ui.label(RichText::new("always").color(ed.m.theme.muted));
            }
            let rows = rows.unwrap_or_default();
            for (i, row) in rows.iter().enumerate() {
                ui.horizontal(|ui| {
                    for col in cols {
                        let kind = if col == "duration" {
                            Kind::Seconds
                        } else {
                            Kind::TimeOfDay
                        };
                        ui.label(col);
                        let field = format!("thermal_zones.{name}.{table}[{i}].{col}");
                        let shown = kind.show(ed.clock(), row.get(col));
                        let a11y = format!("Zone {name} {table} {} {col}", i + 1);
                        if let Some(text) =
                            ed.line(ui, &field, &a11y, &shown, NUMBER_FIELD_WIDTH / 1.2)
                            && let Some(Some(v)) = ed.read(&field, kind, &text, None, false)
                        {
                            let mut new = rows.clone();
                            new[i][col] = v;
                            edit = Some((
                                field,
                                json!({ table: new }),
                                format!("{table} of zone {name}"),
                            ));
                        }
                    }
                    if Ed::remove_button(ui, &format!("Remove zone {name} {table} {}", i + 1)) {
                        let mut new = rows.clone();
                        new.remove(i);
                        edit = Some((
                            format!("thermal_zones.{name}.{table}"),
                            json!({ table: new }),
                            format!("{table} of zone {name}"),
                        ));
                    }
                });
                for col in cols {
                    ed.error_ui(ui, &format!("thermal_zones.{name}.{table}[{i}].{col}"));
                }
            }
            ui.horizontal(|ui| {
                let add = if table == "preheat" {
                    "Add preheat row"
                } else {
                    "Add operable period"
                };
                if ui
                    .button(add)
                    .accessible_name(format!("{add} to zone {name}"))
                    .clicked()
                {
                    let mut new = rows.clone();
                    new.push(if table == "preheat" {
                        json!({ "from": 0, "duration": 0 })
                    } else {
                        json!({ "from": 0, "to": 0 })
                    });
                    edit = Some((
                        format!("thermal_zones.{name}.{table}"),
                        json!({ table: new }),
                        format!("{table} of zone {name}"),
                    ));
                }
                if table == "operable"
                    && zone.operable.is_some()
                    && ui
                        .button("Always operable")
                        .accessible_name(format!("Zone {name} always operable"))
                        .clicked()
                {
                    edit = Some((
                        format!("thermal_zones.{name}.{table}"),
                        json!({ table: null }),
                        format!("{table} of zone {name}"),
                    ));
                }
            });
            ed.error_ui(ui, &format!("thermal_zones.{name}.{table}"));
        }
        if let Some((field, change, what)) = edit {
            set_zones(
                ed,
                &field,
                &|all| {
                    if let (Some(Value::Object(z)), Value::Object(change)) =
                        (all.get_mut(name), &change)
                    {
                        for (k, v) in change {
                            if v.is_null() {
                                z.remove(k);
                            } else {
                                z.insert(k.clone(), v.clone());
                            }
                        }
                    }
                },
                &what,
            );
        }
    }
    ui.horizontal(|ui| {
        ui.label("New zone");
        if let Some(name) = ed.line(ui, "thermal_zones/new", "New zone", "", FIELD_WIDTH / 1.5) {
            let name = name.trim().to_string();
            if !name.is_empty() {
                set_zones(ed, "thermal_zones/new", &|all| {
                    all.insert(
                        name.clone(),
                        json!({ "preheat": [{ "from": 0, "duration": 0 }], "preheat_power": 0.0, "maintenance_power": 0.0 }),
                    );
                }, &format!("thermal zones ({name} added)"));
            }
        }
    });
    ed.error_ui(ui, "thermal_zones/new");
    ed.error_ui(ui, "thermal_zones");
}
