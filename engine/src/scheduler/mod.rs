//! The greedy, non-backtracking scheduler and its step trace.
//!
//! One step per activity in `(priority, file index)` order. A step computes the
//! valid start intervals of every phase-1 category, intersects them per window, and
//! runs the exact phase-2 search (`search.rs`) window by window; the first window
//! with a passing start wins, at the passing start nearest its preferred time.

mod cells;
mod duration;
mod inspect;
mod outcomes;
mod phase1;
mod phase2;
mod problem;
mod profiles;
mod resume;
mod state;
mod trace;

#[cfg(debug_assertions)]
use duration::longest_by_scan;
use duration::{duration_monotone, head_tail_split, longest_scanned, longest_split};
pub use inspect::{PartialSchedule, partial_schedule, valid_intervals_at};
pub(crate) use outcomes::{
    Checkpoints, gives_starts, gives_starts_unheated, placement_after_edit, placements_if_placed,
    probe_after_edit, shares_zone,
};
pub use outcomes::{RunOutcomes, run_outcomes};
pub(crate) use phase2::Evaluated;
pub use problem::{Act, Problem};
pub(crate) use problem::{Dep, HeatHold, Win, compile_windows, step_numbers, value_index};
pub use profiles::Profiles;
pub(crate) use resume::{Before, Prior, Resumed, run_resuming};
pub use state::{Placement, State};
#[cfg(debug_assertions)]
use trace::merge_tries;
pub use trace::{
    Category, CategoryIntervals, FailurePhase, Generated, GeneratedKind, Outcome, Phase2Reason,
    ReasonKind, Step, Try,
};
use trace::{Closeness, Numbers, Rejected, merge_tries_with};

use crate::error::Error;
use crate::model::Plan;
use crate::timeline::{Interval, IntervalSet};

/// Which of an activity's dependencies and requirements a probe leaves out (the
/// explainer's inclusion rule for failure steps). The scheduler itself includes all.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Scope {
    /// Indices into the activity's `after` to ignore.
    pub skip_deps: Vec<usize>,
    /// Indices into the activity's `requires` to ignore.
    pub skip_reqs: Vec<usize>,
    /// Leave out the checks of the activity's effects at its end: a relaxation,
    /// never recorded, that bounds the duration of an expanding activity with an
    /// end effect (`duration::longest_bound`).
    pub skip_end_effects: bool,
    /// Leave out the check of the data store's capacity (not the handover
    /// data limit): a placement kept from the run before whose data the
    /// caller proved to fit (`resume::Prior::data_proved`).
    pub skip_data_capacity: bool,
}

/// The entries of `items` whose index `skip` does not list.
fn included<'a, T>(items: &'a [T], skip: &'a [usize]) -> impl Iterator<Item = &'a T> + 'a {
    items
        .iter()
        .enumerate()
        .filter(|(k, _)| !skip.contains(k))
        .map(|(_, x)| x)
}

impl Scope {
    /// The dependencies of `act` this scope includes.
    fn deps<'a>(&'a self, act: &'a Act) -> impl Iterator<Item = &'a problem::Dep> + 'a {
        included(&act.after, &self.skip_deps)
    }

    /// The state requirements of `act` this scope includes.
    fn reqs<'a>(&'a self, act: &'a Act) -> impl Iterator<Item = &'a problem::Requirement> + 'a {
        included(&act.requires, &self.skip_reqs)
    }

    /// This scope without the checks of the activity's end effects.
    fn without_end_effects(&self) -> Scope {
        Scope {
            skip_end_effects: true,
            ..self.clone()
        }
    }
}

/// The result of a scheduling run: the compiled problem and the full step trace.
#[derive(Clone, Debug)]
pub struct Schedule {
    /// The compiled plan the run used.
    pub problem: Problem,
    /// One record per step, `steps[k - 1]` for step k.
    pub steps: Vec<Step>,
    /// Every generated activity that ever existed, with its lifetime in steps.
    pub generated: Vec<Generated>,
    /// The energy margin of each step's placement (derived on first use).
    margins: std::sync::OnceLock<Vec<Option<i128>>>,
    /// Whether each step's data-volume category excluded no start of its
    /// window span (derived on first use).
    data_room: std::sync::OnceLock<Vec<bool>>,
}

