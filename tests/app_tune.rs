//! The "Tune priorities" panel through the real UI, by accessibility labels
//! (egui_kittest): a search run to its end, Cancel keeping the best order
//! found so far, Apply as one undoable edit of the priorities, and the
//! inspector's `value` field.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod support;

use egui_kittest::kittest::Queryable;
use solscope::gui::SolscopeApp;
use solscope::gui::screenshot::{SNAPSHOT_SIZE, View, harness};
use solscope::state::{Command, UiCommand};
use support::index;

type H = egui_kittest::Harness<'static, SolscopeApp>;

/// The tuning example: with the planners' priorities the SuperCam target
/// never runs, and the less valuable of two images takes the place left
/// after a long drive.
fn order_matters() -> SolscopeApp {
    let text = include_str!("../assets/tuning-examples/order-matters.json");
    SolscopeApp::from_text(text, None).expect("example plan")
}

fn priorities(app: &SolscopeApp) -> Vec<i64> {
    app.doc.plan.activities.iter().map(|a| a.priority).collect()
}

/// Types `text` into the field labelled `label` (replacing what it holds).
fn type_into(h: &mut H, label: &str, text: &str) {
    h.get_by_label(label).focus();
    h.run_steps(2);
    h.key_press_modifiers(eframe::egui::Modifiers::COMMAND, eframe::egui::Key::A);
    h.get_by_label(label).type_text(text);
    h.run_steps(2);
}

/// Clicks the widget labelled `label`, scrolled into view first.
fn click(h: &mut H, label: &str) {
    h.get_by_label(label).scroll_to_me();
    h.run_steps(30);
    h.get_by_label(label).click();
    h.run_steps(3);
}

/// Runs frames until `done` holds (the workers are real threads).
fn wait_until(h: &mut H, what: &str, done: impl Fn(&SolscopeApp) -> bool) {
    for _ in 0..6000 {
        if done(h.state()) {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
        h.run_steps(1);
    }
    panic!("{what} never happened");
}

/// The tuning example with the panel opened by its toolbar button and a
/// small, quick search typed in.
fn panel_with_small_settings(app: SolscopeApp) -> H {
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    assert!(h.query_by_label("Tuning runs").is_none(), "closed at first");
    h.get_by_label("File").click();
    h.run_steps(2);
    h.get_by_label("Tune priorities").click();
    h.run_steps(3);
    // The command line's defaults.
    for (label, default) in [
        ("Tuning runs", "20"),
        ("Tuning seed", "1"),
        ("Held-out runs", "40"),
        ("Held-out seed", "2"),
        ("Budget", "60"),
    ] {
        assert_eq!(
            h.get_by_label(label).value().as_deref(),
            Some(default),
            "{label}"
        );
    }
    type_into(&mut h, "Tuning runs", "8");
    type_into(&mut h, "Held-out runs", "12");
    type_into(&mut h, "Budget", "40");
    h
}

#[test]
fn a_search_runs_to_its_end_and_shows_what_changed_and_why() {
    let mut h = panel_with_small_settings(order_matters());
    h.get_by_label("Tune").click();
    h.run_steps(3);
    let r = h.state().tune_result().expect("tuned in the frame").clone();
    assert_eq!((r.settings.runs, r.settings.confirm_runs), (8, 12));
    assert_eq!(r.settings.budget, 40);
    assert!(!r.stopped_early());
    assert!(h.query_by_label_contains("Stopped early").is_none());
    assert!(!r.tuning.changes.is_empty(), "the example's order matters");
    // Each change with its reason, as the engine words it.
    for (c, why) in r.tuning.changes.iter().zip(&r.reasons) {
        let id = &h.state().doc.plan.activities[c.activity].id;
        let head = format!("{id}: priority {} → {}", c.before, c.after);
        assert!(h.query_by_label(&head).is_some(), "{head}");
        assert!(h.query_by_label(why).is_some(), "{why}");
    }
    // The objective on the held-out sample, and the verdict.
    assert!(h.query_by_label("Held-out, 12 runs (seed 2):").is_some());
    let t = &r.tuning;
    let original = solscope_engine::score_line(&t.held_out_scores.original, 12);
    let tuned = solscope_engine::score_line(&t.held_out_scores.tuned, 12);
    assert!(h.query_by_label(&original).is_some(), "{original}");
    assert!(h.query_by_label(&tuned).is_some(), "{tuned}");
    assert!(t.held_out_no_worse());
    assert!(
        h.query_by_label("The tuned order is no worse than the original on the held-out sample.")
            .is_some()
    );
    // SuperCam never ran with the planners' order; it does once tuned.
    let supercam = index(h.state(), "supercam_target");
    let c = t.counts[supercam];
    assert_eq!(c.held_out_before.completed, 0);
    assert_eq!(c.held_out_after.completed, 12);
    let bars = "supercam_target: completed 0% → 100% of 12 held-out runs";
    assert!(h.query_by_label(bars).is_some());
    // Clicking an activity selects it.
    assert_eq!(h.state().ui.nav.selected, None);
    // The change list's button (the Gantt also labels the failed row with the id).
    let link = h.get_by_role_and_label(eframe::egui::accesskit::Role::Button, "supercam_target");
    link.scroll_to_me();
    h.run_steps(30);
    h.get_by_role_and_label(eframe::egui::accesskit::Role::Button, "supercam_target")
        .click();
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.selected, Some(supercam));
    // The overlay of the tuned schedule toggles; Dismiss forgets the result.
    assert!(!h.state().tune_model().overlay);
    click(&mut h, "Tuned schedule on the Gantt");
    assert!(h.state().tune_model().overlay);
    click(&mut h, "Dismiss tuning");
    assert!(h.state().tune_result().is_none());
    assert!(!h.state().tune_model().overlay);
    assert!(h.query_by_label(bars).is_none());
}

