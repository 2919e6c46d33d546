//! The explainer: why an activity failed and what to change.
//!
//! Everything here returns structured values; `text` is the one place that turns
//! them into sentences, and `report::explain` into the explanation document.
//!
//! Failure steps come from one replay of the run (`replay`): per failed activity f
//! with failure step k_f, at most k_f + 1 probes, each looked at only when a
//! placement could change its answer. Then per failure: minimal conflicts and
//! relaxations (`conflicts`), the placed activities to blame (`culprits`), and
//! verified suggestions (`suggest`).

mod conflicts;
mod culprits;
mod floors;
mod replay;
mod spending;
mod suggest;
mod text;

use serde::Serialize;

pub use conflicts::{Relaxation, minimal_conflicts};
pub use culprits::{Blame, Consumer, energy_consumers, peak_users};
pub use text::{
    explain_text, explanation_notes, explanation_notes_and_lead, explanation_text, involved,
    reason_line, reasons_in_reading_order, suggestion_description, suggestion_line,
};

use crate::error::Error;
use crate::model::Plan;
use crate::scheduler::{
    Category, CategoryIntervals, FailurePhase, Outcome, Phase2Reason, Schedule, Step, StepTrace,
    step_intervals,
};
use crate::timeline::IntervalSet;

/// The phase in which an activity failed, as the spec names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Phase {
    /// No start satisfies the phase-1 categories together.
    ValidIntervals,
    /// Valid intervals exist but phase 2 failed everywhere.
    Placement,
    /// A dependency failed or was skipped.
    Dependency,
    /// Skipped: another member of its group was scheduled.
    Group,
}

impl Phase {
    /// The spec's name.
    pub fn name(self) -> &'static str {
        match self {
            Phase::ValidIntervals => "valid_intervals",
            Phase::Placement => "placement",
            Phase::Dependency => "dependency",
            Phase::Group => "group",
        }
    }
}

/// A range of starts tried in phase 2 that failed for one reason.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct ReasonRange {
    /// First start of the range.
    pub first: i64,
    /// Last start of the range.
    pub last: i64,
    /// Duration tried.
    pub duration: i64,
    /// The reason, with its numbers (evaluated at `probe`).
    pub reason: Phase2Reason,
    /// The start at which the numbers were evaluated.
    pub probe: i64,
}

/// An already placed activity that contributes to a failure.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Culprit {
    /// Activity index.
    pub activity: usize,
    /// The step that placed it.
    pub step: usize,
    /// What it is blamed for.
    pub blame: Blame,
}

/// A suggested edit in the spec's edit format, verified by rescheduling.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Suggestion {
    /// Plain-language description.
    pub description: String,
    /// `"plan"` or `"activity:ID"`.
    pub target: String,
    /// Replacement top-level fields of the target.
    pub set: serde_json::Map<String, serde_json::Value>,
    /// Activities (indices) that were scheduled before the edit and fail after it.
    pub side_effects: Vec<usize>,
}

/// Why one activity ended as it did, and what would change it.
#[derive(Clone, Debug, Serialize)]
pub struct Explanation {
    /// Activity index.
    pub activity: usize,
    /// Its step in the run.
    pub step: usize,
    /// The run's outcome.
    pub outcome: Outcome,
    /// Earliest step k (0 <= k < step) at which it fails when placed after steps
    /// 1..k; `None` for a scheduled activity.
    pub failure_step: Option<usize>,
    /// The failure phase at the failure step.
    pub phase: Option<Phase>,
    /// The dependency target or group member responsible (phase dependency/group).
    pub blocked_by: Option<usize>,
    /// Duration the intervals are for.
    pub duration: i64,
    /// Valid starts per category at the failure step (or at its step when
    /// scheduled).
    pub categories: Vec<CategoryIntervals>,
    /// Their intersection within the windows.
    pub intersection: IntervalSet,
    /// Every minimal set of categories whose valid intervals do not intersect.
    pub conflicts: Vec<Vec<Category>>,
    /// Every minimal set of categories whose removal leaves a start, with a witness.
    pub relaxations: Vec<Relaxation>,
    /// Phase-2 failures, grouped into ranges of starts, in the order tried.
    pub reasons: Vec<ReasonRange>,
    /// When more than [`REASON_RANGES_MAX`] ranges failed: how many there were
    /// before `reasons` joined those of one duration and reason across the
    /// starts between them that were not tried (`None`: listed as tried).
    pub reasons_joined: Option<usize>,
    /// Placed activities to blame.
    pub culprits: Vec<Culprit>,
    /// Verified suggestions, least disruptive first.
    pub suggestions: Vec<Suggestion>,
    /// When suggestions were verified and no single edit makes the activity
    /// schedule: `Some`, with two edits that together do (verified by
    /// rescheduling with both), or empty when no pair tried does.
    pub together: Option<Vec<Suggestion>>,
}

