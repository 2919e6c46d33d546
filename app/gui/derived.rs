//! Values derived from the plan for the activity looked at: its explanation, valid
//! intervals and verified suggestions, each kept with the activity and plan
//! revision it was derived for, and the worker thread that verifies suggestions.
//! Also the step profiles ([`step_view`]), the execution of the plan with
//! the scheduler runs of its cycles ([`ExecutionCache`], with its workers), and
//! the Monte Carlo campaign ([`CampaignCache`], with its worker), and the
//! flexible form of the schedule ([`FlexCache`], with its worker).

use std::collections::BTreeMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, TryRecvError};

use solscope_engine::{
    CategoryIntervals, Explanation, Flex, Loss, MJ_PER_WH, MW_PER_W, Phase, Phase2Reason, Plan,
    ReasonRange, RunOutcome, Suggestion, format_watts, format_wh, involved,
};

use super::document::Analysis;
use super::execution::{ActualsSource, CycleRun, ExecutionRun};
use super::montecarlo::{CampaignResult, Progress, StopReason, Stopped, total_runs};
use super::state::{FreeSlackProgress, OverlayPlot, OverlayReason, StepView, WouldCause};

/// A value derived for one activity at one plan revision (its explanation, valid
/// intervals, verified suggestions, or the worker computing them). It is read back
/// only for that activity and revision, so nothing stale is ever shown.
#[derive(Debug)]
struct Derived<T> {
    activity: usize,
    revision: u64,
    value: T,
}

impl<T> Derived<T> {
    /// The value in `slot` if it was derived for `activity` at `revision`.
    fn get(slot: &Option<Self>, activity: usize, revision: u64) -> Option<&T> {
        slot.as_ref()
            .filter(|d| d.activity == activity && d.revision == revision)
            .map(|d| &d.value)
    }
}

/// The derived values of the activity looked at (one of each at a time).
#[derive(Debug, Default)]
pub struct DerivedCache {
    /// Explanation of the selected activity (none when it scheduled), or why it
    /// could not be explained, per plan revision.
    explanation: Option<Derived<Result<Option<Explanation>, String>>>,
    /// What the selected activity, failed on energy or peak power, would have
    /// caused (none for any other), per plan revision.
    would_cause: Option<Derived<Option<WouldCause>>>,
    /// Full valid intervals of the selected scheduled activity as it saw them.
    valid: Option<Derived<Vec<CategoryIntervals>>>,
    /// Verified suggestions of the selected activity, per plan revision.
    suggestions: Option<Derived<Vec<Suggestion>>>,
    /// Suggestions being verified on a worker thread (rescheduling once per
    /// candidate edit can take seconds on a big plan): activity, revision, result.
    pending: Option<Derived<Receiver<Vec<Suggestion>>>>,
}

impl DerivedCache {
    /// The explanation of activity `a` if it did not schedule (computed once per
    /// plan revision).
    pub fn explanation_for(
        &mut self,
        plan: &Plan,
        analysis: &Analysis,
        revision: u64,
        a: usize,
    ) -> Option<&Explanation> {
        if Derived::get(&self.explanation, a, revision).is_none() {
            self.explanation = Some(Derived {
                activity: a,
                revision,
                value: analysis.explain(plan, a).map_err(|e| e.to_string()),
            });
        }
        self.explanation(a, revision)
    }

    /// The explanation of `a`, if derived at `revision`.
    pub fn explanation(&self, a: usize, revision: u64) -> Option<&Explanation> {
        Derived::get(&self.explanation, a, revision)
            .and_then(|r| r.as_ref().ok())
            .and_then(Option::as_ref)
    }

    /// Why `a` could not be explained at `revision`, if that is what happened.
    pub fn explanation_error(&self, a: usize, revision: u64) -> Option<&str> {
        Derived::get(&self.explanation, a, revision)
            .and_then(|r| r.as_ref().err().map(String::as_str))
    }

    /// Derives what activity `a` would have caused at the start of its
    /// explanation's energy or peak-power reason `shown`, when it failed in
    /// placement on energy or peak power (once per activity, plan revision and
    /// reason shown: it replays the schedule).
    pub fn would_cause_for(
        &mut self,
        plan: &Plan,
        analysis: &Analysis,
        revision: u64,
        (a, shown): (usize, usize),
    ) {
        let same = Derived::get(&self.would_cause, a, revision).is_some_and(|w| {
            w.as_ref()
                .is_none_or(|w| w.shown == shown.min(w.reasons.len().saturating_sub(1)))
        });
        if !same {
            let value = self
                .explanation_for(plan, analysis, revision, a)
                .and_then(|ex| would_cause(plan, analysis, ex, shown));
            self.would_cause = Some(Derived {
                activity: a,
                revision,
                value,
            });
        }
    }

    /// What `a` would have caused, if derived at `revision` and it failed on
    /// energy or peak power.
    pub fn would_cause(&self, a: usize, revision: u64) -> Option<&WouldCause> {
        Derived::get(&self.would_cause, a, revision).and_then(Option::as_ref)
    }

