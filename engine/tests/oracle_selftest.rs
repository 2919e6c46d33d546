//! Hand-made cases proving the oracle before it judges the scheduler.
//!
//! Every expected schedule below was worked out by hand from docs/semantics.md
//! (derivations in the comments). The oracle must accept it, and reject each
//! deliberately wrong variant with the expected kind of message. Finally the oracle's
//! fast resource checks are cross-checked against the naive full re-simulation on
//! generated plans (paranoid mode).
#![allow(clippy::panic, clippy::unwrap_used, clippy::expect_used)]

mod oracle;
#[path = "gen/mod.rs"]
mod plangen;

use proptest::prelude::*;
use serde_json::{Value, json};
use solscope_engine::Plan;

use oracle::Options;

const PARANOID: Options = Options { paranoid: true };

fn plan(v: Value) -> Plan {
    match solscope_engine::load_plan(&v.to_string()) {
        Ok(l) => l.plan,
        Err(e) => panic!("hand-made plan rejected by load_plan: {e}"),
    }
}

fn wh(mj: f64) -> f64 {
    mj / 3.6e6
}

/// The document must be accepted by replay (paranoid), check_valid, and equal
/// what the oracle itself produces (activities and generated).
fn accept(p: &Plan, doc: &Value) {
    if let Err(e) = oracle::replay_with(p, doc, PARANOID) {
        panic!("oracle rejected the hand-made schedule: {e}");
    }
    if let Err(e) = oracle::check_valid(p, doc) {
        panic!("check_valid rejected the hand-made schedule: {e}");
    }
    let own = match oracle::solve(p, PARANOID) {
        Ok(v) => v,
        Err(e) => panic!("solve failed: {e}"),
    };
    assert_eq!(own["activities"], doc["activities"]);
    if let Err(e) = oracle::replay_with(p, &own, PARANOID) {
        panic!("oracle rejected its own schedule: {e}");
    }
    if let Err(e) = oracle::check_generated_order(&own) {
        panic!("{e}");
    }
}

fn set(doc: &Value, ptr: &str, v: Value) -> Value {
    let mut d = doc.clone();
    match d.pointer_mut(ptr) {
        Some(slot) => *slot = v,
        None => panic!("no {ptr} in {doc}"),
    }
    d
}

fn reject(p: &Plan, doc: &Value, needle: &str) {
    match oracle::replay(p, doc) {
        Ok(()) => panic!("oracle accepted a wrong schedule (expected `{needle}`): {doc}"),
        Err(e) => assert!(e.contains(needle), "message lacks `{needle}`: {e}"),
    }
}

fn reject_valid(p: &Plan, doc: &Value, needle: &str) {
    match oracle::check_valid(p, doc) {
        Ok(()) => panic!("check_valid accepted an invalid schedule (expected `{needle}`): {doc}"),
        Err(e) => assert!(e.contains(needle), "message lacks `{needle}`: {e}"),
    }
}

fn valid_ok(p: &Plan, doc: &Value) {
    if let Err(e) = oracle::check_valid(p, doc) {
        panic!("check_valid rejected a valid (if suboptimal) schedule: {e}");
    }
}

fn doc(acts: Value, generated: Value, soc: Value, peak: Value, data: Value) -> Value {
    json!({"format": "solscope.schedule/1", "plan": "t", "activities": acts, "generated": generated,
           "warnings": [], "profiles": {"soc": soc, "peak_power": peak, "data_volume": data}})
}

fn sched(id: &str, step: usize, s: i64, e: i64) -> Value {
    json!({"id": id, "status": "scheduled", "step": step, "start": s, "end": e})
}

fn failed(id: &str, step: usize) -> Value {
    json!({"id": id, "status": "failed", "step": step})
}

fn skipped(id: &str, step: usize) -> Value {
    json!({"id": id, "status": "skipped", "step": step})
}

fn awake(s: i64, e: i64, step: usize) -> Value {
    json!({"kind": "awake", "start": s, "end": e, "step": step})
}

fn heat(kind: &str, zone: &str, for_: &str, s: i64, e: i64, power: f64, step: usize) -> Value {
    json!({"kind": kind, "zone": zone, "for": for_, "start": s, "end": e, "power": power, "step": step})
}

