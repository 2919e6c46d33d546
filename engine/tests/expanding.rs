#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

//! Expanding activities whose feasibility is not monotone in the duration (the
//! min_awake extension near the plan end): the longest duration is found without
//! trying every duration, and the trace stays small.

use std::time::{Duration, Instant};

use serde_json::json;
use solscope_engine::{
    ExplainOptions, FailurePhase, GeneratedKind, Outcome, Phase2Reason, explain, load_plan,
    schedule,
};

/// A valid five-line plan that hung with memory growing ~50 MB/s (the
/// scheduler tried every duration from 999,000,000 s down, one second at a time,
/// keeping every failed try). Kept exactly as reported.
const HANG: &str = r#"{"format":"solscope.plan/1","horizon":{"start":0,"end":1000000000},
 "battery":{"capacity":1600.0,"initial":1200.0,"min_soc":500.0},
 "power":{"rtg":110.0,"asleep":25.0,"awake":190.0,"max_peak":900.0},
 "sleep":{"min_awake":1800},
 "activities":[{"id":"x","priority":1,"duration":{"min":1,"max":999000000},"peak_power":5000.0}]}"#;

#[test]
fn huge_expanding_range_without_windows_fails_quickly() {
    let loaded = load_plan(HANG).expect("valid plan");
    let t = Instant::now();
    let s = schedule(&loaded.plan).expect("schedules");
    let took = t.elapsed();
    // Debug builds cross-check every shortcut; the release run takes milliseconds.
    assert!(took < Duration::from_secs(30), "schedule took {took:?}");
    let step = &s.steps[0];
    assert_eq!(step.outcome, Outcome::Failed(FailurePhase::Placement));
    // The record is that of the shortest duration (docs/semantics.md), and the
    // trace holds merged ranges, not one entry per duration tried.
    assert_eq!(step.duration, 1);
    let tries = s.tries(step.step);
    assert!(!tries.is_empty() && tries.len() <= 4, "{tries:?}");
    for t in &tries {
        assert_eq!(t.duration, 1);
        assert!(
            matches!(t.reason, Some(Phase2Reason::MaxPeakPower { .. })),
            "{t:?}"
        );
    }
    let t = Instant::now();
    let ex = explain(&loaded.plan, &s, &ExplainOptions::default()).expect("explains");
    let took = t.elapsed();
    assert!(took < Duration::from_secs(60), "explain took {took:?}");
    assert_eq!(ex.len(), 1);
    assert_eq!(ex[0].duration, 1);
    assert!(!ex[0].reasons.is_empty() && ex[0].reasons.len() <= 4);
}

/// The hanging plan with `power.awake < power.asleep`: a longer awake period
/// then charges more, so no duration bound of the monotone kind holds and every
/// duration used to be searched. Its peak power (5000 W against 900 W) fails at
/// any start whatever the duration, which the start's peak alone proves.
#[test]
fn charging_awake_expanding_activity_that_fails_on_peak_fails_quickly() {
    let mut p: serde_json::Value = serde_json::from_str(HANG).expect("json");
    p["power"]["awake"] = json!(20.0);
    let loaded = load_plan(&p.to_string()).expect("valid plan");
    let t = Instant::now();
    let s = schedule(&loaded.plan).expect("schedules");
    let took = t.elapsed();
    assert!(took < Duration::from_secs(30), "schedule took {took:?}");
    let step = &s.steps[0];
    assert_eq!(step.outcome, Outcome::Failed(FailurePhase::Placement));
    assert_eq!(step.duration, 1);
    let tries = s.tries(step.step);
    assert!(!tries.is_empty() && tries.len() <= 4, "{tries:?}");
}