    /// Derives the valid intervals of activity `a` at its own step (over the whole
    /// horizon: the trace keeps them only within the window span).
    pub fn valid_for(&mut self, analysis: &Analysis, revision: u64, a: usize) {
        if Derived::get(&self.valid, a, revision).is_none() {
            let sched = &analysis.schedule;
            // An activity without a step has no valid intervals to show.
            let value = sched
                .step_of(a)
                .map(|st| {
                    solscope_engine::valid_intervals_at(sched, a, st.step - 1, Some(st.duration))
                })
                .unwrap_or_default();
            self.valid = Some(Derived {
                activity: a,
                revision,
                value,
            });
        }
    }

    /// The valid intervals of `a`, if derived at `revision`.
    pub fn valid(&self, a: usize, revision: u64) -> Option<&[CategoryIntervals]> {
        Derived::get(&self.valid, a, revision).map(Vec::as_slice)
    }

    /// Starts deriving the verified suggestions for activity `a` unless they are
    /// known or a worker is busy: in place, or with `background` on a worker
    /// thread. One worker at a time: a request made while another activity's (or
    /// an older revision's) worker runs waits for it to finish, so stepping through
    /// many activities does not pile up threads that each reschedule the plan.
    pub fn request_suggestions(
        &mut self,
        plan: &Plan,
        analysis: &Analysis,
        revision: u64,
        a: usize,
        background: bool,
    ) {
        if self.suggestions(a, revision).is_some() || self.pending.is_some() {
            return;
        }
        match self.explanation_for(plan, analysis, revision, a).cloned() {
            Some(ex) if background => {
                let (tx, rx) = mpsc::channel();
                let plan = plan.clone();
                let schedule = std::sync::Arc::clone(&analysis.schedule);
                std::thread::spawn(move || {
                    let list = solscope_engine::verified_suggestions(&plan, &schedule, &ex);
                    // A send fails only when the app let go of this request (another
                    // plan was opened): nobody waits for the result, which is dropped
                    // with the error on purpose.
                    drop(tx.send(list));
                });
                self.pending = Some(Derived {
                    activity: a,
                    revision,
                    value: rx,
                });
            }
            ex => {
                let value = ex.map_or_else(Vec::new, |ex| {
                    solscope_engine::verified_suggestions(plan, &analysis.schedule, &ex)
                });
                self.suggestions = Some(Derived {
                    activity: a,
                    revision,
                    value,
                });
            }
        }
    }

    /// The verified suggestions of `a`, if derived at `revision`.
    pub fn suggestions(&self, a: usize, revision: u64) -> Option<&[Suggestion]> {
        Derived::get(&self.suggestions, a, revision).map(Vec::as_slice)
    }

    /// Takes a finished worker's result: kept when it is for `revision`, dropped
    /// otherwise. A worker that stopped without a result (it panicked) leaves an
    /// empty list, so nothing waits for it, and is reported as an error.
    pub fn reap_worker(&mut self, revision: u64) -> Result<(), String> {
        let Some(pending) = &self.pending else {
            return Ok(());
        };
        let (value, lost) = match pending.value.try_recv() {
            Ok(list) => (list, false),
            Err(TryRecvError::Empty) => return Ok(()),
            Err(TryRecvError::Disconnected) => (Vec::new(), true),
        };
        let activity = pending.activity;
        let current = pending.revision == revision;
        self.pending = None;
        if current {
            self.suggestions = Some(Derived {
                activity,
                revision,
                value,
            });
        }
        if lost && current {
            return Err("Verifying suggestions failed: the worker stopped without a result".into());
        }
        Ok(())
    }

    /// The activity whose suggestions a worker is verifying, if any.
    pub fn verifying(&self) -> Option<usize> {
        self.pending.as_ref().map(|p| p.activity)
    }
}

/// The profiles as of step `k`, as plot points.
pub fn step_view(analysis: &Analysis, k: usize) -> StepView {
    StepView::from_profiles(k, &analysis.schedule.profiles_after(k))
}

/// The step profiles derived off the frame while the step moves (a drag of the
/// step slider, held keys, play): one worker at a time, and when it is done the
/// next one is for the latest step only, so however fast the step moves a frame
/// never waits on the profiles and the work never piles up behind the pointer.
#[derive(Debug, Default)]
pub struct StepViewCache {
    /// The worker, keyed by the plan revision and step it derives.
    pending: Option<Job<(u64, usize), StepView>>,
}

impl StepViewCache {
    /// Starts deriving the profiles after step `k` at `revision` unless a
    /// worker is busy (it is asked again for the latest step when that one is
    /// done).
    pub fn request(&mut self, analysis: &Analysis, revision: u64, k: usize) {
        if self.pending.is_some() {
            return;
        }
        let schedule = Arc::clone(&analysis.schedule);
        self.pending = Some(Job::spawn((revision, k), move || {
            StepView::from_profiles(k, &schedule.profiles_after(k))
        }));
    }

    /// The worker's profiles once in, when they are of `revision` (another
    /// revision's are dropped). A worker that stopped without a result is
    /// reported.
    pub fn reap(&mut self, revision: u64) -> Result<Option<StepView>, String> {
        let Some(job) = &self.pending else {
            return Ok(None);
        };
        let Some(result) = job.poll() else {
            return Ok(None);
        };
        let (r, k) = job.key;
        self.pending = None;
        match result {
            Ok(view) if r == revision => Ok(Some(view)),
            Ok(_) => Ok(None),
            Err(()) => Err(format!(
                "Deriving the profiles after step {k} failed: the worker stopped without a result"
            )),
        }
    }

