//! `solscope check` through the real binary: the shared examples are valid, each
//! loader warning is printed with its path (a denormal in short form), a missing
//! file is an error. Every command that reads a file reads it through the size
//! limit (`/dev/zero` is refused at 32 MiB, or at `--max-input-mib`), a byte-order
//! mark is accepted on plans, actuals and Monte Carlo parts, and output that cannot
//! be written (`> /dev/full`) is reported. The execution extension's plan
//! additions (`execution`, `duration_model`) check, and their invalid values are
//! refused at their path. Also `solscope generate`: its realistic plans check, it
//! refuses zero sols, and `--uncertain` adds duration models that check and
//! execute.

// Test helpers outside `#[test]` functions are not covered by clippy.toml's
// allow-*-in-tests; a failed expectation here is a test failure.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::{Value, json};

fn solscope_check(plan: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_solscope"))
        .arg("check")
        .arg(plan)
        .output()
        .expect("solscope runs")
}

fn stdout(out: &Output) -> String {
    String::from_utf8(out.stdout.clone()).expect("UTF-8 stdout")
}

fn stderr(out: &Output) -> String {
    String::from_utf8(out.stderr.clone()).expect("UTF-8 stderr")
}

/// Writes `bytes` to a scratch file named `name` and returns its path.
fn write_scratch(name: &str, bytes: &[u8]) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_check");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let path = dir.join(name);
    std::fs::write(&path, bytes).expect("write scratch file");
    path
}

/// Writes `plan` to a scratch file named `name` and returns its path.
fn write_plan(name: &str, plan: &Value) -> PathBuf {
    write_scratch(
        name,
        serde_json::to_string_pretty(plan).expect("json").as_bytes(),
    )
}

/// A valid plan with the given activities.
fn plan_with(activities: Value) -> Value {
    json!({
        "format": "solscope.plan/1",
        "horizon": { "start": 0, "end": 7200 },
        "battery": { "capacity": 1000.0, "initial": 900.0, "min_soc": 100.0 },
        "power": { "rtg": 100.0, "asleep": 10.0, "awake": 60.0 },
        "states": { "door": { "values": ["closed", "open"], "initial": "closed" } },
        "activities": activities
    })
}

/// Runs `check` on a plan expected to be valid and returns its warning lines
/// (without the `warning: ` prefix), checking the ok line.
fn check_warnings(name: &str, plan: &Value) -> Vec<String> {
    let path = write_plan(name, plan);
    let out = solscope_check(&path);
    let (so, se) = (stdout(&out), stderr(&out));
    assert_eq!(out.status.code(), Some(0), "stderr: {se}");
    assert!(se.is_empty(), "stderr: {se}");
    let lines: Vec<&str> = so.lines().collect();
    let (ok, warnings) = lines.split_last().expect("at least the ok line");
    let activities = plan["activities"].as_array().map_or(0, Vec::len);
    assert_eq!(
        *ok,
        format!(
            "ok: {} is a valid plan with {activities} activities and {} warning(s)",
            path.display(),
            warnings.len()
        )
    );
    warnings
        .iter()
        .map(|w| {
            w.strip_prefix("warning: ")
                .unwrap_or_else(|| panic!("not a warning line: {w:?}"))
                .to_string()
        })
        .collect()
}

#[test]
fn shared_examples_are_valid() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/examples");
    let mut plans: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    plans.sort();
    assert!(!plans.is_empty(), "no examples in {}", dir.display());
    for plan in plans {
        let out = solscope_check(&plan);
        let (so, se) = (stdout(&out), stderr(&out));
        assert_eq!(out.status.code(), Some(0), "{}: {se}", plan.display());
        assert!(se.is_empty(), "{}: {se}", plan.display());
        let doc: Value =
            serde_json::from_str(&std::fs::read_to_string(&plan).expect("read")).expect("json");
        let activities = doc["activities"].as_array().map_or(0, Vec::len);
        let lines: Vec<&str> = so.lines().collect();
        let (ok, warnings) = lines.split_last().expect("output");
        assert!(warnings.iter().all(|w| w.starts_with("warning: ")), "{so}");
        assert_eq!(
            *ok,
            format!(
                "ok: {} is a valid plan with {activities} activities and {} warning(s)",
                plan.display(),
                warnings.len()
            )
        );
    }
}

