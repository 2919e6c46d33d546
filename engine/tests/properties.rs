//! Property tests: the scheduler against the independent brute-force oracle.
//!
//! 1. replay: on random small plans the schedule document agrees with the oracle at
//!    every step (validity, completeness, the exact choice rule), and its generated
//!    activities and profiles match the oracle's second-by-second simulation;
//!    the same on plans with a starved battery (`plangen::starved_plan_text`);
//! 2. determinism: scheduling twice gives byte-identical JSON;
//! 3. every shipped example and asset schedules and replays clean; the pitfall
//!    example gives A at 0 and B failed;
//! 4. rescheduling an edited plan from the previous run's unchanged prefix gives
//!    exactly what scheduling it from scratch gives.
#![allow(clippy::panic, clippy::unwrap_used, clippy::expect_used)]

mod oracle;
#[path = "gen/mod.rs"]
mod plangen;

use std::path::{Path, PathBuf};

use proptest::prelude::*;
use serde_json::Value;
use solscope_engine::{LoadedPlan, load_plan, reschedule, schedule, schedule_document};

fn schedule_json(loaded: &LoadedPlan) -> Result<Value, String> {
    let sched = schedule(&loaded.plan).map_err(|e| format!("schedule failed: {e}"))?;
    let doc = schedule_document(loaded, &sched, "plan");
    serde_json::to_value(&doc).map_err(|e| format!("schedule document does not serialize: {e}"))
}

/// Loads, schedules and replays one plan text; `Err` carries a self-contained report.
fn check_plan(text: &str) -> Result<Value, String> {
    let loaded = load_plan(text).map_err(|e| format!("load_plan rejected the plan: {e}"))?;
    let doc = schedule_json(&loaded)?;
    oracle::check_valid(&loaded.plan, &doc).map_err(|e| format!("INVALID: {e}"))?;
    oracle::replay(&loaded.plan, &doc)?;
    oracle::check_generated_order(&doc)?;
    Ok(doc)
}

fn pretty(text: &str) -> String {
    serde_json::from_str::<Value>(text)
        .ok()
        .and_then(|v| serde_json::to_string_pretty(&v).ok())
        .unwrap_or_else(|| text.to_string())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 256,
        failure_persistence: None,
        max_shrink_iters: 2000,
        ..ProptestConfig::default()
    })]

    #[test]
    fn replay_agrees_with_oracle(text in plangen::plan_text()) {
        if let Err(e) = check_plan(&text) {
            return Err(TestCaseError::fail(format!("{e}\nplan:\n{}", pretty(&text))));
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 128,
        failure_persistence: None,
        max_shrink_iters: 2000,
        ..ProptestConfig::default()
    })]

    /// The same on plans whose battery hovers near its minimum: most steps are
    /// decided by the state-of-charge shortcuts.
    #[test]
    fn replay_agrees_with_oracle_when_starved(text in plangen::starved_plan_text()) {
        if let Err(e) = check_plan(&text) {
            return Err(TestCaseError::fail(format!("{e}\nplan:\n{}", pretty(&text))));
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 64,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn scheduling_is_deterministic(text in plangen::plan_text()) {
        let loaded = load_plan(&text).map_err(|e| TestCaseError::fail(format!("load_plan: {e}")))?;
        let run = || -> Result<String, String> {
            let v = schedule_json(&loaded)?;
            serde_json::to_string_pretty(&v).map_err(|e| e.to_string())
        };
        let a = run().map_err(TestCaseError::fail)?;
        let b = run().map_err(TestCaseError::fail)?;
        prop_assert!(a == b, "two runs differ on plan:\n{}", pretty(&text));
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 512,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn rescheduling_an_edit_matches_scheduling_from_scratch(
        text in plangen::plan_text(),
        pick in 0usize..64,
        kind in 0u8..5,
        amount in -3i64..4,
    ) {
        let loaded = load_plan(&text).map_err(|e| TestCaseError::fail(format!("load_plan: {e}")))?;
        let before = schedule(&loaded.plan).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let mut plan = loaded.plan.clone();
        let n = plan.activities.len();
        prop_assume!(n > 0);
        let act = &mut plan.activities[pick % n];
        match kind {
            0 => act.priority += amount,
            1 => {
                if let Some(w) = act.windows.as_mut().and_then(|w| w.first_mut()) {
                    w.start += amount * 60;
                }
            }
            2 => act.mandatory = !act.mandatory,
            3 => act.energy_rate += amount as f64,
            _ => plan.activities.swap(pick % n, (pick / 2) % n),
        }
        // Edits that make the plan invalid are refused before any rescheduling.
        let edited = serde_json::to_string(&plan).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let Ok(edited) = load_plan(&edited) else { return Ok(()) };
        let full = schedule(&edited.plan).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let reused = reschedule(&before, &edited.plan).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(&full.steps, &reused.steps, "plan:\n{}", pretty(&text));
        prop_assert_eq!(&full.generated, &reused.generated);
    }
}

fn json_files(dir: &Path) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = match std::fs::read_dir(dir) {
        Ok(rd) => rd
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| p.extension().is_some_and(|x| x == "json"))
            .collect(),
        Err(e) => panic!("{}: {e}", dir.display()),
    };
    out.sort();
    out
}

