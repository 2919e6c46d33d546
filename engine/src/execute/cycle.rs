//! The plan a scheduling cycle at time `t` runs: the activities not yet started,
//! in the same step order, from the state the rover is really in at `t`
//! (docs/semantics.md, "Execution").

use super::sim::Started;
use crate::error::Error;
use crate::model::{CycleStart, Duration, EffectAt, Plan, Window};
use crate::scheduler::{Schedule, schedule};
use crate::units::{BIT_PER_MBIT, MJ_PER_WH};

/// The plan a scheduling cycle scheduled ([`Execution::cycle_plan`]).
///
/// [`Execution::cycle_plan`]: super::Execution::cycle_plan
#[derive(Clone, Debug, PartialEq)]
pub struct CyclePlan {
    /// The cycle's own plan: the activities not yet started, and the ones
    /// still executing (placed first), from the state the rover was in.
    pub plan: Plan,
    /// The plan activity index of each of its activities.
    pub activity_of: Vec<usize>,
}

impl CyclePlan {
    /// The cycle plan's index of plan activity `a`, if the cycle had it.
    pub fn index_of(&self, a: usize) -> Option<usize> {
        self.activity_of.binary_search(&a).ok()
    }

    /// The cycle's scheduler run with its full step trace (the execution
    /// keeps only the outcomes).
    pub fn schedule(&self) -> Result<Schedule, Error> {
        schedule(&self.plan)
    }
}

/// Why an activity not yet started is left out of a cycle's plan (it can no
/// longer run).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Dropped {
    /// Another member of its group started (plan activity index).
    GroupMemberRan(usize),
    /// A dependency on an activity that ended at `end` leaves no start at or after
    /// the cycle (plan activity index of the target).
    DependencyPassed {
        /// The activity it depends on.
        on: usize,
        /// When that one ended.
        end: i64,
    },
    /// It depends on an activity that can no longer run.
    DependsOnDropped(usize),
}

/// What the execution knows at the cycle about one activity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Status {
    /// Not started.
    Waiting,
    /// Started at `start`, still executing at the cycle; holds until `hold`
    /// (`max(start + duration, t + 1)`).
    Executing { start: i64, hold: i64 },
    /// Ended (completed or aborted) at `end`.
    Ended { end: i64 },
}

impl Status {
    /// The status at a cycle at `t` of an activity that started as `run`
    /// before the cycle (`None`: not started).
    pub(super) fn at(run: Option<&Started>, t: i64) -> Self {
        match run {
            None => Status::Waiting,
            Some(r) if r.end <= t => Status::Ended { end: r.end },
            Some(r) => Status::Executing {
                start: r.start,
                hold: r.planned_end.max(t + 1),
            },
        }
    }
}

/// The cycle's plan and, for each of its activities, the plan activity it is.
pub(super) struct Built {
    pub plan: Plan,
    pub activity_of: Vec<usize>,
    pub dropped: Vec<(usize, Dropped)>,
}

/// The plan activity index of each dependency's target (`None`: an unknown
/// id), by activity and dependency: looked up once per execution rather than
/// at every cycle.
#[derive(Clone, Debug)]
pub(super) struct Links {
    after: Vec<Vec<Option<usize>>>,
}

impl Links {
    pub(super) fn new(plan: &Plan) -> Self {
        let ids = plan.index_by_id();
        Self {
            after: plan
                .activities
                .iter()
                .map(|a| {
                    a.after
                        .iter()
                        .map(|d| ids.get(d.activity.as_str()).copied())
                        .collect()
                })
                .collect(),
        }
    }
}

