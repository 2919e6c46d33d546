//! proptest generator of small random `solscope.plan/1` plans exercising every
//! feature: windows with preferred/cutoff, expanding durations, unit resources,
//! sequence engines, binding min_soc / max_peak / data capacity, handover limits
//! with optional activities, states, dependencies (meets, delays, later steps),
//! uhf, groups, awake modes with wake/sleep rules, thermal zones with preheat tables
//! and (wrapping) operable periods, short sols with offsets.
//!
//! Raw draws are integers (fractions of the horizon, indices modulo counts) that
//! `assemble` resolves into a consistent plan, so shrinking stays meaningful.
#![allow(dead_code)]

use proptest::collection::vec;
use proptest::option;
use proptest::prelude::*;
use serde_json::{Map, Value, json};

const RESOURCES: [&str; 3] = ["r0", "r1", "r2"];
const KINDS: [&str; 2] = ["uhf", "xband"];
const VALUES: [&str; 3] = ["a", "b", "c"];

#[derive(Clone, Debug)]
pub struct WinG {
    start: u32,
    width: u32,
    pref: Option<u32>,
    cutoff: Option<u32>,
}

#[derive(Clone, Debug)]
pub struct DepG {
    target: usize,
    meets: bool,
    min_delay: Option<i64>,
    max_extra: Option<i64>,
    /// allow a target that comes later in step order (the dependency then fails)
    later: bool,
}

#[derive(Clone, Debug)]
pub struct ActG {
    priority: i64,
    mandatory: bool,
    dur: i64,
    expand: Option<i64>,
    windows: Option<Vec<WinG>>,
    resources: u8,
    engines: Option<u32>,
    energy: u32,
    peak: u32,
    data: i32,
    awake: u8,
    zones: u8,
    after: Vec<DepG>,
    requires: Vec<(usize, usize)>,
    effects: Vec<(usize, usize, bool)>,
    uhf: Option<u8>,
    comm: Option<usize>,
    group: Option<usize>,
    /// For an expanding activity: no windows, awake required and (for an even
    /// `dur`, with states) an effect at its end, the shapes whose feasibility is not monotone in the
    /// duration (the min_awake extension near the plan end, end effects).
    near_end: bool,
}

#[derive(Clone, Debug)]
pub struct ZoneG {
    rows: Vec<(u32, i64)>,
    first: i64,
    preheat: u32,
    maint: u32,
    operable: Option<Vec<(u32, u32)>>,
}

#[derive(Clone, Debug)]
pub struct PlanG {
    start: i64,
    len: i64,
    local: Option<(i64, u32)>,
    cap: i64,
    min_pct: u32,
    init_pct: u32,
    /// rarely: let the rover asleep all horizon break min_soc on its own
    unsafe_base: bool,
    rtg: u32,
    asleep: u32,
    awake_extra: u32,
    max_peak: Option<u32>,
    sleep: Option<(i64, i64, i64, i64)>,
    engines: Option<u32>,
    data: Option<(u32, u32)>,
    handover: Option<(u32, Option<u32>, Option<u32>)>,
    states: Vec<(usize, usize)>,
    zones: Vec<ZoneG>,
    acts: Vec<ActG>,
}

fn window() -> impl Strategy<Value = WinG> {
    (
        0u32..800,
        0u32..1000,
        option::weighted(0.5, 0u32..=1000),
        option::weighted(0.3, 0u32..=1000),
    )
        .prop_map(|(start, width, pref, cutoff)| WinG {
            start,
            width,
            pref,
            cutoff,
        })
}

fn dep() -> impl Strategy<Value = DepG> {
    (
        0usize..10,
        prop::bool::weighted(0.15),
        option::weighted(0.3, 0i64..=300),
        option::weighted(0.3, 0i64..=600),
        prop::bool::weighted(0.15),
    )
        .prop_map(|(target, meets, min_delay, max_extra, later)| DepG {
            target,
            meets,
            min_delay,
            max_extra,
            later,
        })
}

