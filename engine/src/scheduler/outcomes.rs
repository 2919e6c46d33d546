//! Outcome-only runs: where activities are placed in the run of an edited plan,
//! without the step trace and without searching the steps whose outcome is known
//! from a one-point check. Suggestion verification asks only that.
//!
//! Three shortcuts, each exact:
//!
//! - The ideal placement. The greedy step picks, among the feasible (start,
//!   duration) pairs, the longest duration, then the first window, then the start
//!   nearest the window's preferred time. If the longest duration at the preferred
//!   time (clamped into the first window that admits it) fits, nothing can beat it:
//!   it is the outcome, whatever the rest of the state.
//! - A plan-wide limit relaxed (`battery.min_soc` or `handover.min_soc` lowered,
//!   `power.max_peak`, `data.capacity` or `handover.max_data_volume` raised), as
//!   the explainer's least-relaxation search does: while every step so far came
//!   out as in the original run, the state is the same, a relaxation only adds
//!   feasible starts, and a step's outcome can change only where the starts it
//!   rejected on the relaxed limit came within the relaxation of it (the record
//!   bounds how close they came; [`Relaxation::keeps`]).
//! - Steps after a new placement. For an edit that makes activity `a` schedule,
//!   the steps after `a`'s see one difference from the original run: `a`'s
//!   placement (and what it generates). When that difference can only take starts
//!   away from a later activity `j` (it adds load, busy time, data, sleep or awake
//!   time that `j` cannot use), `j`'s feasible set can only shrink, so if `j`'s
//!   original placement still fits it is still the choice, and if `j` failed it
//!   still fails. From the first step whose outcome changes, steps are searched.
//!   The same holds when the edit also moves `a` in the step order (a new
//!   priority) and `a` failed in the original run: its original step changed
//!   nothing, so the others' steps, in their unchanged order, see only `a`'s new
//!   placement.
//!
//! The steps a rerun shares with the run explained (the same activities, placed
//! the same, in a problem with the same timelines) leave the state that run had
//! after them: a rerun starts from the latest of that run's [`Checkpoints`]
//! among them instead of replaying them all.
//!
//! Debug builds compare every outcome with the full scheduler's.

use super::state::{Placement, State};
use super::{Detail, Evaluated, Schedule, Scope, run_step};
use crate::error::Error;
use crate::model::{AwakeMode, Plan};

/// Placements by activity index (`None`: not placed, or its step not run).
pub(crate) type Placements = Vec<Option<(i64, i64)>>;

/// Where activity `a` is placed when the edited plan compiled as `problem`
/// is scheduled (`None`: it fails), running only the steps up to `a`'s and
/// reusing the steps of `prev` (the run before the edit) that the edit cannot
/// change.
pub(crate) fn placement_after_edit(
    prev: &Schedule,
    starts: Option<&Checkpoints<'_>>,
    problem: super::Problem,
    a: usize,
) -> Result<Option<(i64, i64)>, Error> {
    Ok(run_to(prev, starts, problem, a, false)?.0)
}

/// [`placement_after_edit`], with the run's record of the steps up to `a`'s: a
/// [`Schedule`] of those steps alone (no generated activities) that can stand
/// as `prev` for an edit that relaxes the same plan-wide limit further. The
/// least-relaxation search probes values each looser than the last that
/// failed; run from that one, a probe's relaxation is small, so most steps keep
/// their outcome ([`Relaxation::keeps`]) and are replayed, not searched. Debug
/// builds compare each recorded step's activity and placement with a full run;
/// a record's bounds are checked where a later run keeps its step (against a
/// search, in [`Run::up_to`]).
pub(crate) fn probe_after_edit(
    prev: &Schedule,
    starts: Option<&Checkpoints<'_>>,
    problem: super::Problem,
    a: usize,
) -> Result<(Option<(i64, i64)>, Schedule), Error> {
    run_to(prev, starts, problem, a, true)
}