/// What a step's record leaves out, derived by running the step again on the
/// state before it ([`Schedule::trace`]): the run computes phase 1 only as far
/// as its search needs, and keeps no tries.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct StepTrace {
    /// Valid starts per category for the step's duration, within the span of
    /// the activity's windows (empty for a step that did not search: held,
    /// skipped, or failed on a dependency).
    pub categories: Vec<CategoryIntervals>,
    /// Their intersection, restricted per window.
    pub intersection: IntervalSet,
    /// The phase-2 tries merged into ranges: every start range searched, with
    /// its reason or as passing.
    pub tries: Vec<Try>,
}

impl Schedule {
    /// A schedule of `problem` with these records.
    pub(super) fn from_parts(
        problem: Problem,
        steps: Vec<Step>,
        generated: Vec<Generated>,
    ) -> Self {
        Self {
            problem,
            steps,
            generated,
            margins: std::sync::OnceLock::new(),
            data_room: std::sync::OnceLock::new(),
        }
    }

    /// Where activity `act` was placed, if it was.
    pub fn placement(&self, act: usize) -> Option<(i64, i64)> {
        self.step_of(act)?.outcome.placement()
    }

    /// The step of activity `act` (through the problem's activity -> step index).
    pub fn step_of(&self, act: usize) -> Option<&Step> {
        let k = *self.problem.step_of.get(act)?;
        self.steps.get(k.checked_sub(1)?)
    }

    /// Rebuilds the state of every timeline after step `k` (0 = before step 1) by
    /// replaying the placements of steps `1..=k`.
    pub fn state_after(&self, k: usize) -> State<'_> {
        State::replayed(&self.problem, &self.steps[..k.min(self.steps.len())])
    }

    /// The energy margin (`min(lowest soc - min_soc, handover soc - handover
    /// min)`, mJ) of step `k`'s placement in the state before it, for every step
    /// that placed its activity (`margins()[k - 1]`).
    pub(crate) fn margins(&self) -> &[Option<i128>] {
        self.margins.get_or_init(|| {
            let mut state = State::new(&self.problem);
            self.steps
                .iter()
                .map(|step| {
                    let (s, e) = step.outcome.placement()?;
                    let ev = state.evaluate(step.activity, s, e - s).ok()?;
                    state.apply(step.step, &ev.placement);
                    Some(ev.margin)
                })
                .collect()
        })
    }

    /// What step `k`'s record (1-based) leaves out: its category intervals
    /// and its tries, derived by running step `k` again on the state before
    /// it (what the run did, at the cost of replaying `k - 1` placements and
    /// one search). Empty for `k` out of range.
    pub fn trace(&self, k: usize) -> StepTrace {
        let Some(step) = k.checked_sub(1).and_then(|i| self.steps.get(i)) else {
            return StepTrace::default();
        };
        let state = self.state_after(k - 1);
        again(&state, step, Detail::Trace).trace
    }

    /// The phase-2 tries of step `k` ([`Schedule::trace`]'s).
    pub fn tries(&self, k: usize) -> Vec<Try> {
        self.trace(k).tries
    }

    /// [`Schedule::trace`] of every step (`all_traces()[k - 1]` for step k),
    /// in one replay of the run, the cost of one run with every category
    /// computed over each window span (what a view of a whole run needs, where
    /// [`Schedule::trace`] per step would replay again each time). Only failed
    /// steps get their tries.
    pub fn all_traces(&self) -> Vec<StepTrace> {
        let mut state = State::new(&self.problem);
        self.steps
            .iter()
            .map(|step| {
                let failed = matches!(
                    step.outcome,
                    Outcome::Failed(FailurePhase::Placement | FailurePhase::ValidIntervals)
                );
                let detail = if failed {
                    Detail::Trace
                } else {
                    Detail::Intervals
                };
                let trace = again(&state, step, detail).trace;
                state.replay(step);
                trace
            })
            .collect()
    }

    /// Whether the data-volume category of step `k` (1-based) excluded no
    /// start of its activity's window span, so that a looser data limit cannot
    /// add one (derived for every step on first use, in one replay).
    pub(crate) fn data_room(&self, k: usize) -> bool {
        let room = self.data_room.get_or_init(|| {
            let mut state = State::new(&self.problem);
            self.steps
                .iter()
                .map(|step| {
                    let problem = &self.problem;
                    let act = &problem.acts[step.activity];
                    // Only where a data limit can bind (`Relaxation::keeps`
                    // asks no other), and for steps that searched.
                    let binds = act.data > 0 || (!act.mandatory && problem.handover_data.is_some());
                    let searched = !act.held
                        && matches!(
                            step.outcome,
                            Outcome::Scheduled { .. }
                                | Outcome::Failed(
                                    FailurePhase::Placement | FailurePhase::ValidIntervals
                                )
                        );
                    let (lo, hi) = window_span(problem, step.activity);
                    let room = binds
                        && searched
                        && state
                            .data_category(step.activity, step.duration, lo, hi)
                            .intervals()
                            == [crate::timeline::Interval::new(lo, hi)];
                    state.replay(step);
                    room
                })
                .collect()
        });
        k.checked_sub(1)
            .and_then(|i| room.get(i))
            .is_some_and(|&r| r)
    }

    /// The generated activities alive after step `k`.
    pub fn generated_after(&self, k: usize) -> impl Iterator<Item = &Generated> {
        self.generated.iter().filter(move |g| g.alive_after(k))
    }
}

