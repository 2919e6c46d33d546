//! Recorded outputs: `schedule`, `explain` and `explain --text` of the bundled
//! plans, the example plans and generated plans stay byte-identical to what
//! `tests/golden/` holds. The files were recorded with the release binary before
//! the engine was restructured; a change in any output byte fails here.
//!
//! An intended change of output re-records them (review the diff before
//! committing):
//!
//! ```sh
//! UPDATE_GOLDEN=1 cargo test --test golden
//! ```

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

fn golden_dir() -> PathBuf {
    root().join("tests/golden")
}

/// Each command's arguments before the plan path, and the recorded file's suffix.
type Commands = &'static [(&'static [&'static str], &'static str)];

/// Every output: schedule, explanation with verified suggestions, and its text.
const ALL: Commands = &[
    (&["schedule"], "schedule.json"),
    (&["explain"], "explain.json"),
    (&["explain", "--text"], "explain.txt"),
];

/// For plans whose suggestions take long to verify (about 40 s for the 300-activity
/// plan): the explanation without suggestions.
const NO_SUGGESTIONS: Commands = &[
    (&["schedule"], "schedule.json"),
    (
        &["explain", "--no-suggestions"],
        "explain-no-suggestions.json",
    ),
    (
        &["explain", "--text", "--no-suggestions"],
        "explain-no-suggestions.txt",
    ),
];

/// The plans, by the name their outputs are recorded under.
const PLANS: [(&str, &str, Commands); 6] = [
    ("default-plan", "assets/default-plan.json", ALL),
    ("tutorial-plan", "assets/tutorial-plan.json", ALL),
    ("pitfall", "assets/examples/pitfall.json", ALL),
    ("drill-sol", "assets/examples/drill-sol.json", ALL),
    (
        "gen-120-1sol-seed1",
        "tests/golden/plans/gen-120-1sol-seed1.json",
        ALL,
    ),
    (
        "gen-300-2sol-seed7",
        "tests/golden/plans/gen-300-2sol-seed7.json",
        NO_SUGGESTIONS,
    ),
];

/// `generate` arguments of the generated plans above.
const GENERATED: [(&str, [&str; 6]); 2] = [
    (
        "gen-120-1sol-seed1",
        ["--activities", "120", "--sols", "1", "--seed", "1"],
    ),
    (
        "gen-300-2sol-seed7",
        ["--activities", "300", "--sols", "2", "--seed", "7"],
    ),
];

fn solscope(args: &[&str]) -> Vec<u8> {
    let out = Command::new(env!("CARGO_BIN_EXE_solscope"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("solscope runs");
    assert!(
        out.status.success(),
        "solscope {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// Compares `actual` with the recorded file, or records it under `UPDATE_GOLDEN`.
/// Returns a line describing a difference, if any.
fn compare(file: &Path, actual: &[u8]) -> Option<String> {
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        std::fs::create_dir_all(file.parent().unwrap()).unwrap();
        std::fs::write(file, actual).unwrap();
        return None;
    }
    let expected = match std::fs::read(file) {
        Ok(bytes) => bytes,
        Err(e) => return Some(format!("{}: {e}", file.display())),
    };
    if expected == actual {
        return None;
    }
    let at = expected
        .iter()
        .zip(actual)
        .position(|(a, b)| a != b)
        .unwrap_or(expected.len().min(actual.len()));
    let line = expected[..at].iter().filter(|&&b| b == b'\n').count() + 1;
    Some(format!(
        "{}: differs from line {line} (recorded {} bytes, now {} bytes)",
        file.display(),
        expected.len(),
        actual.len()
    ))
}

#[test]
fn generated_plans_are_what_generate_prints() {
    let mut diffs = Vec::new();
    for (name, args) in GENERATED {
        let mut full = vec!["generate"];
        full.extend(args);
        let file = golden_dir().join(format!("plans/{name}.json"));
        diffs.extend(compare(&file, &solscope(&full)));
    }
    assert!(diffs.is_empty(), "{}", diffs.join("\n"));
}

#[test]
fn outputs_are_byte_identical_to_the_recorded_ones() {
    let mut diffs = Vec::new();
    let mut compared = 0;
    let mut expected = 0;
    for (name, plan, commands) in PLANS {
        assert!(root().join(plan).is_file(), "{plan} is missing");
        expected += commands.len();
        for (args, suffix) in commands {
            let mut full = args.to_vec();
            full.push(plan);
            let file = golden_dir().join(format!("{name}.{suffix}"));
            diffs.extend(compare(&file, &solscope(&full)));
            compared += 1;
        }
    }
    assert_eq!(compared, expected);
    assert!(diffs.is_empty(), "{}", diffs.join("\n"));
}
