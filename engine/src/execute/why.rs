//! Why an activity the first cycle placed did not complete: the explainer's
//! answer at the cycle that dropped it from the schedule for good (the first after
//! the last that placed it), or the cycle's reason for leaving it
//! out, and what ran differently from the prediction before then.

use std::collections::BTreeMap;

use super::{Dropped, Execution, RunOutcome};
use crate::error::Error;
use crate::explain::{ExplainOptions, Phase, explain, involved};
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
/// order. Needs the cycle plans (an execution run without
/// `ExecuteOptions::outcomes_only`; those kept by
/// `ExecuteOptions::failed_plans_only` suffice: a loss is explained at the
/// first cycle that left the activity unplaced after one that placed it).
pub fn losses(plan: &Plan, ex: &Execution) -> Result<Vec<Loss>, Error> {
    // Losses often share the cycle that decided them: its trace is rebuilt once.
    let mut traces = BTreeMap::new();
    let mut out = Vec::new();
    for (a, run) in ex.activities.iter().enumerate() {
        if run.predicted.is_none() || run.outcome == RunOutcome::Completed {
            continue;
        }
        out.push(loss_with(plan, ex, a, &mut traces)?);
    }
    Ok(out)
}

/// Why activity `a` did not complete (it may also be one the first cycle did
/// not place).
pub fn loss(plan: &Plan, ex: &Execution, a: usize) -> Result<Loss, Error> {
    loss_with(plan, ex, a, &mut BTreeMap::new())
}

/// [`loss`], with the cycles' traces rebuilt so far.
fn loss_with(
    plan: &Plan,
    ex: &Execution,
    a: usize,
    traces: &mut BTreeMap<usize, Schedule>,
) -> Result<Loss, Error> {
    let run = &ex.activities[a];
    let (cycle, cause) = if run.outcome == RunOutcome::Aborted {
        (run.cycle, Cause::Overran)
    } else if let Some(k) = ex
        .cycles
        .iter()
        .position(|c| c.dropped.iter().any(|(x, _)| *x == a))
    {
        let why = ex.cycles[k]
            .dropped
            .iter()
            .find(|(x, _)| *x == a)
            .map(|(_, d)| d.clone());
        (Some(k), why.map_or(Cause::Held, Cause::Dropped))
    } else if let Some(last) = run.last_cycle {
        // The cycle that dropped it from the schedule for good: the first one
        // after the last that placed it (later cycles only find its windows
        // passing).
        let placed_last = (0..=last)
            .rev()
            .find(|&k| ex.cycles[k].placement(a).is_some());
        let from = placed_last.map_or(0, |k| k + 1);
        match (from..=last).find(|&k| ex.cycles[k].index_of(a).is_some()) {
            Some(k) => (Some(k), failed(plan, ex, k, a, traces)?),
            None => (Some(last), Cause::Held),
        }
    } else {
        (None, Cause::Held)
    };
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
    Ok(Loss {
        activity: a,
        outcome: run.outcome,
        cycle: at,
        cause,
        changed,
    })
}

/// The explainer's answer for plan activity `a` at cycle `k`.
fn failed(
    plan: &Plan,
    ex: &Execution,
    k: usize,
    a: usize,
    traces: &mut BTreeMap<usize, Schedule>,
) -> Result<Cause, Error> {
    let c = &ex.cycles[k];
    let (Some(cycle_plan), Some(i)) = (c.plan.as_ref(), c.index_of(a)) else {
        return Ok(Cause::Held);
    };
    let sched = match traces.entry(k) {
        std::collections::btree_map::Entry::Occupied(e) => e.into_mut(),
        std::collections::btree_map::Entry::Vacant(e) => {
            e.insert(crate::scheduler::schedule(cycle_plan)?)
        }
    };
    let opts = ExplainOptions {
        activity: Some(plan.activities[a].id.clone()),
        no_suggestions: true,
    };
    let explanations = explain(cycle_plan, sched, &opts)?;
    let Some(ex1) = explanations.iter().find(|e| e.activity == i) else {
        return Ok(Cause::Held);
    };
    let Some(phase) = ex1.phase else {
        return Ok(Cause::Held);
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
        .filter_map(|cu| c.activity_of.get(cu.activity).copied())
        .collect();
    Ok(Cause::Failed {
        phase,
        detail,
        culprits,
    })
}
