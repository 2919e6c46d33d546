//! Suggestions: concrete edits in the spec's edit format, each verified by
//! rescheduling the edited plan, ranked by least disruption.
//!
//! One candidate builder per failure kind (`group` and `dependency` phases,
//! each minimal relaxation of a `valid_intervals` failure, each phase-2 reason of
//! a `placement` failure), plus re-prioritising around the culprits for every
//! kind; `verify` keeps the candidates that make the activity schedule.

mod intervals;
mod placement;
mod verify;

use rayon::prelude::*;
use serde::Serialize;
use serde_json::{Map, Value, json};

use super::{Explanation, Phase, Suggestion};
use crate::model::{Activity, Plan};
use crate::scheduler::Schedule;

/// Two groups of candidates, each relaxing one of two constraint categories that
/// only together block the activity: a pair of one from each may fix it.
type Pairing = (Vec<Candidate>, Vec<Candidate>);

/// A failed activity and its candidate edits.
type Failure = (usize, Vec<Candidate>);

/// At most this many pairs of edits are tried per failure without a single fix.
const PAIRS_PER_FAILURE: usize = 12;

/// At most this many pairs of edits are tried in one explanation run (in failure
/// order), so that explaining a large plan stays bounded.
const PAIRS_PER_RUN: usize = 240;

/// A candidate edit before verification.
struct Candidate {
    description: String,
    target: String,
    set: Map<String, Value>,
}

impl Candidate {
    /// An edit of one top-level field of the plan.
    fn plan(description: String, key: &str, value: Value) -> Self {
        Self {
            description,
            target: "plan".into(),
            set: set1(key, value),
        }
    }

    /// An edit of one field inside a section of the plan (`battery.min_soc`, ...):
    /// the section as it is, with that field replaced.
    fn plan_section(
        description: String,
        section: &str,
        current: &impl Serialize,
        field: &str,
        value: f64,
    ) -> Self {
        let mut edited = serde_json::to_value(current).unwrap_or(Value::Null);
        edited[field] = json!(value);
        Self::plan(description, section, edited)
    }

    /// An edit of one field of an activity.
    fn activity(activity: &Activity, description: String, key: &str, value: Value) -> Self {
        Self {
            description,
            target: format!("activity:{}", activity.id),
            set: set1(key, value),
        }
    }
}

fn set1(key: &str, value: Value) -> Map<String, Value> {
    let mut m = Map::new();
    m.insert(key.to_string(), value);
    m
}

/// What verification found for one failure.
#[derive(Clone, Debug, Default)]
pub(crate) struct Fixes {
    /// Verified single edits, least disruptive first.
    pub single: Vec<Suggestion>,
    /// When no single edit works and pairs were tried: `Some`, with two edits
    /// that together make it schedule (empty when no pair tried does).
    pub together: Option<Vec<Suggestion>>,
}

/// Verified suggestions for each explanation, in order (none for an activity
/// that did not fail).
///
/// The candidates of each failure are built in parallel (the least-relaxation
/// searches run then), and every distinct edit among them is verified once for
/// all the failures that propose it. A failure that no single edit fixes then
/// tries pairs: of two categories that only together block it, one edit each;
/// else two of its own candidates (bounded per failure and per run).
pub(crate) fn suggestions(plan: &Plan, sched: &Schedule, exs: &[Explanation]) -> Vec<Fixes> {
    let failing = exs.iter().filter(|ex| ex.failure_step.is_some()).count();
    let runs = verify::Runs::new(plan, sched, failing > 1);
    let (failures, pairings): (Vec<Failure>, Vec<Vec<Pairing>>) = exs
        .par_iter()
        .map(|ex| {
            let (candidates, pairings) = if ex.failure_step.is_some() {
                candidates(&runs, ex)
            } else {
                (Vec::new(), Vec::new())
            };
            ((ex.activity, candidates), pairings)
        })
        .unzip();
    let singles = verify::verified(&runs, &failures);
    // The pairs each failure without a single fix may try, within the budgets.
    let mut budget = PAIRS_PER_RUN;
    let asked: Vec<Option<Vec<(&Candidate, &Candidate)>>> = failures
        .iter()
        .zip(&pairings)
        .zip(&singles)
        .zip(exs)
        .map(|((((_, candidates), pairings), single), ex)| {
            if !single.is_empty() || ex.failure_step.is_none() {
                return None;
            }
            let mut pairs = Vec::new();
            for (xs, ys) in pairings {
                for x in xs {
                    for y in ys {
                        pairs.push((x, y));
                    }
                }
            }
            let first: Vec<&Candidate> = candidates.iter().take(5).collect();
            for (i, &x) in first.iter().enumerate() {
                for &y in &first[i + 1..] {
                    pairs.push((x, y));
                }
            }
            // Two edits of the same field are one edit.
            pairs.retain(|(x, y)| {
                x.target != y.target || x.set.keys().all(|k| !y.set.contains_key(k))
            });
            pairs.truncate(PAIRS_PER_FAILURE.min(budget));
            budget -= pairs.len();
            Some(pairs)
        })
        .collect();
    let together: Vec<Option<Vec<Suggestion>>> = failures
        .par_iter()
        .zip(asked.par_iter())
        .map(|((a, _), pairs)| {
            let pairs = pairs.as_ref()?;
            // The first pair in order that works (pairs after it may be run
            // too, on idle threads: a failure that no pair fixes, the common
            // case here, runs them all anyway).
            let found = pairs
                .par_iter()
                .find_map_first(|(x, y)| runs.verify_pair(x, y, *a));
            Some(found.unwrap_or_default())
        })
        .collect();
    singles
        .into_iter()
        .zip(together)
        .map(|(single, together)| Fixes { single, together })
        .collect()
}

