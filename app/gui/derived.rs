//! Values derived from the plan for the activity looked at: its explanation, valid
//! intervals and verified suggestions, each kept with the activity and plan
//! revision it was derived for, and the worker thread that verifies suggestions.
//! Also the step profiles ([`step_view`]).

use std::sync::mpsc::{self, Receiver, TryRecvError};

use solscope_engine::{CategoryIntervals, Explanation, Plan, Suggestion};

use super::document::Analysis;
use super::state::StepView;

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
    let profiles = analysis.schedule.profiles_after(k);
    let points = |series: &[(i64, f64)]| -> Vec<[f64; 2]> {
        series.iter().map(|&(t, v)| [t as f64, v]).collect()
    };
    // Peak power holds from each breakpoint to the next (the last one is the
    // horizon end): two points per segment draw it as steps.
    let peak = profiles
        .peak_power
        .windows(2)
        .flat_map(|w| [[w[0].0 as f64, w[0].1], [w[1].0 as f64, w[0].1]])
        .collect();
    StepView {
        step: k,
        soc: points(&profiles.soc),
        peak,
        data: points(&profiles.data_volume),
    }
}
