//! Interaction tests through the real UI, by accessibility labels (egui_kittest).

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod support;

use egui_kittest::kittest::{NodeT, Queryable};
use solscope::gui::screenshot::{SNAPSHOT_SIZE, View, harness};
use solscope::gui::{Look, SolscopeApp};
use solscope::state::{Command, Dialog, ListFilter, Mode, StatusFilter, UiCommand};
use support::{frames_until, generated_plan_file, index, scratch_file, tutorial};

/// The tutorial plan at step 0 (nothing placed yet), in a harness.
fn tutorial_at_step_zero() -> egui_kittest::Harness<'static, SolscopeApp> {
    harness(
        tutorial(),
        SNAPSHOT_SIZE.into(),
        &View {
            step: Some(0),
            ..View::default()
        },
    )
    .unwrap()
}

/// The tutorial plan with activity `id` selected, in a harness.
fn tutorial_with_selected(id: &str) -> egui_kittest::Harness<'static, SolscopeApp> {
    let view = View {
        select: Some(id.into()),
        ..View::default()
    };
    harness(tutorial(), SNAPSHOT_SIZE.into(), &view).unwrap()
}

#[test]
fn stepping_moves_activities_between_lanes() {
    let mut h = tutorial_at_step_zero();
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

/// The scheduling terms explain themselves in plain words on hover.
#[test]
fn scheduling_terms_have_hover_help() {
    let mut h = harness(tutorial(), SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    let a = index(h.state(), "sky_flats_mast_busy");
    let step = h.state().analysis.schedule.step_of(a).unwrap().step;
    h.get_by_label(&format!("x {step:>3} sky_flats_mast_busy"))
        .click();
    h.run_steps(3);
    assert!(
        h.query_by_label_contains("every timing rule at once")
            .is_none()
    );
    h.get_by_label("Why it did not schedule").hover();
    h.run_steps(60);
    assert!(
        h.query_by_label_contains("every timing rule at once")
            .is_some(),
        "the failure's help"
    );
    h.get_by_label_contains("Valid starts per constraint")
        .hover();
    h.run_steps(60);
    assert!(
        h.query_by_label_contains("only start where every row is green")
            .is_some(),
        "the valid starts' help"
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

/// Scrolls the widget labelled `label` into view (the scroll is animated:
/// a click lands where it is once it stops).
fn show(h: &mut egui_kittest::Harness<'static, SolscopeApp>, label: &str) {
    h.get_by_label(label).scroll_to_me();
    h.run_steps(30);
}

/// Clicks the widget labelled `label`, scrolled into view first.
fn click(h: &mut egui_kittest::Harness<'static, SolscopeApp>, label: &str) {
    show(h, label);
    h.get_by_label(label).click();
    h.run_steps(3);
}

/// Types `text` into the editor field labelled `label` and presses Enter.
fn commit(h: &mut egui_kittest::Harness<'static, SolscopeApp>, label: &str, text: &str) {
    show(h, label);
    type_into(h, label, text);
    h.key_press(eframe::egui::Key::Enter);
    h.run_steps(3);
}

#[test]
fn editing_a_window_s_start_in_sol_time_reruns_and_updates_the_banner() {
    let mut h = tutorial_with_selected("sky_flats_mast_busy");
    let a = index(h.state(), "sky_flats_mast_busy");
    assert!(h.state().analysis.placement(a).is_none());
    let revision = h.state().revision;
    // The field shows the start in sol and local time.
    let shown = h.get_by_label("Window 1 start").value();
    assert_eq!(shown.as_deref(), Some("Sol 0 10:13:08"), "37800 s");
    commit(&mut h, "Window 1 start", "Sol 0 10:00");
    let w = h.state().doc.plan.activities[a].windows.clone().unwrap();
    // 10:00 LMST is 36000 LMST seconds, the first plan second at or after it
    // 36990 (a sol of 88775 s).
    assert_eq!((w[0].start, w[0].end), (36990, 38700));
    assert_eq!(h.state().revision, revision + 1, "rescheduled once");
    assert!(
        h.state().analysis.placement(a).is_some(),
        "the widened window fits: error {:?}",
        h.state().ui.messages.error
    );
    assert!(h.state().doc.dirty);
    assert!(
        h.query_by_label_contains("Set window 1 start of sky_flats_mast_busy")
            .is_some()
    );
    // A time of day alone stays in the window's sol (10:50 LMST: plan second
    // 40073).
    commit(&mut h, "Window 1 end", "10:50");
    let w = h.state().doc.plan.activities[a].windows.clone().unwrap();
    assert_eq!(w[0].end, 40073);
}

#[test]
fn a_bad_value_is_shown_and_never_applied() {
    let mut h = tutorial_with_selected("sky_flats_mast_busy");
    let before = h.state().doc.plan.clone();
    commit(&mut h, "Priority", "high");
    assert_eq!(h.state().doc.plan, before, "nothing applied");
    assert!(
        h.query_by_label_contains("\"high\" is not a whole number")
            .is_some(),
        "the error is shown next to the field"
    );
    commit(&mut h, "Window 1 start", "Sol 0 27:00");
    assert_eq!(h.state().doc.plan, before, "nothing applied");
    assert!(h.query_by_label_contains("is not a time").is_some());
}

#[test]
fn a_window_ending_before_its_start_shows_the_error_and_changes_nothing() {
    let view = View {
        select: Some("drill_core_413".into()),
        ..View::default()
    };
    let mut h = harness(
        SolscopeApp::with_default_plan().unwrap(),
        SNAPSHOT_SIZE.into(),
        &view,
    )
    .unwrap();
    let before = h.state().doc.plan.clone();
    commit(&mut h, "Window 1 end", "Sol 413 09:00");
    assert_eq!(h.state().doc.plan, before, "nothing applied");
    assert!(h.get_by_label("Undo").accesskit_node().is_disabled());
    let err = h.get_by_label_contains("must be >= start").rect();
    let field = h.get_by_label("Window 1 end").rect();
    assert!(
        err.right() <= SNAPSHOT_SIZE[0],
        "the message ends inside the window: {err:?}"
    );
    assert!(err.left() < field.left(), "under the window: {err:?}");
    // Escape puts the plan's value back.
    h.get_by_label("Window 1 end").focus();
    h.run_steps(2);
    h.key_press(eframe::egui::Key::Escape);
    h.run_steps(2);
    assert_eq!(
        h.get_by_label("Window 1 end").value().as_deref(),
        Some("Sol 413 11:11:32")
    );
}

#[test]
fn the_mandatory_checkbox_toggles_and_undo_restores() {
    let mut h = tutorial_with_selected("meda_night");
    let a = index(h.state(), "meda_night");
    assert!(!h.state().doc.plan.activities[a].mandatory);
    click(&mut h, "Mandatory");
    assert!(h.state().doc.plan.activities[a].mandatory);
    assert!(
        h.query_by_label_contains("Set mandatory of meda_night")
            .is_some()
    );
    h.get_by_label("Undo").click();
    h.run_steps(3);
    assert!(!h.state().doc.plan.activities[a].mandatory);
    assert_eq!(h.state().ui.nav.selected, Some(a), "still selected");
}

#[test]
fn a_dependency_is_added_from_the_searchable_picker() {
    let mut h = tutorial_with_selected("libs_raster_low_battery");
    let a = index(h.state(), "libs_raster_low_battery");
    assert!(h.state().doc.plan.activities[a].after.is_empty());
    click(&mut h, "Add dependency");
    type_into(&mut h, "Search Add dependency", "navcam");
    // Only the matching activities are offered.
    assert!(h.query_by_label("zcam_pano").is_none());
    h.get_by_label("navcam_post_drive").click();
    h.run_steps(3);
    let after = &h.state().doc.plan.activities[a].after;
    assert_eq!(after.len(), 1);
    assert_eq!(after[0].activity, "navcam_post_drive");
    assert!(h.query_by_label("after navcam_post_drive").is_some());
    // Its delay is a field of its own.
    commit(&mut h, "Dependency on navcam_post_drive max delay", "600");
    assert_eq!(
        h.state().doc.plan.activities[a].after[0].max_delay,
        Some(600)
    );
}

#[test]
fn activities_are_added_duplicated_and_deleted_with_undo() {
    let mut h = tutorial_with_selected("zcam_pano");
    let before = h.state().doc.plan.clone();
    let n = before.activities.len();
    let ids = |h: &egui_kittest::Harness<'static, SolscopeApp>| -> Vec<String> {
        h.state()
            .doc
            .plan
            .activities
            .iter()
            .map(|a| a.id.clone())
            .collect()
    };
    h.get_by_label("Duplicate activity").click();
    h.run_steps(3);
    assert_eq!(h.state().doc.plan.activities.len(), n + 1);
    let copy = index(h.state(), "zcam_pano_copy");
    assert_eq!(copy, index(h.state(), "zcam_pano") + 1, "right after it");
    assert_eq!(
        h.state().ui.nav.selected,
        Some(copy),
        "the copy is selected"
    );
    h.get_by_label("Add activity").click();
    h.run_steps(3);
    assert_eq!(ids(&h)[copy + 1], "new_activity");
    assert_eq!(h.state().ui.nav.selected, Some(copy + 1));
    // Deleting arm_stow drops watson's dependent's entry with it.
    let stow = index(h.state(), "arm_stow");
    h.state_mut().push(Command::Select(Some(stow)));
    h.run_steps(2);
    h.get_by_label("Delete activity").click();
    h.run_steps(3);
    assert!(!ids(&h).contains(&"arm_stow".to_string()));
    assert!(h.state().ui.nav.selected.is_none());
    assert!(
        h.query_by_label_contains("Delete arm_stow (and the dependencies of drive on it)")
            .is_some()
    );
    for _ in 0..3 {
        h.get_by_label("Undo").click();
        h.run_steps(3);
    }
    assert_eq!(h.state().doc.plan, before, "undo restores every step");
    assert!(h.get_by_label("Undo").accesskit_node().is_disabled());
}

#[test]
fn a_structured_edit_that_changes_nothing_is_not_recorded() {
    let mut h = tutorial_with_selected("sky_flats_mast_busy");
    // The start it has, in plan seconds instead of sol time.
    commit(&mut h, "Window 1 start", "37800");
    assert!(!h.state().doc.dirty);
    assert!(h.get_by_label("Undo").accesskit_node().is_disabled());
    assert!(h.query_by_label_contains("the plan is unchanged").is_some());
    // Finishing without typing is no edit at all.
    h.state_mut().push(Command::DismissBanner);
    h.get_by_label("Priority").focus();
    h.run_steps(2);
    h.key_press(eframe::egui::Key::Enter);
    h.run_steps(3);
    assert!(h.state().ui.messages.banner.is_none());
}

/// The tutorial plan broken in four places, as a planner's file.
fn broken_tutorial() -> String {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/tutorial-plan.json"
    ))
    .unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["battery"]["initial"] = serde_json::json!(1000.0);
    v["activities"][0]["windows"] = serde_json::json!([{ "start": 5000, "end": 4000 }]);
    v["activities"][1]["energy_rate"] = serde_json::json!(-3);
    v["activities"][2]["after"] = serde_json::json!([{ "activity": "nobody" }]);
    serde_json::to_string_pretty(&v).unwrap()
}

const BROKEN_PATHS: [&str; 4] = [
    "battery.initial",
    "activities[0].windows[0].end",
    "activities[1].energy_rate",
    "activities[2].after[0].activity",
];

/// Jumps to the error at `path` and puts `value` there.
fn replace_at(h: &mut egui_kittest::Harness<'static, SolscopeApp>, path: &str, value: &str) {
    h.get_by_label(path).click();
    h.run_steps(3);
    type_into(h, "Value at this path", value);
    h.get_by_label("Replace and re-check").click();
    h.run_steps(3);
}

#[test]
fn an_invalid_file_opens_in_the_repair_view_listing_every_error() {
    let mut h = harness(tutorial(), SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    let before = h.state().doc.plan.clone();
    let path = scratch_file("repair", "broken.json", &broken_tutorial());
    h.state_mut().push(Command::Open(path.clone()));
    h.run_steps(3);
    assert_eq!(h.state().doc.plan, before, "the open plan stays");
    assert!(h.query_by_label("Repair broken.json").is_some());
    assert!(h.query_by_label("Errors (4)").is_some());
    for p in BROKEN_PATHS {
        assert!(h.query_by_label(p).is_some(), "{p} is listed");
    }
    assert!(h.query_by_label_contains("must be >= 0 (got -3)").is_some());
    // The first error is looked at: its value is there to edit.
    assert_eq!(
        h.get_by_label("Value at this path").value().as_deref(),
        Some("1000.0")
    );
    h.get_by_label("activities[1].energy_rate").click();
    h.run_steps(3);
    assert_eq!(
        h.get_by_label("Value at this path").value().as_deref(),
        Some("-3")
    );
    replace_at(&mut h, "activities[1].energy_rate", "3");
    assert!(h.query_by_label("Errors (3)").is_some());
    assert_eq!(
        h.state().doc.plan,
        before,
        "not open until every error is fixed"
    );
    replace_at(&mut h, "battery.initial", "800.0");
    replace_at(&mut h, "activities[0].windows[0].end", "5000");
    replace_at(&mut h, "activities[2].after[0].activity", "\"uhf_pass_am\"");
    // Fixed: it is the plan now, unsaved (its file still holds the broken text).
    assert!(h.state().ui.messages.repair.is_none());
    let plan = &h.state().doc.plan;
    assert_eq!(plan.activities[1].energy_rate, 3.0);
    assert_eq!(plan.battery.initial, 800.0);
    assert_eq!(h.state().doc.path.as_deref(), Some(path.as_path()));
    assert!(h.state().doc.dirty);
    assert!(h.query_by_label_contains("(unsaved)").is_some());
    assert_eq!(
        h.state().persisted.recent.first(),
        Some(&std::path::absolute(&path).unwrap())
    );
}

#[test]
fn the_repair_view_goes_back_to_the_open_plan_and_the_text_can_be_fixed_whole() {
    let mut h = harness(tutorial(), SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    let before = h.state().doc.plan.clone();
    let path = scratch_file("repair-back", "broken.json", &broken_tutorial());
    h.state_mut().push(Command::Open(path.clone()));
    h.run_steps(3);
    // Keys are the text's: no undo or stepping of the plan behind.
    h.key_press(eframe::egui::Key::ArrowLeft);
    h.run_steps(2);
    assert_eq!(h.state().ui.nav.step, h.state().analysis.steps());
    h.get_by_label("Back to the open plan").click();
    h.run_steps(3);
    assert!(h.state().ui.messages.repair.is_none());
    assert_eq!(h.state().doc.plan, before);
    assert!(h.query_by_label("Errors (4)").is_none());
    assert!(!h.state().doc.dirty);
    // A file that is not even JSON: the one error, and the whole text to fix.
    let path = scratch_file(
        "repair-back",
        "cut.json",
        "{\"format\": \"solscope.plan/1\",",
    );
    h.state_mut().push(Command::Open(path));
    h.run_steps(3);
    assert!(h.query_by_label("Errors (1)").is_some());
    type_into(&mut h, "Plan text", &broken_tutorial().replace("-3", "3"));
    h.get_by_label("Re-check").click();
    h.run_steps(3);
    assert!(
        h.query_by_label("Errors (3)").is_some(),
        "the text's own errors now"
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
            "preheat_operability for starts Sol 412 05:35:51 (t=44680)–Sol 412 05:50:27 (t=45580): mast preheat from Sol 412 04:37:27 (t=41080)"
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
    // (Unless the worker is already done: a frame can take two passes.)
    if h.state().cached_suggestions(first).is_none() {
        assert_eq!(h.state().verifying(), Some(first));
    }
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

/// The example plan with uncertain durations.
fn uncertain_drive() -> SolscopeApp {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/execution-examples/uncertain-drive.json"
    );
    let text = std::fs::read_to_string(path).unwrap();
    SolscopeApp::from_text(&text, Some(path.into())).expect("uncertain drive")
}

/// `(completed, aborted, not run)` of the execution shown, once derived.
fn counts(h: &egui_kittest::Harness<'static, SolscopeApp>) -> Option<(usize, usize, usize)> {
    h.state().execution_run().map(|r| r.counts())
}

#[test]
fn switching_to_execution_and_back() {
    let mut h = harness(uncertain_drive(), SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    assert_eq!(h.state().ui.nav.mode, Mode::Schedule);
    h.get_by_label("Execution").click();
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.mode, Mode::Execution);
    // Nominal actuals by default: everything runs where the first cycle put it.
    assert!(h.query_by_label("nominal").is_some());
    assert_eq!(counts(&h), Some((4, 0, 0)));
    assert!(
        h.query_by_label("4 completed, 0 aborted, 0 not run")
            .is_some()
    );
    assert!(h.query_by_label_contains("cycle 0 of 21").is_some());
    // Cmd+1 goes back to the schedule; the step slider is the plan's again.
    h.key_press_modifiers(eframe::egui::Modifiers::COMMAND, eframe::egui::Key::Num1);
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.mode, Mode::Schedule);
    assert!(h.query_by_label_contains("step 4: sky_survey").is_some());
    h.key_press_modifiers(eframe::egui::Modifiers::COMMAND, eframe::egui::Key::Num2);
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.mode, Mode::Execution);
}

#[test]
fn the_cycle_slider_and_the_step_slider_inside_a_cycle() {
    let mut app = uncertain_drive();
    app.apply(UiCommand::ShowExecution.into());
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    h.get_by_label("Cycle >").click();
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.cycle, 1);
    assert!(
        h.query_by_label_contains("cycle 1 of 21: at Sol 0 10:13:08 (t=1800), replan period")
            .is_some()
    );
    // Page Down moves on; the cycle's run is shown at its last step.
    for _ in 0..3 {
        h.key_press(eframe::egui::Key::PageDown);
        h.run_steps(2);
    }
    assert_eq!(h.state().ui.nav.cycle, 4);
    // Cycle 4 runs when the drive ends at 6400; its plan holds the three
    // activities not yet started, and its run is shown at its last step.
    let run = h.state().execution_run().unwrap();
    let cycle = &run.execution.cycles[4];
    assert_eq!(cycle.time, 6400);
    assert_eq!(h.state().cycle_run().unwrap().activity_of.len(), 3);
    assert_eq!(h.state().cycle_run().unwrap().steps(), 3);
    assert!(
        h.query_by_label_contains("cycle 4 of 21: at Sol 0 11:27:45 (t=6400), after drive ended")
            .is_some()
    );
    assert!(
        h.query_by_label_contains("cycle 4, step 3: sky_survey")
            .is_some()
    );
    // The step buttons step inside that run.
    h.get_by_label("< Previous").click();
    h.run_steps(3);
    assert!(h.query_by_label_contains("cycle 4, step 2:").is_some());
    h.key_press(eframe::egui::Key::Home);
    h.run_steps(3);
    assert!(
        h.query_by_label_contains("cycle 4, before step 1: nothing placed")
            .is_some()
    );
    // The plan's own step did not move.
    assert_eq!(h.state().ui.nav.step, h.state().analysis.steps());
    h.key_press(eframe::egui::Key::PageUp);
    h.run_steps(2);
    assert_eq!(h.state().ui.nav.cycle, 3);
    assert!(h.query_by_label_contains("cycle 3, step 4:").is_some());
}

/// The inspector shows what a cycle's run saw at the selected activity's
/// step: its valid starts per constraint, which the run itself no longer
/// keeps (`Schedule::all_traces` derives them for the cycle view).
#[test]
fn a_cycle_step_shows_the_valid_starts_its_run_saw() {
    let mut app = uncertain_drive();
    app.apply(UiCommand::ShowExecution.into());
    let sky = index(&app, "sky_survey");
    app.apply(Command::Select(Some(sky)));
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    h.get_by_label("Cycle >").click();
    h.run_steps(3);
    for _ in 0..3 {
        h.key_press(eframe::egui::Key::PageDown);
        h.run_steps(2);
    }
    assert_eq!(h.state().ui.nav.cycle, 4);
    assert!(
        h.query_by_label_contains("cycle 4, step 3: sky_survey")
            .is_some()
    );
    assert!(
        h.query_by_label_contains(
            "Valid starts per constraint (within its windows, cycle 4 step 3)"
        )
        .is_some()
    );
    let cr = h.state().cycle_run().unwrap();
    let trace = &cr.traces[2];
    assert!(!trace.categories.is_empty());
    // Before its step, it is pending: no sets.
    h.key_press(eframe::egui::Key::Home);
    h.run_steps(3);
    assert!(
        h.query_by_label_contains("Valid starts per constraint (within its windows")
            .is_none()
    );
}

#[test]
fn an_actuals_file_is_used_and_an_invalid_one_changes_nothing() {
    let mut app = uncertain_drive();
    app.apply(UiCommand::ShowExecution.into());
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    let good = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/execution-examples/uncertain-drive.actuals.json"
    );
    h.state_mut().push(Command::OpenActuals(good.into()));
    h.run_steps(3);
    assert!(h.query_by_label("uncertain-drive.actuals.json").is_some());
    let drive = index(h.state(), "drive");
    let run = h.state().execution_run().unwrap();
    assert_eq!(run.execution.activities[drive].actual, Some((1000, 7300)));
    let before = (h.state().actuals.clone(), counts(&h));
    let cycles = run.execution.cycles.len();
    // An unknown activity: the path-named error, and nothing changes.
    let bad = scratch_file(
        "bad-actuals",
        "bad.actuals.json",
        r#"{"format": "solscope.actuals/1", "durations": {"nope": 10}}"#,
    );
    h.state_mut().push(Command::OpenActuals(bad.clone()));
    h.run_steps(3);
    assert!(
        h.query_by_label_contains("Could not open actuals")
            .is_some()
    );
    assert!(
        h.query_by_label_contains("durations.nope").is_some(),
        "the path-named error is shown: {:?}",
        h.state().ui.messages.error
    );
    assert_eq!((h.state().actuals.clone(), counts(&h)), before);
    assert_eq!(
        h.state().execution_run().unwrap().execution.cycles.len(),
        cycles
    );
    assert!(h.query_by_label("uncertain-drive.actuals.json").is_some());
    // Neither does a file that is not there.
    h.state_mut()
        .push(Command::OpenActuals(bad.with_file_name("missing.json")));
    h.run_steps(3);
    assert!(h.query_by_label_contains("missing.json").is_some());
    assert_eq!((h.state().actuals.clone(), counts(&h)), before);
}