#[test]
fn a_bad_setting_is_named_and_nothing_runs() {
    let mut h = panel_with_small_settings(order_matters());
    type_into(&mut h, "Held-out runs", "4");
    h.get_by_label("Tune").click();
    h.run_steps(3);
    assert!(h.state().tune_result().is_none());
    assert!(
        h.query_by_label(
            "Held-out runs: the held-out sample needs at least as many runs as the tuning \
             sample (got 4 < 8)"
        )
        .is_some()
    );
    type_into(&mut h, "Budget", "many");
    h.get_by_label("Tune").click();
    h.run_steps(3);
    assert_eq!(
        h.state().ui.messages.error.as_deref(),
        Some("Budget: enter a whole number from 0 to 18446744073709551615")
    );
}

#[test]
fn cancel_keeps_the_best_order_so_far_marked_stopped_early() {
    let mut app = SolscopeApp::with_default_plan().unwrap();
    app.background = true;
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    h.key_press_modifiers(eframe::egui::Modifiers::COMMAND, eframe::egui::Key::T);
    h.run_steps(3);
    assert!(h.state().tune_model().open, "Ctrl+T opens the panel");
    // A budget far beyond what the test waits for.
    type_into(&mut h, "Tuning runs", "2");
    type_into(&mut h, "Held-out runs", "2");
    type_into(&mut h, "Budget", "1000000");
    h.get_by_label("Tune").click();
    h.run_steps(2);
    let p = h.state().tune_running().expect("running off the frame");
    assert_eq!(p.budget, 1_000_000);
    assert!(
        h.query_by_label_contains("/ 1000000 orders scored")
            .is_some()
    );
    wait_until(&mut h, "the original order scored", |app| {
        app.tune_running().is_some_and(|p| p.best.is_some())
    });
    h.run_steps(1);
    assert!(
        h.query_by_label_contains("best so far on 2 runs:")
            .is_some()
    );
    h.get_by_label("Cancel tuning").hover();
    h.run_steps(2);
    h.get_by_label("Cancel tuning").click();
    h.run_steps(2);
    wait_until(&mut h, "the confirmed result", |app| {
        app.tune_running().is_none()
    });
    h.run_steps(2);
    let r = h
        .state()
        .tune_result()
        .expect("the best order so far is kept");
    assert!(r.stopped_early());
    assert_eq!(r.tuning.stop, solscope_engine::Stop::Cancelled);
    assert!(r.tuning.evaluations < 1_000_000);
    assert_eq!(r.tuning.held_out.runs, 2, "confirmed all the same");
    assert!(
        h.query_by_label_contains("Stopped early (cancelled)")
            .is_some()
    );
}

