//! Independent brute-force oracle for solscope schedules.
//!
//! Works second by second on the fixed-point quantities of docs/semantics.md and
//! uses nothing of the engine but the plan model types. For every step it tries
//! every integer start (and every duration of an expanding activity) and derives
//! what the greedy scheduler must do; see `replay`.
#![allow(dead_code)]

pub mod problem;
pub mod state;

use serde_json::{Value, json};
use solscope_engine::Plan;

use problem::Prob;
use state::{Change, HeatKind, StepCtx, WinSel, World};

/// Oracle options.
#[derive(Clone, Copy, Debug, Default)]
pub struct Options {
    /// Evaluate every phase-1 candidate with both the fast and the naive resource
    /// checks and fail on any disagreement (slow; for self-tests).
    pub paranoid: bool,
}

/// What the scheduler must do at a step.
#[derive(Clone, Debug)]
enum Outcome {
    Skipped { by: usize },
    DepFailed { on: usize },
    Failed,
    Scheduled { s: i64, d: i64, change: Change },
}

/// One entry of the schedule's `activities`.
#[derive(Clone, Debug)]
struct Entry {
    id: String,
    status: String,
    step: i64,
    start: Option<i64>,
    end: Option<i64>,
}

fn as_int(v: &Value, what: &str) -> Result<i64, String> {
    if let Some(i) = v.as_i64() {
        return Ok(i);
    }
    match v.as_f64() {
        Some(f) if f.fract() == 0.0 && f.abs() < 9e15 => Ok(f as i64),
        _ => Err(format!("{what}: expected an integer, got {v}")),
    }
}

fn opt_int(obj: &Value, key: &str, what: &str) -> Result<Option<i64>, String> {
    match obj.get(key) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => as_int(v, &format!("{what}.{key}")).map(Some),
    }
}

fn parse_entries(p: &Prob, doc: &Value) -> Result<Vec<Entry>, String> {
    if doc.get("format").and_then(Value::as_str) != Some("solscope.schedule/1") {
        return Err(format!(
            "schedule: format is {:?}, expected \"solscope.schedule/1\"",
            doc.get("format")
        ));
    }
    let list = doc
        .get("activities")
        .and_then(Value::as_array)
        .ok_or("schedule: missing `activities` array")?;
    if list.len() != p.acts.len() {
        return Err(format!(
            "schedule: {} activities listed, plan has {}",
            list.len(),
            p.acts.len()
        ));
    }
    let mut out = Vec::new();
    for (k, v) in list.iter().enumerate() {
        let what = format!("activities[{k}]");
        out.push(Entry {
            id: v
                .get("id")
                .and_then(Value::as_str)
                .ok_or(format!("{what}.id missing"))?
                .to_string(),
            status: v
                .get("status")
                .and_then(Value::as_str)
                .ok_or(format!("{what}.status missing"))?
                .to_string(),
            step: as_int(
                v.get("step").unwrap_or(&Value::Null),
                &format!("{what}.step"),
            )?,
            start: opt_int(v, "start", &what)?,
            end: opt_int(v, "end", &what)?,
        });
    }
    Ok(out)
}

/// Starts in `[lo, hi]` by distance to `pref`, ties to the earlier.
fn nearest_order(pref: i64, lo: i64, hi: i64) -> impl Iterator<Item = i64> {
    let kmin = if pref < lo {
        lo - pref
    } else if pref > hi {
        pref - hi
    } else {
        0
    };
    let kmax = (pref - lo).abs().max((hi - pref).abs());
    (kmin..=kmax).flat_map(move |k| {
        let a = pref - k;
        let b = pref + k;
        let first = (lo <= a && a <= hi).then_some(a);
        let second = (k > 0 && lo <= b && b <= hi).then_some(b);
        first.into_iter().chain(second)
    })
}

fn describe(p: &Prob, ai: usize) -> String {
    format!("`{}`", p.acts[ai].id)
}

