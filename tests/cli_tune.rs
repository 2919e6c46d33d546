//! `solscope tune` through the real binary: on the tuning example the document
//! fixes both problems the example describes, byte-identical from run to run and
//! on one or two threads; `--write-plan` writes a plan that differs from the
//! input only in priorities and that schedules; Ctrl+C stops the search and
//! still prints the best order found, marked as stopped early; bad input is
//! refused at its path with nothing on stdout, exit status 2 and no file written.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::Duration;

use serde_json::Value;

const EXAMPLE: &str = "assets/tuning-examples/order-matters.json";
const BUNDLED: &str = "assets/default-plan.json";

fn solscope_env(args: &[&str], env: &[(&str, &str)]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_solscope"))
        .args(args)
        .envs(env.iter().copied())
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("solscope runs")
}

fn solscope(args: &[&str]) -> Output {
    solscope_env(args, &[])
}

fn ok(out: Output, what: &str) -> Vec<u8> {
    assert_eq!(
        out.status.code(),
        Some(0),
        "{what}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// A fresh directory of this test's own.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("cli_tune-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn activity<'a>(doc: &'a Value, id: &str) -> &'a Value {
    doc["activities"]
        .as_array()
        .unwrap()
        .iter()
        .find(|a| a["id"] == id)
        .unwrap_or_else(|| panic!("no {id}"))
}

fn completed(doc: &Value, id: &str, when: &str) -> u64 {
    activity(doc, id)["held_out"][when]["completed"]
        .as_u64()
        .unwrap()
}

fn step_rank(doc: &Value, id: &str) -> (i64, usize) {
    let all = doc["activities"].as_array().unwrap();
    let index = all.iter().position(|a| a["id"] == id).unwrap();
    (all[index]["priority_after"].as_i64().unwrap(), index)
}

