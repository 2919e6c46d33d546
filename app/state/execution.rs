//! The execution of the open plan (execution mode): where its actual durations
//! come from ([`ActualsSource`]), one execution with the plot points the views
//! draw ([`ExecutionRun`]), and one scheduling cycle's scheduler run with its
//! step trace ([`CycleRun`]). Built from the plan, never edited; the app derives
//! them per plan revision and actuals choice (`derived::ExecutionCache`).

use std::path::PathBuf;

use solscope_engine::{
    ActivityRun, Actuals, CyclePlan, Error, Execution, Plan, RunOutcome, Schedule, Step, StepTrace,
    execute, load_actuals, mbit, sample_run, watts, wh,
};

use super::ui::StepView;

/// Where the actual durations of the execution come from.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum ActualsSource {
    /// Every activity runs exactly its `duration`.
    #[default]
    Nominal,
    /// Drawn from the plan's `duration_model`s: Monte Carlo run `run` of a
    /// campaign seeded with `seed` (run 0 is what "Sample" draws); drawn again
    /// for every revision of the plan, so an edited model is followed.
    Sampled {
        /// The campaign seed.
        seed: u64,
        /// The run index.
        run: u64,
    },
    /// A `solscope.actuals/1` file: its text, read again against every revision
    /// of the plan.
    File {
        /// Where it was read from.
        path: PathBuf,
        /// What it held.
        text: String,
    },
}

impl ActualsSource {
    /// How the toolbar names it: `nominal`, `sampled, seed 7` (run 0),
    /// `sampled, seed 7, run 12`, or the file name.
    pub fn describe(&self) -> String {
        match self {
            Self::Nominal => "nominal".into(),
            Self::Sampled { seed, run: 0 } => format!("sampled, seed {seed}"),
            Self::Sampled { seed, run } => format!("sampled, seed {seed}, run {run}"),
            Self::File { path, .. } => path.file_name().map_or_else(
                || path.display().to_string(),
                |n| n.to_string_lossy().into_owned(),
            ),
        }
    }

    /// The actual durations for `plan` (a file is validated against it, with
    /// path-named errors).
    pub fn actuals(&self, plan: &Plan) -> Result<Actuals, Error> {
        match self {
            Self::Nominal => Ok(Actuals::nominal()),
            Self::Sampled { seed, run } => Ok(sample_run(plan, *seed, *run)),
            Self::File { text, .. } => load_actuals(text, plan),
        }
    }
}

/// One execution of the plan, with its profiles as plot points.
#[derive(Debug)]
pub struct ExecutionRun {
    /// The plan executed (shared with the workers that rebuild a cycle's plan
    /// or explain a loss, so that asking for one copies nothing on the UI
    /// thread).
    pub plan: std::sync::Arc<Plan>,
    /// The execution.
    pub execution: Execution,
    /// The actual durations it ran with.
    pub actuals: Actuals,
    /// The executed state of charge, peak power and data volume.
    pub executed: StepView,
    /// The first cycle's prediction: its schedule's profiles after its last step
    /// (or why its scheduler run could not be repeated).
    pub predicted: Result<StepView, String>,
}

impl ExecutionRun {
    /// Executes `plan` with the actuals of `source`; also returns the first
    /// cycle's scheduler run (its final profiles are the prediction), so that it
    /// need not be run twice.
    pub fn of(
        plan: std::sync::Arc<Plan>,
        source: &ActualsSource,
    ) -> Result<(Self, Option<CycleRun>), String> {
        let actuals = source
            .actuals(&plan)
            .map_err(|e| format!("actuals ({}): {e}", source.describe()))?;
        let execution = execute(&plan, &actuals).map_err(|e| e.to_string())?;
        let first = CycleRun::of(0, &execution, &plan);
        let predicted = match &first {
            Some(run) => run
                .schedule
                .as_ref()
                .map(|s| StepView::from_profiles(s.steps.len(), &s.profiles_after(s.steps.len())))
                .map_err(Clone::clone),
            None => Err("the execution kept no cycle plan".into()),
        };
        let executed = executed_view(&execution);
        let run = Self {
            plan,
            execution,
            actuals,
            executed,
            predicted,
        };
        Ok((run, first))
    }