#[test]
fn sampling_with_a_seed_names_the_source() {
    let mut app = uncertain_drive();
    app.apply(UiCommand::ShowExecution.into());
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    h.get_by_label("Seed").focus();
    h.run_steps(2);
    h.key_press_modifiers(eframe::egui::Modifiers::COMMAND, eframe::egui::Key::A);
    h.get_by_label("Seed").type_text("7");
    h.run_steps(2);
    h.get_by_label("Sample").click();
    h.run_steps(3);
    assert!(h.query_by_label("sampled, seed 7").is_some());
    let want = solscope_engine::sample_actuals(&h.state().doc.plan, 7);
    assert_eq!(h.state().execution_run().unwrap().actuals, want);
    // A seed that is not a number is an error, and the source stays.
    h.get_by_label("Seed").focus();
    h.run_steps(2);
    h.key_press_modifiers(eframe::egui::Modifiers::COMMAND, eframe::egui::Key::A);
    h.get_by_label("Seed").type_text("seven");
    h.run_steps(2);
    h.get_by_label("Sample").click();
    h.run_steps(3);
    assert!(
        h.query_by_label_contains("Seed: enter a whole number")
            .is_some()
    );
    assert!(h.query_by_label("sampled, seed 7").is_some());
    h.get_by_label("Nominal").click();
    h.run_steps(3);
    assert!(h.query_by_label("nominal").is_some());
}

#[test]
fn an_edit_reruns_the_execution_and_the_inspector_shows_what_happened() {
    let mut app = uncertain_drive();
    app.apply(UiCommand::ShowExecution.into());
    let long = scratch_file(
        "edit",
        "long.actuals.json",
        r#"{"format": "solscope.actuals/1", "durations": {"drive": 6600, "sky_survey": 1500}}"#,
    );
    app.apply(Command::OpenActuals(long));
    let post = index(&app, "post_drive_imaging");
    app.apply(Command::Select(Some(post)));
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    assert_eq!(counts(&h), Some((3, 1, 0)));
    // The drive ran long: post-drive imaging was held back by it.
    assert!(
        h.query_by_label_contains("held post_drive_imaging: dependency: drive had not ended")
            .is_none(),
        "cycle 0 does not hold it"
    );
    assert!(
        h.query_by_label_contains("(cycle 3): dependency: drive had not ended")
            .is_some()
    );
    assert!(h.query_by_label("Outcome: completed").is_some());
    // Raising the minimum state of charge: the long drive now breaks it, and
    // less runs.
    let mut set = serde_json::Map::new();
    set.insert(
        "battery".into(),
        serde_json::json!({"capacity": 1600.0, "initial": 1300.0, "min_soc": 950.0}),
    );
    h.state_mut().push(Command::Edit {
        target: "plan".into(),
        set,
        description: "Raise min_soc".into(),
    });
    h.run_steps(3);
    assert_eq!(counts(&h), Some((1, 1, 2)));
    assert!(
        h.query_by_label_contains("1 limit(s) broken: min_soc")
            .is_some()
    );
    assert!(
        h.query_by_label_contains("min_soc broken from Sol 0 11:37:58 (t=7030): worst 915.1 Wh")
            .is_some()
    );
    assert!(
        h.query_by_label("Outcome: not run: it never started")
            .is_some()
    );
    assert!(
        h.query_by_label_contains("Last in the plan of cycle 18")
            .is_some()
    );
    // Why, from the explainer at the cycle that decided it.
    assert!(
        h.query_by_label_contains(
            "post_drive_imaging was not run: at the cycle at Sol 0 11:40:44 (t=7200) the scheduler could not place it: placement (min_soc)"
        )
        .is_some()
    );
    h.get_by_label("Show cycle 4").click();
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.cycle, 4);
}

#[test]
fn the_execution_is_derived_off_the_frame_and_never_stale() {
    let mut app = uncertain_drive();
    app.background = true;
    app.apply(UiCommand::ShowExecution.into());
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    let wait = |h: &mut egui_kittest::Harness<'static, SolscopeApp>| {
        for _ in 0..1000 {
            if h.state().execution_run().is_some() && h.state().cycle_run().is_some() {
                return;
            }
            std::thread::sleep(std::time::Duration::from_millis(10));
            h.run_steps(1);
        }
        panic!("the execution never arrived");
    };
    wait(&mut h);
    assert_eq!(counts(&h), Some((4, 0, 0)));
    h.state_mut()
        .push(Command::SampleActuals { seed: 7, run: 0 });
    h.run_steps(1);
    // The execution of the nominal actuals is not shown for the sampled ones.
    if let Some(run) = h.state().execution_run() {
        assert_eq!(
            run.actuals,
            solscope_engine::sample_actuals(&h.state().doc.plan, 7)
        );
    }
    wait(&mut h);
    assert_eq!(
        h.state().execution_run().unwrap().actuals,
        solscope_engine::sample_actuals(&h.state().doc.plan, 7)
    );
}

/// The uncertain-drive example in execution mode.
fn uncertain_drive_executing() -> SolscopeApp {
    let mut app = uncertain_drive();
    app.apply(UiCommand::ShowExecution.into());
    app
}

/// Types `text` into the field labelled `label` (replacing what it holds).
fn type_into(h: &mut egui_kittest::Harness<'static, SolscopeApp>, label: &str, text: &str) {
    h.get_by_label(label).focus();
    h.run_steps(2);
    h.key_press_modifiers(eframe::egui::Modifiers::COMMAND, eframe::egui::Key::A);
    h.get_by_label(label).type_text(text);
    h.run_steps(2);
}