#[test]
fn pitfall() {
    // A (step 1) is awake-required, W = S = 0, min_awake 0: need [0, 600) -> awake
    // [0, 600). B's only start 0 overlaps A on `arm`: failed.
    // SOC (mJ): 900 Wh = 3.24e9; [0,600) rate 100-60-20 = +20 W -> 3.252e9 at 600;
    // then +90 W; cap 3.6e9 needs 348e6/90e3 = 3866.67 s: 3.59994e9 at 4466, cap at 4467.
    let p = plan(json!({
        "format": "solscope.plan/1", "horizon": {"start": 0, "end": 7200},
        "battery": {"capacity": 1000.0, "initial": 900.0, "min_soc": 100.0},
        "power": {"rtg": 100.0, "asleep": 10.0, "awake": 60.0},
        "activities": [
            {"id": "A", "priority": 1, "duration": 600, "resources": ["arm"], "energy_rate": 20.0},
            {"id": "B", "priority": 2, "duration": 600, "resources": ["arm"], "energy_rate": 20.0,
             "windows": [{"start": 0, "end": 0}]}
        ]
    }));
    let good = doc(
        json!([sched("A", 1, 0, 600), failed("B", 2)]),
        json!([awake(0, 600, 1)]),
        json!([
            [0, 900.0],
            [600, wh(3.252e9)],
            [4466, wh(3.59994e9)],
            [4467, 1000.0],
            [7200, 1000.0]
        ]),
        json!([[0, 60.0], [600, 10.0], [7200, 10.0]]),
        json!([[0, 0.0], [7200, 0.0]]),
    );
    accept(&p, &good);
    // A later start: feasible but not nearest to preferred 0.
    let late = set(
        &set(&good, "/activities/0/start", json!(10)),
        "/activities/0/end",
        json!(610),
    );
    reject(&p, &late, "choice rule prefers");
    reject(&p, &late, "expected scheduled at [0, 600)");
    // B placed overlapping A on the arm.
    let b = set(&good, "/activities/1", sched("B", 2, 0, 600));
    reject(&p, &b, "unit_resource");
    reject_valid(&p, &b, "unit_resource");
    // A failed although feasible.
    let a_failed = set(&good, "/activities/0", failed("A", 1));
    reject(&p, &a_failed, "the scheduler missed it");
    // Missing awake period.
    reject(
        &p,
        &set(&good, "/generated", json!([])),
        "generated activities differ",
    );
    // Awake period with the wrong step.
    reject(
        &p,
        &set(&good, "/generated/0/step", json!(2)),
        "generated activities differ",
    );
    // A wrong SOC breakpoint.
    reject(
        &p,
        &set(&good, "/profiles/soc/1/1", json!(903.0)),
        "profiles.soc",
    );
    // Missing the capacity breakpoint (linear 600 -> 7200 is wrong in between).
    let no_cap = set(
        &good,
        "/profiles/soc",
        json!([[0, 900.0], [600, wh(3.252e9)], [7200, 1000.0]]),
    );
    reject(&p, &no_cap, "profiles.soc");
    reject(
        &p,
        &set(&good, "/profiles/peak_power/1/1", json!(60.0)),
        "profiles.peak_power",
    );
    reject(
        &p,
        &set(&good, "/profiles/data_volume/1/0", json!(7000)),
        "profiles.data_volume",
    );
    reject(
        &p,
        &set(&good, "/activities/1/id", json!("A")),
        "schedule lists",
    );
}

#[test]
fn min_soc_delays_start() {
    // E(0) = 2 Wh = 7.2e6 mJ, asleep net +10 W. X (any) nets 20-10-36 = -26 W for
    // 200 s = -5.2e6 mJ. E(s) - 5.2e6 >= 3.6e6 (min 1 Wh) <=> 7.2e6 + 1e4 s >= 8.8e6
    // <=> s >= 160. X at 160; E(360) = 3.6e6 = min exactly; cap 36e6 at 360 + 3240.
    let p = plan(json!({
        "format": "solscope.plan/1", "horizon": {"start": 0, "end": 4000},
        "battery": {"capacity": 10.0, "initial": 2.0, "min_soc": 1.0},
        "power": {"rtg": 20.0, "asleep": 10.0, "awake": 20.0},
        "activities": [
            {"id": "X", "priority": 1, "duration": 200, "awake": "any", "energy_rate": 36.0,
             "windows": [{"start": 0, "end": 3600}]}
        ]
    }));
    let good = doc(
        json!([sched("X", 1, 160, 360)]),
        json!([]),
        json!([
            [0, 2.0],
            [160, wh(8.8e6)],
            [360, 1.0],
            [3600, 10.0],
            [4000, 10.0]
        ]),
        json!([[0, 10.0], [4000, 10.0]]),
        json!([[0, 0.0], [4000, 0.0]]),
    );
    accept(&p, &good);
    let at0 = set(
        &set(&good, "/activities/0/start", json!(0)),
        "/activities/0/end",
        json!(200),
    );
    reject(&p, &at0, "min_soc");
    reject_valid(&p, &at0, "min_soc");
    let at161 = set(
        &set(&good, "/activities/0/start", json!(161)),
        "/activities/0/end",
        json!(361),
    );
    reject(&p, &at161, "choice rule prefers");
    valid_ok(&p, &at161);
    let at159 = set(
        &set(&good, "/activities/0/start", json!(159)),
        "/activities/0/end",
        json!(359),
    );
    reject_valid(&p, &at159, "min_soc");
}

