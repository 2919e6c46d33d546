//! `solscope execute` and `solscope montecarlo` through the real binary: the
//! extension's example runs as the spec says (nominal and with its actuals file),
//! bad actuals are refused at their path with nothing on stdout, a sampled run
//! written with --write-actuals replays to the same document, a Monte Carlo run
//! replays as `execute --sample S --run I`, and shards merge into exactly the
//! one-machine summary, also as CSV; a replanning campaign of a long
//! dependency chain is refused at the chain.

// Test helpers outside `#[test]` functions are not covered by clippy.toml's
// allow-*-in-tests; a failed expectation here is a test failure.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn solscope(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_solscope"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("solscope runs")
}

fn ok_json(args: &[&str]) -> Value {
    let out = solscope(args);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON on stdout")
}

fn refused(args: &[&str]) -> String {
    let out = solscope(args);
    assert_eq!(out.status.code(), Some(2), "{args:?}");
    assert!(out.stdout.is_empty(), "{args:?}: stdout not empty");
    String::from_utf8(out.stderr).expect("UTF-8")
}

fn scratch(name: &str, text: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_execute");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write");
    path
}

const EXAMPLE: &str = "assets/execution-examples/uncertain-drive.json";
const ACTUALS: &str = "assets/execution-examples/uncertain-drive.actuals.json";

#[test]
fn the_example_runs_nominal_and_with_its_actuals() {
    let nominal = ok_json(&["execute", EXAMPLE]);
    assert_eq!(nominal["format"], "solscope.execution/1");
    for a in nominal["activities"].as_array().unwrap() {
        assert_eq!(a["outcome"], "completed", "{a}");
        assert_eq!(a["start"], a["predicted_start"], "{a}");
        assert_eq!(a["end"], a["predicted_end"], "{a}");
    }
    let doc = ok_json(&["execute", EXAMPLE, "--actuals", ACTUALS]);
    assert_eq!(doc["actuals"]["drive"], 6300);
    let drive = &doc["activities"][0];
    assert_eq!(
        (drive["start"].as_i64(), drive["end"].as_i64()),
        (Some(1000), Some(7300))
    );
    // The imaging after the drive waits for it: the cycle at its end starts it.
    let imaging = &doc["activities"][1];
    assert_eq!(imaging["start"], 7300);
    let cycle = &doc["cycles"][imaging["cycle"].as_u64().unwrap() as usize];
    assert_eq!(cycle["trigger"], "end");
    assert_eq!(cycle["ended"], "drive");
    // Replanning every 1800 s and on every end: cycles at 0, 1800, ... and 7300.
    let times: Vec<i64> = doc["cycles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["time"].as_i64().unwrap())
        .collect();
    assert!(
        times.starts_with(&[0, 1800, 3600, 5400, 7200, 7300]),
        "{times:?}"
    );
}

#[test]
fn bad_actuals_are_refused_at_their_path() {
    let unknown = scratch(
        "unknown.json",
        r#"{ "format": "solscope.actuals/1", "durations": { "rover": 10 } }"#,
    );
    let err = refused(&["execute", EXAMPLE, "--actuals", unknown.to_str().unwrap()]);
    assert!(
        err.contains("unknown.json: durations.rover: unknown activity \"rover\""),
        "{err}"
    );
    let negative = scratch(
        "negative.json",
        r#"{ "format": "solscope.actuals/1", "durations": { "drive": -5 } }"#,
    );
    let err = refused(&["execute", EXAMPLE, "--actuals", negative.to_str().unwrap()]);
    assert!(err.contains("durations.drive"), "{err}");
    let err = refused(&["execute", EXAMPLE, "--actuals", "/nonexistent/actuals.json"]);
    assert!(err.contains("/nonexistent/actuals.json"), "{err}");
    // A plan with an invalid duration_model is refused before anything runs.
    let plan = scratch(
        "bad-model.json",
        &std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(EXAMPLE))
            .unwrap()
            .replace("\"min\": 3600", "\"min\": 9000"),
    );
    let err = refused(&["execute", plan.to_str().unwrap()]);
    assert!(
        err.contains("activities[0].duration_model.max: must be >= min"),
        "{err}"
    );
}

#[test]
fn a_sampled_run_written_out_replays() {
    // Its own scratch directory: the tests run in any order, in parallel.
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_execute_sampled");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let written = dir.join("sampled.json");
    if written.exists() {
        std::fs::remove_file(&written).expect("remove the previous run's file");
    }
    let sampled = ok_json(&[
        "execute",
        EXAMPLE,
        "--sample",
        "42",
        "--run",
        "3",
        "--write-actuals",
        written.to_str().unwrap(),
    ]);
    let actuals: Value = serde_json::from_str(&std::fs::read_to_string(&written).unwrap()).unwrap();
    assert_eq!(actuals["format"], "solscope.actuals/1");
    let drive = actuals["durations"]["drive"].as_i64().unwrap();
    assert!((3600..=6600).contains(&drive), "{drive}");
    let replayed = ok_json(&["execute", EXAMPLE, "--actuals", written.to_str().unwrap()]);
    assert_eq!(sampled, replayed);
}

