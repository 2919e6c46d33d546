//! Execution (`execute`): property tests on random plans and one hand-worked
//! scenario per rule.
//!
//! 1. With every actual duration equal to `duration`, every activity starts where
//!    the first cycle placed it, and runs exactly when that schedule placed it
//!    (when the first schedule keeps the handover limits: a mandatory activity
//!    that breaks one makes the later cycles, which see the real state of charge,
//!    drop optional activities it was placed after; docs/semantics.md).
//! 2. With random actual durations, an independent replay of the executed
//!    timeline finds no two activities sharing a unit resource at once, no
//!    start while too few sequence engines were free, no dependency started early, no start outside the activity's windows or
//!    before its required states hold, at most one member of a group run, and
//!    each started activity dispatched by exactly one cycle.
//! 3. Scenarios: an optional activity aborted; a mandatory one running long and
//!    pushing a later optional one out; a shorter drive letting optional science
//!    in; a replan period against replanning on every end.
#![allow(clippy::panic, clippy::unwrap_used, clippy::expect_used)]

#[path = "gen/mod.rs"]
mod plangen;

use std::collections::BTreeMap;

use proptest::option;
use proptest::prelude::*;
use serde_json::{Value, json};
use solscope_engine::{
    ACTUALS_FORMAT, Actuals, AwakeMode, Event, ExecuteOptions, Execution, Guard, Plan, Policy,
    RunOutcome, Trigger, ViolationKind, execute, execute_with, load_plan,
};

fn load(v: &Value) -> Plan {
    load_plan(&v.to_string()).expect("valid plan").plan
}

fn actuals(durations: &[(&str, i64)]) -> Actuals {
    Actuals {
        format: ACTUALS_FORMAT.into(),
        durations: durations
            .iter()
            .map(|(id, d)| ((*id).to_string(), *d))
            .collect(),
    }
}

/// Whether the first cycle's schedule keeps the handover limits.
fn keeps_handover(plan: &Plan, ex: &Execution) -> bool {
    let sched = ex.cycle_plan(plan, 0).unwrap().schedule().unwrap();
    let p = &sched.problem;
    let Some(ht) = p.handover_time else {
        return true;
    };
    let state = sched.state_after(sched.steps.len());
    let soc_ok = p.handover_soc.is_none_or(|m| state.soc.level_at(ht) >= m);
    let data_ok = p.handover_data.is_none_or(|m| state.produced <= m);
    soc_ok && data_ok
}

/// Whether every placement of `plan` only takes starts away from the others:
/// nothing gives charge, data room or peak power back (awake costs at least
/// asleep, no negative rates), and no activity changes a state, heats a zone or
/// opens an awake period another could use. Only then does a past placement of a lower-priority
/// activity, which the later cycles see in the real state, never help a
/// higher-priority one to an earlier start (docs/semantics.md, "Execution").
///
/// Nor may an activity depend on one later in step order: it fails in the
/// first cycle, but once that one has run, a later cycle finds the dependency
/// met (the spec: ended activities satisfy dependencies).
fn only_restrictive(plan: &Plan) -> bool {
    let step_key = |id: &str| {
        plan.activities
            .iter()
            .enumerate()
            .find(|(_, a)| a.id == id)
            .map(|(i, a)| (a.priority, i))
    };
    let deps_forward = plan.activities.iter().enumerate().all(|(i, a)| {
        a.after
            .iter()
            .all(|d| step_key(&d.activity).is_some_and(|k| k < (a.priority, i)))
    });
    deps_forward
        && plan.power.awake >= plan.power.asleep
        && plan.activities.iter().all(|a| {
            a.energy_rate >= 0.0
                && a.peak_power >= 0.0
                && a.data_rate >= 0.0
                && a.effects.is_empty()
                && a.thermal_zones.is_empty()
                && a.awake != AwakeMode::Required
        })
}