#[test]
fn preheat_operability_min_awake_and_heater_on() {
    // H: preheat table tod<1800 -> 300 s; operable [1000, 3000]; so s - 300 >= 1000:
    // H at 1300 (nearest to 500), preheat [1000,1300) 10 W, maintenance [1300,1500).
    // Need [1250,1550) (W = S = 50) shorter than min_awake 600 -> [1250,1850).
    // H2 (zone z, any) at 1500: the heater is on at 1499 (H's maintenance): no preheat.
    // Rates (W): [0,1000) -10, [1000,1250) -20, [1250,1300) -30, [1300,1600) -25,
    // [1600,1850) -20, then -10.  E (mJ): 180e6, 170e6, 165e6, 163.5e6, 156e6,
    // 151e6, 133.5e6.
    let p = plan(json!({
        "format": "solscope.plan/1", "horizon": {"start": 0, "end": 3600},
        "local_time": {"sol_length": 3600, "offset": 0},
        "battery": {"capacity": 100.0, "initial": 50.0, "min_soc": 0.0},
        "power": {"rtg": 0.0, "asleep": 10.0, "awake": 20.0},
        "sleep": {"wakeup_duration": 50, "shutdown_duration": 50, "min_awake": 600, "min_sleep": 0},
        "thermal_zones": {"z": {"preheat": [{"from": 0, "duration": 300}, {"from": 1800, "duration": 100}],
            "preheat_power": 10.0, "maintenance_power": 5.0, "operable": [{"from": 1000, "to": 3000}]}},
        "activities": [
            {"id": "H", "priority": 1, "duration": 200, "thermal_zones": ["z"],
             "windows": [{"start": 500, "end": 2500}]},
            {"id": "H2", "priority": 2, "duration": 100, "thermal_zones": ["z"], "awake": "any",
             "windows": [{"start": 1500, "end": 2000}]}
        ]
    }));
    let good = doc(
        json!([sched("H", 1, 1300, 1500), sched("H2", 2, 1500, 1600)]),
        json!([
            awake(1250, 1850, 1),
            heat("preheat", "z", "H", 1000, 1300, 10.0, 1),
            heat("maintenance", "z", "H", 1300, 1500, 5.0, 1),
            heat("maintenance", "z", "H2", 1500, 1600, 5.0, 2)
        ]),
        json!([
            [0, 50.0],
            [1000, wh(170e6)],
            [1250, wh(165e6)],
            [1300, wh(163.5e6)],
            [1600, wh(156e6)],
            [1850, wh(151e6)],
            [3600, wh(133.5e6)]
        ]),
        json!([
            [0, 10.0],
            [1000, 20.0],
            [1250, 30.0],
            [1300, 25.0],
            [1600, 20.0],
            [1850, 10.0],
            [3600, 10.0]
        ]),
        json!([[0, 0.0], [3600, 0.0]]),
    );
    accept(&p, &good);
    // Missing preheat.
    let g = good["generated"].as_array().cloned().unwrap_or_default();
    let mut no_preheat = good.clone();
    no_preheat["generated"] = json!([g[0], g[2], g[3]]);
    reject(
        &p,
        &no_preheat,
        "missing (expected, not in schedule): [\"preheat",
    );
    // A preheat for H2 although the heater is on.
    let mut extra = good.clone();
    extra["generated"] = json!([
        g[0],
        g[1],
        g[2],
        g[3],
        heat("preheat", "z", "H2", 1200, 1500, 10.0, 2)
    ]);
    reject(
        &p,
        &extra,
        "unexpected (in schedule): [\"preheat zone=z for=H2",
    );
    // Awake period too short (not extended to min_awake).
    reject(
        &p,
        &set(&good, "/generated/0/end", json!(1550)),
        "generated activities differ",
    );
    // H one second earlier: its preheat would start at local 999, not operable.
    let early = set(
        &set(&good, "/activities/0/start", json!(1299)),
        "/activities/0/end",
        json!(1499),
    );
    reject(&p, &early, "preheat_operability");
    reject_valid(&p, &early, "preheat_operability");
    // Wrong heater power.
    reject(
        &p,
        &set(&good, "/generated/1/power", json!(12.0)),
        "generated activities differ",
    );
    // Order check: heater entries before awake.
    let mut disorder = good.clone();
    disorder["generated"] = json!([g[1], g[0], g[2], g[3]]);
    assert!(oracle::check_generated_order(&disorder).is_err());
    assert!(oracle::check_generated_order(&good).is_ok());
}