/// Searches the placement the choice rule demands. `Err` only for an internal
/// inconsistency of the oracle.
fn search(w: &World<'_>, ai: usize, opts: Options) -> Result<Option<(i64, i64, Change)>, String> {
    let p = w.p;
    let a = &p.acts[ai];
    let ctx = w.step_ctx(ai);
    for d in (a.dmin.max(1)..=a.dmax).rev() {
        for win in &a.windows {
            let mut lo = win.start.max(p.hs);
            let mut hi = win.end.min(p.he - d);
            if let Some(c) = win.cutoff {
                hi = hi.min(c - d);
            }
            if a.awake == solscope_engine::AwakeMode::Required {
                lo = lo.max(p.hs + p.wake);
                hi = hi.min(p.he - d - p.shut);
            }
            if lo > hi {
                continue;
            }
            for s in nearest_order(win.preferred, lo, hi) {
                let fast = w.evaluate(&ctx, s, d, WinSel::One(win), false);
                if opts.paranoid || fast.is_ok() {
                    let naive = w.evaluate(&ctx, s, d, WinSel::One(win), true);
                    let same = match (&fast, &naive) {
                        (Ok(a), Ok(b)) => a == b,
                        (Err(a), Err(b)) => a.kind() == b.kind(),
                        _ => false,
                    };
                    if !same {
                        return Err(format!(
                            "ORACLE INTERNAL INCONSISTENCY at {} s={s} d={d}: fast {:?} vs naive {:?}",
                            describe(p, ai),
                            fast,
                            naive
                        ));
                    }
                }
                if let Ok(ch) = fast {
                    return Ok(Some((s, d, ch)));
                }
            }
        }
    }
    Ok(None)
}

fn expect(w: &World<'_>, ai: usize, opts: Options) -> Result<Outcome, String> {
    let p = w.p;
    let a = &p.acts[ai];
    if let Some(g) = &a.group {
        if let Some(by) = (0..p.acts.len())
            .find(|&o| o != ai && p.acts[o].group.as_ref() == Some(g) && w.sched[o].is_some())
        {
            return Ok(Outcome::Skipped { by });
        }
    }
    if let Some(dep) = a.after.iter().find(|d| w.sched[d.target].is_none()) {
        return Ok(Outcome::DepFailed { on: dep.target });
    }
    Ok(match search(w, ai, opts)? {
        Some((s, d, change)) => Outcome::Scheduled { s, d, change },
        None => Outcome::Failed,
    })
}

/// Why the choice rule prefers `(s, d)` over the feasible `(gs, gd)`.
fn preference_reason(p: &Prob, ai: usize, s: i64, d: i64, gs: i64, gd: i64) -> String {
    let a = &p.acts[ai];
    if d != gd {
        return format!("duration {d} is feasible and longer than {gd}");
    }
    let wi = |st: i64| {
        a.windows
            .iter()
            .position(|w| w.start <= st && st <= w.end && w.cutoff.is_none_or(|c| st + d <= c))
    };
    let (w1, w2) = (wi(s), wi(gs));
    if w1 != w2 {
        return format!(
            "window {:?} (1-based) has a feasible start, the scheduler's start is in window {:?}",
            w1.map(|x| x + 1),
            w2.map(|x| x + 1)
        );
    }
    let pref = w1.map_or(0, |i| a.windows[i].preferred);
    format!(
        "preferred {pref}: |{s} - {pref}| = {} vs |{gs} - {pref}| = {} (ties to the earlier)",
        (s - pref).abs(),
        (gs - pref).abs()
    )
}

/// Checks the scheduler's placement `(gs, ge)` of a step; returns the change when
/// feasible.
fn check_placement(
    w: &World<'_>,
    ctx: &StepCtx,
    ai: usize,
    gs: i64,
    ge: i64,
) -> Result<Change, String> {
    let a = &w.p.acts[ai];
    let gd = ge - gs;
    if gd < a.dmin || gd > a.dmax {
        return Err(format!("duration {gd} outside [{}, {}]", a.dmin, a.dmax));
    }
    w.evaluate(ctx, gs, gd, WinSel::Any, true)
        .map_err(|r| format!("violates {r}"))
}

/// Replays a schedule document against the plan: validity, completeness, the exact
/// choice rule, generated activities and profiles.
pub fn replay(plan: &Plan, doc: &Value) -> Result<(), String> {
    replay_with(plan, doc, Options::default())
}

