//! What the planner reads is true and in view: panels that never overlap, plot
//! readouts of the plotted values, dialogs in the plan's folder, LMST times
//! (egui_kittest, by accessibility labels).

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod support;

use egui_kittest::kittest::{NodeT, Queryable};
use solscope::gui::SolscopeApp;
use solscope::gui::screenshot::{SNAPSHOT_SIZE, View, harness};
use solscope::state::{Command, Dialog, UiCommand};
use support::index;

type H = egui_kittest::Harness<'static, SolscopeApp>;

/// Plan time `t` as the planner reads it, worked out here from the plan's
/// clock: the sol, then the 24-hour Mars clock (LMST: a Mars second is
/// `sol_length / 86400` plan seconds), then the plan second.
fn lmst(app: &SolscopeApp, t: i64) -> String {
    let c = app.doc.plan.local_time;
    let since = c.offset + t;
    let sol = c.first_sol.unwrap_or(0) + since.div_euclid(c.sol_length);
    let m = since.rem_euclid(c.sol_length) * 86_400 / c.sol_length;
    format!(
        "Sol {sol} {:02}:{:02}:{:02} (t={t})",
        m / 3600,
        m / 60 % 60,
        m % 60
    )
}

/// The label of every node in the tree.
fn labels(h: &H) -> Vec<String> {
    // (A label keeps its text in its value.)
    h.query_all_by(|_| true)
        .flat_map(|n| {
            let k = n.accesskit_node();
            [k.label(), k.value()]
                .into_iter()
                .flatten()
                .map(|l| l.to_string())
        })
        .collect()
}

/// The value of a series of `[t, value]` points (a step function given as
/// pairs of points at each jump: the later value) at `t`.
fn value_at(series: &[[f64; 2]], t: f64) -> f64 {
    let i = series.partition_point(|p| p[0] <= t);
    let (a, b) = (series[i - 1], series[i]);
    a[1] + (b[1] - a[1]) * (t - a[0]) / (b[0] - a[0])
}

#[test]
fn hovering_a_plot_reads_the_profile_at_that_time_not_the_pointer() {
    let mut h = harness(
        SolscopeApp::with_default_plan().unwrap(),
        SNAPSHOT_SIZE.into(),
        &View::default(),
    )
    .unwrap();
    let clock = h.state().doc.plan.local_time;
    for (title, pick) in [
        (
            "Peak power (W)",
            (|v| &v.peak) as fn(&solscope::state::StepView) -> &Vec<[f64; 2]>,
        ),
        ("Data volume (Mbit)", |v| &v.data),
    ] {
        // Well above the curve: near the top of the plot, under its title.
        let top = h.get_by_label(title).rect();
        let at = eframe::egui::pos2(top.center().x + 100.0, top.bottom() + 12.0);
        h.hover_at(at);
        h.run_steps(3);
        let unit = &title[title.find('(').unwrap() + 1..title.len() - 1];
        let readout = labels(&h)
            .into_iter()
            .find(|l| l.starts_with("Sol ") && l.ends_with(&format!(" {unit}")))
            .unwrap_or_else(|| panic!("{title}: no readout in {:?}", labels(&h)));
        let mut lines = readout.lines();
        let time = lines.next().unwrap();
        let t = solscope_engine::parse_local(&clock, time, None).expect("a time");
        assert_eq!(
            time,
            lmst(h.state(), t),
            "the time, in LMST and plan seconds"
        );
        let value = lines.next().unwrap();
        let want = value_at(pick(&h.state().step_view), t as f64);
        assert_eq!(
            value,
            format!("{want:.1} {unit}"),
            "{title}: the profile's value at {time}"
        );
    }
}

