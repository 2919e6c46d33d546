//! Large plans through the real UI: the flexibility layer starts off above
//! `FLEX_LAYER_MAX_ACTIVITIES` activities (its free slack not computed until
//! it is turned on), and smaller plans keep the setting.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use egui_kittest::kittest::{NodeT, Queryable};
use solscope::gui::SolscopeApp;
use solscope::gui::screenshot::{SNAPSHOT_SIZE, View, harness};
use solscope::state::{Command, FLEX_LAYER_MAX_ACTIVITIES, UiCommand};

fn generated(activities: usize) -> SolscopeApp {
    let plan = solscope_engine::generate_plan(activities, 1, 3);
    SolscopeApp::from_text(&serde_json::to_string(&plan).unwrap(), None).unwrap()
}

/// Placed activities whose free slack is known.
fn free_slack_known(app: &SolscopeApp) -> usize {
    app.flex().map_or(0, |f| {
        f.activities
            .iter()
            .filter(|a| a.free_slack.is_some())
            .count()
    })
}

#[test]
fn the_flexibility_layer_starts_off_on_a_large_plan_and_its_free_slack_waits() {
    let mut h = harness(
        generated(FLEX_LAYER_MAX_ACTIVITIES + 1),
        SNAPSHOT_SIZE.into(),
        &View::default(),
    )
    .unwrap();
    h.run_steps(3);
    assert!(!h.state().flex_shown());
    let toggle = h.get_by_label(UiCommand::ToggleFlex.label());
    assert_eq!(
        toggle.accesskit_node().toggled(),
        Some(eframe::egui::accesskit::Toggled::False)
    );
    assert!(h.query_by_label("Flexibility:").is_none(), "no legend");
    // Nothing of the free slack computed, even for a selected activity.
    h.state_mut().push(Command::Select(Some(0)));
    h.run_steps(3);
    assert_eq!(free_slack_known(h.state()), 0);
    assert!(
        h.query_by_label_contains("computed once the flexibility layer is on")
            .is_some()
    );
    // The toggle turns it on for this plan, the setting as it was.
    h.state_mut().apply(Command::Ui(UiCommand::ToggleFlex));
    assert!(h.state().flex_shown());
    assert!(!h.state().persisted.hide_flex);
}

#[test]
fn a_plan_at_the_size_limit_shows_the_layer_as_set() {
    let mut app = generated(FLEX_LAYER_MAX_ACTIVITIES);
    assert!(app.flex_shown(), "shown by default");
    app.apply(Command::Ui(UiCommand::ToggleFlex));
    assert!(!app.flex_shown());
    assert!(app.persisted.hide_flex, "in the settings");
}

/// What the frame drawn last tessellates to: its vertex count.
fn vertices(h: &egui_kittest::Harness<'_, SolscopeApp>) -> usize {
    let out = h.output();
    h.ctx
        .tessellate(out.shapes.clone(), out.pixels_per_point)
        .iter()
        .map(|p| match &p.primitive {
            eframe::epaint::Primitive::Mesh(m) => m.vertices.len(),
            eframe::epaint::Primitive::Callback(_) => 0,
        })
        .sum()
}

/// The whole plan in view at step `k` (`None`: the last step).
fn whole_plan_vertices(activities: usize, k: Option<usize>) -> usize {
    let plan = solscope_engine::generate_plan(activities, 3, 1);
    let app = SolscopeApp::from_text(&serde_json::to_string(&plan).unwrap(), None).unwrap();
    let view = View {
        step: k,
        ..View::default()
    };
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &view).unwrap();
    h.run_steps(2);
    vertices(&h)
}

/// The frame draws what fits its pixels: ten times the activities over the
/// same sols (thousands of pending or failed activities' windows stacked in
/// one lane) tessellate to as many vertices, within a tenth, not more with
/// every window (before overlapping windows were merged: 83,052 vertices at
/// 2,000 activities, 110,224 at 20,000, at the last step).
#[test]
fn a_dense_plan_s_frame_is_bounded_by_its_pixels() {
    for k in [Some(0), None] {
        let small = whole_plan_vertices(2_000, k);
        let large = whole_plan_vertices(20_000, k);
        assert!(
            large * 10 <= small * 11,
            "at step {k:?}: {large} vertices at 20,000 activities, {small} at 2,000"
        );
    }
}