/// `replay` with options.
pub fn replay_with(plan: &Plan, doc: &Value, opts: Options) -> Result<(), String> {
    let p = Prob::compile(plan)?;
    let entries = parse_entries(&p, doc)?;
    let mut w = World::new(&p);
    for (k, &ai) in p.order.iter().enumerate() {
        let step = k + 1;
        let got = &entries[k];
        let act = &p.acts[ai];
        let here = format!("step {step} ({})", describe(&p, ai));
        if got.id != act.id {
            return Err(format!(
                "{here}: schedule lists `{}` at this position",
                got.id
            ));
        }
        if got.step != step as i64 {
            return Err(format!("{here}: `step` is {}", got.step));
        }
        let expected = expect(&w, ai, opts)?;
        let got_place = match (got.status.as_str(), got.start, got.end) {
            ("scheduled", Some(s), Some(e)) => Some((s, e)),
            ("scheduled", _, _) => return Err(format!("{here}: scheduled without start/end")),
            ("failed" | "skipped", None, None) => None,
            ("failed" | "skipped", _, _) => {
                return Err(format!("{here}: {} but has start/end", got.status));
            }
            (other, _, _) => return Err(format!("{here}: unknown status `{other}`")),
        };
        match expected {
            Outcome::Skipped { by } => {
                if got.status != "skipped" {
                    return Err(format!(
                        "{here}: expected skipped (group member {} is scheduled), got {} {:?}",
                        describe(&p, by),
                        got.status,
                        got_place
                    ));
                }
            }
            Outcome::DepFailed { on } => {
                if got.status != "failed" {
                    return Err(format!(
                        "{here}: expected failed (dependency {} is not scheduled), got {} {:?}",
                        describe(&p, on),
                        got.status,
                        got_place
                    ));
                }
            }
            Outcome::Failed => {
                if got.status != "failed" {
                    let ctx = w.step_ctx(ai);
                    let why = match got_place {
                        Some((gs, ge)) => match check_placement(&w, &ctx, ai, gs, ge) {
                            Err(m) => m,
                            Ok(_) => {
                                return Err(format!(
                                    "ORACLE INTERNAL INCONSISTENCY {here}: [{gs}, {ge}) is feasible but the search found nothing"
                                ));
                            }
                        },
                        None => "no feasible start exists".into(),
                    };
                    return Err(format!(
                        "{here}: expected failed (no feasible start/duration), got {} {:?}: {why}",
                        got.status, got_place
                    ));
                }
            }
            Outcome::Scheduled { s, d, change } => match got_place {
                Some((gs, ge)) if gs == s && ge == s + d => {
                    w.apply(ai, step, s, d, &change);
                }
                Some((gs, ge)) => {
                    let ctx = w.step_ctx(ai);
                    let detail = match check_placement(&w, &ctx, ai, gs, ge) {
                        Err(m) => format!("the scheduler's placement {m}"),
                        Ok(_) => format!(
                            "the scheduler's placement is feasible, but the choice rule prefers the oracle's: {}",
                            preference_reason(&p, ai, s, d, gs, ge - gs)
                        ),
                    };
                    return Err(format!(
                        "{here}: expected scheduled at [{s}, {}) (duration {d}), got [{gs}, {ge}): {detail}",
                        s + d
                    ));
                }
                None => {
                    return Err(format!(
                        "{here}: expected scheduled at [{s}, {}) (duration {d}), got {}: that start is feasible (the scheduler missed it)",
                        s + d,
                        got.status
                    ));
                }
            },
        }
    }
    compare_generated(&w, doc)?;
    compare_profiles(&w, doc)?;
    Ok(())
}

/// Checks only that every placement of the schedule satisfies every constraint
/// (given the placements of the earlier steps), independent of the choice rule
/// and of completeness; also that skipped/dependency statuses are possible.
pub fn check_valid(plan: &Plan, doc: &Value) -> Result<(), String> {
    check_valid_with(plan, doc, problem::Units::Scheduler)
}