#[test]
fn awake_merging_min_sleep_min_awake() {
    // min_sleep 500, min_awake 300, W = S = 0.
    // A [1000,1100): need extended to [1000,1300). B [1300,1400): gap 0 -> merged
    // [1000,1400) (step 2). C forbidden [1450,1550): no awake overlap.
    // D need [1600,1700): gap 200 < 500 -> Q1 [1000,1700) crosses C: min_sleep, failed.
    // E [2100,2200): gap 700, extended to [2100,2400). F [4900,5000): forward
    // extension passes the end -> backward [4700,5000). C2 forbidden [3700,3800).
    // G need [3500,3550) -> extended [3500,3800) overlaps C2: min_awake, failed.
    // SOC: +90 W asleep, +80 W awake, no cap: mJ 1.8e9, 1.89e9 (1000), 1.922e9
    // (1400), 1.985e9 (2100), 2.009e9 (2400), 2.216e9 (4700), 2.24e9 (5000).
    let any_act = |id: &str, prio: i64, d: i64, s: i64, mode: &str| {
        json!({"id": id, "priority": prio, "duration": d, "awake": mode, "sequence_engines": 0,
               "windows": [{"start": s, "end": s}]})
    };
    let p = plan(json!({
        "format": "solscope.plan/1", "horizon": {"start": 0, "end": 5000},
        "battery": {"capacity": 1000.0, "initial": 500.0, "min_soc": 0.0},
        "power": {"rtg": 100.0, "asleep": 10.0, "awake": 20.0},
        "sleep": {"min_awake": 300, "min_sleep": 500},
        "activities": [
            any_act("A", 1, 100, 1000, "required"), any_act("B", 2, 100, 1300, "required"),
            any_act("C", 3, 100, 1450, "forbidden"), any_act("D", 4, 100, 1600, "required"),
            any_act("E", 5, 100, 2100, "required"), any_act("F", 6, 100, 4900, "required"),
            any_act("C2", 7, 100, 3700, "forbidden"), any_act("G", 8, 50, 3500, "required")
        ]
    }));
    let good = doc(
        json!([
            sched("A", 1, 1000, 1100),
            sched("B", 2, 1300, 1400),
            sched("C", 3, 1450, 1550),
            failed("D", 4),
            sched("E", 5, 2100, 2200),
            sched("F", 6, 4900, 5000),
            sched("C2", 7, 3700, 3800),
            failed("G", 8)
        ]),
        json!([
            awake(1000, 1400, 2),
            awake(2100, 2400, 5),
            awake(4700, 5000, 6)
        ]),
        json!([
            [0, 500.0],
            [1000, wh(1.89e9)],
            [1400, wh(1.922e9)],
            [2100, wh(1.985e9)],
            [2400, wh(2.009e9)],
            [4700, wh(2.216e9)],
            [5000, wh(2.24e9)]
        ]),
        json!([
            [0, 10.0],
            [1000, 20.0],
            [1400, 10.0],
            [2100, 20.0],
            [2400, 10.0],
            [4700, 20.0],
            [5000, 20.0]
        ]),
        json!([[0, 0.0], [5000, 0.0]]),
    );
    accept(&p, &good);
    // Not merged.
    let mut unmerged = good.clone();
    unmerged["generated"] = json!([
        awake(1000, 1300, 1),
        awake(1300, 1400, 2),
        awake(2100, 2400, 5),
        awake(4700, 5000, 6)
    ]);
    reject(&p, &unmerged, "generated activities differ");
    let d = set(&good, "/activities/3", sched("D", 4, 1600, 1700));
    reject(&p, &d, "min_sleep");
    reject_valid(&p, &d, "min_sleep");
    let g = set(&good, "/activities/7", sched("G", 8, 3500, 3550));
    reject(&p, &g, "min_awake");
    reject_valid(&p, &g, "min_awake");
    reject(
        &p,
        &set(&good, "/generated/2/start", json!(4900)),
        "generated activities differ",
    );
}

#[test]
fn expanding_longest_duration() {
    // P holds r over [250,350). X in [0,100], 100..300: any d > 250 overlaps P, d = 250
    // fits only at s = 0. X2 50..80 in [400,500] pref 450 cutoff 520: d = 80, s <= 440.
    let p = plan(json!({
        "format": "solscope.plan/1", "horizon": {"start": 0, "end": 1000},
        "battery": {"capacity": 1000.0, "initial": 900.0, "min_soc": 0.0},
        "power": {"rtg": 100.0, "asleep": 0.0, "awake": 0.0},
        "activities": [
            {"id": "P", "priority": 1, "duration": 100, "awake": "any", "resources": ["r"],
             "windows": [{"start": 250, "end": 250}]},
            {"id": "X", "priority": 2, "duration": {"min": 100, "max": 300}, "awake": "any",
             "resources": ["r"], "windows": [{"start": 0, "end": 100}]},
            {"id": "X2", "priority": 3, "duration": {"min": 50, "max": 80}, "awake": "any",
             "resources": ["r"], "windows": [{"start": 400, "end": 500, "preferred": 450, "cutoff": 520}]}
        ]
    }));
    let good = doc(
        json!([
            sched("P", 1, 250, 350),
            sched("X", 2, 0, 250),
            sched("X2", 3, 440, 520)
        ]),
        json!([]),
        json!([[0, 900.0], [1000, wh(3.34e9)]]),
        json!([[0, 0.0], [1000, 0.0]]),
        json!([[0, 0.0], [1000, 0.0]]),
    );
    accept(&p, &good);
    let short = set(&good, "/activities/1/end", json!(200));
    reject(&p, &short, "duration 250 is feasible and longer than 200");
    valid_ok(&p, &short);
    let x2 = set(
        &set(&good, "/activities/2/start", json!(400)),
        "/activities/2/end",
        json!(480),
    );
    reject(&p, &x2, "preferred 450");
    let cut = set(
        &set(&good, "/activities/2/start", json!(450)),
        "/activities/2/end",
        json!(530),
    );
    reject_valid(&p, &cut, "execution");
    let too_long = set(&good, "/activities/1/end", json!(301));
    reject_valid(&p, &too_long, "duration 301 outside");
}

