//! Valid plans whose size lies in an unusual place, through the real binary:
//! the work and the output stay in proportion to what is reported.
//!
//! - Many windows: an expanding activity failing on the battery in each of
//!   thousands of windows is explained with one reason range per duration
//!   tried (ranges joined across the starts not tried), not one per window and
//!   duration; below the joining threshold every range is listed as tried.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::{Value, json};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_solscope"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("solscope runs")
}

/// A new, empty scratch directory for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("cli_bounds")
        .join(name);
    if dir.exists() {
        std::fs::remove_dir_all(&dir).unwrap();
    }
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `activities` expanding activities (300 to 600 s) with `windows` windows
/// each, 300 s wide every 1,000 s, drawing far more than the battery holds:
/// every start of every duration fails on `min_soc`.
fn many_windows_plan(activities: usize, windows: i64) -> Value {
    let acts: Vec<Value> = (0..activities)
        .map(|a| {
            let shift = 10 * a as i64;
            let ws: Vec<Value> = (0..windows)
                .map(|i| json!({ "start": i * 1000 + shift, "end": i * 1000 + shift + 300 }))
                .collect();
            json!({
                "id": format!("a{a}"),
                "priority": a + 1,
                "duration": { "min": 300, "max": 600 },
                "energy_rate": 20000.0,
                "windows": ws,
            })
        })
        .collect();
    json!({
        "format": "solscope.plan/1",
        "name": "many windows",
        "horizon": { "start": 0, "end": windows * 1000 + 1000 },
        "battery": { "capacity": 1000.0, "initial": 900.0, "min_soc": 100.0 },
        "power": { "rtg": 100.0, "asleep": 10.0, "awake": 60.0 },
        "activities": acts,
    })
}

