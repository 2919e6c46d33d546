//! Execution: what the onboard scheduler does while the plan runs, with actual
//! durations that differ from the predicted ones (the execution extension of the
//! format, `spec/execution.md`; readings in docs/semantics.md, "Execution").
//!
//! Scheduling cycles happen at `horizon.start`, every `replan_period`, and (with
//! `replan_on_end`) whenever an executing activity ends. Each cycle runs the
//! ordinary scheduler on a plan of its own ([`cycle`]): the activities not yet
//! started, from the state the rover is really in, so the step trace and the
//! explainer work on any cycle unchanged. Between cycles activities start at the
//! latest cycle's start times when the dispatch guard lets them (`policy::dispatch`),
//! and run for their actual durations; the executed profiles are integrated from
//! what really ran ([`record`]).

mod actuals;
mod cycle;
mod montecarlo;
mod policy;
mod record;
mod text;
mod why;

pub use actuals::{ACTUALS_FORMAT, Actuals, load_actuals, sample_actuals, sample_run};
pub use cycle::Dropped;
pub use montecarlo::{
    ActivitySummary, Campaign, CauseCount, Distribution, LimitSummary, LossRecord, LostSummary,
    MONTECARLO_FORMAT, MONTECARLO_RUNS_FORMAT, PairSummary, Predictor, Quantiles, RunRecord,
    RunsDoc, Summary, campaign, campaign_runs, campaign_with, merge_parts, run_record, summarize,
};
pub use policy::Policy;
pub use record::{ExecutedProfile, Violation, ViolationKind};
pub use text::loss_line;
pub use why::{Cause, Loss, loss, losses};

pub(crate) use montecarlo::runs_of;

use crate::error::Error;
use crate::model::{CycleStart, EffectAt, HeaterHold, Plan};
use crate::scheduler::{Problem, Schedule, run_outcomes, schedule};
use cycle::{Status, cycle_plan};
use record::{Integrator, Record, union};

/// One execution of a plan.
#[derive(Clone, Debug)]
pub struct Execution {
    /// The scheduling cycles, in time order.
    pub cycles: Vec<Cycle>,
    /// What happened to each plan activity (file order).
    pub activities: Vec<ActivityRun>,
    /// The executed state of charge, data volume and peak power.
    pub profile: ExecutedProfile,
    /// Limits the executed profile breaks, in the order first broken.
    pub violations: Vec<Violation>,
    /// Lowest executed state of charge (mJ) and its time.
    pub lowest_soc: (i128, i64),
    /// Executed state of charge at `handover.time` (mJ), when the plan has one.
    pub handover_soc: Option<i128>,
    /// The compiled plan (fixed-point figures the profiles are in).
    pub problem: Problem,
}

/// Why a cycle ran.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Trigger {
    /// The first cycle, at `horizon.start`.
    Start,
    /// A `replan_period` boundary.
    Period,
    /// An executing activity ended (plan activity index).
    End(usize),
}

/// One scheduling cycle.
#[derive(Clone, Debug)]
pub struct Cycle {
    /// When it ran.
    pub time: i64,
    /// Why.
    pub trigger: Trigger,
    /// The plan it scheduled (its activities are those not yet started, and the
    /// ones still executing, placed first); `None` when the execution was run
    /// without keeping them (Monte Carlo).
    pub plan: Option<Plan>,
    /// State of charge it started from (mJ).
    pub soc: i128,
    /// Where it placed each of its activities (by cycle-plan index).
    pub placements: Vec<Option<(i64, i64)>>,
    /// The plan activity index of each of the cycle plan's activities.
    pub activity_of: Vec<usize>,
    /// Activities not yet started that this cycle left out (they can no longer
    /// run), with why.
    pub dropped: Vec<(usize, Dropped)>,
    /// What the dispatcher did until the next cycle.
    pub events: Vec<Event>,
}

impl Cycle {
    /// The cycle plan's index of plan activity `a`, if the cycle has it.
    pub fn index_of(&self, a: usize) -> Option<usize> {
        self.activity_of.iter().position(|&x| x == a)
    }