/// Runs frames until `done` holds (the workers are real threads).
fn wait_until(
    h: &mut egui_kittest::Harness<'static, SolscopeApp>,
    what: &str,
    done: impl Fn(&SolscopeApp) -> bool,
) {
    for _ in 0..3000 {
        if done(h.state()) {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
        h.run_steps(1);
    }
    panic!("{what} never happened");
}

#[test]
fn a_small_campaign_shows_shares_causes_and_the_state_of_charge() {
    let mut h = harness(
        uncertain_drive_executing(),
        SNAPSHOT_SIZE.into(),
        &View::default(),
    )
    .unwrap();
    assert!(
        h.query_by_label_contains("Executes the plan once per run")
            .is_some()
    );
    type_into(&mut h, "Runs", "20");
    h.get_by_label("Run").click();
    h.run_steps(3);
    let result = h
        .state()
        .campaign_result()
        .expect("summarised in the frame");
    assert_eq!(result.runs(), 20);
    let arm = index(h.state(), "arm_science");
    let s = result.activity(arm).unwrap().clone();
    assert_eq!((s.completed, s.aborted, s.not_run), (10, 10, 0));
    assert!(
        h.query_by_label("20 runs, seed 1: no run broke a limit")
            .is_some()
    );
    assert!(h.query_by_label("Lowest state of charge per run").is_some());
    assert!(
        h.query_by_label_contains("min_soc 500.0 Wh: no run below")
            .is_some()
    );
    // Every activity's shares as a bar in the list.
    let arm_bar = "arm_science: completed 10 (50%), aborted 10 (50%), not run 0 of 20 runs";
    assert!(h.query_all_by_label(arm_bar).next().is_some());
    assert!(
        h.query_by_label("drive: completed 20 (100%), aborted 0, not run 0 of 20 runs")
            .is_some()
    );
    // Nothing selected: the activities lost most often, to select.
    h.get_by_label("arm_science: lost in 50%").click();
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.selected, Some(arm));
    assert!(h.query_by_label("Across 20 runs (seed 1)").is_some());
    assert!(
        h.query_by_label(
            "Lost in 50% of runs (10 of 20); in 10 of the 10 lost runs arm_science ran longer \
             than 2359 s, and of the 10 runs in which it did, 10 lost it."
        )
        .is_some()
    );
    assert!(
        h.query_by_label("• aborted: it ran longer than its duration — 10 runs (100% of lost)")
            .is_some()
    );
    assert!(h.query_by_label("In this execution (nominal)").is_some());
}

#[test]
fn opening_a_run_that_lost_the_activity_executes_that_run() {
    let mut app = uncertain_drive_executing();
    app.apply(Command::RunCampaign { runs: 20, seed: 1 });
    let arm = index(&app, "arm_science");
    app.apply(Command::Select(Some(arm)));
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    let runs = h
        .state()
        .campaign_result()
        .unwrap()
        .lost_runs(arm, "aborted")
        .to_vec();
    assert!(!runs.is_empty());
    let run = runs[runs.len() - 1];
    h.get_by_label(&format!("run {run}")).click();
    h.run_steps(3);
    assert_eq!(
        h.state().actuals,
        solscope::state::ActualsSource::Sampled { seed: 1, run }
    );
    assert!(
        h.query_by_label(&format!("sampled, seed 1, run {run}"))
            .is_some()
    );
    let ex = h.state().execution_run().unwrap();
    let plan = &h.state().doc.plan;
    assert_eq!(ex.actuals, solscope_engine::sample_run(plan, 1, run));
    assert_eq!(
        ex.execution.activities[arm].outcome,
        solscope_engine::RunOutcome::Aborted,
        "run {run} lost it"
    );
    assert!(
        h.query_by_label(&format!("In this execution (sampled, seed 1, run {run})"))
            .is_some()
    );
    assert!(h.query_by_label_contains("Outcome: aborted").is_some());
}

#[test]
fn a_campaign_runs_off_the_frame_and_cancel_keeps_nothing() {
    let mut app = SolscopeApp::with_default_plan().unwrap();
    app.apply(UiCommand::ShowExecution.into());
    app.background = true;
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    // The most runs (minutes of work on the bundled plan): cancelled long
    // before they are done.
    type_into(&mut h, "Runs", "20000");
    h.get_by_label("Run").click();
    h.run_steps(2);
    let p = h.state().campaign_progress().expect("running");
    assert_eq!((p.runs, p.seed), (20_000, 1));
    assert!(h.query_by_label_contains("/ 20000 runs (seed 1)").is_some());
    // The panel's body did not change, so its header (with Cancel) stayed
    // where Run was clicked.
    assert!(
        h.query_by_label_contains("Executes the plan once per run")
            .is_some()
    );
    // (Moved off Run first: its tooltip, under the pointer, would take the
    // click.)
    h.get_by_label("Cancel").hover();
    h.run_steps(2);
    h.get_by_label("Cancel").click();
    h.run_steps(2);
    assert!(h.state().campaign_progress().is_none_or(|p| p.cancelling));
    wait_until(&mut h, "cancelling", |app| {
        app.campaign_progress().is_none()
    });
    h.run_steps(2);
    let stopped = h.state().campaign_stopped().expect("stopped");
    assert_eq!(stopped.why, solscope::state::StopReason::Cancelled);
    assert!(stopped.done < stopped.runs);
    assert!(h.state().campaign_result().is_none(), "nothing kept");
    assert!(h.query_by_label_contains("Cancelled after").is_some());
    // A small one runs to its end on the worker, with the same summary as in
    // the frame.
    type_into(&mut h, "Runs", "16");
    h.get_by_label("Run").click();
    h.run_steps(1);
    wait_until(&mut h, "the summary", |app| app.campaign_result().is_some());
    h.run_steps(2);
    let worker = h.state().campaign_result().unwrap().clone();
    let mut direct = SolscopeApp::with_default_plan().unwrap();
    direct.apply(Command::RunCampaign { runs: 16, seed: 1 });
    assert_eq!(&worker, direct.campaign_result().unwrap());
    assert!(h.state().campaign_stopped().is_none());
    assert!(h.query_by_label_contains("16 runs, seed 1").is_some());
}

/// What the panel says of `n` of 20 runs (every share of 20 is a whole
/// percentage).
fn of_20(n: u64) -> String {
    if n == 0 {
        "0".into()
    } else {
        format!("{n} ({}%)", n * 5)
    }
}

#[test]
fn comparing_policies_shows_each_policy_s_summary_side_by_side() {
    let mut app = SolscopeApp::with_default_plan().unwrap();
    app.apply(UiCommand::ShowExecution.into());
    app.background = true;
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    h.get_by_label("Compare policies").click();
    h.run_steps(2);
    assert!(h.state().persisted.compare_policies);
    type_into(&mut h, "Runs", "20");
    h.get_by_label("Run").click();
    h.run_steps(1);
    let p = h.state().campaign_progress().expect("running");
    assert!(p.compare && p.runs == 20 && p.total() == 60);
    wait_until(&mut h, "the comparison", |app| {
        app.campaign_result().is_some()
    });
    h.run_steps(3);
    let result = h.state().campaign_result().unwrap().clone();
    let plan = h.state().doc.plan.clone();
    let compared = result.compared();
    assert_eq!(compared.len(), 3);
    // Each policy's summary is the engine's of the same runs under it.
    let mut summaries = Vec::new();
    for (k, policy) in [
        solscope_engine::Policy::Replan,
        solscope_engine::Policy::Dispatch,
        solscope_engine::Policy::Fixed,
    ]
    .into_iter()
    .enumerate()
    {
        let c = solscope_engine::campaign_with(&plan, 1, 20, "plan", policy).unwrap();
        let indices: Vec<u64> = (0..20).collect();
        let records = solscope_engine::campaign_runs(&plan, &c, &indices, &|| {}, None)
            .unwrap()
            .unwrap();
        let s = solscope_engine::summarize(&c, &records);
        assert_eq!(compared[k], s, "{}", policy.name());
        summaries.push(s);
    }
    // The replan campaign is the one the rest of the app details.
    assert_eq!(result.summary, summaries[0]);
    // Per policy: the runs that broke a limit and the median lowest state
    // of charge, as shown.
    for s in &summaries {
        let lowest = solscope_engine::format_wh(
            (s.lowest_soc.p50 * solscope_engine::MJ_PER_WH).round() as i128,
        );
        let b = s.limits.runs_breaking;
        let line = if b == 0 {
            format!(
                "{}: no run broke a limit · median lowest state of charge {lowest}",
                s.policy.name()
            )
        } else {
            format!(
                "{}: {b} of 20 runs broke a limit ({}%) · median lowest state of charge {lowest}",
                s.policy.name(),
                b * 5
            )
        };
        assert!(h.query_by_label(&line).is_some(), "{line}");
    }
    let counts: Vec<String> = summaries
        .iter()
        .map(|s| format!("{} {}", s.policy.name(), s.limits.runs_breaking))
        .collect();
    let headline = format!(
        "Broke a limit: {} (20 runs each, seed 1)",
        counts.join(", ")
    );
    assert!(h.query_by_label(&headline).is_some(), "{headline}");
    // Per activity lost in some run under some policy (and run under some),
    // those whose completed runs differ most between the policies first: its
    // shares under each policy. The list scrolls: the first rows are laid
    // out.
    let mut listed: Vec<(std::cmp::Reverse<u64>, std::cmp::Reverse<u64>, usize)> =
        (0..plan.activities.len())
            .filter_map(|a| {
                let of = || summaries.iter().map(|s| &s.activities[a]);
                let lost = of().map(|x| x.aborted + x.not_run).max().unwrap();
                let ran = of().any(|x| x.completed + x.aborted > 0);
                let most = of().map(|x| x.completed).max().unwrap();
                let least = of().map(|x| x.completed).min().unwrap();
                (lost > 0 && ran).then_some((
                    std::cmp::Reverse(most - least),
                    std::cmp::Reverse(lost),
                    a,
                ))
            })
            .collect();
    listed.sort();
    let listed: Vec<usize> = listed.into_iter().map(|(_, _, a)| a).collect();
    assert!(!listed.is_empty(), "some activity lost in some run");
    let mut shown = 0;
    for (row, &a) in listed.iter().enumerate() {
        for s in &summaries {
            let x = &s.activities[a];
            let label = format!(
                "{}, {}: completed {}, aborted {}, not run {} of 20 runs",
                s.policy.name(),
                x.id,
                of_20(x.completed),
                of_20(x.aborted),
                of_20(x.not_run)
            );
            let found = h.query_by_label(&label).is_some();
            assert!(found || row >= 3, "{label}");
            shown += usize::from(found);
        }
    }
    assert!(shown >= 3.min(listed.len()) * 3);
    // Off again: Run runs the replanning executive alone, and the
    // single-policy view is back. (Moved off Run first: its tooltip, under
    // the pointer, would take the click.)
    h.get_by_label("Compare policies").hover();
    h.run_steps(2);
    h.get_by_label("Compare policies").click();
    h.run_steps(2);
    assert!(!h.state().persisted.compare_policies);
    h.get_by_label("Run").click();
    h.run_steps(1);
    wait_until(&mut h, "the replan campaign", |app| {
        app.campaign_result()
            .is_some_and(|r| r.compared().is_empty())
    });
    h.run_steps(3);
    assert_eq!(h.state().campaign_result().unwrap().summary, summaries[0]);
    assert!(h.query_by_label("Lowest state of charge per run").is_some());
}

/// The edit that raises the minimum state of charge of the example to 950 Wh.
fn raise_min_soc() -> Command {
    let mut set = serde_json::Map::new();
    set.insert(
        "battery".into(),
        serde_json::json!({"capacity": 1600.0, "initial": 1300.0, "min_soc": 950.0}),
    );
    Command::Edit {
        target: "plan".into(),
        set,
        description: "Raise min_soc".into(),
    }
}

#[test]
fn an_edit_makes_the_summary_stale_until_the_campaign_runs_again() {
    let mut app = uncertain_drive_executing();
    app.apply(Command::RunCampaign { runs: 20, seed: 1 });
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    let bar = "arm_science: completed 10 (50%), aborted 10 (50%), not run 0 of 20 runs";
    assert!(h.query_all_by_label(bar).next().is_some());
    h.state_mut().push(raise_min_soc());
    h.run_steps(3);
    // The summary of the plan before the edit is not shown, and the panel
    // says why.
    assert!(h.state().campaign_result().is_none());
    assert!(h.query_all_by_label(bar).next().is_none());
    assert!(h.query_by_label("Lowest state of charge per run").is_none());
    assert!(
        h.query_by_label_contains(
            "The plan was edited after the last campaign (20 runs, seed 1): its summary no longer applies"
        )
        .is_some()
    );
    type_into(&mut h, "Runs", "20");
    h.get_by_label("Run").click();
    h.run_steps(3);
    let result = h.state().campaign_result().expect("the edited plan's");
    assert_eq!(result.runs(), 20);
    assert!(result.summary.limits.runs_breaking > 0, "950 Wh is broken");
    assert!(
        h.query_by_label_contains("The plan was edited after")
            .is_none()
    );
    assert!(h.query_by_label_contains("runs went below").is_some());
}

#[test]
fn an_edit_while_a_campaign_runs_stops_it() {
    let mut app = SolscopeApp::with_default_plan().unwrap();
    app.apply(UiCommand::ShowExecution.into());
    app.background = true;
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    h.state_mut().push(Command::RunCampaign {
        runs: 20_000,
        seed: 1,
    });
    h.run_steps(1);
    assert!(h.state().campaign_progress().is_some());
    let mut set = serde_json::Map::new();
    set.insert(
        "battery".into(),
        serde_json::json!({"capacity": 2400.0, "initial": 1850.0, "min_soc": 990.0}),
    );
    h.state_mut().push(Command::Edit {
        target: "plan".into(),
        set,
        description: "Lower min_soc".into(),
    });
    h.run_steps(2);
    // Its summary would be of the plan before the edit: it is stopped at once.
    assert!(h.state().campaign_progress().is_none());
    let stopped = h.state().campaign_stopped().expect("stopped");
    assert_eq!(stopped.why, solscope::state::StopReason::PlanEdited);
    assert!(stopped.done < stopped.runs);
    assert!(h.state().campaign_result().is_none());
    assert!(
        h.query_by_label_contains("The plan was edited while the campaign ran")
            .is_some()
    );
}

#[test]
fn a_plan_without_duration_models_cannot_run_a_campaign() {
    let mut app = tutorial();
    app.apply(UiCommand::ShowExecution.into());
    let h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    assert!(
        h.query_by_label_contains("This plan has no duration_model")
            .is_some()
    );
    assert!(h.get_by_label("Run").accesskit_node().is_disabled());
}

/// The default plan in a harness, its Gantt zoomed to `[from, to]`.
fn default_plan_over(from: f64, to: f64) -> egui_kittest::Harness<'static, SolscopeApp> {
    let mut app = SolscopeApp::with_default_plan().unwrap();
    app.apply(Command::SetAxis(solscope::state::TimeAxis::new(from, to)));
    harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap()
}

#[test]
fn the_flexibility_layer_toggles_by_checkbox_and_key() {
    let mut h = default_plan_over(50_000.0, 80_000.0);
    assert!(!h.state().persisted.hide_flex, "shown by default");
    assert!(h.state().flex().is_some(), "derived in the frame");
    let a = index(h.state(), "watson_pre_abrasion");
    let with_layer = h.state().gantt_bar(a).expect("drawn");
    h.get_by_label("Flexibility layer").click();
    h.run_steps(3);
    assert!(h.state().persisted.hide_flex);
    // Without the layer, bars pack by their own span again (fewer lanes).
    let without = h.state().gantt_bar(a).expect("drawn");
    assert!(without.top() <= with_layer.top());
    h.key_press(eframe::egui::Key::F);
    h.run_steps(3);
    assert!(!h.state().persisted.hide_flex);
    assert_eq!(h.state().gantt_bar(a), Some(with_layer));
}

