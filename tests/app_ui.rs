//! Interaction tests through the real UI, by accessibility labels (egui_kittest).

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use egui_kittest::kittest::Queryable;
use solscope::gui::{Command, SolscopeApp};
use solscope::screenshot::{SNAPSHOT_SIZE, View, harness};

fn tutorial() -> SolscopeApp {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/tutorial-plan.json"
    ))
    .unwrap();
    SolscopeApp::from_text(&text, None).expect("tutorial plan")
}

/// The tutorial plan with activity `id` selected, in a harness.
fn tutorial_with_selected(id: &str) -> egui_kittest::Harness<'static, SolscopeApp> {
    let view = View {
        select: Some(id.into()),
        ..View::default()
    };
    harness(tutorial(), SNAPSHOT_SIZE.into(), &view).unwrap()
}

fn index(app: &SolscopeApp, id: &str) -> usize {
    app.doc
        .plan
        .activities
        .iter()
        .position(|a| a.id == id)
        .expect("activity")
}

#[test]
fn stepping_moves_activities_between_lanes() {
    let mut h = harness(
        tutorial(),
        SNAPSHOT_SIZE.into(),
        &View {
            step: Some(0),
            ..View::default()
        },
    )
    .unwrap();
    let first = h.state().analysis.schedule.steps[0].activity;
    let id = h.state().doc.plan.activities[first].id.clone();
    // Pending before step 1, scheduled after it.
    assert!(h.query_by_label(&format!(".   1 {id}")).is_some());
    h.get_by_label("Next >").click();
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.step, 1);
    assert!(h.query_by_label(&format!("+   1 {id}")).is_some());
    // Keyboard: End goes to the last step, Home back to 0.
    h.key_press(eframe::egui::Key::End);
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.step, h.state().analysis.steps());
    h.key_press(eframe::egui::Key::Home);
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.step, 0);
}

#[test]
fn clicking_a_failed_activity_shows_its_explanation() {
    let mut h = harness(tutorial(), SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    let a = index(h.state(), "sky_flats_mast_busy");
    let step = h.state().analysis.schedule.step_of(a).unwrap().step;
    h.get_by_label(&format!("x {step:>3} sky_flats_mast_busy"))
        .click();
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.selected, Some(a));
    assert!(h.query_by_label("Why it did not schedule").is_some());
    assert!(
        h.query_by_label_contains("Conflict: execution + unit_resource")
            .is_some()
    );
}

#[test]
fn applying_a_suggestion_makes_it_schedule_and_undo_restores() {
    let mut h = tutorial_with_selected("sky_flats_mast_busy");
    let a = index(h.state(), "sky_flats_mast_busy");
    let before = h.state().doc.plan.clone();
    assert!(h.state().analysis.placement(a).is_none());
    h.get_by_label_contains("Apply: Widen window 1 of sky_flats_mast_busy")
        .click();
    h.run_steps(3);
    assert!(
        h.state().analysis.placement(a).is_some(),
        "the suggestion schedules it"
    );
    let banner = h
        .state()
        .ui
        .messages
        .banner
        .clone()
        .expect("outcome banner");
    assert!(
        banner
            .newly_scheduled
            .contains(&"sky_flats_mast_busy".to_string())
    );
    assert!(
        h.query_by_label_contains("newly scheduled: sky_flats_mast_busy")
            .is_some()
    );
    // Ctrl+Z restores the plan and the outcome.
    h.key_press_modifiers(eframe::egui::Modifiers::COMMAND, eframe::egui::Key::Z);
    h.run_steps(3);
    assert_eq!(h.state().doc.plan, before);
    assert!(h.state().analysis.placement(a).is_none());
}