/// Step `step` run again on `state` (the state before it) to `detail`: what
/// the run did, checked in debug builds.
fn again(state: &State<'_>, step: &Step, detail: Detail) -> StepRun {
    let run = run_step(state, step.activity, step.step, &Scope::default(), detail);
    debug_assert_eq!(
        (&run.step.outcome, run.step.duration),
        (&step.outcome, step.duration),
        "a step run again differs from the run's"
    );
    run
}

/// The category intervals of `step` (within its window span), run again on
/// `state`, the state before it: a record's [`StepTrace`] without tries.
pub(crate) fn step_intervals(state: &State<'_>, step: &Step) -> StepTrace {
    again(state, step, Detail::Intervals).trace
}

/// Schedules a validated plan.
pub fn schedule(plan: &Plan) -> Result<Schedule, Error> {
    Ok(schedule_compiled(Problem::compile(plan)?))
}

/// Schedules a compiled plan.
pub(crate) fn schedule_compiled(problem: Problem) -> Schedule {
    let until = problem.order.len();
    schedule_compiled_until(problem, until)
}

/// The first `until` steps of [`schedule_compiled`]'s run: what its records
/// up to there are (each step reads only the steps before it).
pub(crate) fn schedule_compiled_until(problem: Problem, until: usize) -> Schedule {
    // A cycle of an execution starts in the awake period the rover is in.
    let generated = problem
        .awake0
        .map(|(start, end)| Generated {
            kind: GeneratedKind::Awake,
            start,
            end,
            power_mw: problem.awake - problem.asleep,
            added_at: 0,
            retired_at: None,
        })
        .into_iter()
        .collect();
    run(problem, Vec::new(), generated, until)
}

/// Schedules an edited plan, reusing the steps of `prev` (the run of the plan
/// before the edit) that the edit cannot change: the steps before the first one
/// whose activity moved or changed. The result is identical to [`schedule`]'s.
pub fn reschedule(prev: &Schedule, plan: &Plan) -> Result<Schedule, Error> {
    let problem = Problem::compile(plan)?;
    let until = problem.order.len();
    Ok(rerun(prev, problem, until))
}

/// Runs `problem` (an edit of `prev`'s) up to step `until`, reusing the steps of
/// `prev` the edit cannot change.
fn rerun(prev: &Schedule, problem: Problem, until: usize) -> Schedule {
    let k = prev.problem.common_steps(&problem).min(until);
    let steps = prev.steps[..k].to_vec();
    // Generated activities are recorded in step order, so those of the first k
    // steps are a prefix; undo the retirements that later steps made.
    let generated = prev
        .generated
        .iter()
        .take_while(|g| g.added_at <= k)
        .map(|g| Generated {
            retired_at: g.retired_at.filter(|&r| r <= k),
            ..*g
        })
        .collect();
    run(problem, steps, generated, until)
}

