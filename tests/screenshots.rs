//! Screenshot regression: key views rendered by software (wgpu on Mesa) and compared
//! with the reference PNGs in `screenshots/`. Update them with
//! `UPDATE_SNAPSHOTS=1 cargo test --test screenshots` and review the diff.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use serde_json::json;
use solscope::gui::{Command, SolscopeApp};
use solscope::screenshot::{SNAPSHOT_SIZE, View, harness, snapshot_options};

fn app() -> SolscopeApp {
    SolscopeApp::with_default_plan().expect("default plan")
}

fn check(name: &str, app: SolscopeApp, view: View) {
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &view).expect("harness");
    h.snapshot_options(name, &snapshot_options());
}

#[test]
fn overview_at_a_middle_step() {
    check(
        "overview_step_35",
        app(),
        View {
            step: Some(35),
            ..View::default()
        },
    );
}

#[test]
fn failed_activity_explanation() {
    check(
        "explain_moxie",
        app(),
        View {
            select: Some("moxie_run_413".into()),
            ..View::default()
        },
    );
}

#[test]
fn clicked_energy_plot_lists_consumers() {
    check(
        "energy_probe",
        app(),
        View {
            probe: Some(150_000),
            ..View::default()
        },
    );
}

#[test]
fn editor_after_an_edit() {
    let mut app = app();
    let mut set = serde_json::Map::new();
    set.insert("windows".into(), json!([{ "start": 79480, "end": 80980 }]));
    app.apply(Command::Edit {
        target: "activity:rimfax_stationary_412".into(),
        set,
        description: "Widen the RIMFAX window".into(),
    });
    check(
        "editor_after_edit",
        app,
        View {
            select: Some("rimfax_stationary_412".into()),
            ..View::default()
        },
    );
}

#[test]
fn gantt_grouped_by_resource() {
    let mut app = app();
    app.apply(Command::GroupByResource(true));
    check(
        "overview_by_resource",
        app,
        View {
            step: Some(35),
            ..View::default()
        },
    );
}
