//! Screenshot regression: key views rendered by software (wgpu on Mesa) and compared
//! with the reference PNGs in `screenshots/`. Update them with
//! `UPDATE_SNAPSHOTS=1 cargo test --test screenshots` and review the diff.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use egui_kittest::kittest::Queryable;
use serde_json::json;
use solscope::gui::SolscopeApp;
use solscope::gui::screenshot::{SNAPSHOT_SIZE, View, harness, snapshot_options};
use solscope::state::{Command, TimeAxis, UiCommand};

fn app() -> SolscopeApp {
    SolscopeApp::with_default_plan().expect("default plan")
}

/// The index of the activity `id` of the plan open in `h`.
fn activity(h: &egui_kittest::Harness<'_, SolscopeApp>, id: &str) -> usize {
    h.state()
        .doc
        .plan
        .activities
        .iter()
        .position(|x| x.id == id)
        .expect("activity")
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
fn peak_power_failure_draws_on_the_peak_plot() {
    check(
        "explain_peak_power",
        app(),
        View {
            select: Some("supercam_libs_413".into()),
            ..View::default()
        },
    );
}

#[test]
fn a_failure_on_two_limits_marks_both_and_draws_the_one_picked() {
    // X breaks the battery minimum for its early starts and the peak power
    // beside H for the later ones: the second reason drawn on the peak plot,
    // the first marked hollow on the state of charge.
    let plan = include_str!("plans/two-limits.json");
    let mut app = SolscopeApp::from_text(plan, None).expect("two-limits plan");
    app.apply(Command::ShowReason {
        activity: 1,
        index: 1,
    });
    check(
        "explain_two_reasons",
        app,
        View {
            select: Some("X".into()),
            ..View::default()
        },
    );
}

#[test]
fn energy_failure_in_the_light_theme() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/tutorial-plan.json"
    ))
    .unwrap();
    let mut app = SolscopeApp::from_text(&text, None).expect("tutorial plan");
    app.apply(Command::SetDark(false));
    check(
        "explain_light_theme",
        app,
        View {
            select: Some("libs_raster_low_battery".into()),
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

/// The uncertain-drive example with the minimum state of charge raised to 950 Wh,
/// in execution mode, executed with a drive 1,200 s longer than planned and a
/// sky survey 300 s longer: the drive breaks the minimum, post-drive imaging is
/// held back and never runs, contact science never fits, the survey is aborted.
fn long_drive() -> SolscopeApp {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/execution-examples/uncertain-drive.json"
    );
    let text = std::fs::read_to_string(path).expect("example plan");
    let mut app = SolscopeApp::from_text(&text, Some(path.into())).expect("example plan");
    let mut set = serde_json::Map::new();
    set.insert(
        "battery".into(),
        json!({"capacity": 1600.0, "initial": 1300.0, "min_soc": 950.0}),
    );
    app.apply(Command::Edit {
        target: "plan".into(),
        set,
        description: "Raise min_soc to 950 Wh".into(),
    });
    app.apply(Command::DismissBanner);
    // The file name is shown: a fixed name in a directory of this process.
    let dir = std::env::temp_dir().join(format!("solscope-shots-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let actuals = dir.join("long-drive.actuals.json");
    std::fs::write(
        &actuals,
        r#"{"format": "solscope.actuals/1", "durations": {"drive": 6600, "sky_survey": 1500}}"#,
    )
    .expect("actuals file");
    app.apply(UiCommand::ShowExecution.into());
    app.apply(Command::OpenActuals(actuals));
    assert!(
        app.ui.messages.error.is_none(),
        "{:?}",
        app.ui.messages.error
    );
    app
}

#[test]
fn execution_with_a_long_drive() {
    let mut app = long_drive();
    // Cycle 3, whose dispatcher held post-drive imaging back for the drive.
    app.apply(Command::SetCycle(3));
    check(
        "execution_long_drive",
        app,
        View {
            select: Some("post_drive_imaging".into()),
            ..View::default()
        },
    );
}

#[test]
fn execution_step_inside_the_first_cycle() {
    let mut app = long_drive();
    app.apply(Command::SetCycle(0));
    // Contact science's own step in the first cycle's run, where it fails.
    app.apply(Command::SetCycleStep(3));
    check(
        "execution_cycle_step",
        app,
        View {
            select: Some("arm_science".into()),
            ..View::default()
        },
    );
}

#[test]
fn execution_of_the_default_plan() {
    let mut app = app();
    app.apply(UiCommand::ShowExecution.into());
    app.apply(Command::SetCycle(20));
    check(
        "execution_default_plan",
        app,
        View {
            probe: Some(150_000),
            ..View::default()
        },
    );
}

/// The default plan's Monte Carlo campaign (200 runs, seed 1) with the
/// post-drive Mastcam-Z stereo of sol 413 selected (lost in about a third of
/// the runs, to three causes), executed with the first run that lost it.
#[test]
fn monte_carlo_of_the_default_plan() {
    let mut app = app();
    app.apply(UiCommand::ShowExecution.into());
    app.apply(Command::RunCampaign { runs: 200, seed: 1 });
    let a = app
        .doc
        .plan
        .activities
        .iter()
        .position(|x| x.id == "zcam_postdrive_413")
        .expect("activity");
    let result = app.campaign_result().expect("summarised");
    let lost = result.activity(a).and_then(|s| s.lost.as_ref());
    let cause = &lost.expect("lost in some runs").causes[0].cause;
    let run = result.lost_runs(a, cause)[0];
    app.apply(Command::SampleActuals { seed: 1, run });
    check(
        "monte_carlo",
        app,
        View {
            select: Some("zcam_postdrive_413".into()),
            ..View::default()
        },
    );
}

/// The sol-412 arm campaign zoomed in, with the flexibility layer: whiskers,
/// free slack in two tones, and the WATSON pre-abrasion image selected with its
/// dispatchable neighbours outlined and its Flexibility section.
#[test]
fn flexibility_of_the_arm_campaign() {
    let mut app = app();
    app.apply(Command::SetAxis(TimeAxis::new(52_000.0, 72_000.0)));
    check(
        "flex_arm_412",
        app,
        View {
            select: Some("watson_pre_abrasion".into()),
            ..View::default()
        },
    );
}

/// PIXL's bar dragged 40 minutes later (inside its bounds, outside its free
/// slack): the ghost and the label saying so, nothing rescheduled.
#[test]
fn dragging_a_bar_previews_the_shift() {
    let mut app = app();
    app.apply(Command::SetAxis(TimeAxis::new(52_000.0, 72_000.0)));
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).expect("harness");
    let a = activity(&h, "pixl_abrasion");
    let r = h.state().gantt_bar(a).expect("drawn");
    let (s, e) = h.state().analysis.placement(a).expect("placed");
    let dx = 2400.0 * r.width() / (e - s) as f32;
    let from = r.center();
    h.hover_at(from);
    h.run_steps(1);
    h.drag_at(from);
    h.run_steps(1);
    h.hover_at(from + eframe::egui::vec2(dx / 2.0, 0.0));
    h.run_steps(1);
    h.hover_at(from + eframe::egui::vec2(dx, 0.0));
    h.run_steps(3);
    h.snapshot_options("flex_drag_preview", &snapshot_options());
}

/// The tooltip of a Gantt bar at the pointer: name, status, sol time,
/// duration and what it holds (the default plan's noon MEDA run on sol 412).
#[test]
fn a_gantt_bar_s_tooltip() {
    let mut app = app();
    app.apply(Command::SetAxis(TimeAxis::new(55_000.0, 72_000.0)));
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).expect("harness");
    let a = activity(&h, "meda_412_1200");
    let r = h.state().gantt_bar(a).expect("drawn");
    h.hover_at(r.center());
    // Tooltips show once the pointer rests (egui's tooltip delay).
    h.run_steps(60);
    h.snapshot_options("gantt_tooltip", &snapshot_options());
}

/// The structured editor of drill_core_413, scrolled to its windows, with a
/// window end before its start typed in: the reason in red under the
/// fields, nothing applied.
#[test]
fn structured_editor_with_a_bad_window() {
    use egui_kittest::kittest::Queryable;
    let view = View {
        select: Some("drill_core_413".into()),
        ..View::default()
    };
    let mut h = harness(app(), SNAPSHOT_SIZE.into(), &view).expect("harness");
    h.get_by_label("Window 1 end").scroll_to_me();
    h.run_steps(30);
    h.get_by_label("Window 1 end").focus();
    h.run_steps(2);
    h.key_press_modifiers(eframe::egui::Modifiers::COMMAND, eframe::egui::Key::A);
    h.get_by_label("Window 1 end").type_text("Sol 413 09:00");
    h.key_press(eframe::egui::Key::Enter);
    h.run_steps(4);
    h.get_by_label("Window 1 start").scroll_to_me();
    h.run_steps(30);
    h.snapshot_options("editor_structured", &snapshot_options());
}

/// The default plan's file broken in four places, opened: the repair view
/// lists every error and shows the third at its place in the text.
#[test]
fn repair_view_of_a_broken_plan() {
    use egui_kittest::kittest::Queryable;
    let mut v: serde_json::Value =
        serde_json::from_str(solscope::state::DEFAULT_PLAN).expect("default plan");
    v["battery"]["initial"] = json!(2600.0);
    v["activities"][0]["windows"] = json!([{ "start": 5000, "end": 4000 }]);
    v["activities"][1]["energy_rate"] = json!(-3.0);
    v["activities"][2]["after"] = json!([{ "activity": "nobody" }]);
    let dir = std::env::temp_dir().join(format!("solscope-shots-repair-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("sols-412-413.json");
    std::fs::write(&path, serde_json::to_string_pretty(&v).expect("json")).expect("file");
    let mut app = app();
    app.apply(Command::Open(path));
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).expect("harness");
    h.get_by_label("activities[1].energy_rate").click();
    h.run_steps(30);
    h.snapshot_options("repair_view", &snapshot_options());
}

/// Sol 412 searched for "meda": the MEDA weather runs outlined on the Gantt,
/// everything else faded, the list showing the matches with the noon run
/// selected.
#[test]
fn a_search_highlights_its_matches_on_the_gantt() {
    let mut app = app();
    app.apply(Command::SetAxis(TimeAxis::new(
        23_975.0,
        23_975.0 + 88_775.0,
    )));
    app.apply(Command::SetFilter("meda".into()));
    check(
        "gantt_search",
        app,
        View {
            select: Some("meda_412_1200".into()),
            ..View::default()
        },
    );
}

#[test]
fn the_screenshot_command_is_quiet_without_xdg_runtime_dir() {
    let out = std::env::temp_dir().join(format!("solscope-quiet-{}.png", std::process::id()));
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_solscope"))
        .args(["screenshot", "assets/examples/pitfall.json", "--out"])
        .arg(&out)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env_remove("XDG_RUNTIME_DIR")
        .output()
        .expect("runs");
    assert!(run.status.success(), "{run:?}");
    assert_eq!(
        String::from_utf8_lossy(&run.stderr),
        "",
        "nothing on stderr"
    );
    assert!(out.exists(), "the PNG is written");
    std::fs::remove_file(&out).expect("clean up");
    // A bad argument still says what is wrong, once, with its exit status.
    let bad = std::process::Command::new(env!("CARGO_BIN_EXE_solscope"))
        .args([
            "screenshot",
            "assets/examples/pitfall.json",
            "--size",
            "5x5",
            "--out",
        ])
        .arg(&out)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env_remove("XDG_RUNTIME_DIR")
        .output()
        .expect("runs");
    assert_eq!(bad.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&bad.stderr)
            .matches("error:")
            .count(),
        1
    );
}

#[test]
fn guided_tour_on_why_the_tutorials_failure_did_not_fit() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/tutorial-plan.json"
    ))
    .unwrap();
    let mut app = SolscopeApp::from_text(&text, None).expect("tutorial plan");
    app.apply(Command::Ui(UiCommand::GuidedTour));
    app.apply(Command::TourPage(2));
    check("tour_why", app, View::default());
}