    /// Where the cycle placed plan activity `a`.
    pub fn placement(&self, a: usize) -> Option<(i64, i64)> {
        self.placements[self.index_of(a)?]
    }

    /// The cycle's scheduler run with its full step trace (run again from the
    /// cycle's plan: the execution keeps only the outcomes). `None` when the
    /// plan was not kept.
    pub fn schedule(&self) -> Option<Result<Schedule, Error>> {
        self.plan.as_ref().map(schedule)
    }
}

/// What [`execute_with`] keeps.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ExecuteOptions {
    /// Drop each cycle's plan (a Monte Carlo run needs only the outcomes).
    pub outcomes_only: bool,
    /// How activities are started (default: replanning every cycle).
    pub policy: Policy,
}

/// A dispatch event.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Event {
    /// Activity started at `time`.
    Started {
        /// Plan activity index.
        activity: usize,
        /// When.
        time: i64,
    },
    /// Activity was due at `time` but the guard held it back.
    Held {
        /// Plan activity index.
        activity: usize,
        /// When.
        time: i64,
        /// Why.
        guard: Guard,
    },
}

/// Why the dispatcher held an activity back.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Guard {
    /// A dependency had not ended (or its `min_delay` had not passed).
    Dependency(usize),
    /// An activity sharing a unit resource was still executing.
    Resource(usize),
    /// A required state did not hold (state index, value index).
    State(usize, usize),
    /// Dispatch policy: its skip condition passed before its start condition held.
    Skipped,
}

/// How an activity ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunOutcome {
    /// Ran for its actual duration.
    Completed,
    /// Optional, ran longer than `duration`: stopped at `start + duration`.
    Aborted,
    /// Never started.
    NotRun,
}

impl RunOutcome {
    /// The name in the execution document.
    pub fn name(self) -> &'static str {
        match self {
            RunOutcome::Completed => "completed",
            RunOutcome::Aborted => "aborted",
            RunOutcome::NotRun => "not_run",
        }
    }
}

/// What happened to one activity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ActivityRun {
    /// Completed, aborted or not run.
    pub outcome: RunOutcome,
    /// Where the first cycle placed it.
    pub predicted: Option<(i64, i64)>,
    /// Actual start and end.
    pub actual: Option<(i64, i64)>,
    /// The cycle that dispatched it.
    pub cycle: Option<usize>,
    /// The duration it would run for if started (its actual duration).
    pub duration: i64,
    /// The last cycle whose plan had it, if it never started.
    pub last_cycle: Option<usize>,
}

/// Executes `plan` with the actual durations of `actuals` (validated against the
/// plan by [`load_actuals`]; an activity not listed runs its `duration`).
pub fn execute(plan: &Plan, actuals: &Actuals) -> Result<Execution, Error> {
    execute_with(plan, actuals, ExecuteOptions::default())
}

/// [`execute`], keeping what `options` says.
pub fn execute_with(
    plan: &Plan,
    actuals: &Actuals,
    options: ExecuteOptions,
) -> Result<Execution, Error> {
    let problem = Problem::compile(plan)?;
    if !options.policy.is_replan() {
        let prepared = policy::Prepared::new(plan, options.policy)?;
        return Ok(policy::run(&problem, plan, &prepared, actuals, options));
    }
    let mut sim = Sim::new(&problem, plan, actuals);
    while sim.cycle(&problem, plan, options)? {}
    Ok(sim.finish(problem, plan))
}

/// The state of an execution between cycles (cloned to resume a run from a
/// shared prefix: [`Prefix::execute`]).
#[derive(Clone, Debug)]
struct Sim {
    /// Actual duration by activity (`None`: its `duration`).
    actual: Vec<Option<i64>>,
    status: Vec<Status>,
    runs: Vec<Option<Started>>,
    last_cycle: Vec<Option<usize>>,
    record: Record,
    integ: Integrator,
    cycles: Vec<Cycle>,
    /// The next cycle's time and trigger.
    t: i64,
    trigger: Trigger,
    prev_awake: Vec<(i64, i64)>,
    prev_heat: Vec<Heat>,
}