/// [`check_valid`] with the plan's figures read in `units` (`Units::Exact`: the
/// exact decimals, so that a placement the rounding let through shows).
pub fn check_valid_with(plan: &Plan, doc: &Value, units: problem::Units) -> Result<(), String> {
    let p = Prob::compile_with(plan, units)?;
    let entries = parse_entries(&p, doc)?;
    let mut w = World::new(&p);
    for (k, &ai) in p.order.iter().enumerate() {
        let step = k + 1;
        let got = &entries[k];
        let act = &p.acts[ai];
        let here = format!("step {step} ({})", describe(&p, ai));
        if got.id != act.id {
            return Err(format!(
                "{here}: schedule lists `{}` at this position",
                got.id
            ));
        }
        let group_taken = act.group.as_ref().is_some_and(|g| {
            (0..p.acts.len())
                .any(|o| o != ai && p.acts[o].group.as_ref() == Some(g) && w.sched[o].is_some())
        });
        match got.status.as_str() {
            "scheduled" => {
                let (Some(gs), Some(ge)) = (got.start, got.end) else {
                    return Err(format!("{here}: scheduled without start/end"));
                };
                if group_taken {
                    return Err(format!("{here}: scheduled although its group is taken"));
                }
                if let Some(dep) = act.after.iter().find(|d| w.sched[d.target].is_none()) {
                    return Err(format!(
                        "{here}: scheduled although dependency {} is not",
                        describe(&p, dep.target)
                    ));
                }
                let ctx = w.step_ctx(ai);
                let change = check_placement(&w, &ctx, ai, gs, ge)
                    .map_err(|m| format!("{here}: placement [{gs}, {ge}) {m}"))?;
                w.apply(ai, step, gs, ge - gs, &change);
            }
            "skipped" => {
                if !group_taken {
                    return Err(format!(
                        "{here}: skipped but no member of its group is scheduled"
                    ));
                }
            }
            "failed" => {}
            other => return Err(format!("{here}: unknown status `{other}`")),
        }
    }
    Ok(())
}

/// A generated activity in comparable form.
fn gen_key(kind: &str, zone: &str, for_: &str, s: i64, e: i64, step: i64, mw: i64) -> String {
    if kind == "awake" {
        format!("awake [{s}, {e}) step {step}")
    } else {
        format!("{kind} zone={zone} for={for_} [{s}, {e}) power={mw}mW step {step}")
    }
}

fn expected_generated(w: &World<'_>) -> Vec<String> {
    let p = w.p;
    let mut out: Vec<String> = w
        .awake
        .iter()
        .map(|a| gen_key("awake", "", "", a.s, a.e, a.step as i64, 0))
        .collect();
    for d in &w.demands {
        let kind = match d.kind {
            HeatKind::Preheat => "preheat",
            HeatKind::Maintenance => "maintenance",
        };
        out.push(gen_key(
            kind,
            &p.zones[d.zone].name,
            &p.acts[d.act].id,
            d.s,
            d.e,
            d.step as i64,
            d.mw,
        ));
    }
    out
}

fn parse_generated(doc: &Value) -> Result<Vec<String>, String> {
    let list = doc
        .get("generated")
        .and_then(Value::as_array)
        .ok_or("schedule: missing `generated` array")?;
    let mut out = Vec::new();
    for (k, g) in list.iter().enumerate() {
        let what = format!("generated[{k}]");
        let kind = g
            .get("kind")
            .and_then(Value::as_str)
            .ok_or(format!("{what}.kind missing"))?;
        let s = opt_int(g, "start", &what)?.ok_or(format!("{what}.start missing"))?;
        let e = opt_int(g, "end", &what)?.ok_or(format!("{what}.end missing"))?;
        let step = opt_int(g, "step", &what)?.ok_or(format!("{what}.step missing"))?;
        match kind {
            "awake" => out.push(gen_key("awake", "", "", s, e, step, 0)),
            "preheat" | "maintenance" => {
                let zone = g
                    .get("zone")
                    .and_then(Value::as_str)
                    .ok_or(format!("{what}.zone"))?;
                let for_ = g
                    .get("for")
                    .and_then(Value::as_str)
                    .ok_or(format!("{what}.for"))?;
                let power = g
                    .get("power")
                    .and_then(Value::as_f64)
                    .ok_or(format!("{what}.power missing"))?;
                let mw = problem::mw(power);
                if (power - mw as f64 / 1000.0).abs() > 1e-9 {
                    return Err(format!("{what}.power {power} is not a whole number of mW"));
                }
                out.push(gen_key(kind, zone, for_, s, e, step, mw));
            }
            other => return Err(format!("{what}.kind `{other}` unknown")),
        }
    }
    Ok(out)
}