/// Only starts after `horizon.end - min_awake + wakeup` fit (a blocker's peak power
/// rules out every earlier one), so the longest duration comes from the part of
/// the search where the awake period is extended backwards from the activity's end.
///
/// Horizon 0..10000, no wakeup/shutdown, min_awake 1800, awake and asleep draw 0.
/// B holds 100 W of peak over [0, 8300) with max_peak 100 W, so X (10 W) starts at
/// 8300 or later; X's end is at most 10000, so its longest duration is 1700 at
/// 8300, and its awake period [8300, 10000) is 1700 s long: the forward extension
/// would pass the plan end, so it is extended backwards to [8200, 10000).
#[test]
fn longest_duration_from_a_start_after_the_head() {
    let p = json!({
        "format": "solscope.plan/1",
        "horizon": { "start": 0, "end": 10000 },
        "battery": { "capacity": 1000.0, "initial": 1000.0, "min_soc": 0.0 },
        "power": { "rtg": 0.0, "asleep": 0.0, "awake": 0.0, "max_peak": 100.0 },
        "sleep": { "min_awake": 1800 },
        "activities": [
            { "id": "B", "priority": 1, "duration": 8300, "awake": "any",
              "peak_power": 100.0, "windows": [ { "start": 0, "end": 0 } ] },
            { "id": "X", "priority": 2, "duration": { "min": 10, "max": 5000 },
              "peak_power": 10.0 }
        ]
    });
    let loaded = load_plan(&p.to_string()).expect("valid plan");
    let s = schedule(&loaded.plan).expect("schedules");
    let x = s.step_of(1).expect("step");
    assert_eq!(
        x.outcome,
        Outcome::Scheduled {
            start: 8300,
            end: 10000
        }
    );
    assert_eq!(x.duration, 1700);
    let tries = s.tries(x.step);
    assert!(tries.iter().all(|t| t.duration == 1700), "{tries:?}");
    let awake: Vec<(i64, i64)> = s
        .generated_after(2)
        .filter(|g| g.kind == GeneratedKind::Awake)
        .map(|g| (g.start, g.end))
        .collect();
    assert_eq!(awake, vec![(8200, 10000)]);
}

/// With `power.awake < power.asleep` an awake period charges the battery, so a
/// longer awake-required activity can pass where a shorter one fails `min_soc`.
/// The binary search over durations assumed the opposite and failed this activity
/// (its middle duration fails, so it looked only shorter), although its longest
/// duration fits: 7200 s awake out of 10 h keeps the battery at 700 Wh >= 675.
#[test]
fn an_awake_period_that_charges_still_gets_the_longest_duration() {
    let plan = json!({
        "format": "solscope.plan/1",
        "horizon": { "start": 0, "end": 36000 },
        "battery": { "capacity": 1000.0, "initial": 1000.0, "min_soc": 675.0 },
        "power": { "rtg": 60.0, "asleep": 100.0, "awake": 50.0 },
        "activities": [ { "id": "x", "priority": 1, "duration": { "min": 600, "max": 7200 } } ]
    });
    let loaded = load_plan(&plan.to_string()).expect("valid plan");
    let s = schedule(&loaded.plan).expect("schedules");
    assert_eq!(
        s.steps[0].outcome,
        Outcome::Scheduled {
            start: 0,
            end: 7200
        }
    );
}

/// The once-hanging plan with an effect at the activity's end, which makes
/// feasibility non-monotone in the duration, so that a binary search cannot decide
/// it: every duration used to be searched, one second at a time. Leaving out the
/// state_effect category bounds the answer, and here proves that no duration
/// fits (its peak power fails everywhere).
#[test]
fn end_effect_expanding_activity_that_fails_everywhere_fails_quickly() {
    let mut p: serde_json::Value = serde_json::from_str(HANG).expect("json");
    p["states"] = json!({ "arm": { "values": ["stowed", "unstowed"], "initial": "stowed" } });
    p["activities"][0]["effects"] = json!([{ "state": "arm", "value": "unstowed", "at": "end" }]);
    let loaded = load_plan(&p.to_string()).expect("valid plan");
    let t = Instant::now();
    let s = schedule(&loaded.plan).expect("schedules");
    let took = t.elapsed();
    assert!(took < Duration::from_secs(30), "schedule took {took:?}");
    let step = &s.steps[0];
    assert_eq!(step.outcome, Outcome::Failed(FailurePhase::Placement));
    assert_eq!(step.duration, 1);
    let tries = s.tries(step.step);
    assert!(!tries.is_empty() && tries.len() <= 4, "{tries:?}");
    assert!(tries.iter().all(|t| t.duration == 1
        && matches!(t.reason, Some(Phase2Reason::MaxPeakPower { .. }))));
    let ex = explain(&loaded.plan, &s, &ExplainOptions::default()).expect("explains");
    assert_eq!(ex.len(), 1);
    assert!(!ex[0].reasons.is_empty() && ex[0].reasons.len() <= 4);
}