impl Sim {
    fn new(problem: &Problem, plan: &Plan, actuals: &Actuals) -> Self {
        let n = plan.activities.len();
        Self {
            actual: actual_durations(plan, actuals),
            status: vec![Status::Waiting; n],
            runs: vec![None; n],
            last_cycle: vec![None; n],
            record: Record::default(),
            integ: Integrator::new(problem),
            cycles: Vec::new(),
            t: problem.h0,
            trigger: Trigger::Start,
            prev_awake: Vec::new(),
            prev_heat: Vec::new(),
        }
    }

    /// Runs the cycle at `self.t` and dispatches until the next one; `false`
    /// when there is none.
    fn cycle(
        &mut self,
        problem: &Problem,
        plan: &Plan,
        options: ExecuteOptions,
    ) -> Result<bool, Error> {
        let (h0, h1) = (problem.h0, problem.h1);
        let period = plan.execution.and_then(|e| e.replan_period);
        let on_end = plan.execution.is_none_or(|e| e.replan_on_end);
        let t = self.t;
        let Sim {
            actual,
            status,
            runs,
            last_cycle,
            record,
            integ,
            cycles,
            prev_awake,
            prev_heat,
            ..
        } = self;
        integ.advance(problem, record, t);
        for (i, r) in runs.iter().enumerate() {
            if let Some(r) = r {
                status[i] = if r.end <= t {
                    Status::Ended { end: r.end }
                } else {
                    Status::Executing {
                        start: r.start,
                        hold: r.planned_end.max(t + 1),
                    }
                };
            }
        }
        let start = cycle_start(
            problem, plan, t, status, runs, record, integ, prev_awake, prev_heat,
        );
        let values = state_values(problem, plan, runs, t, true);
        let soc = start.soc_mj;
        let cp = cycle_plan(plan, t, status, &values, start);
        let run = run_outcomes(&cp.plan)?;
        let k = cycles.len();
        for &a in &cp.activity_of {
            if matches!(status[a], Status::Waiting) {
                last_cycle[a] = Some(k);
            }
        }
        // The next cycle: the next period boundary, or the first end after `t`.
        let mut next = period.map_or(h1, |p| {
            let done = (t - h0) / p;
            h0.saturating_add(p.saturating_mul(done + 1))
        });
        next = next.min(h1);
        let mut next_trigger = Trigger::Period;
        if on_end {
            if let Some((end, a)) = runs
                .iter()
                .enumerate()
                .filter_map(|(a, r)| r.map(|r| (r.end, a)))
                .filter(|&(end, _)| end > t)
                .min()
            {
                if end < next {
                    next = end;
                    next_trigger = Trigger::End(a);
                }
            }
        }
        // Dispatch: the cycle's start times, in time then step order.
        let mut due: Vec<(i64, usize, usize, i64)> = run
            .placements
            .iter()
            .enumerate()
            .filter_map(|(i, p)| {
                let (s, e) = (*p)?;
                let a = cp.activity_of[i];
                matches!(status[a], Status::Waiting).then_some((s, run.step_of[i], a, e - s))
            })
            .collect();
        due.sort_unstable();
        let mut events = Vec::new();
        let mut seq = runs.iter().flatten().count();
        for (s, _, a, planned) in due {
            if s >= next {
                break;
            }
            if let Some(guard) = guard(problem, plan, a, s, runs) {
                events.push(Event::Held {
                    activity: a,
                    time: s,
                    guard,
                });
                continue;
            }
            let (end, aborted) = end_of(plan, a, s, planned, actual[a]);
            runs[a] = Some(Started {
                start: s,
                end,
                planned_end: s + planned,
                aborted,
                cycle: k,
                seq,
            });
            seq += 1;
            status[a] = Status::Executing {
                start: s,
                hold: s + planned,
            };
            record.activity(problem, a, s, end);
            events.push(Event::Started {
                activity: a,
                time: s,
            });
            if on_end && end > t && end < next {
                next = end;
                next_trigger = Trigger::End(a);
            }
        }
        // What this cycle's schedule generated runs until the next cycle, and so
        // do the heaters that were already on.
        prev_awake.clear();
        prev_heat.clear();
        for h in cp.plan.cycle.iter().flat_map(|c| &c.heaters) {
            if let Some(z) = problem.zone_names.iter().position(|n| *n == h.zone) {
                let owner = h
                    .owner
                    .as_ref()
                    .and_then(|id| plan.activities.iter().position(|a| &a.id == id));
                prev_heat.push(Heat {
                    zone: z,
                    start: t,
                    end: h.end,
                    power: h.power_mw,
                    owner,
                });
                let b = h.end.min(next);
                if t < b {
                    record.heat.push((z, t, b, h.power_mw));
                }
            }
        }
        for &(a, b) in &run.awake {
            prev_awake.push((a, b));
            let (a, b) = (a.max(t), b.min(next));
            if a < b {
                record.awake.push((a, b));
            }
        }
        for &(zone, start, end, act) in &run.preheats {
            let power = problem.zones[zone].preheat;
            prev_heat.push(Heat {
                zone,
                start,
                end,
                power,
                owner: cp.activity_of.get(act).copied(),
            });
            let (a, b) = (start.max(t), end.min(next));
            if a < b {
                record.heat.push((zone, a, b, power));
            }
        }
        cycles.push(Cycle {
            time: t,
            trigger: self.trigger,
            plan: (!options.outcomes_only).then_some(cp.plan),
            soc,
            placements: run.placements,
            activity_of: cp.activity_of,
            dropped: cp.dropped,
            events,
        });
        if next >= h1 {
            return Ok(false);
        }
        self.t = next;
        self.trigger = next_trigger;
        Ok(true)
    }

