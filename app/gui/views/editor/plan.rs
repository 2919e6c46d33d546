//! The plan-limits form: battery, power, sleep, data and engines, handover,
//! horizon and clock, the plan's states and its thermal zones, each field
//! committing one edit of the plan.

use eframe::egui::{self, RichText};
use serde_json::{Map, Value, json};
use solscope_engine::{Plan, ThermalZone};

use super::kit::At::{In, Top};
use super::kit::{Ed, FormRow, Kind, Named, Pick, heading_row};
use crate::gui::theme::{FIELD_WIDTH, NUMBER_FIELD_WIDTH};
use crate::gui::views::Model;
use crate::state::Command;
use crate::state::TextBuffers;

/// The structured editor of the plan-wide fields: limits, horizon and clock,
/// states and thermal zones.
pub(in crate::gui::views) fn plan_fields_ui(
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
    egui::Grid::new("plan_fields")
        .num_columns(2)
        .show(ui, |ui| {
            for (heading, rows) in [
                ("Battery", BATTERY),
                ("Power", POWER),
                ("Sleep", SLEEP),
                ("Data and engines", DATA),
            ] {
                heading_row(ui, heading);
                ed.rows(ui, &obj, rows);
            }
            handover_rows(ui, &mut ed, plan, &obj);
            heading_row(ui, "Horizon and clock");
            ed.rows(ui, &obj, CLOCK);
        });
    ui.separator();
    plan_states_ui(ui, &mut ed, plan);
    ui.separator();
    zones_ui(ui, &mut ed, plan);
}

/// Energy, power and data volume, in their units.
const WH: Kind = Kind::Number("Wh");
const W: Kind = Kind::Number("W");
const MBIT: Kind = Kind::Number("Mbit");

/// The battery's capacity, initial charge and minimum.
const BATTERY: &[FormRow<'static>] = &[
    ("Capacity", In("battery", "capacity"), WH, false),
    ("Initial charge", In("battery", "initial"), WH, false),
    ("Minimum charge", In("battery", "min_soc"), WH, false),
];

/// The RTG, the draws asleep and awake, and the peak power limit.
const POWER: &[FormRow<'static>] = &[
    ("RTG output", In("power", "rtg"), W, false),
    ("Draw asleep", In("power", "asleep"), W, false),
    ("Draw awake", In("power", "awake"), W, false),
    ("Peak power limit", In("power", "max_peak"), W, true),
];

/// Waking up and shutting down, and the shortest awake and sleep periods.
const SLEEP: &[FormRow<'static>] = &[
    (
        "Wakeup",
        In("sleep", "wakeup_duration"),
        Kind::Seconds,
        false,
    ),
    (
        "Shutdown",
        In("sleep", "shutdown_duration"),
        Kind::Seconds,
        false,
    ),
    (
        "Shortest awake",
        In("sleep", "min_awake"),
        Kind::Seconds,
        false,
    ),
    (
        "Shortest sleep",
        In("sleep", "min_sleep"),
        Kind::Seconds,
        false,
    ),
];

/// Data storage and the sequence engines.
const DATA: &[FormRow<'static>] = &[
    ("Storage capacity", In("data", "capacity"), MBIT, true),
    ("Initial data", In("data", "initial"), MBIT, false),
    ("Sequence engines", Top("sequence_engines"), Kind::Int, true),
];

/// The handover's time and limits, when it has them.
const HANDOVER: &[FormRow<'static>] = &[
    ("Handover time", In("handover", "time"), Kind::Time, false),
    ("Handover charge", In("handover", "min_soc"), WH, true),
    (
        "Data produced by then",
        In("handover", "max_data_volume"),
        MBIT,
        true,
    ),
];

/// The horizon and the clock.
const CLOCK: &[FormRow<'static>] = &[
    ("Plan start", In("horizon", "start"), Kind::Time, false),
    ("Plan end", In("horizon", "end"), Kind::Time, false),
    (
        "Sol length",
        In("local_time", "sol_length"),
        Kind::Seconds,
        false,
    ),
    (
        "Local time at t=0",
        In("local_time", "offset"),
        Kind::Seconds,
        false,
    ),
    ("Sol at t=0", In("local_time", "first_sol"), Kind::Int, true),
];