#[test]
fn editing_a_window_reruns_and_updates_the_banner() {
    let mut h = tutorial_with_selected("sky_flats_mast_busy");
    let a = index(h.state(), "sky_flats_mast_busy");
    h.get_by_label("windows").scroll_to_me();
    h.run_steps(2);
    h.get_by_label("windows").focus();
    h.run_steps(2);
    h.key_press_modifiers(eframe::egui::Modifiers::COMMAND, eframe::egui::Key::A);
    h.get_by_label("windows")
        .type_text(r#"[{"start": 36000, "end": 38700}]"#);
    h.run_steps(2);
    h.key_press(eframe::egui::Key::Enter);
    h.run_steps(3);
    assert!(
        h.state().analysis.placement(a).is_some(),
        "the widened window fits: editor {:?}, error {:?}",
        h.state()
            .ui
            .text
            .editor
            .get("activity:sky_flats_mast_busy/windows"),
        h.state().ui.messages.error
    );
    assert!(h.state().doc.dirty);
    assert!(
        h.query_by_label_contains("Set windows of activity:sky_flats_mast_busy")
            .is_some()
    );
}

#[test]
fn a_bad_value_is_shown_and_never_applied() {
    let mut h = tutorial_with_selected("sky_flats_mast_busy");
    let before = h.state().doc.plan.clone();
    h.get_by_label("priority").scroll_to_me();
    h.run_steps(2);
    h.get_by_label("priority").focus();
    h.run_steps(2);
    h.key_press_modifiers(eframe::egui::Modifiers::COMMAND, eframe::egui::Key::A);
    h.get_by_label("priority").type_text("\"high\"");
    h.key_press(eframe::egui::Key::Enter);
    h.run_steps(3);
    assert_eq!(h.state().doc.plan, before, "nothing applied");
    assert!(
        h.query_by_label_contains("invalid type").is_some(),
        "the error is shown next to the field"
    );
}

#[test]
fn opening_a_bad_file_keeps_the_plan_and_shows_the_error() {
    let mut h = harness(tutorial(), SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    let before = h.state().doc.plan.clone();
    let bad = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/malformed/window-end-before-start.json"
    );
    h.state_mut().push(Command::Open(bad.into()));
    h.run_steps(3);
    assert_eq!(h.state().doc.plan, before);
    assert!(h.query_by_label_contains("Could not open").is_some());
    assert!(
        h.query_by_label_contains("windows[0].end").is_some(),
        "the path-named error is shown"
    );
}

#[test]
fn unsaved_edits_are_guarded_on_open() {
    let mut h = tutorial_with_selected("sky_flats_mast_busy");
    h.get_by_label_contains("Apply: Widen window 1").click();
    h.run_steps(3);
    assert!(h.state().doc.dirty);
    let edited = h.state().doc.plan.clone();
    let other = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/examples/pitfall.json");
    h.state_mut().push(Command::Open(other.into()));
    h.run_steps(3);
    assert!(h.query_by_label("Unsaved changes").is_some());
    h.get_by_label("Keep editing").click();
    h.run_steps(3);
    assert_eq!(h.state().doc.plan, edited, "the edits are kept");
}

#[test]
fn suggestions_are_verified_off_the_frame_and_never_stale() {
    let mut app = tutorial();
    app.background = true;
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    let a = index(h.state(), "sky_flats_mast_busy");
    h.state_mut().apply(Command::Select(Some(a)));
    h.run_steps(1);
    // The frame does not wait for the worker: the inspector says so meanwhile.
    let wait_for = |h: &mut egui_kittest::Harness<'static, SolscopeApp>| {
        for _ in 0..1000 {
            if h.state().cached_suggestions(a).is_some() {
                return;
            }
            std::thread::sleep(std::time::Duration::from_millis(10));
            h.run_steps(1);
        }
        panic!("suggestions never arrived");
    };
    wait_for(&mut h);
    let first: Vec<String> = h
        .state()
        .cached_suggestions(a)
        .unwrap()
        .iter()
        .map(|s| s.description.clone())
        .collect();
    assert!(
        first.iter().any(|d| d.starts_with("Widen window 1")),
        "{first:?}"
    );
    assert!(
        h.query_by_label_contains("Apply: Widen window 1 of sky_flats_mast_busy")
            .is_some()
    );
    // After an edit the old list is not shown: new ones are verified for the new
    // revision (here the edit makes it schedule, so there are none).
    h.get_by_label_contains("Apply: Widen window 1 of sky_flats_mast_busy")
        .click();
    h.run_steps(2);
    assert!(h.state().analysis.placement(a).is_some());
    wait_for(&mut h);
    assert_eq!(h.state().cached_suggestions(a), Some(&[][..]));
}

#[test]
fn every_reason_kind_shows_its_numbers() {
    let view = View {
        select: Some("supercam_dawn_sky_412".into()),
        ..View::default()
    };
    let h = harness(
        SolscopeApp::with_default_plan().unwrap(),
        SNAPSHOT_SIZE.into(),
        &view,
    )
    .unwrap();
    // A preheat reason names the zone and when the preheat would start, not only
    // its kind.
    assert!(
        h.query_by_label_contains(
            "preheat_operability for starts 44680–45580: mast preheat from 41080"
        )
        .is_some()
    );
}

#[test]
fn one_suggestion_worker_at_a_time() {
    let mut app = SolscopeApp::with_default_plan().unwrap();
    app.background = true;
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    let first = index(h.state(), "moxie_run_413");
    let second = index(h.state(), "supercam_dawn_sky_412");
    h.state_mut().apply(Command::Select(Some(first)));
    h.run_steps(1);
    assert_eq!(h.state().verifying(), Some(first));
    // Selecting another activity while the first is verified does not start a
    // second worker; its turn comes when the first is done.
    h.state_mut().apply(Command::Select(Some(second)));
    h.run_steps(1);
    if h.state().cached_suggestions(first).is_none() {
        assert_eq!(h.state().verifying(), Some(first));
    }
    for _ in 0..3000 {
        if h.state().cached_suggestions(second).is_some() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
        h.run_steps(1);
    }
    let list = h.state().cached_suggestions(second).expect("arrived");
    assert!(
        list.iter().any(|s| s.description.contains("mast heating")),
        "{list:?}"
    );
}
