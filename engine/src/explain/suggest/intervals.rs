//! Candidates for a `valid_intervals` failure: one builder per single-category
//! minimal relaxation (the category that alone blocks a witness start).

use serde_json::{Value, json};

use super::verify::{Runs, tune_limit};
use super::{Candidate, round3};
use crate::explain::Explanation;
use crate::model::{Activity, Dependency, Plan, Window};
use crate::scheduler::{Category, Schedule};
use crate::timeline::IntervalSet;

/// The candidates of every single-category relaxation, in relaxation order.
pub(super) fn candidates(runs: &Runs<'_>, ex: &Explanation) -> Vec<Candidate> {
    let (plan, sched) = (runs.plan, runs.sched);
    let activity = &plan.activities[ex.activity];
    let mut out = Vec::new();
    for relaxation in &ex.relaxations {
        match relaxation.categories.as_slice() {
            [Category::Execution] => {
                let problem = &sched.problem;
                out.extend(widen_window(
                    activity,
                    problem.h0,
                    problem.h1,
                    relaxation.witness,
                    ex.duration,
                ));
            }
            [Category::Dependency] => out.extend(dependencies(plan, sched, ex)),
            [Category::SequenceEngines] => out.push(more_engines(plan)),
            [Category::StateRequirement] => out.extend(initial_states(plan, activity)),
            [Category::DataVolume] => out.extend(data_limits(runs, ex)),
            _ => {}
        }
    }
    out
}

/// Widens the window nearest `witness` so that it allows that start.
fn widen_window(
    activity: &Activity,
    h0: i64,
    h1: i64,
    witness: i64,
    duration: i64,
) -> Option<Candidate> {
    let w = witness;
    let mut windows: Vec<Window> = activity.windows.clone().unwrap_or_else(|| {
        vec![Window {
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
    let mut what = if w < win.start {
        win.start = w;
        format!("start at {w}")
    } else if w > win.end {
        win.end = w;
        format!("end at {w}")
    } else {
        String::new()
    };
    if let Some(c) = win.cutoff {
        if w + duration > c {
            win.cutoff = Some(w + duration);
            what = if what.is_empty() {
                format!("cutoff at {}", w + duration)
            } else {
                format!("{what}, cutoff at {}", w + duration)
            };
        }
    }
    if what.is_empty() {
        return None;
    }
    Some(Candidate::activity(
        activity,
        format!("Widen window {} of {} to {what}", i + 1, activity.id),
        "windows",
        serde_json::to_value(&windows).ok()?,
    ))
}

/// For each dependency: loosen it to a delay that reaches a start the other
/// categories allow, then drop it.
fn dependencies(plan: &Plan, sched: &Schedule, ex: &Explanation) -> Vec<Candidate> {
    let problem = &sched.problem;
    let activity = &plan.activities[ex.activity];
    let id = &activity.id;
    let mut out = Vec::new();
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
        // The start the other categories allow nearest the current bounds, at or
        // after the target's end.
        let others = ex
            .categories
            .iter()
            .filter(|c| c.category != Category::Dependency)
            .fold(IntervalSet::single(problem.h0, problem.h1), |acc, c| {
                acc.intersect(&c.valid)
            });
        let reach = target_end.and_then(|e| {
            let wanted = e.saturating_add(dep.min_delay.unwrap_or(0));
            others.clip(e, problem.h1).nearest(wanted).map(|s| s - e)
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
            let loosened = Dependency {
                activity: dep.activity.clone(),
                meets: false,
                min_delay: (min > 0).then_some(min),
                max_delay: max,
            };
            let mut loosened_after = after.clone();
            loosened_after[j] = serde_json::to_value(&loosened).unwrap_or(Value::Null);
            let bound = match max {
                Some(m) => format!("{min}..{m} s"),
                None => format!("at least {min} s"),
            };
            out.push(Candidate::activity(
                activity,
                format!(
                    "Loosen the dependency of {id} on {} to a delay of {bound} after it ends",
                    dep.activity
                ),
                "after",
                Value::Array(loosened_after),
            ));
        }
        after.remove(j);
        out.push(Candidate::activity(
            activity,
            format!("Drop the dependency of {id} on {}", dep.activity),
            "after",
            Value::Array(after),
        ));
    }
    out
}

/// One more sequence engine.
fn more_engines(plan: &Plan) -> Candidate {
    let n = plan.sequence_engines.unwrap_or(0) + 1;
    Candidate::plan(
        format!("Raise the number of sequence engines to {n}"),
        "sequence_engines",
        json!(n),
    )
}

/// Start the plan in each required state value that it does not start in.
fn initial_states(plan: &Plan, activity: &Activity) -> Vec<Candidate> {
    let mut out = Vec::new();
    for req in &activity.requires {
        if let Some(def) = plan.states.get(&req.state) {
            if def.initial != req.value {
                let mut states = serde_json::to_value(&plan.states).unwrap_or(Value::Null);
                states[&req.state]["initial"] = json!(req.value);
                out.push(Candidate::plan(
                    format!(
                        "Start the plan with {} = {} (instead of {})",
                        req.state, req.value, def.initial
                    ),
                    "states",
                    states,
                ));
            }
        }
    }
    out
}

/// The least raise of the data capacity, and for an optional activity of the data
/// allowed before handover, that makes the activity schedule.
fn data_limits(runs: &Runs<'_>, ex: &Explanation) -> Vec<Candidate> {
    let plan = runs.plan;
    let a = ex.activity;
    let activity = &plan.activities[a];
    let extra = activity.data_rate.max(0.0) * ex.duration as f64;
    let mut out = Vec::new();
    if let Some(cap) = plan.data.capacity {
        let make = |mbit: f64| {
            Candidate::plan_section(
                format!("Raise the data capacity to {mbit} Mbit"),
                "data",
                &plan.data,
                "capacity",
                mbit,
            )
        };
        out.extend(tune_limit(runs, a, &make, cap, round3(cap + extra), 1e12));
    }
    if let (false, Some(h)) = (activity.mandatory, plan.handover) {
        if let Some(max) = h.max_data_volume {
            let make = |mbit: f64| {
                Candidate::plan_section(
                    format!("Raise the data allowed before handover to {mbit} Mbit"),
                    "handover",
                    &h,
                    "max_data_volume",
                    mbit,
                )
            };
            out.extend(tune_limit(runs, a, &make, max, round3(max + extra), 1e12));
        }
    }
    out
}
