#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

//! Brute-force cross-checks of the explainer on random small plans:
//! - the failure step equals the smallest k found by rescheduling partial plans
//!   from scratch (the activities of steps k+1.. moved after the explained one,
//!   its excluded dependencies and requirements removed);
//! - the conflict sets equal those found by enumerating all subsets of categories;
//! - every suggestion, applied to the plan file, makes the activity schedule.

#[path = "gen/mod.rs"]
mod plangen;

use proptest::prelude::*;
use serde_json::Value;
use solscope_engine::{
    Category, ExplainOptions, Explanation, IntervalSet, Outcome, Phase, Plan, Schedule, explain,
    load_plan, schedule,
};

/// Step number (1-based) of every activity.
fn steps(s: &Schedule) -> Vec<usize> {
    let mut v = vec![0; s.problem.acts.len()];
    for st in &s.steps {
        v[st.activity] = st.step;
    }
    v
}

/// Whether activity `a` fails when scheduled right after steps 1..k, by
/// rescheduling a partial plan from scratch.
fn fails_after(plan: &Plan, sched: &Schedule, a: usize, k: usize) -> bool {
    let step = steps(sched);
    let mine = step[a];
    let mut v = serde_json::to_value(plan).expect("plan json");
    let max_priority = plan
        .activities
        .iter()
        .map(|x| x.priority)
        .max()
        .unwrap_or(0);
    let pending = |x: usize| x != a && step[x] < mine && step[x] > k;
    let acts = v["activities"].as_array_mut().expect("activities");
    for (x, act) in acts.iter_mut().enumerate() {
        if pending(x) {
            // Move after the explained activity (relative order kept by file order
            // among equal priorities, which cannot affect `a`).
            act["priority"] = Value::from(max_priority + 1);
        }
    }
    // The inclusion rule: drop dependencies on pending activities and requirements
    // some pending activity could satisfy.
    let me = &plan.activities[a];
    let after: Vec<Value> = me
        .after
        .iter()
        .filter(|d| {
            !plan
                .activities
                .iter()
                .position(|o| o.id == d.activity)
                .is_some_and(pending)
        })
        .map(|d| serde_json::to_value(d).expect("dep"))
        .collect();
    let requires: Vec<Value> = me
        .requires
        .iter()
        .filter(|r| {
            !plan.activities.iter().enumerate().any(|(x, o)| {
                pending(x)
                    && o.effects
                        .iter()
                        .any(|e| e.state == r.state && e.value == r.value)
            })
        })
        .map(|r| serde_json::to_value(r).expect("req"))
        .collect();
    acts[a]["after"] = Value::Array(after);
    acts[a]["requires"] = Value::Array(requires);
    let partial: Plan = serde_json::from_value(v).expect("partial plan");
    let s = schedule(&partial).expect("schedules");
    s.placement(a).is_none()
}

/// Minimal conflict sets by enumerating every subset of the categories.
fn brute_conflicts(ex: &Explanation, lo: i64, hi: i64) -> Vec<Vec<Category>> {
    let cats = &ex.categories;
    let n = cats.len();
    let mut found: Vec<u32> = Vec::new();
    let mut subsets: Vec<u32> = (1..(1u32 << n)).collect();
    subsets.sort_by_key(|s| s.count_ones());
    for s in subsets {
        if found.iter().any(|f| f & s == *f) {
            continue;
        }
        let inter = (0..n)
            .filter(|i| s >> i & 1 == 1)
            .fold(IntervalSet::single(lo, hi), |acc, i| {
                acc.intersect(&cats[i].valid)
            });
        if inter.is_empty() {
            found.push(s);
        }
    }
    let mut out: Vec<Vec<Category>> = found
        .into_iter()
        .map(|s| {
            let mut v: Vec<Category> = (0..n)
                .filter(|i| s >> i & 1 == 1)
                .map(|i| cats[i].category)
                .collect();
            v.sort();
            v
        })
        .collect();
    out.sort();
    out
}