    /// Whether a worker is running.
    pub fn busy(&self) -> bool {
        self.pending.is_some()
    }
}

/// What the activity of `ex`, failed in placement, would have caused: every
/// energy or peak-power reason of its explanation (each evaluated at its own
/// start), and for reason `shown` of them (the last when there are fewer) the
/// profile of its plot had it been placed at that start, in the state of its
/// failure step. `None` for an explanation without such a reason.
pub fn would_cause(
    plan: &Plan,
    analysis: &Analysis,
    ex: &Explanation,
    shown: usize,
) -> Option<WouldCause> {
    if ex.phase != Some(Phase::Placement) {
        return None;
    }
    let k = ex.failure_step?;
    // In the order the inspector lists them: the explanation's own duration
    // first (an expanding activity's search tried others too).
    let reasons: Vec<OverlayReason> = solscope_engine::reasons_in_reading_order(ex)
        .into_iter()
        .filter_map(|i| overlay_reason(plan, i, &ex.reasons[i]))
        .collect();
    let shown = shown.min(reasons.len().checked_sub(1)?);
    let r = &reasons[shown];
    let points = analysis
        .schedule
        .profiles_if_placed(k, ex.activity, r.start, r.duration)
        .map(|profiles| {
            let view = StepView::from_profiles(k, &profiles);
            match r.plot {
                OverlayPlot::Soc => view.soc,
                OverlayPlot::Peak => view.peak,
            }
        })
        .unwrap_or_default();
    Some(WouldCause {
        activity: ex.activity,
        reasons,
        shown,
        points,
        culprits: involved(ex).iter().map(|c| c.activity).collect(),
    })
}

/// Reason `i` of an explanation as the plots mark it, when it broke an energy
/// or peak-power limit: its plot, its violation point and label.
fn overlay_reason(plan: &Plan, i: usize, r: &ReasonRange) -> Option<OverlayReason> {
    let wh_mj = |wh: f64| (wh * MJ_PER_WH).round() as i128;
    let (plot, at, value, label) = match r.reason {
        Phase2Reason::MinSoc { at, soc_mj } => {
            let min = plan.battery.min_soc;
            let label = format!(
                "would reach {} < min_soc {}",
                format_wh(i128::from(soc_mj)),
                format_wh(wh_mj(min))
            );
            (OverlayPlot::Soc, at, soc_mj as f64 / MJ_PER_WH, label)
        }
        Phase2Reason::HandoverSoc { soc_mj } => {
            let h = plan.handover?;
            let label = format!(
                "would reach {} at handover < handover min_soc {}",
                format_wh(i128::from(soc_mj)),
                format_wh(wh_mj(h.min_soc.unwrap_or_default()))
            );
            (OverlayPlot::Soc, h.time, soc_mj as f64 / MJ_PER_WH, label)
        }
        Phase2Reason::MaxPeakPower { at, peak_mw } => {
            let max = plan.power.max_peak.unwrap_or_default();
            let label = format!(
                "would reach {} > max_peak {}",
                format_watts(peak_mw),
                format_watts((max * MW_PER_W).round() as i64)
            );
            (OverlayPlot::Peak, at, peak_mw as f64 / MW_PER_W, label)
        }
        _ => return None,
    };
    Some(OverlayReason {
        reason: i,
        plot,
        first: r.first,
        last: r.last,
        start: r.probe,
        duration: r.duration,
        at,
        value,
        label,
    })
}

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
const KEPT_CYCLE_RUNS: usize = 16;

/// A job on a worker thread: what it is for, and where its result comes.
#[derive(Debug)]
struct Job<K, T> {
    key: K,
    rx: Receiver<T>,
}