#[test]
fn montecarlo_runs_replay_and_shards_merge() {
    let whole = solscope(&["montecarlo", EXAMPLE, "--runs", "40", "--seed", "5"]);
    assert_eq!(whole.status.code(), Some(0));
    let summary: Value = serde_json::from_slice(&whole.stdout).unwrap();
    assert_eq!(summary["format"], "solscope.montecarlo/1");
    assert_eq!(summary["runs"], 40);
    for a in summary["activities"].as_array().unwrap() {
        let total = a["completed"].as_u64().unwrap()
            + a["aborted"].as_u64().unwrap()
            + a["not_run"].as_u64().unwrap();
        assert_eq!(total, 40, "{a}");
    }
    // Shards in any order merge into exactly the same bytes.
    let mut parts = Vec::new();
    for i in [2, 0, 1] {
        let out = solscope(&[
            "montecarlo",
            EXAMPLE,
            "--runs",
            "40",
            "--seed",
            "5",
            "--shard",
            &format!("{i}/3"),
        ]);
        assert_eq!(out.status.code(), Some(0));
        let part = scratch(
            &format!("part{i}.json"),
            std::str::from_utf8(&out.stdout).unwrap(),
        );
        parts.push(part.to_str().unwrap().to_string());
    }
    let mut args = vec!["montecarlo", "merge"];
    args.extend(parts.iter().map(String::as_str));
    let merged = solscope(&args);
    assert_eq!(merged.status.code(), Some(0));
    assert_eq!(merged.stdout, whole.stdout);
    // CSV: one row per run, the same from the merge as from one machine.
    let csv = solscope(&[
        "montecarlo",
        EXAMPLE,
        "--runs",
        "40",
        "--seed",
        "5",
        "--csv",
    ]);
    let text = String::from_utf8(csv.stdout.clone()).unwrap();
    assert_eq!(text.lines().count(), 41);
    assert!(text.starts_with("run,lowest_soc_wh,"), "{text}");
    // RFC 4180: every line, the header's too, ends with CRLF.
    assert_eq!(text.matches("\r\n").count(), 41, "{text:?}");
    assert_eq!(text.matches('\n').count(), 41, "{text:?}");
    assert!(text.ends_with("\r\n"), "{text:?}");
    args.push("--csv");
    assert_eq!(solscope(&args).stdout, csv.stdout);
    // A missing shard is refused.
    let err = refused(&["montecarlo", "merge", &parts[0], &parts[1]]);
    assert!(
        err.contains("missing") || err.contains("of 40 runs"),
        "{err}"
    );
    // Run 7 of the campaign is `execute --sample 5 --run 7`.
    let rows: Vec<&str> = text.lines().collect();
    let header: Vec<&str> = rows[0].split(',').collect();
    let row7: Vec<&str> = rows[8].split(',').collect();
    let col = header.iter().position(|h| *h == "duration:drive").unwrap();
    let ex = ok_json(&["execute", EXAMPLE, "--sample", "5", "--run", "7"]);
    assert_eq!(ex["actuals"]["drive"].to_string(), row7[col]);
    // One process runs at most 100,000 runs: a bigger campaign is sharded.
    let err = refused(&["montecarlo", EXAMPLE, "--runs", "200000"]);
    assert!(err.contains("split the campaign with --shard"), "{err}");
    // Bad shards are refused.
    for bad in ["3/3", "1", "a/b", "0/0"] {
        let err = refused(&["montecarlo", EXAMPLE, "--shard", bad]);
        assert!(err.contains("--shard"), "{bad}: {err}");
    }
}

/// The parts of `--runs RUNS` split `of` ways, written to scratch files named
/// after `tag`, in shard order.
fn shard_files(tag: &str, runs: u64, of: u64) -> Vec<String> {
    (0..of)
        .map(|i| {
            let args = [
                "montecarlo",
                EXAMPLE,
                "--runs",
                &runs.to_string(),
                "--shard",
                &format!("{i}/{of}"),
            ];
            let out = solscope(&args);
            assert_eq!(
                out.status.code(),
                Some(0),
                "{args:?}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            let part = scratch(
                &format!("{tag}-{i}.json"),
                std::str::from_utf8(&out.stdout).unwrap(),
            );
            part.to_str().unwrap().to_string()
        })
        .collect()
}