/// The run of the edited plan compiled as `problem` up to `a`'s step: where
/// `a` is placed, and with `record` the steps' records (else none).
fn run_to(
    prev: &Schedule,
    starts: Option<&Checkpoints<'_>>,
    problem: super::Problem,
    a: usize,
    record: bool,
) -> Result<(Option<(i64, i64)>, Schedule), Error> {
    let until = problem.step_of.get(a).copied().unwrap_or(0);
    let run = Run::up_to(prev, starts, &problem, until, Some(a), record);
    let placed = run.placements.get(a).copied().flatten();
    let steps = run.steps;
    #[cfg(debug_assertions)]
    {
        let full = super::schedule_compiled(problem.clone());
        debug_assert_eq!(placed, full.placement(a), "the outcome-only run disagrees");
        for (mine, theirs) in steps.iter().zip(&full.steps) {
            debug_assert_eq!(
                (mine.activity, mine.outcome.placement()),
                (theirs.activity, theirs.outcome.placement()),
                "a recorded step of the outcome-only run disagrees"
            );
        }
    }
    Ok((placed, Schedule::from_parts(problem, steps, Vec::new())))
}

/// Where each activity is placed in the run of the edited plan (compiled:
/// `problem`), when one of the activities `targets` is placed in it; `None` when none is (only the steps
/// up to the last target's are then run). `prev` is the run of the plan before
/// the edit.
///
/// One run answers every target: the suggestion verifier asks once for an edit
/// that several failures propose, and once, with every activity as a target, for
/// an edit whose whole run it keeps. With a single target `a`, the steps after
/// `a`'s keep their original placement where `a`'s new placement can only take
/// starts away from them (the module docs).
///
/// The run stops after the last of the targets' steps and the steps of the
/// activities placed in `prev`: the later steps' activities failed in `prev`,
/// and what the verifier asks of a run is where the targets go and which of
/// `prev`'s placements are lost (the activities after it are left `None`).
/// On a plan whose last placements come early (standard 1k: the last at step
/// 754, nine in ten by step 257) that leaves out the failing tail, where
/// every step is a whole search.
pub(crate) fn placements_if_placed(
    prev: &Schedule,
    starts: Option<&Checkpoints<'_>>,
    problem: &super::Problem,
    targets: &[usize],
) -> Result<Option<Placements>, Error> {
    let until = targets
        .iter()
        .filter_map(|&t| problem.step_of.get(t).copied())
        .max()
        .unwrap_or(0);
    let single = match targets {
        &[a] => Some(a),
        _ => None,
    };
    let Run {
        mut state,
        mut placements,
        placed_a,
        done,
        ..
    } = Run::up_to(prev, starts, problem, until, single, false);
    let any_placed = match single {
        Some(_) => placed_a.is_some(),
        None => targets
            .iter()
            .any(|&t| placements.get(t).is_some_and(Option::is_some)),
    };
    if !any_placed {
        return Ok(None);
    }
    // The original run's state, stepped alongside while only `a`'s placement
    // differs: every other activity unchanged, in the same order, and `a` either
    // at its own step or, when it failed in the original run (so its step there
    // changed nothing), moved earlier or later in the order (a new priority).
    // Steps are matched by activity: `orig[j]` is `j`'s index in `prev.steps`.
    let orig = |j: usize| prev.problem.step_of[j] - 1;
    let drain = placed_a.as_ref().map_or(0, |ev| ev.energy);
    let mut old = match (single, placed_a) {
        (Some(a), Some(placed_a))
            if (problem.differs_only_in(&prev.problem, a)
                || (prev.placement(a).is_none() && moved_only(&prev.problem, problem, a)))
                && restrictive(problem, &placed_a) =>
        {
            // The original steps of the activities run so far, in their order:
            // a prefix of the original run, and past it (when `a` moved) the
            // steps of the activities that moved before it.
            let mut run: Vec<usize> = problem.order[..done].iter().map(|&j| orig(j)).collect();
            run.sort_unstable();
            let prefix = run.iter().enumerate().take_while(|&(i, &k)| i == k).count();
            let (from, mut old_state) = match starts {
                Some(c) => {
                    let (k, state) = c.at_most(c.agree(prev, &prev.problem, prefix));
                    (k, state.rebased(&prev.problem))
                }
                None => (0, State::new(&prev.problem)),
            };
            for &i in &run[from..] {
                old_state.replay(&prev.steps[i]);
            }
            Some((old_state, placed_a.placement))
        }
        _ => None,
    };
    // The steps run: up to the last target's and the last that placed an
    // activity in `prev`.
    let stop = problem
        .order
        .iter()
        .rposition(|&j| prev.placement(j).is_some())
        .map_or(0, |k| k + 1)
        .max(until);
    for (k, &j) in problem.order.iter().enumerate().take(stop).skip(done) {
        let step_no = k + 1;
        if let Some((old_state, pa)) = old.as_mut() {
            let before = &prev.steps[orig(j)];
            if !interacts(problem, pa, j) {
                let old_ev = old_state.replay(before);
                match (before.outcome.placement(), old_ev) {
                    (None, _) => continue,
                    (Some((s, e)), Some(old_ev)) => {
                        // The state of charge is lower than in the original run
                        // by at most the charge `a`'s placement drains (a capped
                        // integrator falls by at most the extra drain), so a
                        // margin at least that large needs no energy check.
                        let soc = prev.margins()[orig(j)].is_none_or(|m| m < drain);
                        if let Some(ev) = state.fitting_inner(j, s, e - s, &Scope::default(), soc) {
                            if !same_generated(&ev.placement, &old_ev.placement) {
                                old = None;
                            }
                            placements[j] = Some((s, e));
                            state.apply(step_no, &ev.placement);
                            continue;
                        }
                        // The original placement no longer fits: search below.
                        old = None;
                    }
                    (Some(_), None) => old = None,
                }
            }
        }
        // A step that failed in the original run rarely gets its ideal
        // placement now: searched at once.
        let hint = prev.steps[orig(j)].outcome.placement().is_some();
        let ev = recorded_step(&state, j, step_no, false, hint).0;
        let placement = ev.as_ref().map(|ev| span(&ev.placement));
        if let Some((old_state, _)) = old.as_mut() {
            let before = &prev.steps[orig(j)];
            let old_ev = old_state.replay(before);
            let same = placement == before.outcome.placement()
                && match (&ev, &old_ev) {
                    (Some(x), Some(y)) => same_generated(&x.placement, &y.placement),
                    (None, None) => true,
                    _ => false,
                };
            if !same {
                old = None;
            }
        }
        placements[j] = placement;
        if let Some(ev) = ev {
            state.apply(step_no, &ev.placement);
        }
    }
    #[cfg(debug_assertions)]
    {
        let full = super::schedule_compiled(problem.clone());
        let mut want: Vec<Option<(i64, i64)>> =
            (0..problem.acts.len()).map(|x| full.placement(x)).collect();
        for &j in &problem.order[stop.max(done)..] {
            want[j] = None;
        }
        debug_assert_eq!(
            placements, want,
            "the shortcut rerun disagrees with a full run"
        );
    }
    Ok(Some(placements))
}