/// The handover limits: on or off, and when on their time and limits.
fn handover_rows(ui: &mut egui::Ui, ed: &mut Ed<'_, '_>, plan: &Plan, obj: &Value) {
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
        ed.rows(ui, obj, HANDOVER);
    }
}

/// The plan's states: values (comma-separated) and initial value; add one,
/// remove one.
fn plan_states_ui(ui: &mut egui::Ui, ed: &mut Ed<'_, '_>, plan: &Plan) {
    ui.label(RichText::new("States").strong());
    let states = serde_json::to_value(&plan.states).unwrap_or(Value::Null);
    let named = Named::new("states", &states, ("state", "states"));
    for (name, def) in &plan.states {
        // Sets `key` of this state's definition.
        let set_def =
            |ed: &mut Ed<'_, '_>, field: &str, (key, value): (&str, Value), what: &str| {
                let change = |all: &mut Map<String, Value>| {
                    if let Some(d) = all.get_mut(name) {
                        d[key] = value.clone();
                    }
                };
                ed.submit_named(&named, field, &change, what);
            };
        ed.entry_heading(ui, &named, name);
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
                    let what = format!("the values of state {name}");
                    set_def(ed, &field, ("values", json!(values)), &what);
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
                    let what = format!("the initial value of state {name}");
                    set_def(ed, &field, ("initial", json!(v)), &what);
                }
                ed.error_row(ui, &field);
            });
    }
    let fresh = json!({ "values": ["off", "on"], "initial": "off" });
    ed.new_entry_row(ui, &named, "New state", &fresh);
}

/// The plan's thermal zones: heater powers, preheat table and operable
/// periods (local times of day); add one, remove one.
fn zones_ui(ui: &mut egui::Ui, ed: &mut Ed<'_, '_>, plan: &Plan) {
    ui.label(RichText::new("Thermal zones").strong());
    let zones = serde_json::to_value(&plan.thermal_zones).unwrap_or(Value::Null);
    let named = Named::new("thermal_zones", &zones, ("zone", "thermal zones"));
    for (name, zone) in &plan.thermal_zones {
        let z = zones.get(name).cloned().unwrap_or(Value::Null);
        ed.entry_heading(ui, &named, name);
        let mut edit = zone_powers_ui(ui, ed, name, &z);
        for (table, cols) in [
            ("preheat", ["from", "duration"]),
            ("operable", ["from", "to"]),
        ] {
            if let Some(e) = zone_table_ui(ui, ed, (name, zone, &z), table, cols) {
                edit = Some(e);
            }
        }
        if let Some((field, change, what)) = edit {
            ed.submit_named(
                &named,
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
    let fresh = json!({
        "preheat": [{ "from": 0, "duration": 0 }],
        "preheat_power": 0.0,
        "maintenance_power": 0.0,
    });
    ed.new_entry_row(ui, &named, "New zone", &fresh);
}

/// The edit of a zone: the field it was typed in, the zone's fields it
/// replaces (a null removes one), and what it changes.
type ZoneEdit = (String, Value, String);

/// A zone's heater powers: the edit typed, if any.
fn zone_powers_ui(
    ui: &mut egui::Ui,
    ed: &mut Ed<'_, '_>,
    name: &str,
    z: &Value,
) -> Option<ZoneEdit> {
    let mut edit = None;
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
    edit
}

/// A zone's preheat table or operable periods (`table`, its columns
/// `cols`), a row each with a remove button, and the buttons that add a row
/// or drop the periods: the edit made, if any.
fn zone_table_ui(
    ui: &mut egui::Ui,
    ed: &mut Ed<'_, '_>,
    (name, zone, z): (&str, &ThermalZone, &Value),
    table: &str,
    cols: [&str; 2],
) -> Option<ZoneEdit> {
    let mut edit = None;
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
                if let Some(text) = ed.line(ui, &field, &a11y, &shown, NUMBER_FIELD_WIDTH / 1.2)
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
    edit
}