/// An end effect that makes the longest durations fail while shorter ones fit.
/// X starts in 0..=1000 and sets `arm` to `b` at its end; Y sets it back to `a` at
/// 4000 and R needs `a` over [4500, 5000), so an end in [4000, 5000) fails on
/// state_effect. B holds all the peak power over [4900, 5100), so an end after
/// 4900 fails phase 2. Of 100..=4500 the longest duration that fits is 3999, from
/// 0. The longer durations with an end after 4900 fail in phase 2; the trace
/// holds the tries of 3999 only (docs/semantics.md), not one entry per duration.
#[test]
fn end_effect_longest_duration_below_a_blocked_band() {
    let p = json!({
        "format": "solscope.plan/1",
        "horizon": { "start": 0, "end": 20000 },
        "battery": { "capacity": 1000.0, "initial": 1000.0, "min_soc": 0.0 },
        "power": { "rtg": 0.0, "asleep": 0.0, "awake": 0.0, "max_peak": 100.0 },
        "states": { "arm": { "values": ["a", "b"], "initial": "a" } },
        "activities": [
            { "id": "R", "priority": 1, "duration": 500, "awake": "any",
              "windows": [ { "start": 4500, "end": 4500 } ],
              "requires": [ { "state": "arm", "value": "a" } ] },
            { "id": "Y", "priority": 2, "duration": 100, "awake": "any",
              "windows": [ { "start": 4000, "end": 4000 } ],
              "effects": [ { "state": "arm", "value": "a", "at": "start" } ] },
            { "id": "B", "priority": 3, "duration": 200, "awake": "any",
              "peak_power": 100.0, "windows": [ { "start": 4900, "end": 4900 } ] },
            { "id": "X", "priority": 4, "duration": { "min": 100, "max": 4500 },
              "awake": "any", "peak_power": 10.0, "windows": [ { "start": 0, "end": 1000 } ],
              "effects": [ { "state": "arm", "value": "b", "at": "end" } ] }
        ]
    });
    let loaded = load_plan(&p.to_string()).expect("valid plan");
    let s = schedule(&loaded.plan).expect("schedules");
    let x = s.step_of(3).expect("step");
    assert_eq!(
        x.outcome,
        Outcome::Scheduled {
            start: 0,
            end: 3999
        }
    );
    assert_eq!(x.duration, 3999);
    let tries = s.tries(x.step);
    assert!(tries.iter().all(|t| t.duration == 3999), "{tries:?}");
}

