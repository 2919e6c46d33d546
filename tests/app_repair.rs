//! The repair view through the real UI, by accessibility labels: every error
//! of a broken plan in one pass, and an unknown id replaced by one of the
//! plan's, undoably.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use egui_kittest::kittest::{NodeT, Queryable};
use solscope::gui::SolscopeApp;
use solscope::gui::screenshot::{SNAPSHOT_SIZE, View, harness};
use solscope::state::Command;

const TUTORIAL: &str = include_str!("../assets/tutorial-plan.json");

/// The tutorial plan with wrong types on one activity's `duration` and
/// `priority` and a dependency on an unknown id in the next one, in a file.
fn broken_file() -> std::path::PathBuf {
    let mut v: serde_json::Value = serde_json::from_str(TUTORIAL).unwrap();
    v["activities"][1]["duration"] = serde_json::json!("ten minutes");
    v["activities"][1]["priority"] = serde_json::json!("high");
    v["activities"][2]["after"] = serde_json::json!([{ "activity": "nobody" }]);
    let dir = std::env::temp_dir().join(format!("solscope-app-repair-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("broken.json");
    std::fs::write(&path, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    path
}

fn opened_broken() -> egui_kittest::Harness<'static, SolscopeApp> {
    let app = SolscopeApp::from_text(TUTORIAL, None).unwrap();
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    h.state_mut().push(Command::Open(broken_file()));
    h.run_steps(3);
    h
}

#[test]
fn type_errors_and_an_unknown_id_are_listed_in_one_pass_in_planner_words() {
    let h = opened_broken();
    assert!(h.query_by_label("Errors (3)").is_some());
    assert!(
        h.query_by_label_contains("3 errors (every one is listed")
            .is_some()
    );
    for path in [
        "activities[1].priority",
        "activities[1].duration",
        "activities[2].after[0].activity",
    ] {
        assert!(h.query_by_label(path).is_some(), "{path} is listed");
    }
    assert!(
        h.query_all_by_label("must be a whole number (got the text \"high\")")
            .next()
            .is_some()
    );
    assert!(
        h.query_all_by_label_contains("must be a whole number of seconds")
            .next()
            .is_some()
    );
    assert!(
        h.query_all_by_label_contains("expected i64")
            .next()
            .is_none()
    );
    assert!(
        h.query_all_by_label("unknown activity \"nobody\"")
            .next()
            .is_some(),
        "checked although activity 1 does not parse"
    );
}

#[test]
fn an_unknown_id_is_replaced_by_one_picked_from_the_plan_and_the_pick_undone() {
    let mut h = opened_broken();
    // Nothing to pick for a type error.
    assert!(
        h.query_by_label("Or pick one of the plan's activities:")
            .is_none()
    );
    h.get_by_label("activities[2].after[0].activity").click();
    h.run_steps(3);
    let pick = "Or pick one of the plan's activities:";
    h.get_by_label(pick).focus();
    h.run_steps(2);
    h.get_by_label(pick).type_text("UHF_PASS");
    h.run_steps(2);
    // Narrowed (in any case): the ids without it are gone.
    assert!(h.query_by_label("uhf_pass_am").is_some());
    assert!(h.query_by_label("sky_flats_mast_busy").is_none());
    assert!(
        h.query_by_label("Undo replace")
            .is_some_and(|b| b.accesskit_node().is_disabled())
    );
    h.get_by_label("uhf_pass_am").click();
    h.run_steps(3);
    assert!(h.query_by_label("Errors (2)").is_some());
    assert!(
        h.query_by_label("activities[2].after[0].activity")
            .is_none()
    );
    let text = &h.state().ui.text.repair_text;
    assert!(text.contains("\"activity\": \"uhf_pass_am\""), "{text}");
    assert!(!text.contains("nobody"));
    // Undone: the text as it was, its three errors.
    h.get_by_label("Undo replace").click();
    h.run_steps(3);
    assert!(h.query_by_label("Errors (3)").is_some());
    assert!(
        h.state()
            .ui
            .text
            .repair_text
            .contains("\"activity\": \"nobody\"")
    );
    assert!(
        h.query_by_label("Undo replace")
            .is_some_and(|b| b.accesskit_node().is_disabled())
    );
}