/// Options for [`explain`].
#[derive(Clone, Debug, Default)]
pub struct ExplainOptions {
    /// Explain only this activity (by id), whatever its outcome.
    pub activity: Option<String>,
    /// Skip the (rescheduling) verification of suggestions and list none.
    pub no_suggestions: bool,
}

/// Explains every failed or skipped activity of a run (or the one named).
/// `plan` must be valid (as [`load_plan`](crate::load_plan) gives it) and
/// `sched` its schedule: suggestions edit the plan on that assumption.
pub fn explain(
    plan: &Plan,
    sched: &Schedule,
    opts: &ExplainOptions,
) -> Result<Vec<Explanation>, Error> {
    let mut out = Vec::new();
    explain_each(plan, sched, opts, &mut |_, _| {}, &mut |ex| out.push(ex))?;
    Ok(out)
}

/// [`explain`], handing each explanation to `each` in step order, and reporting
/// `progress(steps replayed, steps)` as the run is replayed. Without suggestions
/// an explanation is handed on once it and every one before it are complete
/// (checked after each block of a few hundred replayed steps), so that a caller
/// can write a large document as it goes, in bounded memory; with suggestions
/// (verified together, edits shared between failures) all of them come at the
/// end.
pub fn explain_each(
    plan: &Plan,
    sched: &Schedule,
    opts: &ExplainOptions,
    progress: &mut dyn FnMut(usize, usize),
    each: &mut dyn FnMut(Explanation),
) -> Result<(), Error> {
    explain_rendered(plan, sched, opts, |ex| ex, progress, each)
}

/// [`explain_each`], handing on `render(explanation)` instead of the
/// explanation (e.g. formatted as a document entry): the explanations ready
/// to go are rendered on rayon's threads, 64 at a time in parallel, and `each`
/// gets the results in step order on the caller's thread.
pub fn explain_rendered<R: Send>(
    plan: &Plan,
    sched: &Schedule,
    opts: &ExplainOptions,
    render: impl Fn(Explanation) -> R + Sync,
    progress: &mut dyn FnMut(usize, usize),
    each: &mut dyn FnMut(R),
) -> Result<(), Error> {
    let targets: Vec<usize> = match &opts.activity {
        Some(id) => {
            let a = plan
                .activities
                .iter()
                .position(|x| &x.id == id)
                .ok_or_else(|| Error::UnknownActivity(id.clone()))?;
            vec![a]
        }
        None => sched
            .steps
            .iter()
            .filter(|s| s.outcome.placement().is_none())
            .map(|s| s.activity)
            .collect(),
    };
    explain_targets(
        plan,
        sched,
        &targets,
        opts.no_suggestions,
        render,
        progress,
        each,
    )
}