    /// The execution, after the last cycle.
    fn finish(mut self, problem: Problem, plan: &Plan) -> Execution {
        let (h0, h1) = (problem.h0, problem.h1);
        self.integ.advance(&problem, &self.record, h1);
        let first = &self.cycles[0];
        let activities = (0..plan.activities.len())
            .map(|a| {
                let predicted = first.placement(a);
                let run = self.runs[a];
                ActivityRun {
                    outcome: match run {
                        None => RunOutcome::NotRun,
                        Some(r) if r.aborted => RunOutcome::Aborted,
                        Some(_) => RunOutcome::Completed,
                    },
                    predicted,
                    actual: run.map(|r| (r.start, r.end)),
                    cycle: run.map(|r| r.cycle),
                    duration: self.actual[a].unwrap_or(plan.activities[a].duration.max()),
                    last_cycle: if run.is_none() {
                        self.last_cycle[a]
                    } else {
                        None
                    },
                }
            })
            .collect();
        let mut profile = std::mem::take(&mut self.integ.profile);
        profile.awake = union(
            self.record
                .awake
                .iter()
                .map(|&(a, b)| (a.max(h0), b.min(h1)))
                .filter(|(a, b)| a < b)
                .collect(),
        );
        Execution {
            cycles: self.cycles,
            activities,
            profile,
            violations: self.integ.violations,
            lowest_soc: self.integ.lowest,
            handover_soc: self.integ.at_handover,
            problem,
        }
    }
}

/// The nominal execution's state before each of its cycles, from which a run
/// with other actual durations resumes at the last cycle before its first
/// difference ([`Prefix::execute`]).
#[derive(Clone, Debug)]
pub(crate) struct Prefix {
    /// The state before cycle `k` (without the cycles, kept once in `cycles`).
    before: Vec<Sim>,
    cycles: Vec<Cycle>,
}

impl Prefix {
    /// Runs the nominal execution of `plan`, keeping its state before each cycle.
    pub(crate) fn nominal(
        problem: &Problem,
        plan: &Plan,
        options: ExecuteOptions,
    ) -> Result<Self, Error> {
        let mut sim = Sim::new(problem, plan, &Actuals::nominal());
        let mut before = Vec::new();
        loop {
            let mut snapshot = sim.clone();
            snapshot.cycles = Vec::new();
            before.push(snapshot);
            if !sim.cycle(problem, plan, options)? {
                break;
            }
        }
        Ok(Self {
            before,
            cycles: sim.cycles,
        })
    }