#[test]
fn selecting_an_activity_shows_its_flexibility() {
    let view = View {
        select: Some("watson_pre_abrasion".into()),
        ..View::default()
    };
    let mut h = harness(
        SolscopeApp::with_default_plan().unwrap(),
        SNAPSHOT_SIZE.into(),
        &view,
    )
    .unwrap();
    // The same numbers as `solscope flex --text`.
    let text = solscope_engine::flex_text(&h.state().doc.plan, h.state().flex().unwrap());
    assert!(text.contains(
        "watson_pre_abrasion: scheduled at Sol 412 09:09:57 (t=57880); may start from Sol 412 08:55:22 (t=56980) \
         to Sol 412 10:42:25 (t=63580) (15 min earlier, 1 h 35 min later)."
    ));
    assert!(h.query_by_label("Flexibility").is_some());
    for line in [
        "Scheduled at Sol 412 09:09:57 (t=57880).",
        "May start from Sol 412 08:55:22 (t=56980) to Sol 412 10:42:25 (t=63580) (15 min earlier, 1 h 35 min later).",
        "Starts no earlier than 10 min after arm_unstow_412 starts.",
        "Starts no earlier than 10 min after fsw_housekeeping_412 starts.",
        "Starts no later than 40 min after arm_unstow_412 starts.",
        "Skipped once the earliest of Sol 412 10:42:25 (t=63580) and 40 min after arm_unstow_412 starts \
         has passed without it starting.",
        "Free slack (every check, others fixed): Sol 412 09:09:57 (t=57880) to Sol 412 09:19:41 (t=58480)",
        // The bundled plan's sol-413 drive is not dynamically controllable; the
        // WATSON image is not involved: one line, not the whole verdict.
        "The plan is not dynamically controllable, because of drive_413; this activity is not involved.",
    ] {
        assert!(h.query_by_label(line).is_some(), "missing: {line}");
    }
    assert!(
        h.query_by_label("NOT dynamically controllable. The constraints that make it so:")
            .is_none()
    );
    // Its dispatchable neighbours, to select.
    let fa = h
        .state()
        .flex()
        .unwrap()
        .activity(index(h.state(), "watson_pre_abrasion"))
        .unwrap()
        .clone();
    let unstow = index(h.state(), "arm_unstow_412");
    assert!(fa.neighbours.contains(&unstow));
    h.get_by_label("arm_unstow_412").click();
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.selected, Some(unstow));
    assert!(
        h.query_by_label(
            "May start from Sol 412 08:45:38 (t=56380) to Sol 412 10:13:13 (t=61780) (15 min earlier, 1 h 15 min later)."
        )
        .is_some()
    );
    // The drive itself shows the verdict in full.
    let drive = index(h.state(), "drive_413");
    h.state_mut().apply(Command::Select(Some(drive)));
    h.run_steps(3);
    for line in [
        "NOT dynamically controllable. The constraints that make it so:",
        "• drive_413 lasts 50 min to 1 h 35 min",
        "This activity is one of those involved.",
    ] {
        assert!(h.query_by_label(line).is_some(), "missing: {line}");
    }
    // A plan without uncertain durations has no verdict to show.
    let mut h = tutorial_with_selected("zcam_pano");
    h.run_steps(2);
    assert!(h.query_by_label("Flexibility").is_some());
    assert!(
        h.query_by_label_contains("dynamically controllable")
            .is_none()
    );
}

type H = egui_kittest::Harness<'static, SolscopeApp>;

/// The screen point of activity `a`'s bar shifted by `dt` seconds (x from its
/// drawn rect: its start and end are known times).
fn bar_point(h: &H, a: usize, dt: i64) -> eframe::egui::Pos2 {
    let r = h.state().gantt_bar(a).expect("bar drawn");
    let (s, e) = h.state().analysis.placement(a).unwrap();
    let px_per_s = r.width() / (e - s) as f32;
    r.center() + eframe::egui::vec2(dt as f32 * px_per_s, 0.0)
}

/// Presses on activity `a`'s bar and moves by `dt` seconds, without releasing.
fn drag_bar(h: &mut H, a: usize, dt: i64) -> eframe::egui::Pos2 {
    let from = bar_point(h, a, 0);
    let to = bar_point(h, a, dt);
    h.hover_at(from);
    h.run_steps(1);
    h.drag_at(from);
    h.run_steps(1);
    h.hover_at(eframe::egui::pos2((from.x + to.x) / 2.0, from.y));
    h.run_steps(1);
    h.hover_at(to);
    h.run_steps(2);
    to
}

#[test]
fn dragging_a_bar_inside_its_slack_previews_and_changes_nothing() {
    let mut h = default_plan_over(55_000.0, 72_000.0);
    let meda = index(h.state(), "meda_412_1200");
    let before = (h.state().doc.plan.clone(), h.state().revision);
    let placed = h.state().analysis.placement(meda);
    let axis = h.state().ui.nav.axis;
    // 15 min later: inside its free slack (67180-68980).
    let to = drag_bar(&mut h, meda, 900);
    assert!(
        h.query_by_label_contains("meda_412_1200 at")
            .is_some_and(|n| n
                .accesskit_node()
                .value()
                .unwrap_or_default()
                .contains("inside its free slack")),
        "the preview says where it is"
    );
    assert_eq!(h.state().ui.nav.selected, Some(meda), "dragging selects it");
    assert_eq!(h.state().ui.nav.axis, axis, "a bar drag does not pan");
    h.drop_at(to);
    h.run_steps(3);
    assert!(h.state().ui.messages.pin.is_none(), "nothing to confirm");
    assert_eq!((h.state().doc.plan.clone(), h.state().revision), before);
    assert_eq!(h.state().analysis.placement(meda), placed);
    // Inside [lb, ub] but not its free slack: said so, nothing changes either.
    let watson = index(h.state(), "watson_pre_abrasion");
    let to = drag_bar(&mut h, watson, 3000);
    assert!(
        h.query_by_label_contains("watson_pre_abrasion at Sol 412 09:58:37 (t=60880)")
            .is_some_and(|n| n
                .accesskit_node()
                .value()
                .unwrap_or_default()
                .contains("inside its bounds [lb, ub] only")),
        "bounds only"
    );
    h.drop_at(to);
    h.run_steps(3);
    assert!(h.state().ui.messages.pin.is_none());
    assert_eq!((h.state().doc.plan.clone(), h.state().revision), before);
}

#[test]
fn dropping_a_bar_outside_its_slack_offers_to_pin_it_and_undo_restores() {
    let mut h = default_plan_over(55_000.0, 72_000.0);
    let meda = index(h.state(), "meda_412_1200");
    let before = h.state().doc.plan.clone();
    let placed = h.state().analysis.placement(meda);
    // 50 min later: past its window (it ends at 68980).
    let to = drag_bar(&mut h, meda, 3000);
    assert!(
        h.query_by_label_contains("outside its slack: release to pin it here")
            .is_some()
    );
    h.drop_at(to);
    h.run_steps(3);
    let offer = h.state().ui.messages.pin.expect("offered");
    assert_eq!(offer.activity, meda);
    assert!((70_100..=70_260).contains(&offer.start), "{}", offer.start);
    assert_eq!(
        h.state().doc.plan,
        before,
        "nothing changes before confirming"
    );
    // Keeping the schedule forgets the offer.
    h.get_by_label("Keep the schedule").click();
    h.run_steps(3);
    assert!(h.state().ui.messages.pin.is_none());
    assert_eq!(h.state().doc.plan, before);
    let to = drag_bar(&mut h, meda, 3000);
    h.drop_at(to);
    h.run_steps(3);
    let offer = h.state().ui.messages.pin.expect("offered again");
    h.get_by_label("Pin and reschedule").click();
    h.run_steps(3);
    let act = &h.state().doc.plan.activities[meda];
    let w = act.windows.as_ref().expect("windows")[0];
    assert_eq!(act.windows.as_ref().map(Vec::len), Some(1));
    assert_eq!(
        (w.start, w.end, w.preferred),
        (offer.start, offer.start, Some(offer.start))
    );
    assert_eq!(
        h.state().analysis.placement(meda).map(|p| p.0),
        Some(offer.start),
        "rescheduled there"
    );
    assert!(h.state().doc.dirty);
    assert!(h.query_by_label_contains("Pin meda_412_1200 at").is_some());
    h.key_press_modifiers(eframe::egui::Modifiers::COMMAND, eframe::egui::Key::Z);
    h.run_steps(3);
    assert_eq!(h.state().doc.plan, before);
    assert_eq!(h.state().analysis.placement(meda), placed);
}

#[test]
fn the_flexible_schedule_is_derived_off_the_frame_per_revision() {
    let mut app = SolscopeApp::with_default_plan().unwrap();
    app.background = true;
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    // First without free slack (fast), then with it.
    wait_until(&mut h, "the flexible schedule", |app| app.flex().is_some());
    wait_until(&mut h, "its free slack", |app| {
        app.flex()
            .is_some_and(|f| f.activities.iter().all(|a| a.free_slack.is_some()))
    });
    let direct = solscope_engine::flex(&h.state().doc.plan, &h.state().analysis.schedule);
    assert_eq!(h.state().flex(), Some(&direct));
    // After an edit the old one is not shown; the new revision's arrives.
    let meda = index(h.state(), "meda_412_1200");
    h.state_mut().push(Command::Pin {
        activity: meda,
        start: 70_000,
    });
    h.run_steps(1);
    if let Some(f) = h.state().flex() {
        assert_eq!(f.activity(meda).map(|fa| fa.start.nom), Some(70_000));
    }
    wait_until(&mut h, "the edited plan's", |app| app.flex().is_some());
    let fa = h.state().flex().unwrap().activity(meda).unwrap();
    assert_eq!(
        (fa.start.lb, fa.start.nom, fa.start.ub),
        (70_000, 70_000, 70_000)
    );
}

#[test]
fn an_activity_fixed_in_time_outlines_no_unrelated_neighbours() {
    let view = View {
        select: Some("uhf_mro_411_eve".into()),
        ..View::default()
    };
    let h = harness(
        SolscopeApp::with_default_plan().unwrap(),
        SNAPSHOT_SIZE.into(),
        &view,
    )
    .unwrap();
    let uhf = index(h.state(), "uhf_mro_411_eve");
    // Nothing propagates through the horizon start: a pass fixed in time has no
    // neighbours there.
    let listed = &h.state().flex().unwrap().activity(uhf).unwrap().neighbours;
    assert!(listed.is_empty(), "{listed:?}");
    assert!(
        h.query_by_label(
            "May start from Sol 411 18:39:14 (t=4200) to Sol 411 18:39:14 (t=4200) (0 s earlier, 0 s later)."
        )
        .is_some()
    );
    assert!(
        h.query_by_label("Dispatchable neighbours (click to select)")
            .is_none()
    );
}

#[test]
fn a_controllable_plan_shows_the_waits_of_the_selected_activity() {
    let mut app = uncertain_drive();
    let post = index(&app, "post_drive_imaging");
    app.apply(Command::Select(Some(post)));
    let h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    for line in [
        "May start from Sol 0 10:58:33 (t=4600) to Sol 0 12:16:25 (t=9400) (30 min earlier, 50 min later).",
        "Starts no earlier than when drive ends.",
        "Starts no later than 30 min after drive ends.",
        "Skipped once the earliest of Sol 0 12:16:25 (t=9400) and 30 min after drive ends has passed \
         without it starting.",
        "Dynamically controllable: every outcome of the uncertain durations can be met.",
        "Waits until drive ends or 1 h 50 min after it starts.",
    ] {
        assert!(h.query_by_label(line).is_some(), "missing: {line}");
    }
}

// ---- Keyboard, editing, files and one culprit list ----

type Hs = egui_kittest::Harness<'static, SolscopeApp>;

/// The label of the step row for step `k` of the tutorial plan, up to the
/// activity's id (`step 5: id`).
fn step_text(h: &Hs, k: usize) -> String {
    let a = h.state().analysis.schedule.steps[k - 1].activity;
    format!("step {k}: {}", h.state().doc.plan.activities[a].id)
}

#[test]
fn every_key_press_counts_also_several_in_one_frame() {
    let mut h = tutorial_at_step_zero();
    // Five presses arrive before the next frame (30 ms apart at 60 fps).
    for _ in 0..5 {
        h.key_press(eframe::egui::Key::ArrowRight);
    }
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.step, 5);
    assert!(h.query_by_label_contains(&step_text(&h, 5)).is_some());
    for _ in 0..2 {
        h.key_press(eframe::egui::Key::ArrowLeft);
    }
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.step, 3);
}

#[test]
fn the_step_label_follows_the_slider_in_the_same_frame() {
    let mut h = tutorial_at_step_zero();
    // One pass per frame, as most frames are: a second pass (egui's discard of
    // a frame whose layout changed) would hide a label one frame behind.
    h.ctx
        .options_mut(|o| o.max_passes = std::num::NonZeroUsize::MIN);
    let n = h.state().analysis.steps();
    let rail = h
        .query_all_by_label("Step")
        .find(|n| n.accesskit_node().role() == eframe::egui::accesskit::Role::Slider)
        .expect("the step slider")
        .rect();
    // The far right end of the rail: the last step.
    let end = eframe::egui::pos2(rail.left() + 318.0, rail.center().y);
    h.hover_at(end);
    h.step();
    // One frame (kittest runs one per event): the press moves the slider, and
    // the label drawn in that frame shows the step it moved to.
    h.drag_at(end);
    h.step();
    assert_eq!(
        h.state().ui.nav.step,
        n,
        "the slider moved to the last step"
    );
    assert!(
        h.query_by_label_contains(&step_text(&h, n)).is_some(),
        "the label shows the step of the slider in the frame it moved"
    );
    h.drop_at(end);
    h.step();
}