#[test]
fn states_dependencies_groups() {
    // A [200,300) sets s0=b at its end. B after A (min_delay 50), requires b: 350.
    // D requires a in [250,400]: a only before 300, so s + 100 <= 300 -> none: failed.
    // C after D: failed (dependency). G1 group g at 0; G2 skipped.
    // E sets a at its start, window [300,1000]: s < 450 changes what B sees in
    // [350,450) (at s = 300 its later step wins over A's effect): E at 450.
    // M meets E: 550. N after A with max_delay 10: [300,310], nearest 0 -> 300.
    let act = |id: &str, prio: i64, extra: Value| {
        let mut a = json!({"id": id, "priority": prio, "duration": 100, "awake": "any",
                           "sequence_engines": 0});
        if let (Some(obj), Some(ext)) = (a.as_object_mut(), extra.as_object()) {
            for (k, v) in ext {
                obj.insert(k.clone(), v.clone());
            }
        }
        a
    };
    let p = plan(json!({
        "format": "solscope.plan/1", "horizon": {"start": 0, "end": 2000},
        "battery": {"capacity": 1000.0, "initial": 900.0, "min_soc": 0.0},
        "power": {"rtg": 100.0, "asleep": 0.0, "awake": 0.0},
        "states": {"s0": {"values": ["a", "b"], "initial": "a"}},
        "activities": [
            act("A", 1, json!({"windows": [{"start": 200, "end": 500}],
                               "effects": [{"state": "s0", "value": "b", "at": "end"}]})),
            act("B", 2, json!({"after": [{"activity": "A", "min_delay": 50}],
                               "requires": [{"state": "s0", "value": "b"}]})),
            act("D", 3, json!({"requires": [{"state": "s0", "value": "a"}],
                               "windows": [{"start": 250, "end": 400}]})),
            act("C", 4, json!({"after": [{"activity": "D"}]})),
            act("G1", 5, json!({"group": "g"})),
            act("G2", 6, json!({"group": "g"})),
            act("E", 7, json!({"windows": [{"start": 300, "end": 1000}],
                               "effects": [{"state": "s0", "value": "a", "at": "start"}]})),
            act("M", 8, json!({"duration": 50, "after": [{"activity": "E", "meets": true}]})),
            act("N", 9, json!({"duration": 50, "after": [{"activity": "A", "max_delay": 10}]}))
        ]
    }));
    let good = doc(
        json!([
            sched("A", 1, 200, 300),
            sched("B", 2, 350, 450),
            failed("D", 3),
            failed("C", 4),
            sched("G1", 5, 0, 100),
            skipped("G2", 6),
            sched("E", 7, 450, 550),
            sched("M", 8, 550, 600),
            sched("N", 9, 300, 350)
        ]),
        json!([]),
        json!([[0, 900.0], [2000, wh(3.44e9)]]),
        json!([[0, 0.0], [2000, 0.0]]),
        json!([[0, 0.0], [2000, 0.0]]),
    );
    accept(&p, &good);
    let e = set(
        &set(&good, "/activities/6/start", json!(400)),
        "/activities/6/end",
        json!(500),
    );
    reject(&p, &e, "state_effect");
    reject_valid(&p, &e, "state_effect");
    let b = set(
        &set(&good, "/activities/1/start", json!(300)),
        "/activities/1/end",
        json!(400),
    );
    reject_valid(&p, &b, "dependency");
    let b2 = set(
        &set(&good, "/activities/1/start", json!(360)),
        "/activities/1/end",
        json!(460),
    );
    // ... which makes E at 450 break B's requirement
    reject_valid(
        &p,
        &b2,
        "step 7 (`E`): placement [450, 550) violates state_effect",
    );
    let b2 = set(
        &set(&b2, "/activities/6/start", json!(460)),
        "/activities/6/end",
        json!(560),
    );
    let b2 = set(
        &set(&b2, "/activities/7/start", json!(560)),
        "/activities/7/end",
        json!(610),
    );
    valid_ok(&p, &b2);
    reject(&p, &b2, "choice rule prefers");
    let g2 = set(&good, "/activities/5", sched("G2", 6, 100, 200));
    reject(&p, &g2, "expected skipped");
    reject_valid(&p, &g2, "group is taken");
    let c = set(&good, "/activities/3", sched("C", 4, 0, 100));
    reject(&p, &c, "expected failed (dependency");
    reject_valid(&p, &c, "dependency");
    let skipped_g1 = set(&good, "/activities/4", skipped("G1", 5));
    reject_valid(&p, &skipped_g1, "no member of its group");
    let m = set(
        &set(&good, "/activities/7/start", json!(551)),
        "/activities/7/end",
        json!(601),
    );
    reject_valid(&p, &m, "dependency");
    let d = set(&good, "/activities/2", sched("D", 3, 250, 350));
    reject_valid(&p, &d, "state_requirement");
    reject(&p, &d, "expected failed (no feasible");
}