#[test]
fn save_as_and_export_open_in_the_plans_folder() {
    let dir = std::env::temp_dir().join(format!("solscope-read-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/tutorial-plan.json"
    ))
    .unwrap();
    // Opened by a relative path, as `solscope plan.json` does from its folder.
    let relative = std::path::PathBuf::from("plans/mine.json");
    let app = SolscopeApp::from_text(&text, Some(relative)).unwrap();
    let folder = std::path::absolute("plans").unwrap();
    for (dialog, name) in [
        (Dialog::SaveAs, "mine.json"),
        (Dialog::ExportSchedule, "mine-schedule.json"),
        (Dialog::ExportScheduleCsv, "mine-schedule.csv"),
        (Dialog::ExportPng, "mine.png"),
    ] {
        let path = app.suggested_path(dialog);
        assert!(path.is_absolute(), "{dialog:?}: {}", path.display());
        assert_eq!(path, folder.join(name), "{dialog:?}");
        let (dir, file) = solscope::gui::dialog_start(dialog, &path, true);
        assert_eq!(
            dir.as_deref(),
            Some(folder.as_path()),
            "{dialog:?}: portal folder"
        );
        assert_eq!(file.as_deref(), Some(name), "{dialog:?}: portal name");
        // zenity takes no folder: the whole path goes in its file name.
        let (dir, file) = solscope::gui::dialog_start(dialog, &path, false);
        assert_eq!(dir, None, "{dialog:?}");
        assert_eq!(
            file.as_deref(),
            Some(folder.join(name).to_str().unwrap()),
            "{dialog:?}: zenity file name"
        );
    }
    let open = app.suggested_path(Dialog::Open);
    assert_eq!(open, folder.join(""));
    let (dir, file) = solscope::gui::dialog_start(Dialog::Open, &open, false);
    assert_eq!(dir, None);
    assert_eq!(file, Some(format!("{}/", folder.display())));
}

#[test]
fn times_read_in_lmst_with_the_plan_second() {
    let mut app = SolscopeApp::with_default_plan().unwrap();
    let a = index(&app, "drive_412");
    app.apply(Command::Select(Some(a)));
    let h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    let (s, e) = h.state().analysis.placement(a).unwrap();
    let want = format!("scheduled {} – {}", lmst(h.state(), s), lmst(h.state(), e));
    assert!(
        h.query_by_label_contains(&want).is_some(),
        "{want} in {:?}",
        labels(&h)
            .into_iter()
            .filter(|l| l.contains("scheduled"))
            .collect::<Vec<_>>()
    );
    // Said once: which clock that is.
    assert!(h.query_by_label("Time range (LMST)").is_some());
    // No clock reads past 24:00.
    for l in labels(&h) {
        for w in l.split("Sol ").skip(1) {
            if let Some(hh) = w.split(' ').nth(1).and_then(|c| c.get(..2)) {
                if let Ok(hh) = hh.parse::<u32>() {
                    assert!(hh < 24, "{l}");
                }
            }
        }
    }
}

/// The bundled plan in execution mode after a campaign of `runs`, with the
/// activity lost most often selected from the inspector's list, at `size`.
fn executing_with_a_lost_activity(runs: u64, size: [f32; 2]) -> H {
    let mut app = SolscopeApp::with_default_plan().unwrap();
    app.apply(UiCommand::ShowExecution.into());
    app.apply(Command::RunCampaign { runs, seed: 1 });
    let mut h = harness(app, size.into(), &View::default()).unwrap();
    let lost = labels(&h)
        .into_iter()
        .find(|l| l.contains(": lost in "))
        .expect("an activity lost in some run");
    h.get_by_label(&lost).click();
    h.run_steps(4);
    assert!(h.state().ui.nav.selected.is_some(), "{lost} selected");
    h
}

/// The rect of the node labelled `label`.
fn rect_of(h: &H, label: &str) -> eframe::egui::Rect {
    h.get_by_label(label).rect()
}

#[test]
fn panels_never_overlap_in_execution_mode_with_a_lost_activity() {
    for (runs, size) in [
        (200, [1400.0, 900.0]),
        (50, [1600.0, 1000.0]),
        (50, [900.0, 600.0]),
    ] {
        let h = executing_with_a_lost_activity(runs, size);
        let gantt = rect_of(&h, "Gantt chart");
        for label in [
            &format!("Across {runs} runs (seed 1)"),
            "In this execution (nominal)",
        ] {
            let r = rect_of(&h, label);
            assert!(
                r.left() >= gantt.right(),
                "{size:?}: the inspector's \"{label}\" at {r:?}, under the Gantt ({gantt:?})"
            );
        }
        // The header's counts and the mode switch side by side, not over
        // each other.
        let counts = labels(&h)
            .into_iter()
            .find(|l| l.ends_with(" not") && l.contains(" scheduled, "))
            .unwrap();
        let counts = rect_of(&h, &counts);
        let view = rect_of(&h, "View");
        assert!(
            !counts.intersects(view),
            "{size:?}: {counts:?} over View {view:?}"
        );
    }
}