/// A whole run's outcome without its trace (what an execution cycle dispatches
/// from): where each activity is placed, and the awake periods and preheats the
/// run generated.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RunOutcomes {
    /// Placement by activity index.
    pub placements: Vec<Option<(i64, i64)>>,
    /// The awake periods at the end of the run, sorted.
    pub awake: Vec<(i64, i64)>,
    /// Preheats `(zone, start, end, activity)`.
    pub preheats: Vec<(usize, i64, i64, usize)>,
    /// The step (1-based) of each activity.
    pub step_of: Vec<usize>,
}

impl RunOutcomes {
    /// The outcomes of the run `sched` records, its steps replayed (what
    /// [`run_outcomes`] gives for its plan, without searching again).
    pub fn of(sched: &Schedule) -> Self {
        Self::collect(&sched.problem, |state, k, _| state.replay(&sched.steps[k]))
    }

    /// The outcomes of the run of `problem` in which step `k + 1` (activity
    /// `a`) places what `step(state, k, a)` returns, leaving it applied to
    /// `state`.
    fn collect(
        problem: &super::Problem,
        mut step: impl FnMut(&mut State<'_>, usize, usize) -> Option<Evaluated>,
    ) -> Self {
        let mut state = State::new(problem);
        let mut placements = vec![None; problem.acts.len()];
        let mut preheats = Vec::new();
        for (k, &a) in problem.order.iter().enumerate() {
            if let Some(ev) = step(&mut state, k, a) {
                placements[a] = Some(span(&ev.placement));
                preheats.extend(ev.placement.preheats.iter().map(|&(z, s, e)| (z, s, e, a)));
            }
        }
        Self {
            placements,
            awake: state.awake,
            preheats,
            step_of: problem.step_of.clone(),
        }
    }
}

/// Schedules `plan` for its outcomes only: the same placements as [`schedule`]
/// (debug builds check it), without the trace.
///
/// [`schedule`]: super::schedule
pub fn run_outcomes(plan: &Plan) -> Result<RunOutcomes, Error> {
    let problem = super::Problem::compile(plan)?;
    let out = RunOutcomes::collect(&problem, |state, k, a| {
        let ev = outcome_step(state, a, k + 1)?;
        state.apply(k + 1, &ev.placement);
        Some(ev)
    });
    #[cfg(debug_assertions)]
    {
        let full = super::schedule_compiled(problem.clone());
        let want: Vec<Option<(i64, i64)>> =
            (0..problem.acts.len()).map(|x| full.placement(x)).collect();
        debug_assert_eq!(out.placements, want, "the outcome-only run disagrees");
    }
    Ok(out)
}

/// The states of a run after every `every` steps: reruns of edits of its
/// plan start from the latest one among the steps they share with it, rather
/// than replaying those steps from the start. At most [`CHECKPOINTS`] of
/// them, so that their memory stays a small multiple of one state's.
pub(crate) struct Checkpoints<'p> {
    /// The run.
    sched: &'p Schedule,
    every: usize,
    /// `states[i]`: the state after `i * every` steps.
    states: Vec<State<'p>>,
}

