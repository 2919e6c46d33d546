//! Execution: what the onboard scheduler does while the plan runs, with actual
//! durations that differ from the predicted ones (the execution extension of the
//! format, docs/format.md §10; readings in docs/semantics.md, "Execution").
//!
//! Scheduling cycles happen at `horizon.start`, every `replan_period`, and (with
//! `replan_on_end`) whenever an executing activity ends. Each cycle runs the
//! ordinary scheduler on a plan of its own ([`cycle`]): the activities not yet
//! started, from the state the rover is really in, so the step trace and the
//! explainer work on any cycle unchanged. Between cycles activities start at the
//! latest cycle's start times when the dispatch guard lets them, and run for
//! their actual durations; the executed profiles are integrated from what really
//! ran ([`record`]).
//!
//! One loop runs every execution, whatever its [`Policy`]: `sim`'s `Sim::run`
//! goes cycle after cycle and asks its policy (an `Executive`: replan, fixed or
//! dispatch, in `policy`) what the cycle schedules, when the next cycle is and
//! what starts before it.

mod actuals;
mod cycle;
mod montecarlo;
mod policy;
mod record;
mod resume;
mod sim;
mod text;
mod why;

pub use actuals::{ACTUALS_FORMAT, Actuals, load_actuals, sample_actuals, sample_run};
pub use cycle::{CyclePlan, Dropped};
pub use montecarlo::{
    ActivitySummary, Campaign, CauseCount, Distribution, LimitSummary, LossRecord, LostSummary,
    MONTECARLO_FORMAT, MONTECARLO_RUNS_FORMAT, PairSummary, Predictor, Quantiles, RunRecord,
    RunsDoc, Summary, campaign, campaign_runs, campaign_with, merge_files, merge_parts, read_runs,
    run_record, summarize,
};
pub use policy::Policy;
pub use record::{ExecutedProfile, Violation, ViolationKind};
pub use text::loss_line;
pub use why::{Cause, Loss, loss, losses};

pub(crate) use montecarlo::runs_of;

use crate::error::Error;
use crate::model::{CycleStart, Plan};
use crate::scheduler::Problem;
use cycle::Status;
use policy::{Prepared, Replan};
use sim::{Sim, Started, actual_durations, end_of, state_values};

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
    /// How each activity that started ran (from which the cycles' plans are
    /// rebuilt, [`Execution::cycle_plan`]).
    runs: Vec<Option<Started>>,
}

impl Execution {
    /// The plan cycle `k` scheduled (its activities are those not yet
    /// started, and the ones still executing, placed first), rebuilt from what
    /// ran before the cycle and the state it started from: an execution keeps
    /// per cycle only what its document and loss explanations read, so that
    /// its memory grows with its activities plus its cycles. `plan` is the
    /// plan executed. Debug builds compare every cycle's rebuilt plan with the
    /// one it scheduled.
    pub fn cycle_plan(&self, plan: &Plan, k: usize) -> Option<CyclePlan> {
        let c = self.cycles.get(k)?;
        let Some(start) = &c.start else {
            // A policy that schedules once: the plan as it is.
            return Some(CyclePlan {
                plan: plan.clone(),
                activity_of: (0..plan.activities.len()).collect(),
            });
        };
        let (status, values) = self.cycle_state(plan, k);
        let links = cycle::Links::new(plan);
        let built = cycle::cycle_plan(plan, &links, c.time, &status, &values, start.clone());
        Some(CyclePlan {
            plan: built.plan,
            activity_of: built.activity_of,
        })
    }

    /// What cycle `k` knew of each activity (not started, executing or
    /// ended) and the executed value of every state at its time, rebuilt
    /// from what had started before it (the activities it dispatches start
    /// at or after its time).
    fn cycle_state(&self, plan: &Plan, k: usize) -> (Vec<Status>, Vec<(String, String)>) {
        let time = self.cycles[k].time;
        let runs: Vec<Option<Started>> = self
            .runs
            .iter()
            .map(|r| r.filter(|r| r.cycle < k))
            .collect();
        let status: Vec<Status> = runs.iter().map(|r| Status::at(r.as_ref(), time)).collect();
        let values = state_values(&self.problem, plan, &runs, time);
        (status, values)
    }
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

/// One scheduling cycle: what the execution document and the loss
/// explanations read of it. Its plan and its scheduler run are rebuilt on
/// demand ([`Execution::cycle_plan`], [`CyclePlan::schedule`]).
#[derive(Clone, Debug)]
pub struct Cycle {
    /// When it ran.
    pub time: i64,
    /// Why.
    pub trigger: Trigger,
    /// State of charge it started from (mJ).
    pub soc: i128,
    /// Activities not yet started that this cycle left out (they can no longer
    /// run), with why.
    pub dropped: Vec<(usize, Dropped)>,
    /// What the dispatcher did until the next cycle.
    pub events: Vec<Event>,
    /// The state it started from (`None`: a policy that schedules once, the
    /// plan as it is).
    start: Option<CycleStart>,
    /// How many of its plan's activities it placed.
    placed: usize,
    /// The plan activities it did not place, in file order.
    failed: Vec<usize>,
}

impl Cycle {
    /// How many of its plan's activities it placed (still executing ones
    /// included).
    pub fn placed(&self) -> usize {
        self.placed
    }

    /// The plan activity indices of the activities of its plan it did not
    /// place, in file order.
    pub fn failed(&self) -> &[usize] {
        &self.failed
    }

    /// Whether its plan had plan activity `a` and it did not place it.
    pub fn did_not_place(&self, a: usize) -> bool {
        self.failed.binary_search(&a).is_ok()
    }
}

/// How [`execute_with`] runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ExecuteOptions {
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
    /// Too few sequence engines were free: those held by the executing
    /// activities plus its own exceed `sequence_engines` (the first such
    /// executing activity in file order).
    Engines(usize),
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

/// [`execute`] under the policy `options` names.
pub fn execute_with(
    plan: &Plan,
    actuals: &Actuals,
    options: ExecuteOptions,
) -> Result<Execution, Error> {
    let problem = Problem::compile(plan)?;
    if options.policy.is_replan() {
        let sim = Sim::new(&problem, plan, actuals);
        sim.run(&problem, plan, &Replan::new(plan))
    } else {
        Prepared::new(plan, options.policy)?.execute(&problem, plan, actuals)
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
    pub(crate) fn nominal(problem: &Problem, plan: &Plan) -> Result<Self, Error> {
        let replan = Replan::new(plan);
        let mut sim = Sim::new(problem, plan, &Actuals::nominal());
        let mut before = Vec::new();
        loop {
            let mut snapshot = sim.clone();
            snapshot.cycles = Vec::new();
            before.push(snapshot);
            if !sim.cycle(problem, plan, &replan)? {
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
        let out = sim.run(problem, plan, &Replan::new(plan))?;
        #[cfg(debug_assertions)]
        if let Ok(full) = execute(plan, actuals) {
            debug_assert_eq!(out.activities, full.activities, "the resumed run differs");
            debug_assert_eq!(out.profile, full.profile, "the resumed profile differs");
        }
        Ok(out)
    }
}
