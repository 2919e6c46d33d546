//! The editor's widget kit, shared by the activity and the plan-limits
//! forms: the one-line field that commits when the user finishes it (Enter,
//! Tab or focus lost), puts the value back on Escape and keeps a bad value
//! in red with its reason ([`Ed::line`], [`Ed::value_row`]); rows setting a
//! top-level field or a field of a section; name pickers ([`Ed::pick`]); and
//! the rows of a list of names with a remove button each
//! ([`name_list_ui`]). Every edit is checked with `apply_edit` before it is
//! pushed ([`Ed::submit`]).

use std::collections::BTreeSet;

use eframe::egui::{self, RichText};
use serde_json::{Map, Value, json};
use solscope_engine::{
    Activity, LocalTime, Plan, format_local, format_span, format_time_of_day, lmst_of_day,
    parse_local, parse_time_of_day, time_of_day_of_lmst,
};

use crate::gui::theme::{
    FIELD_WIDTH, NUMBER_FIELD_WIDTH, PICKER_HEIGHT, PICKER_WIDTH, TIME_FIELD_WIDTH,
};
use crate::gui::views::Model;
use crate::state::Command;
use crate::state::TextBuffers;

/// Most options a picker lists (the search narrows them).
const PICK_LIMIT: usize = 60;

/// How a field reads and shows its value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    /// A whole number.
    Int,
    /// A length of time in seconds (shown with its span).
    Seconds,
    /// A decimal number in this unit (none when empty).
    Number(&'static str),
    /// A plan time, in sol and local time (or plan seconds).
    Time,
    /// A local time of day.
    TimeOfDay,
    /// Free text.
    Text,
}

impl Kind {
    pub(super) fn width(self) -> f32 {
        match self {
            Kind::Time => TIME_FIELD_WIDTH,
            Kind::Text => FIELD_WIDTH,
            _ => NUMBER_FIELD_WIDTH,
        }
    }

    /// `v` as the field shows it.
    pub(super) fn show(self, clock: &LocalTime, v: Option<&Value>) -> String {
        match (self, v) {
            (_, None | Some(Value::Null)) => String::new(),
            (Kind::Time, Some(v)) => v
                .as_i64()
                .map_or_else(|| v.to_string(), |t| format_local(clock, t)),
            (Kind::TimeOfDay, Some(v)) => v.as_i64().map_or_else(
                || v.to_string(),
                |t| format_time_of_day(lmst_of_day(clock.sol_length, t)),
            ),
            (Kind::Text, Some(Value::String(s))) => s.clone(),
            (_, Some(v)) => v.to_string(),
        }
    }

    /// The value of `text` (`None` when empty); `near`, the value it had,
    /// gives a time without a sol its sol.
    pub(super) fn read(
        self,
        clock: &LocalTime,
        text: &str,
        near: Option<&Value>,
    ) -> Result<Option<Value>, String> {
        let text = text.trim();
        if text.is_empty() {
            return Ok(None);
        }
        // A time shown to the LMST second stands for the plan second it was:
        // read as shown, it keeps that second.
        if matches!(self, Kind::Time | Kind::TimeOfDay) && text == self.show(clock, near) {
            return Ok(near.cloned());
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
                _ if unit.is_empty() => return Err(format!("\"{text}\" is not a number")),
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
                // Seconds after midnight, or hh:mm[:ss].
                match text.parse::<i64>().ok().or_else(|| {
                    parse_time_of_day(text)
                        .ok()
                        .map(|m| time_of_day_of_lmst(clock.sol_length, m))
                }) {
                    Some(t) => json!(t),
                    None => {
                        return Err(format!(
                            "\"{text}\" is not a local time of day: write 08:30 (LMST) or \
                             plan seconds after midnight"
                        ));
                    }
                }
            }
            Kind::Text => json!(text),
        }))
    }

    /// What the field says beside its value (unit, length of time).
    pub(super) fn note(self, v: Option<&Value>) -> Option<String> {
        match self {
            Kind::Number(unit) => (!unit.is_empty()).then(|| unit.to_string()),
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
pub(super) enum Name<'s> {
    /// By this text (nothing visible says all of it).
    Text(&'s str),
    /// By the visible label beside it.
    Label(egui::Id),
}

/// How a picker offers its options.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Pick {
    /// A plain list.
    List,
    /// A search field in its popup narrows the list.
    Search,
    /// The search field's text can also be chosen as a new name.
    New,
}

/// Where a form row's value sits in the target.
#[derive(Clone, Copy, Debug)]
pub(super) enum At<'k> {
    /// A top-level field.
    Top(&'k str),
    /// Field `.1` of the object `.0` (the whole object is the edit).
    In(&'k str, &'k str),
}

/// A row of a form: its label, where its value sits, its kind, and whether
/// it may be left empty.
pub(super) type FormRow<'k> = (&'k str, At<'k>, Kind, bool);

/// An object field of the target whose entries are named (the plan's states,
/// its thermal zones).
pub(super) struct Named<'v> {
    /// Its key.
    key: &'static str,
    /// Its value.
    whole: &'v Value,
    /// An entry, in a remove button's name (`Remove state NAME`).
    noun: &'static str,
    /// The entries, in the banner (`states (NAME added)`).
    plural: &'static str,
}

