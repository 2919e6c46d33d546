//! The state driven by commands alone, without a window: the reducer's
//! effects checked on the state.

use std::path::{Path, PathBuf};

use super::reduce::write_json;
use super::*;

#[test]
fn opening_at_start_up_falls_back_to_the_default_plan_and_repairs_the_file() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let good = root.join("assets/examples/pitfall.json");
    let app = AppState::open_or_default(Some(&good)).expect("app");
    assert_eq!(app.doc.plan.activities.len(), 2);
    assert_eq!(app.doc.path.as_deref(), Some(good.as_path()));
    assert!(app.ui.messages.error.is_none());
    let bad = root.join("tests/malformed/window-end-before-start.json");
    let app = AppState::open_or_default(Some(&bad)).expect("app");
    assert_eq!(
        app.doc.plan,
        AppState::with_default_plan().expect("default").doc.plan
    );
    // The file is in the repair view, with its error.
    let repair = app.ui.messages.repair.expect("repair view");
    assert_eq!(repair.path.as_deref(), Some(bad.as_path()));
    assert!(
        repair.errors[0].path.ends_with("windows[0].end"),
        "{repair:?}"
    );
    assert!(app.ui.text.repair_text.contains("\"end\""));
    // A file that cannot be read has no text to repair: the error.
    let app = AppState::open_or_default(Some(&root.join("no-such-plan.json"))).expect("app");
    assert!(app.ui.messages.repair.is_none());
    let err = app.ui.messages.error.expect("error shown");
    assert!(err.starts_with("Could not open"), "{err}");
}

#[test]
fn step_view_series_are_monotone_in_time() {
    let app = AppState::with_default_plan().expect("default plan");
    for series in [&app.step_view.soc, &app.step_view.peak, &app.step_view.data] {
        assert!(
            series.windows(2).all(|w| w[0][0] <= w[1][0]),
            "time goes backwards"
        );
    }
    // A step function: consecutive pairs share x or y.
    assert!(
        app.step_view
            .peak
            .windows(2)
            .all(|w| w[0][0] == w[1][0] || w[0][1] == w[1][1])
    );
}

/// A directory that does not exist, in a fresh temporary directory.
fn missing_dir(name: &str) -> PathBuf {
    std::env::temp_dir()
        .join(format!("solscope-{name}-{}", std::process::id()))
        .join("missing")
}

#[test]
fn a_failed_schedule_export_is_shown_and_writes_nothing() {
    let mut app = AppState::with_default_plan().expect("default plan");
    let path = missing_dir("export").join("schedule.json");
    app.apply(Command::ExportScheduleTo(path.clone()));
    let err = app.ui.messages.error.clone().expect("error shown");
    assert!(err.starts_with("Could not write "), "{err}");
    assert!(err.contains("schedule.json"), "{err}");
    assert!(!path.exists());
}

#[test]
fn a_failed_save_is_shown_and_keeps_the_plan_unsaved() {
    let mut app = AppState::with_default_plan().expect("default plan");
    app.doc.dirty = true;
    let path = missing_dir("save").join("plan.json");
    app.apply(Command::SaveTo(path.clone()));
    let err = app.ui.messages.error.clone().expect("error shown");
    assert!(err.starts_with("Could not save "), "{err}");
    assert!(app.doc.dirty);
    assert!(app.doc.path.is_none());
    assert!(!path.exists());
}

