//! Outcome-only runs: where activities are placed in the run of an edited plan,
//! without the step trace and without searching the steps whose outcome is known
//! from a one-point check. Suggestion verification asks only that.
//!
//! Two shortcuts, each exact:
//!
//! - The ideal placement. The greedy step picks, among the feasible (start,
//!   duration) pairs, the longest duration, then the first window, then the start
//!   nearest the window's preferred time. If the longest duration at the preferred
//!   time (clamped into the first window that admits it) fits, nothing can beat it:
//!   it is the outcome, whatever the rest of the state.
//! - Steps after a new placement. For an edit that makes activity `a` schedule,
//!   the steps after `a`'s see one difference from the original run: `a`'s
//!   placement (and what it generates). When that difference can only take starts
//!   away from a later activity `j` (it adds load, busy time, data, sleep or awake
//!   time that `j` cannot use), `j`'s feasible set can only shrink, so if `j`'s
//!   original placement still fits it is still the choice, and if `j` failed it
//!   still fails. From the first step whose outcome changes, steps are searched.
//!
//! Debug builds compare every outcome with the full scheduler's.

use super::state::{Placement, State};
use super::{Detail, Evaluated, Schedule, Scope, run_step};
use crate::error::Error;
use crate::model::{AwakeMode, Plan};

/// Placements by activity index (`None`: not placed, or its step not run).
pub(crate) type Placements = Vec<Option<(i64, i64)>>;

/// Where activity `a` is placed when the edited `plan` is scheduled (`None`: it
/// fails), running only the steps up to `a`'s and reusing the steps of `prev`
/// (the run before the edit) that the edit cannot change.
pub(crate) fn placement_after_edit(
    prev: &Schedule,
    plan: &Plan,
    a: usize,
) -> Result<Option<(i64, i64)>, Error> {
    let problem = super::Problem::compile(plan)?;
    let run = Run::up_to(prev, &problem, a);
    let placed = run.placements[a];
    #[cfg(debug_assertions)]
    if let Ok(full) = super::schedule(plan) {
        debug_assert_eq!(placed, full.placement(a), "the outcome-only run disagrees");
    }
    Ok(placed)
}

