//! The flexible form of the schedule, derived once per plan revision: the
//! network first, then the free slack on a worker of its own, handed on one
//! activity at a time.

use std::sync::Arc;
use std::sync::mpsc::{self, Receiver};

use solscope_engine::{Flex, Plan};

use super::super::document::Analysis;
use super::super::job::{Job, Lost, Signal};
use super::super::ui::FreeSlackProgress;

/// The flexible form of one plan revision's schedule, or why there is none.
pub type FlexResult = Result<Arc<Flex>, String>;

/// A worker computing free slack: its results come one activity at a time.
/// Dropping it cancels the worker (through its job).
#[derive(Debug)]
struct FreeSlackJob {
    /// Ends (with nothing) when the worker stops; keyed by the plan revision.
    job: Job<u64, ()>,
    /// Each activity's free slack as it is known.
    rx: Receiver<(usize, solscope_engine::FreeSlack)>,
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
        if self.free.as_ref().is_some_and(|f| f.job.key() != revision) {
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
            self.pending = Some(Job::spawn(revision, move |_: &Signal| {
                compute_flex(&plan, &analysis, false)
            }));
        } else {
            // The free slack only when the layer is shown
            // (`FlexCache::fill_free_slack`).
            self.source = Some((revision, Arc::clone(&analysis.schedule)));
            self.done = Some((revision, compute_flex(plan, analysis, false)));
        }
    }

    /// In place (no worker: tests, `screenshot`), the free slack of every
    /// activity at `revision` not known yet, once the first stage is in.
    pub fn fill_free_slack(&mut self, revision: u64) {
        let Some((r, Ok(flex))) = &mut self.done else {
            return;
        };
        let Some((_, schedule)) = self.source.as_ref().filter(|(s, _)| *s == *r) else {
            return;
        };
        if *r != revision {
            return;
        }
        let todo: Vec<usize> = flex
            .activities
            .iter()
            .filter(|fa| fa.free_slack.is_none())
            .map(|fa| fa.activity)
            .collect();
        if todo.is_empty() {
            return;
        }
        let found = solscope_engine::free_slack_each(schedule, &todo, None, &|_, _| {});
        let flex = Arc::make_mut(flex);
        for (a, fs) in todo.into_iter().zip(found) {
            if let Some(fs) = fs {
                flex.set_free_slack(a, fs);
            }
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
        let schedule = Arc::clone(schedule);
        let job = Job::spawn(revision, move |signal: &Signal| {
            let flag = signal.cancel_flag();
            let send = |a: usize, fs: &solscope_engine::FreeSlack| {
                // A send fails only when the app let go of this worker (it is
                // then cancelled too): the value is dropped on purpose.
                drop(tx.send((a, fs.clone())));
            };
            let run = || {
                solscope_engine::free_slack_each(&schedule, &order, Some(flag), &send);
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
        self.free = Some(FreeSlackJob { job, rx });
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
        self.one = Some(Job::spawn((revision, a), move |_: &Signal| {
            solscope_engine::free_slack_of(&schedule, a)
        }));
    }

    /// The activity whose free slack is being computed on its own at
    /// `revision`, if any.
    pub fn computing_one(&self, revision: u64) -> Option<usize> {
        self.one
            .as_ref()
            .filter(|j| j.key().0 == revision)
            .map(|j| j.key().1)
    }

    /// Stops the free slack worker (the layer was turned off): what it found
    /// stays.
    pub fn stop_free_slack(&mut self) {
        if let Some(f) = self.free.take() {
            self.spent += f.job.elapsed().as_secs_f64();
            // What it sent since the last reap is kept too (not computed again).
            if let Some((r, Ok(flex))) = &mut self.done {
                if *r == f.job.key() {
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
        let running = self.free.as_ref().is_some_and(|f| f.job.key() == revision);
        let now = self
            .free
            .as_ref()
            .filter(|_| running)
            .map_or(0.0, |f| f.job.elapsed().as_secs_f64());
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
                let current = job.key() == revision;
                self.pending = None;
                match result {
                    Ok(f) if current => self.done = Some((revision, f)),
                    Ok(_) => self.source = None,
                    Err(Lost) if current => {
                        let e = "Computing the flexible schedule failed: the worker stopped \
                                 without a result";
                        self.done = Some((revision, Err(e.into())));
                        return Err(e.into());
                    }
                    Err(Lost) => {}
                }
            }
        }
        if let Some(job) = &self.one {
            if let Some(result) = job.poll() {
                let (r, a) = job.key();
                self.one = None;
                match (result, &mut self.done) {
                    (Ok(Some(fs)), Some((d, Ok(flex)))) if r == revision && *d == r => {
                        Arc::make_mut(flex).set_free_slack(a, fs);
                    }
                    (Ok(_), _) => {}
                    (Err(Lost), _) if r == revision => {
                        self.failed = Some(revision);
                        return Err("Computing the selected activity's free slack failed: the \
                                    worker stopped without a result"
                            .into());
                    }
                    (Err(Lost), _) => {}
                }
            }
        }
        let Some(free) = &self.free else {
            return Ok(());
        };
        if free.job.key() != revision {
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
        self.spent += free.job.elapsed().as_secs_f64();
        self.free = None;
        match ended {
            Ok(()) => Ok(()),
            Err(Lost) => {
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