fn act(max_dur: i64) -> impl Strategy<Value = ActG> {
    let core = (
        0i64..=5,
        prop::bool::weighted(0.8),
        prop_oneof![7 => 30i64..=300, 3 => 30i64..=max_dur],
        option::weighted(0.25, prop_oneof![3 => 1i64..=20, 1 => 1i64..=60]),
        option::weighted(0.6, vec(window(), 1..=3)),
    );
    let res = (
        prop_oneof![1 => Just(0u8), 1 => 1u8..8],
        option::weighted(0.5, 0u32..=2),
        prop_oneof![1 => Just(0u32), 3 => 0u32..=60],
        prop_oneof![1 => Just(0u32), 2 => 0u32..=150],
        prop_oneof![3 => Just(0i32), 2 => -6i32..=6],
    );
    let misc = (
        0u8..20,
        prop_oneof![2 => Just(0u8), 1 => 1u8..4],
        prop_oneof![14 => Just(Vec::new()), 5 => vec(dep(), 1..=1), 1 => vec(dep(), 2..=2)],
        prop_oneof![4 => Just(Vec::new()), 1 => vec((0usize..2, 0usize..3), 1..=2)],
        prop_oneof![3 => Just(Vec::new()), 2 => vec((0usize..2, 0usize..3, any::<bool>()), 1..=2)],
    );
    let comm = (
        option::weighted(0.3, 0u8..4),
        option::weighted(0.2, 0usize..2),
        option::weighted(0.25, 0usize..2),
        prop::bool::weighted(0.5),
    );
    (core, res, misc, comm).prop_map(
        |(
            (priority, mandatory, dur, expand, windows),
            (resources, engines, energy, peak, data),
            (awake, zones, after, requires, effects),
            (uhf, comm, group, near_end),
        )| ActG {
            priority,
            mandatory,
            dur,
            expand,
            windows,
            resources,
            engines,
            energy,
            peak,
            data,
            awake,
            zones,
            after,
            requires,
            effects,
            uhf,
            comm,
            group,
            near_end,
        },
    )
}

fn zone() -> impl Strategy<Value = ZoneG> {
    (
        vec((1u32..1000, 0i64..=600), 0..=3),
        prop_oneof![1 => Just(0i64), 3 => 1i64..=600],
        prop_oneof![1 => Just(0u32), 9 => 1u32..=40],
        prop_oneof![1 => Just(0u32), 6 => 1u32..=20],
        option::weighted(0.5, vec((0u32..1000, 0u32..1000), 1..=2)),
    )
        .prop_map(|(rows, first, preheat, maint, operable)| ZoneG {
            rows,
            first,
            preheat,
            maint,
            operable,
        })
}

fn plan_g(
    len: std::ops::RangeInclusive<i64>,
    n_acts: usize,
    max_dur: i64,
) -> impl Strategy<Value = PlanG> {
    let horizon = (
        prop_oneof![3 => Just(0i64), 1 => 100i64..=3000],
        len,
        option::weighted(0.7, (600i64..=4000, 0u32..1000)),
    );
    let energy = (
        10i64..=150,
        0u32..=50,
        0u32..=100,
        0u32..=50,
        2u32..=20,
        5u32..=60,
        option::weighted(0.35, 60u32..=300),
        prop::bool::weighted(0.04),
    );
    let rules = (
        option::weighted(0.6, (0i64..=120, 0i64..=120, 0i64..=900, 0i64..=900)),
        option::weighted(0.4, 1u32..=3),
        option::weighted(0.6, (20u32..=2000, 0u32..=50)),
        option::weighted(
            0.5,
            (
                0u32..=1000,
                option::weighted(0.7, 0u32..=100),
                option::weighted(0.6, 10u32..=1500),
            ),
        ),
    );
    let world = (
        vec((2usize..=3, 0usize..3), 0..=2),
        vec(zone(), 0..=2),
        vec(act(max_dur), 1..=n_acts),
    );
    (horizon, energy, rules, world).prop_map(
        |(
            (start, len, local),
            (cap, min_pct, init_pct, rtg, asleep, awake_extra, max_peak, unsafe_base),
            (sleep, engines, data, handover),
            (states, zones, acts),
        )| PlanG {
            start,
            len,
            local,
            cap,
            min_pct,
            init_pct,
            unsafe_base,
            rtg,
            asleep,
            awake_extra,
            max_peak,
            sleep,
            engines,
            data,
            handover,
            states,
            zones,
            acts,
        },
    )
}

