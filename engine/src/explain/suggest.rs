//! Suggestions: concrete edits in the spec's edit format, each verified by
//! rescheduling the edited plan, ranked by least disruption.

use serde_json::{Map, Value, json};

use super::{Explanation, Phase, Suggestion, reschedule_outcome};
use crate::io::apply_edit;
use crate::model::Plan;
use crate::scheduler::{Category, MJ_PER_WH, MW_PER_W, Phase2Reason, Schedule};

/// A candidate edit before verification.
struct Candidate {
    description: String,
    target: String,
    set: Map<String, Value>,
}

fn set1(key: &str, value: Value) -> Map<String, Value> {
    let mut m = Map::new();
    m.insert(key.to_string(), value);
    m
}

/// Verified suggestions for one explanation.
pub fn suggestions(
    plan: &Plan,
    sched: &Schedule,
    ex: &Explanation,
    step_of: &[usize],
) -> Vec<Suggestion> {
    let a = ex.activity;
    let activity = &plan.activities[a];
    let id = &activity.id;
    let me = format!("activity:{id}");
    let pb = &sched.problem;
    let mut cands: Vec<Candidate> = Vec::new();

    match ex.phase {
        Some(Phase::Group) => {
            cands.push(Candidate {
                description: format!(
                    "Take {id} out of its group so it no longer excludes or is excluded"
                ),
                target: me.clone(),
                set: set1("group", Value::Null),
            });
        }
        Some(Phase::Dependency) => {
            if let Some(t) = ex.blocked_by {
                let other = &plan.activities[t].id;
                let after: Vec<Value> = activity
                    .after
                    .iter()
                    .filter(|d| &d.activity != other)
                    .filter_map(|d| serde_json::to_value(d).ok())
                    .collect();
                cands.push(Candidate {
                    description: format!(
                        "Drop the dependency of {id} on {other} (which did not schedule)"
                    ),
                    target: me.clone(),
                    set: set1("after", Value::Array(after)),
                });
            }
        }
        Some(Phase::ValidIntervals) => {
            for r in &ex.relaxations {
                let w = r.witness;
                if r.categories == [Category::Execution] {
                    if let Some(c) = widen_window(activity, pb.h0, pb.h1, w, ex.duration) {
                        cands.push(c);
                    }
                }
                if r.categories == [Category::Dependency] {
                    for (j, dep) in activity.after.iter().enumerate() {
                        let mut after: Vec<Value> = activity
                            .after
                            .iter()
                            .filter_map(|d| serde_json::to_value(d).ok())
                            .collect();
                        // Loosen it first: allow a delay that reaches the witness.
                        let target_end = plan
                            .activities
                            .iter()
                            .position(|o| o.id == dep.activity)
                            .and_then(|t| sched.placement(t))
                            .map(|p| p.1);
                        // The start the other categories allow nearest the current
                        // bounds, at or after the target's end.
                        let others = ex
                            .categories
                            .iter()
                            .filter(|c| c.category != Category::Dependency)
                            .fold(
                                crate::timeline::IntervalSet::single(pb.h0, pb.h1),
                                |acc, c| acc.intersect(&c.valid),
                            );
                        let reach = target_end.and_then(|e| {
                            let wanted = e.saturating_add(dep.min_delay.unwrap_or(0));
                            others.clip(e, pb.h1).nearest(wanted).map(|s| s - e)
                        });
                        if let Some(delay) = reach {
                            let min = if dep.meets {
                                0
                            } else {
                                dep.min_delay.unwrap_or(0).min(delay)
                            };
                            let max = if dep.meets {
                                Some(delay)
                            } else {
                                dep.max_delay.map(|m| m.max(delay))
                            };
                            let loosened = crate::model::Dependency {
                                activity: dep.activity.clone(),
                                meets: false,
                                min_delay: (min > 0).then_some(min),
                                max_delay: max,
                            };
                            let mut after2 = after.clone();
                            after2[j] = serde_json::to_value(&loosened).unwrap_or(Value::Null);
                            let bound = match max {
                                Some(m) => format!("{min}..{m} s"),
                                None => format!("at least {min} s"),
                            };
                            cands.push(Candidate {
                                description: format!(
                                    "Loosen the dependency of {id} on {} to a delay of {bound} after it ends",
                                    dep.activity
                                ),
                                target: me.clone(),
                                set: set1("after", Value::Array(after2)),
                            });
                        }
                        after.remove(j);
                        cands.push(Candidate {
                            description: format!("Drop the dependency of {id} on {}", dep.activity),
                            target: me.clone(),
                            set: set1("after", Value::Array(after)),
                        });
                    }
                }
                if r.categories == [Category::SequenceEngines] {
                    let n = plan.sequence_engines.unwrap_or(0) + 1;
                    cands.push(Candidate {
                        description: format!("Raise the number of sequence engines to {n}"),
                        target: "plan".into(),
                        set: set1("sequence_engines", json!(n)),
                    });
                }
                if r.categories == [Category::StateRequirement] {
                    for req in &activity.requires {
                        if let Some(def) = plan.states.get(&req.state) {
                            if def.initial != req.value {
                                let mut states =
                                    serde_json::to_value(&plan.states).unwrap_or(Value::Null);
                                states[&req.state]["initial"] = json!(req.value);
                                cands.push(Candidate {
                                    description: format!(
                                        "Start the plan with {} = {} (instead of {})",
                                        req.state, req.value, def.initial
                                    ),
                                    target: "plan".into(),
                                    set: set1("states", states),
                                });
                            }
                        }
                    }
                }
                if r.categories == [Category::DataVolume] {
                    let extra = activity.data_rate.max(0.0) * ex.duration as f64;
                    if let Some(cap) = plan.data.capacity {
                        let make = |mbit: f64| {
                            let mut data = serde_json::to_value(plan.data).unwrap_or(Value::Null);
                            data["capacity"] = json!(mbit);
                            Candidate {
                                description: format!("Raise the data capacity to {mbit} Mbit"),
                                target: "plan".into(),
                                set: set1("data", data),
                            }
                        };
                        cands.extend(tune_limit(plan, a, &make, cap, round3(cap + extra), 1e12));
                    }
                    if let (false, Some(h)) = (activity.mandatory, plan.handover) {
                        if let Some(max) = h.max_data_volume {
                            let make = |mbit: f64| {
                                let mut handover = serde_json::to_value(h).unwrap_or(Value::Null);
                                handover["max_data_volume"] = json!(mbit);
                                Candidate {
                                    description: format!(
                                        "Raise the data allowed before handover to {mbit} Mbit"
                                    ),
                                    target: "plan".into(),
                                    set: set1("handover", handover),
                                }
                            };
                            cands.extend(tune_limit(
                                plan,
                                a,
                                &make,
                                max,
                                round3(max + extra),
                                1e12,
                            ));
                        }
                    }
                }
            }
        }
        Some(Phase::Placement) => {
            let mut best_soc: Option<i64> = None;
            let mut best_handover: Option<i64> = None;
            let mut best_peak: Option<i64> = None;
            let mut operability: Option<(usize, i64)> = None;
            for r in &ex.reasons {
                match r.reason {
                    Phase2Reason::MinSoc { soc_mj, .. } => best_soc = best_soc.max(Some(soc_mj)),
                    Phase2Reason::HandoverSoc { soc_mj } => {
                        best_handover = best_handover.max(Some(soc_mj))
                    }
                    Phase2Reason::MaxPeakPower { peak_mw, .. } => {
                        best_peak = Some(best_peak.map_or(peak_mw, |p| p.min(peak_mw)))
                    }
                    Phase2Reason::PreheatOperability {
                        zone,
                        preheat_start,
                    } => {
                        operability.get_or_insert((zone, preheat_start));
                    }
                    _ => {}
                }
            }
            if let Some(mj) = best_soc {
                let make = |wh: f64| {
                    let mut battery = serde_json::to_value(plan.battery).unwrap_or(Value::Null);
                    battery["min_soc"] = json!(wh);
                    Candidate {
                        description: format!("Lower the minimum state of charge to {wh} Wh"),
                        target: "plan".into(),
                        set: set1("battery", battery),
                    }
                };
                let needed = floor3(mj as f64 / MJ_PER_WH).max(0.0);
                cands.extend(tune_limit(
                    plan,
                    a,
                    &make,
                    plan.battery.min_soc,
                    needed,
                    0.0,
                ));
            }
            if let (Some(mj), Some(h)) = (best_handover, plan.handover) {
                let make = |wh: f64| {
                    let mut handover = serde_json::to_value(h).unwrap_or(Value::Null);
                    handover["min_soc"] = json!(wh);
                    Candidate {
                        description: format!("Lower the handover state of charge to {wh} Wh"),
                        target: "plan".into(),
                        set: set1("handover", handover),
                    }
                };
                let needed = floor3(mj as f64 / MJ_PER_WH).max(0.0);
                let current = h.min_soc.unwrap_or(0.0);
                cands.extend(tune_limit(plan, a, &make, current, needed, 0.0));
                cands.push(Candidate {
                    description: format!(
                        "Make {id} mandatory (handover limits bind only optional activities)"
                    ),
                    target: me.clone(),
                    set: set1("mandatory", json!(true)),
                });
            }
            if let Some(mw) = best_peak {
                let make = |w: f64| {
                    let mut power = serde_json::to_value(plan.power).unwrap_or(Value::Null);
                    power["max_peak"] = json!(w);
                    Candidate {
                        description: format!("Raise the peak power limit to {w} W"),
                        target: "plan".into(),
                        set: set1("power", power),
                    }
                };
                let needed = (mw as f64 / MW_PER_W).ceil();
                let current = plan.power.max_peak.unwrap_or(needed);
                cands.extend(tune_limit(plan, a, &make, current, needed, 1e6));
            }
            if let Some((z, ps)) = operability {
                let name = &pb.zone_names[z];
                if let Some(zone) = plan.thermal_zones.get(name) {
                    let tod = pb.tod(ps);
                    let mut zones =
                        serde_json::to_value(&plan.thermal_zones).unwrap_or(Value::Null);
                    let mut periods: Vec<Value> = zone
                        .operable
                        .iter()
                        .flatten()
                        .filter_map(|p| serde_json::to_value(p).ok())
                        .collect();
                    // Extend the period starting nearest after the preheat back to it.
                    let next = zone
                        .operable
                        .iter()
                        .flatten()
                        .enumerate()
                        .min_by_key(|(_, p)| (p.from - tod).rem_euclid(pb.sol));
                    if let Some((i, p)) = next {
                        periods[i] = json!({ "from": tod, "to": p.to });
                        zones[name]["operable"] = Value::Array(periods);
                        cands.push(Candidate {
                            description: format!(
                                "Allow {name} heating from {} local time",
                                super::format_local(pb, ps)
                            ),
                            target: "plan".into(),
                            set: set1("thermal_zones", zones),
                        });
                    }
                }
            }
        }
        None => {}
    }
    // Re-prioritise ahead of each blocking activity (once per distinct priority).
    let mut blockers: Vec<(i64, usize)> = ex
        .culprits
        .iter()
        .filter(|c| c.step < step_of[a])
        .map(|c| (plan.activities[c.activity].priority, c.activity))
        .collect();
    blockers.sort_unstable();
    blockers.dedup();
    // Or move a blocker after this activity.
    let mine = activity.priority;
    for &(_, x) in blockers.iter().take(3) {
        cands.push(Candidate {
            description: format!(
                "Schedule {} after {id} by giving it priority {}",
                plan.activities[x].id,
                mine.saturating_add(1)
            ),
            target: format!("activity:{}", plan.activities[x].id),
            set: set1("priority", json!(mine.saturating_add(1))),
        });
    }
    if let Some(&(p, x)) = blockers.first() {
        cands.push(Candidate {
            description: format!(
                "Schedule {id} before {} by giving it priority {}",
                plan.activities[x].id,
                p.saturating_sub(1)
            ),
            target: me.clone(),
            set: set1("priority", json!(p.saturating_sub(1))),
        });
    }

    let mut out: Vec<Suggestion> = Vec::new();
    for c in cands {
        if out.iter().any(|s| s.target == c.target && s.set == c.set) {
            continue;
        }
        let Ok(edited) = apply_edit(plan, &c.target, &c.set) else {
            continue;
        };
        if let Some(side_effects) = reschedule_outcome(&edited, a, sched) {
            out.push(Suggestion {
                description: c.description,
                target: c.target,
                set: c.set,
                side_effects,
            });
        }
    }
    out.sort_by_key(|s| s.side_effects.len());
    out
}