#[test]
fn an_edit_while_a_search_runs_stops_it() {
    let mut app = SolscopeApp::with_default_plan().unwrap();
    app.background = true;
    app.apply(UiCommand::TunePriorities.into());
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    type_into(&mut h, "Budget", "1000000");
    h.get_by_label("Tune").click();
    h.run_steps(2);
    assert!(h.state().tune_running().is_some());
    h.state_mut().apply(UiCommand::AddActivity.into());
    h.run_steps(3);
    assert!(h.state().tune_running().is_none());
    assert!(h.state().tune_result().is_none());
    assert!(
        h.query_by_label("The plan was edited while the search ran: it was stopped (tune again)")
            .is_some()
    );
}

#[test]
fn apply_changes_only_priorities_in_one_undoable_edit() {
    let mut h = panel_with_small_settings(order_matters());
    let before_plan = h.state().doc.plan.clone();
    let before = priorities(h.state());
    h.get_by_label("Tune").click();
    h.run_steps(3);
    let r = h.state().tune_result().expect("tuned").clone();
    click(&mut h, "Apply tuned priorities");
    assert_eq!(
        h.state().doc.plan,
        r.tuning.tuned_plan,
        "only priorities moved"
    );
    assert_ne!(priorities(h.state()), before);
    assert!(h.state().tune_result().is_none(), "applied: retired");
    // The banner names every move, and what the reschedule changed.
    let banner = h.state().ui.messages.banner.clone().expect("banner");
    for c in &r.tuning.changes {
        let id = &before_plan.activities[c.activity].id;
        let moved = format!("{id} {} → {}", c.before, c.after);
        assert!(
            banner.description.contains(&moved),
            "{}",
            banner.description
        );
    }
    assert!(
        banner
            .newly_scheduled
            .contains(&"supercam_target".to_string()),
        "{banner:?}"
    );
    // One undo restores every priority; redo gives them back.
    click(&mut h, "Undo");
    assert_eq!(h.state().doc.plan, before_plan);
    assert!(!h.state().doc.can_undo());
    click(&mut h, "Redo");
    assert_eq!(h.state().doc.plan, r.tuning.tuned_plan);
}

#[test]
fn the_value_field_edits_round_trip_through_save() {
    let view = View {
        select: Some("watson_image".into()),
        ..View::default()
    };
    let mut h = harness(order_matters(), SNAPSHOT_SIZE.into(), &view).unwrap();
    let a = index(h.state(), "watson_image");
    let old = h.state().doc.plan.activities[a].value;
    h.get_by_label("Value").scroll_to_me();
    h.run_steps(30);
    type_into(&mut h, "Value", "7.5");
    h.key_press(eframe::egui::Key::Enter);
    h.run_steps(3);
    assert_eq!(h.state().doc.plan.activities[a].value, Some(7.5));
    // A negative value is the engine's to refuse: shown, not applied.
    type_into(&mut h, "Value", "-1");
    h.key_press(eframe::egui::Key::Enter);
    h.run_steps(3);
    assert_eq!(h.state().doc.plan.activities[a].value, Some(7.5));
    assert!(
        h.query_by_label_contains("must be >= 0 (got -1)").is_some(),
        "the engine's refusal is shown"
    );
    // Written back on save, and read back.
    let dir = std::env::temp_dir().join(format!("solscope-app-tune-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("value.json");
    h.state_mut().apply(Command::SaveTo(file.clone()));
    let saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    let watson = saved["activities"]
        .as_array()
        .unwrap()
        .iter()
        .find(|x| x["id"] == "watson_image")
        .unwrap();
    assert_eq!(watson["value"], serde_json::json!(7.5));
    let reopened = SolscopeApp::open_or_default(Some(&file)).unwrap();
    assert_eq!(reopened.doc.plan.activities[a].value, Some(7.5));
    std::fs::remove_dir_all(&dir).unwrap();
    // Undo restores the value it had.
    h.state_mut().apply(UiCommand::Undo.into());
    assert_eq!(h.state().doc.plan.activities[a].value, old);
}
