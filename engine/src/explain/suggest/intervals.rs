//! Candidates for a `valid_intervals` failure: one builder per single-category
//! minimal relaxation (the category that alone blocks a witness start).

use serde_json::{Value, json};

use super::verify::{Runs, tune_limit};
use super::{Candidate, Pairing, round3};
use crate::explain::Explanation;
use crate::model::{Activity, Dependency, Plan, Window};
use crate::scheduler::{Category, Schedule};
use crate::timeline::IntervalSet;

/// The candidates of every single-category relaxation, in relaxation order; and
/// for each relaxation of two categories, the candidates of each (whose pairs
/// may fix together what no single edit does).
pub(super) fn candidates(runs: &Runs<'_>, ex: &Explanation) -> (Vec<Candidate>, Vec<Pairing>) {
    let mut out = Vec::new();
    let mut pairings = Vec::new();
    for relaxation in &ex.relaxations {
        match relaxation.categories.as_slice() {
            [one] => out.extend(for_category(runs, ex, *one, relaxation.witness)),
            [x, y] => pairings.push((
                for_category(runs, ex, *x, relaxation.witness),
                for_category(runs, ex, *y, relaxation.witness),
            )),
            _ => {}
        }
    }
    (out, pairings)
}

/// The edits that relax category `category` (towards the start `witness`).
fn for_category(
    runs: &Runs<'_>,
    ex: &Explanation,
    category: Category,
    witness: i64,
) -> Vec<Candidate> {
    let (plan, sched) = (runs.plan, runs.sched);
    let activity = &plan.activities[ex.activity];
    let problem = &sched.problem;
    match category {
        Category::Execution => widen_window(activity, problem.h0, problem.h1, witness, ex.duration)
            .into_iter()
            .collect(),
        Category::Dependency => dependencies(plan, sched, ex),
        Category::SequenceEngines => vec![more_engines(plan)],
        Category::StateRequirement => initial_states(plan, activity),
        Category::DataVolume => data_limits(runs, ex),
        Category::UnitResource => release_resources(activity),
        Category::StateEffect => drop_effects(activity),
        Category::Uhf => uhf(activity),
    }
}

/// `unit_resource`: release each resource the activity holds.
fn release_resources(activity: &Activity) -> Vec<Candidate> {
    activity
        .resources
        .iter()
        .map(|r| {
            let rest: Vec<&String> = activity.resources.iter().filter(|x| *x != r).collect();
            Candidate::activity(
                activity,
                format!("Let {} run without holding {r}", activity.id),
                "resources",
                json!(rest),
            )
        })
        .collect()
}

/// `state_effect`: drop each effect of the activity (a placed activity requires
/// the value it would change).
fn drop_effects(activity: &Activity) -> Vec<Candidate> {
    (0..activity.effects.len())
        .map(|j| {
            let e = &activity.effects[j];
            let rest: Vec<Value> = activity
                .effects
                .iter()
                .enumerate()
                .filter(|&(k, _)| k != j)
                .filter_map(|(_, x)| serde_json::to_value(x).ok())
                .collect();
            Candidate::activity(
                activity,
                format!(
                    "Drop the effect of {} that sets {} to {}",
                    activity.id, e.state, e.value
                ),
                "effects",
                Value::Array(rest),
            )
        })
        .collect()
}

/// `uhf`: let the activity overlap every comm activity (no `uhf_interactions`
/// list), or, for a comm activity, drop its kind.
fn uhf(activity: &Activity) -> Vec<Candidate> {
    let mut out = Vec::new();
    if activity.uhf_interactions.is_some() {
        out.push(Candidate::activity(
            activity,
            format!("Let {} overlap comm activities of every kind", activity.id),
            "uhf_interactions",
            Value::Null,
        ));
    }
    if let Some(kind) = &activity.comm_kind {
        out.push(Candidate::activity(
            activity,
            format!(
                "Make {} no {kind} comm activity (drop its comm_kind)",
                activity.id
            ),
            "comm_kind",
            Value::Null,
        ));
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
    if activity.windows.as_ref().is_some_and(Vec::is_empty) {
        // An empty list allows no start at all: without it, the whole plan.
        return Some(Candidate::activity(
            activity,
            format!(
                "Remove the empty windows list of {}, so it may start anywhere in the plan",
                activity.id
            ),
            "windows",
            Value::Null,
        ));
    }
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
