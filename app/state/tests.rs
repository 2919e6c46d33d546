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