#[test]
fn uhf_engines_data_volume() {
    // engines limit 1, data cap 100 Mbit, initial 80.
    // U comm uhf [0,100) 1 engine. V (uhf_interactions []) 0 engines: after U -> 100.
    // W 1 engine, window [50,500] pref 50: engines forbid overlapping U -> 100.
    // P1 downlink -2 Mbit/s [300,350). X +1 Mbit/s 60 s: D(300) = 80 + (300 - s) <= 100
    // -> s >= 280; then [300,340) net -1 -> 60, [340,350) -2 -> 40.
    // Y -1 [400,500): 40 -> 0 at 440, floored. Z +1 [450,550): net 0 till 500 (stays
    // 0), then +1 -> 50.
    let p = plan(json!({
        "format": "solscope.plan/1", "horizon": {"start": 0, "end": 1000},
        "battery": {"capacity": 1000.0, "initial": 900.0, "min_soc": 0.0},
        "power": {"rtg": 100.0, "asleep": 0.0, "awake": 0.0},
        "sequence_engines": 1,
        "data": {"capacity": 100.0, "initial": 80.0},
        "activities": [
            {"id": "U", "priority": 1, "duration": 100, "awake": "any", "comm_kind": "uhf",
             "windows": [{"start": 0, "end": 0}]},
            {"id": "V", "priority": 2, "duration": 100, "awake": "any", "uhf_interactions": [],
             "sequence_engines": 0, "windows": [{"start": 0, "end": 500}]},
            {"id": "W", "priority": 3, "duration": 50, "awake": "any",
             "windows": [{"start": 50, "end": 500}]},
            {"id": "P1", "priority": 4, "duration": 50, "awake": "any", "data_rate": -2.0,
             "sequence_engines": 0, "windows": [{"start": 300, "end": 300}]},
            {"id": "X", "priority": 5, "duration": 60, "awake": "any", "data_rate": 1.0,
             "sequence_engines": 0},
            {"id": "Y", "priority": 6, "duration": 100, "awake": "any", "data_rate": -1.0,
             "sequence_engines": 0, "windows": [{"start": 400, "end": 400}]},
            {"id": "Z", "priority": 7, "duration": 100, "awake": "any", "data_rate": 1.0,
             "sequence_engines": 0, "windows": [{"start": 450, "end": 900}]}
        ]
    }));
    let good = doc(
        json!([
            sched("U", 1, 0, 100),
            sched("V", 2, 100, 200),
            sched("W", 3, 100, 150),
            sched("P1", 4, 300, 350),
            sched("X", 5, 280, 340),
            sched("Y", 6, 400, 500),
            sched("Z", 7, 450, 550)
        ]),
        json!([]),
        json!([[0, 900.0], [1000, wh(3.34e9)]]),
        json!([[0, 0.0], [1000, 0.0]]),
        json!([
            [0, 80.0],
            [280, 80.0],
            [300, 100.0],
            [340, 60.0],
            [350, 40.0],
            [400, 40.0],
            [440, 0.0],
            [500, 0.0],
            [550, 50.0],
            [1000, 50.0]
        ]),
    );
    accept(&p, &good);
    let v = set(
        &set(&good, "/activities/1/start", json!(50)),
        "/activities/1/end",
        json!(150),
    );
    reject_valid(&p, &v, "uhf");
    let w = set(
        &set(&good, "/activities/2/start", json!(50)),
        "/activities/2/end",
        json!(100),
    );
    reject_valid(&p, &w, "sequence_engines");
    let x = set(
        &set(&good, "/activities/4/start", json!(279)),
        "/activities/4/end",
        json!(339),
    );
    reject_valid(&p, &x, "data_volume");
    reject(&p, &x, "data_volume");
    // Without the floor at 0, Z's volume at 550 would be 40 not 50.
    reject(
        &p,
        &set(&good, "/profiles/data_volume/8/1", json!(40.0)),
        "profiles.data_volume",
    );
}

#[test]
fn handover_limits_only_optional() {
    // handover at 500: min_soc 4.5 Wh, max data 30 Mbit.
    // X optional 36 W 100 s (1 Wh): E(500) = 5 - (500 - s)/100 >= 4.5 -> s >= 450.
    // Y optional 1 Mbit/s 100 s: produced before 500 = 500 - s <= 30 -> s >= 470.
    // M mandatory 36 W at 0: ignores the handover (E(500) becomes 3.5).
    let p = plan(json!({
        "format": "solscope.plan/1", "horizon": {"start": 0, "end": 1000},
        "battery": {"capacity": 10.0, "initial": 5.0, "min_soc": 0.0},
        "power": {"rtg": 0.0, "asleep": 0.0, "awake": 0.0},
        "handover": {"time": 500, "min_soc": 4.5, "max_data_volume": 30.0},
        "activities": [
            {"id": "X", "priority": 1, "mandatory": false, "duration": 100, "awake": "any",
             "energy_rate": 36.0, "windows": [{"start": 0, "end": 900}]},
            {"id": "Y", "priority": 2, "mandatory": false, "duration": 100, "awake": "any",
             "data_rate": 1.0, "windows": [{"start": 0, "end": 900}]},
            {"id": "M", "priority": 3, "duration": 100, "awake": "any", "energy_rate": 36.0,
             "windows": [{"start": 0, "end": 0}]}
        ]
    }));
    let good = doc(
        json!([
            sched("X", 1, 450, 550),
            sched("Y", 2, 470, 570),
            sched("M", 3, 0, 100)
        ]),
        json!([]),
        json!([[0, 5.0], [100, 4.0], [450, 4.0], [550, 3.0], [1000, 3.0]]),
        json!([[0, 0.0], [1000, 0.0]]),
        json!([[0, 0.0], [470, 0.0], [570, 100.0], [1000, 100.0]]),
    );
    accept(&p, &good);
    let x = set(
        &set(&good, "/activities/0/start", json!(449)),
        "/activities/0/end",
        json!(549),
    );
    reject(&p, &x, "handover_soc");
    reject_valid(&p, &x, "handover_soc");
    let y = set(
        &set(&good, "/activities/1/start", json!(469)),
        "/activities/1/end",
        json!(569),
    );
    reject_valid(&p, &y, "handover data");
}

