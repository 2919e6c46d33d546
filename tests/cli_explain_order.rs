//! `solscope explain` on an activity that depends on one later in the step
//! order: the note says the other comes later (not that it did not get
//! scheduled), and scheduling it first is a verified suggestion.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::process::{Command, Output};

use serde_json::{Value, json};

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_solscope"))
        .args(args)
        .output()
        .expect("solscope runs")
}

fn plan_file() -> std::path::PathBuf {
    let plan = json!({
        "format": "solscope.plan/1",
        "horizon": { "start": 0, "end": 10000 },
        "battery": { "capacity": 1000.0, "initial": 1000.0, "min_soc": 0.0 },
        "power": { "rtg": 0.0, "asleep": 0.0, "awake": 0.0 },
        "activities": [
            { "id": "img", "priority": 2, "duration": 100, "awake": "any",
              "after": [ { "activity": "drive" } ] },
            { "id": "drive", "priority": 5, "duration": 1000, "awake": "any" }
        ]
    });
    let dir = std::env::temp_dir().join(format!("solscope-cli-order-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("later.json");
    std::fs::write(&path, plan.to_string()).unwrap();
    path
}

#[test]
fn a_dependency_later_in_step_order_is_said_so_and_moved_first() {
    let path = plan_file();
    let path = path.to_str().unwrap();
    let text = run(&["explain", path, "--text"]);
    assert!(text.status.success());
    let text = String::from_utf8(text.stdout).unwrap();
    assert!(
        text.contains(
            "img must come after drive, but drive comes later in step order (priority 5), so \
             it cannot have run first; img cannot be scheduled."
        ),
        "{text}"
    );
    assert!(!text.contains("did not get scheduled"), "{text}");
    let out = run(&["explain", path]);
    assert!(out.status.success());
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
    let ex = doc["explanations"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["activity"] == "img")
        .expect("img explained");
    let moved = ex["suggestions"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["edit"]["target"] == "activity:drive")
        .expect("the reordering is suggested");
    assert_eq!(
        moved["description"],
        "Schedule drive before img by giving it priority 1"
    );
    assert_eq!(moved["edit"]["set"]["priority"], 1);
    assert_eq!(moved["side_effects"], json!([]));
}
