//! The tuning search on a worker: one at a time, its progress (orders scored
//! and the best score so far) read by the frames, Cancel asking the engine to
//! stop searching (it still confirms the best order found), and its result
//! kept with the plan revision it ran on.

use std::sync::{Arc, Mutex};

use solscope_engine::{Plan, Score};

use super::super::job::{Job, Lost, Signal};
use super::{TuneModel, TuneResult, TuneRunning, TuneSettings};

/// What a tuning worker sends back.
type TuneOutcome = Result<TuneResult, String>;

/// The best score so far and the orders scored, as the engine last said.
type Latest = Arc<Mutex<Option<(u64, Score)>>>;

/// A search running on a worker: its job (keyed by the plan revision it
/// runs on) and what its progress callback last heard.
#[derive(Debug)]
struct TuneJob {
    job: Job<u64, TuneOutcome>,
    latest: Latest,
    budget: u64,
    runs: u64,
}

/// The tuning of the open plan: the last one finished (shown only for the
/// plan revision it ran on), the one running, whether the panel and the
/// Gantt's overlay are shown (runtime state: a result belongs to one plan
/// revision), and whether the last search was stopped by an edit.
#[derive(Debug, Default)]
pub struct TuneCache {
    done: Option<(u64, TuneOutcome)>,
    job: Option<TuneJob>,
    interrupted: bool,
    /// The panel is shown.
    pub open: bool,
    /// The Gantt shows the tuned schedule over the original.
    pub overlay: bool,
}

impl TuneCache {
    /// Starts tuning `plan` (at `revision`) with `settings`: in place, or
    /// with `background` on a worker thread. A search still running is
    /// dropped first (which cancels it).
    pub fn start(&mut self, plan: &Plan, revision: u64, settings: TuneSettings, background: bool) {
        self.job = None;
        self.interrupted = false;
        if background {
            let plan = plan.clone();
            let latest: Latest = Arc::default();
            let heard = Arc::clone(&latest);
            // A plan without duration models is tuned on its one predicted run.
            let uncertain = plan.activities.iter().any(|a| a.duration_model.is_some());
            let (budget, runs) = (settings.budget, if uncertain { settings.runs } else { 1 });
            let job = Job::spawn(revision, move |signal: &Signal| {
                let progress = |n: u64, best: &Score| {
                    if let Ok(mut l) = heard.lock() {
                        *l = Some((n, best.clone()));
                    }
                };
                TuneResult::of(
                    &plan,
                    &settings,
                    Some(signal.cancel_flag()),
                    Some(&progress),
                )
            });
            self.job = Some(TuneJob {
                job,
                latest,
                budget,
                runs,
            });
        } else {
            self.done = Some((revision, TuneResult::of(plan, &settings, None, None)));
        }
    }

    /// Asks the search to stop: the best order found so far is confirmed and
    /// becomes the result.
    pub fn cancel(&self) {
        if let Some(j) = &self.job {
            j.job.cancel();
        }
    }

    /// Forgets the result (and hides the overlay).
    pub fn dismiss(&mut self) {
        self.done = None;
        self.overlay = false;
    }

    /// Takes the worker's result when it is for `revision`. A search of an
    /// older revision is stopped at once (its result would be of the plan as
    /// it was). A worker that stopped without a result is reported.
    pub fn reap(&mut self, revision: u64) -> Result<(), String> {
        let Some(j) = &self.job else {
            return Ok(());
        };
        if j.job.key() != revision {
            // Dropping the job cancels it.
            self.job = None;
            self.interrupted = true;
            return Ok(());
        }
        let Some(outcome) = j.job.poll() else {
            return Ok(());
        };
        self.job = None;
        match outcome {
            Ok(r) => self.done = Some((revision, r)),
            Err(Lost) => {
                let e = "Tuning failed: the worker stopped without a result";
                self.done = Some((revision, Err(e.into())));
                return Err(e.into());
            }
        }
        Ok(())
    }

    /// The last tuning finished, if it ran on `revision`.
    pub fn result(&self, revision: u64) -> Option<&TuneOutcome> {
        self.done
            .as_ref()
            .filter(|(r, _)| *r == revision)
            .map(|(_, d)| d)
    }

    /// The search running, if any.
    pub fn running(&self) -> Option<TuneRunning> {
        let j = self.job.as_ref()?;
        let latest = j.latest.lock().ok().and_then(|l| l.clone());
        Some(TuneRunning {
            evaluations: latest.as_ref().map_or(0, |(n, _)| *n),
            budget: j.budget,
            runs: j.runs,
            best: latest.map(|(_, s)| s),
            cancelling: j.job.cancelling(),
            seconds: j.job.elapsed().as_secs(),
        })
    }

    /// What the views read at `revision`.
    pub fn model(&self, revision: u64) -> TuneModel<'_> {
        let result = self.result(revision);
        TuneModel {
            open: self.open,
            overlay: self.overlay && result.is_some(),
            result,
            running: self.running(),
            stale: result.is_none() && matches!(&self.done, Some((r, Ok(_))) if *r != revision),
            interrupted: self.interrupted,
        }
    }
}
