//! `solscope flex` and the execution policies through the real binary: the
//! flexible schedule of the bundled plan is byte-identical from run to run, names
//! the drive conflict, and with `--free-slack` gives every activity a free slack
//! that holds its scheduled start; a plan that does not load is refused at its
//! path with nothing on stdout; `execute --policy fixed|dispatch` with nominal
//! durations runs the schedule, and Monte Carlo campaigns of the three policies
//! draw the same durations run by run.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::process::{Command, Output};

use serde_json::Value;

const BUNDLED: &str = "assets/default-plan.json";

fn solscope(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_solscope"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("solscope runs")
}

fn ok(args: &[&str]) -> Vec<u8> {
    let out = solscope(args);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

fn json(args: &[&str]) -> Value {
    serde_json::from_slice(&ok(args)).expect("JSON on stdout")
}

#[test]
fn flex_of_the_bundled_plan_is_stable_and_names_the_drive_conflict() {
    let a = ok(&["flex", BUNDLED]);
    assert_eq!(a, ok(&["flex", BUNDLED]), "byte-identical");
    let doc: Value = serde_json::from_slice(&a).unwrap();
    assert_eq!(doc["format"], "solscope.flex/1");
    assert_eq!(doc["summary"]["controllability"], "not_controllable");
    let texts: Vec<&str> = doc["controllability"]["constraints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["text"].as_str().unwrap())
        .collect();
    assert!(
        texts.contains(&"drive_413 ends by the cutoff of its window 1"),
        "{texts:?}"
    );
    for a in doc["activities"].as_array().unwrap() {
        let (lb, nom, ub) = (&a["start"]["lb"], &a["start"]["nom"], &a["start"]["ub"]);
        assert!(
            lb.as_i64() <= nom.as_i64() && nom.as_i64() <= ub.as_i64(),
            "{a}"
        );
        assert!(a.get("free_slack").is_none(), "free slack only on request");
    }
    let text = String::from_utf8(ok(&["flex", BUNDLED, "--text", "--free-slack"])).unwrap();
    assert!(text.contains("NOT dynamically controllable"), "{text}");
    assert!(
        text.contains("free slack (every check, others fixed)"),
        "{text}"
    );
}

#[test]
fn free_slack_on_request_holds_each_scheduled_start_of_the_bundled_plan() {
    let doc = json(&["flex", BUNDLED, "--free-slack"]);
    let mut outside = Vec::new();
    for a in doc["activities"].as_array().unwrap() {
        let nom = a["start"]["nom"].as_i64().unwrap();
        let free = a["free_slack"].as_array().expect("free slack");
        let inside = free
            .iter()
            .any(|iv| iv[0].as_i64().unwrap() <= nom && nom <= iv[1].as_i64().unwrap());
        if !inside {
            outside.push(a["id"].as_str().unwrap().to_string());
        }
    }
    assert!(
        outside.is_empty(),
        "scheduled start outside its free slack: {outside:?}"
    );
}

#[test]
fn flex_refuses_a_bad_plan_at_its_path() {
    let out = solscope(&["flex", "tests/malformed/after-unknown-id.json"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("activities[") && err.contains("after"),
        "{err}"
    );
}

#[test]
fn nominal_fixed_and_dispatch_run_the_schedule() {
    let schedule = json(&["schedule", BUNDLED]);
    for policy in ["fixed", "dispatch"] {
        let ex = json(&["execute", BUNDLED, "--policy", policy]);
        for (s, e) in schedule["activities"]
            .as_array()
            .unwrap()
            .iter()
            .zip(ex["activities"].as_array().unwrap())
        {
            assert_eq!(s["id"], e["id"]);
            if s["status"] == "scheduled" {
                assert_eq!(e["outcome"], "completed", "{policy}: {e}");
                assert_eq!(e["start"], s["start"], "{policy}: {e}");
            } else {
                assert_eq!(e["outcome"], "not_run", "{policy}: {e}");
            }
        }
    }
}

#[test]
fn campaigns_of_the_three_policies_share_their_samples() {
    let campaign = |policy: &str, csv: bool| {
        let mut args = vec![
            "montecarlo",
            BUNDLED,
            "--runs",
            "8",
            "--seed",
            "3",
            "--policy",
            policy,
        ];
        if csv {
            args.push("--csv");
        }
        ok(&args)
    };
    let csv = |policy: &str| String::from_utf8(campaign(policy, true)).unwrap();
    // The drawn durations are the columns `duration:ID`: equal under every policy.
    let durations = |text: &str| -> Vec<Vec<String>> {
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let cols: Vec<usize> = (0..header.len())
            .filter(|&i| header[i].starts_with("duration:"))
            .collect();
        assert!(!cols.is_empty());
        lines
            .map(|l| {
                let f: Vec<&str> = l.split(',').collect();
                cols.iter().map(|&i| f[i].to_string()).collect()
            })
            .collect()
    };
    let replan = durations(&csv("replan"));
    assert_eq!(replan, durations(&csv("dispatch")));
    assert_eq!(replan, durations(&csv("fixed")));
    let summary: Value = serde_json::from_slice(&campaign("dispatch", false)).unwrap();
    assert_eq!(summary["policy"], "dispatch");
}

/// A plan of `n` activities, each meeting the one before it: one rigid chain.
fn meets_chain(n: usize) -> String {
    let activities: Vec<String> = (0..n)
        .map(|i| {
            let after = if i == 0 {
                String::new()
            } else {
                format!(
                    r#", "after": [ {{ "activity": "a{}", "meets": true }} ]"#,
                    i - 1
                )
            };
            format!(r#"{{ "id": "a{i}", "priority": {i}, "duration": 10{after} }}"#)
        })
        .collect();
    format!(
        r#"{{ "format": "solscope.plan/1", "name": "chain",
  "horizon": {{ "start": 0, "end": {} }},
  "battery": {{ "capacity": 1000.0, "initial": 900.0, "min_soc": 100.0 }},
  "power": {{ "rtg": 100.0, "asleep": 10.0, "awake": 60.0 }},
  "activities": [ {} ] }}"#,
        20 * n,
        activities.join(",\n")
    )
}

/// A rigid chain lists each member's leader as its neighbour, the leader every
/// member: the neighbour lists are as long as the dispatchable network (a chain
/// of 2,000 once listed the whole chain for every member, 4 million entries).
#[test]
fn neighbours_of_a_rigid_chain_are_linear_in_the_dispatchable_network() {
    let dir = std::env::temp_dir().join(format!("solscope-chain-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let n = 2000;
    let path = dir.join("chain.json");
    std::fs::write(&path, meets_chain(n)).unwrap();
    let doc = json(&["flex", path.to_str().unwrap()]);
    std::fs::remove_dir_all(&dir).unwrap();
    let activities = doc["activities"].as_array().unwrap();
    assert_eq!(activities.len(), n);
    // The neighbours are exactly the activities one dispatchable edge away.
    let mut adjacent: std::collections::BTreeMap<&str, std::collections::BTreeSet<&str>> =
        Default::default();
    for e in doc["dispatchable"].as_array().unwrap() {
        let (from, to) = (e["from"]["activity"].as_str(), e["to"]["activity"].as_str());
        if let (Some(f), Some(t)) = (from, to) {
            if f != t {
                adjacent.entry(f).or_default().insert(t);
                adjacent.entry(t).or_default().insert(f);
            }
        }
    }
    let mut total = 0;
    let mut leaders = 0;
    for a in activities {
        let id = a["id"].as_str().unwrap();
        let listed: std::collections::BTreeSet<&str> = a["neighbours"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_str().unwrap())
            .collect();
        let expected = adjacent.get(id).cloned().unwrap_or_default();
        assert_eq!(listed, expected, "{id}");
        total += listed.len();
        if listed.len() > 1 {
            leaders += 1;
        }
    }
    // One leader for the whole chain: every other activity lists it alone.
    assert_eq!(leaders, 1);
    assert_eq!(total, 2 * (n - 1));
    let edges = doc["dispatchable"].as_array().unwrap().len();
    assert!(total <= 2 * edges, "{total} neighbours, {edges} edges");
}