/// A random plan moved into the claim's domain ([`only_restrictive`]): rates
/// made non-negative, awake no cheaper than asleep, `awake: required` made
/// `any`, no effects or zones, dependencies only on earlier steps. Everything
/// else (windows, resources, engines, groups, UHF, manual sleeps, limits) stays.
fn into_domain(text: &str) -> String {
    let mut v: Value = serde_json::from_str(text).expect("generated JSON");
    let asleep = v["power"]["asleep"].as_f64().unwrap_or(0.0);
    let awake = v["power"]["awake"].as_f64().unwrap_or(0.0);
    v["power"]["awake"] = json!(awake.max(asleep));
    let acts = v["activities"].as_array().cloned().unwrap_or_default();
    let key = |a: &Value, i: usize| (a["priority"].as_i64().unwrap_or(0), i);
    let keys: BTreeMap<String, (i64, usize)> = acts
        .iter()
        .enumerate()
        .map(|(i, a)| (a["id"].as_str().unwrap_or("").to_string(), key(a, i)))
        .collect();
    let mut out = Vec::new();
    for (i, mut a) in acts.into_iter().enumerate() {
        let me = key(&a, i);
        let o = a.as_object_mut().expect("activity object");
        for rate in ["energy_rate", "peak_power", "data_rate"] {
            if let Some(x) = o.get(rate).and_then(Value::as_f64) {
                o.insert(rate.into(), json!(x.abs()));
            }
        }
        if o.get("awake")
            .and_then(Value::as_str)
            .is_none_or(|m| m == "required")
        {
            o.insert("awake".into(), json!("any"));
        }
        o.remove("effects");
        o.remove("thermal_zones");
        if let Some(Value::Array(deps)) = o.get_mut("after") {
            deps.retain(|d| {
                d["activity"]
                    .as_str()
                    .and_then(|id| keys.get(id))
                    .is_some_and(|k| *k < me)
            });
        }
        out.push(a);
    }
    v["activities"] = json!(out);
    v.to_string()
}

/// `Ok(false)`: the plan is outside the domain where the claim holds.
fn nominal_matches_first_cycle(text: &str) -> Result<bool, String> {
    let plan = load_plan(text).map_err(|e| e.to_string())?.plan;
    if !only_restrictive(&plan) {
        return Err("into_domain left the claim's domain".into());
    }
    let ex = execute(&plan, &Actuals::nominal()).map_err(|e| e.to_string())?;
    if !keeps_handover(&plan, &ex) {
        return Ok(false);
    }
    for (a, run) in ex.activities.iter().enumerate() {
        let id = &plan.activities[a].id;
        match (run.predicted, run.actual) {
            (Some(p), Some(x)) if p == x => {}
            (None, None) => {}
            (p, x) => {
                return Err(format!(
                    "{id}: first cycle placed it at {p:?}, it ran at {x:?}"
                ));
            }
        }
        let want = if run.predicted.is_some() {
            RunOutcome::Completed
        } else {
            RunOutcome::NotRun
        };
        if run.outcome != want {
            return Err(format!("{id}: {:?}, expected {want:?}", run.outcome));
        }
    }
    // The executed profile is the predicted one: the same lowest state of charge,
    // and a limit broken exactly when the prediction breaks it (the rover's own
    // draw can, with nothing placed).
    let sched = ex.cycle_plan(&plan, 0).unwrap().schedule().unwrap();
    let state = sched.state_after(sched.steps.len());
    let p = &sched.problem;
    let lowest = state
        .soc
        .profile()
        .iter()
        .map(|&(_, v)| v)
        .min()
        .unwrap_or(p.soc0)
        .min(p.soc0);
    if ex.lowest_soc.0 != lowest {
        return Err(format!(
            "lowest state of charge: executed {:?}, predicted {lowest}",
            ex.lowest_soc
        ));
    }
    let mut expected = Vec::new();
    if lowest < p.min_soc {
        expected.push(ViolationKind::MinSoc);
    }
    if p.max_peak
        .is_some_and(|m| state.peak_max.is_some_and(|(v, _)| v > m))
    {
        expected.push(ViolationKind::MaxPeakPower);
    }
    let mut got: Vec<ViolationKind> = ex.violations.iter().map(|v| v.kind).collect();
    got.sort_by_key(|k| *k as u8);
    if got != expected {
        return Err(format!(
            "the prediction breaks {expected:?}, the execution reports {:?}",
            ex.violations
        ));
    }
    Ok(true)
}