fn compare_generated(w: &World<'_>, doc: &Value) -> Result<(), String> {
    let mut exp = expected_generated(w);
    let mut got = parse_generated(doc)?;
    exp.sort();
    got.sort();
    if exp == got {
        return Ok(());
    }
    let missing: Vec<&String> = exp
        .iter()
        .filter(|x| exp.iter().filter(|y| y == x).count() > got.iter().filter(|y| y == x).count())
        .collect();
    let extra: Vec<&String> = got
        .iter()
        .filter(|x| got.iter().filter(|y| y == x).count() > exp.iter().filter(|y| y == x).count())
        .collect();
    Err(format!(
        "generated activities differ:\n  missing (expected, not in schedule): {missing:?}\n  unexpected (in schedule): {extra:?}"
    ))
}

/// Checks the documented order of `generated`: awake periods first by start,
/// then heater entries by (zone, start).
pub fn check_generated_order(doc: &Value) -> Result<(), String> {
    let list = doc
        .get("generated")
        .and_then(Value::as_array)
        .ok_or("schedule: missing `generated` array")?;
    let key = |g: &Value| -> (u8, String, i64) {
        let kind = g.get("kind").and_then(Value::as_str).unwrap_or("");
        let start = g.get("start").and_then(Value::as_i64).unwrap_or(0);
        if kind == "awake" {
            (0, String::new(), start)
        } else {
            let zone = g
                .get("zone")
                .and_then(Value::as_str)
                .unwrap_or("")
                .to_string();
            (1, zone, start)
        }
    };
    for k in 1..list.len() {
        if key(&list[k - 1]) > key(&list[k]) {
            return Err(format!(
                "generated order: entry {} ({}) comes after entry {} ({})",
                k,
                list[k],
                k - 1,
                list[k - 1]
            ));
        }
    }
    Ok(())
}

const TOL: f64 = 1e-6;

/// Checks one profile: integer, strictly increasing breakpoint times from `hs` to
/// `he`, and at every second the value interpolated (linear, or step) equal to
/// `exp(i)` within `TOL`. `last` is the last index compared.
fn check_profile(
    name: &str,
    doc: &Value,
    hs: i64,
    he: i64,
    linear: bool,
    last: i64,
    exp: &dyn Fn(usize) -> f64,
) -> Result<(), String> {
    let pts = doc
        .get("profiles")
        .and_then(|x| x.get(name))
        .and_then(Value::as_array)
        .ok_or(format!("profiles.{name} missing"))?;
    let mut bp: Vec<(i64, f64)> = Vec::new();
    for (k, pt) in pts.iter().enumerate() {
        let what = format!("profiles.{name}[{k}]");
        let pair = pt
            .as_array()
            .filter(|a| a.len() == 2)
            .ok_or(format!("{what}: not [t, v]"))?;
        let t = as_int(&pair[0], &what)?;
        let v = pair[1]
            .as_f64()
            .ok_or(format!("{what}: value not a number"))?;
        if let Some(&(pt, _)) = bp.last() {
            if t <= pt {
                return Err(format!("{what}: time {t} not after {pt}"));
            }
        }
        bp.push((t, v));
    }
    match (bp.first(), bp.last()) {
        (Some(&(a, _)), Some(&(b, _))) if a == hs && b == he => {}
        _ => {
            return Err(format!(
                "profiles.{name}: must start at horizon.start {hs} and end at horizon.end {he}"
            ));
        }
    }
    let mut k = 0;
    for t in hs..=last {
        while k + 1 < bp.len() && bp[k + 1].0 <= t {
            k += 1;
        }
        let (t0, v0) = bp[k];
        let v = if linear && t > t0 && k + 1 < bp.len() {
            let (t1, v1) = bp[k + 1];
            v0 + (v1 - v0) * ((t - t0) as f64) / ((t1 - t0) as f64)
        } else {
            v0
        };
        let e = exp((t - hs) as usize);
        if (v - e).abs() > TOL {
            return Err(format!(
                "profiles.{name}: at t={t} the schedule gives {v}, the oracle {e} (difference {})",
                v - e
            ));
        }
    }
    Ok(())
}

