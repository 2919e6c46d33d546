//! Where things sit: what comes and goes (the change banner) moves nothing
//! else, a plan opened shows its list from the top, the inspector's valid
//! starts fit its width.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod support;

use egui_kittest::kittest::Queryable;
use serde_json::json;
use solscope::gui::SolscopeApp;
use solscope::gui::screenshot::{SNAPSHOT_SIZE, View, harness};
use solscope::state::Command;
use support::{frames_until, generated_plan_file, index, tutorial};

type H = egui_kittest::Harness<'static, SolscopeApp>;

fn gantt(h: &H) -> eframe::egui::Rect {
    h.get_by_label("Gantt chart").rect()
}

#[test]
fn the_change_banner_moves_nothing() {
    let mut h = harness(tutorial(), SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    let before = gantt(&h);
    let a = index(h.state(), "sky_flats_mast_busy");
    let id = format!("activity:{}", h.state().doc.plan.activities[a].id);
    let mut set = serde_json::Map::new();
    set.insert("priority".into(), json!(1));
    h.state_mut().push(Command::Edit {
        target: id,
        set,
        description: "Raise its priority".into(),
    });
    h.run_steps(3);
    assert!(h.state().ui.messages.banner.is_some());
    assert!(h.query_by_label_contains("Raise its priority").is_some());
    assert!(h.query_by_label("Dismiss").is_some());
    let with = gantt(&h);
    assert_eq!(with.top(), before.top(), "the banner pushed the Gantt down");
    assert_eq!(with.left(), before.left());
    assert_eq!(with.width(), before.width());
    h.get_by_label("Dismiss").click();
    h.run_steps(3);
    assert!(h.state().ui.messages.banner.is_none());
    assert_eq!(gantt(&h), with, "dismissing the banner moved the Gantt");
}

#[test]
fn a_big_plan_opened_with_the_list_scrolled_down_lists_from_row_0() {
    let mut app = SolscopeApp::with_default_plan().unwrap();
    app.background = true;
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    // The list scrolled to row 36: the activity of row 39 selected.
    let row = |h: &mut H, i: usize| {
        let a = h.state_mut().listed().shown[i];
        let step = h.state().analysis.schedule.step_of(a).unwrap().step;
        let id = &h.state().doc.plan.activities[a].id;
        h.query_by_label_contains(&format!("{step:>3} {id}"))
            .is_some()
    };
    let a = h.state_mut().listed().shown[39];
    h.state_mut().push(Command::Select(Some(a)));
    h.run_steps(3);
    assert!(row(&mut h, 36) && !row(&mut h, 0), "scrolled to row 36");
    let (path, name) = generated_plan_file("list-top-10k", 10_000, 30);
    h.state_mut().push(Command::Open(path));
    h.run_steps(2);
    frames_until(&mut h, |app| {
        app.doc.plan.name.as_deref() == Some(name.as_str())
    });
    h.run_steps(3);
    assert_eq!(h.state().doc.plan.activities.len(), 10_000);
    assert!(
        row(&mut h, 0),
        "the list of the plan opened starts at row 0"
    );
    assert!(!row(&mut h, 36), "row 36 is out of view");
}

/// The valid starts of `id`, selected in the tutorial plan with the
/// inspector `width` wide: the strip's rect, the inspector's, and the
/// labels of its time axis with their rects.
fn valid_starts_strip(
    width: f32,
    id: &str,
) -> (
    eframe::egui::Rect,
    eframe::egui::Rect,
    Vec<(String, eframe::egui::Rect)>,
) {
    use egui_kittest::kittest::NodeT;
    let mut app = tutorial();
    app.persisted.inspector_width = Some(width);
    let view = View {
        select: Some(id.into()),
        ..View::default()
    };
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &view).unwrap();
    h.run_steps(3);
    let strip = h.get_by_label("Valid starts by constraint").rect();
    // The inspector's content: from its heading to the window's right edge
    // less the panel's margin (the heading's distance from the Gantt).
    let heading = h.get_by_label("Inspector").rect();
    let margin = heading.left() - gantt(&h).right();
    let inspector = eframe::egui::Rect::from_x_y_ranges(
        heading.left()..=SNAPSHOT_SIZE[0] - margin,
        heading.top()..=SNAPSHOT_SIZE[1],
    );
    let ticks = h
        .query_all(egui_kittest::kittest::by().role(eframe::egui::accesskit::Role::Label))
        .filter(|n| strip.intersects(n.rect()))
        .filter_map(|n| {
            let node = n.accesskit_node();
            let text = node.label().or(node.value())?.to_string();
            Some((text, n.rect()))
        })
        .collect();
    (strip, inspector, ticks)
}

#[test]
fn the_valid_starts_strip_has_a_time_axis_and_fits_the_inspector() {
    for width in [220.0, 300.0, 420.0, 640.0] {
        for id in ["sky_flats_mast_busy", "zcam_pano"] {
            let (strip, inspector, ticks) = valid_starts_strip(width, id);
            assert!(
                strip.right() <= inspector.right(),
                "{id} at {width}: the strip {strip:?} is cut at the inspector's right edge \
                 {inspector:?}"
            );
            assert!(
                strip.width() >= inspector.width() / 2.0,
                "{strip:?} in {inspector:?}"
            );
            // A time axis in LMST: times of day or sol starts, inside the strip.
            assert!(ticks.len() >= 2, "{id} at {width}: no time axis: {ticks:?}");
            for (label, r) in &ticks {
                let lmst = label.starts_with("Sol ")
                    || label
                        .split(':')
                        .all(|p| p.len() == 2 && p.parse::<u8>().is_ok());
                assert!(lmst, "{label} is not an LMST time");
                assert!(r.right() <= strip.right(), "{label} {r:?} cut in {strip:?}");
            }
        }
    }
}

#[test]
fn a_long_change_banner_scrolls_within_a_quarter_of_the_chart() {
    let mut h = harness(tutorial(), SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    let before = gantt(&h);
    // A rerun that moved hundreds of activities: its summary runs to
    // hundreds of lines at this width.
    let clock = h.state().doc.plan.local_time;
    h.state_mut().ui.messages.banner = Some(solscope::state::document::OutcomeDiff {
        description: "Raise the battery minimum".into(),
        moved: (0..600)
            .map(|i| (format!("moved_activity_{i:03}"), 1000 + i, 90_000 + i))
            .collect(),
        clock,
        ..Default::default()
    });
    h.run_steps(3);
    let text = h.get_by_label_contains("Raise the battery minimum").rect();
    let dismiss = h.get_by_label("Dismiss").rect();
    let window = eframe::egui::Vec2::from(SNAPSHOT_SIZE);
    // The text's visible part starts at most a quarter of the chart area
    // above the banner's foot (the area is less than the window).
    let shown = dismiss.bottom() - text.top();
    assert!(
        shown <= 0.25 * window.y + 2.0 * dismiss.height() + 24.0,
        "the banner is {shown} px tall in a {} px window",
        window.y
    );
    assert!(dismiss.bottom() <= window.y, "Dismiss is out of reach");
    assert!(
        text.top() > before.top(),
        "the banner's text covers the whole Gantt"
    );
    h.get_by_label("Dismiss").click();
    h.run_steps(3);
    assert!(h.state().ui.messages.banner.is_none());
}