#[test]
fn shards_past_the_last_run_are_empty_and_merge() {
    let parts = shard_files("wide", 10, 32);
    // Shards 10 to 31 hold no run.
    for (i, part) in parts.iter().enumerate() {
        let doc: Value = serde_json::from_str(&std::fs::read_to_string(part).unwrap()).unwrap();
        let records = doc["records"].as_array().unwrap();
        assert_eq!(records.len(), usize::from(i < 10), "shard {i}");
        assert_eq!(doc["shard"], serde_json::json!([i, 32]));
    }
    let mut args = vec!["montecarlo", "merge"];
    args.extend(parts.iter().map(String::as_str));
    let merged = solscope(&args);
    assert_eq!(merged.status.code(), Some(0));
    let whole = solscope(&["montecarlo", EXAMPLE, "--runs", "10"]);
    assert_eq!(whole.status.code(), Some(0));
    assert_eq!(merged.stdout, whole.stdout);
    args.push("--csv");
    let merged_csv = solscope(&args);
    assert_eq!(merged_csv.status.code(), Some(0));
    let whole_csv = solscope(&["montecarlo", EXAMPLE, "--runs", "10", "--csv"]);
    assert_eq!(whole_csv.status.code(), Some(0));
    assert_eq!(merged_csv.stdout, whole_csv.stdout);
    // Shards far past the runs, up to the largest K, hold nothing either.
    let max = u64::MAX.to_string();
    for shard in [
        "11/32".to_string(),
        format!("{}/{max}", u64::MAX - 1),
        format!("9/{max}"),
    ] {
        let doc = ok_json(&["montecarlo", EXAMPLE, "--runs", "10", "--shard", &shard]);
        let want = usize::from(shard.starts_with('9'));
        assert_eq!(doc["records"].as_array().unwrap().len(), want, "{shard}");
    }
}

/// Merges the three parts of a 30-run campaign with `edit` applied to the
/// part of shard 1 (written as `part-1.json`): the merge's output.
fn merge_edited(tag: &str, edit: impl Fn(&mut Value)) -> Output {
    let parts = shard_files(tag, 30, 3);
    let mut doc: Value =
        serde_json::from_str(&std::fs::read_to_string(&parts[1]).unwrap()).unwrap();
    edit(&mut doc);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("cli_execute")
        .join(tag);
    std::fs::create_dir_all(&dir).unwrap();
    let edited = dir.join("part-1.json");
    std::fs::write(&edited, serde_json::to_string_pretty(&doc).unwrap()).unwrap();
    let edited = edited.to_str().unwrap().to_string();
    let args = ["montecarlo", "merge", &parts[0], &edited, &parts[2]];
    // Unedited, the same parts merge.
    let fine = solscope(&["montecarlo", "merge", &parts[0], &parts[1], &parts[2]]);
    assert_eq!(fine.status.code(), Some(0), "{tag}");
    solscope(&args)
}

/// The merge was refused with nothing on stdout and the message names the
/// edited file and `path`.
fn refused_at(out: &Output, path: &str) -> String {
    let err = String::from_utf8(out.stderr.clone()).unwrap();
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(out.stdout.is_empty(), "stdout not empty: {err}");
    assert!(err.contains(&format!("part-1.json: {path}: ")), "{err}");
    err
}

#[test]
fn merge_refuses_an_outcome_character_out_of_its_enumeration() {
    let out = merge_edited("outcome-char", |doc| {
        let o = doc["records"][4]["outcomes"].as_str().unwrap().to_string();
        doc["records"][4]["outcomes"] = Value::from(format!("x{}", &o[1..]));
    });
    let err = refused_at(&out, "records[4].outcomes");
    assert!(err.contains("'x'"), "{err}");
}

#[test]
fn merge_refuses_a_loss_of_no_activity() {
    let out = merge_edited("loss-index", |doc| {
        let loss = serde_json::json!({
            "activity": 999999, "cause": "aborted", "cycle_time": null, "culprits": []
        });
        doc["records"][2]["losses"]
            .as_array_mut()
            .unwrap()
            .push(loss);
    });
    let err = refused_at(&out, "records[2].losses[0].activity");
    assert!(err.contains("999999"), "{err}");
}

#[test]
fn merge_refuses_outcomes_one_character_short() {
    let out = merge_edited("outcome-short", |doc| {
        let o = doc["records"][0]["outcomes"].as_str().unwrap().to_string();
        doc["records"][0]["outcomes"] = Value::from(&o[1..]);
    });
    refused_at(&out, "records[0].outcomes");
}

#[test]
fn merge_refuses_a_shard_with_i_not_below_k() {
    let out = merge_edited("shard-1-0", |doc| {
        doc["shard"] = serde_json::json!([1, 0]);
    });
    refused_at(&out, "shard");
}