#[test]
fn the_side_panels_resize_and_their_widths_are_kept() {
    let mut h = harness(
        SolscopeApp::with_default_plan().unwrap(),
        SNAPSHOT_SIZE.into(),
        &View::default(),
    )
    .unwrap();
    let handles: Vec<eframe::egui::Rect> = h
        .query_all_by_label("Resize panel")
        .map(|n| n.rect())
        .collect();
    assert_eq!(handles.len(), 2, "the list's and the inspector's");
    let inspector = handles
        .iter()
        .max_by(|a, b| a.center().x.total_cmp(&b.center().x))
        .unwrap()
        .center();
    let before = rect_of(&h, "Gantt chart").width();
    h.hover_at(inspector);
    h.run_steps(1);
    h.drag_at(inspector);
    h.run_steps(1);
    let to = inspector - eframe::egui::vec2(100.0, 0.0);
    h.hover_at(to);
    h.run_steps(1);
    h.drop_at(to);
    h.run_steps(3);
    let width = h.state().persisted.inspector_width.expect("kept");
    assert!((width - 480.0).abs() <= 2.0, "{width}");
    let after = rect_of(&h, "Gantt chart").width();
    assert!((before - after - 100.0).abs() <= 2.0, "{before} -> {after}");
    // Restored on the next start.
    let kept = h.state().persisted.clone();
    let mut app = SolscopeApp::with_default_plan().unwrap();
    app.restore_persisted(kept);
    let h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    assert!((rect_of(&h, "Gantt chart").width() - after).abs() <= 1.0);
}

#[test]
fn suggestions_and_the_banner_say_times_in_sol_time() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/tutorial-plan.json"
    ))
    .unwrap();
    let mut app = SolscopeApp::from_text(&text, None).unwrap();
    let a = index(&app, "sky_flats_mast_busy");
    app.apply(Command::Select(Some(a)));
    let mut h = harness(app, SNAPSHOT_SIZE.into(), &View::default()).unwrap();
    let apply = labels(&h)
        .into_iter()
        .find(|l| l.starts_with("Apply: Widen window 1 of sky_flats_mast_busy to "))
        .expect("the window suggestion");
    // "... to start at Sol 412 09:45:05 (t=60045)": the time in LMST with its
    // plan second, never plan seconds alone.
    let at = &apply[apply.find(" at ").unwrap() + 4..];
    let t: i64 = at[at.find("(t=").expect("a sol time") + 3..at.find(')').unwrap()]
        .parse()
        .unwrap();
    assert!(at.starts_with(&lmst(h.state(), t)), "{apply}");
    let edge = h.state().doc.plan.activities[a].windows.clone();
    h.get_by_label(&apply).click();
    h.run_steps(3);
    // The edit itself is exact, in plan seconds.
    let w = &h.state().doc.plan.activities[a].windows.as_ref().unwrap()[0];
    assert!(w.start == t || w.end == t, "{edge:?} -> {w:?}");
    let banner = labels(&h)
        .into_iter()
        .find(|l| l.contains("newly scheduled:"))
        .expect("the banner");
    assert!(banner.contains(&lmst(h.state(), t)), "{banner}");
    if let Some(moved) = banner.split("moved: ").nth(1).filter(|m| *m != "none") {
        assert!(
            moved.contains("(Sol ") && moved.contains(" → Sol "),
            "{banner}"
        );
    }
}

/// The header's counts ("N of M scheduled, K not") and the mode switch's
/// "View" at every window width from the smallest allowed: side by side with
/// a gap, or the switch on a row of its own, never touching.
#[test]
fn the_header_counts_never_touch_the_mode_switch_at_any_width() {
    let mut h = harness(
        SolscopeApp::with_default_plan().unwrap(),
        [900.0, 700.0].into(),
        &View::default(),
    )
    .unwrap();
    let counts = labels(&h)
        .into_iter()
        .find(|l| l.ends_with(" not") && l.contains(" scheduled, "))
        .unwrap();
    // Every width, so that every place the row can end is tried whatever
    // the plan's name and counts (a 10,000-activity plan's are longer).
    for width in 900..=1700 {
        h.set_size([width as f32, 700.0].into());
        h.run_steps(2);
        let (c, v) = (rect_of(&h, &counts), rect_of(&h, "View"));
        assert!(
            c.right() < v.left() || v.top() >= c.bottom(),
            "{width} px: {counts:?} at {c:?} touches View at {v:?}"
        );
    }
}
