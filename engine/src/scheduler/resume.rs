//! A run that resumes the run before it: an execution's cycle keeps the
//! outcome the previous cycle gave an activity wherever it can prove that
//! the activity's step comes out the same, instead of searching it again.
//!
//! The proof is a monotonicity argument, made per step. While every earlier
//! step of this run came out as in the run before (the same placement,
//! generating an equivalent awake period and preheats), this run's state
//! before a step is the earlier run's state before the same activity plus
//! differences the caller vouches can only take starts away from it (more
//! load, more busy time, more data: [`Prior::may_keep`]), within the span of
//! starts this run can still choose. Then the activity's feasible starts are
//! a subset of those it had, so a failure fails again, and the earlier
//! choice, if it still fits, is still the best. The awake periods are the
//! one difference the caller cannot judge alone: more of them is more load,
//! but an awake period the rover is in at the cycle can spare an activity
//! that needs the rover awake its wakeup, a merge or a `min_awake`
//! extension. Such an activity is kept only when the two runs' periods
//! within its reach are the same (the run before's are replayed alongside,
//! [`same_periods`]), or when every start it could take stays clear of the
//! periods near the cycle ([`awake_clear`]).
//!
//! Debug builds check every kept step against the full step.

use super::outcomes::{RunOutcomes, recorded_step, span};
use super::state::{Placement, State};
use super::{Evaluated, Problem, Scope};
use crate::model::AwakeMode;
use crate::timeline::RateTimeline;

/// The outcome the run before gave an activity of this run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Before<'a> {
    /// It had no step there that can stand for this one.
    Unknown,
    /// It failed (or was skipped).
    Failed,
    /// It was placed so.
    Placed(&'a Placement),
}

/// What a run may keep of the run before it.
#[derive(Clone, Debug)]
pub(crate) struct Prior<'a> {
    /// By activity of this run's problem.
    pub before: Vec<Before<'a>>,
    /// By activity: whether every difference between this run's starting
    /// state and the run before's state at that activity's step, apart from
    /// the awake periods, can only take starts away from it.
    pub may_keep: Vec<bool>,
    /// By activity: its step index in the run before (`usize::MAX`: none).
    pub pos: Vec<usize>,
    /// Whether a kept placement's energy needs no check against `min_soc`:
    /// this run's loads up to and with it are among the run before's final
    /// loads, from the same state of charge at the cycle, and that run's
    /// final levels keep the minimum from the cycle on.
    pub energy_proved: bool,
    /// By activity: whether, besides, a kept placement's level at the
    /// handover needs no check against the handover minimum, the limit only
    /// optional activities are held to: the run before's final level there
    /// keeps it (mandatory activities may take it under), or this run's loads
    /// from the cycle on are the run before's at the same step (see
    /// `execute::resume`).
    pub handover_proved: Vec<bool>,
    /// By activity: whether a kept placement needs no check of the data
    /// store's capacity: this run stores no more data than a run it fitted
    /// in, at every time from the cycle on (see `execute::resume`).
    pub data_proved: Vec<bool>,
    /// The latest time up to which the awake periods of the two runs may
    /// differ (the cycle, or the end of the awake period the rover is in).
    pub awake_reach: i64,
    /// Whether no activity that keeps the rover asleep ran within reach of
    /// the cycle (`min_sleep` before the awake period the rover is in, or
    /// before the cycle): the run before knew such a sleep, this run does
    /// not, so equal awake periods alone do not make the runs agree.
    pub no_sleep_near: bool,
    /// The run before's awake periods at its start, its placements (by its
    /// activity) and its step order: its periods before any of its steps
    /// are replayed from these.
    pub awake_start: &'a [(i64, i64)],
    pub placed_before: &'a [Option<Placement>],
    pub order_before: &'a [usize],
}

