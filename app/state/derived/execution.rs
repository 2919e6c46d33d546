//! The execution of the plan at one [`ExecKey`] (plan revision and actuals),
//! the scheduler runs of the cycles looked at, the profiles of the step shown
//! inside one of them, and why the selected activity did not complete.

use std::collections::BTreeMap;
use std::sync::Arc;

use solscope_engine::{Loss, Plan, RunOutcome};

use super::super::execution::{ActualsSource, CycleRun, ExecutionRun};
use super::super::job::{Job, Lost, Signal};
use super::super::ui::StepView;

/// What an execution is derived for: the plan revision and the actuals choice
/// (bumped whenever the source of the actual durations changes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ExecKey {
    /// The plan revision.
    pub revision: u64,
    /// The actuals revision.
    pub actuals: u64,
}

/// What an execution worker sends back: the execution and the first cycle's run.
type ExecResult = Result<(ExecutionRun, Option<CycleRun>), String>;

/// At most this many cycles' scheduler runs are kept (each is one schedule of
/// the plan's remaining activities).
pub(super) const KEPT_CYCLE_RUNS: usize = 16;

/// The execution of the plan at one [`ExecKey`], the scheduler runs of the
/// cycles looked at, the profiles of the step shown inside one of them, and why
/// the selected activity did not complete.
/// Each value is read back only for the key it was derived for. With
/// `background` each is computed on a worker thread (one of each kind at a
/// time; a result for an older key is dropped), so a large plan never stalls a
/// frame.
#[derive(Debug, Default)]
pub struct ExecutionCache {
    /// The execution (shared with the worker explaining a loss).
    run: Option<(ExecKey, Result<Arc<ExecutionRun>, String>)>,
    pub(super) pending: Option<Job<ExecKey, ExecResult>>,
    /// Cycle runs of the execution in `run`, by cycle.
    pub(super) cycles: BTreeMap<usize, CycleRun>,
    pending_cycle: Option<Job<(ExecKey, usize), Option<CycleRun>>>,
    /// The profiles after one step of one cycle's run.
    view: Option<((ExecKey, usize, usize), StepView)>,
    /// Why one activity did not complete (the explainer at the cycle that
    /// decided it).
    loss: Option<((ExecKey, usize), Result<Loss, String>)>,
    pending_loss: Option<Job<(ExecKey, usize), Result<Loss, String>>>,
}

impl ExecutionCache {
    /// The execution at `key`, or why there is none, once derived.
    pub fn run(&self, key: ExecKey) -> Option<&Result<Arc<ExecutionRun>, String>> {
        self.run.as_ref().filter(|(k, _)| *k == key).map(|(_, r)| r)
    }

    /// Starts deriving the execution of `plan` with `source` at `key` unless it
    /// is known or a worker is busy.
    pub fn request(&mut self, plan: &Plan, source: &ActualsSource, key: ExecKey, background: bool) {
        if self.run(key).is_some() || self.pending.is_some() {
            return;
        }
        if background {
            let (plan, source) = (Arc::new(plan.clone()), source.clone());
            self.pending = Some(Job::spawn(key, move |_: &Signal| {
                ExecutionRun::of(plan, &source)
            }));
        } else {
            self.store(key, ExecutionRun::of(Arc::new(plan.clone()), source));
        }
    }

    fn store(&mut self, key: ExecKey, result: ExecResult) {
        self.cycles.clear();
        self.view = None;
        self.loss = None;
        let run = result.map(|(run, first)| {
            if let Some(first) = first {
                self.cycles.insert(0, first);
            }
            Arc::new(run)
        });
        self.run = Some((key, run));
    }

    /// Takes finished workers' results: kept when they are for `key`, dropped
    /// otherwise. A worker that stopped without a result is reported.
    pub fn reap(&mut self, key: ExecKey) -> Result<(), String> {
        let mut lost = None;
        if let Some(job) = &self.pending {
            if let Some(result) = job.poll() {
                let current = job.key() == key;
                self.pending = None;
                match result {
                    Ok(r) if current => self.store(key, r),
                    Ok(_) => {}
                    Err(Lost) => {
                        if current {
                            let e =
                                "Executing the plan failed: the worker stopped without a result";
                            self.store(key, Err(e.into()));
                            lost = Some(e.to_string());
                        }
                    }
                }
            }
        }
        if let Some(job) = &self.pending_cycle {
            if let Some(result) = job.poll() {
                let (job_key, k) = job.key();
                self.pending_cycle = None;
                let current = job_key == key && self.run(key).is_some();
                match result {
                    Ok(Some(run)) if current => self.keep_cycle(k, run),
                    Ok(_) => {}
                    Err(Lost) => {
                        if current {
                            let e = format!(
                                "Scheduling cycle {k} again failed: the worker stopped without a result"
                            );
                            self.keep_cycle(
                                k,
                                CycleRun {
                                    index: k,
                                    schedule: Err(e.clone()),
                                    plan: None,
                                    activity_of: Vec::new(),
                                    traces: Vec::new(),
                                },
                            );
                            lost = Some(e);
                        }
                    }
                }
            }
        }
        if let Some(job) = &self.pending_loss {
            if let Some(result) = job.poll() {
                let job_key = job.key();
                self.pending_loss = None;
                if job_key.0 == key {
                    let value = result.unwrap_or_else(|Lost| {
                        Err("the worker stopped without a result".to_string())
                    });
                    self.loss = Some((job_key, value));
                }
            }
        }
        lost.map_or(Ok(()), Err)
    }