/// The independent replay of an executed timeline.
fn replay_clean(plan: &Plan, ex: &Execution) -> Result<(), String> {
    let ran: Vec<(usize, i64, i64)> = ex
        .activities
        .iter()
        .enumerate()
        .filter_map(|(a, r)| r.actual.map(|(s, e)| (a, s, e)))
        .collect();
    let act = |a: usize| &plan.activities[a];
    for &(a, s, e) in &ran {
        let id = &act(a).id;
        if e <= s {
            return Err(format!("{id} ran over [{s}, {e})"));
        }
        // Unit resources: no overlap with another activity sharing one.
        for &(b, s2, e2) in &ran {
            if b != a
                && s < e2
                && s2 < e
                && act(a)
                    .resources
                    .iter()
                    .any(|r| act(b).resources.contains(r))
            {
                return Err(format!(
                    "{id} [{s},{e}) and {} [{s2},{e2}) share a resource",
                    act(b).id
                ));
            }
        }
        // Sequence engines: those of the activities running at its start plus
        // its own stay within the cap (engines are only taken at starts, so
        // every instant is checked).
        if let (Some(cap), true) = (plan.sequence_engines, act(a).sequence_engines > 0) {
            let held: u32 = ran
                .iter()
                .filter(|&&(b, s2, e2)| b != a && s2 <= s && s < e2)
                .map(|&(b, ..)| act(b).sequence_engines)
                .sum();
            if held + act(a).sequence_engines > cap {
                return Err(format!(
                    "{id} started at {s} needing {} engines while {held} of {cap} were held",
                    act(a).sequence_engines
                ));
            }
        }
        // Dependencies: the target ran and ended `min_delay` before.
        for d in &act(a).after {
            let Some(&(_, _, te)) = ran.iter().find(|x| act(x.0).id == d.activity) else {
                return Err(format!("{id} ran before its dependency {} ran", d.activity));
            };
            if s < te + d.min_delay.unwrap_or(0) {
                return Err(format!("{id} started at {s}, {} ended at {te}", d.activity));
            }
        }
        // Windows (the start range of one of them), or the horizon.
        let in_window = act(a)
            .windows
            .as_ref()
            .is_none_or(|ws| ws.iter().any(|w| w.start <= s && s <= w.end));
        if !in_window || s < plan.horizon.start {
            return Err(format!("{id} started at {s}, outside its windows"));
        }
        // Required states at the start, from the effects of what ran before.
        for req in &act(a).requires {
            let mut value = plan.states[&req.state].initial.clone();
            let mut changes: Vec<(i64, usize, String)> = Vec::new();
            for &(b, s2, e2) in &ran {
                for eff in act(b).effects.iter().filter(|f| f.state == req.state) {
                    let at = match eff.at {
                        solscope_engine::EffectAt::Start => s2,
                        solscope_engine::EffectAt::End => e2,
                    };
                    if at <= s && b != a {
                        changes.push((at, b, eff.value.clone()));
                    }
                }
            }
            changes.sort();
            if let Some(last) = changes.last() {
                // Effects at one instant: the last dispatched wins; a test plan
                // with two at once is checked only when they agree.
                let same_time: Vec<&String> = changes
                    .iter()
                    .filter(|c| c.0 == last.0)
                    .map(|c| &c.2)
                    .collect();
                if same_time.iter().any(|v| *v != same_time[0]) {
                    continue;
                }
                value = last.2.clone();
            }
            if value != req.value {
                return Err(format!(
                    "{id} started at {s} with {} = {value}, it requires {}",
                    req.state, req.value
                ));
            }
        }
        // Dispatched by exactly one cycle, at its start.
        let started: Vec<(usize, i64)> = ex
            .cycles
            .iter()
            .enumerate()
            .flat_map(|(k, c)| {
                c.events.iter().filter_map(move |e| match *e {
                    Event::Started { activity, time } if activity == a => Some((k, time)),
                    _ => None,
                })
            })
            .collect();
        if started != [(ex.activities[a].cycle.unwrap_or(usize::MAX), s)] {
            return Err(format!("{id}: dispatch events {started:?}"));
        }
    }
    // Groups: at most one member ran.
    let mut members: BTreeMap<&str, usize> = BTreeMap::new();
    for &(a, _, _) in &ran {
        if let Some(g) = &act(a).group {
            *members.entry(g).or_default() += 1;
        }
    }
    if let Some((g, n)) = members.into_iter().find(|&(_, n)| n > 1) {
        return Err(format!("{n} members of group {g} ran"));
    }
    Ok(())
}