/// Most checkpoints kept of one run.
const CHECKPOINTS: usize = 32;

/// Fewest steps between two checkpoints: a state costs more to copy than a
/// few steps to replay. Debug builds keep one after every step of a small
/// run, so that the property tests' small plans start reruns from them.
const MIN_SPACING: usize = if cfg!(debug_assertions) { 1 } else { 16 };

impl<'p> Checkpoints<'p> {
    /// The checkpoints of `sched`, its steps replayed once.
    pub(crate) fn new(sched: &'p Schedule) -> Self {
        let n = sched.steps.len();
        let every = n.div_ceil(CHECKPOINTS).max(MIN_SPACING);
        let mut state = State::new(&sched.problem);
        let mut states = vec![state.clone()];
        for (k, step) in sched.steps.iter().enumerate() {
            state.replay(step);
            if (k + 1) % every == 0 {
                states.push(state.clone());
            }
        }
        Self {
            sched,
            every,
            states,
        }
    }

    /// How many of the first `upto` steps of `prev`, run on `problem`, give
    /// the states of these checkpoints' run: `prev` is that run, or those
    /// steps place the same activities, compiled the same, at the same times,
    /// in a problem with the same timelines (a relaxed limit aside). The
    /// least-relaxation search runs each probe from the last one's run, which
    /// agrees with the run explained up to its first change.
    fn agree(&self, prev: &Schedule, problem: &super::Problem, upto: usize) -> usize {
        let upto = upto.min(prev.steps.len());
        if std::ptr::eq(self.sched, prev) {
            return upto;
        }
        let mine = &self.sched.problem;
        if mine.acts.len() != problem.acts.len()
            || mine.without_limits() != problem.without_limits()
        {
            return 0;
        }
        self.sched
            .steps
            .iter()
            .zip(&prev.steps[..upto])
            .take_while(|(x, y)| {
                x.activity == y.activity
                    && x.outcome.placement() == y.outcome.placement()
                    && mine.acts[x.activity] == problem.acts[x.activity]
            })
            .count()
    }

    /// The latest checkpoint at or before step `k`: its step count and state.
    fn at_most(&self, k: usize) -> (usize, &State<'p>) {
        let i = (k / self.every).min(self.states.len() - 1);
        (i * self.every, &self.states[i])
    }
}

/// The state and placements of an outcome-only run up to some step.
struct Run<'p> {
    state: State<'p>,
    placements: Placements,
    /// The evaluation of the activity looked at (`a`), when it is placed.
    placed_a: Option<Evaluated>,
    /// Steps run.
    done: usize,
    /// The record of each step run, when asked for.
    steps: Vec<super::Step>,
}

