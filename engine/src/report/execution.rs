//! The execution document (`solscope.execution/1`, docs/format.md section 10).

use std::collections::BTreeMap;

use serde::Serialize;

use crate::execute::{
    Actuals, Cause, Dropped, Event, Execution, Guard, Loss, Trigger, ViolationKind, loss_line,
};
use crate::model::Plan;
use crate::scheduler::Profiles;
use crate::units::{mbit, watts, wh};

/// The value of `format` in every execution document.
pub const EXECUTION_FORMAT: &str = "solscope.execution/1";

/// `solscope.execution/1` (its cycles' lists of ids borrow the plan's: a
/// long execution lists as many as its cycles times its activities).
#[derive(Clone, Debug, Serialize)]
pub struct ExecutionDoc<'a> {
    /// Always [`EXECUTION_FORMAT`].
    pub format: &'static str,
    /// Plan name.
    pub plan: String,
    /// The actual durations the execution used, where they differ from `duration`
    /// or were given.
    pub actuals: BTreeMap<String, i64>,
    /// Counts and extremes.
    pub summary: SummaryEntry,
    /// Every activity, in file order.
    pub activities: Vec<RunEntry>,
    /// Every scheduling cycle, in time order.
    pub cycles: Vec<CycleEntry<'a>>,
    /// Limits the executed profile breaks.
    pub violations: Vec<ViolationEntry>,
    /// The executed profiles, as breakpoints.
    pub profiles: Profiles,
    /// The executed awake periods `[start, end)`.
    pub awake: Vec<(i64, i64)>,
}

/// Counts and extremes of one execution.
#[derive(Clone, Debug, Serialize)]
pub struct SummaryEntry {
    /// Activities that ran to their end.
    pub completed: usize,
    /// Optional activities stopped at `start + duration`.
    pub aborted: usize,
    /// Activities that never started.
    pub not_run: usize,
    /// Scheduling cycles.
    pub cycles: usize,
    /// Lowest executed state of charge (Wh) and its time.
    pub lowest_soc: TimedValue,
    /// Executed state of charge at `handover.time` (Wh).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub handover_soc: Option<f64>,
    /// Limits broken.
    pub violations: usize,
}

/// A value at a time.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct TimedValue {
    /// Plan time.
    pub time: i64,
    /// Value (Wh, W or Mbit).
    pub value: f64,
}

/// One activity's execution.
#[derive(Clone, Debug, Serialize)]
pub struct RunEntry {
    /// Activity id.
    pub id: String,
    /// `completed`, `aborted` or `not_run`.
    pub outcome: &'static str,
    /// Where the first cycle placed it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub predicted_start: Option<i64>,
    /// Its predicted end.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub predicted_end: Option<i64>,
    /// Actual start.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub start: Option<i64>,
    /// Actual end (the abort time when aborted).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub end: Option<i64>,
    /// The cycle that dispatched it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cycle: Option<usize>,
    /// For an activity that did not run: the last cycle that had it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub last_cycle: Option<usize>,
    /// For an activity the first cycle placed that did not complete: why.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub why: Option<WhyEntry>,
}

/// Why an activity the first cycle placed did not complete.
#[derive(Clone, Debug, Serialize)]
pub struct WhyEntry {
    /// The cycle that decided it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cycle: Option<usize>,
    /// Its time.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time: Option<i64>,
    /// The cause: `placement/min_soc`, `valid_intervals/unit_resource`,
    /// `dropped/dependency_passed`, `aborted`, `held`, ...
    pub cause: String,
    /// The activities to blame.
    pub culprits: Vec<String>,
    /// Activities that ran before then for other than their predicted duration.
    pub changed: Vec<ChangedEntry>,
    /// The same in one sentence.
    pub text: String,
}

/// An activity that ran for other than its predicted duration.
#[derive(Clone, Debug, Serialize)]
pub struct ChangedEntry {
    /// Activity id.
    pub activity: String,
    /// Actual duration (s).
    pub actual: i64,
    /// Predicted duration (s).
    pub duration: i64,
}