/// The candidates for one failure, each edit once (the first keeps its place),
/// and the pairings of two categories that only together block it.
fn candidates(runs: &verify::Runs<'_>, ex: &Explanation) -> (Vec<Candidate>, Vec<Pairing>) {
    let plan = runs.plan;
    let activity = &plan.activities[ex.activity];
    let mut pairings = Vec::new();
    let mut candidates = match ex.phase {
        Some(Phase::Group) => vec![leave_group(activity)],
        Some(Phase::Dependency) => drop_failed_dependency(plan, ex).into_iter().collect(),
        Some(Phase::ValidIntervals) => {
            let (c, p) = intervals::candidates(runs, ex);
            pairings = p;
            c
        }
        Some(Phase::Placement) => placement::candidates(runs, ex),
        None => Vec::new(),
    };
    candidates.extend(reprioritise(plan, ex));
    let mut unique: Vec<Candidate> = Vec::with_capacity(candidates.len());
    for c in candidates {
        if !unique
            .iter()
            .any(|u| u.target == c.target && u.set == c.set)
        {
            unique.push(c);
        }
    }
    (unique, pairings)
}

/// Phase `group`: leave the group.
fn leave_group(activity: &Activity) -> Candidate {
    Candidate::activity(
        activity,
        format!(
            "Take {} out of its group so it no longer excludes or is excluded",
            activity.id
        ),
        "group",
        Value::Null,
    )
}

/// Phase `dependency`: drop the dependency on the target that did not schedule.
fn drop_failed_dependency(plan: &Plan, ex: &Explanation) -> Option<Candidate> {
    let activity = &plan.activities[ex.activity];
    let other = &plan.activities[ex.blocked_by?].id;
    let after: Vec<Value> = activity
        .after
        .iter()
        .filter(|d| &d.activity != other)
        .filter_map(|d| serde_json::to_value(d).ok())
        .collect();
    Some(Candidate::activity(
        activity,
        format!(
            "Drop the dependency of {} on {other} (which did not schedule)",
            activity.id
        ),
        "after",
        Value::Array(after),
    ))
}

/// Every kind: schedule a blocking culprit (placed at an earlier step) after the
/// activity, or the activity before the first of them, by priority.
fn reprioritise(plan: &Plan, ex: &Explanation) -> Vec<Candidate> {
    let activity = &plan.activities[ex.activity];
    let id = &activity.id;
    let mut blockers: Vec<(i64, usize)> = ex
        .culprits
        .iter()
        .filter(|c| c.step < ex.step)
        .map(|c| (plan.activities[c.activity].priority, c.activity))
        .collect();
    blockers.sort_unstable();
    blockers.dedup();
    let mine = activity.priority;
    let mut out = Vec::new();
    for &(_, x) in blockers.iter().take(3) {
        let blocker = &plan.activities[x];
        out.push(Candidate::activity(
            blocker,
            format!(
                "Schedule {} after {id} by giving it priority {}",
                blocker.id,
                mine.saturating_add(1)
            ),
            "priority",
            json!(mine.saturating_add(1)),
        ));
    }
    if let Some(&(p, x)) = blockers.first() {
        out.push(Candidate::activity(
            activity,
            format!(
                "Schedule {id} before {} by giving it priority {}",
                plan.activities[x].id,
                p.saturating_sub(1)
            ),
            "priority",
            json!(p.saturating_sub(1)),
        ));
    }
    out
}

fn round3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

fn floor3(x: f64) -> f64 {
    (x * 1000.0).floor() / 1000.0
}