#[test]
fn up_and_down_move_the_selection_through_the_list() {
    let mut h = tutorial_with_selected("sky_flats_mast_busy");
    let steps: Vec<usize> = h
        .state()
        .analysis
        .schedule
        .steps
        .iter()
        .map(|s| s.activity)
        .collect();
    let a = index(h.state(), "sky_flats_mast_busy");
    let i = steps.iter().position(|&b| b == a).unwrap();
    h.key_press(eframe::egui::Key::ArrowDown);
    h.key_press(eframe::egui::Key::ArrowDown);
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.selected, Some(steps[i + 2]));
    h.key_press(eframe::egui::Key::ArrowUp);
    h.run_steps(3);
    let b = steps[i + 1];
    assert_eq!(h.state().ui.nav.selected, Some(b));
    // The inspector shows the activity selected by key.
    let id = h.state().doc.plan.activities[b].id.clone();
    let label = match &h.state().doc.plan.activities[b].name {
        Some(name) => format!("{id} — {name}"),
        None => id.clone(),
    };
    assert!(h.query_by_label(&label).is_some(), "{label}");
    // The list filtered: Up and Down stay inside what it shows.
    h.state_mut().push(Command::SetFilter("sky_flats".into()));
    h.state_mut().push(Command::Select(None));
    h.run_steps(2);
    h.key_press(eframe::egui::Key::ArrowDown);
    h.run_steps(3);
    let sel = h.state().ui.nav.selected.expect("selected");
    assert!(h.state().doc.plan.activities[sel].id.contains("sky_flats"));
}

#[test]
fn next_and_previous_failure_by_button_and_key() {
    let mut h = tutorial_at_step_zero();
    let failed: Vec<(usize, usize)> = h
        .state()
        .analysis
        .schedule
        .steps
        .iter()
        .filter(|s| s.outcome.placement().is_none() && s.outcome.status() == "failed")
        .map(|s| (s.step, s.activity))
        .collect();
    assert!(failed.len() >= 2, "the tutorial plan has failures");
    assert!(
        h.get_by_label("<< Previous failure")
            .accesskit_node()
            .is_disabled(),
        "no failure before step 0"
    );
    h.get_by_label("Next failure >>").click();
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.step, failed[0].0);
    assert_eq!(h.state().ui.nav.selected, Some(failed[0].1));
    assert!(h.query_by_label("Why it did not schedule").is_some());
    h.key_press_modifiers(
        eframe::egui::Modifiers::SHIFT,
        eframe::egui::Key::ArrowRight,
    );
    h.run_steps(3);
    assert_eq!(
        h.state().ui.nav.step,
        failed[1].0,
        "Shift+Right: next failure"
    );
    assert_eq!(h.state().ui.nav.selected, Some(failed[1].1));
    h.key_press_modifiers(eframe::egui::Modifiers::SHIFT, eframe::egui::Key::ArrowLeft);
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.step, failed[0].0, "Shift+Left: previous");
    h.get_by_label("<< Previous failure").click();
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.step, failed[0].0, "none before the first");
}

/// The default plan with drill_core_413 selected, its windows field holding
/// `text` and Enter pressed.
fn drill_core_windows(text: &str) -> Hs {
    let view = View {
        select: Some("drill_core_413".into()),
        ..View::default()
    };
    let mut h = harness(
        SolscopeApp::with_default_plan().unwrap(),
        SNAPSHOT_SIZE.into(),
        &view,
    )
    .unwrap();
    click(&mut h, "Advanced (JSON)");
    show(&mut h, "windows");
    type_into(&mut h, "windows", text);
    h.key_press(eframe::egui::Key::Enter);
    h.run_steps(3);
    h
}

#[test]
fn a_long_error_wraps_inside_the_inspector() {
    let mut h = drill_core_windows(r#"[{"start":150000,"end":140000}]"#);
    h.get_by_label_contains("must be >= start").scroll_to_me();
    h.run_steps(2);
    let err = h.get_by_label_contains("must be >= start").rect();
    let field = h.get_by_label("windows").rect();
    assert!(
        err.right() <= SNAPSHOT_SIZE[0],
        "the message ends inside the window: {err:?}"
    );
    assert!(
        err.right() <= field.right() + 1.0,
        "wrapped at the field's width: {err:?} vs {field:?}"
    );
    assert!(err.height() > 2.0 * 14.0, "on several lines: {err:?}");
}

#[test]
fn an_edit_that_changes_nothing_is_not_recorded() {
    let app = SolscopeApp::with_default_plan().unwrap();
    let a = index(&app, "drill_core_413");
    let w = &app.doc.plan.activities[a].windows;
    let same = serde_json::to_value(w).unwrap().to_string();
    // The same windows, written differently: another text, the same plan.
    let h = drill_core_windows(&same.replace(',', ", "));
    assert!(!h.state().doc.dirty);
    assert!(h.query_by_label_contains("(unsaved)").is_none());
    assert!(h.get_by_label("Undo").accesskit_node().is_disabled());
    assert!(h.query_by_label_contains("the plan is unchanged").is_some());
}

#[test]
fn undoing_back_to_the_saved_plan_clears_unsaved() {
    let mut h = tutorial_with_selected("sky_flats_mast_busy");
    h.get_by_label_contains("Apply: Widen window 1").click();
    h.run_steps(3);
    assert!(h.query_by_label_contains("(unsaved)").is_some());
    h.get_by_label("Undo").click();
    h.run_steps(3);
    assert!(h.query_by_label_contains("(unsaved)").is_none());
    h.get_by_label("Redo").click();
    h.run_steps(3);
    assert!(h.query_by_label_contains("(unsaved)").is_some());
    // Saved there: undo is unsaved again, redo back is saved.
    let path = scratch_file("undo-saved", "plan.json", "");
    h.state_mut().push(Command::SaveTo(path));
    h.run_steps(3);
    assert!(h.query_by_label_contains("(unsaved)").is_none());
    h.get_by_label("Undo").click();
    h.run_steps(3);
    assert!(h.query_by_label_contains("(unsaved)").is_some());
    h.get_by_label("Redo").click();
    h.run_steps(3);
    assert!(h.query_by_label_contains("(unsaved)").is_none());
}

#[test]
fn the_banner_s_arrows_are_glyphs_the_font_has() {
    let mut app = SolscopeApp::with_default_plan().unwrap();
    let a = index(&app, "drill_core_413");
    let start = app.analysis.placement(a).expect("placed").0;
    app.apply(Command::Pin {
        activity: a,
        start: start + 600,
    });
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    h.run_steps(2);
    let banner = h
        .state()
        .ui
        .messages
        .banner
        .clone()
        .expect("banner")
        .summary();
    assert!(h.query_by_label(&banner).is_some(), "shown: {banner}");
    assert!(banner.contains('→'), "{banner}");
    let font = eframe::egui::FontId::proportional(14.0);
    let missing: Vec<char> = banner
        .chars()
        .filter(|&c| !h.ctx.fonts_mut(|f| f.has_glyph(&font, c)))
        .collect();
    assert!(missing.is_empty(), "no glyph for {missing:?} in {banner}");
}

#[test]
fn with_no_file_dialog_open_asks_for_a_typed_path() {
    let mut h = harness(tutorial(), SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    // What the host sends when no file dialog service answers.
    h.state_mut().push(Command::AskPath {
        dialog: Dialog::Open,
        why: "No file dialog is available here".into(),
    });
    h.run_steps(3);
    assert!(h.query_by_label("Open a plan").is_some());
    assert!(
        h.query_by_label("No file dialog is available here")
            .is_some()
    );
    let pitfall = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/examples/pitfall.json");
    type_into(&mut h, "Path", pitfall);
    h.get_by_label("Open").click();
    h.run_steps(3);
    assert_eq!(
        h.state().doc.plan.activities.len(),
        2,
        "pitfall.json opened"
    );
    assert!(
        h.query_by_label("Open a plan").is_none(),
        "the prompt is gone"
    );
    assert_eq!(
        h.state().persisted.recent.first().map(|p| p.as_path()),
        Some(std::path::Path::new(pitfall))
    );
}

#[test]
fn the_save_prompt_suggests_a_file_name_and_saves_there() {
    let mut h = tutorial_with_selected("sky_flats_mast_busy");
    h.get_by_label_contains("Apply: Widen window 1").click();
    h.run_steps(3);
    h.state_mut().push(Command::AskPath {
        dialog: Dialog::SaveAs,
        why: "No file dialog is available here".into(),
    });
    h.run_steps(3);
    assert!(h.query_by_label("Save the plan as").is_some());
    // Named after the plan (it has no file yet), in the working directory.
    let suggested = h.state().suggested_path(Dialog::SaveAs);
    let name = suggested
        .file_name()
        .unwrap()
        .to_string_lossy()
        .into_owned();
    assert!(
        name.ends_with(".json") && name.len() > ".json".len(),
        "{name}"
    );
    assert_eq!(h.state().ui.text.path_text, suggested.display().to_string());
    let path = scratch_file("save-prompt", "x.json", "").with_file_name("typed");
    type_into(&mut h, "Path", &path.display().to_string());
    h.get_by_label("Save").click();
    h.run_steps(3);
    let saved = path.with_extension("json");
    assert!(saved.exists(), "the extension is added");
    assert!(!h.state().doc.dirty);
    // Exports are suggested beside the plan, named after it.
    let csv = h.state().suggested_path(Dialog::ExportScheduleCsv);
    assert_eq!(csv, saved.with_file_name("typed-schedule.csv"));
}

#[test]
fn the_guard_saves_and_opens() {
    let path = scratch_file(
        "save-and-open",
        "tutorial.json",
        &std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/assets/tutorial-plan.json"
        ))
        .unwrap(),
    );
    let text = std::fs::read_to_string(&path).unwrap();
    let app = SolscopeApp::from_text(&text, Some(path.clone())).unwrap();
    let view = View {
        select: Some("sky_flats_mast_busy".into()),
        ..View::default()
    };
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &view).unwrap();
    h.get_by_label_contains("Apply: Widen window 1").click();
    h.run_steps(3);
    let edited = h.state().doc.plan.clone();
    let other = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/examples/pitfall.json");
    h.state_mut().push(Command::Open(other.into()));
    h.run_steps(3);
    h.get_by_label("Save and open").click();
    h.run_steps(3);
    assert_eq!(
        h.state().doc.plan.activities.len(),
        2,
        "pitfall.json opened"
    );
    let saved = solscope_engine::load_plan(&std::fs::read_to_string(&path).unwrap())
        .unwrap()
        .plan;
    assert_eq!(saved, edited, "the edits were saved first");
}

#[test]
fn the_guard_saves_a_plan_without_a_file_and_quits() {
    let mut h = tutorial_with_selected("sky_flats_mast_busy");
    h.get_by_label_contains("Apply: Widen window 1").click();
    h.run_steps(3);
    h.state_mut().push(UiCommand::Quit.into());
    h.run_steps(3);
    h.get_by_label("Save and quit").click();
    h.run_steps(3);
    assert_eq!(
        h.state_mut().take_dialog(),
        Some(Dialog::SaveAs),
        "asks where"
    );
    assert!(!h.state().quit_confirmed(), "not before it is saved");
    let path = scratch_file("save-and-quit", "x.json", "").with_file_name("saved.json");
    h.state_mut().push(Command::Chosen {
        dialog: Dialog::SaveAs,
        path: path.clone(),
    });
    h.run_steps(3);
    assert!(path.exists());
    assert!(h.state().quit_confirmed());
}

#[test]
fn a_plan_opened_from_the_command_line_is_in_recent() {
    let pitfall = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/examples/pitfall.json");
    let mut app = SolscopeApp::open_or_default(Some(std::path::Path::new(pitfall))).unwrap();
    // What the host does at start-up with the settings it restored.
    let older = solscope::state::Persisted {
        recent: vec!["/elsewhere/older.json".into()],
        ..Default::default()
    };
    app.restore_persisted(older);
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    h.get_by_label("File").click();
    h.run_steps(3);
    assert!(h.query_by_label(pitfall).is_some(), "listed under Recent");
    assert!(h.query_by_label("/elsewhere/older.json").is_some());
    assert_eq!(h.state().persisted.recent[0], std::path::Path::new(pitfall));
}

