//! The Monte Carlo campaign: one at a time, on a worker that counts its runs
//! and stops when cancelled, its result kept with the plan revision it ran on.

use solscope_engine::Plan;

use super::super::job::{Job, Lost, Signal};
use super::super::montecarlo::{CampaignResult, Progress, StopReason, Stopped, total_runs};

/// What a campaign worker sends back: the result, `None` when cancelled.
type CampaignOutcome = Result<Option<CampaignResult>, String>;

/// A campaign running on a worker thread: its job counts the runs done and
/// holds the flag that stops starting runs. Dropping it cancels the campaign
/// (nobody would read its result).
#[derive(Debug)]
struct CampaignJob {
    /// The job, keyed by the plan revision it runs on.
    job: Job<u64, CampaignOutcome>,
    seed: u64,
    runs: u64,
    /// It compares the policies (`runs` runs each).
    compare: bool,
}

impl CampaignJob {
    fn progress(&self) -> Progress {
        Progress {
            seed: self.seed,
            runs: self.runs,
            compare: self.compare,
            done: self.job.done().min(total_runs(self.runs, self.compare)),
            cancelling: self.job.cancelling(),
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
            let plan = plan.clone();
            let job = Job::spawn(revision, move |signal: &Signal| {
                let progress = || signal.tick();
                CampaignResult::of(
                    &plan,
                    seed,
                    runs,
                    compare,
                    &progress,
                    Some(signal.cancel_flag()),
                )
            });
            self.job = Some(CampaignJob {
                job,
                seed,
                runs,
                compare,
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
            job.job.cancel();
        }
    }

    /// Takes the worker's result: kept when it is for `revision`. A campaign
    /// of an older revision is stopped at once (its summary would be of the
    /// plan as it was). A worker that stopped without a result is reported.
    pub fn reap(&mut self, revision: u64) -> Result<(), String> {
        let Some(job) = &self.job else {
            return Ok(());
        };
        if job.job.key() != revision {
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
            Err(Lost) => {
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