/// Random actual durations (half to twice `duration`) for the fixed-duration
/// activities of `plan`.
fn random_actuals(plan: &Plan, factors: &[u32]) -> Actuals {
    let mut durations = BTreeMap::new();
    for (a, f) in plan.activities.iter().zip(factors.iter().cycle()) {
        if let solscope_engine::Duration::Fixed(d) = a.duration {
            let actual = (d * i64::from(*f) / 100).max(1);
            durations.insert(a.id.clone(), actual);
        }
    }
    Actuals {
        format: ACTUALS_FORMAT.into(),
        durations,
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 384,
        failure_persistence: None,
        // Plans outside the nominal claim's domain are rejected, not passed.
        max_global_rejects: 20_000,
        ..ProptestConfig::default()
    })]

    #[test]
    fn nominal_execution_follows_the_first_cycle(text in plangen::plan_text()) {
        let text = into_domain(&text);
        match nominal_matches_first_cycle(&text) {
            Ok(checked) => prop_assume!(checked),
            Err(e) => return Err(TestCaseError::fail(format!("{e}\nplan: {text}"))),
        }
    }

    #[test]
    fn executed_timeline_replays_clean(
        text in plangen::plan_text(),
        factors in proptest::collection::vec(50u32..=200, 1..8),
    ) {
        let plan = load_plan(&text).map_err(|e| TestCaseError::fail(e.to_string()))?.plan;
        let acts = random_actuals(&plan, &factors);
        let ex = execute(&plan, &acts).map_err(|e| TestCaseError::fail(e.to_string()))?;
        if let Err(e) = replay_clean(&plan, &ex) {
            return Err(TestCaseError::fail(format!("{e}\nactuals: {:?}\nplan: {text}", acts.durations)));
        }
        // Deterministic: the same inputs give the same execution.
        let again = execute(&plan, &acts).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(&again.activities, &ex.activities);
        prop_assert_eq!(&again.profile, &ex.profile);
    }
}

