//! The Gantt's rows: windows, cached rows, grouping by resource and the
//! rows of execution mode.

use eframe::egui;

use super::execution::execution_rows;
use super::layout::{Row, rows};
use crate::gui::theme::LANE_HEIGHT;
use crate::gui::views::Model;
use crate::state::Command;
use crate::state::window_spans;
// The tests drive the whole app (test code only: the views themselves never
// reach up into it).
use crate::gui::SolscopeApp;

#[test]
fn an_unplaced_activity_is_drawn_over_each_of_its_windows() {
    let plan = solscope_engine::load_plan(
        r#"{"format":"solscope.plan/1","horizon":{"start":0,"end":1000},
            "battery":{"capacity":100.0,"initial":100.0,"min_soc":0.0},
            "power":{"rtg":100.0,"asleep":10.0,"awake":20.0},
            "activities":[
              {"id":"two","priority":1,"duration":{"min":10,"max":50},
               "windows":[{"start":100,"end":200},{"start":900,"end":990}]},
              {"id":"none","priority":2,"duration":10}]}"#,
    )
    .expect("plan")
    .plan;
    // Start to end plus the longest duration, clipped to the horizon.
    assert_eq!(
        window_spans(&plan, &plan.activities[0]),
        [(100, 250), (900, 1000)]
    );
    assert_eq!(window_spans(&plan, &plan.activities[1]), [(0, 1000)]);
}

fn model(app: &SolscopeApp) -> Model<'_> {
    Model {
        doc: &app.doc,
        analysis: &app.analysis,
        theme: app.theme,
        step_view: &app.step_view,
        persisted: &app.persisted,
        suggestions: None,
        revision: app.revision,
        explanation: None,
        explanation_error: None,
        valid: None,
        would_cause: None,
        flex: None,
        free_slack: None,
        nav: &app.ui.nav,
        messages: &app.ui.messages,
        exec: crate::gui::views::ExecModel {
            source: &app.actuals,
            actuals_rev: 0,
            run: None,
            cycle: 0,
            cycle_run: None,
            step: 0,
            view: None,
            loss: None,
            campaign: crate::gui::views::CampaignModel::default(),
        },
        tune: Default::default(),
    }
}

/// `(row label, activity ids)` of the activity bars drawn after the last step
/// (a continuation lane carries its group's label; heating rows left out).
fn layout(app: &SolscopeApp) -> Vec<(String, Vec<String>)> {
    let m = model(app);
    let mut group = String::new();
    rows(&m, app.analysis.steps(), false)
        .into_iter()
        .map(|mut r| {
            if r.label.is_empty() {
                r.label = group.clone();
            } else {
                group = r.label.clone();
            }
            let ids = r
                .bars
                .iter()
                .filter_map(|b| b.activity)
                .map(|a| app.doc.plan.activities[a].id.clone())
                .collect();
            (r.label, ids)
        })
        .filter(|r| !r.0.starts_with("Heat: "))
        .collect()
}

/// `(label, bar count)` per row drawn after step `k` of rows kept between
/// frames (the bars drawn then).
fn shown_shape(kept: &super::GanttRows, k: usize) -> Vec<(String, usize)> {
    kept.shown(k)
        .into_iter()
        .map(|r| {
            (
                r.label.clone(),
                r.bars.iter().filter(|b| b.shown_at(k)).count(),
            )
        })
        .collect()
}

/// `(label, bar count)` per row.
fn shape(rows: &[Row]) -> Vec<(String, usize)> {
    rows.iter()
        .map(|r| (r.label.clone(), r.bars.len()))
        .collect()
}

#[test]
fn cached_rows_follow_the_step_the_plan_and_the_grouping() {
    let mut app = SolscopeApp::with_default_plan().expect("default plan");
    let ctx = egui::Context::default();
    let check = |app: &mut SolscopeApp| {
        let mut out = ctx.run_ui(egui::RawInput::default(), |ui| app.frame_ui(ui));
        out.textures_delta.clear();
        let cached = app.view_cache.gantt.clone().expect("rows kept");
        // The app's own model: with the flexible schedule.
        let (m, _) = app.model_and_widgets();
        assert!(m.flex_layer().is_some());
        assert_eq!(
            shown_shape(&cached, m.nav.step),
            shape(&rows(&m, m.nav.step, false))
        );
    };
    check(&mut app);
    for k in [0, 10, 35] {
        app.apply(Command::SetStep(k));
        check(&mut app);
    }
    app.apply(Command::GroupByResource(true));
    check(&mut app);
    app.apply(Command::GroupByResource(false));
    app.apply(crate::state::UiCommand::ToggleFlex.into());
    let mut out = ctx.run_ui(egui::RawInput::default(), |ui| app.frame_ui(ui));
    out.textures_delta.clear();
    let (m, _) = app.model_and_widgets();
    assert!(m.flex_layer().is_none(), "hidden");
    let plain = shape(&rows(&m, m.nav.step, false));
    let step = m.nav.step;
    assert_eq!(
        shown_shape(&app.view_cache.gantt.clone().expect("kept"), step),
        plain
    );
    app.apply(crate::state::UiCommand::ToggleFlex.into());
    check(&mut app);
    let mut set = serde_json::Map::new();
    set.insert("mandatory".into(), serde_json::json!(false));
    let id = app.doc.plan.activities[0].id.clone();
    app.apply(Command::Edit {
        target: format!("activity:{id}"),
        set,
        description: "test".into(),
    });
    check(&mut app);
}

