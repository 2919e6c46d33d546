//! `solscope check --all-errors`: every error of an invalid plan found in one
//! pass, one `error:` line each, led by the one `check` says without it.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::process::Output;

fn check(name: &str, args: &[&str], text: &str) -> Output {
    let dir =
        std::env::temp_dir().join(format!("solscope-all-errors-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("plan.json");
    std::fs::write(&path, text).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_solscope"))
        .arg("check")
        .args(args)
        .arg(&path)
        .output()
        .expect("solscope runs");
    std::fs::remove_dir_all(&dir).ok();
    out
}

const BROKEN: &str = r#"{"format":"solscope.plan/1","horizon":{"start":0,"end":1000},
    "battery":{"capacity":10.0,"initial":5.0,"min_soc":1.0},
    "power":{"rtg":10.0,"asleep":1.0,"awake":2.0},"activities":[
    {"id":"a","priority":1,"duration":10},
    {"id":"b","priority":"high","duration":"ten"},
    {"id":"c","priority":3,"duration":10,"after":[{"activity":"ghost"}]}]}"#;

#[test]
fn every_error_is_listed_in_one_pass_in_planner_words() {
    let all = check("broken-all", &["--all-errors"], BROKEN);
    assert_eq!(all.status.code(), Some(2));
    assert!(all.stdout.is_empty());
    assert_eq!(
        String::from_utf8(all.stderr).unwrap(),
        "error: activities[1].priority: must be a whole number (got the text \"high\")\n\
         error: activities[1].duration: must be a whole number of seconds or \
         { \"min\": m, \"max\": M } (got the text \"ten\")\n\
         error: activities[2].after[0].activity: unknown activity \"ghost\"\n"
    );
    // Without the flag: the first alone, as every command says it.
    let first = check("broken-first", &[], BROKEN);
    assert_eq!(first.status.code(), Some(2));
    assert!(first.stdout.is_empty());
    assert_eq!(
        String::from_utf8(first.stderr).unwrap(),
        "error: activities[1].priority: must be a whole number (got the text \"high\")\n"
    );
}

#[test]
fn a_valid_plan_checks_the_same_with_the_flag() {
    let plan = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/default-plan.json"
    ))
    .unwrap();
    let with = check("valid", &["--all-errors"], &plan);
    let without = check("valid", &[], &plan);
    assert_eq!(with.status.code(), Some(0));
    assert_eq!(with.stdout, without.stdout);
    assert!(String::from_utf8(with.stdout).unwrap().starts_with("ok: "));
}