/// A generated plan of 1,000 activities (standard profile, seed 1) at its
/// last step: the packed lanes, the failed activities folded into one row,
/// the flexibility layer inside the lanes.
#[test]
fn a_thousand_generated_activities_at_the_last_step() {
    let plan = solscope_engine::generate_plan(1000, 3, 1);
    let text = serde_json::to_string(&plan).unwrap();
    let app = SolscopeApp::from_text(&text, None).expect("generated plan");
    check("generated_1000_last_step", app, View::default());
}

/// Execution mode after the 200-run campaign with the activity lost most
/// often (the first in the inspector's list) selected: the inspector beside
/// the Gantt and plots, never under them.
#[test]
fn execution_with_a_lost_activity_selected() {
    let mut app = app();
    app.apply(UiCommand::ShowExecution.into());
    app.apply(Command::RunCampaign { runs: 200, seed: 1 });
    check(
        "execution_lost_activity",
        app,
        View {
            select: Some("zcam_mosaic_small_413".into()),
            ..View::default()
        },
    );
}

/// The peak-power plot hovered well above its curve: the readout is the
/// profile's value at the time under the pointer.
#[test]
fn hover_readout_on_the_peak_plot() {
    let mut h = harness(app(), SNAPSHOT_SIZE.into(), &View::default()).expect("harness");
    let top = h.get_by_label("Peak power (W)").rect();
    h.hover_at(eframe::egui::pos2(
        top.center().x + 100.0,
        top.bottom() + 12.0,
    ));
    h.run_steps(3);
    h.snapshot_options("peak_hover_readout", &snapshot_options());
}

#[test]
fn the_tuning_panel_with_a_result_and_the_tuned_schedule_on_the_gantt() {
    let text = include_str!("../assets/tuning-examples/order-matters.json");
    let mut app = SolscopeApp::from_text(text, None).expect("tuning example");
    // A small search (the example has few orders): fast and the same every run.
    app.apply(Command::RunTune(solscope::state::tune::TuneSettings {
        runs: 8,
        confirm_runs: 12,
        budget: 40,
        ..Default::default()
    }));
    app.apply(Command::Ui(UiCommand::ToggleTuneOverlay));
    assert!(app.tune_result().is_some(), "tuned in place");
    check("tune_order_matters", app, View::default());
}