impl<'p> Run<'p> {
    /// Runs `problem` (an edit of `prev`'s) up to step `until`, replaying the
    /// steps of `prev` the edit cannot change (from the latest of `starts`
    /// among them, when they agree with `prev`); keeps the evaluation of `a`,
    /// and with `record` the record of each step (a replayed step keeps
    /// `prev`'s, which still bounds its rejected starts: the same state, and a
    /// relaxed limit rejects fewer).
    fn up_to(
        prev: &Schedule,
        starts: Option<&Checkpoints<'_>>,
        problem: &'p super::Problem,
        until: usize,
        a: Option<usize>,
        record: bool,
    ) -> Self {
        let mut steps = Vec::new();
        let common = prev.problem.common_steps(problem).min(until);
        // While every step so far came out as in `prev`, the state is the same as
        // there, and a plan-wide relaxation can change a step only through the
        // tries its record shows failing on the relaxed limit.
        let relaxed = Relaxation::between(&prev.problem, problem);
        // The steps that come out as in `prev`: the common ones, then (for a
        // relaxation) those it keeps.
        let kept = match relaxed {
            Some(r) => {
                common
                    + prev.steps[common..until.min(prev.steps.len())]
                        .iter()
                        .enumerate()
                        .take_while(|(i, _)| r.keeps(problem, prev, common + i))
                        .count()
            }
            None => common,
        };
        #[cfg(debug_assertions)]
        for k in common..kept {
            let j = problem.order[k];
            debug_assert_eq!(
                outcome_step(&State::replayed(problem, &prev.steps[..k]), j, k + 1)
                    .map(|ev| span(&ev.placement)),
                prev.steps[k].outcome.placement(),
                "a step the relaxation {relaxed:?} keeps changed: {:?}",
                prev.steps[k]
            );
        }
        // Their state is `prev`'s: after the latest checkpoint among them (not
        // past `a`'s step, whose evaluation is kept), the steps after it
        // replayed.
        let a_step = a
            .and_then(|a| prev.problem.step_of.get(a))
            .map_or(usize::MAX, |&k| k - 1);
        let (from, mut state) = match starts {
            Some(c) if kept > 0 => {
                let (k, state) = c.at_most(c.agree(prev, problem, kept.min(a_step)));
                (k, state.rebased(problem))
            }
            _ => (0, State::new(problem)),
        };
        let mut placements = vec![None; problem.acts.len()];
        let mut placed_a = None;
        for (k, step) in prev.steps[..kept].iter().enumerate() {
            placements[step.activity] = step.outcome.placement();
            if k >= from {
                let ev = state.replay(step);
                if Some(step.activity) == a {
                    placed_a = ev;
                }
            }
            if record {
                steps.push(step.clone());
            }
        }
        let mut same_so_far = true;
        for (k, &j) in problem.order.iter().enumerate().take(until).skip(kept) {
            let before = &prev.steps[k];
            if same_so_far && relaxed.is_some_and(|r| r.keeps(problem, prev, k)) {
                placements[j] = before.outcome.placement();
                let ev = state.replay(before);
                debug_assert_eq!(
                    outcome_step(&State::replayed(problem, &prev.steps[..k]), j, k + 1)
                        .map(|ev| span(&ev.placement)),
                    placements[j],
                    "a step the relaxation {relaxed:?} keeps changed: {before:?}"
                );
                if Some(j) == a {
                    placed_a = ev;
                }
                if record {
                    steps.push(before.clone());
                }
                continue;
            }
            let hint = before.activity != j || before.outcome.placement().is_some();
            let (ev, step) = recorded_step(&state, j, k + 1, record, hint);
            steps.extend(step);
            let placement = ev.as_ref().map(|ev| span(&ev.placement));
            same_so_far &= before.activity == j && placement == before.outcome.placement();
            if let Some(ev) = ev {
                placements[j] = placement;
                state.apply(k + 1, &ev.placement);
                if Some(j) == a {
                    placed_a = Some(ev);
                }
            }
        }
        Self {
            state,
            placements,
            placed_a,
            done: until,
            steps,
        }
    }
}

/// One plan-wide limit relaxed, everything else equal: the edits the explainer
/// searches to the least relaxation that works.
#[derive(Clone, Copy, Debug)]
enum Relaxation {
    /// `battery.min_soc` lowered to this (mJ).
    MinSoc(i128),
    /// `power.max_peak` raised to this (mW).
    MaxPeak(i64),
    /// `data.capacity` raised.
    DataCap,
    /// `handover.min_soc` lowered.
    HandoverSoc,
    /// `handover.max_data_volume` raised.
    HandoverData,
}

