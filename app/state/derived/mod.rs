//! Values derived from the plan off the frame, each kept with what it was
//! derived for and read back only for that, so nothing stale is ever shown:
//! for the activity looked at, its explanation, valid intervals, verified
//! suggestions and what it would have caused ([`DerivedCache`], its
//! suggestions on a worker); the step profiles ([`step_view`],
//! [`StepViewCache`]); the execution of the plan with the scheduler runs of its
//! cycles ([`ExecutionCache`]); the Monte Carlo campaign ([`CampaignCache`]);
//! and the flexible form of the schedule ([`FlexCache`]). Every worker is a
//! [`Job`].

mod campaign;
mod execution;
mod flex;
#[cfg(test)]
mod tests;

use std::sync::Arc;

use solscope_engine::{
    CategoryIntervals, Explanation, MJ_PER_WH, MW_PER_W, Phase, Phase2Reason, Plan, ReasonRange,
    Suggestion, format_watts, format_wh, involved,
};

pub use campaign::CampaignCache;
pub use execution::{ExecKey, ExecutionCache};
pub use flex::{FlexCache, FlexResult};

use super::document::Analysis;
use super::job::{Job, Lost, Signal};
use super::ui::{OverlayPlot, OverlayReason, StepView, WouldCause};

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
    /// candidate edit can take seconds on a big plan), keyed by activity and
    /// revision.
    pending: Option<Job<(usize, u64), Vec<Suggestion>>>,
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
                let plan = plan.clone();
                let schedule = Arc::clone(&analysis.schedule);
                self.pending = Some(Job::spawn((a, revision), move |_: &Signal| {
                    solscope_engine::verified_suggestions(&plan, &schedule, &ex)
                }));
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
        let (value, lost) = match pending.poll() {
            Some(Ok(list)) => (list, false),
            None => return Ok(()),
            Some(Err(Lost)) => (Vec::new(), true),
        };
        let (activity, at) = pending.key();
        let current = at == revision;
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
        self.pending.as_ref().map(|p| p.key().0)
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
        self.pending = Some(Job::spawn((revision, k), move |_: &Signal| {
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
        let (r, k) = job.key();
        self.pending = None;
        match result {
            Ok(view) if r == revision => Ok(Some(view)),
            Ok(_) => Ok(None),
            Err(Lost) => Err(format!(
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
