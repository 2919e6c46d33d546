//! The execution policies beside replanning (`fixed`, `dispatch`), on random small
//! plans with uncertain durations added to some fixed-duration activities:
//!
//! 1. with every actual duration equal to `duration`, both run the schedule (dispatch
//!    when the network is not made controllable with waits and tightened bounds)
//!    exactly: every placed activity starts at its scheduled start and completes,
//!    nothing else runs (replanning may run more: a later cycle can find room),
//!    and the two executed profiles are the same;
//! 2. with sampled durations, `fixed` starts an activity only at its scheduled
//!    start, and `dispatch` starts one only when its start condition holds for the
//!    events that happened (every `after` bound met, no `within` bound of an event
//!    that happened earlier passed, inside `[lb, ub]`), and never while an
//!    activity sharing a unit resource still runs or before a dependency ended;
//! 3. Monte Carlo under each policy gives the same records on one thread and many.
#![allow(clippy::panic, clippy::unwrap_used, clippy::expect_used)]

#[path = "gen/mod.rs"]
mod plangen;

use proptest::prelude::*;
use serde_json::Value;
use solscope_engine::{
    Actuals, Controllability, ExecuteOptions, FlexOptions, Plan, Policy, RunOutcome, TimePoint,
    campaign_runs, campaign_with, execute_with, flex_with, load_plan, sample_run, schedule,
};

/// The plan with a `duration_model` on every third fixed-duration activity:
/// `[d / 2, 2 d]`.
fn with_models(text: &str) -> Plan {
    let mut v: Value = serde_json::from_str(text).unwrap();
    for (i, a) in v["activities"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .enumerate()
    {
        if let Some(d) = a["duration"].as_i64() {
            if i % 3 == 0 && d >= 2 {
                a["duration_model"] = serde_json::json!({ "min": d / 2, "max": 2 * d });
            }
        }
    }
    load_plan(&v.to_string()).expect("valid plan").plan
}

fn run(plan: &Plan, actuals: &Actuals, policy: Policy) -> solscope_engine::Execution {
    execute_with(plan, actuals, ExecuteOptions { policy }).unwrap()
}

fn check(plan: &Plan, seed: u64) -> Result<(), String> {
    let sched = schedule(plan).map_err(|e| e.to_string())?;
    let nominal = Actuals::nominal();
    let flex = flex_with(plan, &sched, FlexOptions { free_slack: false });
    // A controllable network may make dispatch wait where the schedule relied on
    // a predicted duration: then even nominal durations need not reproduce it.
    let exact = !matches!(flex.controllability, Controllability::Controllable { .. });
    let mut profiles = Vec::new();
    for policy in [Policy::Fixed, Policy::Dispatch] {
        if policy == Policy::Dispatch && !exact {
            continue;
        }
        let ex = run(plan, &nominal, policy);
        for (a, r) in ex.activities.iter().enumerate() {
            let placed = sched.placement(a);
            match (placed, r.actual) {
                (Some(p), Some(act)) if p == act && r.outcome == RunOutcome::Completed => {}
                (None, None) => {}
                other => {
                    return Err(format!(
                        "{policy:?}, nominal: {} scheduled/ran {other:?}",
                        plan.activities[a].id
                    ));
                }
            }
        }
        profiles.push(ex.profile);
    }
    if profiles.len() == 2 && profiles[0] != profiles[1] {
        return Err("nominal: fixed and dispatch profiles differ".into());
    }
    let actuals = sample_run(plan, seed, 0);
    let fixed = run(plan, &actuals, Policy::Fixed);
    for (a, r) in fixed.activities.iter().enumerate() {
        if let Some((s, _)) = r.actual {
            if sched.placement(a).map(|p| p.0) != Some(s) {
                return Err(format!("fixed started {} at {s}", plan.activities[a].id));
            }
        }
    }
    let ex = run(plan, &actuals, Policy::Dispatch);
    let time = |e: TimePoint| match e {
        TimePoint::Origin => Some(plan.horizon.start),
        TimePoint::Start(b) => ex.activities[b].actual.map(|x| x.0),
        TimePoint::End(b) => ex.activities[b].actual.map(|x| x.1),
    };
    for fa in &flex.activities {
        let a = fa.activity;
        let Some((s, _)) = ex.activities[a].actual else {
            continue;
        };
        let id = &plan.activities[a].id;
        if s < fa.start.lb || s > fa.start.ub {
            return Err(format!(
                "dispatch started {id} at {s} outside [{}, {}]",
                fa.start.lb, fa.start.ub
            ));
        }
        for b in &fa.condition.after {
            match time(b.event) {
                Some(t) if t <= s && s >= t + b.offset => {}
                // A negative offset binds only an event that happened first.
                Some(t) if t > s && b.offset < 0 => {}
                None if b.offset < 0 => {}
                other => {
                    return Err(format!(
                        "dispatch started {id} at {s}: after {b:?} at {other:?}"
                    ));
                }
            }
        }
        for b in &fa.condition.within {
            if let Some(t) = time(b.event) {
                if t <= s && s > t + b.offset {
                    return Err(format!("dispatch started {id} at {s}: within {b:?} at {t}"));
                }
            }
        }
        for (c, rc) in ex.activities.iter().enumerate() {
            let Some((cs, ce)) = rc.actual else { continue };
            let shared = plan.activities[a]
                .resources
                .iter()
                .any(|r| plan.activities[c].resources.contains(r));
            if c != a && shared && cs <= s && s < ce {
                return Err(format!(
                    "dispatch started {id} while {} ran",
                    plan.activities[c].id
                ));
            }
        }
        // Sequence engines held at its start (by what actually ran) plus its own.
        let own = plan.activities[a].sequence_engines;
        if let (Some(cap), true) = (plan.sequence_engines, own > 0) {
            let held: u32 = ex
                .activities
                .iter()
                .enumerate()
                .filter(|&(c, rc)| c != a && rc.actual.is_some_and(|(cs, ce)| cs <= s && s < ce))
                .map(|(c, _)| plan.activities[c].sequence_engines)
                .sum();
            if held + own > cap {
                return Err(format!(
                    "dispatch started {id} at {s} with {held} of {cap} engines held"
                ));
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 128,
        failure_persistence: None,
        max_shrink_iters: 500,
        ..ProptestConfig::default()
    })]

    #[test]
    fn policies_run_the_schedule_and_keep_their_rules(text in plangen::plan_text(), seed in 0u64..1000) {
        let plan = with_models(&text);
        if let Err(e) = check(&plan, seed) {
            return Err(TestCaseError::fail(format!("{e}\nplan:\n{}", serde_json::to_string_pretty(&plan).unwrap())));
        }
    }
}

#[test]
fn monte_carlo_under_each_policy_is_the_same_on_any_thread_count() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../assets/default-plan.json"
    ))
    .unwrap();
    let plan = load_plan(&text).unwrap().plan;
    let indices: Vec<u64> = (0..40).collect();
    for policy in [Policy::Fixed, Policy::Dispatch] {
        let c = campaign_with(&plan, 5, 40, "plan", policy).unwrap();
        let on_threads = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| {
                    campaign_runs(&plan, &c, &indices, &|| {}, None)
                        .unwrap()
                        .unwrap()
                })
        };
        let (one, many) = (on_threads(1), on_threads(4));
        assert_eq!(one, many, "{policy:?}");
        // The policies draw the same durations run by run.
        let replan = campaign_with(&plan, 5, 40, "plan", Policy::Replan).unwrap();
        let r = campaign_runs(&plan, &replan, &indices[..3], &|| {}, None)
            .unwrap()
            .unwrap();
        assert_eq!(r[2].durations, one[2].durations);
    }
}