/// Runs the steps after `done` (the records of the first steps, already known)
/// up to step `until`, with `generated` the generated activities of those steps.
/// A run that stops early holds the first `until` steps only.
fn run(problem: Problem, done: Vec<Step>, generated: Vec<Generated>, until: usize) -> Schedule {
    let mut steps = done;
    steps.reserve(problem.acts.len().saturating_sub(steps.len()));
    let mut generated = generated;
    // Index into `generated` of each current awake period (parallel to state.awake,
    // which is sorted by start).
    let mut awake_gen: Vec<usize> = {
        let k = steps.len();
        let mut alive: Vec<usize> = (0..generated.len())
            .filter(|&g| generated[g].kind == GeneratedKind::Awake && generated[g].alive_after(k))
            .collect();
        alive.sort_by_key(|&g| generated[g].start);
        alive
    };
    {
        let mut state = State::replayed(&problem, &steps);
        for (k, &a) in problem
            .order
            .iter()
            .enumerate()
            .take(until)
            .skip(steps.len())
        {
            let step_no = k + 1;
            // The run records outcomes and category intervals; a step's phase-2
            // tries are derived on demand (`Schedule::tries`).
            let StepRun {
                step: mut record,
                found,
                ..
            } = run_step(&state, a, step_no, &Scope::default(), Detail::Outcome);
            if let Some(placement) = found.map(|ev| ev.placement) {
                // Record generated activities.
                let act = &problem.acts[a];
                let (s, e) = (placement.start, placement.start + placement.duration);
                if let Some((qa, qb)) = placement.new_awake {
                    for &i in &placement.retire {
                        let g = awake_gen[i];
                        generated[g].retired_at = Some(step_no);
                        record.retired.push(g);
                    }
                    let mut kept: Vec<usize> = awake_gen
                        .iter()
                        .enumerate()
                        .filter(|(i, _)| !placement.retire.contains(i))
                        .map(|(_, &g)| g)
                        .collect();
                    let at = state
                        .awake
                        .iter()
                        .enumerate()
                        .filter(|(i, p)| !placement.retire.contains(i) && p.0 < qa)
                        .count();
                    kept.insert(at, generated.len());
                    awake_gen = kept;
                    record.added.push(generated.len());
                    generated.push(Generated {
                        kind: GeneratedKind::Awake,
                        start: qa,
                        end: qb,
                        power_mw: problem.awake - problem.asleep,
                        added_at: step_no,
                        retired_at: None,
                    });
                }
                for &z in &act.zones {
                    if let Some(&(_, ps, pe)) = placement.preheats.iter().find(|x| x.0 == z) {
                        record.added.push(generated.len());
                        generated.push(Generated {
                            kind: GeneratedKind::Preheat {
                                zone: z,
                                activity: a,
                            },
                            start: ps,
                            end: pe,
                            power_mw: problem.zones[z].preheat,
                            added_at: step_no,
                            retired_at: None,
                        });
                    }
                    record.added.push(generated.len());
                    generated.push(Generated {
                        kind: GeneratedKind::Maintenance {
                            zone: z,
                            activity: a,
                        },
                        start: s,
                        end: e,
                        power_mw: problem.zones[z].maintenance,
                        added_at: step_no,
                        retired_at: None,
                    });
                }
                state.apply(step_no, &placement);
            }
            steps.push(record);
        }
    }
    Schedule::from_parts(problem, steps, generated)
}

/// How much of a step's record [`run_step`] fills in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Detail {
    /// Where the activity lands, and nothing else: the record's outcome of a
    /// failure may name phase 1 where phase 2 failed (a part of a window that
    /// the state-of-charge bound proves failing is not looked at again to
    /// tell the two apart). Reruns that ask only for placements.
    Placement,
    /// The outcome and duration only: no category intervals and no tries (runs
    /// that only ask where activities land, and why a step failed).
    Outcome,
    /// The outcome, duration and category intervals within the window span,
    /// but no tries, and no record of the rejected starts (`Step::rejected`
    /// stays empty): a cell is searched only for its passing start nearest the
    /// preferred time, as for [`Detail::Placement`] (the explainer's probes and
    /// the traces without tries, which read neither).
    Intervals,
    /// The category intervals within the activity's window span and the
    /// tries ([`Schedule::trace`]).
    Trace,
    /// The trace, with category intervals over the whole horizon (the
    /// explainer's probes).
    Horizon,
}