/// [`explain_rendered`] for the activities `targets` (in step order), with
/// suggestions unless `no_suggestions`: one replay of the run serves them
/// all, up to the last one's step.
pub(crate) fn explain_targets<R: Send>(
    plan: &Plan,
    sched: &Schedule,
    targets: &[usize],
    no_suggestions: bool,
    render: impl Fn(Explanation) -> R + Sync,
    progress: &mut dyn FnMut(usize, usize),
    each: &mut dyn FnMut(R),
) -> Result<(), Error> {
    let step_of = &sched.problem.step_of;
    debug_assert!(
        targets.is_sorted_by_key(|&a| step_of[a]),
        "targets not in step order"
    );
    let total = sched.steps.len();
    // Without suggestions each explanation goes out once it and those before it
    // are done (the ready ones rendered in parallel); with them they are kept
    // for the verification at the end.
    let stream = no_suggestions;
    let mut kept: Vec<Explanation> = Vec::new();
    // The explanation of targets[i] once complete (taken when handed on).
    let found: std::cell::RefCell<Vec<Option<Explanation>>> =
        std::cell::RefCell::new(vec![None; targets.len()]);
    let next = std::cell::Cell::new(0usize);
    // Hands on the complete explanations at the front, in step order.
    let flush = |each: &mut dyn FnMut(R), kept: &mut Vec<Explanation>| {
        let mut ready = Vec::new();
        {
            let mut found = found.borrow_mut();
            while let Some(ex) = found.get_mut(next.get()).and_then(Option::take) {
                next.set(next.get() + 1);
                ready.push(ex);
            }
        }
        if stream {
            render_each(ready, &render, each);
        } else {
            kept.append(&mut ready);
        }
    };
    // Culprits need the state at the failure step: take it from the replay that
    // finds the step instead of rebuilding it per activity.
    let rank = culprits::EnergyRank::new(sched);
    replay::failure_probes(
        sched,
        targets,
        |i, k, record, trace, state| {
            let a = targets[i];
            let step = &sched.steps[step_of[a] - 1];
            let mut ex = from_probe(sched, a, step, k, record, trace);
            ex.culprits = culprits::culprits(state, &ex, &rank);
            join_untried_gaps(&mut ex);
            ex
        },
        |i, ex| found.borrow_mut()[i] = Some(ex),
        |k| {
            progress(k, total);
            flush(each, &mut kept);
        },
    );
    // Targets the replay did not find fail on their own records.
    for (i, &a) in targets.iter().enumerate().skip(next.get()) {
        let missing = found.borrow()[i].is_none();
        if missing {
            let step = &sched.steps[step_of[a] - 1];
            let state = sched.state_after(step.step - 1);
            let mut ex = from_step(a, step, step_intervals(&state, step));
            ex.culprits = culprits::culprits(&state, &ex, &rank);
            join_untried_gaps(&mut ex);
            found.borrow_mut()[i] = Some(ex);
        }
    }
    flush(each, &mut kept);
    progress(total, total);
    if !stream {
        // In parallel, collected in order, so the output does not depend on the
        // number of threads.
        let lists = suggest::suggestions(plan, sched, &kept);
        let done = kept.into_iter().zip(lists).map(|(mut ex, fixes)| {
            ex.suggestions = fixes.single;
            ex.together = fixes.together;
            ex
        });
        render_each(done.collect(), &render, each);
    }
    Ok(())
}

/// The most reason ranges an explanation lists one by one. Past it, ranges of
/// one duration and one reason that only starts not tried separate (starts
/// outside the windows, or failing phase 1) are joined: one entry per run of a
/// reason instead of one per window, so that a plan of many windows gets an
/// explanation in proportion to what differs, not to its windows. Plans with
/// fewer ranges list them exactly as tried.
pub const REASON_RANGES_MAX: usize = 5000;

/// Whether two reasons are the same for [`join_untried_gaps`]: the same kind,
/// about the same manual sleep or zone (numbers may differ).
fn same_reason(x: &Phase2Reason, y: &Phase2Reason) -> bool {
    use Phase2Reason as R;
    match (x, y) {
        (R::ForcedSleep { sleep: a }, R::ForcedSleep { sleep: b })
        | (R::MinAwake { sleep: a }, R::MinAwake { sleep: b }) => a == b,
        (R::MinSleep { sleep: a }, R::MinSleep { sleep: b }) => a == b,
        (R::PreheatOutsidePlan { zone: a, .. }, R::PreheatOutsidePlan { zone: b, .. })
        | (R::PreheatOperability { zone: a, .. }, R::PreheatOperability { zone: b, .. }) => a == b,
        _ => x.kind() == y.kind(),
    }
}