    /// [`execute_with`] for `actuals`, from the last nominal cycle before the
    /// first end that `actuals` move: everything before it is the nominal run's
    /// (no end, start or cycle differs before then). Debug builds compare the
    /// result with a run from the start.
    pub(crate) fn execute(
        &self,
        problem: &Problem,
        plan: &Plan,
        actuals: &Actuals,
        options: ExecuteOptions,
    ) -> Result<Execution, Error> {
        let actual = actual_durations(plan, actuals);
        let last = &self.before[self.before.len() - 1];
        // The first time the run can differ: an activity the nominal run started
        // ending at another time (the earlier of the two ends).
        let diverges = last
            .runs
            .iter()
            .enumerate()
            .filter_map(|(a, r)| {
                let r = (*r)?;
                let end = end_of(plan, a, r.start, r.planned_end - r.start, actual[a]).0;
                (end != r.end).then_some(end.min(r.end))
            })
            .min()
            .unwrap_or(i64::MAX);
        let k = self
            .before
            .iter()
            .rposition(|s| s.t < diverges)
            .unwrap_or(0);
        let mut sim = self.before[k].clone();
        sim.cycles = self.cycles[..k].to_vec();
        sim.actual = actual;
        // Activities started before the resumed cycle end after it either way:
        // give them their actual ends.
        for a in 0..sim.runs.len() {
            let Some(r) = sim.runs[a] else { continue };
            let (end, aborted) = end_of(plan, a, r.start, r.planned_end - r.start, sim.actual[a]);
            if (end, aborted) != (r.end, r.aborted) {
                sim.record.forget_activity(problem, a, r.start, r.end);
                sim.record.activity(problem, a, r.start, end);
                sim.runs[a] = Some(Started { end, aborted, ..r });
            }
        }
        while sim.cycle(problem, plan, options)? {}
        let out = sim.finish(problem.clone(), plan);
        #[cfg(debug_assertions)]
        if let Ok(full) = execute_with(plan, actuals, options) {
            debug_assert_eq!(out.activities, full.activities, "the resumed run differs");
            debug_assert_eq!(out.profile, full.profile, "the resumed profile differs");
        }
        Ok(out)
    }
}

/// When an activity started at `start` for a planned `planned` seconds ends,
/// and whether it is aborted: an optional one stops at `start + planned`.
fn end_of(plan: &Plan, a: usize, start: i64, planned: i64, actual: Option<i64>) -> (i64, bool) {
    let end = start + actual.unwrap_or(planned);
    if !plan.activities[a].mandatory && end > start + planned {
        (start + planned, true)
    } else {
        (end, false)
    }
}

/// The actual duration of each activity under `actuals` (`None`: its
/// `duration`).
fn actual_durations(plan: &Plan, actuals: &Actuals) -> Vec<Option<i64>> {
    plan.activities
        .iter()
        .map(|a| actuals.durations.get(&a.id).copied())
        .collect()
}

/// A started activity.
#[derive(Clone, Copy, Debug)]
struct Started {
    start: i64,
    /// Actual end (the abort time when aborted).
    end: i64,
    /// `start` + the duration the cycle placed it for.
    planned_end: i64,
    aborted: bool,
    cycle: usize,
    /// Dispatch order (breaks ties between effects at one instant).
    seq: usize,
}

/// A heater demand of a cycle's schedule, or a heater already on at its start.
#[derive(Clone, Copy, Debug)]
struct Heat {
    zone: usize,
    start: i64,
    end: i64,
    power: i64,
    /// The activity (plan index) whose preheat it is.
    owner: Option<usize>,
}