/// Feasibility with gaps in the duration, which a binary search over the
/// activity itself would miss: X starts at 0 and sets `arm` to `b` at its end,
/// which holds until the next effect. Y1, Y2 and Y3 set `a` at 1001, 3000 and
/// 3501; R2 needs `a` over [2900, 3000) and R4 over [4400, 4600). An end in
/// [1001, 2999] leaves `b` over R2, an end after 3500 over R4, so of 100..=4500
/// the durations that fit are 100..=1000 and 3000..=3500. A binary search would
/// try 2300, fail, and settle on 1000; the bound without the end-effect checks is
/// 4500, and the scan down from it finds 3500.
#[test]
fn end_effect_longest_duration_above_a_gap() {
    let fixed = |id: &str, at: i64, dur: i64, key: &str| {
        json!({ "id": id, "priority": 1, "duration": dur, "awake": "any",
                "windows": [ { "start": at, "end": at } ],
                key: if key == "effects" {
                    json!([{ "state": "arm", "value": "a", "at": "start" }])
                } else {
                    json!([{ "state": "arm", "value": "a" }])
                } })
    };
    let p = json!({
        "format": "solscope.plan/1",
        "horizon": { "start": 0, "end": 20000 },
        "battery": { "capacity": 1000.0, "initial": 1000.0, "min_soc": 0.0 },
        "power": { "rtg": 0.0, "asleep": 0.0, "awake": 0.0 },
        "states": { "arm": { "values": ["a", "b"], "initial": "a" } },
        "activities": [
            fixed("Y1", 1001, 10, "effects"),
            fixed("Y2", 3000, 10, "effects"),
            fixed("Y3", 3501, 10, "effects"),
            fixed("R2", 2900, 100, "requires"),
            fixed("R4", 4400, 200, "requires"),
            { "id": "X", "priority": 2, "duration": { "min": 100, "max": 4500 },
              "awake": "any", "windows": [ { "start": 0, "end": 0 } ],
              "effects": [ { "state": "arm", "value": "b", "at": "end" } ] }
        ]
    });
    let loaded = load_plan(&p.to_string()).expect("valid plan");
    let s = schedule(&loaded.plan).expect("schedules");
    let x = s.step_of(5).expect("step");
    assert_eq!(
        x.outcome,
        Outcome::Scheduled {
            start: 0,
            end: 3500
        }
    );
}

/// The hanging plan's shape with an end effect that only short durations can
/// take: X (1 s to 900,000,000 s, starting by 1000) sets `arm` to `b` at its
/// end, Y sets `a` at 5000, and R needs `a` near the plan end. An end at 5000
/// or later leaves `b` over R, so the longest duration that fits is 4999, from
/// 0. Without the end-effect checks every duration passes, so the bound is the
/// longest; the scan must skip the durations whose ends no start can reach
/// before 5000 rather than search 900 million of them.
#[test]
fn end_effect_blocked_near_the_plan_end_scans_only_reachable_durations() {
    let p = json!({
        "format": "solscope.plan/1",
        "horizon": { "start": 0, "end": 1_000_000_000 },
        "battery": { "capacity": 1600.0, "initial": 1200.0, "min_soc": 500.0 },
        "power": { "rtg": 110.0, "asleep": 25.0, "awake": 190.0, "max_peak": 900.0 },
        "states": { "arm": { "values": ["a", "b"], "initial": "a" } },
        "activities": [
            { "id": "Y", "priority": 1, "duration": 10, "awake": "any",
              "windows": [ { "start": 5000, "end": 5000 } ],
              "effects": [ { "state": "arm", "value": "a", "at": "start" } ] },
            { "id": "R", "priority": 1, "duration": 1000, "awake": "any",
              "windows": [ { "start": 999_999_000, "end": 999_999_000 } ],
              "requires": [ { "state": "arm", "value": "a" } ] },
            { "id": "X", "priority": 2, "duration": { "min": 1, "max": 900_000_000 },
              "awake": "any", "peak_power": 5.0, "windows": [ { "start": 0, "end": 1000 } ],
              "effects": [ { "state": "arm", "value": "b", "at": "end" } ] }
        ]
    });
    let loaded = load_plan(&p.to_string()).expect("valid plan");
    let t = Instant::now();
    let s = schedule(&loaded.plan).expect("schedules");
    let took = t.elapsed();
    assert!(took < Duration::from_secs(30), "schedule took {took:?}");
    let x = s.step_of(2).expect("step");
    assert_eq!(
        x.outcome,
        Outcome::Scheduled {
            start: 0,
            end: 4999
        }
    );
}