#[test]
fn drill_sol_example_warns_about_optional_before_manual_sleep() {
    // supercam_big and supercam_small (optional, priorities 40/41) come before the
    // mandatory night_sleep (priority 50).
    let plan = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/examples/drill-sol.json");
    let out = solscope_check(&plan);
    let so = stdout(&out);
    assert_eq!(out.status.code(), Some(0));
    let warnings: Vec<&str> = so.lines().filter(|l| l.starts_with("warning: ")).collect();
    assert_eq!(warnings.len(), 2, "{so}");
    assert!(warnings[0].starts_with("warning: activities[7]: optional activity \"supercam_big\""));
    assert!(
        warnings[1].starts_with("warning: activities[8]: optional activity \"supercam_small\"")
    );
    assert!(
        warnings
            .iter()
            .all(|w| w.contains("mandatory activity \"night_sleep\""))
    );
}

#[test]
fn clean_plan_has_no_warnings() {
    let plan = plan_with(json!([
        { "id": "a", "priority": 1, "duration": 60, "effects": [ { "state": "door", "value": "open" } ] },
        { "id": "b", "priority": 2, "duration": 60, "after": [ { "activity": "a" } ],
          "requires": [ { "state": "door", "value": "open" } ] },
        { "id": "c", "priority": 3, "mandatory": false, "duration": 60, "energy_rate": 12.345 }
    ]));
    assert_eq!(check_warnings("clean.json", &plan), Vec::<String>::new());
}

#[test]
fn warns_optional_before_mandatory() {
    let plan = plan_with(json!([
        { "id": "opt", "priority": 1, "mandatory": false, "duration": 60 },
        { "id": "must", "priority": 2, "duration": 60 }
    ]));
    assert_eq!(
        check_warnings("optional-first.json", &plan),
        [
            "activities[0]: optional activity \"opt\" (step 1, priority 1) comes before mandatory \
          activity \"must\" (step 2, priority 2) in step order and may take what the mandatory \
          one needs"
        ]
    );
}

#[test]
fn warns_dependency_on_later_activity() {
    let plan = plan_with(json!([
        { "id": "late", "priority": 5, "duration": 60 },
        { "id": "early", "priority": 1, "duration": 60, "after": [ { "activity": "late" } ] }
    ]));
    assert_eq!(
        check_warnings("dependency-later.json", &plan),
        [
            "activities[1].after[0]: depends on \"late\" (step 2), which comes later in step order \
          than \"early\" (step 1), so \"early\" can never be scheduled"
        ]
    );
}

#[test]
fn warns_unsatisfiable_requirement() {
    let plan = plan_with(json!([
        { "id": "a", "priority": 1, "duration": 60,
          "requires": [ { "state": "door", "value": "open" } ],
          "effects": [ { "state": "door", "value": "open", "at": "start" } ] }
    ]));
    assert_eq!(
        check_warnings("requirement.json", &plan),
        [
            "activities[0].requires[0]: state \"door\" is never \"open\": it is not the initial \
          value and no other activity has an effect setting it, so \"a\" can never be scheduled"
        ]
    );
}

#[test]
fn warns_values_rounded_to_fixed_point() {
    let mut plan = plan_with(json!([
        { "id": "a", "priority": 1, "duration": 60, "energy_rate": 12.3456, "data_rate": 0.0000004 }
    ]));
    plan["battery"]["initial"] = json!(900.00000001);
    assert_eq!(
        check_warnings("precision.json", &plan),
        [
            "battery.initial: 900.00000001 Wh is more precise than 1 mJ (1/3600000 Wh) and is \
             rounded down to 900 Wh (the safe side)",
            "activities[0].energy_rate: 12.3456 W is more precise than 1 mW and is rounded up \
             to 12.346 W (the safe side)",
            "activities[0].data_rate: 0.0000004 Mbit/s is more precise than 1 bit/s (1e-6 \
             Mbit/s) and is rounded up to 0.000001 Mbit/s (the safe side)",
        ]
    );
}