fn frac(x: u32, of: i64) -> i64 {
    i64::from(x) * of / 1000
}

/// Resolves the raw draws into a consistent plan (JSON).
pub fn assemble(g: &PlanG) -> Value {
    let hs = g.start;
    let len = g.len;
    let he = hs + len;
    let mut plan = Map::new();
    plan.insert("format".into(), json!("solscope.plan/1"));
    plan.insert("name".into(), json!("generated"));
    plan.insert("horizon".into(), json!({"start": hs, "end": he}));
    let sol = match g.local {
        Some((sol, off)) => {
            plan.insert(
                "local_time".into(),
                json!({"sol_length": sol, "offset": frac(off, sol)}),
            );
            sol
        }
        None => 88775,
    };
    // battery (Wh, tenths)
    let cap = g.cap as f64;
    let min_soc = (cap * f64::from(g.min_pct) / 100.0 * 10.0).round() / 10.0;
    let initial = min_soc + ((cap - min_soc) * f64::from(g.init_pct) / 100.0 * 10.0).round() / 10.0;
    let initial = initial.min(cap);
    plan.insert(
        "battery".into(),
        json!({"capacity": cap, "initial": initial, "min_soc": min_soc}),
    );
    // power: the rover asleep all horizon must not break min_soc on its own
    let asleep = f64::from(g.asleep);
    let mut rtg = f64::from(g.rtg);
    let drain = (asleep - rtg).max(0.0) * len as f64 / 3600.0;
    if initial - drain < min_soc + 0.5 && !g.unsafe_base {
        rtg = asleep;
    }
    // Now and then the rover draws less awake than asleep (awake periods then
    // give charge back, which several of the scheduler's shortcuts must not
    // assume away).
    let awake = if g.awake_extra % 6 == 0 {
        (asleep - f64::from(g.awake_extra / 6)).max(0.0)
    } else {
        asleep + f64::from(g.awake_extra)
    };
    let mut power = json!({"rtg": rtg, "asleep": asleep, "awake": awake});
    if let Some(mp) = g.max_peak {
        power["max_peak"] = json!(asleep + f64::from(mp));
    }
    plan.insert("power".into(), power);
    if let Some((w, s, ma, ms)) = g.sleep {
        plan.insert(
            "sleep".into(),
            json!({"wakeup_duration": w, "shutdown_duration": s, "min_awake": ma, "min_sleep": ms}),
        );
    }
    if let Some(e) = g.engines {
        plan.insert("sequence_engines".into(), json!(e));
    }
    if let Some((c, ip)) = g.data {
        let c = f64::from(c);
        plan.insert(
            "data".into(),
            json!({"capacity": c, "initial": (c * f64::from(ip) / 100.0).round()}),
        );
    }
    if let Some((t, ms, md)) = g.handover {
        let mut h = json!({"time": hs + frac(t, len)});
        if let Some(pct) = ms {
            h["min_soc"] = json!(min_soc + ((cap - min_soc) * f64::from(pct) / 100.0).round());
        }
        if let Some(md) = md {
            h["max_data_volume"] = json!(f64::from(md));
        }
        plan.insert("handover".into(), h);
    }
    // states
    let mut states = Map::new();
    for (i, &(nv, init)) in g.states.iter().enumerate() {
        states.insert(
            format!("s{i}"),
            json!({"values": VALUES[..nv].to_vec(), "initial": VALUES[init % nv]}),
        );
    }
    if !states.is_empty() {
        plan.insert("states".into(), Value::Object(states));
    }
    // thermal zones
    let mut zones = Map::new();
    for (i, z) in g.zones.iter().enumerate() {
        let mut rows: Vec<(i64, i64)> = vec![(0, z.first)];
        for &(f, d) in &z.rows {
            let from = frac(f, sol).max(1);
            if from < sol && !rows.iter().any(|r| r.0 == from) {
                rows.push((from, d));
            }
        }
        rows.sort_unstable();
        let table: Vec<Value> = rows
            .iter()
            .map(|&(from, duration)| json!({"from": from, "duration": duration}))
            .collect();
        let mut zj = json!({"preheat": table, "preheat_power": f64::from(z.preheat),
                            "maintenance_power": f64::from(z.maint)});
        if let Some(ops) = &z.operable {
            let periods: Vec<Value> = ops
                .iter()
                .map(|&(f, t)| json!({"from": frac(f, sol), "to": frac(t, sol)}))
                .collect();
            zj["operable"] = json!(periods);
        }
        zones.insert(format!("z{i}"), zj);
    }
    if !zones.is_empty() {
        plan.insert("thermal_zones".into(), Value::Object(zones));
    }
    // activities
    let n = g.acts.len();
    let nz = g.zones.len();
    let ns = g.states.len();
    let mut acts = Vec::new();
    for (i, a) in g.acts.iter().enumerate() {
        let mut o = Map::new();
        o.insert("id".into(), json!(format!("a{i}")));
        o.insert("priority".into(), json!(a.priority));
        if !a.mandatory {
            o.insert("mandatory".into(), json!(false));
        }
        let dmin = a.dur.min((len / 6).max(30));
        match a.expand {
            Some(x) => o.insert("duration".into(), json!({"min": dmin, "max": dmin + x})),
            None => o.insert("duration".into(), json!(dmin)),
        };
        let dmax = dmin + a.expand.unwrap_or(0);
        let near_end = a.near_end && a.expand.is_some();
        if let (false, Some(ws)) = (near_end, &a.windows) {
            let list: Vec<Value> = ws
                .iter()
                .map(|w| {
                    let start = hs + frac(w.start, len);
                    let mut end = (start + frac(w.width, len) / 2).min(he);
                    // expanding activities: sometimes a narrow window with a cutoff
                    // that leaves room for only part of [min, max]
                    let tight = a.expand.is_some() && w.cutoff.is_some_and(|c| c < 700);
                    if tight {
                        end = (start + frac(w.width, 10)).min(he);
                    }
                    let mut wj = json!({"start": start, "end": end});
                    if let Some(pf) = w.pref {
                        wj["preferred"] = json!(start + frac(pf, end - start));
                    }
                    if let (true, Some(c)) = (tight, w.cutoff) {
                        let room = dmax - dmin + 1;
                        wj["cutoff"] =
                            json!((end + dmin + i64::from(c) % room).min(he).max(start + 1));
                    } else if let Some(c) = w.cutoff {
                        // between the window end and window end + 2 * dmax
                        // (validation: cutoff > start)
                        let cutoff = (end + i64::from(c) * 2 * dmax / 1000)
                            .min(he)
                            .max(end)
                            .max(start + 1);
                        wj["cutoff"] = json!(cutoff);
                    }
                    wj
                })
                .collect();
            o.insert("windows".into(), json!(list));
        }
        let res: Vec<&str> = (0..3)
            .filter(|b| a.resources & (1 << b) != 0)
            .map(|b| RESOURCES[b])
            .collect();
        if !res.is_empty() {
            o.insert("resources".into(), json!(res));
        }
        if let Some(e) = a.engines {
            o.insert("sequence_engines".into(), json!(e));
        }
        if a.energy != 0 {
            o.insert("energy_rate".into(), json!(f64::from(a.energy)));
        }
        if a.peak != 0 {
            o.insert("peak_power".into(), json!(f64::from(a.peak)));
        }
        if a.data != 0 {
            o.insert("data_rate".into(), json!(f64::from(a.data) * 0.5));
        }
        let awake = match a.awake {
            _ if near_end => None,
            0..=10 => None,
            11..=16 => Some("any"),
            _ => Some("forbidden"),
        };
        if let Some(m) = awake {
            o.insert("awake".into(), json!(m));
        }
        let zs: Vec<String> = (0..nz)
            .filter(|b| a.zones & (1 << b) != 0)
            .map(|b| format!("z{b}"))
            .collect();
        if !zs.is_empty() {
            o.insert("thermal_zones".into(), json!(zs));
        }
        // dependencies only on lower file indices (acyclic); priorities may still
        // put the target in a later step
        let mut after: Vec<Value> = Vec::new();
        let mut targets: Vec<usize> = Vec::new();
        if i > 0 {
            for d in &a.after {
                // mostly a target that comes earlier in step order
                let earlier: Vec<usize> = (0..i)
                    .filter(|&t| g.acts[t].priority <= a.priority)
                    .collect();
                let t = if d.later || earlier.is_empty() {
                    d.target % i
                } else {
                    earlier[d.target % earlier.len()]
                };
                if targets.contains(&t) {
                    continue;
                }
                targets.push(t);
                let mut dj = json!({"activity": format!("a{t}")});
                if d.meets {
                    dj["meets"] = json!(true);
                } else {
                    let min = d.min_delay.unwrap_or(0);
                    if d.min_delay.is_some() {
                        dj["min_delay"] = json!(min);
                    }
                    if let Some(x) = d.max_extra {
                        dj["max_delay"] = json!(min + x);
                    }
                }
                after.push(dj);
            }
        }
        if !after.is_empty() {
            o.insert("after".into(), json!(after));
        }
        if ns > 0 {
            let mut req: Vec<Value> = Vec::new();
            let mut seen: Vec<usize> = Vec::new();
            for &(s, v) in &a.requires {
                let s = s % ns;
                if seen.contains(&s) {
                    continue;
                }
                seen.push(s);
                let nv = g.states[s].0;
                req.push(json!({"state": format!("s{s}"), "value": VALUES[v % nv]}));
            }
            if !req.is_empty() {
                o.insert("requires".into(), json!(req));
            }
            let mut eff: Vec<Value> = Vec::new();
            let mut seen: Vec<(usize, bool)> = Vec::new();
            let end_effect =
                (near_end && a.dur % 2 == 0).then_some((a.priority as usize, i, false));
            for &(s, v, at_start) in a.effects.iter().chain(&end_effect) {
                let s = s % ns;
                if seen.contains(&(s, at_start)) {
                    continue;
                }
                seen.push((s, at_start));
                let nv = g.states[s].0;
                eff.push(json!({"state": format!("s{s}"), "value": VALUES[v % nv],
                                "at": if at_start { "start" } else { "end" }}));
            }
            if !eff.is_empty() {
                o.insert("effects".into(), json!(eff));
            }
        }
        if let Some(bits) = a.uhf {
            let k: Vec<&str> = (0..2)
                .filter(|b| bits & (1 << b) != 0)
                .map(|b| KINDS[b])
                .collect();
            o.insert("uhf_interactions".into(), json!(k));
        }
        if let Some(c) = a.comm {
            o.insert("comm_kind".into(), json!(KINDS[c]));
        }
        if let Some(gr) = a.group {
            o.insert("group".into(), json!(format!("g{gr}")));
        }
        acts.push(Value::Object(o));
    }
    let _ = n;
    plan.insert("activities".into(), json!(acts));
    Value::Object(plan)
}

