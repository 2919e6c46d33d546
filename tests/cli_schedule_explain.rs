//! `solscope schedule` and `solscope explain` through the real binary.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

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

fn json(out: &Output) -> Value {
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON on stdout")
}

const PLANS: [&str; 4] = [
    "assets/default-plan.json",
    "assets/tutorial-plan.json",
    "assets/examples/drill-sol.json",
    "assets/examples/pitfall.json",
];

#[test]
fn schedule_is_byte_identical_across_runs_and_lists_every_activity() {
    for plan in PLANS {
        let a = run(&["schedule", plan]);
        let b = run(&["schedule", plan]);
        assert_eq!(a.stdout, b.stdout, "{plan}: output differs between runs");
        let doc = json(&a);
        assert_eq!(doc["format"], "solscope.schedule/1");
        let text = std::fs::read_to_string(root().join(plan)).unwrap();
        let plan_doc: Value = serde_json::from_str(&text).unwrap();
        let n = plan_doc["activities"].as_array().unwrap().len();
        let acts = doc["activities"].as_array().unwrap();
        assert_eq!(acts.len(), n, "{plan}");
        let steps: Vec<u64> = acts.iter().map(|a| a["step"].as_u64().unwrap()).collect();
        assert_eq!(
            steps,
            (1..=n as u64).collect::<Vec<_>>(),
            "{plan}: step order"
        );
        for key in ["soc", "peak_power", "data_volume"] {
            assert!(
                !doc["profiles"][key].as_array().unwrap().is_empty(),
                "{plan}: {key}"
            );
        }
    }
}

#[test]
fn explain_covers_every_failed_activity() {
    for plan in PLANS {
        let sched = json(&run(&["schedule", plan]));
        let failed: Vec<&str> = sched["activities"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|a| a["status"] != "scheduled")
            .map(|a| a["id"].as_str().unwrap())
            .collect();
        let doc = json(&run(&["explain", plan]));
        assert_eq!(doc["format"], "solscope.explain/1");
        let explained: Vec<&str> = doc["explanations"]
            .as_array()
            .unwrap()
            .iter()
            .map(|e| e["activity"].as_str().unwrap())
            .collect();
        assert_eq!(explained, failed, "{plan}");
        for e in doc["explanations"].as_array().unwrap() {
            assert!(e["failure_step"].as_u64().unwrap() < e["step"].as_u64().unwrap());
            assert!(!e["notes"].as_array().unwrap().is_empty());
            let phase = e["phase"].as_str().unwrap();
            assert!(["valid_intervals", "placement", "dependency", "group"].contains(&phase));
            if phase == "valid_intervals" {
                assert!(!e["conflicts"].as_array().unwrap().is_empty());
            }
            if phase == "placement" {
                assert!(!e["reasons"].as_array().unwrap().is_empty());
            }
        }
    }
}

#[test]
fn explain_text_and_single_activity() {
    let out = run(&["explain", "--text", "assets/examples/pitfall.json"]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("== B (B), step 2"), "{text}");
    assert!(
        text.contains("Sol 0 00:00:00 (t=0)"),
        "sol and local times are shown: {text}"
    );
    // A scheduled activity on request.
    let doc = json(&run(&[
        "explain",
        "--activity",
        "A",
        "assets/examples/pitfall.json",
    ]));
    let e = &doc["explanations"][0];
    assert_eq!(e["activity"], "A");
    assert_eq!(e["status"], "scheduled");
    assert!(e["failure_step"].is_null());
    // An unknown id is an error: message on stderr, nothing on stdout, exit 2.
    let out = run(&[
        "explain",
        "--activity",
        "nope",
        "assets/examples/pitfall.json",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    assert!(String::from_utf8_lossy(&out.stderr).contains("nope"));
}

#[test]
fn pitfall_explains_b_by_the_arm() {
    let doc = json(&run(&["explain", "assets/examples/pitfall.json"]));
    let e = &doc["explanations"][0];
    assert_eq!(e["activity"], "B");
    assert_eq!(e["failure_step"], 1);
    assert_eq!(e["phase"], "valid_intervals");
    assert_eq!(
        e["conflicts"],
        serde_json::json!([["execution", "unit_resource"]])
    );
    assert_eq!(
        e["culprits"],
        serde_json::json!([{ "activity": "A", "category": "unit_resource", "step": 1 }])
    );
}

#[test]
fn readme_worked_example_is_current() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let start = readme
        .find("$ solscope explain --text assets/examples/pitfall.json\n")
        .expect("example in README");
    let block = &readme[start..];
    let body = &block[block.find('\n').unwrap() + 1..block.find("```").unwrap()];
    let out = run(&["explain", "--text", "assets/examples/pitfall.json"]);
    assert_eq!(
        String::from_utf8(out.stdout).unwrap().trim_end(),
        body.trim_end()
    );
}

#[test]
fn a_failed_write_of_the_output_says_what_failed() {
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .expect("/dev/full (Linux)");
    let out = Command::new(env!("CARGO_BIN_EXE_solscope"))
        .args(["schedule", "assets/examples/pitfall.json"])
        .current_dir(root())
        .stdout(full)
        .output()
        .expect("solscope runs");
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("could not write the output"),
        "stderr: {stderr}"
    );
}

#[test]
fn explain_is_byte_identical_on_one_and_on_several_threads() {
    let with_threads = |n: &str| {
        Command::new(env!("CARGO_BIN_EXE_solscope"))
            .args(["explain", "assets/default-plan.json"])
            .env("RAYON_NUM_THREADS", n)
            .current_dir(root())
            .output()
            .expect("solscope runs")
    };
    let one = with_threads("1");
    let four = with_threads("4");
    assert!(one.status.success() && four.status.success());
    assert!(!one.stdout.is_empty());
    assert_eq!(
        one.stdout, four.stdout,
        "output depends on the thread count"
    );
}