impl<'v> Named<'v> {
    /// The field `key` holding `whole`, its entries named by `noun` and
    /// `plural`.
    pub(super) fn new(
        key: &'static str,
        whole: &'v Value,
        (noun, plural): (&'static str, &'static str),
    ) -> Self {
        Self {
            key,
            whole,
            noun,
            plural,
        }
    }
}

/// What the fields of one target (an activity, or the plan) draw with.
pub(super) struct Ed<'a, 'm> {
    pub(super) m: &'a Model<'m>,
    pub(super) st: &'a mut TextBuffers,
    pub(super) cmds: &'a mut Vec<Command>,
    /// `plan` or `activity:ID`.
    pub(super) target: String,
    /// How the banner names the target: its id, or `the plan`.
    pub(super) name: String,
}

impl Ed<'_, '_> {
    pub(super) fn clock(&self) -> &LocalTime {
        &self.m.doc.plan.local_time
    }

    /// The text buffer of `field`.
    pub(super) fn key(&self, field: &str) -> String {
        format!("s/{}/{field}", self.target)
    }

    /// A one-line field named `name` (its accessibility label) showing
    /// `shown` until typed in: the text when the user finishes (Enter or
    /// focus lost) and it differs from `shown`; Escape puts `shown` back.
    pub(super) fn line(
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
    pub(super) fn line_hint(
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
    pub(super) fn fail(&mut self, field: &str, msg: String) {
        let key = self.key(field);
        if let Some(entry) = self.st.editor.get_mut(&key) {
            entry.1 = Some(msg);
        } else {
            self.st.editor.insert(key, (String::new(), Some(msg)));
        }
    }

    /// The error of `field`, wrapped to the width there is.
    pub(super) fn error_ui(&self, ui: &mut egui::Ui, field: &str) {
        if let Some((_, Some(err))) = self.st.editor.get(&self.key(field)) {
            ui.add(egui::Label::new(RichText::new(err).color(self.m.theme.error)).wrap());
        }
    }

    /// In a two-column grid: the error of `field` under its value.
    pub(super) fn error_row(&self, ui: &mut egui::Ui, field: &str) {
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
    pub(super) fn submit_to(
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
    pub(super) fn submit(&mut self, field: &str, key: &str, value: Value, what: &str) {
        let mut set = Map::new();
        set.insert(key.to_string(), value);
        let target = self.target.clone();
        let description = format!("Set {what} of {}", self.name);
        self.submit_to(&target, field, set, description);
    }

    /// A field of `kind` in a grid row labelled `label`: the new value (`None`:
    /// emptied, only when `optional`) once the user finishes typing one that
    /// reads.
    pub(super) fn value_row(
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
    pub(super) fn read(
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
    pub(super) fn field_row(
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
    pub(super) fn section_row(
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

    /// A remove button named `name` for item `i` of the list field `key`
    /// (`list`): the edit without it, described as `what`.
    pub(super) fn remove_item<T: serde::Serialize + Clone>(
        &mut self,
        ui: &mut egui::Ui,
        name: &str,
        (key, list, i): (&str, &[T], usize),
        what: &str,
    ) {
        if Ed::remove_button(ui, name) {
            let v = list_value(list, |l| {
                l.remove(i);
            });
            self.submit(key, key, v, what);
        }
    }

    /// The rows of a form, in order (see [`FormRow`]).
    pub(super) fn rows(&mut self, ui: &mut egui::Ui, obj: &Value, rows: &[FormRow<'_>]) {
        for &(label, at, kind, optional) in rows {
            match at {
                At::Top(key) => self.field_row(ui, label, key, kind, obj, optional),
                At::In(section, key) => {
                    self.section_row(ui, label, (section, key), kind, obj, optional);
                }
            }
        }
    }

    /// Submits the named entries `n` after `change` (typed in `field`).
    pub(super) fn submit_named(
        &mut self,
        n: &Named<'_>,
        field: &str,
        change: &dyn Fn(&mut Map<String, Value>),
        what: &str,
    ) {
        let mut all = n.whole.as_object().cloned().unwrap_or_default();
        change(&mut all);
        self.submit(field, n.key, Value::Object(all), what);
    }

    /// The heading of entry `name` of `n`, with a button that removes it.
    pub(super) fn entry_heading(&mut self, ui: &mut egui::Ui, n: &Named<'_>, name: &str) {
        ui.horizontal_wrapped(|ui| {
            ui.label(RichText::new(name).monospace());
            if Ed::remove_button(ui, &format!("Remove {} {name}", n.noun)) {
                let what = format!("{} ({name} removed)", n.plural);
                let remove = |all: &mut Map<String, Value>| {
                    all.remove(name);
                };
                self.submit_named(n, n.key, &remove, &what);
            }
        });
    }

    /// The row `label` naming a new entry of `n`, added as `fresh`; then the
    /// errors of the entries.
    pub(super) fn new_entry_row(
        &mut self,
        ui: &mut egui::Ui,
        n: &Named<'_>,
        label: &str,
        fresh: &Value,
    ) {
        let field = format!("{}/new", n.key);
        if let Some(name) = self.new_name_row(ui, &field, label) {
            let what = format!("{} ({name} added)", n.plural);
            let add = |all: &mut Map<String, Value>| {
                all.insert(name.clone(), fresh.clone());
            };
            self.submit_named(n, &field, &add, &what);
        }
        self.error_ui(ui, &field);
        self.error_ui(ui, n.key);
    }

    /// A row `label` with an empty field that names something new: the name
    /// typed (trimmed, not empty) when the user finishes it.
    pub(super) fn new_name_row(
        &mut self,
        ui: &mut egui::Ui,
        field: &str,
        label: &str,
    ) -> Option<String> {
        ui.horizontal(|ui| {
            ui.label(label);
            let name = self.line(ui, field, label, "", FIELD_WIDTH / 1.5)?;
            let name = name.trim().to_string();
            (!name.is_empty()).then_some(name)
        })
        .inner
    }

    /// A combo box named `name` showing `shown`: the option chosen (see
    /// [`Pick`]).
    pub(super) fn pick(
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

    /// A picker named `label` that adds one of `options` to the list field
    /// `key`: the option chosen.
    pub(super) fn add_pick(
        &mut self,
        ui: &mut egui::Ui,
        key: &str,
        label: &str,
        options: &[String],
        how: Pick,
    ) -> Option<String> {
        self.pick(
            ui,
            &format!("{key}/add"),
            label,
            &format!("{label}…"),
            options,
            how,
        )
    }

    /// A small remove button named `name` (its hover text too).
    pub(super) fn remove_button(ui: &mut egui::Ui, name: &str) -> bool {
        ui.small_button("×")
            .accessible_name(name)
            .on_hover_text(name)
            .clicked()
    }
}

/// A list field of the activity after `change`, as a JSON value.
pub(super) fn list_value<T: serde::Serialize + Clone>(
    list: &[T],
    change: impl FnOnce(&mut Vec<T>),
) -> Value {
    let mut list = list.to_vec();
    change(&mut list);
    serde_json::to_value(list).unwrap_or(Value::Null)
}

/// Every name the plan's activities use in `names` (sorted, once each).
pub(super) fn used_names<'p>(
    plan: &'p Plan,
    names: impl Fn(&'p Activity) -> Vec<&'p String>,
) -> Vec<String> {
    let set: BTreeSet<&String> = plan.activities.iter().flat_map(names).collect();
    set.into_iter().cloned().collect()
}

/// A list of names with a remove button each and a picker to add one.
pub(super) fn name_list_ui(
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
            ed.remove_item(ui, &format!("Remove {what} {name}"), (key, names, i), key);
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
        if let Some(name) = ed.add_pick(ui, key, &label, &free, how) {
            let v = list_value(names, |l| l.push(name));
            ed.submit(key, key, v, key);
        }
    });
    ed.error_ui(ui, key);
}

/// A strong heading across a two-column grid.
pub(super) fn heading_row(ui: &mut egui::Ui, text: &str) {
    ui.label(RichText::new(text).strong());
    ui.end_row();
}