/// The run before's awake periods, replayed step by step alongside this run.
struct AwakeBefore<'a> {
    placed: &'a [Option<Placement>],
    order: &'a [usize],
    done: usize,
    periods: Vec<(i64, i64)>,
}

impl AwakeBefore<'_> {
    /// The run before's periods before its step `k` (0-based; `k` never
    /// decreases from one call to the next).
    fn before_step(&mut self, k: usize) -> &[(i64, i64)] {
        while self.done < k.min(self.order.len()) {
            let placed = self.placed[self.order[self.done]].as_ref();
            if let Some((retire, (qa, qb))) = placed.and_then(|p| Some((&p.retire, p.new_awake?))) {
                let mut i = 0;
                self.periods.retain(|_| {
                    i += 1;
                    !retire.contains(&(i - 1))
                });
                let at = self.periods.partition_point(|x| x.0 < qa);
                self.periods.insert(at, (qa, qb));
            }
            self.done += 1;
        }
        &self.periods
    }
}

/// A run's outcomes, and what a run resuming from it needs.
#[derive(Clone, Debug)]
pub(crate) struct Resumed {
    /// The run's outcomes.
    pub outcomes: RunOutcomes,
    /// The placement of each activity, with what it generated.
    pub placed: Vec<Option<Placement>>,
    /// The state of charge after the run.
    pub soc: RateTimeline,
    /// The data timeline (`-D`) after the run.
    pub data: RateTimeline,
    /// The highest total peak power after the run, and its first time.
    pub peak_max: Option<(i64, i64)>,
    /// Steps that kept the run before's outcome without a search.
    pub kept: usize,
    /// Kept placements that store data whose check of the store's capacity
    /// the run before proved.
    pub capacity_proved: usize,
}

/// Runs `problem` for its outcomes, keeping what `prior` allows: the same
/// outcomes as [`super::run_outcomes`] (debug builds check each kept step).
pub(crate) fn run_resuming(problem: &Problem, prior: Option<&Prior>) -> Resumed {
    let n = problem.acts.len();
    let mut state = State::new(problem);
    let mut placements = vec![None; n];
    let mut placed: Vec<Option<Placement>> = vec![None; n];
    let mut preheats = Vec::new();
    // Whether every step so far came out as in the run before.
    let mut same = prior.is_some();
    let mut kept = 0;
    let mut capacity_proved = 0;
    let mut awake_before = prior.map(|p| AwakeBefore {
        placed: p.placed_before,
        order: p.order_before,
        done: 0,
        periods: p.awake_start.to_vec(),
    });
    // Periods ending before this are out of every start's reach (periods
    // are `min_sleep` apart, and no start needs the rover awake before the
    // awake period it is in at the cycle, or before the cycle).
    let awake_cut = problem
        .awake0
        .map_or(problem.h0, |(w, _)| w.min(problem.h0))
        .saturating_sub(problem.min_sleep.max(1));
    for (k, &a) in problem.order.iter().enumerate() {
        let step_no = k + 1;
        let prior = prior.filter(|_| same && !problem.acts[a].held);
        let before = prior.map(|p| p.before[a]);
        let keep = prior.is_some_and(|p| {
            p.may_keep[a]
                && (awake_clear(&state, a, p.awake_reach)
                    || p.no_sleep_near
                        && awake_before.as_mut().is_some_and(|b| {
                            same_periods(&state.awake, b.before_step(p.pos[a]), awake_cut)
                        }))
        });
        let ev = match before.filter(|_| keep) {
            Some(Before::Failed) => {
                debug_assert!(
                    recorded_step(&state, a, step_no, false, false).0.is_none(),
                    "a failure kept from the cycle before places its activity now"
                );
                kept += 1;
                continue;
            }
            Some(Before::Placed(old)) => {
                let soc = prior.is_none_or(|p| {
                    !p.energy_proved
                        || !p.handover_proved[a] && problem.handover_soc_of(a).is_some()
                });
                let scope = Scope {
                    skip_data_capacity: prior.is_some_and(|p| p.data_proved[a]),
                    ..Scope::default()
                };
                if scope.skip_data_capacity && problem.acts[a].data > 0 {
                    capacity_proved += 1;
                }
                state
                    .fitting_inner(a, old.start, old.duration, &scope, soc)
                    .filter(|ev| equivalent(problem, &ev.placement, old))
            }
            _ => None,
        };
        let ev = match ev {
            Some(ev) => {
                debug_assert_eq!(
                    recorded_step(&state, a, step_no, false, true)
                        .0
                        .map(|e| span(&e.placement)),
                    Some(span(&ev.placement)),
                    "a placement kept from the cycle before is not the step's"
                );
                kept += 1;
                Some(ev)
            }
            None => {
                // A step that failed before rarely gets its ideal placement.
                let hint = !matches!(before, Some(Before::Failed));
                let ev = recorded_step(&state, a, step_no, false, hint).0;
                if let Some(before) = before {
                    same = match (before, &ev) {
                        (Before::Failed, None) => true,
                        (Before::Placed(old), Some(ev)) => equivalent(problem, &ev.placement, old),
                        _ => false,
                    };
                }
                ev
            }
        };
        if let Some(Evaluated { placement, .. }) = ev {
            placements[a] = Some(span(&placement));
            preheats.extend(placement.preheats.iter().map(|&(z, s, e)| (z, s, e, a)));
            state.apply(step_no, &placement);
            placed[a] = Some(placement);
        }
    }
    Resumed {
        outcomes: RunOutcomes {
            placements,
            awake: state.awake.clone(),
            preheats,
            step_of: problem.step_of.clone(),
        },
        placed,
        soc: state.soc.clone(),
        data: state.data.clone(),
        peak_max: state.peak_max,
        kept,
        capacity_proved,
    }
}