/// Where each activity is placed in the run of the edited `plan`, when activity
/// `a` is placed in it; `None` when `a` is not (only the steps up to `a`'s are
/// then run). `prev` is the run of the plan before the edit.
pub(crate) fn placements_if_placed(
    prev: &Schedule,
    plan: &Plan,
    a: usize,
) -> Result<Option<Placements>, Error> {
    let problem = super::Problem::compile(plan)?;
    let Run {
        mut state,
        mut placements,
        placed_a,
        done,
    } = Run::up_to(prev, &problem, a);
    let Some(placed_a) = placed_a else {
        return Ok(None);
    };
    // The original run's state, stepped alongside while only `a`'s placement
    // differs (the same step order and every other activity unchanged).
    let drain = placed_a.energy;
    let mut old = (problem.differs_only_in(&prev.problem, a) && restrictive(&problem, &placed_a))
        .then(|| {
            let mut old = State::new(&prev.problem);
            for step in &prev.steps[..done] {
                old.replay(step);
            }
            (old, placed_a.placement)
        });
    for (k, &j) in problem.order.iter().enumerate().skip(done) {
        let step_no = k + 1;
        if let Some((old_state, pa)) = old.as_mut() {
            let before = &prev.steps[k];
            if !interacts(&problem, pa, j) {
                let old_ev = old_state.replay(before);
                match (before.outcome.placement(), old_ev) {
                    (None, _) => continue,
                    (Some((s, e)), Some(old_ev)) => {
                        // The state of charge is lower than in the original run
                        // by at most the charge `a`'s placement drains (a capped
                        // integrator falls by at most the extra drain), so a
                        // margin at least that large needs no energy check.
                        let soc = prev.margins()[k].is_none_or(|m| m < drain);
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
        let ev = outcome_step(&state, j, step_no);
        let placement = ev.as_ref().map(|ev| span(&ev.placement));
        if let Some((old_state, _)) = old.as_mut() {
            let before = &prev.steps[k];
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
    if let Ok(full) = super::schedule(plan) {
        let want: Vec<Option<(i64, i64)>> =
            (0..problem.acts.len()).map(|x| full.placement(x)).collect();
        debug_assert_eq!(
            placements, want,
            "the shortcut rerun disagrees with a full run"
        );
    }
    Ok(Some(placements))
}

/// The state and placements of an outcome-only run up to activity `a`'s step.
struct Run<'p> {
    state: State<'p>,
    placements: Placements,
    /// `a`'s evaluation, when it is placed.
    placed_a: Option<Evaluated>,
    /// Steps run (`a`'s is the last).
    done: usize,
}

impl<'p> Run<'p> {
    /// Runs `problem` (an edit of `prev`'s) up to `a`'s step, replaying the
    /// steps of `prev` the edit cannot change.
    fn up_to(prev: &Schedule, problem: &'p super::Problem, a: usize) -> Self {
        let until = problem.step_of.get(a).copied().unwrap_or(0);
        let common = prev.problem.common_steps(problem).min(until);
        let mut state = State::new(problem);
        let mut placements = vec![None; problem.acts.len()];
        let mut placed_a = None;
        for step in &prev.steps[..common] {
            placements[step.activity] = step.outcome.placement();
            let ev = state.replay(step);
            if step.activity == a {
                placed_a = ev;
            }
        }
        for (k, &j) in problem.order.iter().enumerate().take(until).skip(common) {
            if let Some(ev) = outcome_step(&state, j, k + 1) {
                placements[j] = Some(span(&ev.placement));
                state.apply(k + 1, &ev.placement);
                if j == a {
                    placed_a = Some(ev);
                }
            }
        }
        Self {
            state,
            placements,
            placed_a,
            done: until,
        }
    }
}

/// The placement step `step_no` (activity `a`) makes in `state`: the ideal one
/// when it fits, else the full search's.
fn outcome_step(state: &State<'_>, a: usize, step_no: usize) -> Option<Evaluated> {
    if let Some(ev) = ideal(state, a) {
        debug_assert_eq!(
            run_step(state, a, step_no, &Scope::default(), Detail::Outcome)
                .0
                .outcome
                .placement(),
            Some(span(&ev.placement)),
            "the ideal placement is not the step's"
        );
        return Some(ev);
    }
    run_step(state, a, step_no, &Scope::default(), Detail::Outcome).1
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
fn span(p: &Placement) -> (i64, i64) {
    (p.start, p.start + p.duration)
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
/// `j` depends on `a` or shares its group; `a` changes a state `j` requires or
/// changes; `a` downlinks data `j` would produce; `a` created or extended an
/// awake period `j` could share; or they share a heating zone (`j` could find
/// its zone already heated).
fn interacts(problem: &super::Problem, pa: &Placement, j: usize) -> bool {
    let (a, x) = (&problem.acts[pa.act], &problem.acts[j]);
    x.after.iter().any(|d| d.target == pa.act)
        || (a.group.is_some() && a.group == x.group)
        || a.effects.iter().any(|e| {
            x.requires.iter().any(|r| r.state == e.state)
                || x.effects.iter().any(|f| f.state == e.state)
        })
        || (a.data < 0 && x.data > 0)
        || (pa.new_awake.is_some() && x.awake == AwakeMode::Required)
        || a.zones.iter().any(|z| x.zones.contains(z))
}

/// Whether two placements of one activity generate the same awake period and
/// preheats.
fn same_generated(x: &Placement, y: &Placement) -> bool {
    x.start == y.start
        && x.duration == y.duration
        && x.new_awake == y.new_awake
        && x.preheats == y.preheats
}