fn plan_dirs() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    vec![root.join("../assets/examples"), root.join("../assets")]
}

#[test]
fn examples_and_assets_replay_clean() {
    let mut failures = Vec::new();
    let mut seen = 0;
    for dir in plan_dirs() {
        for path in json_files(&dir) {
            let Ok(text) = std::fs::read_to_string(&path) else {
                failures.push(format!("{}: unreadable", path.display()));
                continue;
            };
            // Only plan files (assets may hold other documents).
            let is_plan = serde_json::from_str::<Value>(&text).ok().is_some_and(|v| {
                v.get("format").and_then(Value::as_str) == Some("solscope.plan/1")
            });
            if !is_plan {
                continue;
            }
            seen += 1;
            if let Err(e) = check_plan(&text) {
                failures.push(format!("{}: {e}", path.display()));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // The two bundled plans and the two example plans.
    assert!(seen >= 4, "only {seen} plans found");
    eprintln!("{seen} example/asset plans replayed clean");
}

#[test]
fn pitfall_a_at_zero_b_failed() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("../assets/examples/pitfall.json"))
        .expect("assets/examples/pitfall.json is in the repository");
    let doc = match check_plan(&text) {
        Ok(d) => d,
        Err(e) => panic!("{e}"),
    };
    let acts = &doc["activities"];
    assert_eq!(acts[0]["id"], "A");
    assert_eq!(acts[0]["status"], "scheduled");
    assert_eq!(acts[0]["start"], 0);
    assert_eq!(acts[0]["end"], 600);
    assert_eq!(acts[1]["id"], "B");
    assert_eq!(acts[1]["status"], "failed");
}

/// How often the generator makes the plans that exercise the expanding search's
/// split paths: an expanding, awake-required activity with `min_awake >
/// 0` whose window (or the whole horizon) ends within `min_awake - wakeup` of the
/// plan end, with and without an effect at its end. The property tests above only
/// test these paths as often as this finds them.
#[test]
fn generator_covers_non_monotone_expanding_activities() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
    let mut runner = TestRunner::new_with_rng(
        Config::default(),
        TestRng::from_seed(RngAlgorithm::ChaCha, &[7; 32]),
    );
    let strategy = plangen::plan_text();
    let (mut backward, mut end_effect, mut windowless) = (0, 0, 0);
    let n = 256;
    for _ in 0..n {
        let text = strategy.new_tree(&mut runner).unwrap().current();
        let v: Value = serde_json::from_str(&text).unwrap();
        let h1 = v["horizon"]["end"].as_i64().unwrap();
        let wake = v["sleep"]["wakeup_duration"].as_i64().unwrap_or(0);
        let min_awake = v["sleep"]["min_awake"].as_i64().unwrap_or(0);
        let (mut b, mut e, mut w) = (false, false, false);
        for a in v["activities"].as_array().unwrap() {
            if !a["duration"].is_object() {
                continue;
            }
            let required = a.get("awake").is_none_or(|m| m == "required");
            let ends = a["windows"].as_array().map_or(vec![h1], |ws| {
                ws.iter().map(|w| w["end"].as_i64().unwrap()).collect()
            });
            let near = ends.iter().any(|&x| x - wake + min_awake > h1);
            let has_end_effect = a["effects"]
                .as_array()
                .is_some_and(|es| es.iter().any(|x| x["at"] == "end"));
            b |= required && min_awake > 0 && near && !has_end_effect;
            e |= has_end_effect;
            w |= a.get("windows").is_none();
        }
        backward += usize::from(b);
        end_effect += usize::from(e);
        windowless += usize::from(w);
    }
    eprintln!(
        "of {n} plans: {backward} with a backward-extension expanding activity, \
         {end_effect} with an end-effect one, {windowless} with a windowless one"
    );
    assert!(backward >= n / 8, "{backward}");
    assert!(end_effect >= n / 10, "{end_effect}");
    assert!(windowless >= n / 4, "{windowless}");
}
