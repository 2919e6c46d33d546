//! The structured editor in the inspector: every field of the selected
//! activity (`activity`, with its state requirements and effects in
//! `states`) and of the plan-wide limits (`plan`) as a widget of its kind
//! (times in sol and local time, numbers with their units, checkboxes, names
//! picked from what the plan has), each committing one edit when the user
//! finishes it (Enter, Tab or focus lost; Escape puts the value back). An
//! edit is checked with `apply_edit` first: a bad one stays in its field, in
//! red with the reason, and is never applied. An edit that changes nothing
//! is not recorded (the app says so). Both forms draw with one widget kit
//! (`kit`).

mod activity;
mod kit;
mod plan;
mod states;

pub(super) use activity::activity_fields_ui;
pub(super) use plan::plan_fields_ui;