/// What the cycle at `t` starts from.
#[allow(clippy::too_many_arguments)]
fn cycle_start(
    problem: &Problem,
    plan: &Plan,
    t: i64,
    status: &[Status],
    runs: &[Option<Started>],
    record: &Record,
    integ: &Integrator,
    prev_awake: &[(i64, i64)],
    prev_heat: &[Heat],
) -> CycleStart {
    let held: Vec<usize> = (0..status.len())
        .filter(|&a| matches!(status[a], Status::Executing { .. }))
        .collect();
    // The awake period the rover is in: on in the second before the cycle, to
    // its planned end in the latest schedule, and at least while an activity
    // that requires it is still executing (with its shutdown).
    let awake = (t > problem.h0)
        .then(|| record.awake_since(t - 1))
        .flatten()
        .and_then(|since| {
            let planned = prev_awake
                .iter()
                .filter(|&&(a, b)| a < t && t <= b)
                .map(|&(_, b)| b)
                .max();
            let running = held
                .iter()
                .filter(|&&a| problem.acts[a].awake == crate::model::AwakeMode::Required)
                .filter_map(|&a| match status[a] {
                    Status::Executing { hold, .. } => Some(hold + problem.shut),
                    _ => None,
                })
                .max();
            let end = planned.max(running)?;
            (end > t).then_some((since, end))
        });
    let mut heaters: Vec<HeaterHold> = prev_heat
        .iter()
        .filter(|h| h.start < t && t <= h.end)
        .map(|h| HeaterHold {
            zone: problem.zone_names[h.zone].clone(),
            end: h.end,
            power_mw: h.power,
            owner: h
                .owner
                .filter(|&o| matches!(status[o], Status::Waiting))
                .map(|o| plan.activities[o].id.clone()),
        })
        .collect();
    // A zone kept warm by an activity running in the second before the cycle is
    // on then too (an activity starting at the cycle needs no preheat; one still
    // executing keeps it on through its own placement).
    for (a, r) in runs.iter().enumerate() {
        let Some(r) = r else { continue };
        if r.start < t && t <= r.end {
            for &z in &problem.acts[a].zones {
                heaters.push(HeaterHold {
                    zone: problem.zone_names[z].clone(),
                    end: t,
                    power_mw: problem.zones[z].maintenance,
                    owner: None,
                });
            }
        }
    }
    CycleStart {
        soc_mj: integ.soc,
        data_bit: integ.data,
        produced_bit: integ.produced,
        held: held
            .iter()
            .map(|&a| plan.activities[a].id.clone())
            .collect(),
        awake,
        heaters,
    }
}

/// The executed value of every state at `t` (`(state, value)` names): effects
/// at or before `t` (`inclusive`) or strictly before it, in time then dispatch
/// order.
fn state_values(
    problem: &Problem,
    plan: &Plan,
    runs: &[Option<Started>],
    t: i64,
    inclusive: bool,
) -> Vec<(String, String)> {
    let mut values = problem.state_initial.clone();
    let mut effects: Vec<(i64, usize, usize, usize)> = Vec::new();
    for (a, r) in runs.iter().enumerate() {
        let Some(r) = r else { continue };
        for e in &problem.acts[a].effects {
            let at = if e.at == EffectAt::Start {
                r.start
            } else {
                r.end
            };
            if at < t || (inclusive && at == t) {
                effects.push((at, r.seq, e.state, e.value));
            }
        }
    }
    effects.sort_unstable();
    for (_, _, s, v) in effects {
        values[s] = v;
    }
    plan.states
        .iter()
        .zip(values)
        .map(|((name, def), v)| (name.clone(), def.values[v].clone()))
        .collect()
}

/// Why activity `a` may not start at `s`, if it may not.
fn guard(
    problem: &Problem,
    plan: &Plan,
    a: usize,
    s: i64,
    runs: &[Option<Started>],
) -> Option<Guard> {
    let act = &problem.acts[a];
    for d in &act.after {
        let ended = runs[d.target].is_some_and(|r| r.end.saturating_add(d.min_delay) <= s);
        if !ended {
            return Some(Guard::Dependency(d.target));
        }
    }
    for (b, r) in runs.iter().enumerate() {
        let Some(r) = r else { continue };
        if b != a
            && r.start <= s
            && s < r.end
            && problem.acts[b]
                .resources
                .iter()
                .any(|x| act.resources.contains(x))
        {
            return Some(Guard::Resource(b));
        }
    }
    if !act.requires.is_empty() {
        let values = state_values(problem, plan, runs, s, true);
        for req in &act.requires {
            let (name, def) = plan.states.iter().nth(req.state)?;
            let now = &values.iter().find(|(n, _)| n == name)?.1;
            if def.values[req.value] != *now {
                return Some(Guard::State(req.state, req.value));
            }
        }
    }
    None
}