/// What [`run_step`] gives.
pub(crate) struct StepRun {
    /// The step's record.
    pub step: Step,
    /// What the record leaves out, filled in to the detail asked for. Its
    /// tries are merged into ranges (`merge_tries`): of every duration tried,
    /// except for an expanding activity searched in two parts (the min_awake
    /// extension near the plan end), whose partial searches are not recorded:
    /// only the tries of `step.duration` (the chosen one, or the shortest).
    pub trace: StepTrace,
    /// The evaluation of the placement to apply, if the activity fits.
    pub found: Option<Evaluated>,
}

/// Runs one step against `state`.
pub(crate) fn run_step(
    state: &State<'_>,
    a: usize,
    step_no: usize,
    scope: &Scope,
    detail: Detail,
) -> StepRun {
    run_step_in(state, a, step_no, scope, detail, None)
}

/// Where step `step_no` (activity `a`, in `state`) would place its activity
/// if its starts were only those in `[lo, hi]`: the scheduler's choice among
/// them (the longest duration with such a start, then the first window,
/// the start nearest its preferred time), `None` when none passes.
pub(crate) fn step_within(
    state: &State<'_>,
    a: usize,
    step_no: usize,
    (lo, hi): (i64, i64),
) -> Option<Evaluated> {
    let scope = Scope::default();
    run_step_in(state, a, step_no, &scope, Detail::Placement, Some((lo, hi))).found
}

