//! Why an activity the first cycle placed did not complete: the explainer's
//! answer at the cycle that dropped it from the schedule for good (the first after
//! the last that placed it), or the cycle's reason for leaving it
//! out, and what ran differently from the prediction before then.

use std::collections::BTreeMap;

use super::{CyclePlan, Dropped, Execution, RunOutcome};
use crate::error::Error;
use crate::explain::{Explanation, Phase, explain_targets, involved};
use crate::model::Plan;
use crate::scheduler::Schedule;

/// Why one activity did not complete.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Loss {
    /// Plan activity index.
    pub activity: usize,
    /// Not run, or aborted.
    pub outcome: RunOutcome,
    /// The cycle that decided it (the last that had it; for an abort, the one
    /// that dispatched it), and its time.
    pub cycle: Option<(usize, i64)>,
    /// The cause.
    pub cause: Cause,
    /// Activities that ran before that cycle for other than their predicted
    /// duration: `(activity, actual duration, duration)`.
    pub changed: Vec<(usize, i64, i64)>,
}

/// The cause of a loss, as data.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Cause {
    /// It ran longer than its `duration` and was stopped (optional).
    Overran,
    /// The cycle left it out: it could no longer run.
    Dropped(Dropped),
    /// The cycle's scheduler did not place it: the explainer's phase, the
    /// category or reason kind that decided it, and the culprits (plan indices).
    Failed {
        /// The failure phase.
        phase: Phase,
        /// The categories of the first minimal conflict (`valid_intervals`) or
        /// the first reason kind (`placement`), by the spec's names.
        detail: Vec<&'static str>,
        /// The activities to blame (the first few, as every planner view lists).
        culprits: Vec<usize>,
    },
    /// The cycle placed it, but the dispatch guard held it back until no cycle
    /// came again before its start.
    Held,
}

impl Cause {
    /// A short key for counting causes across runs: `placement/min_soc`,
    /// `valid_intervals/execution+unit_resource`, `dropped/dependency_passed`,
    /// `aborted`, `held`.
    pub fn key(&self) -> String {
        match self {
            Cause::Overran => "aborted".into(),
            Cause::Held => "held".into(),
            Cause::Dropped(d) => format!("dropped/{}", d.name()),
            Cause::Failed { phase, detail, .. } => {
                if detail.is_empty() {
                    phase.name().to_string()
                } else {
                    format!("{}/{}", phase.name(), detail.join("+"))
                }
            }
        }
    }
}

impl Dropped {
    /// The name in documents.
    pub fn name(&self) -> &'static str {
        match self {
            Dropped::GroupMemberRan(_) => "group_member_ran",
            Dropped::DependencyPassed { .. } => "dependency_passed",
            Dropped::DependsOnDropped(_) => "depends_on_dropped",
        }
    }
}

/// Why each activity that the first cycle placed did not complete, in plan
/// order. A loss is explained at the first cycle that left the activity
/// unplaced after the last one that placed it, whose plan is rebuilt
/// ([`Execution::cycle_plan`]) and scheduled again for its trace.
pub fn losses(plan: &Plan, ex: &Execution) -> Result<Vec<Loss>, Error> {
    let lost: Vec<usize> = ex
        .activities
        .iter()
        .enumerate()
        .filter(|(_, run)| run.predicted.is_some() && run.outcome != RunOutcome::Completed)
        .map(|(a, _)| a)
        .collect();
    losses_of(plan, ex, &lost)
}

/// Why activity `a` did not complete (it may also be one the first cycle did
/// not place).
pub fn loss(plan: &Plan, ex: &Execution, a: usize) -> Result<Loss, Error> {
    let mut one = losses_of(plan, ex, &[a])?;
    one.pop()
        .ok_or_else(|| Error::invalid("activities", format!("no activity {a}")))
}