#[test]
fn the_schedule_exports_as_csv_from_the_file_menu() {
    let mut h = harness(tutorial(), SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    h.get_by_label("File").click();
    h.run_steps(3);
    h.get_by_label("Export schedule CSV…").click();
    h.run_steps(3);
    assert_eq!(h.state_mut().take_dialog(), Some(Dialog::ExportScheduleCsv));
    let path = scratch_file("csv", "x.json", "").with_file_name("schedule");
    h.state_mut().push(Command::Chosen {
        dialog: Dialog::ExportScheduleCsv,
        path: path.clone(),
    });
    h.run_steps(3);
    let csv = std::fs::read_to_string(path.with_extension("csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert!(lines[0].starts_with("step,id,name,status,start,end"));
    assert_eq!(lines.len(), h.state().analysis.steps() + 1);
    let failed = h.state().analysis.failed();
    assert_eq!(
        lines.iter().filter(|l| l.contains(",failed,")).count(),
        failed
    );
}

#[test]
fn the_inspector_s_involved_list_is_the_explanation_s_culprits() {
    let view = View {
        select: Some("moxie_run_413".into()),
        ..View::default()
    };
    let mut h = harness(
        SolscopeApp::with_default_plan().unwrap(),
        SNAPSHOT_SIZE.into(),
        &view,
    )
    .unwrap();
    let a = index(h.state(), "moxie_run_413");
    let ex = h.state_mut().explanation_for(a).cloned().expect("failed");
    let named = solscope_engine::involved(&ex);
    assert!(
        named.len() < ex.culprits.len(),
        "some culprits are not named"
    );
    let plan = h.state().doc.plan.clone();
    let link = |c: &solscope_engine::Culprit| {
        format!(
            "{} (step {}, {})",
            plan.activities[c.activity].id,
            c.step,
            c.blame.name()
        )
    };
    for c in named {
        assert!(h.query_by_label(&link(c)).is_some(), "{}", link(c));
    }
    for c in &ex.culprits[named.len()..] {
        assert!(
            h.query_by_label(&link(c)).is_none(),
            "not named: {}",
            link(c)
        );
    }
    // The inspector's own sentence names the same ones (by name).
    let sentence = |c: &solscope_engine::Culprit| {
        format!(
            "{} (step {}, {})",
            plan.activities[c.activity].display_name(),
            c.step,
            c.blame.name()
        )
    };
    let text = format!(
        "Involved: {}.",
        named.iter().map(sentence).collect::<Vec<_>>().join(", ")
    );
    assert!(h.query_by_label(&text).is_some(), "{text}");
}

/// Replaces the text of the time range's "from" and "to" fields.
fn type_range(h: &mut H, from: &str, to: &str) {
    for (label, text) in [("from", from), ("to", to)] {
        h.get_by_label(label).focus();
        h.run_steps(1);
        h.key_press_modifiers(eframe::egui::Modifiers::COMMAND, eframe::egui::Key::A);
        h.get_by_label(label).type_text(text);
        h.run_steps(1);
    }
}

#[test]
fn a_time_range_is_typed_in_sols_and_local_time() {
    let mut h = harness(
        SolscopeApp::with_default_plan().unwrap(),
        SNAPSHOT_SIZE.into(),
        &View::default(),
    )
    .unwrap();
    // The fields show the visible range as sol and local time.
    assert_eq!(
        h.state().ui.text.range_text,
        [
            "Sol 411 17:31:06".to_string(),
            "Sol 413 17:31:06".to_string()
        ]
    );
    type_range(&mut h, "Sol 412 08:00", "12:00");
    h.get_by_label("Apply range").click();
    h.run_steps(3);
    // Sol 412 starts at plan time 23975 (local midnight): 08:00 LMST is 29592
    // plan seconds later (28800 LMST s of a 88775 s sol, rounded up), 12:00
    // LMST 44388; the end without a sol is in the start's sol.
    let axis = h.state().ui.nav.axis;
    assert_eq!((axis.start, axis.end), (53_567.0, 68_363.0));
    assert_eq!(
        h.state().ui.text.range_text,
        [
            "Sol 412 08:00:00".to_string(),
            "Sol 412 12:00:00".to_string()
        ]
    );
    // The plan seconds of the range, on hover.
    h.get_by_label("to").hover();
    h.run_steps(60);
    assert!(h.query_by_label("t=68363 s").is_some());
    // Plan seconds still work, and a bad time says what to type.
    type_range(&mut h, "60000", "Sol 412 25:00");
    h.get_by_label("Apply range").click();
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.axis, axis, "nothing applied");
    assert!(
        h.state()
            .ui
            .messages
            .error
            .as_deref()
            .is_some_and(|e| e.contains("Sol 413 08:00")),
        "{:?}",
        h.state().ui.messages.error
    );
}

#[test]
fn hovering_a_bar_says_what_it_is_when_and_for_how_long() {
    let mut h = default_plan_over(55_000.0, 72_000.0);
    let meda = index(h.state(), "meda_412_1200");
    let at = bar_point(&h, meda, 0);
    h.hover_at(at);
    // Tooltips show once the pointer rests (egui's tooltip delay).
    h.run_steps(60);
    let tip = h
        .query_by_label_contains("meda_412_1200 — MEDA")
        .and_then(|n| n.accesskit_node().value())
        .expect("a tooltip at the bar");
    assert!(
        tip.contains(
            "\nscheduled Sol 412 11:40:49 (t=67180) – Sol 412 12:10:00 (t=68980) (30 min)\nholds meda\n"
        ),
        "who, when, how long, what it holds: {tip}"
    );
    // The general hint is for places where no bar is.
    assert!(
        h.query_by_label_contains("Click a bar to inspect it")
            .is_none()
    );
}

// ---- Linked navigation: back and forward, search, filters ----

/// The default plan's failed MOXIE run selected, in a harness.
fn moxie_selected() -> H {
    let view = View {
        select: Some("moxie_run_413".into()),
        ..View::default()
    };
    harness(
        SolscopeApp::with_default_plan().unwrap(),
        SNAPSHOT_SIZE.into(),
        &view,
    )
    .unwrap()
}

/// `(selected, step)` of the app in `h`.
fn at(h: &H) -> (Option<usize>, usize) {
    (h.state().ui.nav.selected, h.state().ui.nav.step)
}

#[test]
fn following_a_culprit_then_back_and_forward() {
    let mut h = moxie_selected();
    let moxie = index(h.state(), "moxie_run_413");
    let drive = index(h.state(), "drive_412");
    let last = h.state().analysis.steps();
    assert_eq!(at(&h), (Some(moxie), last));
    assert!(
        h.get_by_label("Forward").accesskit_node().is_disabled(),
        "nothing ahead yet"
    );
    // A culprit in the inspector's Involved list: selected at its step.
    h.get_by_label("drive_412 (step 21, min_soc)").click();
    h.run_steps(3);
    assert_eq!(at(&h), (Some(drive), 21));
    // Back returns to the selection and the step before the link.
    h.get_by_label("Back").click();
    h.run_steps(3);
    assert_eq!(at(&h), (Some(moxie), last));
    assert!(h.query_by_label("Why it did not schedule").is_some());
    h.get_by_label("Forward").click();
    h.run_steps(3);
    assert_eq!(at(&h), (Some(drive), 21), "Forward redoes it");
    // The keys do the same.
    h.key_press_modifiers(eframe::egui::Modifiers::ALT, eframe::egui::Key::ArrowLeft);
    h.run_steps(3);
    assert_eq!(at(&h), (Some(moxie), last), "Alt+Left");
    h.key_press_modifiers(eframe::egui::Modifiers::ALT, eframe::egui::Key::ArrowRight);
    h.run_steps(3);
    assert_eq!(at(&h), (Some(drive), 21), "Alt+Right");
    // Back, then another link: what was ahead is forgotten.
    h.key_press_modifiers(eframe::egui::Modifiers::ALT, eframe::egui::Key::ArrowLeft);
    h.run_steps(3);
    h.get_by_label("drill_core_413 (step 35, min_soc)").click();
    h.run_steps(3);
    assert_eq!(at(&h), (Some(index(h.state(), "drill_core_413")), 35));
    assert!(h.get_by_label("Forward").accesskit_node().is_disabled());
    h.get_by_label("Back").click();
    h.run_steps(3);
    assert_eq!(at(&h), (Some(moxie), last));
}

#[test]
fn next_failure_and_a_click_in_the_list_are_links_up_and_down_are_not() {
    let mut h = tutorial_at_step_zero();
    h.get_by_label("Next failure >>").click();
    h.run_steps(3);
    let failure = at(&h);
    assert!(failure.0.is_some());
    // Down twice moves the selection without a way back to each row.
    h.key_press(eframe::egui::Key::ArrowDown);
    h.key_press(eframe::egui::Key::ArrowDown);
    h.run_steps(3);
    assert_ne!(at(&h), failure);
    h.key_press_modifiers(eframe::egui::Modifiers::ALT, eframe::egui::Key::ArrowLeft);
    h.run_steps(3);
    assert_eq!(at(&h), (None, 0), "back to before Next failure");
    h.key_press_modifiers(eframe::egui::Modifiers::ALT, eframe::egui::Key::ArrowRight);
    h.run_steps(3);
    assert_ne!(at(&h), (None, 0));
    // A click in the list is one.
    let a = index(h.state(), "sky_flats_mast_busy");
    let before = at(&h);
    let step = h.state().analysis.schedule.step_of(a).unwrap().step;
    h.get_by_label(&format!("x {step:>3} sky_flats_mast_busy"))
        .click();
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.selected, Some(a));
    h.get_by_label("Back").click();
    h.run_steps(3);
    assert_eq!(at(&h), before);
}

#[test]
fn selecting_an_off_screen_activity_brings_it_into_view_and_back_restores_the_range() {
    // Zoomed into the morning of sol 412.
    let mut h = default_plan_over(50_000.0, 60_000.0);
    let drive = index(h.state(), "drive_413");
    let (s, e) = h.state().analysis.placement(drive).unwrap();
    assert!(s > 60_000, "the sol-413 drive is out of view");
    // Selected from the Gantt, the list or the inspector alike (the list's
    // row is out of its view).
    h.state_mut().push(Command::Select(Some(drive)));
    h.run_steps(3);
    let axis = h.state().ui.nav.axis;
    assert!(
        axis.start < s as f64 && (e as f64) < axis.end,
        "{axis:?} shows [{s}, {e}]"
    );
    assert_eq!(axis.span(), 10_000.0, "panned, not zoomed");
    let clock = h.state().doc.plan.local_time;
    assert_eq!(
        h.state().ui.text.range_text[0],
        solscope_engine::format_local(&clock, axis.start.round() as i64),
        "the range fields follow"
    );
    assert!(h.state().gantt_bar(drive).is_some(), "its bar is drawn");
    let step = h.state().analysis.schedule.step_of(drive).unwrap().step;
    assert!(
        h.query_by_label(&format!("+ {step:>3} drive_413"))
            .is_some(),
        "the list scrolled to its row"
    );
    // Back: the range as it was.
    h.get_by_label("Back").click();
    h.run_steps(3);
    let axis = h.state().ui.nav.axis;
    assert_eq!((axis.start, axis.end), (50_000.0, 60_000.0));
    assert_eq!(h.state().ui.nav.selected, None);
    // A failed activity is shown by its windows: one of them comes into view.
    let moxie = index(h.state(), "moxie_run_413");
    h.state_mut().push(Command::Select(Some(moxie)));
    h.run_steps(3);
    let axis = h.state().ui.nav.axis;
    let windows = h.state().doc.plan.activities[moxie]
        .windows
        .clone()
        .expect("windows");
    assert!(
        windows
            .iter()
            .any(|w| (w.start as f64) < axis.end && (w.end as f64) > axis.start),
        "{axis:?} shows a window of {windows:?}"
    );
}

#[test]
fn ctrl_f_searches_the_list_and_highlights_the_gantt() {
    let mut h = harness(
        SolscopeApp::with_default_plan().unwrap(),
        SNAPSHOT_SIZE.into(),
        &View::default(),
    )
    .unwrap();
    h.key_press_modifiers(eframe::egui::Modifiers::COMMAND, eframe::egui::Key::F);
    h.run_steps(2);
    assert!(h.get_by_label("Search").is_focused(), "Ctrl+F focuses it");
    h.get_by_label("Search").type_text("MEDA");
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.filter.search, "MEDA");
    let plan = h.state().doc.plan.clone();
    let is_match = |a: usize| {
        let act = &plan.activities[a];
        act.id.contains("meda") || act.display_name().to_lowercase().contains("meda")
    };
    let shown = h.state_mut().list_shown();
    let matches = (0..plan.activities.len()).filter(|&a| is_match(a)).count();
    assert!(matches >= 10);
    assert_eq!(shown.len(), matches);
    assert!(shown.iter().all(|&a| is_match(a)));
    // The list's rows are the matches (all in view).
    let row = |h: &H, a: usize| {
        let step = h.state().analysis.schedule.step_of(a).unwrap();
        let mark = match step.outcome.status() {
            "scheduled" => "+",
            "failed" => "x",
            _ => "-",
        };
        format!("{mark} {:>3} {}", step.step, plan.activities[a].id)
    };
    for &a in &shown {
        assert!(h.query_by_label(&row(&h, a)).is_some(), "{}", row(&h, a));
    }
    let drive = index(h.state(), "drive_413");
    assert!(h.query_by_label(&row(&h, drive)).is_none(), "filtered out");
    assert!(
        h.query_by_label(&format!("{matches} of {} shown", plan.activities.len()))
            .is_some()
    );
    // The Gantt outlines the matches and fades the rest.
    let looks = h.state().gantt_looks().to_vec();
    let highlighted: Vec<usize> = looks
        .iter()
        .filter(|l| l.1 == Look::Highlighted)
        .map(|l| l.0)
        .collect();
    let dimmed: Vec<usize> = looks
        .iter()
        .filter(|l| l.1 == Look::Dimmed)
        .map(|l| l.0)
        .collect();
    assert!(
        shown.iter().all(|a| highlighted.contains(a)),
        "every match drawn"
    );
    assert!(highlighted.iter().all(|&a| is_match(a)));
    assert!(!dimmed.is_empty() && dimmed.iter().all(|&a| !is_match(a)));
    assert!(looks.iter().all(|l| l.1 != Look::Plain));
    // Enter selects the first match, and the field keeps the keyboard: Enter
    // again the next.
    h.key_press(eframe::egui::Key::Enter);
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.selected, Some(shown[0]));
    assert!(h.get_by_label("Search").is_focused());
    h.key_press(eframe::egui::Key::Enter);
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.selected, Some(shown[1]));
    assert!(
        h.query_by_label(&format!(
            "2 of {matches} ({} in all)",
            plan.activities.len()
        ))
        .is_some()
    );
    // Previous match wraps round to the last.
    h.get_by_label("Previous match").click();
    h.get_by_label("Previous match").click();
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.selected, shown.last().copied());
    // Cleared: the whole list, the Gantt plain.
    h.get_by_label("Clear filters").click();
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.filter, ListFilter::default());
    assert!(h.state().gantt_looks().iter().all(|l| l.1 == Look::Plain));
}

#[test]
fn the_status_filter_lists_one_status_and_keeps_the_selection_in_view() {
    let mut h = harness(tutorial(), SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    let zcam = index(h.state(), "zcam_pano");
    h.state_mut().push(Command::Select(Some(zcam)));
    h.run_steps(3);
    h.get_by_label("Status").click();
    h.run_steps(2);
    h.get_by_label("Failed").click();
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.filter.status, Some(StatusFilter::Failed));
    let failed: Vec<usize> = h
        .state()
        .analysis
        .schedule
        .steps
        .iter()
        .filter(|s| s.outcome.status() == "failed")
        .map(|s| s.activity)
        .collect();
    assert_eq!(h.state_mut().list_shown(), failed);
    for &a in &failed {
        let step = h.state().analysis.schedule.step_of(a).unwrap().step;
        let id = &h.state().doc.plan.activities[a].id;
        assert!(h.query_by_label(&format!("x {step:>3} {id}")).is_some());
    }
    // The selection, scheduled, is hidden by the filter: pinned above the list.
    assert!(
        h.query_by_label("Selected (hidden by the filters):")
            .is_some()
    );
    let step = h.state().analysis.schedule.step_of(zcam).unwrap().step;
    assert!(
        h.query_by_label(&format!("+ {step:>3} zcam_pano"))
            .is_some()
    );
    // Before step 1 nothing has failed yet.
    h.key_press(eframe::egui::Key::Home);
    h.run_steps(3);
    assert!(h.state_mut().list_shown().is_empty());
    assert!(h.query_by_label("No activity matches.").is_some());
    h.get_by_label("Clear filters").click();
    h.run_steps(3);
    assert_eq!(h.state().ui.nav.filter.status, None);
    assert!(
        h.query_by_label("Selected (hidden by the filters):")
            .is_none()
    );
}

/// The default plan with activity `id` selected, in a harness.
fn default_with_selected(id: &str) -> egui_kittest::Harness<'static, SolscopeApp> {
    let view = View {
        select: Some(id.into()),
        ..View::default()
    };
    let app = SolscopeApp::with_default_plan().expect("default plan");
    harness(app, SNAPSHOT_SIZE.into(), &view).unwrap()
}