/// [`run_step`], its starts only those in `within` when given.
fn run_step_in(
    state: &State<'_>,
    a: usize,
    step_no: usize,
    scope: &Scope,
    detail: Detail,
    within: Option<(i64, i64)>,
) -> StepRun {
    let problem = state.problem;
    let act = &problem.acts[a];
    let mut step = Step {
        step: step_no,
        activity: a,
        outcome: Outcome::Failed(FailurePhase::ValidIntervals),
        duration: act.dur_max,
        rejected: Rejected::default(),
        added: Vec::new(),
        retired: Vec::new(),
    };
    if act.held {
        let ev = state.held_placement(a);
        let p = &ev.placement;
        step.outcome = Outcome::Scheduled {
            start: p.start,
            end: p.start + p.duration,
        };
        return StepRun {
            step,
            trace: StepTrace::default(),
            found: Some(ev),
        };
    }
    let no_search = |step: Step| StepRun {
        step,
        trace: StepTrace::default(),
        found: None,
    };
    if let Some(by) = act.group.and_then(|g| state.group_member[g]) {
        step.outcome = Outcome::Skipped { by };
        return no_search(step);
    }
    if let Some(dep) = scope.deps(act).find(|d| state.placed[d.target].is_none()) {
        step.outcome = Outcome::Failed(FailurePhase::Dependency { on: dep.target });
        return no_search(step);
    }
    let mut any_candidate = false;
    // A trace holds category intervals within the window span only, so phase 1
    // need not look further; probes (`Detail::Horizon`) want the whole horizon.
    let span = if detail == Detail::Horizon {
        (problem.h0, problem.h1)
    } else {
        window_span(problem, a)
    };
    let span = match within {
        // Nothing within: no start passes.
        Some((lo, hi)) if span.0.max(lo) > span.1.min(hi) => return no_search(step),
        Some((lo, hi)) => (span.0.max(lo), span.1.min(hi)),
        None => span,
    };
    let mut pending: Vec<(Try, Closeness)> = Vec::new();
    let traced = matches!(detail, Detail::Trace | Detail::Horizon);
    let mut rejected = Rejected::default();
    let mut trace = StepTrace::default();
    let mut attempt = |d: i64, step: &mut Step, record: bool| {
        let part = Part {
            record: traced,
            bare: matches!(detail, Detail::Outcome | Detail::Placement),
            found_only: matches!(detail, Detail::Placement | Detail::Intervals),
            ..Part::default()
        };
        let tried = try_duration(state, a, d, scope, span, part);
        any_candidate |= tried.any;
        pending.extend(tried.tries);
        rejected = rejected.join(tried.rejected);
        if record || tried.found.is_some() {
            step.duration = d;
            trace.categories = tried.categories;
            trace.intersection = tried.union;
        }
        tried.found
    };
    let found = if act.dur_min == act.dur_max {
        attempt(act.dur_max, &mut step, true)
    } else if duration_monotone(problem, a) {
        // Feasibility is downward closed in the duration: binary search the longest.
        let (mut lo, mut hi) = (act.dur_min, act.dur_max);
        let mut best = None;
        while lo <= hi {
            let mid = lo + (hi - lo) / 2;
            match attempt(mid, &mut step, mid == act.dur_min) {
                Some(ev) => {
                    best = Some(ev);
                    lo = mid + 1;
                }
                None => hi = mid - 1,
            }
        }
        // Successes come at increasing durations, so the last one `attempt` recorded
        // is the chosen duration's.
        best
    } else {
        // Feasibility is not monotone in the duration (the min_awake extension near
        // the plan end, an effect at the activity's end, an awake period that
        // charges): find the longest duration with outcome-only searches, then
        // search it (or the shortest, when none fits) again with the record, so
        // that the start and the record are those of the plain search and the
        // trace holds one duration's tries.
        let d = if let Some(head_end) = head_tail_split(problem, a) {
            longest_split(state, a, scope, span, head_end)
        } else {
            longest_scanned(state, a, scope, span)
        };
        #[cfg(debug_assertions)]
        if act.dur_max - act.dur_min <= 400 {
            debug_assert_eq!(
                d,
                longest_by_scan(state, a, scope, span),
                "duration search disagrees with the scan"
            );
        }
        let found = attempt(d.unwrap_or(act.dur_min), &mut step, true);
        debug_assert_eq!(found.is_some(), d.is_some());
        found
    };
    // Cells proven to fail on min_soc carry a bound instead of numbers; the exact
    // numbers are computed only for those that could be reported. Debug builds (the
    // property tests) check the result against computing every cell exactly.
    #[cfg(debug_assertions)]
    let all_exact = merge_tries(
        pending
            .iter()
            .flat_map(|(t, closeness)| match closeness {
                Closeness::Cell(_) => state.cell_tries(a, t.duration, t.starts.lo, t.starts.hi),
                Closeness::Cells(_) => state.span_tries(a, t.duration, t.starts.lo, t.starts.hi),
                Closeness::Exact => vec![t.clone()],
            })
            .collect(),
    );
    let tries = merge_tries_with(
        std::mem::take(&mut pending),
        Numbers {
            exact: |t: &Try| {
                let exact = state.cell_tries(a, t.duration, t.starts.lo, t.starts.hi);
                debug_assert!(exact.len() == 1 && exact[0].reason.is_some());
                exact
                    .into_iter()
                    .find(|x| x.reason.is_some())
                    .unwrap_or_else(|| t.clone())
            },
            refine: |t: &Try| state.generated_cell_bound(a, t.duration, t.starts.lo, t.starts.hi),
            tighter: |t: &Try| {
                state.failing_cell_soc_bound(a, t.duration, t.starts.lo, t.starts.hi)
            },
            split: |t: &Try| state.span_cells(a, t.duration, t.starts.lo, t.starts.hi),
        },
    );
    #[cfg(debug_assertions)]
    debug_assert_eq!(tries, all_exact, "pruned cells changed the reported tries");
    step.outcome = match &found {
        Some(ev) => Outcome::Scheduled {
            start: ev.placement.start,
            end: ev.placement.start + ev.placement.duration,
        },
        None if any_candidate => Outcome::Failed(FailurePhase::Placement),
        None => Outcome::Failed(FailurePhase::ValidIntervals),
    };
    step.rejected = if traced {
        Rejected::of_tries(tries.iter(), problem.handover_gap(a))
    } else {
        rejected
    };
    trace.tries = tries;
    StepRun { step, trace, found }
}

/// What one duration gave.
pub(super) struct Tried {
    categories: Vec<CategoryIntervals>,
    union: IntervalSet,
    /// Whether some start passes phase 1 (`union` is not empty, or would not be
    /// when it is left out).
    any: bool,
    found: Option<Evaluated>,
    tries: Vec<(Try, Closeness)>,
    /// What an outcome-only search rejected (a recorded one: from its tries).
    rejected: Rejected,
}

impl Tried {
    /// An outcome without category intervals or tries.
    fn bare(any: bool, found: Option<Evaluated>, rejected: Rejected) -> Self {
        Self {
            categories: Vec::new(),
            union: IntervalSet::empty(),
            any,
            found,
            tries: Vec::new(),
            rejected,
        }
    }
}