/// Whether placement `new` of this run generates what `old` (the same
/// activity's in the run before) did: the same span and awake period, and the
/// same preheats but those already running at the cycle (for which `new`
/// needs none: the heater the cycle found on is the same demand).
fn equivalent(problem: &Problem, new: &Placement, old: &Placement) -> bool {
    new.start == old.start
        && new.duration == old.duration
        && new.new_awake == old.new_awake
        && old
            .preheats
            .iter()
            .filter(|&&(z, _, end)| !problem.preheat_running(new.act, z, end))
            .eq(new.preheats.iter())
}

/// Whether two lists of awake periods (sorted, disjoint) hold the same
/// periods ending at or after `cut`.
fn same_periods(x: &[(i64, i64)], y: &[(i64, i64)], cut: i64) -> bool {
    let from = |v: &[(i64, i64)]| v.partition_point(|p| p.1 < cut);
    x[from(x)..] == y[from(y)..]
}

/// Whether activity `a`, if it needs the rover awake, can take no start whose
/// wakeup, merge or `min_awake` extension reaches the awake periods up to
/// `reach` (where this run's periods may differ from the run before's): its
/// leftmost possible awake need, merged with the periods in `state` as the
/// scheduler merges it, stays more than `min_sleep` after `reach`. Right of
/// that point the two runs have the same periods.
fn awake_clear(state: &State<'_>, a: usize, reach: i64) -> bool {
    let problem = state.problem;
    let act = &problem.acts[a];
    if act.awake != AwakeMode::Required {
        return true;
    }
    let Some(lo) = act
        .windows
        .iter()
        .map(|w| state.window_range(a, w, act.dur_max).lo)
        .min()
    else {
        return true;
    };
    let gap = problem.min_sleep.max(1);
    let first = lo
        .saturating_sub(problem.wake)
        .min(lo.saturating_add(act.dur_min + problem.shut - problem.min_awake));
    let reach = reach.saturating_add(gap);
    first > reach && state.merge((first, first.saturating_add(1))).0.0 > reach
}