impl Relaxation {
    /// The relaxation that turns `old` into `new`, if that is all that differs.
    fn between(old: &super::Problem, new: &super::Problem) -> Option<Self> {
        if old.acts != new.acts || old.order != new.order {
            return None;
        }
        let (old, new) = (old.plan_wide(), new.plan_wide());
        let with = |f: &dyn Fn(&mut super::Problem)| {
            let mut x = new.clone();
            f(&mut x);
            x == old
        };
        if new.min_soc < old.min_soc && with(&|x| x.min_soc = old.min_soc) {
            return Some(Self::MinSoc(new.min_soc));
        }
        if let (Some(n), Some(o)) = (new.max_peak, old.max_peak) {
            if n > o && with(&|x| x.max_peak = old.max_peak) {
                return Some(Self::MaxPeak(n));
            }
        }
        if let (Some(n), Some(o)) = (new.data_cap, old.data_cap) {
            if n > o && with(&|x| x.data_cap = old.data_cap) {
                return Some(Self::DataCap);
            }
        }
        if let (Some(n), Some(o)) = (new.handover_soc, old.handover_soc) {
            if n < o && with(&|x| x.handover_soc = old.handover_soc) {
                return Some(Self::HandoverSoc);
            }
        }
        if let (Some(n), Some(o)) = (new.handover_data, old.handover_data) {
            if n > o && with(&|x| x.handover_data = old.handover_data) {
                return Some(Self::HandoverData);
            }
        }
        None
    }

    /// Whether the step recorded in `step` (run on the same state under the
    /// stricter limit) comes out the same under this relaxation. A relaxation only
    /// adds feasible starts, so the recorded choice stays feasible; it stays the
    /// choice, and a failure stays a failure, when every start the step rejected
    /// still fails: only those rejected on the relaxed limit could pass, and the
    /// record bounds how close they came (`Step::rejected`: the highest lowest
    /// state of charge, the lowest peak), except where the failing part of a
    /// cell touches its passing part. The record covers the durations the step
    /// recorded, so an expanding activity that failed or got less than its
    /// longest duration is not kept. Phase 1 does not look at energy or peak
    /// power; the data limits change it only where the record shows the data
    /// category excluding some start of the window span. `k` is the step's
    /// index in `prev`, the run it is recorded in.
    fn keeps(self, problem: &super::Problem, prev: &Schedule, k: usize) -> bool {
        let step = &prev.steps[k];
        let act = &problem.acts[step.activity];
        if act.dur_min != act.dur_max && step.duration != act.dur_max {
            return false;
        }
        if act.dur_min != act.dur_max && step.outcome.placement().is_none() {
            return false;
        }
        let handover_binds = !act.mandatory && problem.handover_time.is_some();
        match self {
            Self::MinSoc(min) => {
                // The record bounds the lowest state of charge of every start
                // rejected on energy that the handover limit lets pass
                // (`Rejected::soc`). A cell whose feasible part is a sub-range
                // reports the rest with the numbers of its far end, not its
                // best: a failing range touching a passing one is not trusted.
                let r = &step.rejected;
                !r.soc_untrusted && r.soc.is_none_or(|soc| i128::from(soc) < min)
            }
            Self::MaxPeak(max) => step.rejected.peak.is_none_or(|peak| peak > max),
            Self::DataCap => act.data <= 0 || prev.data_room(k + 1),
            Self::HandoverSoc => !handover_binds,
            Self::HandoverData => act.mandatory || prev.data_room(k + 1),
        }
    }
}

/// The placement step `step_no` (activity `a`) makes in `state`: the ideal one
/// when it fits, else the full search's.
fn outcome_step(state: &State<'_>, a: usize, step_no: usize) -> Option<Evaluated> {
    recorded_step(state, a, step_no, false, true).0
}

/// [`outcome_step`], with the step's record when `record` (the ideal placement,
/// which nothing can beat, records no rejected start). Without `try_ideal`
/// (a hint that it rarely fits: the activity failed in a run like this one)
/// the step is searched at once: the same outcome, without the cost of the
/// ideal placement's check where it fails.
pub(super) fn recorded_step(
    state: &State<'_>,
    a: usize,
    step_no: usize,
    record: bool,
    try_ideal: bool,
) -> (Option<Evaluated>, Option<super::Step>) {
    if let Some(ev) = try_ideal.then(|| ideal(state, a)).flatten() {
        debug_assert_eq!(
            run_step(state, a, step_no, &Scope::default(), Detail::Outcome)
                .step
                .outcome
                .placement(),
            Some(span(&ev.placement)),
            "the ideal placement is not the step's"
        );
        let step = record.then(|| {
            let (start, end) = span(&ev.placement);
            super::Step {
                step: step_no,
                activity: a,
                outcome: super::Outcome::Scheduled { start, end },
                duration: end - start,
                rejected: super::Rejected::default(),
                added: Vec::new(),
                retired: Vec::new(),
            }
        });
        return (Some(ev), step);
    }
    // Without the record, only where `a` lands counts.
    let detail = if record {
        Detail::Outcome
    } else {
        Detail::Placement
    };
    let run = run_step(state, a, step_no, &Scope::default(), detail);
    (run.found, record.then_some(run.step))
}