/// Plans for the property tests: horizon 600..7200 s (mostly short), up to 10
/// activities.
pub fn plan_text() -> impl Strategy<Value = String> {
    let len = prop_oneof![3 => 600i64..=2400, 1 => 2400i64..=7200];
    len.prop_flat_map(|l| plan_g(l..=l, 10, 900))
        .prop_map(|g| assemble(&g).to_string())
}

/// [`plan_text`]'s plans on a starved battery, as the generator's `starved`
/// profile makes them at scale: the battery starts within a tenth of its room
/// above `min_soc`, the RTG gives no more than the sleeping rover draws, and a
/// handover minimum (when drawn) sits at most a fifth of the room above
/// `min_soc`, so most placements fail on the battery or handover minimum, at
/// most starts they try, and the state-of-charge shortcuts decide most steps.
pub fn starved_plan_text() -> impl Strategy<Value = String> {
    let len = prop_oneof![3 => 600i64..=2400, 1 => 2400i64..=7200];
    len.prop_flat_map(|l| plan_g(l..=l, 10, 900))
        .prop_map(|mut g| {
            starve(&mut g);
            assemble(&g).to_string()
        })
}

/// Moves a drawn plan's battery near its minimum (see [`starved_plan_text`]).
fn starve(g: &mut PlanG) {
    g.min_pct += 40;
    g.init_pct /= 10;
    g.rtg = g.rtg.min(g.asleep);
    if let Some((_, Some(pct), _)) = g.handover.as_mut() {
        *pct /= 5;
    }
}

/// Smaller plans for paranoid (fast-vs-naive) oracle self-checks.
pub fn small_plan_text() -> impl Strategy<Value = String> {
    plan_g(300..=1500, 6, 300).prop_map(|g| assemble(&g).to_string())
}
