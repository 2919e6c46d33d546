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

    /// Whether `other` edits the same fields of the same target to the same
    /// values.
    fn same_edit(&self, other: &Candidate) -> bool {
        self.target == other.target && self.set == other.set
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
    let (failures, pairings, singles) = if failing > 1 {
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
        (failures, pairings, singles)
    } else {
        let mut failures = Vec::with_capacity(exs.len());
        let mut pairings = Vec::with_capacity(exs.len());
        let mut singles = Vec::with_capacity(exs.len());
        for ex in exs {
            let (candidates, pairs, single) = if ex.failure_step.is_some() {
                verified_alone(&runs, ex)
            } else {
                (Vec::new(), Vec::new(), Vec::new())
            };
            failures.push((ex.activity, candidates));
            pairings.push(pairs);
            singles.push(single);
        }
        (failures, pairings, singles)
    };
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
    let (mut candidates, pairings) = own_candidates(runs, ex);
    candidates.extend(reprioritise(runs.plan, ex));
    (distinct(candidates), pairings)
}

/// The candidates of a failure's own kind (its phase), and its pairings. The
/// least-relaxation searches among them reschedule the edited plan.
fn own_candidates(runs: &verify::Runs<'_>, ex: &Explanation) -> (Vec<Candidate>, Vec<Pairing>) {
    let plan = runs.plan;
    let activity = &plan.activities[ex.activity];
    match ex.phase {
        Some(Phase::Group) => (vec![leave_group(activity)], Vec::new()),
        Some(Phase::Dependency) => (
            drop_failed_dependency(plan, runs.sched, ex)
                .into_iter()
                .chain(dependency_first(plan, runs.sched, ex))
                .collect(),
            Vec::new(),
        ),
        Some(Phase::ValidIntervals) => intervals::candidates(runs, ex),
        Some(Phase::Placement) => (placement::candidates(runs, ex), Vec::new()),
        None => (Vec::new(), Vec::new()),
    }
}

/// Each edit once, the first keeping its place.
fn distinct(candidates: Vec<Candidate>) -> Vec<Candidate> {
    let mut unique: Vec<Candidate> = Vec::with_capacity(candidates.len());
    for c in candidates {
        if !unique.iter().any(|u| u.same_edit(&c)) {
            unique.push(c);
        }
    }
    unique
}

/// [`candidates`] and [`verify::verified`] for the one failure explained
/// (nothing to share with other failures): the re-prioritising candidates need
/// no run to be built, so they are verified while the least-relaxation
/// searches of the failure's own candidates run, on the other threads. The
/// candidates, their order and what is kept are those of the two steps one
/// after the other.
fn verified_alone(
    runs: &verify::Runs<'_>,
    ex: &Explanation,
) -> (Vec<Candidate>, Vec<Pairing>, Vec<Suggestion>) {
    let a = ex.activity;
    let ((own, pairings), (moves, moved)) = rayon::join(
        || {
            let (own, pairings) = own_candidates(runs, ex);
            (distinct(own), pairings)
        },
        || {
            let moves = distinct(reprioritise(runs.plan, ex));
            let moved = verify::verified_each(runs, a, &moves);
            (moves, moved)
        },
    );
    let checked = verify::verified_each(runs, a, &own);
    let mut candidates = own;
    let mut results = checked;
    for (c, r) in moves.into_iter().zip(moved) {
        if !candidates.iter().any(|u| u.same_edit(&c)) {
            candidates.push(c);
            results.push(r);
        }
    }
    let single = verify::suggestions_of(&candidates, &results);
    (candidates, pairings, single)
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
fn drop_failed_dependency(plan: &Plan, sched: &Schedule, ex: &Explanation) -> Option<Candidate> {
    let activity = &plan.activities[ex.activity];
    let b = ex.blocked_by?;
    let other = &plan.activities[b].id;
    let why = if comes_later(sched, b, ex) {
        "which comes later in step order"
    } else {
        "which did not schedule"
    };
    let after: Vec<Value> = activity
        .after
        .iter()
        .filter(|d| &d.activity != other)
        .filter_map(|d| serde_json::to_value(d).ok())
        .collect();
    Some(Candidate::activity(
        activity,
        format!("Drop the dependency of {} on {other} ({why})", activity.id),
        "after",
        Value::Array(after),
    ))
}

/// Phase `dependency`, when the activity depended on comes later in the
/// step order (it was not tried when the activity failed): give it the
/// priority just below the activity's, so that it runs first.
fn dependency_first(plan: &Plan, sched: &Schedule, ex: &Explanation) -> Option<Candidate> {
    let b = ex.blocked_by?;
    if !comes_later(sched, b, ex) {
        return None;
    }
    let activity = &plan.activities[ex.activity];
    let other = &plan.activities[b];
    let p = activity.priority.saturating_sub(1);
    Some(Candidate::activity(
        other,
        format!(
            "Schedule {} before {} by giving it priority {p}",
            other.id, activity.id
        ),
        "priority",
        json!(p),
    ))
}

/// Whether activity `b` comes after the failure `ex` in the step order.
fn comes_later(sched: &Schedule, b: usize, ex: &Explanation) -> bool {
    sched.step_of(b).is_some_and(|s| s.step > ex.step)
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
