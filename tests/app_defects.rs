//! Smaller defects of the app, each through the real UI (egui_kittest, by
//! accessibility labels): keys typed right after Ctrl+F.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use eframe::egui;
use egui_kittest::kittest::Queryable;
use solscope::gui::SolscopeApp;
use solscope::gui::screenshot::{SNAPSHOT_SIZE, View, harness};

type H = egui_kittest::Harness<'static, SolscopeApp>;

fn tutorial() -> H {
    let app = SolscopeApp::from_text(include_str!("../assets/tutorial-plan.json"), None).unwrap();
    harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap()
}

/// Events that arrive in one frame (the harness queues one event a frame).
fn in_one_frame(h: &mut H, events: Vec<egui::Event>) {
    h.input_mut().events.extend(events);
    h.run_steps(1);
}

fn key(key: egui::Key, pressed: bool, modifiers: egui::Modifiers) -> egui::Event {
    egui::Event::Key {
        key,
        physical_key: None,
        pressed,
        repeat: false,
        modifiers,
    }
}

/// `text` typed with `k`, no modifier.
fn typed(k: egui::Key, text: &str) -> Vec<egui::Event> {
    let none = egui::Modifiers::NONE;
    vec![
        key(k, true, none),
        egui::Event::Text(text.into()),
        key(k, false, none),
    ]
}

#[test]
fn keys_typed_in_the_frame_of_ctrl_f_reach_the_search_field() {
    let mut h = tutorial();
    let flex_before = h.state().flex_shown();
    // Ctrl+F and the text after it arrive in one frame: "f" is also the
    // flexibility layer's key, which must not fire while typing.
    let ctrl = egui::Modifiers::COMMAND;
    let mut events = vec![
        key(egui::Key::F, true, ctrl),
        key(egui::Key::F, false, ctrl),
    ];
    events.extend(typed(egui::Key::F, "f"));
    events.push(egui::Event::Text("lats".into()));
    in_one_frame(&mut h, events);
    assert_eq!(h.state().ui.nav.filter.search, "flats");
    assert_eq!(
        h.state().flex_shown(),
        flex_before,
        "F was typed, not a shortcut"
    );
    // The field keeps the keyboard: the next frame's keys go on.
    in_one_frame(&mut h, typed(egui::Key::Num1, "1"));
    h.run_steps(1);
    assert_eq!(h.state().ui.nav.filter.search, "flats1");
    assert!(h.query_by_label("Search").is_some());
}