/// The least relaxation of a numeric plan limit (from `current`, which fails) that
/// makes activity `a` schedule. `needed` is what the failure's numbers call for;
/// knock-on effects on earlier steps can ask for less or more, so the value is
/// binary-searched between `current` and `needed` when `needed` works, else between
/// `needed` and `loosest`, to a resolution of 0.001.
fn tune_limit(
    plan: &Plan,
    a: usize,
    make: &dyn Fn(f64) -> Candidate,
    current: f64,
    needed: f64,
    loosest: f64,
) -> Option<Candidate> {
    let works = |v: f64| {
        let c = make(v);
        apply_edit(plan, &c.target, &c.set)
            .ok()
            .and_then(|p| crate::scheduler::schedule(&p).ok())
            .is_some_and(|s| s.placement(a).is_some())
    };
    let (mut bad, mut good) = if works(needed) {
        (current, needed)
    } else if works(loosest) {
        (needed, loosest)
    } else {
        return None;
    };
    for _ in 0..48 {
        let mid = round3((bad + good) / 2.0);
        if (good - bad).abs() <= 0.001 || mid == bad || mid == good {
            break;
        }
        if works(mid) {
            good = mid;
        } else {
            bad = mid;
        }
    }
    Some(make(good))
}

/// Widens the window nearest `w` so that `w` is a start it allows.
fn widen_window(
    activity: &crate::model::Activity,
    h0: i64,
    h1: i64,
    w: i64,
    d: i64,
) -> Option<Candidate> {
    let mut windows: Vec<crate::model::Window> = activity.windows.clone().unwrap_or_else(|| {
        vec![crate::model::Window {
            start: h0,
            end: h1,
            preferred: None,
            cutoff: None,
        }]
    });
    let (i, _) = windows.iter().enumerate().min_by_key(|(_, x)| {
        if w < x.start {
            x.start - w
        } else {
            (w - x.end).max(0)
        }
    })?;
    let win = &mut windows[i];
    let what = if w < win.start {
        win.start = w;
        format!("start at {w}")
    } else if w > win.end {
        win.end = w;
        format!("end at {w}")
    } else {
        String::new()
    };
    let mut what = what;
    if let Some(c) = win.cutoff {
        if w + d > c {
            win.cutoff = Some(w + d);
            what = if what.is_empty() {
                format!("cutoff at {}", w + d)
            } else {
                format!("{what}, cutoff at {}", w + d)
            };
        }
    }
    if what.is_empty() {
        return None;
    }
    Some(Candidate {
        description: format!("Widen window {} of {} to {what}", i + 1, activity.id),
        target: format!("activity:{}", activity.id),
        set: set1("windows", serde_json::to_value(&windows).ok()?),
    })
}

fn round3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

fn floor3(x: f64) -> f64 {
    (x * 1000.0).floor() / 1000.0
}