/// On a controllable network, dispatch with sampled durations keeps every
/// temporal edge among the events that happened and skips nothing (a strategy
/// that meets every constraint exists: dispatch must find it). `Ok(false)` when
/// the network is not controllable (nothing to check).
fn controllable_keeps_edges(plan: &Plan, seed: u64) -> Result<bool, String> {
    let sched = schedule(plan).map_err(|e| e.to_string())?;
    let flex = flex_with(plan, &sched, FlexOptions { free_slack: false });
    if !matches!(flex.controllability, Controllability::Controllable { .. }) {
        return Ok(false);
    }
    let actuals = sample_run(plan, seed, 0);
    let ex = run(plan, &actuals, Policy::Dispatch);
    let time = |e: TimePoint| match e {
        TimePoint::Origin => Some(plan.horizon.start),
        TimePoint::Start(b) => ex.activities[b].actual.map(|x| x.0),
        TimePoint::End(b) => ex.activities[b].actual.map(|x| x.1),
    };
    let skipped: Vec<&str> = flex
        .activities
        .iter()
        .filter(|fa| ex.activities[fa.activity].actual.is_none())
        .map(|fa| plan.activities[fa.activity].id.as_str())
        .collect();
    for e in &flex.network {
        if matches!(e.why, solscope_engine::Constraint::Duration { .. }) {
            continue;
        }
        if let (Some(a), Some(b)) = (time(e.from), time(e.to)) {
            if b - a > e.max {
                return Err(format!(
                    "broke {:?}: {} > {} (skipped {skipped:?})",
                    e.why,
                    b - a,
                    e.max
                ));
            }
        }
    }
    if !skipped.is_empty() {
        return Err(format!("skipped {skipped:?}"));
    }
    Ok(true)
}

#[test]
fn controllable_dispatch_keeps_the_network() {
    use proptest::test_runner::{Config, TestRunner};
    use std::sync::atomic::{AtomicUsize, Ordering};
    let cases = 512;
    let mut runner = TestRunner::new(Config {
        cases,
        failure_persistence: None,
        max_shrink_iters: 200,
        ..Config::default()
    });
    let checked = AtomicUsize::new(0);
    let result = runner.run(&(plangen::plan_text(), 0u64..1000), |(text, seed)| {
        let plan = with_models(&text);
        match controllable_keeps_edges(&plan, seed) {
            Ok(c) => {
                checked.fetch_add(usize::from(c), Ordering::Relaxed);
                Ok(())
            }
            Err(e) => Err(TestCaseError::fail(format!(
                "{e}\nplan:\n{text}\nseed {seed}"
            ))),
        }
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    // Not hollow: a good share of the random plans are controllable with
    // uncertain durations.
    let checked = checked.into_inner();
    assert!(
        checked * 5 >= cases as usize,
        "only {checked} of {cases} plans checked"
    );
}