#[test]
fn missing_file_is_an_error_naming_it() {
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_check/no-such-plan.json");
    let out = solscope_check(&path);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    let se = stderr(&out);
    assert!(
        se.starts_with(&format!("error: {}: ", path.display())),
        "stderr: {se}"
    );
}

fn solscope(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_solscope"))
        .args(args)
        .output()
        .expect("solscope runs")
}

#[test]
fn generate_refuses_zero_sols() {
    for profile in ["standard", "realistic", "starved"] {
        let out = solscope(&["generate", "--sols", "0", "--profile", profile]);
        assert_eq!(out.status.code(), Some(2), "{profile}");
        assert!(out.stdout.is_empty(), "{profile}");
        assert_eq!(
            stderr(&out),
            "error: --sols: must be at least 1 (got 0)\n",
            "{profile}"
        );
    }
}

#[test]
fn generated_realistic_plan_checks() {
    let out = solscope(&[
        "generate",
        "--profile",
        "realistic",
        "--activities",
        "80",
        "--sols",
        "2",
        "--seed",
        "3",
    ]);
    assert_eq!(out.status.code(), Some(0), "stderr: {}", stderr(&out));
    let plan: Value = serde_json::from_slice(&out.stdout).expect("a JSON plan");
    let warnings = check_warnings("generated-realistic.json", &plan);
    // Only the step-order remark on optional activities: nothing rounded.
    assert!(
        warnings.iter().all(|w| w.contains("optional activity")),
        "{warnings:?}"
    );
    // The profile is not the default one.
    let standard = solscope(&[
        "generate",
        "--activities",
        "80",
        "--sols",
        "2",
        "--seed",
        "3",
    ]);
    assert_ne!(standard.stdout, out.stdout);
}

/// `generate --uncertain`: the same plan with a `duration_model` on the share
/// asked of its fixed-duration activities (not passes or sleeps), the same for
/// the same seed; it checks, and executes on sampled durations; a share outside
/// 0 to 1 is refused at the flag.
#[test]
fn generate_uncertain_adds_models_to_a_share() {
    let args = [
        "generate",
        "--profile",
        "realistic",
        "--activities",
        "100",
        "--sols",
        "2",
        "--seed",
        "4",
    ];
    let plain = solscope(&args);
    assert_eq!(plain.status.code(), Some(0), "stderr: {}", stderr(&plain));
    let with_args: Vec<&str> = args.iter().copied().chain(["--uncertain", "0.3"]).collect();
    let out = solscope(&with_args);
    assert_eq!(out.status.code(), Some(0), "stderr: {}", stderr(&out));
    assert_eq!(solscope(&with_args).stdout, out.stdout, "deterministic");
    let plain: Value = serde_json::from_slice(&plain.stdout).expect("a JSON plan");
    let plan: Value = serde_json::from_slice(&out.stdout).expect("a JSON plan");
    let acts = plan["activities"].as_array().expect("activities");
    let eligible = |a: &Value| {
        a["duration"].is_i64() && a.get("comm_kind").is_none() && a["awake"] != "forbidden"
    };
    let candidates = acts.iter().filter(|a| eligible(a)).count();
    let modelled: Vec<&Value> = acts
        .iter()
        .filter(|a| a.get("duration_model").is_some())
        .collect();
    assert_eq!(modelled.len(), (candidates as f64 * 0.3).round() as usize);
    for a in &modelled {
        assert!(eligible(a), "{a}");
        let d = a["duration"].as_i64().expect("fixed");
        let (min, max) = (
            a["duration_model"]["min"].as_i64().expect("min"),
            a["duration_model"]["max"].as_i64().expect("max"),
        );
        assert!(0 < min && min < d && d < max, "{a}");
    }
    // Without the models it is the plan `generate` gives without the flag.
    let mut back = plan.clone();
    for a in back["activities"].as_array_mut().expect("activities") {
        a.as_object_mut().expect("object").remove("duration_model");
    }
    assert_eq!(back, plain);
    let path = write_plan("generated-uncertain.json", &plan);
    let check = solscope_check(&path);
    assert_eq!(check.status.code(), Some(0), "stderr: {}", stderr(&check));
    let path_arg = path.to_str().expect("UTF-8 path");
    let ex = solscope(&["execute", path_arg, "--sample", "2"]);
    assert_eq!(ex.status.code(), Some(0), "stderr: {}", stderr(&ex));
    for bad in ["1.5", "-0.1", "NaN"] {
        let out = solscope(&["generate", "--uncertain", bad]);
        assert_eq!(out.status.code(), Some(2), "{bad}");
        assert!(out.stdout.is_empty(), "{bad}");
        assert_eq!(
            stderr(&out),
            format!("error: --uncertain: must be a share from 0 to 1 (got {bad})\n"),
            "{bad}"
        );
    }
}