/// `explain --no-suggestions` of `plan`, written to `dir`: the document and
/// its length in bytes.
fn explain(dir: &Path, plan: &Value) -> (Value, usize) {
    let path = dir.join("plan.json");
    std::fs::write(&path, serde_json::to_vec(plan).unwrap()).unwrap();
    let out = run(&["explain", "--no-suggestions", path.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    (doc, out.stdout.len())
}

/// The durations of an explanation's reasons, in order, without repeats.
fn durations(ex: &Value) -> Vec<i64> {
    let mut out: Vec<i64> = Vec::new();
    for r in ex["reasons"].as_array().unwrap() {
        let d = r["duration"].as_i64().unwrap();
        if out.last() != Some(&d) {
            out.push(d);
        }
    }
    out
}

#[test]
fn many_windows_give_one_reason_range_per_duration() {
    let windows = 1500;
    let dir = scratch("many");
    let (doc, bytes) = explain(&dir, &many_windows_plan(2, windows));
    let exs = doc["explanations"].as_array().unwrap();
    assert_eq!(exs.len(), 2);
    for (a, ex) in exs.iter().enumerate() {
        assert_eq!(ex["phase"], "placement");
        let reasons = ex["reasons"].as_array().unwrap();
        let ds = durations(ex);
        // The binary search tries a handful of durations, each once.
        assert!(ds.len() >= 2 && ds.len() <= 10, "durations {ds:?}");
        assert_eq!(reasons.len(), ds.len(), "one range per duration");
        let shift = 10 * a as i64;
        for r in reasons {
            assert_eq!(r["kind"], "min_soc");
            // From the first window's first start to the last window's.
            assert_eq!(r["start"].as_i64().unwrap(), shift);
            let d = r["duration"].as_i64().unwrap();
            let last_window = (windows - 1) * 1000 + shift;
            assert_eq!(r["end"].as_i64().unwrap(), last_window + 300);
            assert!((300..=600).contains(&d));
        }
        let notes: Vec<&str> = ex["notes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|n| n.as_str().unwrap())
            .collect();
        let tried = ds.len() as i64 * windows;
        let said = format!("(The starts tried fell into {tried} ranges;");
        assert!(
            notes.iter().any(|n| n.starts_with(&said)),
            "no note of the joined ranges in {notes:?}"
        );
    }
    // The rest of the explanation (valid intervals, intersection) holds a
    // few entries per window; a range per window and duration would be over
    // 1,000 bytes per window.
    let per_window = bytes as i64 / (2 * windows);
    assert!(per_window < 300, "{per_window} bytes per window");
}

#[test]
fn few_windows_list_every_range_as_tried() {
    let windows = 60;
    let dir = scratch("few");
    let (doc, _) = explain(&dir, &many_windows_plan(1, windows));
    let ex = &doc["explanations"][0];
    let reasons = ex["reasons"].as_array().unwrap();
    let ds = durations(ex);
    // One range per window and duration, each inside its window.
    assert_eq!(reasons.len() as i64, ds.len() as i64 * windows);
    for r in reasons {
        let (start, end) = (r["start"].as_i64().unwrap(), r["end"].as_i64().unwrap());
        assert_eq!(start % 1000, 0);
        assert!(
            end - start <= 300,
            "{start}..={end} spans more than a window"
        );
    }
    let joined = ex["notes"].as_array().unwrap().iter().any(|n| {
        n.as_str()
            .unwrap()
            .starts_with("(The starts tried fell into")
    });
    assert!(!joined);
}

/// `activities` expanding activities (10 min to 2 h) heated in a zone with an
/// operable period, without windows, over a horizon of `horizon` seconds; they
/// draw little, so each fits in the first sols.
fn heated_plan(activities: usize, horizon: i64) -> Value {
    let acts: Vec<Value> = (0..activities)
        .map(|a| {
            json!({
                "id": format!("h{a}"),
                "priority": a + 1,
                "duration": { "min": 600, "max": 7200 },
                "energy_rate": 20.0,
                "thermal_zones": ["arm"],
                "awake": "required",
            })
        })
        .collect();
    json!({
        "format": "solscope.plan/1",
        "name": "heated over a long horizon",
        "horizon": { "start": 0, "end": horizon },
        "battery": { "capacity": 1600.0, "initial": 1150.0, "min_soc": 600.0 },
        "power": { "rtg": 110.0, "asleep": 25.0, "awake": 180.0 },
        "sleep": { "wakeup_duration": 300, "shutdown_duration": 300, "min_awake": 1800, "min_sleep": 3600 },
        "thermal_zones": { "arm": {
            "preheat": [ { "from": 0, "duration": 3600 }, { "from": 32000, "duration": 2400 } ],
            "preheat_power": 45.0, "maintenance_power": 15.0,
            "operable": [ { "from": 28800, "to": 64800 } ]
        } },
        "activities": acts,
    })
}

fn write_plan(dir: &Path, plan: &Value) -> String {
    let path = dir.join("plan.json");
    std::fs::write(&path, serde_json::to_vec(plan).unwrap()).unwrap();
    path.display().to_string()
}

#[test]
fn heated_expanding_searches_over_too_many_sols_are_refused_path_named() {
    let dir = scratch("heated");
    // 1e9 s is 11,265 sols of 88,775 s: two such activities pass 20,000.
    let path = write_plan(&dir, &heated_plan(2, 1_000_000_000));
    for command in ["schedule", "explain", "execute", "flex"] {
        let out = run(&[command, &path]);
        assert_eq!(out.status.code(), Some(2), "{command}");
        assert!(out.stdout.is_empty(), "{command} printed a document");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.starts_with("error: activities[1].duration: expanding activities heated in a zone with operable periods"),
            "{command}: {err}"
        );
        assert!(
            err.contains("\"h1\" brings the plan to 22530 (11265 of its own)"),
            "{err}"
        );
    }
    // One of them is within the limit and schedules.
    let path = write_plan(&dir, &heated_plan(1, 1_000_000_000));
    let out = run(&["schedule", &path]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(doc["activities"][0]["status"], "scheduled");
}

#[test]
fn suggestions_for_too_many_failures_are_refused_but_one_failure_is_explained() {
    let dir = scratch("suggestions");
    let generated = run(&["generate", "--activities", "2500", "--sols", "1"]);
    assert!(generated.status.success());
    let path = dir.join("plan.json");
    std::fs::write(&path, &generated.stdout).unwrap();
    let path = path.display().to_string();
    let out = run(&["explain", &path]);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.starts_with("error: activities: ") && err.contains(" of the 2500 activities fail;"),
        "{err}"
    );
    assert!(
        err.contains("use --no-suggestions, or --activity ID"),
        "{err}"
    );
    // The last failure alone, with its suggestions verified (reruns from its
    // step on: the cheapest for a debug build).
    let sched = run(&["schedule", &path]);
    let doc: Value = serde_json::from_slice(&sched.stdout).unwrap();
    let failed = doc["activities"]
        .as_array()
        .unwrap()
        .iter()
        .rfind(|a| a["status"] == "failed")
        .unwrap()["id"]
        .as_str()
        .unwrap()
        .to_string();
    let out = run(&["explain", "--activity", &failed, &path]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(doc["explanations"][0]["activity"], failed.as_str());
}