/// How much of one duration's search [`try_duration`] does.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Part {
    /// Only the starts in this range as well as in the span: a partial search,
    /// never recorded (its categories are for the clipped span).
    pub only: Option<(i64, i64)>,
    /// Keep the tries. Without it only the outcome counts, and the search may
    /// skip whole spans that a bound proves to fail (`State::search_outcome`).
    pub record: bool,
    /// Only the outcome: no category intervals, so phase 1 covers each window
    /// ring by ring outward from its preferred time, only as far as the search
    /// needs ([`try_rings`]).
    pub bare: bool,
    /// No record of the rejected starts (`Tried::rejected` comes back empty):
    /// each cell is searched for its passing start nearest the preferred time
    /// only. With `bare`, only `found` counts: [`Tried::any`] may be false
    /// where a part the state-of-charge bound skipped had starts passing
    /// phase 1.
    pub found_only: bool,
}

/// Phase 1 over starts in `span` and the window-by-window phase-2 search for one
/// duration, to the extent `part` says.
pub(super) fn try_duration(
    state: &State<'_>,
    a: usize,
    d: i64,
    scope: &Scope,
    span: (i64, i64),
    part: Part,
) -> Tried {
    let problem = state.problem;
    let act = &problem.acts[a];
    let Part {
        only,
        record,
        bare,
        found_only,
    } = part;
    debug_assert!(!(record && (only.is_some() || scope.skip_end_effects || bare)));
    let span = only.map_or(span, |(lo, hi)| (span.0.max(lo), span.1.min(hi)));
    if span.0 > span.1 {
        return Tried::bare(false, None, Rejected::default());
    }
    if bare {
        let tried = try_rings(state, a, d, scope, span, found_only);
        #[cfg(debug_assertions)]
        {
            let full = Part {
                bare: false,
                found_only: false,
                ..part
            };
            let want = try_duration(state, a, d, scope, span, full);
            debug_assert_eq!(
                (
                    tried.any || (found_only && want.any),
                    tried.found.as_ref().map(|ev| ev.placement.start)
                ),
                (want.any, want.found.as_ref().map(|ev| ev.placement.start)),
                "the search ring by ring differs from the whole span's"
            );
        }
        return tried;
    }
    let categories = state.phase1_in(a, d, scope, span.0, span.1);
    let others = outside_execution(&categories, span);
    // Every window's candidates, made one set once all are walked (a union per
    // window would copy the set so far each time: quadratic in the windows).
    let mut pieces: Vec<Interval> = Vec::new();
    let mut found = None;
    let mut tries = Vec::new();
    let mut rejected = Rejected::default();
    for w in &act.windows {
        let range = state.window_range(a, w, d);
        let cand = others.clip(range.lo.max(span.0), range.hi.min(span.1));
        if cand.is_empty() {
            continue;
        }
        pieces.extend_from_slice(cand.intervals());
        if found.is_none() {
            found = if record {
                let (chosen, t) = state.search(a, d, &cand, w.preferred);
                tries.extend(t);
                chosen
            } else {
                let (chosen, r) = state.search_outcome(a, d, &cand, w.preferred, found_only);
                rejected = rejected.join(r);
                chosen
            };
        }
    }
    let union = IntervalSet::from_intervals(pieces);
    Tried {
        categories,
        any: !union.is_empty(),
        union,
        found,
        tries,
        rejected,
    }
}