#[test]
fn the_example_is_tuned_to_fix_both_problems_the_same_on_any_threads() {
    let one = ok(
        solscope_env(&["tune", EXAMPLE], &[("RAYON_NUM_THREADS", "1")]),
        "1 thread",
    );
    let two = ok(
        solscope_env(&["tune", EXAMPLE], &[("RAYON_NUM_THREADS", "2")]),
        "2 threads",
    );
    let again = ok(solscope(&["tune", EXAMPLE]), "again");
    assert!(one == two, "byte-identical on 1 and 2 threads");
    assert!(two == again, "byte-identical from run to run");
    assert!(one.ends_with(b"}\n"), "one document and a final newline");
    let doc: Value = serde_json::from_slice(&one).unwrap();
    assert_eq!(doc["format"], "solscope.tuning/1");
    assert_eq!(doc["search"]["stopped_early"], false);
    // SuperCam now comes before the mosaic, the SHERLOC scan before WATSON.
    assert!(step_rank(&doc, "supercam_target") < step_rank(&doc, "mastcam_mosaic"));
    assert!(step_rank(&doc, "sherloc_scan") < step_rank(&doc, "watson_image"));
    let changed: Vec<&str> = doc["changes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["id"].as_str().unwrap())
        .collect();
    assert!(changed.contains(&"supercam_target"), "{changed:?}");
    assert!(changed.contains(&"sherloc_scan"), "{changed:?}");
    // ...and both now complete in every held-out run, where they did not.
    let runs = doc["held_out_sample"]["runs"].as_u64().unwrap();
    for id in ["supercam_target", "sherloc_scan"] {
        assert!(completed(&doc, id, "before") < runs, "{id} was lost before");
        assert_eq!(completed(&doc, id, "after"), runs, "{id} after");
    }
    assert_eq!(doc["held_out"]["verdict"], "better");
}

#[test]
fn the_written_plan_differs_only_in_priorities_and_schedules() {
    let dir = scratch("write");
    let target = dir.join("tuned.json");
    std::fs::write(&target, "old").unwrap();
    let t = target.to_str().unwrap();
    let out = ok(solscope(&["tune", EXAMPLE, "--write-plan", t]), "tune");
    let doc: Value = serde_json::from_slice(&out).unwrap();
    let mut input: Value =
        serde_json::from_str(&std::fs::read_to_string(EXAMPLE).unwrap()).unwrap();
    let mut tuned: Value = serde_json::from_str(&std::fs::read_to_string(&target).unwrap())
        .expect("the old file was replaced by the tuned plan");
    // The written priorities are the document's, and they changed.
    let edits = doc["edits"].as_array().unwrap();
    assert!(!edits.is_empty());
    let mut changed = 0;
    for (a, b) in input["activities"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .zip(tuned["activities"].as_array_mut().unwrap())
    {
        assert_eq!(a["id"], b["id"]);
        let after = activity(&doc, a["id"].as_str().unwrap())["priority_after"].clone();
        assert_eq!(b["priority"], after, "{}", a["id"]);
        if a["priority"] != b["priority"] {
            changed += 1;
        }
        a.as_object_mut().unwrap().remove("priority");
        b.as_object_mut().unwrap().remove("priority");
    }
    assert_eq!(changed, edits.len());
    assert_eq!(input, tuned, "nothing but priorities differs");
    let schedule = ok(solscope(&["schedule", t]), "schedule the tuned plan");
    let schedule: Value = serde_json::from_slice(&schedule).unwrap();
    assert_eq!(schedule["format"], "solscope.schedule/1");
    let leftovers: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert_eq!(leftovers.len(), 1, "no temporary file is left behind");
}

#[test]
fn ctrl_c_stops_the_search_and_prints_the_best_order_so_far() {
    // A search far longer than the test: tens of minutes to use the budget.
    let child = Command::new(env!("CARGO_BIN_EXE_solscope"))
        .args([
            "tune",
            BUNDLED,
            "--runs",
            "20",
            "--confirm-runs",
            "20",
            "--budget",
            "100000",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("solscope runs");
    std::thread::sleep(Duration::from_secs(3));
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(kill.success());
    let out = child.wait_with_output().unwrap();
    let doc: Value = serde_json::from_slice(&ok(out, "interrupted")).unwrap();
    assert_eq!(doc["format"], "solscope.tuning/1");
    assert_eq!(doc["search"]["stopped_early"], true);
    assert_eq!(doc["search"]["stop"], "cancelled");
    let evaluations = doc["search"]["evaluations"].as_u64().unwrap();
    assert!((1..100_000).contains(&evaluations), "{evaluations}");
    assert!(doc["held_out"]["no_worse"].is_boolean());
}

/// Runs `tune` with `args` and `--write-plan` into a fresh directory: exit
/// status 2, nothing on stdout, a message naming `path`, and no file.
fn refused(name: &str, plan: &str, args: &[&str], path: &str) {
    let dir = scratch(name);
    let target = dir.join("tuned.json");
    let mut all = vec!["tune", plan, "--write-plan", target.to_str().unwrap()];
    all.extend_from_slice(args);
    let out = solscope(&all);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{name}: {err}");
    assert!(out.stdout.is_empty(), "{name}: nothing on stdout");
    assert!(
        err.starts_with(&format!("error: {path}: ")),
        "{name}: {err}"
    );
    assert!(!target.exists(), "{name}: no file written");
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0, "{name}");
}

#[test]
fn an_unknown_pin_is_refused() {
    refused(
        "pin",
        EXAMPLE,
        &["--pin", "drive", "--pin", "no_such"],
        "--pin",
    );
}

#[test]
fn zero_runs_and_a_smaller_held_out_sample_are_refused() {
    refused("runs", EXAMPLE, &["--runs", "0"], "--runs");
    refused(
        "confirm",
        EXAMPLE,
        &["--runs", "30", "--confirm-runs", "29"],
        "--confirm-runs",
    );
    refused("seed", EXAMPLE, &["--confirm-seed", "1"], "--confirm-seed");
    refused("budget", EXAMPLE, &["--budget", "0"], "--budget");
}

#[test]
fn a_plan_where_nothing_can_move_is_refused() {
    // Every activity pinned.
    let ids = [
        "mastcam_mosaic",
        "supercam_target",
        "drive",
        "watson_image",
        "sherloc_scan",
    ];
    let mut args = Vec::new();
    for id in ids {
        args.extend(["--pin", id]);
    }
    let input: Value = serde_json::from_str(&std::fs::read_to_string(EXAMPLE).unwrap()).unwrap();
    let all: Vec<&str> = input["activities"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a["id"].as_str().unwrap())
        .collect();
    assert_eq!(all, ids, "the example's activities");
    refused("all-pinned", EXAMPLE, &args, EXAMPLE);
    // A plan of one activity.
    let mut one = input.clone();
    one["activities"].as_array_mut().unwrap().truncate(1);
    let dir = scratch("one-plan");
    let plan = dir.join("one.json");
    std::fs::write(&plan, one.to_string()).unwrap();
    let plan = plan.to_str().unwrap();
    refused("one", plan, &[], plan);
}

#[test]
fn a_plan_that_cannot_be_written_leaves_nothing_behind() {
    // The target is a directory: the rename fails after the search.
    let dir = scratch("unwritable");
    let target = dir.join("taken");
    std::fs::create_dir(&target).unwrap();
    std::fs::write(target.join("inside"), "kept").unwrap();
    let out = solscope(&["tune", EXAMPLE, "--write-plan", target.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(out.stdout.is_empty(), "nothing on stdout");
    assert!(
        err.starts_with(&format!("error: {}: could not write: ", target.display())),
        "{err}"
    );
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["taken"], "no temporary file is left behind");
    assert_eq!(
        std::fs::read_to_string(target.join("inside")).unwrap(),
        "kept"
    );
    // A directory that does not exist is refused before the search.
    let missing = dir.join("no/such/dir/tuned.json");
    let out = solscope(&["tune", EXAMPLE, "--write-plan", missing.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty());
    assert!(!dir.join("no").exists());
}

#[test]
fn refused_input_leaves_an_old_plan_untouched() {
    let dir = scratch("old");
    let target = dir.join("tuned.json");
    std::fs::write(&target, "old").unwrap();
    let out = solscope(&[
        "tune",
        EXAMPLE,
        "--runs",
        "0",
        "--write-plan",
        target.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "old");
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
}