#[test]
fn merge_refuses_runs_outside_the_shard_or_the_campaign() {
    // Run 3 is not 1 modulo 3.
    let out = merge_edited("run-other-shard", |doc| {
        doc["records"][0]["run"] = Value::from(3);
    });
    refused_at(&out, "records[0].run");
    // Run 31 is 1 modulo 3 but not below 30.
    let out = merge_edited("run-past-runs", |doc| {
        let last = doc["records"].as_array().unwrap().len() - 1;
        doc["records"][last]["run"] = Value::from(31);
    });
    refused_at(&out, "records[9].run");
    // A header that disagrees with the other parts'.
    let out = merge_edited("header", |doc| {
        doc["campaign"]["seed"] = Value::from(99);
    });
    refused_at(&out, "campaign");
}

#[test]
fn merge_refuses_a_run_given_twice() {
    let parts = shard_files("twice", 30, 3);
    let out = solscope(&[
        "montecarlo",
        "merge",
        &parts[0],
        &parts[1],
        &parts[2],
        &parts[1],
    ]);
    let err = String::from_utf8(out.stderr.clone()).unwrap();
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(out.stdout.is_empty());
    assert!(
        err.contains(&format!(
            "{}: records[0].run: run 1 appears twice",
            parts[1]
        )),
        "{err}"
    );
}

#[test]
fn an_activity_listed_twice_in_actuals_is_refused() {
    // A plan refuses a duplicate id; so do actuals (a map would keep the last).
    let twice = scratch(
        "twice.json",
        r#"{ "format": "solscope.actuals/1", "durations": { "drive": 6300, "drive": 4000 } }"#,
    );
    let err = refused(&["execute", EXAMPLE, "--actuals", twice.to_str().unwrap()]);
    assert!(
        err.contains("twice.json: durations") && err.contains("duplicate id \"drive\""),
        "{err}"
    );
    let once = scratch(
        "once.json",
        r#"{ "format": "solscope.actuals/1", "durations": { "drive": 6300, "arm_science": 2000 } }"#,
    );
    ok_json(&["execute", EXAMPLE, "--actuals", once.to_str().unwrap()]);
}

/// A chain of `n` activities of 600 s, each meeting the one before, every
/// tenth with a duration model (the shape docs/performance.md measures).
fn meets_chain(n: usize) -> String {
    let activities: Vec<Value> = (0..n)
        .map(|i| {
            let mut a = serde_json::json!({
                "id": format!("a{i}"), "priority": i + 1, "duration": 600,
                "energy_rate": 40.0, "resources": ["arm"]
            });
            if i > 0 {
                a["after"] =
                    serde_json::json!([{ "activity": format!("a{}", i - 1), "meets": true }]);
            }
            if i % 10 == 5 {
                a["duration_model"] = serde_json::json!({ "min": 400, "max": 900 });
            }
            a
        })
        .collect();
    serde_json::json!({
        "format": "solscope.plan/1",
        "name": "chain",
        "horizon": { "start": 0, "end": n * 1200 + 10000 },
        "battery": { "capacity": 2000.0, "initial": 1500.0, "min_soc": 500.0 },
        "power": { "rtg": 200.0, "asleep": 25.0, "awake": 150.0 },
        "sleep": { "wakeup_duration": 300, "shutdown_duration": 300,
                   "min_awake": 1800, "min_sleep": 3600 },
        "activities": activities
    })
    .to_string()
}

#[test]
fn a_replanning_campaign_of_a_long_dependency_chain_is_refused_at_the_chain() {
    // 20 runs of a 2,000-activity chain: each run schedules the rest of the
    // chain at every end (minutes of CPU), refused before any run.
    let long = scratch("chain-2000.json", &meets_chain(2000));
    let long = long.to_str().expect("UTF-8 path");
    let err = refused(&["montecarlo", long, "--runs", "20"]);
    assert!(err.contains("activities[1999].after"), "{err}");
    assert!(err.contains("chain of 2000 activities"), "{err}");
    assert!(err.contains("at most 5"), "{err}");
    // The bound is on the work: a short chain runs a few runs, and is refused
    // past the same work.
    let short = scratch("chain-100.json", &meets_chain(100));
    let short = short.to_str().expect("UTF-8 path");
    let summary = ok_json(&["montecarlo", short, "--runs", "3"]);
    assert_eq!(summary["runs"], 3, "{summary}");
    let err = refused(&["montecarlo", short, "--runs", "2001"]);
    assert!(err.contains("activities[99].after"), "{err}");
    assert!(err.contains("at most 2000"), "{err}");
    // A policy that does not replan is not bounded: one run past the bound.
    let fixed = ok_json(&["montecarlo", long, "--runs", "6", "--policy", "fixed"]);
    assert_eq!(fixed["runs"], 6, "{fixed}");
}