/// When `ex` lists more than [`REASON_RANGES_MAX`] reason ranges, joins each
/// run of ranges (in their order: duration, longest first, then start) of one
/// duration and the same reason ([`same_reason`]) into one range from the
/// first start to the last, keeping the numbers of the range that came
/// closest to passing (the earliest on a tie, as the ranges themselves keep
/// theirs). Only in phase `placement`, where no start passed: the ranges of
/// a duration list every start tried, in order, so no start between two
/// joined ranges was tried with that duration and another outcome. The
/// culprits are those of the ranges before joining (`ex.culprits` is filled
/// first).
fn join_untried_gaps(ex: &mut Explanation) {
    if ex.reasons.len() <= REASON_RANGES_MAX
        || ex.phase != Some(Phase::Placement)
        || ex.outcome.placement().is_some()
    {
        return;
    }
    let before = ex.reasons.len();
    let mut out: Vec<ReasonRange> = Vec::new();
    for r in std::mem::take(&mut ex.reasons) {
        match out.last_mut() {
            Some(last) if last.duration == r.duration && same_reason(&last.reason, &r.reason) => {
                let (lc, rc) = (last.reason.closeness(), r.reason.closeness());
                // Later ranges start later: a tie keeps the earlier numbers.
                if rc > lc {
                    last.reason = r.reason;
                    last.probe = r.probe;
                }
                last.last = last.last.max(r.last);
            }
            _ => out.push(r),
        }
    }
    ex.reasons = out;
    ex.reasons_joined = Some(before);
}

/// Hands `render(explanation)` of each explanation to `each`, in order,
/// rendering a few at a time in parallel: the output does not depend on the
/// number of threads, and only a few rendered ones wait at any time.
fn render_each<R: Send>(
    exs: Vec<Explanation>,
    render: &(impl Fn(Explanation) -> R + Sync),
    each: &mut dyn FnMut(R),
) {
    use rayon::prelude::*;
    /// Explanations rendered together.
    const CHUNK: usize = 64;
    let mut exs = exs.into_iter();
    loop {
        let chunk: Vec<Explanation> = exs.by_ref().take(CHUNK).collect();
        if chunk.is_empty() {
            break;
        }
        let rendered: Vec<R> = if chunk.len() > 1 {
            chunk.into_par_iter().with_min_len(8).map(render).collect()
        } else {
            chunk.into_iter().map(render).collect()
        };
        for r in rendered {
            each(r);
        }
    }
}

/// The verified suggestions for an explained failure (what [`explain`] adds unless
/// `no_suggestions`): for a caller that already holds the explanation, such as the
/// app, which explains on selection and verifies suggestions in the background.
/// Reschedules the plan once per candidate edit. `plan` must be valid and
/// `sched` its schedule, `ex` one of its explanations (edited plans are
/// compiled sharing `sched`'s compiled activities).
pub fn verified_suggestions(plan: &Plan, sched: &Schedule, ex: &Explanation) -> Vec<Suggestion> {
    if ex.failure_step.is_none() {
        return Vec::new();
    }
    suggest::suggestions(plan, sched, std::slice::from_ref(ex))
        .pop()
        .unwrap_or_default()
        .single
}

/// The explanation skeleton of a scheduled activity (its own step's record,
/// and `trace`, the category intervals of the step run again).
fn from_step(a: usize, step: &Step, trace: StepTrace) -> Explanation {
    Explanation {
        activity: a,
        step: step.step,
        outcome: step.outcome.clone(),
        failure_step: None,
        phase: None,
        blocked_by: None,
        duration: step.duration,
        categories: trace.categories,
        intersection: trace.intersection,
        conflicts: Vec::new(),
        relaxations: Vec::new(),
        reasons: Vec::new(),
        reasons_joined: None,
        culprits: Vec::new(),
        suggestions: Vec::new(),
        together: None,
    }
}

