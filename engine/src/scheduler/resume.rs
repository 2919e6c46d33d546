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
//! Past a point the two runs agree outright: from the step after every
//! difference the caller knows of (in the run before's step order), once
//! every step before came out as there, this run's state is the run
//! before's at the same step from the cycle on ([`Prior::same_from`]), so
//! the rest of the run is the run before's, taken without a step run or a
//! timeline touched: its outcomes and final timelines are the run before's.
//!
//! Debug builds check every kept step against the full step.

use super::outcomes::{RunOutcomes, recorded_step, span};
use super::state::{Placement, State, edit_periods};
use super::{Evaluated, Problem, Scope, step_within};
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
    /// By activity: the latest start a heater of an activity that started
    /// between the two runs may have given it (`None`: none). Such a heater
    /// can spare the activity a preheat or share its heating demand, so the
    /// starts from the cycle up to this one may pass now where they did not:
    /// the kept outcome also needs none of them preferred to it
    /// ([`step_within`]); every later start can only have been taken away.
    pub heat_until: Vec<Option<i64>>,
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
    /// The run before's step position from which on this run is the run
    /// before's, once every step before it came out as there (`None`: from
    /// none): from the first such step the two runs have the same state from
    /// the cycle on, so every later step comes out as there without a check
    /// (see `execute::resume`).
    pub same_from: Option<usize>,
    /// The run before's final state of charge and data timeline (what debug
    /// builds check this run's against when its last steps were the run
    /// before's).
    pub soc_before: &'a RateTimeline,
    pub data_before: &'a RateTimeline,
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
            if let Some(p) = &self.placed[self.order[self.done]] {
                edit_periods(&mut self.periods, p);
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
    /// The state of charge and the data timeline (`-D`) after the run, from
    /// the cycle on (when its last steps were the run before's,
    /// [`Prior::same_from`], the run before's final ones: the same there).
    pub soc: RateTimeline,
    pub data: RateTimeline,
    /// Whether the total peak power went over the limit anywhere.
    pub peak_over: bool,
    /// Steps that kept the run before's outcome without a search.
    pub kept: usize,
    /// Kept placements that store data whose check of the store's capacity
    /// the run before proved.
    pub capacity_proved: usize,
    /// Of the kept steps, those that were the run before's last steps
    /// ([`Prior::same_from`]).
    pub kept_rest: usize,
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
    // The step from which on the run is the run before's, if it comes (tried
    // at the first step the run before's position allows, and only there).
    let mut rest_from = None;
    let mut rest_tried = false;
    for (k, &a) in problem.order.iter().enumerate() {
        let step_no = k + 1;
        let prior = prior.filter(|_| same && !problem.acts[a].held);
        if let (Some(p), Some(b)) = (prior.filter(|_| !rest_tried), awake_before.as_mut()) {
            rest_tried = p
                .same_from
                .is_some_and(|f| p.pos[a] >= f && p.pos[a] != usize::MAX);
            if rest_tried
                && rest_as_before(problem, p, k)
                && same_periods(&state.awake, b.before_step(p.pos[a]), awake_cut)
            {
                rest_from = Some(k);
                break;
            }
        }
        let before = prior.map(|p| p.before[a]);
        let keep = prior.is_some_and(|p| {
            p.may_keep[a]
                && (awake_clear(&state, a, p.awake_reach)
                    || p.no_sleep_near
                        && awake_before.as_mut().is_some_and(|b| {
                            same_periods(&state.awake, b.before_step(p.pos[a]), awake_cut)
                        }))
        });
        // Where heaters of activities that started in between reach, the
        // starts the step would choose among them (see `Prior::heat_until`).
        let heat = prior.and_then(|p| p.heat_until[a]);
        let within = |hi: i64| step_within(&state, a, step_no, (problem.h0, hi));
        let ev = match before.filter(|_| keep) {
            Some(Before::Failed) if heat.is_none_or(|hi| within(hi).is_none()) => {
                debug_assert!(
                    recorded_step(&state, a, step_no, false, false).0.is_none(),
                    "a failure kept from the cycle before places its activity now"
                );
                kept += 1;
                continue;
            }
            Some(Before::Placed(old)) => {
                // Against `min_soc` unless proved; against the handover
                // minimum apart, where it binds and is not proved.
                let soc = prior.is_none_or(|p| !p.energy_proved);
                let handover = !soc && prior.is_some_and(|p| !p.handover_proved[a]);
                let scope = Scope {
                    skip_data_capacity: prior.is_some_and(|p| p.data_proved[a]),
                    ..Scope::default()
                };
                if scope.skip_data_capacity && problem.acts[a].data > 0 {
                    capacity_proved += 1;
                }
                state
                    .fitting_inner(a, old.start, old.duration, &scope, soc)
                    .filter(|ev| equivalent(&state, &ev.placement, old))
                    .filter(|ev| !handover || state.keeps_handover(a, &ev.placement))
                    .filter(|ev| {
                        heat.is_none_or(|hi| {
                            within(hi).is_none_or(|x| !prefers(&state, &x.placement, &ev.placement))
                        })
                    })
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
                        (Before::Placed(old), Some(ev)) => equivalent(&state, &ev.placement, old),
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
    let over = |state: &State<'_>| {
        matches!(
            (problem.max_peak, state.peak_max),
            (Some(max), Some((v, _))) if v > max
        )
    };
    let mut kept_rest = 0;
    let (soc, data, peak_over) = match (rest_from, prior, awake_before.as_mut()) {
        (Some(k), Some(p), Some(b)) => {
            kept_rest = problem.order.len() - k;
            kept += kept_rest;
            rest_of_run(problem, p, b, k, &mut state, &mut placed, &mut preheats);
            for &a in &problem.order[k..] {
                placements[a] = placed[a].as_ref().map(span);
            }
            debug_assert!(
                agree_from(&state.soc, p.soc_before, problem.h0)
                    && agree_from(&state.data, p.data_before, problem.h0)
                    && !over(&state),
                "the run before's timelines or peak are not this run's from the cycle on"
            );
            // From the cycle on, the run before's timelines are this run's,
            // and so is its peak, which kept the limit (a run resumes from
            // no run whose peak broke it).
            (p.soc_before.clone(), p.data_before.clone(), false)
        }
        _ => (state.soc.clone(), state.data.clone(), over(&state)),
    };
    Resumed {
        outcomes: RunOutcomes {
            placements,
            awake: state.awake.clone(),
            preheats,
            step_of: problem.step_of.clone(),
        },
        placed,
        soc,
        data,
        peak_over,
        kept,
        capacity_proved,
        kept_rest,
    }
}

/// Whether the steps of `problem` from its `k`-th (0-based) on are the run
/// before's steps from the same activity's on, in the same order: none held,
/// each known to the run before at a later position than the step before
/// it, and as many placed there as the run before placed from there on
/// (so this run leaves out only activities the run before did not place).
fn rest_as_before(problem: &Problem, p: &Prior<'_>, k: usize) -> bool {
    let rest = &problem.order[k..];
    let mut last = None;
    let mut placed = 0;
    for &a in rest {
        let pos = p.pos[a];
        if problem.acts[a].held || pos == usize::MAX || last.is_some_and(|l| l >= pos) {
            return false;
        }
        last = Some(pos);
        placed += usize::from(matches!(p.before[a], Before::Placed(_)));
    }
    let from = rest.first().map_or(usize::MAX, |&a| p.pos[a]);
    let placed_before = p
        .order_before
        .iter()
        .skip(from)
        .filter(|&&x| p.placed_before[x].is_some())
        .count();
    placed == placed_before
}

/// Takes the run before's outcomes for the steps of `problem` from its `k`-th
/// (0-based) on ([`rest_as_before`]) into `placed` and `preheats`, and applies
/// what the next cycle reads of them to `state`: the awake periods (the
/// timelines are the run before's; debug builds run each step in full and
/// apply it all). The two runs' awake periods agree from where a start can
/// reach on ([`same_periods`]) and those steps change no period before it,
/// so a placement's retired periods are the same periods here, shifted by
/// the difference in the two lists' lengths.
fn rest_of_run<'a>(
    problem: &Problem,
    p: &Prior<'a>,
    before: &mut AwakeBefore<'a>,
    k: usize,
    state: &mut State<'_>,
    placed: &mut [Option<Placement>],
    preheats: &mut Vec<(usize, i64, i64, usize)>,
) {
    let Some(&first) = problem.order.get(k) else {
        return;
    };
    let len = |v: &[(i64, i64)]| isize::try_from(v.len()).unwrap_or(isize::MAX);
    let shift = len(&state.awake) - len(before.before_step(p.pos[first]));
    for (k, &a) in problem.order.iter().enumerate().skip(k) {
        let placement = match p.before[a] {
            Before::Placed(old) => Some(Placement {
                act: a,
                retire: old
                    .retire
                    .iter()
                    .map(|&i| i.checked_add_signed(shift).unwrap_or(usize::MAX))
                    .collect(),
                ..old.clone()
            }),
            _ => None,
        };
        if cfg!(debug_assertions) {
            let full = recorded_step(state, a, k + 1, false, true).0;
            let full = full.map(|ev| ev.placement);
            assert_eq!(
                full, placement,
                "a step of the run before's last steps comes out otherwise"
            );
            if let Some(full) = &full {
                state.apply(k + 1, full);
            }
        } else if let Some(placement) = &placement {
            state.edit_awake(placement);
        }
        if let Some(placement) = placement {
            preheats.extend(placement.preheats.iter().map(|&(z, s, e)| (z, s, e, a)));
            placed[a] = Some(placement);
        }
    }
}

/// Whether two timelines have the same levels from `t` on (debug checks).
fn agree_from(x: &RateTimeline, y: &RateTimeline, t: i64) -> bool {
    let (px, py) = (x.profile(), y.profile());
    px.iter()
        .chain(&py)
        .map(|&(u, _)| u)
        .filter(|&u| u >= t)
        .chain([t])
        .all(|u| x.level_at(u) == y.level_at(u))
        && x.lowest_from(t) == y.lowest_from(t)
}
/// Whether placement `new` of this run, made in `state`, generates what
/// `old` (the same activity's in the run before) did: the same span; the
/// same awake period, or none where one period of `state` already holds the
/// one `old` generated (the period the rover is in at the cycle, or one an
/// activity held first generated: awake over at least the same time, which
/// later steps judge as any other difference in the periods); and the same
/// preheats but those already running at the cycle (for which `new` needs
/// none: the heater the cycle found on is the same demand).
fn equivalent(state: &State<'_>, new: &Placement, old: &Placement) -> bool {
    let problem = state.problem;
    let awake_held = |(qa, qb): (i64, i64)| state.awake.iter().any(|&(a, b)| a <= qa && qb <= b);
    new.start == old.start
        && new.duration == old.duration
        && (new.new_awake == old.new_awake
            || new.new_awake.is_none() && old.new_awake.is_some_and(awake_held))
        && old
            .preheats
            .iter()
            .filter(|&&(z, _, end)| !problem.preheat_running(new.act, z, end))
            .eq(new.preheats.iter())
}

/// Whether the scheduler, choosing among starts where both pass in
/// `state`, chooses placement `x` over `y` of the same activity: the
/// longer duration; at the same duration, the start in the earlier window
/// (the first whose range for the duration holds it), nearer that window's
/// preferred time, or as near and earlier. A start in no window's range
/// cannot be ranked, and is taken as chosen.
fn prefers(state: &State<'_>, x: &Placement, y: &Placement) -> bool {
    if x.duration != y.duration {
        return x.duration > y.duration;
    }
    let (a, d) = (x.act, x.duration);
    let rank = |s: i64| {
        state.problem.acts[a]
            .windows
            .iter()
            .enumerate()
            .find(|(_, w)| state.window_range(a, w, d).contains(s))
            .map(|(k, w)| (k, (s - w.preferred).abs(), s))
    };
    match (rank(x.start), rank(y.start)) {
        (Some(rx), Some(ry)) => rx < ry,
        _ => true,
    }
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