/// Activity `a`'s ideal placement, if it fits: the longest duration, in the
/// first window whose execution range admits it, at the start nearest the
/// window's preferred time.
fn ideal(state: &State<'_>, a: usize) -> Option<Evaluated> {
    let act = &state.problem.acts[a];
    if act.group.and_then(|g| state.group_member[g]).is_some() {
        return None;
    }
    let d = act.dur_max;
    let (w, range) = act
        .windows
        .iter()
        .map(|w| (w, state.window_range(a, w, d)))
        .find(|(_, r)| !r.is_empty())?;
    let s = w.preferred.clamp(range.lo, range.hi);
    state.fitting(a, s, d, &Scope::default())
}

/// `[start, end)` of a placement.
pub(super) fn span(p: &Placement) -> (i64, i64) {
    (p.start, p.start + p.duration)
}

/// Whether `new` is `old` with only activity `a` changed, possibly at another
/// place in the step order: the same plan-wide parameters, every other activity
/// the same and in the same relative order.
fn moved_only(old: &super::Problem, new: &super::Problem, a: usize) -> bool {
    old.acts.len() == new.acts.len()
        && old
            .acts
            .iter()
            .zip(&new.acts)
            .enumerate()
            .all(|(j, (x, y))| j == a || x == y)
        && old
            .order
            .iter()
            .filter(|&&j| j != a)
            .eq(new.order.iter().filter(|&&j| j != a))
        && old.plan_wide() == new.plan_wide()
}

/// Whether the placement `ev` of activity `a` only ever takes starts away from
/// later activities, whatever they are (before the per-activity exceptions of
/// [`interacts`]): it drains charge and adds peak power (never gives charge back).
fn restrictive(problem: &super::Problem, ev: &Evaluated) -> bool {
    let p = &ev.placement;
    let act = &problem.acts[p.act];
    act.energy >= 0
        && act.peak >= 0
        && (p.new_awake.is_none() || problem.awake >= problem.asleep)
        && act
            .zones
            .iter()
            .all(|&z| problem.zones[z].preheat >= 0 && problem.zones[z].maintenance >= 0)
}

/// Whether `a`'s placement `pa` can give activity `j` a start it did not have:
/// the activities interact ([`gives_starts`]), or `a` created or extended an
/// awake period `j` could share.
fn interacts(problem: &super::Problem, pa: &Placement, j: usize) -> bool {
    gives_starts(problem, pa.act, j)
        || (pa.new_awake.is_some() && problem.acts[j].awake == AwakeMode::Required)
}

/// Whether activity `a` placed (or having run) can give activity `j` a start
/// it did not have, apart from the awake periods it generates: `j` depends
/// on `a` or shares its group; `a` changes a state `j` requires or changes;
/// `a` downlinks data `j` would produce; or they share a heating zone (`j`
/// could find its zone already heated).
pub(crate) fn gives_starts(problem: &super::Problem, a: usize, j: usize) -> bool {
    gives_starts_unheated(problem, a, j) || shares_zone(problem, a, j)
}

/// [`gives_starts`] but for a shared heating zone.
pub(crate) fn gives_starts_unheated(problem: &super::Problem, a: usize, j: usize) -> bool {
    let (x, y) = (&problem.acts[a], &problem.acts[j]);
    y.after.iter().any(|d| d.target == a)
        || (x.group.is_some() && x.group == y.group)
        || x.effects.iter().any(|e| {
            y.requires.iter().any(|r| r.state == e.state)
                || y.effects.iter().any(|f| f.state == e.state)
        })
        || (x.data < 0 && y.data > 0)
}

/// Whether activities `a` and `j` share a heating zone.
pub(crate) fn shares_zone(problem: &super::Problem, a: usize, j: usize) -> bool {
    let (x, y) = (&problem.acts[a], &problem.acts[j]);
    x.zones.iter().any(|z| y.zones.contains(z))
}

/// Whether two placements of one activity generate the same awake period and
/// preheats.
fn same_generated(x: &Placement, y: &Placement) -> bool {
    x.start == y.start
        && x.duration == y.duration
        && x.new_awake == y.new_awake
        && x.preheats == y.preheats
}
