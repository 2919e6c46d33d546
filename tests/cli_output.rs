//! Files the commands write, through the real binary: `--output FILE` holds
//! exactly what standard output would have held (and standard output nothing)
//! for every command that prints a document; a command that fails leaves the
//! file as it was and nothing beside it; a file that cannot be written is named
//! with exit status 1. `screenshot` checks its `--out` name, its `--select` and
//! its `--step` before it renders, with the exit status of every command's
//! invalid input.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BUNDLED: &str = "assets/default-plan.json";
const UNCERTAIN: &str = "assets/execution-examples/uncertain-drive.json";

fn solscope(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_solscope"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("solscope runs")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A new, empty scratch directory for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("cli_output")
        .join(name);
    if dir.exists() {
        std::fs::remove_dir_all(&dir).unwrap();
    }
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The names in a directory, sorted.
fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn output_holds_what_stdout_would_have_and_stdout_nothing() {
    let dir = scratch("same");
    let parts: Vec<String> = (0..2)
        .map(|i| dir.join(format!("part{i}.json")).display().to_string())
        .collect();
    for (i, part) in parts.iter().enumerate() {
        let shard = format!("{i}/2");
        let out = solscope(&[
            "montecarlo",
            UNCERTAIN,
            "--runs",
            "6",
            "--shard",
            &shard,
            "--output",
            part,
        ]);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        assert!(out.stdout.is_empty());
    }
    let commands: Vec<Vec<&str>> = vec![
        vec!["schedule", BUNDLED],
        vec!["explain", "assets/examples/pitfall.json"],
        vec!["explain", "--text", "assets/examples/pitfall.json"],
        vec!["check", BUNDLED],
        vec!["execute", UNCERTAIN, "--sample", "3"],
        vec!["montecarlo", UNCERTAIN, "--runs", "6"],
        vec!["montecarlo", "merge", &parts[0], &parts[1]],
        vec!["montecarlo", "merge", &parts[0], &parts[1], "--csv"],
        vec!["flex", BUNDLED, "--text"],
        vec!["generate", "--activities", "20"],
        vec![
            "tune",
            "assets/tuning-examples/order-matters.json",
            "--runs",
            "4",
            "--confirm-runs",
            "4",
            "--budget",
            "3",
        ],
    ];
    for (i, args) in commands.iter().enumerate() {
        let printed = solscope(args);
        assert_eq!(
            printed.status.code(),
            Some(0),
            "{args:?}: {}",
            stderr(&printed)
        );
        assert!(!printed.stdout.is_empty(), "{args:?}");
        let file = dir.join(format!("out{i}"));
        let file_arg = file.display().to_string();
        // Over an older file, which is replaced.
        std::fs::write(&file, "older").unwrap();
        let mut with = args.clone();
        with.extend(["--output", &file_arg]);
        let written = solscope(&with);
        assert_eq!(
            written.status.code(),
            Some(0),
            "{with:?}: {}",
            stderr(&written)
        );
        assert!(written.stdout.is_empty(), "{with:?}: stdout");
        assert_eq!(std::fs::read(&file).unwrap(), printed.stdout, "{with:?}");
    }
    let mut expected: Vec<String> = (0..commands.len()).map(|i| format!("out{i}")).collect();
    expected.extend(["part0.json".into(), "part1.json".into()]);
    expected.sort();
    assert_eq!(entries(&dir), expected, "nothing else left beside them");
}

#[test]
fn a_failed_command_leaves_the_file_as_it_was() {
    let dir = scratch("failed");
    let file = dir.join("out.json");
    let file_arg = file.display().to_string();
    let bad = dir.join("bad.json");
    std::fs::write(&bad, "{ \"format\": \"solscope.plan/1\", ").unwrap();
    let bad_arg = bad.display().to_string();
    for args in [
        vec!["schedule", &bad_arg],
        vec!["explain", &bad_arg],
        vec!["flex", &bad_arg],
        vec!["montecarlo", &bad_arg, "--runs", "3"],
        vec!["explain", BUNDLED, "--activity", "nope"],
    ] {
        std::fs::write(&file, "the old summary").unwrap();
        let mut with = args.clone();
        with.extend(["--output", &file_arg]);
        let out = solscope(&with);
        assert_eq!(out.status.code(), Some(2), "{with:?}: {}", stderr(&out));
        assert!(out.stdout.is_empty());
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "the old summary");
        assert_eq!(entries(&dir), ["bad.json", "out.json"], "{with:?}");
    }
    // --write-actuals as well: a plan that does not load writes nothing.
    let actuals = dir.join("actuals.json");
    std::fs::write(&actuals, "old actuals").unwrap();
    let actuals_arg = actuals.display().to_string();
    let out = solscope(&[
        "execute",
        &bad_arg,
        "--sample",
        "1",
        "--write-actuals",
        &actuals_arg,
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(std::fs::read_to_string(&actuals).unwrap(), "old actuals");
}

#[test]
fn an_output_that_cannot_be_written_is_named_before_the_work() {
    let dir = scratch("unwritable");
    let missing = dir.join("no/such/dir/out.json");
    let missing_arg = missing.display().to_string();
    let dir_arg = dir.display().to_string();
    for (target, says) in [
        (missing_arg.as_str(), "does not exist"),
        (dir_arg.as_str(), "is a directory"),
        ("/dev/full", "No space left on device"),
    ] {
        for args in [
            vec!["schedule", BUNDLED],
            vec!["explain", "assets/examples/pitfall.json"],
            vec!["generate", "--activities", "5"],
        ] {
            let mut with = args.clone();
            with.extend(["--output", target]);
            let out = solscope(&with);
            assert_eq!(out.status.code(), Some(1), "{with:?}");
            assert!(out.stdout.is_empty());
            let err = stderr(&out);
            assert!(
                err.starts_with(&format!("error: {target}: could not write: "))
                    && err.contains(says),
                "{with:?}: {err}"
            );
        }
    }
    assert!(entries(&dir).is_empty());
}

#[test]
fn screenshot_checks_its_arguments_before_rendering() {
    let dir = scratch("screenshot");
    let jpg = dir.join("k.jpg");
    std::fs::write(&jpg, "an older picture").unwrap();
    let jpg_arg = jpg.display().to_string();
    let out = solscope(&["screenshot", BUNDLED, "--out", &jpg_arg]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert_eq!(
        stderr(&out),
        format!(
            "error: --out: {jpg_arg}: screenshots are written as PNG only: the file name must end in .png\n"
        )
    );
    assert_eq!(std::fs::read_to_string(&jpg).unwrap(), "an older picture");
    let out = solscope(&["screenshot", BUNDLED, "--out", "/dev/full"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("PNG only"), "{}", stderr(&out));
    // A directory named like a PNG, and a directory that does not exist.
    let png_dir = dir.join("view.png");
    std::fs::create_dir(&png_dir).unwrap();
    let png_dir_arg = png_dir.display().to_string();
    let out = solscope(&["screenshot", BUNDLED, "--out", &png_dir_arg]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        stderr(&out),
        format!("error: {png_dir_arg}: could not write: it is a directory\n")
    );
    let nowhere = dir.join("no/view.png").display().to_string();
    let out = solscope(&["screenshot", BUNDLED, "--out", &nowhere]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("does not exist"), "{}", stderr(&out));
    // An unknown activity is invalid input, as for `explain --activity`.
    let out_png = dir.join("v.png").display().to_string();
    let screenshot = solscope(&["screenshot", BUNDLED, "--out", &out_png, "--select", "nope"]);
    let explain = solscope(&["explain", BUNDLED, "--activity", "nope"]);
    assert_eq!(screenshot.status.code(), Some(2));
    assert_eq!(explain.status.code(), Some(2));
    assert_eq!(stderr(&screenshot), stderr(&explain));
    assert_eq!(stderr(&screenshot), "error: no activity with id `nope`\n");
    // A step past the last is refused with the range.
    let steps = solscope(&["schedule", BUNDLED]);
    let doc: serde_json::Value = serde_json::from_slice(&steps.stdout).unwrap();
    // One step per activity, numbered from 1: the last is the number of steps.
    let n = doc["activities"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|a| a["step"].as_u64())
        .max()
        .expect("steps");
    let past = (n + 1).to_string();
    let out = solscope(&["screenshot", BUNDLED, "--out", &out_png, "--step", &past]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        stderr(&out),
        format!("error: --step: must be between 0 and {n}, the plan's steps (got {past})\n")
    );
    assert_eq!(entries(&dir), ["k.jpg", "view.png"]);
}