#[test]
fn max_peak_power() {
    // max_peak 100 W, asleep 10, awake 50. P1 peak 60 at 0 (70 W). P2 peak 50 must not
    // overlap P1 (120 W): 100. P3 needs the rover awake: 50 + 60 > 100 anywhere: failed.
    let p = plan(json!({
        "format": "solscope.plan/1", "horizon": {"start": 0, "end": 1000},
        "battery": {"capacity": 1000.0, "initial": 900.0, "min_soc": 0.0},
        "power": {"rtg": 100.0, "asleep": 10.0, "awake": 50.0, "max_peak": 100.0},
        "activities": [
            {"id": "P1", "priority": 1, "duration": 100, "awake": "any", "peak_power": 60.0,
             "windows": [{"start": 0, "end": 0}]},
            {"id": "P2", "priority": 2, "duration": 100, "awake": "any", "peak_power": 50.0,
             "windows": [{"start": 0, "end": 500}]},
            {"id": "P3", "priority": 3, "duration": 50, "peak_power": 60.0,
             "windows": [{"start": 0, "end": 500}]}
        ]
    }));
    let good = doc(
        json!([
            sched("P1", 1, 0, 100),
            sched("P2", 2, 100, 200),
            failed("P3", 3)
        ]),
        json!([]),
        json!([[0, 900.0], [1000, 925.0]]),
        json!([[0, 70.0], [100, 60.0], [200, 10.0], [1000, 10.0]]),
        json!([[0, 0.0], [1000, 0.0]]),
    );
    accept(&p, &good);
    let p2 = set(
        &set(&good, "/activities/1/start", json!(50)),
        "/activities/1/end",
        json!(150),
    );
    reject_valid(&p, &p2, "max_peak_power");
    let p3 = set(&good, "/activities/2", sched("P3", 3, 0, 50));
    reject(&p, &p3, "max_peak_power");
}

#[test]
fn nearest_preferred_ties_and_windows() {
    // Q, R, W hold r over [100,200), [300,350), [600,650). Derivations below.
    let r = |id: &str, prio: i64, d: i64, wins: Value| {
        json!({"id": id, "priority": prio, "duration": d, "awake": "any", "resources": ["r"],
               "windows": wins})
    };
    let p = plan(json!({
        "format": "solscope.plan/1", "horizon": {"start": 0, "end": 1000},
        "battery": {"capacity": 1000.0, "initial": 900.0, "min_soc": 0.0},
        "power": {"rtg": 0.0, "asleep": 0.0, "awake": 0.0},
        "activities": [
            r("Q", 1, 100, json!([{"start": 100, "end": 100}])),
            r("R", 2, 50, json!([{"start": 300, "end": 300}])),
            r("W", 3, 50, json!([{"start": 600, "end": 600}])),
            r("S", 4, 50, json!([{"start": 60, "end": 240, "preferred": 150}])),
            r("T", 5, 50, json!([{"start": 100, "end": 150}, {"start": 0, "end": 1000, "preferred": 700}])),
            r("V", 6, 100, json!([{"start": 0, "end": 1000, "preferred": 600}]))
        ]
    }));
    // S: starts with [s,s+50) free of [100,200),[300,350),[600,650): s in [60,50] (none)
    // or [200,250] -> within window 1 [60,240]: 200..240, nearest to 150: 200.
    // T: window 1 [100,150]: blocked by Q/S? [100,200) Q -> all blocked; window 2 pref
    // 700: free -> 700.
    // V (100 s) pref 600: busy [100,200) Q, [200,250) S, [300,350) R, [600,650) W,
    // [700,750) T. Free starts: [0,0], [350,500], [750,900]. Distances: 500 -> 100,
    // 750 -> 150. -> 500.
    let good = doc(
        json!([
            sched("Q", 1, 100, 200),
            sched("R", 2, 300, 350),
            sched("W", 3, 600, 650),
            sched("S", 4, 200, 250),
            sched("T", 5, 700, 750),
            sched("V", 6, 500, 600)
        ]),
        json!([]),
        json!([[0, 900.0], [1000, 900.0]]),
        json!([[0, 0.0], [1000, 0.0]]),
        json!([[0, 0.0], [1000, 0.0]]),
    );
    accept(&p, &good);
    let v = set(
        &set(&good, "/activities/5/start", json!(350)),
        "/activities/5/end",
        json!(450),
    );
    reject(&p, &v, "preferred 600");
    // Tie: a plan where two starts are equally near the preferred time.
    let p2 = plan(json!({
        "format": "solscope.plan/1", "horizon": {"start": 0, "end": 1000},
        "battery": {"capacity": 1000.0, "initial": 900.0, "min_soc": 0.0},
        "power": {"rtg": 0.0, "asleep": 0.0, "awake": 0.0},
        "activities": [
            r("B", 1, 100, json!([{"start": 450, "end": 450}])),
            r("K", 2, 50, json!([{"start": 0, "end": 1000, "preferred": 475}]))
        ]
    }));
    // K free starts: s <= 400 or s >= 550; |400-475| = 75 = |550-475|: tie -> 400.
    let good2 = doc(
        json!([sched("B", 1, 450, 550), sched("K", 2, 400, 450)]),
        json!([]),
        json!([[0, 900.0], [1000, 900.0]]),
        json!([[0, 0.0], [1000, 0.0]]),
        json!([[0, 0.0], [1000, 0.0]]),
    );
    accept(&p2, &good2);
    let k = set(
        &set(&good2, "/activities/1/start", json!(550)),
        "/activities/1/end",
        json!(600),
    );
    reject(&p2, &k, "ties to the earlier");
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 96,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// The fast resource checks agree with the naive full re-simulation on every
    /// candidate, and the oracle accepts its own schedule.
    #[test]
    fn fast_checks_match_naive(text in plangen::small_plan_text()) {
        let loaded = match solscope_engine::load_plan(&text) {
            Ok(l) => l,
            Err(e) => return Err(TestCaseError::fail(format!("generated plan rejected: {e}\n{text}"))),
        };
        let own = oracle::solve(&loaded.plan, PARANOID).map_err(TestCaseError::fail)?;
        oracle::replay_with(&loaded.plan, &own, PARANOID).map_err(TestCaseError::fail)?;
        oracle::check_valid(&loaded.plan, &own).map_err(TestCaseError::fail)?;
        oracle::check_generated_order(&own).map_err(TestCaseError::fail)?;
    }
}