/// Runs solscope with `args`, standard output going to `stdout`, and fails the
/// test if it has not finished within a minute (an unbounded read of
/// `/dev/zero` grows for much longer than that, or until memory runs out).
fn solscope_within_a_minute(args: &[&str], stdout: std::process::Stdio) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_solscope"))
        .args(args)
        .stdout(stdout)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("solscope runs");
    let started = std::time::Instant::now();
    while child.try_wait().expect("wait").is_none() {
        if started.elapsed() > std::time::Duration::from_secs(60) {
            child.kill().ok();
            panic!("solscope {args:?} still runs after a minute");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.wait_with_output().expect("output")
}

#[test]
fn every_input_is_read_through_the_size_limit() {
    let zero = "/dev/zero";
    if !Path::new(zero).exists() {
        return;
    }
    let plan = write_plan(
        "bounded.json",
        &plan_with(json!([{ "id": "a", "priority": 1, "duration": 60 }])),
    );
    let plan = plan.to_str().expect("UTF-8 path");
    let commands: [&[&str]; 12] = [
        &["check", zero],
        &["screenshot", zero, "--out", "never-written.png"],
        &[
            "screenshot",
            "--max-input-mib",
            "1",
            zero,
            "--out",
            "never-written.png",
        ],
        &["schedule", zero],
        &["explain", zero],
        &["explain", "--text", zero],
        &["flex", zero],
        &["execute", zero],
        &["execute", plan, "--actuals", zero],
        &["montecarlo", zero, "--runs", "2"],
        &["montecarlo", "merge", zero],
        &["check", "--max-input-mib", "1", zero],
    ];
    for args in commands {
        let out = solscope_within_a_minute(args, std::process::Stdio::piped());
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(out.stdout.is_empty(), "{args:?}");
        let limit = if args.contains(&"--max-input-mib") {
            1
        } else {
            32
        };
        assert_eq!(
            stderr(&out),
            format!(
                "error: $: /dev/zero is larger than {limit} MiB, the input size limit \
                 (--max-input-mib raises it)\n"
            ),
            "{args:?}"
        );
    }
}

#[test]
fn the_size_limit_is_set_in_mib_on_the_commands_that_read_files() {
    // A valid plan of just over 1 MiB (padded with spaces).
    let plan = plan_with(json!([{ "id": "a", "priority": 1, "duration": 60 }]));
    let mut text = serde_json::to_string(&plan).expect("json");
    text.push_str(&" ".repeat(1 << 20));
    let path = write_scratch("over-one-mib.json", text.as_bytes());
    let path = path.to_str().expect("UTF-8 path");
    let refused = solscope(&["check", "--max-input-mib", "1", path]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(stdout(&refused).is_empty());
    assert!(
        stderr(&refused).contains("is larger than 1 MiB, the input size limit"),
        "{}",
        stderr(&refused)
    );
    let png =
        std::env::temp_dir().join(format!("solscope-over-one-mib-{}.png", std::process::id()));
    let png = png.to_str().expect("UTF-8 path");
    for args in [
        &["check", "--max-input-mib", "2", path][..],
        &["check", path],
        &["schedule", "--max-input-mib", "2", path],
        &["screenshot", "--max-input-mib", "2", path, "--out", png],
    ] {
        let out = solscope(args);
        assert_eq!(out.status.code(), Some(0), "{args:?}: {}", stderr(&out));
    }
    // The raised limit let the screenshot read the plan and render it.
    assert!(Path::new(png).is_file(), "{png} was not written");
    std::fs::remove_file(png).expect("remove the screenshot");
    // Past the default 32 MiB too: read, parsed and drawn under the raised limit.
    let mut big = serde_json::to_string(&plan).expect("json");
    big.push_str(&" ".repeat(33 << 20));
    let big = write_scratch("over-32-mib.json", big.as_bytes());
    let big = big.to_str().expect("UTF-8 path");
    let drawn = solscope(&["screenshot", "--max-input-mib", "40", big, "--out", png]);
    assert_eq!(drawn.status.code(), Some(0), "{}", stderr(&drawn));
    assert!(Path::new(png).is_file(), "{png} was not written");
    std::fs::remove_file(png).expect("remove the screenshot");
    let refused = solscope(&["screenshot", big, "--out", png]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(!Path::new(png).exists());
    std::fs::remove_file(big).expect("remove the plan");
    let refused = solscope(&["screenshot", "--max-input-mib", "1", path, "--out", png]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(
        stderr(&refused).contains("is larger than 1 MiB, the input size limit"),
        "{}",
        stderr(&refused)
    );
    // Refused where it would change nothing (the app reads up to 32 MiB,
    // generate reads no file) and out of range: clap's usage error.
    for args in [
        &["--max-input-mib", "64", path][..],
        &["generate", "--max-input-mib", "64"],
        &["check", "--max-input-mib", "0", path],
    ] {
        let out = solscope(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(out.stdout.is_empty(), "{args:?}");
        assert!(stderr(&out).starts_with("error: "), "{args:?}");
    }
}

#[test]
fn a_full_disk_is_reported() {
    let full = Path::new("/dev/full");
    if !full.exists() {
        return;
    }
    let plan = write_plan(
        "to-full-disk.json",
        &plan_with(json!([{ "id": "a", "priority": 1, "duration": 60 }])),
    );
    let plan = plan.to_str().expect("UTF-8 path");
    for args in [
        &["schedule", plan][..],
        &["check", plan],
        &["explain", plan],
        &["generate", "--activities", "5"],
    ] {
        let sink = std::fs::OpenOptions::new()
            .write(true)
            .open(full)
            .expect("open /dev/full");
        let out = solscope_within_a_minute(args, sink.into());
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        assert_eq!(
            stderr(&out),
            "error: could not write the output to standard output: No space left on device \
             (os error 28)\n",
            "{args:?}"
        );
    }
}

#[test]
fn a_byte_order_mark_is_accepted() {
    let plan = plan_with(json!([{ "id": "a", "priority": 1, "duration": 60 }]));
    let mut bytes = b"\xEF\xBB\xBF".to_vec();
    bytes.extend(serde_json::to_vec(&plan).expect("json"));
    let out = solscope_check(&write_scratch("bom.json", &bytes));
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}

#[test]
fn a_byte_order_mark_is_accepted_on_actuals_and_monte_carlo_parts() {
    let plan = plan_with(json!([
        { "id": "a", "priority": 1, "duration": 60,
          "duration_model": { "min": 30, "max": 90 } }
    ]));
    let plan = write_plan("bom-plan.json", &plan);
    let plan = plan.to_str().expect("UTF-8 path");
    let with_bom = |name: &str, text: &[u8]| {
        let mut bytes = b"\xEF\xBB\xBF".to_vec();
        bytes.extend_from_slice(text);
        write_scratch(name, &bytes)
    };
    let actuals = with_bom(
        "bom-actuals.json",
        br#"{"format":"solscope.actuals/1","durations":{"a":75}}"#,
    );
    let out = solscope(&[
        "execute",
        plan,
        "--actuals",
        actuals.to_str().expect("UTF-8"),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let doc: Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert!(doc.to_string().contains("75"), "{doc}");
    let part = solscope(&["montecarlo", plan, "--runs", "4", "--shard", "0/1"]);
    assert_eq!(part.status.code(), Some(0), "{}", stderr(&part));
    let part = with_bom("bom-part.json", &part.stdout);
    let merged = solscope(&["montecarlo", "merge", part.to_str().expect("UTF-8")]);
    assert_eq!(merged.status.code(), Some(0), "{}", stderr(&merged));
    let direct = solscope(&["montecarlo", plan, "--runs", "4"]);
    assert_eq!(merged.stdout, direct.stdout);
}

#[test]
fn a_denormal_figure_is_printed_short() {
    let plan = plan_with(json!([
        { "id": "a", "priority": 1, "duration": 60, "energy_rate": 5e-324 }
    ]));
    assert_eq!(
        check_warnings("denormal.json", &plan),
        [
            "activities[0].energy_rate: 5e-324 W is more precise than 1 mW and is rounded up to \
          0.001 W (the safe side)"
        ]
    );
}

#[test]
fn empty_windows_are_warned_about() {
    let plan = plan_with(json!([{ "id": "a", "priority": 1, "duration": 60, "windows": [] }]));
    let warnings = check_warnings("empty-windows.json", &plan);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].starts_with("activities[0].windows: \"a\" has an empty list of windows"),
        "{warnings:?}"
    );
}

#[test]
fn execution_example_is_valid() {
    let plan = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/execution-examples/uncertain-drive.json");
    let out = solscope_check(&plan);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(
        stdout(&out).ends_with("with 4 activities and 0 warning(s)\n"),
        "{}",
        stdout(&out)
    );
}

/// Each invalid execution addition: exit 2, nothing on stdout, the JSON path and
/// the reason on stderr.
#[test]
fn invalid_execution_additions_are_refused_at_their_path() {
    let drive = |extra: Value| {
        let mut a = json!({ "id": "drive", "priority": 1, "duration": 600 });
        for (k, v) in extra.as_object().expect("object") {
            a[k] = v.clone();
        }
        a
    };
    let cases = [
        (
            "expanding-model",
            plan_with(json!([drive(json!({
                "duration": { "min": 300, "max": 600 },
                "duration_model": { "min": 300, "max": 900 }
            }))])),
            "activities[0].duration_model: an expanding activity cannot have a duration_model",
        ),
        (
            "model-min-above-max",
            plan_with(json!([drive(
                json!({ "duration_model": { "min": 900, "max": 300 } })
            )])),
            "activities[0].duration_model.max: must be >= min (got 300 < 900)",
        ),
        (
            "model-zero-min",
            plan_with(json!([drive(
                json!({ "duration_model": { "min": 0, "max": 300 } })
            )])),
            "activities[0].duration_model.min: must be > 0 (got 0)",
        ),
        (
            "model-as-array",
            plan_with(json!([drive(json!({ "duration_model": [300, 900] }))])),
            "activities[0].duration_model: invalid type: array, expected a JSON object",
        ),
        (
            "model-unknown-field",
            plan_with(json!([drive(
                json!({ "duration_model": { "min": 1, "max": 2, "mode": 3 } })
            )])),
            "activities[0].duration_model",
        ),
        (
            "zero-period",
            {
                let mut p = plan_with(json!([drive(json!({}))]));
                p["execution"] = json!({ "replan_period": 0 });
                p
            },
            "execution.replan_period: must be > 0 (got 0)",
        ),
        (
            "too-many-cycles",
            {
                let mut p = plan_with(json!([drive(json!({}))]));
                p["horizon"] = json!({ "start": 0, "end": 1_000_000_000 });
                p["execution"] = json!({ "replan_period": 1 });
                p
            },
            "execution.replan_period: gives 1000000000 cycles over the horizon; at most 100000 (a period of at least 10000 s)",
        ),
        (
            "execution-unknown-field",
            {
                let mut p = plan_with(json!([drive(json!({}))]));
                p["execution"] = json!({ "replan_every": 60 });
                p
            },
            "execution",
        ),
    ];
    for (name, plan, want) in cases {
        let out = solscope_check(&write_plan(&format!("{name}.json"), &plan));
        let se = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{name}: {se}");
        assert!(out.stdout.is_empty(), "{name}: {}", stdout(&out));
        assert!(se.contains(want), "{name}: {se}");
    }
}

#[test]
fn a_named_pipe_without_a_writer_is_refused_in_time_and_one_with_a_writer_is_read() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_check_fifo");
    std::fs::create_dir_all(&dir).unwrap();
    let fifo = dir.join("plan.fifo");
    if fifo.exists() {
        std::fs::remove_file(&fifo).unwrap();
    }
    let made = Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .expect("mkfifo runs");
    assert!(made.success());
    // Nothing opens it for writing: refused after the wait, not blocked forever.
    let started = std::time::Instant::now();
    let out = solscope_within_a_minute(
        &["check", fifo.to_str().unwrap()],
        std::process::Stdio::piped(),
    );
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(out.stdout.is_empty());
    assert_eq!(
        stderr(&out),
        format!(
            "error: {}: a named pipe that nothing opened for writing within 5 s\n",
            fifo.display()
        )
    );
    assert!(started.elapsed() < std::time::Duration::from_secs(30));
    // A writer (as a shell's `<(...)` has): read as any file.
    let plan =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/examples/pitfall.json"))
            .unwrap();
    let writer = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::write(&fifo, plan))
    };
    let out = solscope(&["check", fifo.to_str().unwrap()]);
    writer.join().unwrap().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stdout(&out).contains("is a valid plan with 2 activities"));
    std::fs::remove_file(&fifo).unwrap();
}

#[test]
fn two_byte_order_marks_are_refused() {
    let plan =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/examples/pitfall.json"))
            .unwrap();
    let mut one = b"\xEF\xBB\xBF".to_vec();
    one.extend_from_slice(&plan);
    let path = write_scratch("one-bom.json", &one);
    assert_eq!(solscope_check(&path).status.code(), Some(0));
    let mut two = b"\xEF\xBB\xBF".to_vec();
    two.extend_from_slice(&one);
    let path = write_scratch("two-boms.json", &two);
    let out = solscope_check(&path);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    assert_eq!(
        stderr(&out),
        format!(
            "error: $: {} starts with two byte-order marks; a UTF-8 file has at most one\n",
            path.display()
        )
    );
}

#[test]
fn nesting_of_exactly_128_levels_is_said_as_it_is() {
    // The plan object, then 126 arrays in `activities`: 127 levels pass the
    // parser (and fail as a wrong type), 128 are refused as too deep.
    let nested = |levels: usize| {
        let arrays = levels - 1;
        format!(
            r#"{{"activities":{}{}}}"#,
            "[".repeat(arrays),
            "]".repeat(arrays)
        )
    };
    let out = solscope_check(&write_scratch("nest127.json", nested(127).as_bytes()));
    assert_eq!(out.status.code(), Some(2));
    assert!(
        !stderr(&out).contains("nested too deeply"),
        "{}",
        stderr(&out)
    );
    let out = solscope_check(&write_scratch("nest128.json", nested(128).as_bytes()));
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        stderr(&out),
        "error: activities[0]: nested too deeply: the JSON nests 128 levels or more here (a plan nests at most 5)\n"
    );
}

#[test]
fn a_number_below_the_smallest_float_is_rounded_as_the_smallest_one() {
    // 1e-400 is no 64-bit float: read as 0 it would lose the rounding to the
    // safe side (and its warning) that 5e-324 gets.
    let plan = plan_with(json!([
        { "id": "a", "priority": 1, "duration": 60, "energy_rate": 5e-324 }
    ]));
    let text = serde_json::to_string_pretty(&plan).unwrap();
    let tiny = write_scratch("tiny.json", text.as_bytes());
    let expected = [
        "activities[0].energy_rate: 5e-324 W is more precise than 1 mW and is rounded up to \
         0.001 W (the safe side)",
    ];
    let out = solscope_check(&tiny);
    assert!(stdout(&out).starts_with(&format!("warning: {}\n", expected[0])));
    assert!(text.contains("5e-324"));
    let under = write_scratch("under.json", text.replace("5e-324", "1e-400").as_bytes());
    let out = solscope_check(&under);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(
        stdout(&out).starts_with(&format!("warning: {}\n", expected[0])),
        "{}",
        stdout(&out)
    );
}