fn compare_profiles(w: &World<'_>, doc: &Value) -> Result<(), String> {
    let p = w.p;
    let sim = &w.sim;
    check_profile("soc", doc, p.hs, p.he, true, p.he, &|i| {
        sim.soc[i] as f64 / 3.6e6
    })?;
    check_profile("peak_power", doc, p.hs, p.he, false, p.he - 1, &|i| {
        sim.peak[i] as f64 / 1000.0
    })?;
    check_profile("data_volume", doc, p.hs, p.he, true, p.he, &|i| {
        sim.dvol[i] as f64 / 1e6
    })?;
    Ok(())
}

/// Breakpoints of a piecewise-linear series given at every second.
fn linear_breakpoints(hs: i64, vals: &[i64], scale: f64) -> Value {
    let n = vals.len();
    let mut out = Vec::new();
    for i in 0..n {
        let keep = i == 0 || i + 1 == n || vals[i + 1] - vals[i] != vals[i] - vals[i - 1];
        if keep {
            out.push(json!([hs + i as i64, vals[i] as f64 / scale]));
        }
    }
    Value::Array(out)
}

/// The oracle's own schedule document (same shape as `solscope.schedule/1`).
/// Used by the self-tests; the property tests compare the scheduler to `replay`.
pub fn solve(plan: &Plan, opts: Options) -> Result<Value, String> {
    let p = Prob::compile(plan)?;
    let mut w = World::new(&p);
    let mut acts = Vec::new();
    for (k, &ai) in p.order.iter().enumerate() {
        let step = k + 1;
        let id = p.acts[ai].id.clone();
        match expect(&w, ai, opts)? {
            Outcome::Skipped { .. } => {
                acts.push(json!({"id": id, "status": "skipped", "step": step}));
            }
            Outcome::DepFailed { .. } | Outcome::Failed => {
                acts.push(json!({"id": id, "status": "failed", "step": step}));
            }
            Outcome::Scheduled { s, d, change } => {
                w.apply(ai, step, s, d, &change);
                acts.push(json!({"id": id, "status": "scheduled", "step": step, "start": s, "end": s + d}));
            }
        }
    }
    let mut generated = Vec::new();
    for a in &w.awake {
        generated.push(json!({"kind": "awake", "start": a.s, "end": a.e, "step": a.step}));
    }
    let mut heat = w.demands.clone();
    heat.sort_by_key(|d| (d.zone, d.s, d.kind, d.act));
    for d in heat {
        let kind = match d.kind {
            HeatKind::Preheat => "preheat",
            HeatKind::Maintenance => "maintenance",
        };
        generated.push(
            json!({"kind": kind, "zone": p.zones[d.zone].name, "for": p.acts[d.act].id,
            "start": d.s, "end": d.e, "power": d.mw as f64 / 1000.0, "step": d.step}),
        );
    }
    let sim = &w.sim;
    let mut peak = Vec::new();
    for (i, &v) in sim.peak.iter().enumerate() {
        if i == 0 || v != sim.peak[i - 1] {
            peak.push(json!([p.hs + i as i64, v as f64 / 1000.0]));
        }
    }
    let last = sim.peak.last().copied().unwrap_or(0);
    peak.push(json!([p.he, last as f64 / 1000.0]));
    Ok(json!({
        "format": "solscope.schedule/1",
        "plan": plan.name.clone().unwrap_or_default(),
        "activities": acts,
        "generated": generated,
        "warnings": [],
        "profiles": {
            "soc": linear_breakpoints(p.hs, &sim.soc, 3.6e6),
            "peak_power": peak,
            "data_volume": linear_breakpoints(p.hs, &sim.dvol, 1e6),
        }
    }))
}

