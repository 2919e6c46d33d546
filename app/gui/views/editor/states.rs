//! An activity's state requirements and state effects: one list editor
//! serves both (a row each: the state and its value picked from the plan's,
//! an effect's start or end, a remove button; a picker that adds a row),
//! told what differs by [`StateLink`].

use eframe::egui::{self, RichText};
use serde::Serialize;
use solscope_engine::{Activity, EffectAt, Plan, StateEffect, StateRequirement};

use super::kit::{Ed, Pick, list_value};
use crate::gui::theme::COMBO_WIDTH;

/// A row of an activity's state list: what differs between a requirement
/// and an effect.
trait StateLink: Clone + Serialize {
    /// The activity's field holding the list.
    const KEY: &'static str;
    /// The list's heading.
    const HEADING: &'static str;
    /// A row, as its widgets' names start (`Requirement 2 state`; in lower
    /// case inside a name, `Remove requirement 2`).
    const TITLE: &'static str;
    /// Between the state and its value.
    const BETWEEN: &'static str;

    /// The state it names and the value.
    fn link(&self) -> (&str, &str);
    /// It, naming `state` and `value` instead.
    fn with(&self, state: String, value: String) -> Self;
    /// A new row naming `state`, its plan's `initial` value and `values`.
    fn new(state: String, initial: String, values: Vec<String>) -> Self;

    /// The widgets after the value (`n`: the row's number), and the row as
    /// changed there.
    fn more_ui(&self, _ed: &mut Ed<'_, '_>, _ui: &mut egui::Ui, _n: usize) -> Option<Self> {
        None
    }
}

impl StateLink for StateRequirement {
    const KEY: &'static str = "requires";
    const HEADING: &'static str = "Requires (state holds over the whole activity)";
    const TITLE: &'static str = "Requirement";
    const BETWEEN: &'static str = "=";

    fn link(&self) -> (&str, &str) {
        (&self.state, &self.value)
    }

    fn with(&self, state: String, value: String) -> Self {
        Self { state, value }
    }

    fn new(state: String, initial: String, _values: Vec<String>) -> Self {
        Self {
            state,
            value: initial,
        }
    }
}

/// When an effect applies, as its picker reads.
const ATS: [&str; 2] = ["at start", "at end"];

impl StateLink for StateEffect {
    const KEY: &'static str = "effects";
    const HEADING: &'static str = "Effects (state set at its start or end)";
    const TITLE: &'static str = "Effect";
    const BETWEEN: &'static str = "→";

    /// The first value other than the initial one: an effect that changes
    /// something.
    fn new(state: String, initial: String, values: Vec<String>) -> Self {
        let value = values
            .into_iter()
            .find(|v| *v != initial)
            .unwrap_or(initial);
        Self {
            state,
            value,
            at: EffectAt::End,
        }
    }

    /// Its start or end.
    fn more_ui(&self, ed: &mut Ed<'_, '_>, ui: &mut egui::Ui, n: usize) -> Option<Self> {
        let ats = ATS.map(String::from);
        let shown = &ats[usize::from(self.at == EffectAt::End)];
        let j = n - 1;
        let name = format!("Effect {n} when");
        let x = ed.pick(
            ui,
            &format!("effects[{j}].at"),
            &name,
            shown,
            &ats,
            Pick::List,
        )?;
        let at = if x == ats[0] {
            EffectAt::Start
        } else {
            EffectAt::End
        };
        Some(Self { at, ..self.clone() })
    }

    fn link(&self) -> (&str, &str) {
        (&self.state, &self.value)
    }

    /// It at the same point of the activity.
    fn with(&self, state: String, value: String) -> Self {
        Self {
            state,
            value,
            at: self.at,
        }
    }
}

/// State requirements and effects, states and values picked from the plan's.
pub(super) fn states_ui(ui: &mut egui::Ui, ed: &mut Ed<'_, '_>, plan: &Plan, act: &Activity) {
    state_list_ui(ui, ed, plan, &act.requires);
    state_list_ui(ui, ed, plan, &act.effects);
}

/// The list `rows` of the activity (requirements or effects): a row each,
/// then the picker that adds one.
fn state_list_ui<T: StateLink>(ui: &mut egui::Ui, ed: &mut Ed<'_, '_>, plan: &Plan, rows: &[T]) {
    let states: Vec<String> = plan.states.keys().cloned().collect();
    let values = |state: &str| -> Vec<String> {
        plan.states
            .get(state)
            .map(|d| d.values.clone())
            .unwrap_or_default()
    };
    let initial = |state: &str| plan.states.get(state).map(|d| d.initial.clone());
    let key = T::KEY;
    ui.label(RichText::new(T::HEADING).strong());
    let noun = T::TITLE.to_lowercase();
    for (j, r) in rows.iter().enumerate() {
        let (state, value) = r.link();
        ui.horizontal_wrapped(|ui| {
            ui.spacing_mut().combo_width = COMBO_WIDTH;
            let n = j + 1;
            // This row's `part` picked from `options`, and the row set.
            let pick = |ed: &mut Ed<'_, '_>,
                        ui: &mut egui::Ui,
                        (part, shown): (&str, &str),
                        options: &[String]| {
                let name = format!("{} {n} {part}", T::TITLE);
                let field = format!("{key}[{j}].{part}");
                ed.pick(ui, &field, &name, shown, options, Pick::List)
            };
            let set = |ed: &mut Ed<'_, '_>, row: T| {
                let v = list_value(rows, |l| l[j] = row);
                ed.submit(key, key, v, key);
            };
            if let Some(s) = pick(ed, ui, ("state", state), &states)
                && s != state
            {
                let v = initial(&s).unwrap_or_default();
                set(ed, r.with(s, v));
            }
            ui.label(T::BETWEEN);
            if let Some(x) = pick(ed, ui, ("value", value), &values(state)) {
                set(ed, r.with(state.to_string(), x));
            }
            if let Some(changed) = r.more_ui(ed, ui, n) {
                set(ed, changed);
            }
            let name = format!("Remove {noun} {n}");
            ed.remove_item(ui, &name, (key, rows, j), key);
        });
    }
    let add = format!("Add {noun}");
    if let Some(s) = ed.add_pick(ui, key, &add, &states, Pick::List) {
        let row = T::new(s.clone(), initial(&s).unwrap_or_default(), values(&s));
        let v = list_value(rows, |l| l.push(row));
        ed.submit(key, key, v, key);
    }
    ed.error_ui(ui, key);
}
