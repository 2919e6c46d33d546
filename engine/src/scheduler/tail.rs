//! The outcome of every step after an edit that places one more activity, without
//! searching the steps the new placement provably cannot change.
//!
//! Suggestion verification asks, for an edit that makes activity `a` schedule,
//! which activities scheduled before no longer do. The steps after `a`'s see one
//! difference from the original run: `a`'s placement (and what it generates). When
//! that difference can only take starts away from a later activity `j` (it adds
//! load, busy time, data, sleep or awake time that `j` cannot use), `j`'s feasible
//! (start, duration) set can only shrink. The greedy step picks the best member of
//! that set by a fixed order (window, then duration, then distance to the preferred
//! start), so if `j`'s original placement still fits it is still the choice, and
//! if `j` failed it still fails: a one-point check replaces the search. Everywhere
//! else, and from the first step whose outcome changes, steps are run in full.
//! Debug builds compare every outcome with a run from scratch.

use super::state::{Placement, State};
use super::{Evaluated, Schedule, Scope, partial_rerun, run_step};
use crate::error::Error;
use crate::model::{AwakeMode, Plan};

/// Where each activity (by index) is placed in the run of the edited `plan`, when
/// activity `a` is placed in it; `None` when `a` is not (only the steps up to
/// `a`'s are then run). `prev` is the run of the plan before the edit.
pub(crate) fn placements_if_placed(
    prev: &Schedule,
    plan: &Plan,
    a: usize,
) -> Result<Option<Vec<Option<(i64, i64)>>>, Error> {
    let partial = partial_rerun(prev, plan, a)?;
    if partial.placement(a).is_none() {
        return Ok(None);
    }
    let problem = &partial.problem;
    let mut placements: Vec<Option<(i64, i64)>> = vec![None; problem.acts.len()];
    let mut state = State::new(problem);
    let mut placed_a = None;
    for step in &partial.steps {
        placements[step.activity] = step.outcome.placement();
        let ev = state.replay(step);
        if step.activity == a {
            placed_a = ev;
        }
    }
    let done = partial.steps.len();
    // The original run's state, stepped alongside while only `a`'s placement
    // differs (the same step order and every other activity unchanged).
    let drain = placed_a.as_ref().map_or(0, |ev| ev.energy);
    let mut old = placed_a
        .filter(|ev| problem.differs_only_in(&prev.problem, a) && restrictive(problem, ev))
        .map(|ev| {
            let mut old = State::new(&prev.problem);
            for step in &prev.steps[..done] {
                old.replay(step);
            }
            (old, ev.placement)
        });
    for (k, &j) in problem.order.iter().enumerate().skip(done) {
        let step_no = k + 1;
        if let Some((old_state, pa)) = old.as_mut() {
            let before = &prev.steps[k];
            if !interacts(problem, pa, j) {
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
        let (step, ev) = run_step(&state, j, step_no, &Scope::default(), true);
        let placement = step.outcome.placement();
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