/// `(activity id, outcome, reason kinds)` of one step.
pub type StepSummary = (String, String, Vec<&'static str>);

/// Per-step summary of the oracle's own run, for the generator coverage report:
/// `(activity id, outcome, reason kinds seen over all candidates when it failed)`.
pub fn outcome_summary(plan: &Plan) -> Result<Vec<StepSummary>, String> {
    let p = Prob::compile(plan)?;
    let mut w = World::new(&p);
    let mut out = Vec::new();
    for (k, &ai) in p.order.iter().enumerate() {
        let a = &p.acts[ai];
        let (what, kinds) = match expect(&w, ai, Options::default())? {
            Outcome::Skipped { .. } => ("skipped".to_string(), Vec::new()),
            Outcome::DepFailed { .. } => ("failed_dependency".to_string(), Vec::new()),
            Outcome::Failed => {
                let ctx = w.step_ctx(ai);
                let mut kinds: Vec<&'static str> = Vec::new();
                for d in a.dmin.max(1)..=a.dmax {
                    for s in p.hs..=p.he - d {
                        if let Err(r) = w.evaluate(&ctx, s, d, WinSel::Any, false) {
                            if r.kind() != "execution" && !kinds.contains(&r.kind()) {
                                kinds.push(r.kind());
                            }
                        }
                    }
                }
                if kinds.is_empty() {
                    kinds.push("execution");
                }
                ("failed".to_string(), kinds)
            }
            Outcome::Scheduled { s, d, change } => {
                let mut what = String::from("scheduled");
                if a.dmin != a.dmax {
                    what.push_str(if d == a.dmax {
                        "_expanding_max"
                    } else {
                        "_expanding_shorter"
                    });
                }
                if change.demands.iter().any(|x| x.kind == HeatKind::Preheat) {
                    what.push_str("_preheat");
                }
                if change.awake.as_ref().is_some_and(|(_, m)| !m.is_empty()) {
                    what.push_str("_merged");
                }
                w.apply(ai, k + 1, s, d, &change);
                (what, Vec::new())
            }
        };
        out.push((a.id.clone(), what, kinds));
    }
    Ok(out)
}

/// Free slack, checked independently: `id` checked at `[s, e)` at its own step
/// against the steps before it; then, with `id` removed, every other scheduled
/// step replayed in order (each fully checked), `id` checked at `[s, e)` as a
/// step after all of them (as a mandatory activity: the handover limits applied
/// at its own step), and every placed requirement and every dependency on `id`
/// re-checked second by second. `Ok(None)`: the others do not
/// replay without it (nothing to decide); `Ok(Some(()))`: accepted.
pub fn check_moved_last(
    plan: &Plan,
    doc: &Value,
    id: &str,
    s: i64,
    e: i64,
) -> Result<Option<()>, String> {
    let p = Prob::compile(plan)?;
    let entries = parse_entries(&p, doc)?;
    let target = p
        .acts
        .iter()
        .position(|a| a.id == id)
        .ok_or(format!("no activity {id}"))?;
    {
        let mut w = World::new(&p);
        for (k, &ai) in p.order.iter().enumerate() {
            let got = &entries[k];
            if ai == target {
                let ctx = w.step_ctx(ai);
                check_placement(&w, &ctx, ai, s, e).map_err(|m| format!("at its own step: {m}"))?;
                break;
            }
            let (Some(gs), Some(ge)) = (got.start, got.end) else {
                continue;
            };
            let ctx = w.step_ctx(ai);
            let change = check_placement(&w, &ctx, ai, gs, ge)?;
            w.apply(ai, k + 1, gs, ge - gs, &change);
        }
    }
    let mut p = p;
    p.acts[target].mandatory = true;
    let p = p;
    let mut w = World::new(&p);
    w.absent = Some(target);
    for (k, &ai) in p.order.iter().enumerate() {
        let got = &entries[k];
        if ai == target || got.status != "scheduled" {
            continue;
        }
        let (Some(gs), Some(ge)) = (got.start, got.end) else {
            continue;
        };
        let ctx = w.step_ctx(ai);
        match check_placement(&w, &ctx, ai, gs, ge) {
            Ok(change) => w.apply(ai, k + 1, gs, ge - gs, &change),
            Err(_) => return Ok(None),
        }
    }
    let ctx = w.step_ctx(target);
    let change = check_placement(&w, &ctx, target, s, e)?;
    w.apply(target, p.order.len() + 1, s, e - s, &change);
    for (b, act) in p.acts.iter().enumerate() {
        let Some((sb, eb)) = w.sched[b] else { continue };
        for (st, v) in &act.requires {
            for t in sb..eb {
                if w.state_value(*st, t, Some(b), &[]) != v.as_str() {
                    return Err(format!("{} loses {} at {t}", act.id, p.states[*st].0));
                }
            }
        }
        for dep in act.after.iter().filter(|d| d.target == target) {
            let gap = sb - e;
            let max = if dep.meets { Some(0) } else { dep.max_delay };
            if gap < dep.min_delay || max.is_some_and(|m| gap > m) {
                return Err(format!("{} breaks its dependency on {id}", act.id));
            }
        }
    }
    Ok(Some(()))
}