    /// Starts finding out why activity `a` did not complete in the execution at
    /// `key` (the explainer at the cycle that decided it: one explanation of
    /// that cycle's plan), unless it completed, it is known, or a worker is busy.
    pub fn request_loss(&mut self, key: ExecKey, a: usize, background: bool) {
        if self.loss(key, a).is_some() || self.pending_loss.is_some() {
            return;
        }
        let Some(Ok(run)) = self.run(key) else {
            return;
        };
        if run
            .activity(a)
            .is_none_or(|r| r.outcome == RunOutcome::Completed)
        {
            return;
        }
        let explain = move |run: &ExecutionRun| {
            solscope_engine::loss(&run.plan, &run.execution, a).map_err(|e| e.to_string())
        };
        if background {
            let run = Arc::clone(run);
            self.pending_loss = Some(Job::spawn((key, a), move |_: &Signal| explain(&run)));
        } else {
            let value = explain(run);
            self.loss = Some(((key, a), value));
        }
    }

    /// Why activity `a` did not complete in the execution at `key`, once derived.
    pub fn loss(&self, key: ExecKey, a: usize) -> Option<&Result<Loss, String>> {
        self.loss
            .as_ref()
            .filter(|(k, _)| *k == (key, a))
            .map(|(_, l)| l)
    }

    fn keep_cycle(&mut self, k: usize, run: CycleRun) {
        if self.cycles.len() >= KEPT_CYCLE_RUNS {
            // Keep the first cycle (the prediction): forget the one furthest away.
            let far = self
                .cycles
                .keys()
                .copied()
                .filter(|&c| c != 0)
                .max_by_key(|&c| c.abs_diff(k));
            if let Some(far) = far {
                self.cycles.remove(&far);
            }
        }
        self.cycles.insert(k, run);
    }

    /// Starts repeating cycle `k`'s scheduler run of the execution at `key`
    /// unless it is known or a worker is busy: the cycle's plan is rebuilt
    /// and scheduled on the worker (both linear in the activities or more),
    /// from the plan the execution shares with it.
    pub fn request_cycle(&mut self, key: ExecKey, k: usize, background: bool) {
        if self.cycle(key, k).is_some() || self.pending_cycle.is_some() {
            return;
        }
        let Some(Ok(run)) = self.run(key) else {
            return;
        };
        if k >= run.execution.cycles.len() {
            return;
        }
        if background {
            let run = Arc::clone(run);
            self.pending_cycle = Some(Job::spawn((key, k), move |_: &Signal| {
                CycleRun::of(k, &run.execution, &run.plan)
            }));
        } else if let Some(cycle) = CycleRun::of(k, &run.execution, &run.plan) {
            self.keep_cycle(k, cycle);
        }
    }

    /// Cycle `k`'s scheduler run of the execution at `key`, once derived.
    pub fn cycle(&self, key: ExecKey, k: usize) -> Option<&CycleRun> {
        self.run(key)?;
        self.cycles.get(&k)
    }

    /// Derives the profiles after step `step` of cycle `k`'s run (at `key`), if
    /// that run is known.
    pub fn derive_view(&mut self, key: ExecKey, k: usize, step: usize) {
        if self
            .view
            .as_ref()
            .is_some_and(|(v, _)| *v == (key, k, step))
        {
            return;
        }
        let Some(Ok(schedule)) = self.cycle(key, k).map(|c| c.schedule.as_ref()) else {
            return;
        };
        let view = StepView::from_profiles(step, &schedule.profiles_after(step));
        self.view = Some(((key, k, step), view));
    }

    /// The profiles after step `step` of cycle `k`'s run, if derived.
    pub fn view(&self, key: ExecKey, k: usize, step: usize) -> Option<&StepView> {
        self.view
            .as_ref()
            .filter(|(v, _)| *v == (key, k, step))
            .map(|(_, view)| view)
    }

    /// Whether a worker is running (the frame loop polls until it is done).
    pub fn busy(&self) -> bool {
        self.pending.is_some() || self.pending_cycle.is_some() || self.pending_loss.is_some()
    }
}