#[test]
fn grouping_by_resource_gives_one_row_per_resource() {
    let mut app = SolscopeApp::with_default_plan().expect("default plan");
    let packed = layout(&app);
    assert!(packed.iter().any(|r| r.0 == "Scheduled"));
    assert!(!packed.iter().any(|r| r.0.starts_with("Resource: ")));
    app.apply(Command::GroupByResource(true));
    let grouped = layout(&app);
    assert!(!grouped.iter().any(|r| r.0 == "Scheduled"));
    let plan = &app.doc.plan;
    for (a, act) in plan.activities.iter().enumerate() {
        if app.analysis.placement(a).is_none() || act.comm_kind.is_some() {
            continue;
        }
        // Each scheduled activity appears in the row of every resource it holds,
        // or among those holding none.
        let rows_with: Vec<&str> = grouped
            .iter()
            .filter(|r| r.1.contains(&act.id))
            .map(|r| r.0.as_str())
            .collect();
        if act.resources.is_empty() {
            assert_eq!(rows_with, vec!["No resource"], "{}", act.id);
        } else {
            let want: Vec<String> = act
                .resources
                .iter()
                .map(|r| format!("Resource: {r}"))
                .collect();
            assert_eq!(rows_with.len(), want.len(), "{}: {rows_with:?}", act.id);
            assert!(rows_with.iter().all(|r| want.iter().any(|w| w == r)));
        }
    }
    // A unit resource is held by one activity at a time: one row each.
    let labels: Vec<&str> = grouped
        .iter()
        .map(|r| r.0.as_str())
        .filter(|l| l.starts_with("Resource: "))
        .collect();
    let mut unique = labels.clone();
    unique.dedup();
    assert_eq!(labels, unique, "a resource needed a second lane");
    assert!(labels.len() >= 3);
}

/// The app in execution mode after one frame (the execution derived in it).
fn executed(mut app: SolscopeApp) -> SolscopeApp {
    app.apply(crate::state::UiCommand::ShowExecution.into());
    let ctx = egui::Context::default();
    let mut out = ctx.run_ui(egui::RawInput::default(), |ui| app.frame_ui(ui));
    out.textures_delta.clear();
    app
}

#[test]
fn execution_rows_show_every_activity_once_with_its_prediction() {
    let mut app = executed(SolscopeApp::with_default_plan().expect("default plan"));
    let run = app.execution_run().expect("executed");
    let n = app.doc.plan.activities.len();
    let cycles = run.execution.cycles.len();
    let runs = run.execution.activities.clone();
    let (m, _) = app.model_and_widgets();
    let run = m.exec.ready().expect("executed");
    let rows = execution_rows(&m, run);
    assert_eq!(rows[0].label, "Cycles");
    assert_eq!(rows[0].bars.len(), cycles);
    assert!(rows[0].bars.iter().all(|b| b.marker && b.cycle.is_some()));
    // Each activity once: an executed (or not run) bar with its prediction
    // below, or among those never placed.
    let mut main = vec![0; n];
    let mut predicted = vec![0; n];
    let mut never = vec![0; n];
    let mut group = String::new();
    for r in &rows {
        if !r.label.is_empty() {
            group = r.label.clone();
        }
        for b in &r.bars {
            let Some(a) = b.activity else { continue };
            match group.as_str() {
                "Executed" if r.height < LANE_HEIGHT => predicted[a] += 1,
                "Executed" => main[a] += 1,
                "Never placed" => never[a] += 1,
                _ => {}
            }
        }
    }
    for (a, r) in runs.iter().enumerate() {
        let placed = usize::from(r.predicted.is_some());
        assert_eq!(predicted[a], placed, "activity {a}");
        assert_eq!(main[a], placed, "activity {a}");
        assert_eq!(never[a], 1 - placed, "activity {a}");
    }
    assert!(
        never.iter().sum::<usize>() > 0,
        "the default plan has failures"
    );
    // The looked-at cycle's run follows.
    assert!(rows.iter().any(|r| r.label == "Cycle 0: placed"));
}

#[test]
fn cached_execution_rows_follow_the_cycle_and_its_step() {
    let mut app = executed(SolscopeApp::with_default_plan().expect("default plan"));
    let ctx = egui::Context::default();
    let check = |app: &mut SolscopeApp| {
        let mut out = ctx.run_ui(egui::RawInput::default(), |ui| app.frame_ui(ui));
        out.textures_delta.clear();
        let cached = app.view_cache.gantt.clone().expect("rows kept");
        let (m, _) = app.model_and_widgets();
        let fresh = execution_rows(&m, m.exec.ready().expect("executed"));
        assert_eq!(shape(&cached.rows), shape(&fresh));
    };
    check(&mut app);
    for (cycle, step) in [(3, 10), (3, 0), (20, 40), (0, 70)] {
        app.apply(Command::SetCycle(cycle));
        app.apply(Command::SetCycleStep(step));
        check(&mut app);
    }
}