    /// `(completed, aborted, not run)` activities.
    pub fn counts(&self) -> (usize, usize, usize) {
        let count = |o: RunOutcome| {
            self.execution
                .activities
                .iter()
                .filter(|r| r.outcome == o)
                .count()
        };
        (
            count(RunOutcome::Completed),
            count(RunOutcome::Aborted),
            count(RunOutcome::NotRun),
        )
    }

    /// Cycle `k`, clamped to the cycles there are (an execution has at least one).
    pub fn cycle_index(&self, k: usize) -> usize {
        k.min(self.execution.cycles.len().saturating_sub(1))
    }

    /// What happened to plan activity `a`.
    pub fn activity(&self, a: usize) -> Option<&ActivityRun> {
        self.execution.activities.get(a)
    }
}

/// The executed profiles as plot points (peak power as steps to the horizon end).
fn executed_view(execution: &Execution) -> StepView {
    let p = &execution.profile;
    let mut peak: Vec<[f64; 2]> = p
        .peak
        .windows(2)
        .flat_map(|w| {
            let (t0, t1, v) = (w[0].0 as f64, w[1].0 as f64, watts(w[0].1));
            [[t0, v], [t1, v]]
        })
        .collect();
    if let Some(&(t, v)) = p.peak.last() {
        let h1 = execution.problem.h1 as f64;
        peak.extend([[t as f64, watts(v)], [h1, watts(v)]]);
    }
    StepView {
        step: 0,
        soc: p.soc.iter().map(|&(t, x)| [t as f64, wh(x)]).collect(),
        peak,
        data: p.data.iter().map(|&(t, x)| [t as f64, mbit(x)]).collect(),
    }
}

/// One scheduling cycle's scheduler run, repeated with its step trace from the
/// cycle's own plan (the activities not yet started, from the cycle's time).
#[derive(Debug)]
pub struct CycleRun {
    /// Which cycle.
    pub index: usize,
    /// The run (cycle-plan indices), or why it could not be repeated.
    pub schedule: Result<Schedule, String>,
    /// The cycle's plan (rebuilt from the execution; `None` when it could not
    /// be).
    pub plan: Option<Plan>,
    /// The plan activity of each cycle-plan activity.
    pub activity_of: Vec<usize>,
    /// What each step's record leaves out (`traces[k - 1]` for step k): its
    /// category intervals, and the tries of a failed step (the run itself
    /// records outcomes only).
    pub traces: Vec<StepTrace>,
}

impl CycleRun {
    /// The scheduler run of cycle `index` of `execution` (an execution of
    /// `plan`); `None` when it has no such cycle.
    pub fn of(index: usize, execution: &Execution, plan: &Plan) -> Option<Self> {
        Some(Self::from_plan(index, execution.cycle_plan(plan, index)?))
    }

    /// The scheduler run of cycle `index`, whose plan is `cycle`.
    fn from_plan(index: usize, cycle: CyclePlan) -> Self {
        let schedule = cycle.schedule().map_err(|e| e.to_string());
        let traces = schedule.as_ref().map_or(Vec::new(), Schedule::all_traces);
        Self {
            index,
            schedule,
            plan: Some(cycle.plan),
            activity_of: cycle.activity_of,
            traces,
        }
    }

    /// Its number of steps (0 when it could not be repeated).
    pub fn steps(&self) -> usize {
        self.schedule.as_ref().map_or(0, |s| s.steps.len())
    }

    /// The plan activity of cycle-plan activity `i`.
    pub fn plan_activity(&self, i: usize) -> Option<usize> {
        self.activity_of.get(i).copied()
    }

    /// The step record of plan activity `a` in this run, if the cycle had it.
    pub fn step_of(&self, a: usize) -> Option<&Step> {
        let i = self.activity_of.iter().position(|&x| x == a)?;
        self.schedule.as_ref().ok()?.step_of(i)
    }

    /// The plan activity of step `k` (1-based).
    pub fn activity_of_step(&self, k: usize) -> Option<usize> {
        let s = self.schedule.as_ref().ok()?;
        let step = s.steps.get(k.checked_sub(1)?)?;
        self.plan_activity(step.activity)
    }
}