/// [`try_duration`] without category intervals: each window's starts in `span`
/// are searched in rings outward from its preferred time, phase 1 computed for
/// one ring at a time, each ring twice as wide as the one before. Every start
/// of a ring is nearer the preferred time than every start beyond it (a tie
/// goes to the earlier start, which is in the ring), so the first ring with a
/// passing start holds the search's choice over the whole window, and phase 1
/// of a windowless activity that fits early never looks at the rest of the
/// horizon. A part of a ring that the state-of-charge bound proves failing
/// (`State::fails_on_energy`) holds no passing start whatever phase 1 says
/// there, so its phase 1 is left out, unless no part has a candidate at all
/// (the step then fails in phase 1, not phase 2) and the caller asks which
/// (not `found_only`).
fn try_rings(
    state: &State<'_>,
    a: usize,
    d: i64,
    scope: &Scope,
    span: (i64, i64),
    found_only: bool,
) -> Tried {
    let act = &state.problem.acts[a];
    let mut any = false;
    let mut rejected = Rejected::default();
    // Parts a bound proved to fail on energy, whose phase 1 was left out:
    // looked at only if no part had a candidate, to tell the two failure
    // phases apart.
    let mut skipped: Vec<(i64, i64)> = Vec::new();
    let mut candidates = |lo: i64, hi: i64, rejected: &mut Rejected| {
        if let Some(bound) = state.fails_on_energy(a, d, lo, hi) {
            rejected.add_skipped(bound, lo);
            skipped.push((lo, hi));
            return IntervalSet::empty();
        }
        state.phase1_others(a, d, scope, lo, hi)
    };
    for w in &act.windows {
        let range = state.window_range(a, w, d);
        let (lo, hi) = (range.lo.max(span.0), range.hi.min(span.1));
        if lo > hi {
            continue;
        }
        let centre = w.preferred.clamp(lo, hi);
        // Explored so far: [from, to] (empty at first).
        let (mut from, mut to) = (centre, centre - 1);
        let mut width = first_ring(d);
        while from > lo || to < hi {
            let (next_from, next_to) = (
                from.saturating_sub(width).max(lo),
                to.saturating_add(width).min(hi),
            );
            let cand = if from > to {
                // The first ring: one span.
                candidates(next_from, next_to, &mut rejected)
            } else {
                let left =
                    (next_from < from).then(|| candidates(next_from, from - 1, &mut rejected));
                let right = (next_to > to).then(|| candidates(to + 1, next_to, &mut rejected));
                match (left, right) {
                    (Some(l), Some(r)) => l.union(&r),
                    (l, r) => l.or(r).unwrap_or_else(IntervalSet::empty),
                }
            };
            (from, to) = (next_from, next_to);
            width = width.saturating_mul(2);
            if cand.is_empty() {
                continue;
            }
            any = true;
            let (chosen, r) = state.search_outcome(a, d, &cand, w.preferred, found_only);
            rejected = rejected.join(r);
            if chosen.is_some() {
                return Tried::bare(any, chosen, rejected);
            }
        }
    }
    if !any && !found_only {
        any = skipped
            .iter()
            .any(|&(lo, hi)| !state.phase1_others(a, d, scope, lo, hi).is_empty());
    }
    Tried::bare(any, None, rejected)
}

/// The width of the first ring [`try_rings`] searches for a duration `d`:
/// wide enough that a short window is one ring, as before.
fn first_ring(d: i64) -> i64 {
    d.saturating_mul(4).max(4 * 3600)
}

/// The starts in `span` that pass every phase-1 category of `categories` (as
/// `State::phase1_in` gives them) but the first, execution, which each window's
/// range stands for.
fn outside_execution(categories: &[CategoryIntervals], span: (i64, i64)) -> IntervalSet {
    categories
        .iter()
        .skip(1)
        .fold(IntervalSet::single(span.0, span.1), |acc, c| {
            acc.intersect(&c.valid)
        })
}

/// The starts at which activity `a` with duration `d` passes every phase-1
/// category inside one of its windows, and the part of those that also passes
/// phase 2, in `state` (the scheduler's own checks at any start, as the free
/// slack of a flexible schedule needs them).
pub(crate) fn accepted_starts(state: &State<'_>, a: usize, d: i64) -> (IntervalSet, IntervalSet) {
    let problem = state.problem;
    let tried = try_duration(
        state,
        a,
        d,
        &Scope::default(),
        (problem.h0, problem.h1),
        Part::default(),
    );
    let both = state.passing(a, d, &tried.union);
    (tried.union, both)
}

/// The span the trace keeps category intervals in: from the earliest window start
/// to the latest window end, which is what the inspector draws. Over a long horizon
/// the full sets of every step would make the trace O(N^2) in memory and time; the
/// explainer computes full sets itself when it probes.
fn window_span(problem: &Problem, a: usize) -> (i64, i64) {
    let act = &problem.acts[a];
    let lo = act
        .windows
        .iter()
        .map(|w| w.start)
        .min()
        .unwrap_or(problem.h0);
    let hi = act
        .windows
        .iter()
        .map(|w| w.end)
        .max()
        .unwrap_or(problem.h1);
    (lo.max(problem.h0), hi.min(problem.h1))
}