/// Coverage report of the generator (run with `-- --ignored --nocapture`): how often
/// each outcome and each blocking reason occurs, and how long the oracle takes.
#[test]
#[ignore]
fn generator_coverage() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    use std::collections::BTreeMap;
    let mut runner = TestRunner::deterministic();
    let strat = plangen::plan_text();
    let mut outcomes: BTreeMap<String, usize> = BTreeMap::new();
    let mut reasons: BTreeMap<&'static str, usize> = BTreeMap::new();
    let mut slowest = (0u128, String::new());
    let mut solve_total = std::time::Duration::ZERO;
    let n = 300;
    let t0 = std::time::Instant::now();
    for _ in 0..n {
        let text = match strat.new_tree(&mut runner) {
            Ok(t) => t.current(),
            Err(e) => panic!("{e}"),
        };
        let loaded = match solscope_engine::load_plan(&text) {
            Ok(l) => l,
            Err(e) => {
                *outcomes.entry(format!("REJECTED: {e}")).or_default() += 1;
                continue;
            }
        };
        let t = std::time::Instant::now();
        if let Err(e) = oracle::solve(&loaded.plan, Options::default()) {
            panic!("{e}");
        }
        solve_total += t.elapsed();
        let ms = t.elapsed().as_millis();
        if ms > slowest.0 {
            slowest = (ms, text.clone());
        }
        let summary = match oracle::outcome_summary(&loaded.plan) {
            Ok(s) => s,
            Err(e) => panic!("{e}"),
        };
        for (_, what, kinds) in summary {
            *outcomes.entry(what).or_default() += 1;
            for k in kinds {
                *reasons.entry(k).or_default() += 1;
            }
        }
    }
    eprintln!("{n} plans in {:?}", t0.elapsed());
    eprintln!("outcomes: {outcomes:#?}");
    eprintln!("reason kinds blocking failed activities: {reasons:#?}");
    eprintln!(
        "total solve time {solve_total:?}; slowest solve {} ms:\n{}",
        slowest.0, slowest.1
    );
}

/// The oracle's own schedule of every shared example (run with `-- --ignored
/// --nocapture`), with timings.
#[test]
#[ignore]
fn oracle_on_examples() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/examples");
    let Ok(rd) = std::fs::read_dir(&dir) else {
        return;
    };
    let mut paths: Vec<_> = rd.filter_map(Result::ok).map(|e| e.path()).collect();
    paths.sort();
    for path in paths {
        let Ok(text) = std::fs::read_to_string(&path) else {
            continue;
        };
        let loaded = match solscope_engine::load_plan(&text) {
            Ok(l) => l,
            Err(e) => panic!("{}: {e}", path.display()),
        };
        let t = std::time::Instant::now();
        let own = match oracle::solve(&loaded.plan, Options::default()) {
            Ok(v) => v,
            Err(e) => panic!("{e}"),
        };
        eprintln!("{} in {:?}:", path.display(), t.elapsed());
        eprintln!("  activities {}", own["activities"]);
        eprintln!("  generated {}", own["generated"]);
        let t = std::time::Instant::now();
        if let Err(e) = oracle::replay(&loaded.plan, &own) {
            panic!("{e}");
        }
        eprintln!("  replay in {:?}", t.elapsed());
    }
}