/// Builds the plan of the cycle at `t` (`links`: those of `plan`).
pub(super) fn cycle_plan(
    plan: &Plan,
    links: &Links,
    t: i64,
    status: &[Status],
    state_values: &[(String, String)],
    start: CycleStart,
) -> Built {
    let n = plan.activities.len();
    let started = |i: usize| !matches!(status[i], Status::Waiting);
    let mut dropped: Vec<Option<Dropped>> = vec![None; n];
    // Groups with a member that started keep no other member (the first such
    // member, in file order, is named).
    let mut ran_in_group: std::collections::BTreeMap<&str, usize> =
        std::collections::BTreeMap::new();
    for (j, a) in plan.activities.iter().enumerate() {
        if let Some(g) = a.group.as_deref().filter(|_| started(j)) {
            ran_in_group.entry(g).or_insert(j);
        }
    }
    for (i, a) in plan.activities.iter().enumerate() {
        if started(i) {
            continue;
        }
        if let Some(&by) = a.group.as_deref().and_then(|g| ran_in_group.get(g)) {
            dropped[i] = Some(Dropped::GroupMemberRan(by));
        }
    }
    // Windows from `t` on, cut by dependencies on activities that ended.
    let mut windows: Vec<Option<Vec<Window>>> = vec![None; n];
    for (i, a) in plan.activities.iter().enumerate() {
        if started(i) || dropped[i].is_some() {
            continue;
        }
        let horizon_last = plan.horizon.end - 1;
        let mut cut = a.windows.is_some();
        let mut ranges: Vec<Window> = match &a.windows {
            Some(ws) => ws.clone(),
            None => vec![Window {
                start: plan.horizon.start,
                end: horizon_last,
                preferred: None,
                cutoff: None,
            }],
        };
        for (d, &j) in a.after.iter().zip(&links.after[i]) {
            let Some(j) = j else {
                continue;
            };
            if let Status::Ended { end } = status[j] {
                cut = true;
                let (min, max) = if d.meets {
                    (0, Some(0))
                } else {
                    (d.min_delay.unwrap_or(0), d.max_delay)
                };
                let lo = end.saturating_add(min);
                let hi = max.map_or(i64::MAX, |m| end.saturating_add(m));
                ranges = ranges.into_iter().filter_map(|w| clip(w, lo, hi)).collect();
                if ranges.is_empty() {
                    dropped[i] = Some(Dropped::DependencyPassed { on: j, end });
                    break;
                }
            }
        }
        if dropped[i].is_some() {
            continue;
        }
        // No start before the cycle: windows are clipped to `t` (a preferred time
        // before `t` becomes `t`, which ranks the remaining starts the same way).
        ranges = ranges
            .into_iter()
            .filter_map(|w| clip(w, t, i64::MAX))
            .collect();
        windows[i] = cut.then_some(ranges);
    }
    // Dependents of dropped activities can no longer run either.
    loop {
        let mut changed = false;
        for i in 0..n {
            if started(i) || dropped[i].is_some() {
                continue;
            }
            if let Some(j) = links.after[i]
                .iter()
                .flatten()
                .copied()
                .find(|&j| dropped[j].is_some())
            {
                dropped[i] = Some(Dropped::DependsOnDropped(j));
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    let mut activities = Vec::new();
    let mut activity_of = Vec::new();
    for (i, a) in plan.activities.iter().enumerate() {
        // Ended and dropped activities are left out before any copy is made.
        if matches!(status[i], Status::Ended { .. })
            || (matches!(status[i], Status::Waiting) && dropped[i].is_some())
        {
            continue;
        }
        let mut a = a.clone();
        match status[i] {
            Status::Ended { .. } => continue,
            Status::Executing { hold, .. } => {
                a.duration = Duration::Fixed(hold - t);
                a.windows = Some(vec![Window {
                    start: t,
                    end: t,
                    preferred: None,
                    cutoff: None,
                }]);
                a.after.clear();
                a.effects.retain(|e| e.at == EffectAt::End);
                a.duration_model = None;
            }
            Status::Waiting => {
                if dropped[i].is_some() {
                    continue;
                }
                a.windows = windows[i].take();
                // Dependencies on ended activities became windows.
                let mut targets = links.after[i].iter();
                a.after.retain(|_| {
                    targets
                        .next()
                        .copied()
                        .flatten()
                        .is_some_and(|j| !matches!(status[j], Status::Ended { .. }))
                });
            }
        }
        activities.push(a);
        activity_of.push(i);
    }
    // Every plan-wide field as it is (cloning the activities would be wasted).
    let mut out = plan.without_activities();
    out.activities = activities;
    out.horizon.start = t;
    out.battery.initial = (start.soc_mj as f64 / MJ_PER_WH).clamp(0.0, out.battery.capacity);
    out.data.initial = (start.data_bit as f64 / BIT_PER_MBIT).max(0.0);
    if let Some(cap) = out.data.capacity {
        out.data.initial = out.data.initial.min(cap);
    }
    for (name, value) in state_values {
        if let Some(def) = out.states.get_mut(name) {
            def.initial = value.clone();
        }
    }
    // A handover already past binds nothing any more.
    if out.handover.is_some_and(|h| h.time < t) {
        out.handover = None;
    }
    out.cycle = Some(start);
    Built {
        plan: out,
        activity_of,
        dropped: dropped
            .into_iter()
            .enumerate()
            .filter_map(|(i, d)| Some((i, d?)))
            .collect(),
    }
}

/// Window `w` with its start range cut to `[lo, hi]`, if anything is left.
fn clip(w: Window, lo: i64, hi: i64) -> Option<Window> {
    let start = w.start.max(lo);
    let end = w.end.min(hi);
    (start <= end).then(|| Window {
        start,
        end,
        preferred: Some(w.preferred_start().clamp(start, end)),
        cutoff: w.cutoff,
    })
}