#[test]
fn an_energy_failure_draws_what_it_would_have_caused() {
    let mut h = default_with_selected("moxie_run_413");
    h.run_steps(3);
    let a = index(h.state(), "moxie_run_413");
    let (plot, at, value, label, culprits) = {
        let w = h
            .state()
            .would_cause()
            .expect("an overlay for a min_soc failure");
        assert_eq!(w.activity, a);
        assert!(!w.points.is_empty());
        assert_eq!(w.reasons.len(), 1, "one range of starts, on min_soc");
        let r = w.shown().unwrap();
        (r.plot, r.at, r.value, r.label.clone(), w.culprits.clone())
    };
    assert_eq!(plot, solscope::state::OverlayPlot::Soc);
    // The explanation's numbers: lowest 921.5 Wh at t=164050, below min_soc.
    assert_eq!(at, 164_050);
    assert!((value - 921.541_666).abs() < 1e-3, "{value}");
    assert!(
        label.starts_with("would reach 921.5 Wh < min_soc"),
        "{label}"
    );
    let drive = index(h.state(), "drive_412");
    assert!(culprits.contains(&drive));
    // The overlay's line reaches the reported value at the reported time.
    {
        let w = h.state().would_cause().unwrap();
        let there = w.points.iter().find(|p| p[0] == at as f64).unwrap();
        assert!((there[1] - value).abs() < 1e-6);
    }
    assert!(
        h.query_by_label_contains("Dashed: moxie_run_413 if placed at")
            .is_some()
    );
    // None for a scheduled activity.
    let mut h = default_with_selected("drive_412");
    h.run_steps(3);
    assert!(h.state().would_cause().is_none());
    assert!(h.query_by_label_contains("Dashed:").is_none());
}

#[test]
fn a_peak_power_failure_draws_on_the_peak_plot() {
    let mut h = default_with_selected("supercam_libs_413");
    h.run_steps(3);
    let w = h
        .state()
        .would_cause()
        .expect("an overlay for a max_peak failure");
    let r = w.shown().unwrap();
    assert_eq!(r.plot, solscope::state::OverlayPlot::Peak);
    assert_eq!(r.at, 149_350);
    assert!((r.value - 923.0).abs() < 1e-9);
    assert_eq!(r.label, "would reach 923.0 W > max_peak 750.0 W");
    // The step function with it placed reaches the reported peak there.
    assert!(
        w.points
            .iter()
            .any(|p| p[0] == 149_350.0 && (p[1] - 923.0).abs() < 1e-9)
    );
    let xband = index(h.state(), "xband_dte_413");
    assert!(w.culprits.contains(&xband));
}

/// X fails on the battery for its early starts and on the peak power beside
/// H for the later ones: two reasons, one on each plot.
const TWO_LIMITS: &str = include_str!("plans/two-limits.json");

#[test]
fn every_energy_and_peak_reason_is_marked_and_each_can_be_drawn() {
    use solscope::state::OverlayPlot;
    let app = SolscopeApp::from_text(TWO_LIMITS, None).unwrap();
    let view = View {
        select: Some("X".into()),
        ..View::default()
    };
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &view).unwrap();
    h.run_steps(3);
    {
        let w = h.state().would_cause().expect("an overlay");
        let plots: Vec<OverlayPlot> = w.reasons.iter().map(|r| r.plot).collect();
        assert_eq!(plots, [OverlayPlot::Soc, OverlayPlot::Peak]);
        assert_eq!(w.shown, 0, "the first reason is drawn first");
        assert_eq!(
            w.reasons
                .iter()
                .map(|r| (r.first, r.last))
                .collect::<Vec<_>>(),
            [(0, 400), (401, 1500)]
        );
    }
    // The first reason's profile (at the start its numbers were evaluated
    // at) on the state of charge; the peak plot marks the other reason's
    // violation.
    assert!(
        h.query_by_label_contains("Dashed: X if placed at Sol 0 00:06:29 (t=400)")
            .is_some()
    );
    assert!(
        h.query_by_label_contains("Hollow circles: where 1 reason(s) of X on this plot")
            .is_some()
    );
    assert!(h.query_by_label_contains("reason 1 of 2").is_some());
    h.get_by_label("Next reason").click();
    h.run_steps(3);
    {
        let w = h.state().would_cause().unwrap();
        assert_eq!(w.shown, 1);
        let r = w.shown().unwrap();
        assert_eq!(r.plot, OverlayPlot::Peak);
        assert_eq!(r.label, "would reach 660.0 W > max_peak 500.0 W");
        // The profile drawn is the one with X placed at this reason's start:
        // the peak reaches 660 W at H's start.
        assert!(
            w.points
                .iter()
                .any(|p| p[0] == 1000.0 && (p[1] - 660.0).abs() < 1e-9),
            "{:?}",
            w.points
        );
    }
    assert!(h.query_by_label_contains("reason 2 of 2").is_some());
    assert!(
        h.query_by_label_contains("Hollow circles: where 1 reason(s) of X on this plot")
            .is_some(),
        "the state of charge now marks the first reason"
    );
    // The reason picked is X's alone: another activity starts from its first.
    let (x, hh) = (index(h.state(), "X"), index(h.state(), "H"));
    assert_eq!(h.state().ui.nav.overlay_reason_of(x), 1);
    assert_eq!(h.state().ui.nav.overlay_reason_of(hh), 0);
    // The inspector's reason lines pick one too.
    h.get_all_by_label("Show on plot").next().unwrap().click();
    h.run_steps(3);
    assert_eq!(h.state().would_cause().unwrap().shown, 0);
}

/// The tutorial plan's file.
const TUTORIAL_PATH: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/tutorial-plan.json");

/// The app as the desktop starts it on `plan`, with these persisted settings,
/// in a harness.
fn started_on(
    plan: &str,
    persisted: solscope::state::Persisted,
) -> egui_kittest::Harness<'static, SolscopeApp> {
    let mut app = SolscopeApp::open_or_default(Some(std::path::Path::new(plan))).unwrap();
    app.restore_persisted(persisted);
    harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap()
}

/// The page of the guided tour shown (0-based), if it is shown.
fn tour_page(h: &egui_kittest::Harness<'static, SolscopeApp>) -> Option<usize> {
    h.state().ui.messages.tour.as_ref().map(|t| t.page)
}

#[test]
fn the_tutorial_plan_opens_with_the_guided_tour_and_next_selects_its_first_failure() {
    let mut h = started_on(TUTORIAL_PATH, Default::default());
    assert_eq!(tour_page(&h), Some(0));
    assert!(h.query_by_label("Guided tour (1 of 6)").is_some());
    assert!(h.query_by_label("The scheduler works in steps").is_some());
    assert!(h.query_by_label("← Back").is_some());
    // The failure it follows: the first one of the schedule, in step order.
    let first = h
        .state()
        .analysis
        .schedule
        .steps
        .iter()
        .find(|s| s.outcome.status() == "failed")
        .map(|s| s.activity)
        .unwrap();
    assert_eq!(
        h.state().doc.plan.activities[first].id,
        "sky_flats_mast_busy"
    );
    assert_eq!(h.state().ui.nav.selected, None);
    h.get_by_label("Next →").click();
    h.run_steps(3);
    assert_eq!(tour_page(&h), Some(1));
    assert_eq!(h.state().ui.nav.selected, Some(first), "Next selected it");
    let own = h.state().analysis.schedule.step_of(first).unwrap().step;
    assert_eq!(h.state().ui.nav.step, own, "at the step that tried it");
    assert!(
        h.query_by_label_contains("At step 9 the scheduler tried sky_flats_mast_busy")
            .is_some()
    );
    // Why: the slider moves to its failure step, the text reads it.
    h.get_by_label("Next →").click();
    h.run_steps(3);
    assert_eq!(tour_page(&h), Some(2));
    let fs = h
        .state_mut()
        .explanation_for(first)
        .unwrap()
        .failure_step
        .unwrap();
    assert_eq!(h.state().ui.nav.step, fs);
    assert!(
        h.query_by_label_contains(&format!("The slider now shows step {fs}, its failure step"))
            .is_some()
    );
    // Back goes to the page before, and selects the failure again.
    h.state_mut().push(Command::Select(None));
    h.run_steps(2);
    h.get_by_label("← Back").click();
    h.run_steps(3);
    assert_eq!(tour_page(&h), Some(1));
    assert_eq!(h.state().ui.nav.selected, Some(first));
    // The default plan does not open with it.
    let h = started_on(
        concat!(env!("CARGO_MANIFEST_DIR"), "/assets/default-plan.json"),
        Default::default(),
    );
    assert_eq!(tour_page(&h), None);
    assert!(h.query_by_label_contains("Guided tour (").is_none());
}

#[test]
fn the_tour_applies_its_suggestion_and_undoes_it() {
    let mut h = started_on(TUTORIAL_PATH, Default::default());
    for _ in 0..4 {
        h.get_by_label("Next →").click();
        h.run_steps(3);
    }
    assert_eq!(tour_page(&h), Some(4));
    let a = index(h.state(), "sky_flats_mast_busy");
    assert!(h.state().analysis.placement(a).is_none());
    assert!(
        h.query_by_label_contains("(its window becomes Sol 0 10:03:24 to Sol 0 10:27:44)")
            .is_some()
    );
    h.get_by_label("Apply it").click();
    h.run_steps(3);
    assert!(
        h.state().analysis.placement(a).is_some(),
        "the suggestion applied"
    );
    assert!(
        h.query_by_label_contains("sky_flats_mast_busy is scheduled now, at Sol 0 10:03:24")
            .is_some()
    );
    h.get_by_label("Next →").click();
    h.run_steps(3);
    assert_eq!(tour_page(&h), Some(5));
    assert!(h.query_by_label("Next →").is_none(), "the last page");
    h.get_by_label("Undo the change").click();
    h.run_steps(3);
    assert!(h.state().analysis.placement(a).is_none(), "undone");
    assert!(!h.state().doc.dirty);
}

#[test]
fn ending_the_tour_is_remembered_and_the_help_menu_restarts_and_resets_it() {
    let mut h = started_on(TUTORIAL_PATH, Default::default());
    h.get_by_label("End tour").click();
    h.run_steps(3);
    assert_eq!(tour_page(&h), None);
    assert!(h.query_by_label_contains("Guided tour (").is_none());
    let persisted = h.state().persisted.clone();
    assert!(persisted.tour_dismissed);
    // Started again with what was saved: the tutorial opens without it.
    let mut h = started_on(TUTORIAL_PATH, persisted);
    assert_eq!(tour_page(&h), None);
    // Help > Guided tour shows it again.
    h.get_by_label("Help").click();
    h.run_steps(3);
    h.get_by_label("Guided tour").click();
    h.run_steps(3);
    assert_eq!(tour_page(&h), Some(0));
    assert!(h.query_by_label("Guided tour (1 of 6)").is_some());
    // Help > Reset guided tour: it opens by itself again with the tutorial.
    h.get_by_label("End tour").click();
    h.run_steps(3);
    h.get_by_label("Help").click();
    h.run_steps(3);
    h.get_by_label("Reset guided tour").click();
    h.run_steps(3);
    assert!(!h.state().persisted.tour_dismissed);
    let h = started_on(TUTORIAL_PATH, h.state().persisted.clone());
    assert_eq!(tour_page(&h), Some(0));
}

