//! The malformed-plan corpus (`tests/malformed/`): every file is a plan broken in
//! one way. Both `solscope check` and `solscope schedule` must reject it at load
//! time with exit status 2, nothing on standard output, and `error: PATH: REASON`
//! on standard error naming the expected JSON path.

// Test helpers outside `#[test]` functions are not covered by clippy.toml's
// allow-*-in-tests; a failed expectation here is a test failure.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// `(file, expected JSON path, fragment of the reason)`.
const EXPECTED: &[(&str, &str, &str)] = &[
    // syntax and top-level shape
    ("empty.json", "$", "EOF while parsing a value"),
    (
        "truncated.json",
        "activities[3]",
        "EOF while parsing an object",
    ),
    ("top-level-array.json", "$", "expected a JSON object"),
    ("horizon-as-array.json", "horizon", "expected a JSON object"),
    (
        "window-as-array.json",
        "activities[1].windows[0]",
        "expected a JSON object",
    ),
    // unknown fields and wrong types (serde)
    (
        "unknown-top-level-field.json",
        "timezone",
        "unknown field `timezone`",
    ),
    (
        "unknown-activity-field.json",
        "activities[2].prio",
        "unknown field `prio`",
    ),
    (
        "unknown-window-field.json",
        "activities[0].windows[0].latest",
        "unknown field `latest`",
    ),
    (
        "priority-string.json",
        "activities[1].priority",
        "must be a whole number (got the text \"high\")",
    ),
    (
        "mandatory-string.json",
        "activities[4].mandatory",
        "must be true or false (got the text \"no\")",
    ),
    (
        "duration-float.json",
        "activities[2].duration",
        "must be a whole number of seconds or { \"min\": m, \"max\": M } (got 1.5)",
    ),
    (
        "awake-sometimes.json",
        "activities[4].awake",
        "unknown variant `sometimes`",
    ),
    (
        "sequence-engines-negative.json",
        "sequence_engines",
        "must be a whole number >= 0 (got -1)",
    ),
    ("battery-missing.json", "$", "missing field `battery`"),
    (
        "missing-priority.json",
        "activities[4]",
        "missing field `priority`",
    ),
    // plan-level semantics
    ("wrong-format.json", "format", "must be \"solscope.plan/1\""),
    (
        "horizon-start-after-end.json",
        "horizon.end",
        "must be > start (got 88775 <= 88775)",
    ),
    (
        "sol-length-zero.json",
        "local_time.sol_length",
        "must be > 0 (got 0)",
    ),
    (
        "battery-initial-over-capacity.json",
        "battery.initial",
        "must be <= capacity (got 1700 > 1600)",
    ),
    (
        "data-initial-over-capacity.json",
        "data.initial",
        "must be <= capacity (got 9000 > 8000)",
    ),
    (
        "handover-outside-horizon.json",
        "handover.time",
        "inside the horizon [0, 88775] (got 90000)",
    ),
    (
        "state-initial-unknown.json",
        "states.drill.initial",
        "unknown value \"retracted\"",
    ),
    (
        "state-duplicate-value.json",
        "states.arm.values[2]",
        "duplicate value \"stowed\"",
    ),
    (
        "thermal-no-from-zero.json",
        "thermal_zones.arm.preheat",
        "entry with from 0",
    ),
    (
        "thermal-duplicate-from.json",
        "thermal_zones.arm.preheat[2].from",
        "duplicate from 36000",
    ),
    // activity semantics
    (
        "duplicate-id.json",
        "activities[4].id",
        "duplicate id \"drill_core\" (first at activities[1])",
    ),
    (
        "duration-zero.json",
        "activities[0].duration",
        "must be > 0 (got 0)",
    ),
    (
        "duration-negative.json",
        "activities[4].duration",
        "must be > 0 (got -600)",
    ),
    (
        "expanding-min-over-max.json",
        "activities[3].duration.max",
        "must be >= min (got 5400 < 6000)",
    ),
    (
        "window-end-before-start.json",
        "activities[3].windows[0].end",
        "must be >= start (got 52000 < 62000)",
    ),
    (
        "window-outside-horizon.json",
        "activities[4].windows[0].end",
        "must be <= horizon.end (got 90000 > 88775)",
    ),
    (
        "window-preferred-outside.json",
        "activities[1].windows[0].preferred",
        "within the window [36000, 52000] (got 53000)",
    ),
    (
        "window-cutoff-before-start.json",
        "activities[3].windows[0].cutoff",
        "must be > start (got 50000 <= 52000)",
    ),
    (
        "duplicate-resource.json",
        "activities[1].resources[2]",
        "duplicate resource \"arm\"",
    ),
    (
        "negative-energy-rate.json",
        "activities[3].energy_rate",
        "must be >= 0 (got -120)",
    ),
    (
        "unknown-zone.json",
        "activities[2].thermal_zones[1]",
        "unknown thermal zone \"mast\"",
    ),
    (
        "after-unknown-id.json",
        "activities[1].after[0].activity",
        "unknown activity \"arm_unstowe\"",
    ),
    (
        "self-dependency.json",
        "activities[2].after[1].activity",
        "cannot depend on itself",
    ),
    (
        "meets-with-delay.json",
        "activities[2].after[0].min_delay",
        "cannot be combined with \"meets\": true",
    ),
    (
        "delay-min-over-max.json",
        "activities[2].after[0].max_delay",
        "must be >= min_delay (got 60 < 600)",
    ),
    (
        "unknown-state.json",
        "activities[3].requires[0].state",
        "unknown state \"mast\"",
    ),
    (
        "unknown-state-value.json",
        "activities[2].requires[0].value",
        "unknown value \"open\" for state \"drill\" (allowed: stowed, deployed)",
    ),
    (
        "duplicate-requirement.json",
        "activities[1].requires[1]",
        "duplicate requirement on state \"arm\"",
    ),
    (
        "duplicate-effect.json",
        "activities[0].effects[1]",
        "duplicate effect on state \"arm\" at \"end\"",
    ),
    (
        "empty-group.json",
        "activities[4].group",
        "must not be empty",
    ),
    // hostile numbers and structure
    (
        "number-out-of-range.json",
        "battery.capacity",
        "number out of range",
    ),
    (
        "power-too-large.json",
        "power.rtg",
        "must be at most 1000000 W in magnitude",
    ),
    (
        "integer-overflow.json",
        "horizon.end",
        "must be a whole number of seconds (got 1e+23)",
    ),
    (
        "nan-string.json",
        "battery.initial",
        "must be a number (got the text \"NaN\")",
    ),
    (
        "time-too-large.json",
        "horizon.end",
        "must be between -10000000000 and 10000000000",
    ),
    (
        "deeply-nested.json",
        "activities[0].resources[0]",
        "nested too deeply",
    ),
    ("top-level-deeply-nested.json", "$", "nested too deeply"),
    (
        "deeply-nested-horizon-start.json",
        "horizon.start",
        "nested too deeply",
    ),
    // encodings: a UTF-8 byte-order mark is skipped (the error is the plan's
    // own), anything but UTF-8 is named
    (
        "bom-unknown-activity-field.json",
        "activities[2].prio",
        "unknown field `prio`",
    ),
    ("utf16.json", "$", "utf16.json is UTF-16 text"),
    (
        "not-utf8.json",
        "$",
        "not-utf8.json is not UTF-8 text (invalid byte at offset 66)",
    ),
    // numbers are printed short, a denormal too
    (
        "battery-initial-denormal-over-capacity.json",
        "battery.initial",
        "must be <= capacity (got 1e-323 > 5e-324)",
    ),
    (
        "trailing-garbage.json",
        "$",
        "unexpected text after the plan",
    ),
    ("duplicate-key.json", "horizon", "duplicate field `end`"),
];

fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/malformed")
}

fn run(subcommand: &str, file: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_solscope"))
        .arg(subcommand)
        .arg(file)
        .output()
        .expect("solscope runs")
}

#[test]
fn every_corpus_file_has_an_expectation() {
    let on_disk: BTreeSet<String> = std::fs::read_dir(corpus_dir())
        .expect("tests/malformed exists")
        .map(|entry| {
            entry
                .expect("directory entry")
                .file_name()
                .into_string()
                .expect("UTF-8 file name")
        })
        .collect();
    let listed: BTreeSet<String> = EXPECTED.iter().map(|(f, _, _)| f.to_string()).collect();
    assert_eq!(listed.len(), EXPECTED.len(), "a file is listed twice");
    let missing: Vec<_> = on_disk.difference(&listed).collect();
    let stale: Vec<_> = listed.difference(&on_disk).collect();
    assert!(
        missing.is_empty(),
        "corpus files without an expectation: {missing:?}"
    );
    assert!(
        stale.is_empty(),
        "expectations without a corpus file: {stale:?}"
    );
    assert!(
        on_disk.len() >= 24,
        "the corpus has only {} files",
        on_disk.len()
    );
}

#[test]
fn every_corpus_file_is_rejected_with_its_path() {
    let mut failures = Vec::new();
    for &(file, path, fragment) in EXPECTED {
        let plan = corpus_dir().join(file);
        for subcommand in ["check", "schedule"] {
            let out = run(subcommand, &plan);
            let stdout = String::from_utf8_lossy(&out.stdout);
            let stderr = String::from_utf8_lossy(&out.stderr);
            let prefix = format!("error: {path}: ");
            let mut problems = Vec::new();
            if out.status.code() != Some(2) {
                problems.push(format!("exit status {:?}, expected 2", out.status.code()));
            }
            if !stdout.is_empty() {
                problems.push(format!("stdout not empty: {stdout:?}"));
            }
            if !stderr.starts_with(&prefix) {
                problems.push(format!("stderr does not start with {prefix:?}"));
            }
            if !stderr.contains(fragment) {
                problems.push(format!("stderr does not contain {fragment:?}"));
            }
            if stderr.lines().count() != 1 {
                problems.push("stderr is not exactly one line".to_string());
            }
            if !problems.is_empty() {
                failures.push(format!(
                    "solscope {subcommand} {file}: {}\n    stderr: {}",
                    problems.join("; "),
                    stderr.trim_end()
                ));
            }
        }
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
}

#[test]
fn a_hundred_thousand_nested_brackets_are_nested_too_deeply() {
    // The shape a hostile or broken generator writes: no plan at all, only depth.
    let dir = std::env::temp_dir().join(format!("solscope-nested-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cases = [
        ("top.json", "[".repeat(100_000), "$"),
        (
            "in-activities.json",
            format!(
                r#"{{"format":"solscope.plan/1","activities":[{{"id":"a","windows":{}"#,
                "[".repeat(100_000)
            ),
            "activities[0].windows[0]",
        ),
    ];
    for (name, text, path) in cases {
        let file = dir.join(name);
        std::fs::write(&file, text).unwrap();
        for sub in ["check", "schedule"] {
            let out = run(sub, &file);
            assert_eq!(out.status.code(), Some(2), "{sub} {name}");
            assert!(out.stdout.is_empty(), "{sub} {name}");
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(
                err.starts_with(&format!("error: {path}: nested too deeply: ")),
                "{sub} {name}: {err}"
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_million_activities_are_refused_cleanly() {
    // About 60 MB of activities: refused by size before parsing, so loading stays
    // bounded in time and memory.
    let dir = std::env::temp_dir().join(format!("solscope-million-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("million.json");
    let mut text = String::from(
        r#"{ "format": "solscope.plan/1", "horizon": { "start": 0, "end": 7200 },
            "battery": { "capacity": 100.0, "initial": 90.0, "min_soc": 10.0 },
            "power": { "rtg": 50.0, "asleep": 10.0, "awake": 30.0 }, "activities": ["#,
    );
    for i in 0..1_000_000 {
        if i > 0 {
            text.push(',');
        }
        text.push_str(&format!(r#"{{"id":"a{i}","priority":{i},"duration":60}}"#));
    }
    text.push_str("] }");
    std::fs::write(&path, text).unwrap();
    for sub in ["check", "schedule"] {
        let out = run(sub, &path);
        assert_eq!(out.status.code(), Some(2), "{sub}");
        assert!(out.stdout.is_empty());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.starts_with("error: $: "), "{err}");
        assert!(
            err.contains("is larger than 32 MiB, the input size limit"),
            "{err}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `solscope ARGS` with standard output and standard error as given.
fn with_streams(args: &[&str], stdout: Stdio, stderr: Stdio) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_solscope"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(stdout)
        .stderr(stderr)
        .output()
        .expect("solscope runs")
}

/// `/dev/full`, where every write fails with "no space left on device".
fn full() -> Stdio {
    Stdio::from(
        std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .expect("/dev/full"),
    )
}

#[test]
fn a_full_standard_error_ends_with_the_status_alone() {
    // The error cannot be said; the status still says it, with no panic (101).
    let out = with_streams(&["check", "/nonexistent"], Stdio::piped(), full());
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    // A usage error, likewise.
    let out = with_streams(&["check", "--bogus"], Stdio::piped(), full());
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn help_and_version_that_cannot_be_written_fail() {
    for args in [&["--help"][..], &["check", "--help"], &["--version"]] {
        let out = with_streams(args, full(), Stdio::piped());
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.starts_with("error: could not write the output to standard output: "),
            "{args:?}: {err}"
        );
        // Written, they succeed.
        let out = with_streams(args, Stdio::piped(), Stdio::piped());
        assert_eq!(out.status.code(), Some(0), "{args:?}");
        assert!(!out.stdout.is_empty(), "{args:?}");
    }
}

#[test]
fn a_reader_that_stops_early_ends_the_output_quietly() {
    // As `solscope schedule PLAN | head -c 10` once head has exited: the reader's
    // end of the pipe is closed before anything is written (docs/semantics.md,
    // "Output streams": exit status 0, nothing on standard error).
    for args in [
        &["schedule", "assets/default-plan.json"][..],
        &["explain", "assets/examples/pitfall.json"],
        &["generate", "--activities", "2000"],
        &["--help"],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_solscope"))
            .args(args)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("solscope runs");
        drop(child.stdout.take());
        let out = child.wait_with_output().expect("solscope ends");
        assert_eq!(out.status.code(), Some(0), "{args:?}");
        assert!(
            out.stderr.is_empty(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}