/// A plan of sequences competing for `cap` sequence engines: activity `i` has
/// `(duration, engines, mandatory, window start)`; cycles every `period` (if
/// any) and on every end.
fn engine_plan(cap: u32, acts: &[(i64, u32, bool, i64)], period: Option<i64>) -> Plan {
    let activities: Vec<Value> = acts
        .iter()
        .enumerate()
        .map(|(i, &(d, e, mandatory, w))| {
            json!({ "id": format!("seq{i}"), "priority": i + 1, "duration": d,
                    "mandatory": mandatory, "sequence_engines": e,
                    "windows": [{ "start": w, "end": 4000 }] })
        })
        .collect();
    let mut plan = json!({
        "format": "solscope.plan/1",
        "horizon": { "start": 0, "end": 6000 },
        "battery": { "capacity": 2000.0, "initial": 1500.0, "min_soc": 100.0 },
        "power": { "rtg": 110.0, "asleep": 25.0, "awake": 50.0 },
        "sequence_engines": cap,
        "activities": activities,
    });
    if let Some(p) = period {
        plan["execution"] = json!({ "replan_period": p });
    }
    load(&plan)
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 256,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Sequences that run long keep their engines: nothing starts on an engine
    /// still held, under any policy, and a limit broken is still reported.
    #[test]
    fn a_sequence_running_long_keeps_its_engines(
        cap in 1u32..=3,
        acts in proptest::collection::vec((20i64..400, 0u32..=3, prop::bool::ANY, 0i64..600), 2..9),
        factors in proptest::collection::vec(50u32..=250, 1..9),
        period in option::of(30i64..500),
    ) {
        let acts: Vec<_> = acts.into_iter().map(|(d, e, m, w)| (d, e.min(cap), m, w)).collect();
        let plan = engine_plan(cap, &acts, period);
        let actuals = random_actuals(&plan, &factors);
        for policy in [Policy::Replan, Policy::Fixed, Policy::Dispatch] {
            let options = ExecuteOptions { policy };
            let ex = execute_with(&plan, &actuals, options)
                .map_err(|e| TestCaseError::fail(e.to_string()))?;
            if let Err(e) = replay_clean(&plan, &ex) {
                return Err(TestCaseError::fail(format!("{policy:?}: {e}\nactuals: {:?}", actuals.durations)));
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 96,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// A cycle keeps only what it placed and what not; its plan, rebuilt from
    /// the execution, schedules to exactly that (debug builds also compare
    /// every rebuilt plan with the one the cycle scheduled), the first cycle's
    /// placements are the predictions, and an activity that never started is
    /// in every cycle's plan up to the last that had it (what the loss
    /// explanations rely on), and in none after.
    #[test]
    fn cycle_plans_rebuilt_schedule_to_what_the_cycles_kept(
        text in plangen::plan_text(),
        factors in proptest::collection::vec(50u32..=200, 1..8),
    ) {
        let plan = load_plan(&text).map_err(|e| TestCaseError::fail(e.to_string()))?.plan;
        let acts = random_actuals(&plan, &factors);
        let ex = execute(&plan, &acts).map_err(|e| TestCaseError::fail(e.to_string()))?;
        for (k, c) in ex.cycles.iter().enumerate() {
            let cp = ex.cycle_plan(&plan, k).ok_or_else(|| TestCaseError::fail("no cycle plan"))?;
            prop_assert_eq!(cp.plan.horizon.start, c.time);
            let sched = cp.schedule().map_err(|e| TestCaseError::fail(e.to_string()))?;
            let failed: Vec<usize> = (0..cp.activity_of.len())
                .filter(|&i| sched.placement(i).is_none())
                .map(|i| cp.activity_of[i])
                .collect();
            prop_assert_eq!(c.failed(), &failed[..], "cycle {}", k);
            prop_assert_eq!(c.placed(), cp.activity_of.len() - failed.len());
            if k == 0 {
                for (a, run) in ex.activities.iter().enumerate() {
                    let predicted = cp.index_of(a).and_then(|i| sched.placement(i));
                    prop_assert_eq!(run.predicted, predicted);
                }
            }
            for (a, run) in ex.activities.iter().enumerate() {
                if let (None, Some(last)) = (run.actual, run.last_cycle) {
                    prop_assert_eq!(cp.index_of(a).is_some(), k <= last, "cycle {} activity {}", k, a);
                }
            }
        }
        solscope_engine::losses(&plan, &ex).map_err(|e| TestCaseError::fail(e.to_string()))?;
    }
}

#[test]
fn a_mandatory_sequence_running_long_holds_the_next_one_back() {
    // One engine: seq1 is placed after seq0's predicted end, and seq0 runs long.
    let plan = engine_plan(1, &[(300, 1, true, 0), (200, 1, true, 0)], None);
    let ex = execute(&plan, &actuals(&[("seq0", 500)])).unwrap();
    let first = &ex.cycles[0];
    assert_eq!(ex.activities[0].predicted, Some((0, 300)));
    assert_eq!(ex.activities[1].predicted, Some((300, 500)));
    // Due at 300 while seq0 still holds the engine: held back, and started by
    // the cycle at seq0's actual end.
    assert!(first.events.contains(&Event::Held {
        activity: 1,
        time: 300,
        guard: Guard::Engines(0),
    }));
    assert_eq!(ex.activities[0].actual, Some((0, 500)));
    assert_eq!(ex.activities[1].actual, Some((500, 700)));
    assert_eq!(ex.cycles[1].trigger, Trigger::End(0));
    // Engines 0 use none: they start whatever is held.
    let free = engine_plan(1, &[(300, 1, true, 0), (200, 0, true, 0)], None);
    let ex = execute(&free, &actuals(&[("seq0", 500)])).unwrap();
    assert_eq!(ex.activities[1].actual, Some((0, 200)));
}

/// A one-sol-fragment plan: a drive, then science that depends on it.
fn drive_plan(extra: Value) -> Value {
    let mut plan = json!({
        "format": "solscope.plan/1",
        "horizon": { "start": 0, "end": 20000 },
        "battery": { "capacity": 2000.0, "initial": 1500.0, "min_soc": 500.0 },
        "power": { "rtg": 110.0, "asleep": 25.0, "awake": 150.0 },
        "activities": [
            { "id": "drive", "priority": 1, "duration": 3600,
              "duration_model": { "min": 2400, "max": 6000 },
              "windows": [{ "start": 1000, "end": 1000 }],
              "resources": ["mobility"], "energy_rate": 150.0 },
            { "id": "science", "priority": 2, "mandatory": false, "duration": 1800,
              "windows": [{ "start": 4600, "end": 7000, "cutoff": 8000 }],
              "resources": ["arm"], "after": [{ "activity": "drive" }],
              "energy_rate": 40.0 }
        ]
    });
    if let (Some(p), Some(e)) = (plan.as_object_mut(), extra.as_object()) {
        for (k, v) in e {
            p.insert(k.clone(), v.clone());
        }
    }
    plan
}

#[test]
fn an_optional_activity_running_long_is_aborted() {
    let plan = load(&drive_plan(json!({})));
    let ex = execute(&plan, &actuals(&[("science", 2500)])).unwrap();
    let science = ex.activities[1];
    assert_eq!(science.outcome, RunOutcome::Aborted);
    assert_eq!(
        science.actual,
        Some((4600, 6400)),
        "stopped at start + duration"
    );
    // A mandatory one runs to its end.
    let ex = execute(&plan, &actuals(&[("drive", 4000)])).unwrap();
    assert_eq!(ex.activities[0].outcome, RunOutcome::Completed);
    assert_eq!(ex.activities[0].actual, Some((1000, 5000)));
}

#[test]
fn a_long_drive_pushes_optional_science_out() {
    let plan = load(&drive_plan(json!({})));
    // Nominal: the drive ends at 4600 and science starts right after it.
    let ex = execute(&plan, &Actuals::nominal()).unwrap();
    assert_eq!(ex.activities[1].actual, Some((4600, 6400)));
    // 6000 s: the drive ends at 7000; the science window's last start is 7000 but
    // 7000 + 1800 passes its cutoff 8000, so no cycle can place it again.
    let ex = execute(&plan, &actuals(&[("drive", 6000)])).unwrap();
    assert_eq!(ex.activities[0].actual, Some((1000, 7000)));
    assert_eq!(ex.activities[1].outcome, RunOutcome::NotRun);
    assert!(ex.activities[1].last_cycle.is_some());
    // The cycle at the drive's end (7000) is the last one that had it, and it
    // failed there.
    let last = &ex.cycles[ex.activities[1].last_cycle.unwrap()];
    assert_eq!(last.time, 7000);
    assert_eq!(last.trigger, Trigger::End(0));
    assert!(last.did_not_place(1));
    let cycle_plan = ex
        .cycle_plan(&plan, ex.activities[1].last_cycle.unwrap())
        .unwrap();
    let i = cycle_plan.index_of(1).unwrap();
    let sched = cycle_plan.schedule().unwrap();
    assert_eq!(sched.placement(i), None, "the trace agrees");
    // 5000 s: the drive ends at 6000, science starts then (1800 s, ends 7800).
    let ex = execute(&plan, &actuals(&[("drive", 5000)])).unwrap();
    assert_eq!(ex.activities[1].actual, Some((6000, 7800)));
    assert_eq!(ex.activities[1].outcome, RunOutcome::Completed);
}

#[test]
fn a_short_drive_lets_optional_science_in() {
    // Science needs the battery the drive leaves: with the nominal drive the
    // first cycle cannot fit it; with a short drive the cycle at the drive's end
    // sees more charge and places it.
    let mut doc = drive_plan(json!({
        "battery": { "capacity": 2000.0, "initial": 700.0, "min_soc": 500.0 }
    }));
    doc["activities"][1]["energy_rate"] = json!(120.0);
    let plan = load(&doc);
    let ex = execute(&plan, &Actuals::nominal()).unwrap();
    assert_eq!(ex.activities[0].outcome, RunOutcome::Completed);
    assert_eq!(
        ex.activities[1].predicted, None,
        "the first cycle cannot fit it"
    );
    assert_eq!(ex.activities[1].outcome, RunOutcome::NotRun);
    let ex = execute(&plan, &actuals(&[("drive", 2400)])).unwrap();
    assert_eq!(ex.activities[0].actual, Some((1000, 3400)));
    assert_eq!(ex.activities[1].predicted, None);
    assert_eq!(ex.activities[1].outcome, RunOutcome::Completed);
    assert_eq!(ex.activities[1].actual, Some((4600, 6400)));
    assert!(ex.violations.is_empty(), "{:?}", ex.violations);
}

#[test]
fn replan_period_against_replan_on_end() {
    // Replanning only every 3000 s: the drive ends at 3400 but science (due after
    // it) waits for the cycle at 6000, which places it at 6000.
    let periodic = load(&drive_plan(json!({
        "execution": { "replan_period": 3000, "replan_on_end": false }
    })));
    let ex = execute(&periodic, &actuals(&[("drive", 2400)])).unwrap();
    let times: Vec<i64> = ex.cycles.iter().map(|c| c.time).collect();
    assert_eq!(times, [0, 3000, 6000, 9000, 12000, 15000, 18000]);
    assert!(
        ex.cycles
            .iter()
            .skip(1)
            .all(|c| c.trigger == Trigger::Period)
    );
    assert_eq!(ex.activities[1].actual, Some((4600, 6400)));
    // With a long drive the science due at 4600 is held back by the guard (the
    // drive is still running) and waits for the cycle at 6000.
    let ex = execute(&periodic, &actuals(&[("drive", 4500)])).unwrap();
    let held = ex.cycles[1].events.iter().any(|e| {
        matches!(
            e,
            Event::Held {
                activity: 1,
                time: 4600,
                ..
            }
        )
    });
    assert!(held, "{:?}", ex.cycles[1].events);
    assert_eq!(ex.activities[1].actual, Some((6000, 7800)));
    // Replanning on every end instead: a cycle at the drive's end (5500) starts
    // science at once.
    let on_end = load(&drive_plan(
        json!({ "execution": { "replan_on_end": true } }),
    ));
    let ex = execute(&on_end, &actuals(&[("drive", 4500)])).unwrap();
    let times: Vec<i64> = ex.cycles.iter().map(|c| c.time).collect();
    assert_eq!(times, [0, 5500, 7300]);
    assert_eq!(ex.cycles[1].trigger, Trigger::End(0));
    assert_eq!(ex.activities[1].actual, Some((5500, 7300)));
}

#[test]
fn a_mandatory_overrun_below_min_soc_is_reported() {
    let plan = load(&drive_plan(json!({
        "battery": { "capacity": 2000.0, "initial": 760.0, "min_soc": 500.0 }
    })));
    // Nominal: 3600 s at 150 W + awake base; the first cycle fits it.
    let ex = execute(&plan, &Actuals::nominal()).unwrap();
    assert!(ex.violations.is_empty(), "{:?}", ex.violations);
    // Twice as long: the battery goes below min_soc while the drive runs.
    let ex = execute(&plan, &actuals(&[("drive", 6000)])).unwrap();
    let v = ex
        .violations
        .iter()
        .find(|v| v.kind == ViolationKind::MinSoc)
        .expect("a min_soc violation");
    assert!(v.time > 1000 && v.time < 7000, "{v:?}");
    assert!(v.worst.0 < v.limit);
    assert!(ex.lowest_soc.0 < v.limit);
}

#[test]
fn a_cycle_plan_keeps_its_starting_state_through_edits_and_suggestions() {
    let plan = load(&drive_plan(json!({})));
    let ex = execute(&plan, &actuals(&[("drive", 6000)])).unwrap();
    // The cycle at the drive's end, where the science fails.
    let k = ex.activities[1].last_cycle.unwrap();
    let cycle_plan = ex.cycle_plan(&plan, k).unwrap().plan;
    let start = cycle_plan.cycle.clone().expect("a cycle's starting state");
    let mut set = serde_json::Map::new();
    set.insert(
        "battery".into(),
        serde_json::to_value(cycle_plan.battery).unwrap(),
    );
    let edited = solscope_engine::apply_edit(&cycle_plan, "plan", &set).unwrap();
    assert_eq!(edited.cycle.as_ref(), Some(&start));
    // The explainer's suggestions are verified by rescheduling edited cycle
    // plans (debug builds compare its quick edits with apply_edit).
    let sched = solscope_engine::schedule(&cycle_plan).unwrap();
    let opts = solscope_engine::ExplainOptions {
        activity: Some("science".into()),
        no_suggestions: false,
    };
    let explanations = solscope_engine::explain(&cycle_plan, &sched, &opts).unwrap();
    assert_eq!(explanations.len(), 1);
    assert!(explanations[0].phase.is_some());
    // A phase-2 (energy) failure: its plan-wide relaxations are edits of the
    // cycle plan's battery, re-read without the activities.
    let mut doc = drive_plan(json!({
        "battery": { "capacity": 2000.0, "initial": 700.0, "min_soc": 500.0 }
    }));
    doc["activities"][1]["energy_rate"] = json!(120.0);
    let plan = load(&doc);
    let ex = execute(&plan, &Actuals::nominal()).unwrap();
    let cycle_plan = ex.cycle_plan(&plan, 0).unwrap().plan;
    let sched = solscope_engine::schedule(&cycle_plan).unwrap();
    let explanations = solscope_engine::explain(&cycle_plan, &sched, &opts).unwrap();
    let suggestions = &explanations[0].suggestions;
    assert!(
        suggestions.iter().any(|s| s.target == "plan"),
        "a plan-wide relaxation among {suggestions:?}"
    );
}

/// A regression found by `executed_timeline_replays_clean`: a preheat running
/// when a cycle starts serves its activity at its planned start only, and the
/// phase-2 search must treat that start as a cell of its own (debug builds
/// compare the search with the ideal placement's point check).
#[test]
fn a_running_preheat_serves_its_activity_at_its_planned_start() {
    let text = r#"{"activities": [{"duration": 30, "id": "a0", "mandatory": false, "priority": 0}, {"duration": 30, "id": "a1", "mandatory": false, "priority": 0}, {"duration": 63, "id": "a2", "mandatory": false, "priority": 0}, {"duration": 30, "id": "a3", "mandatory": false, "priority": 0}, {"duration": 155, "id": "a4", "mandatory": false, "priority": 0, "thermal_zones": ["z0"], "windows": [{"end": 837, "preferred": 589, "start": 425}]}, {"duration": 30, "id": "a5", "mandatory": false, "priority": 0}, {"duration": 44, "id": "a6", "mandatory": false, "priority": 0, "windows": [{"end": 538, "start": 538}]}, {"duration": 30, "id": "a7", "mandatory": false, "priority": 0}], "battery": {"capacity": 10.0, "initial": 0.5, "min_soc": 0.0}, "format": "solscope.plan/1", "horizon": {"end": 931, "start": 0}, "name": "generated", "power": {"asleep": 2.0, "awake": 7.0, "rtg": 34.0}, "sleep": {"min_awake": 1, "min_sleep": 0, "shutdown_duration": 0, "wakeup_duration": 0}, "thermal_zones": {"z0": {"maintenance_power": 0.0, "preheat": [{"duration": 22, "from": 0}], "preheat_power": 0.0}}}"#;
    let plan = load_plan(text).unwrap().plan;
    let acts = random_actuals(&plan, &[69, 134, 124, 69, 105, 130]);
    let ex = execute(&plan, &acts).unwrap();
    replay_clean(&plan, &ex).unwrap();
}