/// One scheduling cycle.
#[derive(Clone, Debug, Serialize)]
pub struct CycleEntry<'a> {
    /// Index (0 is the first cycle).
    pub index: usize,
    /// Plan time.
    pub time: i64,
    /// `start`, `period` or `end`.
    pub trigger: &'static str,
    /// For `end`: the activity that ended.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ended: Option<String>,
    /// State of charge the cycle started from (Wh).
    pub soc: f64,
    /// Activities placed by the cycle (still executing ones included).
    pub scheduled: usize,
    /// Activities the cycle could not place.
    pub failed: Vec<&'a str>,
    /// Activities it left out because they can no longer run.
    pub dropped: Vec<DroppedEntry>,
    /// What the dispatcher did until the next cycle.
    pub events: Vec<EventEntry>,
}

/// An activity a cycle left out.
#[derive(Clone, Debug, Serialize)]
pub struct DroppedEntry {
    /// Activity id.
    pub activity: String,
    /// `group_member_ran`, `dependency_passed` or `depends_on_dropped`.
    pub reason: &'static str,
    /// The other activity involved.
    pub on: String,
}

/// A dispatch event.
#[derive(Clone, Debug, Serialize)]
pub struct EventEntry {
    /// Plan time.
    pub time: i64,
    /// `started` or `held`.
    pub event: &'static str,
    /// Activity id.
    pub activity: String,
    /// For `held`: `dependency`, `resource` or `state`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub guard: Option<&'static str>,
    /// For `held`: the activity or state that held it back.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub by: Option<String>,
}

/// A broken limit.
#[derive(Clone, Debug, Serialize)]
pub struct ViolationEntry {
    /// `min_soc`, `max_peak_power`, `data_capacity` or `handover_soc`.
    pub kind: &'static str,
    /// The first second at which the executed profile breaks it.
    pub time: i64,
    /// The worst value while broken (Wh, W or Mbit) and its time.
    pub worst: TimedValue,
    /// The limit, in the same unit.
    pub limit: f64,
}

