//! What the app's UI test files share: finding an activity by id, scratch
//! files, generated plans, and running frames until the workers are done.
//! Each test file takes it with `mod support;` and uses what it needs.

#![allow(dead_code, clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use solscope::gui::SolscopeApp;

/// The index of the activity `id` of the plan open in `app`.
pub fn index(app: &SolscopeApp, id: &str) -> usize {
    app.doc
        .plan
        .activities
        .iter()
        .position(|a| a.id == id)
        .expect("activity")
}

/// The tutorial plan's app.
pub fn tutorial() -> SolscopeApp {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/tutorial-plan.json"
    ))
    .unwrap();
    SolscopeApp::from_text(&text, None).expect("tutorial plan")
}

/// A file `name` holding `text` in a fresh temporary directory of this test.
pub fn scratch_file(test: &str, name: &str, text: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("solscope-ui-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// A generated plan of `n` activities over `sols` sols (seed 1) in a scratch
/// file `big-plan.json`, and the plan's name.
pub fn generated_plan_file(test: &str, n: usize, sols: usize) -> (std::path::PathBuf, String) {
    let plan = solscope_engine::generate_plan(n, sols, 1);
    let name = plan.name.clone().expect("generated plans are named");
    let text = serde_json::to_string(&plan).unwrap();
    (scratch_file(test, "big-plan.json", &text), name)
}

/// Runs frames until `done` holds (panics after a minute).
pub fn frames_until(
    h: &mut egui_kittest::Harness<'static, SolscopeApp>,
    done: impl Fn(&SolscopeApp) -> bool,
) {
    for _ in 0..6000 {
        if done(h.state()) {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
        h.run_steps(1);
    }
    panic!("never happened");
}
