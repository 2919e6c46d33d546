//! Priority tuning's evidence search scores the mandatory-first order (every
//! mandatory activity, and what it must follow, ahead of the rest) before its
//! descent, and starts from it when it is better: two mandatory activities,
//! each kept out by an optional one scheduled first, both run after two orders
//! scored, where a move per lost activity would need three.
#![allow(clippy::panic, clippy::unwrap_used, clippy::expect_used)]

use serde_json::{Value, json};
use solscope_engine::{Mode, Plan, TuneOptions, load_plan, tune};

/// An activity `id` at `priority` that must start at 0 on unit resource `r`.
fn at_zero(id: &str, priority: i64, mandatory: bool, r: &str) -> Value {
    json!({
        "id": id, "priority": priority, "mandatory": mandatory, "duration": 600,
        "windows": [{ "start": 0, "end": 0 }], "resources": [r], "awake": "any"
    })
}

/// `a1` takes `r1` from `b1` and `a2` takes `r2` from `b2`; eight optional
/// fillers fit anywhere (so more than eight activities can move: the
/// evidence search, not the exact one).
fn plan() -> Plan {
    let mut acts = vec![
        at_zero("a1", 1, false, "r1"),
        at_zero("b1", 2, true, "r1"),
        at_zero("a2", 3, false, "r2"),
        at_zero("b2", 4, true, "r2"),
    ];
    for k in 0..8 {
        acts.push(json!({
            "id": format!("f{k}"), "priority": 10 + k, "mandatory": false,
            "duration": 60, "awake": "any"
        }));
    }
    let plan = json!({
        "format": "solscope.plan/1",
        "horizon": { "start": 0, "end": 7200 },
        "battery": { "capacity": 1000.0, "initial": 900.0, "min_soc": 100.0 },
        "power": { "rtg": 100.0, "asleep": 10.0, "awake": 60.0 },
        "activities": acts
    });
    load_plan(&plan.to_string()).expect("valid").plan
}

#[test]
fn mandatory_first_order_is_scored_before_the_descent() {
    let plan = plan();
    let options = TuneOptions {
        budget: 2,
        ..TuneOptions::default()
    };
    let t = tune(&plan, &options).expect("tunes");
    assert_eq!(t.mode, Mode::Evidence);
    assert_eq!(t.evaluations, 2);
    // The original order loses both mandatory activities; the tuned one runs
    // both (one run: no duration model).
    assert_eq!(t.tuning_scores.original.mandatory_completed, 0);
    assert_eq!(t.tuning_scores.tuned.mandatory_completed, 2);
    let ids: Vec<&str> = t
        .tuned
        .iter()
        .map(|&a| plan.activities[a].id.as_str())
        .collect();
    assert_eq!(&ids[..2], ["b1", "b2"], "{ids:?}");
    // With a budget of one order, only the original is scored.
    let one = tune(
        &plan,
        &TuneOptions {
            budget: 1,
            ..TuneOptions::default()
        },
    )
    .expect("tunes");
    assert_eq!(one.tuned, one.original);
}