#[test]
fn the_help_menu_opens_the_tutorial_for_the_tour_from_another_plan() {
    let dismissed = solscope::state::Persisted {
        tour_dismissed: true,
        ..Default::default()
    };
    let mut app = SolscopeApp::with_default_plan().unwrap();
    app.restore_persisted(dismissed);
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    // An unsaved edit is guarded.
    h.state_mut().push(Command::Edit {
        target: "plan".into(),
        set: serde_json::from_str(r#"{"name": "edited"}"#).unwrap(),
        description: "rename".into(),
    });
    h.state_mut().push(Command::Ui(UiCommand::ShowExecution));
    h.run_steps(3);
    assert!(h.state().doc.dirty);
    h.get_by_label("Help").click();
    h.run_steps(3);
    h.get_by_label("Guided tour").click();
    h.run_steps(3);
    assert_eq!(
        tour_page(&h),
        None,
        "waiting for the unsaved-changes answer"
    );
    assert!(
        h.query_by_label_contains("discard them and open the tutorial plan")
            .is_some()
    );
    h.get_by_label("Discard changes").click();
    h.run_steps(3);
    assert!(solscope::state::tour::is_tutorial(&h.state().doc.plan));
    assert_eq!(h.state().doc.path, None, "the bundled plan, not a file");
    assert_eq!(
        tour_page(&h),
        Some(0),
        "dismissed or not, the menu starts it"
    );
}

// ---- Big plans: the zoomable step slider, free slack off the frame ----

/// A generated plan (standard or realistic profile) in a harness as the desktop
/// app runs it (workers on), the flexibility layer `shown` or not.
fn generated(profile: solscope_engine::Profile, n: usize, sols: usize, shown: bool) -> Hs {
    let plan = solscope_engine::generate_plan_with(profile, n, sols, 1);
    let text = serde_json::to_string(&plan).unwrap();
    let mut app = SolscopeApp::from_text(&text, None).unwrap();
    app.background = true;
    app.persisted.hide_flex = !shown;
    harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap()
}

/// The step slider's rail on screen.
fn step_rail(h: &Hs) -> eframe::egui::Rect {
    h.query_all_by_label("Step")
        .find(|n| n.accesskit_node().role() == eframe::egui::accesskit::Role::Slider)
        .expect("the step slider")
        .rect()
}

#[test]
fn one_step_of_ten_thousand_is_picked_with_the_mouse_on_the_zoomed_slider() {
    let mut h = generated(solscope_engine::Profile::Standard, 10_000, 30, false);
    let n = h.state().analysis.steps();
    assert!(n >= 10_000);
    // Whole, the rail gives a step a thirtieth of a point: it offers to zoom.
    assert!(
        h.get_by_label("Zoom steps out")
            .accesskit_node()
            .is_disabled(),
        "all steps shown"
    );
    h.state_mut().push(Command::SetStep(5_000));
    h.run_steps(2);
    for _ in 0..4 {
        h.get_by_label("Zoom steps in").click();
        h.run_steps(2);
    }
    let (lo, hi) = h.state().ui.nav.steps_shown.span(n);
    assert!(hi - lo <= 40 && (lo..=hi).contains(&5_000), "{lo}..{hi}");
    assert!(
        h.query_by_label(&format!("steps {lo}–{hi} of {n}"))
            .is_some(),
        "the span is named"
    );
    // A click on the rail picks the step under the pointer, exactly: the
    // middle, then three steps to its right and seven to its left.
    let rail = step_rail(&h);
    let handle = rail.height() / 2.5;
    let per_step = (rail.width() - 2.0 * handle) / (hi - lo) as f32;
    let mid = (lo + hi) / 2;
    for target in [mid, mid + 3, mid - 7] {
        let x = rail.center().x + (target as f32 - (lo + hi) as f32 / 2.0) * per_step;
        let at = eframe::egui::pos2(x, rail.center().y);
        h.hover_at(at);
        h.step();
        h.drag_at(at);
        h.step();
        h.drop_at(at);
        h.run_steps(2);
        assert_eq!(h.state().ui.nav.step, target, "picked at x={x}");
        assert!(
            h.query_by_label_contains(&format!("step {target}: "))
                .is_some()
        );
    }
    // The span follows the step: End goes to the last step, and the span moves
    // there with its width.
    h.key_press(eframe::egui::Key::End);
    h.run_steps(2);
    assert_eq!(h.state().ui.nav.step, n);
    let (lo2, hi2) = h.state().ui.nav.steps_shown.span(n);
    assert_eq!((hi2, hi2 - lo2), (n, hi - lo));
    // Ctrl+wheel over the slider zooms out about the pointer; All steps
    // spans the run again.
    h.hover_at(rail.center());
    h.step();
    h.event(eframe::egui::Event::Zoom(0.5));
    h.run_steps(2);
    let (lo3, hi3) = h.state().ui.nav.steps_shown.span(n);
    assert!(hi3 - lo3 > hi - lo, "{lo3}..{hi3}");
    h.get_by_label("All steps").click();
    h.run_steps(2);
    assert_eq!(h.state().ui.nav.steps_shown.span(n), (0, n));
}

#[test]
fn a_small_plan_s_step_slider_does_not_zoom() {
    let h = harness(tutorial(), SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    assert!(h.query_by_label("Zoom steps in").is_none());
}

#[test]
fn free_slack_fills_in_off_the_frame_says_how_far_and_stops_with_the_layer() {
    let mut h = generated(solscope_engine::Profile::Realistic, 1_000, 3, true);
    wait_until(&mut h, "the flexible schedule", |app| app.flex().is_some());
    wait_until(&mut h, "some free slack", |app| {
        app.free_slack_progress().is_some_and(|p| p.done > 0)
    });
    let p = h.state().free_slack_progress().unwrap();
    assert!(p.running && !p.complete(), "{p:?}");
    assert!(
        h.query_by_label_contains("computing free slack: ")
            .is_some(),
        "the legend says how far it is"
    );
    // What is known is what the engine gives for that activity.
    let known: Vec<(usize, Option<solscope_engine::IntervalSet>)> = h
        .state()
        .flex()
        .unwrap()
        .activities
        .iter()
        .filter(|fa| fa.free_slack.is_some())
        .map(|fa| (fa.activity, fa.free_slack.clone()))
        .take(3)
        .collect();
    for (a, free) in known {
        let one = solscope_engine::free_slack_of(&h.state().analysis.schedule, a);
        assert_eq!(one.map(|(_, both)| both), free);
    }
    // The app answers meanwhile: a step and the frame that shows it.
    h.key_press(eframe::egui::Key::Home);
    h.run_steps(2);
    assert_eq!(h.state().ui.nav.step, 0);
    // The layer off stops the worker, keeping what it found.
    h.key_press(eframe::egui::Key::F);
    h.run_steps(2);
    assert!(h.state().persisted.hide_flex);
    let stopped = h.state().free_slack_progress().unwrap();
    assert!(!stopped.running && stopped.done >= p.done, "{stopped:?}");
    wait_until(&mut h, "the workers to stop", |app| !app.workers_busy());
    // On again: it goes on from there.
    h.key_press(eframe::egui::Key::F);
    h.run_steps(2);
    let again = h.state().free_slack_progress().unwrap();
    assert!(again.running && again.done >= stopped.done, "{again:?}");
}

#[test]
fn execution_mode_stops_the_free_slack_and_schedule_mode_resumes_it() {
    let mut h = generated(solscope_engine::Profile::Realistic, 1_000, 3, true);
    wait_until(&mut h, "some free slack", |app| {
        app.free_slack_progress().is_some_and(|p| p.done > 0)
    });
    // The layer is not drawn in execution mode: nothing computes its shading.
    h.state_mut().push(Command::Ui(UiCommand::ShowExecution));
    h.run_steps(2);
    let stopped = h.state().free_slack_progress().unwrap();
    assert!(!stopped.running, "{stopped:?}");
    h.state_mut().push(Command::Ui(UiCommand::ShowSchedule));
    h.run_steps(2);
    let again = h.state().free_slack_progress().unwrap();
    assert!(again.running && again.done >= stopped.done, "{again:?}");
}

#[test]
fn the_selected_activity_s_free_slack_is_computed_ahead_of_the_rest() {
    // The layer off: no worker computes the plan's free slack.
    let mut h = generated(solscope_engine::Profile::Realistic, 1_000, 3, false);
    wait_until(&mut h, "the flexible schedule", |app| app.flex().is_some());
    let a = h.state().flex().unwrap().activities[500].activity;
    h.state_mut().push(Command::Select(Some(a)));
    h.run_steps(1);
    if h.state().free_slack_progress().unwrap().computing == Some(a) {
        assert!(
            h.query_by_label_contains("Computing its free slack")
                .is_some()
        );
    }
    wait_until(&mut h, "its free slack", |app| {
        app.flex()
            .and_then(|f| f.activity(a))
            .is_some_and(|fa| fa.free_slack.is_some())
    });
    let fa = h.state().flex().unwrap().activity(a).unwrap().clone();
    let one = solscope_engine::free_slack_of(&h.state().analysis.schedule, a).unwrap();
    assert_eq!(
        (fa.free_slack_phase1, fa.free_slack),
        (Some(one.0), Some(one.1))
    );
    // Only its: the rest waits for the layer.
    assert_eq!(h.state().free_slack_progress().map(|p| p.done), Some(1));
    assert!(
        h.query_by_label_contains("Free slack (every check, others fixed)")
            .is_some()
    );
}

/// A failed expanding activity's note saying which duration its reasons are
/// for comes above the reasons, with the sentence that says why it failed
/// (`explanation_notes_and_lead`); the notes that go through the reasons follow them.
#[test]
fn the_duration_note_of_a_failed_expanding_activity_leads_its_reasons() {
    let plan = include_str!("plans/two-limits.json").replace(
        r#""id": "X", "priority": 2, "duration": 600,"#,
        r#""id": "X", "priority": 2, "duration": {"min": 600, "max": 900},"#,
    );
    let mut app = SolscopeApp::from_text(&plan, None).expect("two-limits plan");
    let x = index(&app, "X");
    app.apply(Command::Select(Some(x)));
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    h.run_steps(3);
    // Where the labels containing `text` are (a label may be matched twice,
    // by its node and its container's).
    let span = |text: &str| {
        h.get_all_by_label_contains(text)
            .map(|n| n.rect())
            .reduce(|a, b| a.union(b))
            .expect("a label")
    };
    let note = span("may last from 10 min to 15 min, and no duration fits");
    let why = span("Some start times pass every constraint");
    let reason = span("min_soc for starts");
    let prose = span("below the 300.0 Wh minimum");
    assert!(why.top() < note.top(), "{why:?} {note:?}");
    assert!(note.bottom() <= reason.top(), "{note:?} {reason:?}");
    assert!(reason.bottom() <= prose.top(), "{reason:?} {prose:?}");
    // The reason lines for the note's duration come first and name none;
    // those the duration search tried at longer ones name theirs.
    let mut lines: Vec<(f32, String)> = h
        .get_all_by_label_contains("min_soc for starts")
        .chain(h.get_all_by_label_contains("max_peak_power for starts"))
        .filter_map(|n| Some((n.rect().top(), n.accesskit_node().value()?)))
        .collect();
    lines.sort_by(|a, b| a.0.total_cmp(&b.0));
    let first = lines.first().map(|l| l.1.as_str()).unwrap_or_default();
    assert!(!first.contains("lasting"), "{lines:#?}");
    assert!(
        lines.iter().any(|l| l.1.contains(", lasting 12 min 30 s:")),
        "{lines:#?}"
    );
    // The plots draw the first of them first.
    let first = h.state().would_cause().map(|w| w.reasons[w.shown].reason);
    let ex = h
        .state_mut()
        .explanation_for(x)
        .cloned()
        .expect("explained");
    let first = first.map(|i| ex.reasons[i].duration);
    assert_eq!(first, Some(ex.duration), "{:?}", ex.reasons);
}

/// An expanding activity's valid starts are for one duration, and the header
/// over them says which (the tutorial's drive may last 20 to 60 minutes).
#[test]
fn the_valid_starts_of_an_expanding_activity_name_their_duration() {
    let mut h = tutorial_with_selected("drive");
    h.run_steps(3);
    let a = index(h.state(), "drive");
    let (start, end) = h
        .state()
        .analysis
        .placement(a)
        .expect("the drive is placed");
    let header = format!(", for {})", solscope_engine::format_span(end - start));
    assert!(
        h.query_by_label_contains(&header).is_some(),
        "no header ending {header:?}"
    );
    // A fixed duration is not named.
    let mut h = tutorial_with_selected("sky_flats_mast_busy");
    h.run_steps(3);
    assert!(
        h.query_by_label_contains("Valid starts per constraint")
            .is_some()
    );
    assert!(h.query_by_label_contains(", for ").is_none());
}

#[test]
fn a_big_plan_opens_on_a_worker_with_its_progress_and_cancel_keeps_the_plan_before() {
    let (path, name) = generated_plan_file("open-big", 10_000, 30);
    let mut app = SolscopeApp::with_default_plan().unwrap();
    app.background = true;
    let before = app.doc.plan.clone();
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    // File > Open: the next frame comes at once, says what is opened and how
    // far it has come, and offers Cancel; the plan open stays meanwhile.
    h.state_mut().push(Command::Open(path.clone()));
    h.run_steps(2);
    assert!(
        h.query_by_label_contains("Opening big-plan.json").is_some(),
        "no progress line"
    );
    assert_eq!(h.state().doc.plan, before);
    // The window answers: the menus open while the plan is scheduled.
    h.get_by_label("File").click();
    h.run_steps(2);
    assert!(h.query_by_label("Open…").is_some());
    h.key_press(eframe::egui::Key::Escape);
    h.run_steps(1);
    // The plan's name, once read, is on the line.
    let named = format!("Opening big-plan.json ({name})");
    for _ in 0..100 {
        if h.query_by_label_contains(&named).is_some() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
        h.run_steps(1);
    }
    assert!(h.query_by_label_contains(&named).is_some(), "no name");
    assert_eq!(h.state().doc.plan, before);
    h.get_by_label("Cancel opening").click();
    h.run_steps(2);
    assert!(h.query_by_label_contains("Opening big-plan.json").is_none());
    assert_eq!(
        h.state().doc.plan,
        before,
        "Cancel keeps the plan open before"
    );
    assert!(!h.state().doc.dirty);
    // Nothing comes in later from the cancelled open.
    std::thread::sleep(std::time::Duration::from_millis(300));
    h.run_steps(3);
    assert_eq!(h.state().doc.plan, before);
    // Opened again and left to finish: it becomes the plan, at its last step,
    // first in Recent.
    h.state_mut().push(Command::Open(path.clone()));
    h.run_steps(2);
    frames_until(&mut h, |app| {
        app.doc.plan.name.as_deref() == Some(name.as_str())
    });
    assert_eq!(h.state().doc.plan.activities.len(), 10_000);
    assert_eq!(h.state().ui.nav.step, h.state().analysis.steps());
    assert_eq!(h.state().doc.path.as_deref(), Some(path.as_path()));
    assert!(h.query_by_label_contains("Opening big-plan.json").is_none());
}

#[test]
fn every_failed_or_skipped_activity_looked_at_has_a_row_of_its_own() {
    let (path, _) = generated_plan_file("failed-rows", 1000, 3);
    let text = std::fs::read_to_string(&path).unwrap();
    let mut app = SolscopeApp::from_text(&text, Some(path)).unwrap();
    // Not the point here (its free slack would be derived in the frame).
    app.persisted.hide_flex = true;
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    let unplaced: Vec<usize> = (0..h.state().doc.plan.activities.len())
        .filter(|&a| h.state().analysis.placement(a).is_none())
        .collect();
    assert!(unplaced.len() > 100, "{}", unplaced.len());
    for a in [
        unplaced[0],
        unplaced[unplaced.len() / 2],
        unplaced[unplaced.len() - 1],
    ] {
        let id = h.state().doc.plan.activities[a].id.clone();
        h.state_mut().apply(Command::Select(Some(a)));
        h.run_steps(3);
        // Its row, scrolled into view, is labelled with its id on the Gantt
        // (the list's row reads `x  123 id`, the inspector's id field holds
        // it as text to edit).
        let gantt = h.get_by_label("Gantt chart").rect();
        let row_labels: Vec<_> = h
            .query_all_by_label(&id)
            .filter(|n| n.accesskit_node().role() == eframe::egui::accesskit::Role::Label)
            .map(|n| n.rect())
            .collect();
        assert!(
            row_labels.iter().any(|r| gantt.contains_rect(*r)),
            "{id} has no row of its own: {row_labels:?} outside {gantt:?}"
        );
    }
}

#[test]
fn a_plan_just_opened_lists_its_activities_from_the_top() {
    let mut app = SolscopeApp::with_default_plan().unwrap();
    // Not the point here (its free slack would be derived in the frame).
    app.persisted.hide_flex = true;
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    let last = h.state().analysis.schedule.steps.last().unwrap().activity;
    h.state_mut().apply(Command::Select(Some(last)));
    h.run_steps(3);
    let first_row = |h: &egui_kittest::Harness<'static, SolscopeApp>| {
        let a = h.state().analysis.schedule.steps[0].activity;
        let id = &h.state().doc.plan.activities[a].id;
        h.query_by_label_contains(&format!(" 1 {id}")).is_some()
    };
    assert!(!first_row(&h), "the list scrolled to the selection");
    let (path, _) = generated_plan_file("list-top", 1000, 3);
    h.state_mut().push(Command::Open(path));
    h.run_steps(3);
    assert_eq!(h.state().doc.plan.activities.len(), 1000);
    assert!(
        first_row(&h),
        "the list of the plan opened starts at its top"
    );
}