/// The losses of activities `lost`, in that order. Losses often share the
/// cycle that decided them: each such cycle's trace is rebuilt once, and
/// dropped before the next one's is built (a long execution's traces would
/// not fit in memory together).
fn losses_of(plan: &Plan, ex: &Execution, lost: &[usize]) -> Result<Vec<Loss>, Error> {
    // The first cycle that left each activity out, with why.
    let mut dropped: BTreeMap<usize, (usize, &Dropped)> = BTreeMap::new();
    for (k, c) in ex.cycles.iter().enumerate() {
        for (x, d) in &c.dropped {
            dropped.entry(*x).or_insert((k, d));
        }
    }
    let mut decided: Vec<(usize, Option<usize>, Option<Cause>)> = Vec::with_capacity(lost.len());
    let mut by_cycle: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for &a in lost {
        let run = ex
            .activities
            .get(a)
            .ok_or_else(|| Error::invalid("activities", format!("no activity {a}")))?;
        let (cycle, cause) = if run.outcome == RunOutcome::Aborted {
            (run.cycle, Some(Cause::Overran))
        } else if let Some(&(k, d)) = dropped.get(&a) {
            (Some(k), Some(Cause::Dropped(d.clone())))
        } else if let Some(last) = run.last_cycle {
            // The cycle that dropped it from the schedule for good: the first
            // one after the last that placed it (later cycles only find its
            // windows passing). Every cycle up to the last that had it had it
            // (it never started, and a cycle that leaves an activity out
            // leaves it out of every later one).
            let placed_last = (0..=last).rev().find(|&k| !ex.cycles[k].did_not_place(a));
            let from = placed_last.map_or(0, |k| k + 1);
            if from <= last {
                by_cycle.entry(from).or_default().push(decided.len());
                (Some(from), None)
            } else {
                (Some(last), Some(Cause::Held))
            }
        } else {
            (None, Some(Cause::Held))
        };
        decided.push((a, cycle, cause));
    }
    for (k, indices) in by_cycle {
        let Some(cp) = ex.cycle_plan(plan, k) else {
            for i in indices {
                decided[i].2 = Some(Cause::Held);
            }
            continue;
        };
        // The cycle's failures among these, explained together (one replay
        // of the cycle's run serves them all, up to the last of their steps),
        // by cycle plan index.
        let mut targets: Vec<usize> = indices
            .iter()
            .filter_map(|&i| cp.index_of(decided[i].0))
            .collect();
        let sched = cp.schedule_through(&targets)?;
        targets.sort_unstable_by_key(|&i| sched.problem.step_of[i]);
        targets.dedup();
        // Each target's cause, by cycle plan index.
        let causes = |sched: &Schedule| -> Result<BTreeMap<usize, Cause>, Error> {
            let mut causes = BTreeMap::new();
            explain_targets(
                &cp.plan,
                sched,
                &targets,
                true,
                |e| e,
                &mut |_, _| {},
                &mut |e: Explanation| {
                    causes.insert(e.activity, failed(&cp, &e));
                },
            )?;
            Ok(causes)
        };
        let explained = causes(&sched)?;
        // Debug builds: the whole run gives the same causes.
        debug_assert_eq!(
            cp.schedule().and_then(|full| causes(&full)).ok().as_ref(),
            Some(&explained),
            "a loss explained from its cycle's run up to its step differs"
        );
        for i in indices {
            let cause = cp
                .index_of(decided[i].0)
                .and_then(|x| explained.get(&x))
                .cloned()
                .unwrap_or(Cause::Held);
            decided[i].2 = Some(cause);
        }
    }
    Ok(decided
        .into_iter()
        .map(|(a, cycle, cause)| {
            let at = cycle.map(|k| (k, ex.cycles[k].time));
            let until = at.map_or(i64::MAX, |(_, t)| t);
            let changed = ex
                .activities
                .iter()
                .enumerate()
                .filter_map(|(b, r)| {
                    let (s, e) = r.actual?;
                    let planned = plan.activities[b].duration.max();
                    (s < until && e - s != planned && plan.activities[b].duration_model.is_some())
                        .then_some((b, e - s, planned))
                })
                .collect();
            Loss {
                activity: a,
                outcome: ex.activities[a].outcome,
                cycle: at,
                cause: cause.unwrap_or(Cause::Held),
                changed,
            }
        })
        .collect())
}

/// The explainer's answer `ex1` for an activity of the cycle whose plan is
/// `cp`, as a loss's cause.
fn failed(cp: &CyclePlan, ex1: &Explanation) -> Cause {
    let Some(phase) = ex1.phase else {
        return Cause::Held;
    };
    let detail = match phase {
        Phase::ValidIntervals => ex1
            .conflicts
            .first()
            .map(|cats| cats.iter().map(|c| c.name()).collect())
            .unwrap_or_default(),
        Phase::Placement => ex1
            .reasons
            .first()
            .map(|r| vec![r.reason.kind().name()])
            .unwrap_or_default(),
        Phase::Dependency | Phase::Group => Vec::new(),
    };
    let culprits = involved(ex1)
        .iter()
        .filter_map(|cu| cp.activity_of.get(cu.activity).copied())
        .collect();
    Cause::Failed {
        phase,
        detail,
        culprits,
    }
}