/// The explanation of a failure observed by the probe at step `k` (its record
/// and phase-2 tries).
fn from_probe(
    sched: &Schedule,
    a: usize,
    step: &Step,
    k: usize,
    record: Step,
    trace: StepTrace,
) -> Explanation {
    let (phase, blocked_by) = match record.outcome {
        Outcome::Skipped { by } => (Phase::Group, Some(by)),
        Outcome::Failed(FailurePhase::Dependency { on }) => (Phase::Dependency, Some(on)),
        Outcome::Failed(FailurePhase::ValidIntervals) => (Phase::ValidIntervals, None),
        Outcome::Failed(FailurePhase::Placement) | Outcome::Scheduled { .. } => {
            (Phase::Placement, None)
        }
    };
    let (conflicts, relaxations) = if phase == Phase::ValidIntervals {
        let problem = &sched.problem;
        let preferred = problem.acts[a]
            .windows
            .first()
            .map_or(problem.h0, |w| w.preferred);
        minimal_conflicts(&trace.categories, problem.h0, problem.h1, preferred)
    } else {
        (Vec::new(), Vec::new())
    };
    // The trace already holds the tries grouped into ranges (`merge_tries`).
    let reasons: Vec<ReasonRange> = trace
        .tries
        .iter()
        .filter_map(|t| {
            t.reason.clone().map(|reason| ReasonRange {
                first: t.starts.lo,
                last: t.starts.hi,
                duration: t.duration,
                reason,
                probe: t.probe,
            })
        })
        .collect();
    Explanation {
        activity: a,
        step: step.step,
        outcome: step.outcome.clone(),
        failure_step: Some(k),
        phase: Some(phase),
        blocked_by,
        duration: record.duration,
        categories: trace.categories,
        intersection: trace.intersection,
        conflicts,
        relaxations,
        reasons,
        reasons_joined: None,
        culprits: Vec::new(),
        suggestions: Vec::new(),
        together: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::{Profile, generate_plan_with};
    use crate::scheduler::schedule;

    /// Any subset of a run's failures, explained together on one replay (as
    /// an execution's losses of one cycle are), is explained as each is
    /// among every failure; an activity the run placed, among them, as it
    /// is alone.
    #[test]
    fn subsets_of_failures_are_explained_as_among_all() {
        let json = |e: &Explanation| serde_json::to_value(e).expect("json");
        let mut bits: u64 = 0x9e37_79b9_7f4a_7c15;
        for (profile, seed) in [
            (Profile::Standard, 1),
            (Profile::Realistic, 2),
            (Profile::Starved, 3),
        ] {
            let plan = generate_plan_with(profile, 150, 1, seed);
            let sched = schedule(&plan).expect("schedules");
            let opts = ExplainOptions {
                activity: None,
                no_suggestions: true,
            };
            let all = explain(&plan, &sched, &opts).expect("explains");
            assert!(all.len() >= 4, "{profile:?}: only {} failures", all.len());
            let placed = sched
                .steps
                .iter()
                .find(|s| s.outcome.placement().is_some())
                .map(|s| s.activity)
                .expect("a placed activity");
            let alone = explain(
                &plan,
                &sched,
                &ExplainOptions {
                    activity: Some(plan.activities[placed].id.clone()),
                    no_suggestions: true,
                },
            )
            .expect("explains");
            for round in 0..8 {
                let mut subset: Vec<usize> = all
                    .iter()
                    .map(|e| e.activity)
                    .filter(|_| {
                        bits ^= bits << 13;
                        bits ^= bits >> 7;
                        bits ^= bits << 17;
                        bits % 3 == 0
                    })
                    .collect();
                if round % 2 == 0 {
                    subset.push(placed);
                }
                let step_of = &sched.problem.step_of;
                subset.sort_unstable_by_key(|&a| step_of[a]);
                let mut got = Vec::new();
                explain_targets(
                    &plan,
                    &sched,
                    &subset,
                    true,
                    |e| e,
                    &mut |_, _| {},
                    &mut |e| got.push(e),
                )
                .expect("explains");
                assert_eq!(got.len(), subset.len(), "{profile:?} round {round}");
                for e in &got {
                    let want = all
                        .iter()
                        .chain(&alone)
                        .find(|x| x.activity == e.activity)
                        .expect("explained");
                    assert_eq!(json(e), json(want), "{profile:?} round {round}");
                }
            }
        }
    }
}