#[test]
fn what_cannot_be_serialised_is_an_error_and_no_file() {
    // JSON object keys must be strings: serialising this map fails.
    let value: std::collections::BTreeMap<(u8, u8), u8> = [((1, 2), 3)].into();
    let dir = std::env::temp_dir().join(format!("solscope-ser-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("out.json");
    let err = write_json(&value, &path).expect_err("not serialisable");
    assert!(err.starts_with("cannot serialise it"), "{err}");
    assert!(!path.exists(), "no empty file");
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn an_error_from_a_view_is_a_command() {
    let mut app = AppState::with_default_plan().expect("default plan");
    app.apply(Command::ShowError("Time range: bad".into()));
    assert_eq!(app.ui.messages.error.as_deref(), Some("Time range: bad"));
    app.apply(Command::DismissError);
    assert!(app.ui.messages.error.is_none());
}

/// Activity `id`'s index in the plan open.
fn index_of(app: &AppState, id: &str) -> usize {
    app.doc
        .plan
        .activities
        .iter()
        .position(|a| a.id == id)
        .expect("activity")
}

#[test]
fn an_edit_then_undo_restores_the_plan_and_redo_applies_it_again() {
    let mut app = AppState::with_default_plan().expect("default plan");
    let before = app.doc.plan.clone();
    let id = before.activities[0].id.clone();
    let mut set = serde_json::Map::new();
    set.insert("priority".into(), serde_json::json!(99));
    app.apply(Command::Edit {
        target: format!("activity:{id}"),
        set,
        description: "Raise the priority".into(),
    });
    assert!(
        app.ui.messages.error.is_none(),
        "{:?}",
        app.ui.messages.error
    );
    assert_eq!(app.revision, 1);
    assert!(app.doc.dirty);
    assert_eq!(app.doc.plan.activities[0].priority, 99);
    let banner = app.ui.messages.banner.as_ref().expect("outcome banner");
    assert!(
        banner.summary().starts_with("Raise the priority"),
        "{}",
        banner.summary()
    );
    let edited = app.doc.plan.clone();
    app.apply(UiCommand::Undo.into());
    assert_eq!(app.doc.plan, before);
    assert!(!app.doc.dirty, "the plan as loaded again");
    assert_eq!(app.revision, 2, "an undo is a change of the plan");
    app.apply(UiCommand::Redo.into());
    assert_eq!(app.doc.plan, edited);
    assert!(app.doc.dirty);
    // Nothing left to redo: nothing changes.
    app.apply(UiCommand::Redo.into());
    assert_eq!((app.revision, &app.doc.plan), (3, &edited));
}

#[test]
fn a_bad_edit_changes_nothing_and_says_why() {
    let mut app = AppState::with_default_plan().expect("default plan");
    let before = app.doc.plan.clone();
    let mut set = serde_json::Map::new();
    set.insert("duration".into(), serde_json::json!(-5));
    app.apply(Command::Edit {
        target: format!("activity:{}", before.activities[0].id),
        set,
        description: "Shorten".into(),
    });
    let err = app.ui.messages.error.clone().expect("error shown");
    assert!(err.starts_with("Shorten: not applied"), "{err}");
    assert_eq!(app.doc.plan, before);
    assert_eq!(app.revision, 0);
    assert!(!app.doc.can_undo());
}

#[test]
fn steps_move_one_at_a_time_within_the_run() {
    let mut app = AppState::with_default_plan().expect("default plan");
    let n = app.analysis.steps();
    assert!(n > 10);
    assert_eq!(app.ui.nav.step, n, "opens at the last step");
    app.apply(UiCommand::NextStep.into());
    assert_eq!(app.ui.nav.step, n, "no step after the last");
    app.apply(UiCommand::FirstStep.into());
    assert_eq!(app.ui.nav.step, 0);
    app.apply(UiCommand::PreviousStep.into());
    assert_eq!(app.ui.nav.step, 0, "no step before the first");
    for _ in 0..3 {
        app.apply(UiCommand::NextStep.into());
    }
    assert_eq!(app.ui.nav.step, 3);
    app.apply(UiCommand::PreviousStep.into());
    assert_eq!(app.ui.nav.step, 2);
    app.apply(Command::SetStep(n + 100));
    assert_eq!(app.ui.nav.step, n, "clamped to the run");
    app.apply(UiCommand::FirstStep.into());
    app.apply(UiCommand::LastStep.into());
    assert_eq!(app.ui.nav.step, n);
}

#[test]
fn next_failure_selects_it_at_its_step_and_back_returns() {
    let mut app = AppState::with_default_plan().expect("default plan");
    let failed: Vec<(usize, usize)> = failed_steps(&app.analysis.schedule.steps).collect();
    assert!(failed.len() >= 2, "{failed:?}");
    app.apply(UiCommand::FirstStep.into());
    app.apply(Command::Select(None));
    app.apply(UiCommand::NextFailure.into());
    assert_eq!(app.ui.nav.step, failed[0].0);
    assert_eq!(app.ui.nav.selected, Some(failed[0].1));
    app.apply(UiCommand::NextFailure.into());
    assert_eq!(
        (app.ui.nav.step, app.ui.nav.selected),
        (failed[1].0, Some(failed[1].1))
    );
    app.apply(UiCommand::PreviousFailure.into());
    assert_eq!(app.ui.nav.step, failed[0].0);
    // Back walks the links followed: to the second failure, the first, then
    // the first step with nothing selected.
    app.apply(UiCommand::Back.into());
    assert_eq!(
        (app.ui.nav.step, app.ui.nav.selected),
        (failed[1].0, Some(failed[1].1))
    );
    app.apply(UiCommand::Back.into());
    app.apply(UiCommand::Back.into());
    assert_eq!((app.ui.nav.step, app.ui.nav.selected), (0, None));
    app.apply(UiCommand::Forward.into());
    assert_eq!(
        (app.ui.nav.step, app.ui.nav.selected),
        (failed[0].0, Some(failed[0].1))
    );
}

#[test]
fn up_and_down_move_through_the_list_as_filtered() {
    let mut app = AppState::with_default_plan().expect("default plan");
    app.apply(Command::SetFilter("meda".into()));
    let shown = app.list_shown();
    assert!(shown.len() >= 2, "{shown:?}");
    app.apply(UiCommand::SelectNext.into());
    assert_eq!(app.ui.nav.selected, Some(shown[0]), "from the top");
    app.apply(UiCommand::SelectNext.into());
    assert_eq!(app.ui.nav.selected, Some(shown[1]));
    app.apply(UiCommand::SelectPrevious.into());
    assert_eq!(app.ui.nav.selected, Some(shown[0]));
    app.apply(UiCommand::SelectPrevious.into());
    assert_eq!(app.ui.nav.selected, Some(shown[0]), "stays at the top");
    // Moving through the list is no link: Back has nothing to go back to.
    assert!(!app.ui.nav.history.can_back());
    let last = *shown.last().expect("shown");
    app.apply(UiCommand::PreviousMatch.into());
    assert_eq!(app.ui.nav.selected, Some(last), "matches wrap round");
}

#[test]
fn quitting_with_unsaved_changes_asks_first() {
    let mut app = AppState::with_default_plan().expect("default plan");
    let id = app.doc.plan.activities[1].id.clone();
    app.apply(Command::Select(Some(index_of(&app, &id))));
    app.apply(UiCommand::DeleteActivity.into());
    assert!(app.doc.dirty);
    assert!(app.doc.plan.activities.iter().all(|a| a.id != id));
    app.apply(UiCommand::Quit.into());
    assert!(!app.quit_confirmed());
    assert_eq!(app.ui.messages.confirm, Some(Pending::Quit));
    app.apply(Command::ConfirmDiscard(false));
    assert!(!app.quit_confirmed());
    assert!(app.ui.messages.confirm.is_none());
    app.apply(UiCommand::Quit.into());
    app.apply(Command::ConfirmDiscard(true));
    assert!(app.quit_confirmed());
}

#[test]
fn file_commands_ask_the_host_for_a_dialog_once() {
    let mut app = AppState::with_default_plan().expect("default plan");
    assert_eq!(app.take_dialog(), None);
    app.apply(UiCommand::Save.into());
    assert_eq!(
        app.take_dialog(),
        Some(Dialog::SaveAs),
        "no file yet: save as"
    );
    assert_eq!(app.take_dialog(), None);
    app.apply(UiCommand::ExportScheduleCsv.into());
    assert_eq!(app.take_dialog(), Some(Dialog::ExportScheduleCsv));
    let csv = app.suggested_path(Dialog::ExportScheduleCsv);
    assert!(csv.to_string_lossy().ends_with("-schedule.csv"), "{csv:?}");
}