/// The execution document of `execution` (of `plan`, run with `actuals`), with
/// `losses` (from [`crate::losses`]) as each lost activity's `why`.
pub fn execution_document<'a>(
    plan: &'a Plan,
    execution: &Execution,
    actuals: &Actuals,
    losses: &[Loss],
    default_name: &str,
) -> ExecutionDoc<'a> {
    let id = |a: usize| plan.activities[a].id.clone();
    let why = |a: usize| {
        let loss = losses.iter().find(|l| l.activity == a)?;
        let culprits = match &loss.cause {
            Cause::Failed { culprits, .. } => culprits.iter().map(|&c| id(c)).collect(),
            _ => Vec::new(),
        };
        Some(WhyEntry {
            cycle: loss.cycle.map(|c| c.0),
            time: loss.cycle.map(|c| c.1),
            cause: loss.cause.key(),
            culprits,
            changed: loss
                .changed
                .iter()
                .map(|&(b, actual, duration)| ChangedEntry {
                    activity: id(b),
                    actual,
                    duration,
                })
                .collect(),
            text: loss_line(plan, &execution.problem, loss),
        })
    };
    let activities: Vec<RunEntry> = execution
        .activities
        .iter()
        .enumerate()
        .map(|(a, run)| RunEntry {
            id: id(a),
            outcome: run.outcome.name(),
            predicted_start: run.predicted.map(|p| p.0),
            predicted_end: run.predicted.map(|p| p.1),
            start: run.actual.map(|p| p.0),
            end: run.actual.map(|p| p.1),
            cycle: run.cycle,
            last_cycle: run.last_cycle,
            why: why(a),
        })
        .collect();
    let count = |o: &str| activities.iter().filter(|r| r.outcome == o).count();
    let cycles = execution
        .cycles
        .iter()
        .enumerate()
        .map(|(index, c)| CycleEntry {
            index,
            time: c.time,
            trigger: match c.trigger {
                Trigger::Start => "start",
                Trigger::Period => "period",
                Trigger::End(_) => "end",
            },
            ended: match c.trigger {
                Trigger::End(a) => Some(id(a)),
                _ => None,
            },
            soc: wh(c.soc),
            scheduled: c.placed(),
            failed: c
                .failed()
                .iter()
                .map(|&a| plan.activities[a].id.as_str())
                .collect(),
            dropped: c
                .dropped
                .iter()
                .map(|(a, why)| {
                    let (reason, on) = match *why {
                        Dropped::GroupMemberRan(b) => ("group_member_ran", b),
                        Dropped::DependencyPassed { on, .. } => ("dependency_passed", on),
                        Dropped::DependsOnDropped(b) => ("depends_on_dropped", b),
                    };
                    DroppedEntry {
                        activity: id(*a),
                        reason,
                        on: id(on),
                    }
                })
                .collect(),
            events: c
                .events
                .iter()
                .map(|e| match *e {
                    Event::Started { activity, time } => EventEntry {
                        time,
                        event: "started",
                        activity: id(activity),
                        guard: None,
                        by: None,
                    },
                    Event::Held {
                        activity,
                        time,
                        guard,
                    } => {
                        let (name, by) = match guard {
                            Guard::Dependency(b) => ("dependency", id(b)),
                            Guard::Resource(b) => ("resource", id(b)),
                            Guard::Engines(b) => ("sequence_engines", id(b)),
                            Guard::Skipped => ("skip_condition", String::new()),
                            Guard::State(s, v) => {
                                let (state, def) = plan
                                    .states
                                    .iter()
                                    .nth(s)
                                    .map_or((String::new(), None), |(n, d)| (n.clone(), Some(d)));
                                let value = def
                                    .and_then(|d| d.values.get(v))
                                    .cloned()
                                    .unwrap_or_default();
                                ("state", format!("{state}={value}"))
                            }
                        };
                        EventEntry {
                            time,
                            event: "held",
                            activity: id(activity),
                            guard: Some(name),
                            by: (!by.is_empty()).then_some(by),
                        }
                    }
                })
                .collect(),
        })
        .collect();
    let violations: Vec<ViolationEntry> = execution
        .violations
        .iter()
        .map(|v| {
            let value = |x: i128| match v.kind {
                ViolationKind::MinSoc | ViolationKind::HandoverSoc => wh(x),
                ViolationKind::MaxPeakPower => watts(x as i64),
                ViolationKind::DataCapacity => mbit(x),
            };
            ViolationEntry {
                kind: v.kind.name(),
                time: v.time,
                worst: TimedValue {
                    time: v.worst.1,
                    value: value(v.worst.0),
                },
                limit: value(v.limit),
            }
        })
        .collect();
    let p = &execution.profile;
    let h1 = execution.problem.h1;
    let mut peak_power: Vec<(i64, f64)> = p.peak.iter().map(|&(t, x)| (t, watts(x))).collect();
    if let Some(&(_, last)) = peak_power.last() {
        peak_power.push((h1, last));
    }
    ExecutionDoc {
        format: EXECUTION_FORMAT,
        plan: plan
            .name
            .clone()
            .unwrap_or_else(|| default_name.to_string()),
        actuals: actuals.durations.clone(),
        summary: SummaryEntry {
            completed: count("completed"),
            aborted: count("aborted"),
            not_run: count("not_run"),
            cycles: execution.cycles.len(),
            lowest_soc: TimedValue {
                time: execution.lowest_soc.1,
                value: wh(execution.lowest_soc.0),
            },
            handover_soc: execution.handover_soc.map(wh),
            violations: violations.len(),
        },
        activities,
        cycles,
        violations,
        profiles: Profiles {
            soc: dedup(p.soc.iter().map(|&(t, x)| (t, wh(x))).collect()),
            peak_power,
            data_volume: dedup(p.data.iter().map(|&(t, x)| (t, mbit(x))).collect()),
        },
        awake: p.awake.clone(),
    }
}

/// Drops breakpoints that lie on the straight line through their neighbours'
/// values when equal (repeated times and flat runs).
fn dedup(points: Vec<(i64, f64)>) -> Vec<(i64, f64)> {
    let mut out: Vec<(i64, f64)> = Vec::with_capacity(points.len());
    for p in points {
        if let Some(last) = out.last_mut() {
            if last.0 == p.0 {
                *last = p;
                continue;
            }
        }
        let n = out.len();
        if n >= 2 && out[n - 1].1 == p.1 && out[n - 2].1 == p.1 {
            out[n - 1] = p;
            continue;
        }
        out.push(p);
    }
    out
}