impl<K: Copy, T> Job<K, T> {
    /// Runs `work` on a new thread.
    fn spawn(key: K, work: impl FnOnce() -> T + Send + 'static) -> Self
    where
        T: Send + 'static,
    {
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            // A send fails only when the app let go of this job (another plan was
            // opened): nobody waits for the result, which is dropped on purpose.
            drop(tx.send(work()));
        });
        Self { key, rx }
    }

    /// The result if it is in: `Some(Ok)`, or `Some(Err(()))` when the worker
    /// stopped without one (it panicked); `None` while it runs.
    fn poll(&self) -> Option<Result<T, ()>> {
        match self.rx.try_recv() {
            Ok(v) => Some(Ok(v)),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some(Err(())),
        }
    }
}

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
    pending: Option<Job<ExecKey, ExecResult>>,
    /// Cycle runs of the execution in `run`, by cycle.
    cycles: BTreeMap<usize, CycleRun>,
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
            let (plan, source) = (plan.clone(), source.clone());
            self.pending = Some(Job::spawn(key, move || ExecutionRun::of(&plan, &source)));
        } else {
            self.store(key, ExecutionRun::of(plan, source));
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
                let current = job.key == key;
                self.pending = None;
                match result {
                    Ok(r) if current => self.store(key, r),
                    Ok(_) => {}
                    Err(()) => {
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
                let (job_key, k) = job.key;
                self.pending_cycle = None;
                let current = job_key == key && self.run(key).is_some();
                match result {
                    Ok(Some(run)) if current => self.keep_cycle(k, run),
                    Ok(_) => {}
                    Err(()) => {
                        if current {
                            let e = format!(
                                "Scheduling cycle {k} again failed: the worker stopped without a result"
                            );
                            self.keep_cycle(
                                k,
                                CycleRun {
                                    index: k,
                                    schedule: Err(e.clone()),
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
                let job_key = job.key;
                self.pending_loss = None;
                if job_key.0 == key {
                    let value = result.unwrap_or_else(|()| {
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
    pub fn request_loss(&mut self, plan: &Plan, key: ExecKey, a: usize, background: bool) {
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
        let explain = move |plan: &Plan, run: &ExecutionRun| {
            solscope_engine::loss(plan, &run.execution, a).map_err(|e| e.to_string())
        };
        if background {
            let (plan, run) = (plan.clone(), Arc::clone(run));
            self.pending_loss = Some(Job::spawn((key, a), move || explain(&plan, &run)));
        } else {
            let value = explain(plan, run);
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
    /// unless it is known or a worker is busy.
    pub fn request_cycle(&mut self, key: ExecKey, k: usize, background: bool) {
        if self.cycle(key, k).is_some() || self.pending_cycle.is_some() {
            return;
        }
        let Some(Ok(run)) = self.run(key) else {
            return;
        };
        let Some(cycle) = run.execution.cycles.get(k) else {
            return;
        };
        if background {
            let cycle = cycle.clone();
            self.pending_cycle = Some(Job::spawn((key, k), move || CycleRun::of(k, &cycle)));
        } else if let Some(run) = CycleRun::of(k, cycle) {
            self.keep_cycle(k, run);
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

/// The flexible form of one plan revision's schedule, or why there is none.
pub type FlexResult = Result<Arc<Flex>, String>;

/// A worker computing free slack: its results come one activity at a time.
#[derive(Debug)]
struct FreeSlackJob {
    /// Ends (with nothing) when the worker stops; keyed by the plan revision.
    job: Job<u64, ()>,
    /// Each activity's free slack as it is known.
    rx: Receiver<(usize, solscope_engine::FreeSlack)>,
    /// Set to stop the worker.
    cancel: Arc<AtomicBool>,
    started: std::time::Instant,
}

impl Drop for FreeSlackJob {
    fn drop(&mut self) {
        // Nobody will read what it computes on: it stops within moments.
        self.cancel.store(true, Ordering::Relaxed);
    }
}

/// The flexible form of the schedule ([`solscope_engine::flex`]: bounds, start
/// conditions, controllability and free slack), derived once per plan revision
/// and read back only for it. With `background` it is computed on worker
/// threads (a result for an older revision is dropped) in two stages: first
/// without free slack (the network: milliseconds to a second; the whiskers and
/// conditions show at once), then the free slack, which replays the schedule
/// once per activity (quadratic: minutes on 10,000 activities, much longer on
/// realistic ones). That second worker hands each activity's free slack on as
/// it is known (the shading fills in, the activities nearest the time range in
/// view first), runs on one core fewer than the machine has (the frames keep
/// one), and is cancelled when the plan changes or the layer is turned off
/// ([`FlexCache::stop_free_slack`]); what it found stays, and it goes on from
/// there when asked again.
#[derive(Debug, Default)]
pub struct FlexCache {
    done: Option<(u64, FlexResult)>,
    /// The first stage's worker, keyed by revision.
    pending: Option<Job<u64, FlexResult>>,
    /// The free slack worker.
    free: Option<FreeSlackJob>,
    /// What the free slack worker needs (the schedule of the revision in
    /// `done`).
    source: Option<(u64, Arc<solscope_engine::Schedule>)>,
    /// Seconds the free slack of the revision in `done` was computed for in
    /// runs that ended (stopped or done).
    spent: f64,
    /// The revision whose free slack worker stopped without finishing (it
    /// panicked): not started again for it.
    failed: Option<u64>,
    /// The selected activity's free slack computed on its own, ahead of the
    /// rest (keyed by revision and activity).
    one: Option<Job<(u64, usize), Option<solscope_engine::FreeSlack>>>,
}

/// The flexible form of `schedule` (with or without free slack); a panic in the
/// engine is an error, not a crash of the app.
fn compute_flex(plan: &Plan, analysis: &Analysis, free_slack: bool) -> FlexResult {
    let schedule = &analysis.schedule;
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        solscope_engine::flex_with(plan, schedule, solscope_engine::FlexOptions { free_slack })
    }))
    .map(Arc::new)
    .map_err(|_| "Computing the flexible schedule failed (an internal error)".to_string())
}

/// Threads the free slack worker uses: one fewer than the machine has (at
/// least one), so a frame always finds a core.
fn free_slack_threads() -> usize {
    std::thread::available_parallelism()
        .map_or(1, std::num::NonZeroUsize::get)
        .saturating_sub(1)
        .max(1)
}

impl FlexCache {
    /// The flexible schedule at `revision`, or why there is none, once derived
    /// (its free slack as far as it is known).
    pub fn get(&self, revision: u64) -> Option<&FlexResult> {
        self.done
            .as_ref()
            .filter(|(r, _)| *r == revision)
            .map(|(_, f)| f)
    }

    /// Starts deriving the flexible schedule of `plan` at `revision` unless it
    /// is known or being derived: in place (free slack included), or with
    /// `background` on a worker (the free slack follows through
    /// [`FlexCache::request_free_slack`]). A worker of an older revision is
    /// dropped (the free slack one cancelled).
    pub fn request(&mut self, plan: &Plan, analysis: &Analysis, revision: u64, background: bool) {
        if self.free.as_ref().is_some_and(|f| f.job.key != revision) {
            self.free = None;
        }
        // One first-stage worker at a time: a newer revision's waits for it.
        if self.get(revision).is_some() || self.pending.is_some() {
            return;
        }
        self.spent = 0.0;
        if background {
            self.source = Some((revision, Arc::clone(&analysis.schedule)));
            let (plan, analysis) = (plan.clone(), analysis.clone());
            self.pending = Some(Job::spawn(revision, move || {
                compute_flex(&plan, &analysis, false)
            }));
        } else {
            self.done = Some((revision, compute_flex(plan, analysis, true)));
        }
    }

    /// Starts the free slack worker at `revision` once the first stage is in,
    /// for the activities whose free slack is not known yet, those whose
    /// scheduled start is nearest `near` (plan seconds) first; unless it runs.
    pub fn request_free_slack(&mut self, revision: u64, near: f64) {
        if self.free.is_some() {
            return;
        }
        let Some((r, Ok(flex))) = &self.done else {
            return;
        };
        let Some((_, schedule)) = self.source.as_ref().filter(|(s, _)| *s == *r) else {
            return;
        };
        if *r != revision || self.failed == Some(revision) {
            return;
        }
        let mut todo: Vec<(f64, usize)> = flex
            .activities
            .iter()
            .filter(|fa| fa.free_slack.is_none())
            .map(|fa| ((fa.start.nom as f64 - near).abs(), fa.activity))
            .collect();
        if todo.is_empty() {
            return;
        }
        todo.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        let order: Vec<usize> = todo.into_iter().map(|(_, a)| a).collect();
        let (tx, rx) = mpsc::channel();
        let cancel = Arc::new(AtomicBool::new(false));
        let (schedule, flag) = (Arc::clone(schedule), Arc::clone(&cancel));
        let job = Job::spawn(revision, move || {
            let send = |a: usize, fs: &solscope_engine::FreeSlack| {
                // A send fails only when the app let go of this worker (it is
                // then cancelled too): the value is dropped on purpose.
                drop(tx.send((a, fs.clone())));
            };
            let run = || {
                solscope_engine::free_slack_each(&schedule, &order, Some(&flag), &send);
            };
            match rayon::ThreadPoolBuilder::new()
                .num_threads(free_slack_threads())
                .build()
            {
                Ok(pool) => pool.install(run),
                // No pool of its own: rayon's global one.
                Err(_) => run(),
            }
        });
        self.free = Some(FreeSlackJob {
            job,
            rx,
            cancel,
            started: std::time::Instant::now(),
        });
    }

    /// Starts computing activity `a`'s free slack on its own worker (seconds:
    /// one replay of the schedule), when the flexible schedule at `revision` is
    /// in without it and no such worker runs: what the inspector shows for the
    /// selected activity, whether the layer is shown or not, without waiting
    /// for the rest.
    pub fn request_one(&mut self, revision: u64, a: usize) {
        if self.one.is_some() || self.failed == Some(revision) {
            return;
        }
        let Some((r, Ok(flex))) = &self.done else {
            return;
        };
        let Some((_, schedule)) = self.source.as_ref().filter(|(s, _)| *s == *r) else {
            return;
        };
        if *r != revision || flex.activity(a).is_none_or(|fa| fa.free_slack.is_some()) {
            return;
        }
        let schedule = Arc::clone(schedule);
        self.one = Some(Job::spawn((revision, a), move || {
            solscope_engine::free_slack_of(&schedule, a)
        }));
    }

    /// The activity whose free slack is being computed on its own at
    /// `revision`, if any.
    pub fn computing_one(&self, revision: u64) -> Option<usize> {
        self.one
            .as_ref()
            .filter(|j| j.key.0 == revision)
            .map(|j| j.key.1)
    }

    /// Stops the free slack worker (the layer was turned off): what it found
    /// stays.
    pub fn stop_free_slack(&mut self) {
        if let Some(f) = self.free.take() {
            self.spent += f.started.elapsed().as_secs_f64();
            // What it sent since the last reap is kept too (not computed again).
            if let Some((r, Ok(flex))) = &mut self.done {
                if *r == f.job.key {
                    let flex = Arc::make_mut(flex);
                    while let Ok((a, fs)) = f.rx.try_recv() {
                        flex.set_free_slack(a, fs);
                    }
                }
            }
        }
    }

    /// Where the free slack at `revision` stands, once the first stage is in.
    pub fn free_slack_progress(&self, revision: u64) -> Option<FreeSlackProgress> {
        let flex = self.get(revision)?.as_ref().ok()?;
        let running = self.free.as_ref().is_some_and(|f| f.job.key == revision);
        let now = self
            .free
            .as_ref()
            .filter(|_| running)
            .map_or(0.0, |f| f.started.elapsed().as_secs_f64());
        Some(FreeSlackProgress {
            done: flex
                .activities
                .iter()
                .filter(|fa| fa.free_slack.is_some())
                .count(),
            total: flex.activities.len(),
            running,
            seconds: (self.spent + now) as u64,
            failed: self.failed == Some(revision),
            computing: self.computing_one(revision),
        })
    }

    /// Takes the workers' results: kept when they are for `revision`, dropped
    /// otherwise (the free slack as it comes, one activity at a time). A
    /// worker that stopped without a result is reported.
    pub fn reap(&mut self, revision: u64) -> Result<(), String> {
        if let Some(job) = &self.pending {
            if let Some(result) = job.poll() {
                let current = job.key == revision;
                self.pending = None;
                match result {
                    Ok(f) if current => self.done = Some((revision, f)),
                    Ok(_) => self.source = None,
                    Err(()) if current => {
                        let e = "Computing the flexible schedule failed: the worker stopped \
                                 without a result";
                        self.done = Some((revision, Err(e.into())));
                        return Err(e.into());
                    }
                    Err(()) => {}
                }
            }
        }
        if let Some(job) = &self.one {
            if let Some(result) = job.poll() {
                let (r, a) = job.key;
                self.one = None;
                match (result, &mut self.done) {
                    (Ok(Some(fs)), Some((d, Ok(flex)))) if r == revision && *d == r => {
                        Arc::make_mut(flex).set_free_slack(a, fs);
                    }
                    (Ok(_), _) => {}
                    (Err(()), _) if r == revision => {
                        self.failed = Some(revision);
                        return Err("Computing the selected activity's free slack failed: the \
                                    worker stopped without a result"
                            .into());
                    }
                    (Err(()), _) => {}
                }
            }
        }
        let Some(free) = &self.free else {
            return Ok(());
        };
        if free.job.key != revision {
            self.free = None;
            return Ok(());
        }
        // Whether it ended first: then every result it sent is in.
        let ended = free.job.poll();
        if let Some((r, Ok(flex))) = &mut self.done {
            if *r == revision {
                // Unshared (the views only borrow it): filled in place.
                let flex = Arc::make_mut(flex);
                while let Ok((a, fs)) = free.rx.try_recv() {
                    flex.set_free_slack(a, fs);
                }
            }
        }
        let Some(ended) = ended else {
            return Ok(());
        };
        self.spent += free.started.elapsed().as_secs_f64();
        self.free = None;
        match ended {
            Ok(()) => Ok(()),
            Err(()) => {
                self.failed = Some(revision);
                Err(
                    "Computing free slack failed: the worker stopped without a result \
                     (what it found is shown)"
                        .into(),
                )
            }
        }
    }

    /// Whether a worker is running (the frame loop polls until it is done).
    pub fn busy(&self) -> bool {
        self.pending.is_some() || self.free.is_some() || self.one.is_some()
    }

    /// Whether a worker of seconds at most is running: the first stage, or
    /// one activity's free slack.
    pub fn busy_first_stage(&self) -> bool {
        self.pending.is_some() || self.one.is_some()
    }
}

/// What a campaign worker sends back: the result, `None` when cancelled.
type CampaignOutcome = Result<Option<CampaignResult>, String>;

/// A campaign running on a worker thread, with its progress and cancel flag.
/// Dropping it cancels the campaign (nobody would read its result).
#[derive(Debug)]
struct CampaignJob {
    /// The job, keyed by the plan revision it runs on.
    job: Job<u64, CampaignOutcome>,
    seed: u64,
    runs: u64,
    /// It compares the policies (`runs` runs each).
    compare: bool,
    /// Runs done (counted by the workers).
    done: Arc<AtomicU64>,
    /// Set to stop starting runs.
    cancel: Arc<AtomicBool>,
}

impl CampaignJob {
    fn progress(&self) -> Progress {
        Progress {
            seed: self.seed,
            runs: self.runs,
            compare: self.compare,
            done: self
                .done
                .load(Ordering::Relaxed)
                .min(total_runs(self.runs, self.compare)),
            cancelling: self.cancel.load(Ordering::Relaxed),
        }
    }

    fn stopped(&self, why: StopReason) -> Stopped {
        let p = self.progress();
        Stopped {
            seed: p.seed,
            runs: p.runs,
            compare: p.compare,
            done: p.done,
            why,
        }
    }
}

impl Drop for CampaignJob {
    fn drop(&mut self) {
        self.cancel.store(true, Ordering::Relaxed);
    }
}

/// The Monte Carlo campaign: the last one finished (shown only for the plan
/// revision it ran on), the one running, and the last one that stopped
/// before its summary (cancelled, or the plan was edited while it ran). One
/// campaign at a time; with `background` it runs on a worker thread (its runs
/// in parallel), so the frames go on and it can be cancelled.
#[derive(Debug, Default)]
pub struct CampaignCache {
    /// The last campaign finished, with the plan revision it ran on.
    done: Option<(u64, Result<CampaignResult, String>)>,
    job: Option<CampaignJob>,
    stopped: Option<Stopped>,
}

impl CampaignCache {
    /// Starts a campaign of `runs` runs of `plan` (at `revision`) seeded with
    /// `seed`, with `compare` under each policy one after the other: in
    /// place, or with `background` on a worker thread. A campaign still
    /// running is cancelled first. What the last one came to stays until
    /// this one is done.
    pub fn start(
        &mut self,
        plan: &Plan,
        revision: u64,
        (seed, runs, compare): (u64, u64, bool),
        background: bool,
    ) {
        self.job = None;
        if background {
            let done = Arc::new(AtomicU64::new(0));
            let cancel = Arc::new(AtomicBool::new(false));
            let (plan, count, flag) = (plan.clone(), Arc::clone(&done), Arc::clone(&cancel));
            let job = Job::spawn(revision, move || {
                let progress = move || {
                    count.fetch_add(1, Ordering::Relaxed);
                };
                CampaignResult::of(&plan, seed, runs, compare, &progress, Some(&flag))
            });
            self.job = Some(CampaignJob {
                job,
                seed,
                runs,
                compare,
                done,
                cancel,
            });
        } else {
            self.stopped = None;
            match CampaignResult::of(plan, seed, runs, compare, &|| {}, None) {
                Ok(Some(result)) => self.done = Some((revision, Ok(result))),
                // Nothing cancels a campaign run in place.
                Ok(None) => {}
                Err(e) => self.done = Some((revision, Err(e))),
            }
        }
    }

    /// Asks the running campaign to stop (the runs already started finish;
    /// its summary is not made).
    pub fn cancel(&mut self) {
        if let Some(job) = &self.job {
            job.cancel.store(true, Ordering::Relaxed);
        }
    }

    /// Takes the worker's result: kept when it is for `revision`. A campaign
    /// of an older revision is stopped at once (its summary would be of the
    /// plan as it was). A worker that stopped without a result is reported.
    pub fn reap(&mut self, revision: u64) -> Result<(), String> {
        let Some(job) = &self.job else {
            return Ok(());
        };
        if job.job.key != revision {
            self.stopped = Some(job.stopped(StopReason::PlanEdited));
            // Dropping the job cancels it.
            self.job = None;
            return Ok(());
        }
        let Some(outcome) = job.job.poll() else {
            return Ok(());
        };
        let stopped = job.stopped(StopReason::Cancelled);
        self.job = None;
        self.stopped = None;
        match outcome {
            Ok(Ok(Some(result))) => self.done = Some((revision, Ok(result))),
            Ok(Ok(None)) => self.stopped = Some(stopped),
            Ok(Err(e)) => self.done = Some((revision, Err(e))),
            Err(()) => {
                let e = "The Monte Carlo campaign failed: the worker stopped without a result";
                self.done = Some((revision, Err(e.into())));
                return Err(e.into());
            }
        }
        Ok(())
    }

    /// The last campaign finished, if it ran on `revision`.
    pub fn result(&self, revision: u64) -> Option<&Result<CampaignResult, String>> {
        self.done
            .as_ref()
            .filter(|(r, _)| *r == revision)
            .map(|(_, d)| d)
    }

    /// The seed and runs of the last campaign finished when it ran on another
    /// revision than `revision` (its summary no longer applies).
    pub fn stale(&self, revision: u64) -> Option<(u64, u64)> {
        match &self.done {
            Some((r, Ok(result))) if *r != revision => Some((result.seed, result.runs())),
            _ => None,
        }
    }

    /// The campaign running, if any.
    pub fn progress(&self) -> Option<Progress> {
        self.job.as_ref().map(CampaignJob::progress)
    }

    /// The last campaign that stopped before its summary, until another
    /// campaign ends.
    pub fn stopped(&self) -> Option<&Stopped> {
        self.stopped.as_ref()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan() -> Plan {
        let text = include_str!("../../assets/execution-examples/uncertain-drive.json");
        solscope_engine::load_plan(text).expect("example plan").plan
    }

    /// Reaps `cache` at `key` until its execution worker is done.
    fn wait(cache: &mut ExecutionCache, key: ExecKey) {
        for _ in 0..2000 {
            cache.reap(key).expect("worker result");
            if cache.pending.is_none() {
                return;
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        panic!("the worker never finished");
    }

    #[test]
    fn an_execution_for_an_older_key_is_dropped() {
        let plan = plan();
        let mut cache = ExecutionCache::default();
        let old = ExecKey {
            revision: 0,
            actuals: 0,
        };
        let new = ExecKey {
            revision: 0,
            actuals: 1,
        };
        cache.request(&plan, &ActualsSource::Nominal, old, true);
        assert!(cache.busy());
        // The actuals changed while it ran: its result is not kept.
        wait(&mut cache, new);
        assert!(cache.run(old).is_none() && cache.run(new).is_none());
        cache.request(
            &plan,
            &ActualsSource::Sampled { seed: 7, run: 0 },
            new,
            true,
        );
        wait(&mut cache, new);
        let run = cache.run(new).expect("derived").as_ref().expect("executed");
        assert_eq!(run.actuals, solscope_engine::sample_actuals(&plan, 7));
        // The first cycle's run came with it; another cycle is derived on request.
        assert!(cache.cycle(new, 0).is_some());
        assert!(cache.cycle(new, 3).is_none());
        cache.request_cycle(new, 3, false);
        let three = cache.cycle(new, 3).expect("cycle 3");
        assert_eq!(three.index, 3);
        assert!(three.schedule.is_ok());
        cache.derive_view(new, 3, 1);
        assert_eq!(cache.view(new, 3, 1).map(|v| v.step), Some(1));
        assert!(cache.view(new, 3, 2).is_none());
        assert!(cache.cycle(old, 3).is_none(), "read back only for its key");
    }

    #[test]
    fn at_most_a_bounded_number_of_cycle_runs_are_kept() {
        let plan = plan();
        let mut cache = ExecutionCache::default();
        let key = ExecKey {
            revision: 0,
            actuals: 0,
        };
        cache.request(&plan, &ActualsSource::Nominal, key, false);
        let n = match cache.run(key) {
            Some(Ok(run)) => run.execution.cycles.len(),
            _ => panic!("executed"),
        };
        assert!(n > KEPT_CYCLE_RUNS);
        for k in 0..n {
            cache.request_cycle(key, k, false);
            assert!(cache.cycle(key, k).is_some());
        }
        assert!(cache.cycles.len() <= KEPT_CYCLE_RUNS);
        assert!(cache.cycle(key, 0).is_some(), "the prediction is kept");
    }

    #[test]
    fn why_an_activity_was_lost_is_explained_off_the_frame_for_its_key() {
        let mut plan = plan();
        plan.battery.min_soc = 950.0;
        let source = ActualsSource::File {
            path: "long.json".into(),
            text: r#"{"format": "solscope.actuals/1", "durations": {"drive": 6600}}"#.into(),
        };
        let key = ExecKey {
            revision: 0,
            actuals: 0,
        };
        let mut cache = ExecutionCache::default();
        cache.request(&plan, &source, key, false);
        let post = plan
            .activities
            .iter()
            .position(|a| a.id == "post_drive_imaging")
            .expect("activity");
        let drive = plan.activities.iter().position(|a| a.id == "drive");
        // A completed activity has nothing to explain.
        cache.request_loss(&plan, key, drive.expect("drive"), true);
        assert!(!cache.busy());
        cache.request_loss(&plan, key, post, true);
        for _ in 0..2000 {
            cache.reap(key).expect("worker result");
            if !cache.busy() {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        let loss = cache
            .loss(key, post)
            .expect("derived")
            .as_ref()
            .expect("explained");
        assert_eq!(loss.activity, post);
        assert_eq!(loss.outcome, RunOutcome::NotRun);
        let other = ExecKey {
            revision: 1,
            actuals: 0,
        };
        assert!(
            cache.loss(other, post).is_none(),
            "read back only for its key"
        );
    }

    /// Reaps `cache` at `revision` until no worker runs.
    fn settle_flex(cache: &mut FlexCache, revision: u64) {
        for _ in 0..4000 {
            cache.reap(revision).expect("worker result");
            if !cache.busy() {
                return;
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        panic!("the flex workers never finished");
    }

    #[test]
    fn free_slack_fills_in_on_a_worker_stops_and_goes_on() {
        let text = include_str!("../../assets/default-plan.json");
        let plan = solscope_engine::load_plan(text).expect("plan").plan;
        let analysis = Analysis::of(&plan).expect("scheduled");
        let mut cache = FlexCache::default();
        cache.request(&plan, &analysis, 0, true);
        settle_flex(&mut cache, 0);
        let p = cache.free_slack_progress(0).expect("first stage in");
        assert_eq!((p.done, p.running), (0, false));
        assert!(p.total > 0);
        // Started, then stopped at once: nothing is taken after the stop.
        cache.request_free_slack(0, 0.0);
        assert!(cache.busy() && cache.free_slack_progress(0).is_some_and(|p| p.running));
        cache.stop_free_slack();
        assert!(!cache.busy());
        let stopped = cache.free_slack_progress(0).expect("progress");
        assert!(!stopped.running && !stopped.complete());
        // Asked again, it goes on to the end.
        cache.request_free_slack(0, 0.0);
        settle_flex(&mut cache, 0);
        let done = cache.free_slack_progress(0).expect("progress");
        assert!(done.complete() && !done.running, "{done:?}");
        let flex = cache.get(0).expect("derived").as_ref().expect("computed");
        assert_eq!(**flex, solscope_engine::flex(&plan, &analysis.schedule));
        // Nothing left: no worker starts.
        cache.request_free_slack(0, 0.0);
        assert!(!cache.busy());
        // A newer revision drops the old worker and its values.
        cache.request(&plan, &analysis, 1, true);
        assert!(cache.get(1).is_none());
        settle_flex(&mut cache, 1);
        assert_eq!(cache.free_slack_progress(1).map(|p| p.done), Some(0));
    }

    #[test]
    fn a_flexible_schedule_of_an_older_revision_is_dropped() {
        let plan = plan();
        let analysis = Analysis::of(&plan).expect("scheduled");
        let mut cache = FlexCache::default();
        cache.request(&plan, &analysis, 0, true);
        assert!(cache.busy());
        // One worker at a time: a request for a newer revision waits.
        cache.request(&plan, &analysis, 1, true);
        for _ in 0..2000 {
            cache.reap(1).expect("worker result");
            if !cache.busy() {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        assert!(cache.get(0).is_none() && cache.get(1).is_none());
        cache.request(&plan, &analysis, 1, false);
        let flex = cache.get(1).expect("derived").as_ref().expect("computed");
        assert_eq!(**flex, solscope_engine::flex(&plan, &analysis.schedule));
        assert!(cache.get(0).is_none(), "read back only for its revision");
    }
}