fn check(text: &str) -> Result<(), TestCaseError> {
    let Ok(loaded) = load_plan(text) else {
        return Ok(());
    };
    let plan = loaded.plan;
    let sched = schedule(&plan).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let explanations = explain(&plan, &sched, &ExplainOptions::default())
        .map_err(|e| TestCaseError::fail(e.to_string()))?;
    for ex in &explanations {
        let a = ex.activity;
        let id = &plan.activities[a].id;
        let k = ex
            .failure_step
            .ok_or_else(|| TestCaseError::fail(format!("{id}: no failure step")))?;
        prop_assert!(k < ex.step, "{id}: failure step {k} >= step {}", ex.step);
        // Smallest k by rescheduling partial plans.
        let brute = (0..ex.step).find(|&j| fails_after(&plan, &sched, a, j));
        prop_assert_eq!(brute, Some(k), "{}: failure step", id);
        // Conflicts against subset enumeration (phase valid_intervals).
        if ex.phase == Some(Phase::ValidIntervals) {
            let problem = &sched.problem;
            let mut mine = ex.conflicts.clone();
            for c in &mut mine {
                c.sort();
            }
            mine.sort();
            prop_assert_eq!(
                mine,
                brute_conflicts(ex, problem.h0, problem.h1),
                "{}: conflicts",
                id
            );
            prop_assert!(
                !ex.conflicts.is_empty(),
                "{id}: valid_intervals without a conflict"
            );
        }
        // Explained alone (as `explain --activity` and the app do, where no
        // other failure shares the verifying runs), it is explained the same.
        let opts = ExplainOptions {
            activity: Some(id.clone()),
            no_suggestions: false,
        };
        let alone =
            explain(&plan, &sched, &opts).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(
            serde_json::to_value(&alone).expect("json"),
            serde_json::to_value(std::slice::from_ref(ex)).expect("json"),
            "{}: explained alone differs",
            id
        );
        // Every suggestion, applied to the plan file, makes the activity schedule.
        for s in &ex.suggestions {
            let mut v: Value = serde_json::from_str(text).expect("json");
            let obj = if s.target == "plan" {
                v.as_object_mut()
            } else {
                let want = s.target.trim_start_matches("activity:");
                v["activities"]
                    .as_array_mut()
                    .and_then(|acts| acts.iter_mut().find(|x| x["id"] == want))
                    .and_then(Value::as_object_mut)
            }
            .ok_or_else(|| TestCaseError::fail(format!("bad target {}", s.target)))?;
            for (key, value) in &s.set {
                if value.is_null() {
                    obj.remove(key);
                } else {
                    obj.insert(key.clone(), value.clone());
                }
            }
            let edited = load_plan(&v.to_string())
                .map_err(|e| TestCaseError::fail(format!("{id}: {}: {e}", s.description)))?;
            let again = schedule(&edited.plan).map_err(|e| TestCaseError::fail(e.to_string()))?;
            prop_assert!(
                matches!(
                    again.step_of(a).map(|st| &st.outcome),
                    Some(Outcome::Scheduled { .. })
                ),
                "{id}: suggestion '{}' does not make it schedule",
                s.description
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 128,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn explanations_match_brute_force(text in plangen::plan_text()) {
        check(&text)?;
    }

    /// The same on plans with a starved battery, where most failures are on
    /// the battery or handover minimum.
    #[test]
    fn starved_explanations_match_brute_force(text in plangen::starved_plan_text()) {
        check(&text)?;
    }
}

/// The plans the repository ships (relative to its root).
const BUNDLED_PLANS: [&str; 4] = [
    "assets/default-plan.json",
    "assets/tutorial-plan.json",
    "assets/examples/drill-sol.json",
    "assets/examples/pitfall.json",
];

#[test]
fn bundled_plans_and_examples_are_explained_consistently() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    for path in BUNDLED_PLANS {
        let text = std::fs::read_to_string(root.join(path)).expect("read plan");
        let loaded = load_plan(&text).expect("valid");
        let sched = schedule(&loaded.plan).expect("schedules");
        let failed = sched
            .steps
            .iter()
            .filter(|s| !matches!(s.outcome, Outcome::Scheduled { .. }))
            .count();
        let ex = explain(&loaded.plan, &sched, &ExplainOptions::default()).expect("explains");
        assert_eq!(
            ex.len(),
            failed,
            "{path}: one explanation per failed activity"
        );
        for e in &ex {
            assert!(
                e.failure_step.is_some() && e.phase.is_some(),
                "{path}: {}",
                e.activity
            );
        }
        check(&text).unwrap_or_else(|e| panic!("{path}: {e}"));
    }
}

/// The profiles `Schedule::profiles_if_placed` gives for an energy or peak
/// reason's start reach the reason's numbers: the lowest state of charge
/// (first at `at`), the handover state of charge, or the peak at `at`.
#[test]
fn profiles_if_placed_reach_the_reasons_numbers() {
    use solscope_engine::{Phase2Reason, watts, wh};
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut seen = 0;
    for path in BUNDLED_PLANS {
        let text = std::fs::read_to_string(root.join(path)).expect("read plan");
        let plan = load_plan(&text).expect("valid").plan;
        let sched = schedule(&plan).expect("schedules");
        let opts = ExplainOptions {
            no_suggestions: true,
            ..ExplainOptions::default()
        };
        for ex in explain(&plan, &sched, &opts).expect("explains") {
            let k = ex.failure_step.expect("failure step");
            for r in &ex.reasons {
                let placed = || {
                    sched
                        .profiles_if_placed(k, ex.activity, r.probe, r.duration)
                        .expect("no structural reason")
                };
                match r.reason {
                    Phase2Reason::MinSoc { at, soc_mj } => {
                        let p = placed();
                        let lowest = p.soc.iter().map(|x| x.1).fold(f64::INFINITY, f64::min);
                        assert_eq!(lowest, wh(i128::from(soc_mj)), "{path}: {}", ex.activity);
                        let first = p.soc.iter().find(|x| x.1 == lowest).map(|x| x.0);
                        assert_eq!(first, Some(at), "{path}: {}", ex.activity);
                    }
                    Phase2Reason::HandoverSoc { soc_mj } => {
                        let p = placed();
                        let t = plan.handover.expect("handover").time;
                        // Linear between points.
                        let i = p.soc.partition_point(|x| x.0 <= t).max(1);
                        let ((t0, v0), (t1, v1)) = (p.soc[i - 1], p.soc[i.min(p.soc.len() - 1)]);
                        let there = if t1 > t0 {
                            v0 + (v1 - v0) * (t - t0) as f64 / (t1 - t0) as f64
                        } else {
                            v0
                        };
                        let want = wh(i128::from(soc_mj));
                        assert!((there - want).abs() < 1e-6, "{path}: {there} != {want}");
                    }
                    Phase2Reason::MaxPeakPower { at, peak_mw } => {
                        let p = placed();
                        // Constant from each point to the next.
                        let i = p.peak_power.partition_point(|x| x.0 <= at);
                        let there = p.peak_power[i.saturating_sub(1)].1;
                        assert!(there >= watts(peak_mw), "{path}: {there} at {at}");
                    }
                    _ => continue,
                }
                seen += 1;
            }
        }
    }
    assert!(seen > 0, "no energy or peak reason in the bundled plans");
}
