//! Free slack: the starts at which the scheduler's own checks accept an activity
//! with every other placement fixed.
//!
//! The state is the schedule's without the activity: the steps before its step as
//! recorded, the steps after it checked again at their placements and applied
//! (each re-deriving its wake/sleep and heating without the activity; when one no
//! longer passes, only the scheduled start is free). In that state the activity is checked at every
//! start as a step placed after all of them (every window, phase 1, then phase 2
//! with the wake/sleep and heating the move needs; its effects win same-time
//! ties; handover limits, which the format applies only when an optional activity
//! is placed, waived) and as its own step checked it against the steps before it, every placed requirement must still see its value (its effects may be
//! what one relied on), and the dependencies of the placed activities that depend
//! on it bound its end.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::model::EffectAt;
use crate::scheduler::{Schedule, Scope, accepted_starts};
use crate::timeline::IntervalSet;

/// How many later steps are replayed between two looks at the cancel flag.
const CANCEL_EVERY: usize = 32;

/// The free slack of activity `a` (placed at `(s, e)`): the starts passing phase 1
/// and the dependents' dependencies, and the part of those that also passes phase 2.
/// `None` when `cancel` was set while it ran (looked at every few replayed
/// steps, so a cancel stops it within moments even on a long schedule).
pub(crate) fn free_slack(
    sched: &Schedule,
    a: usize,
    (s, e): (i64, i64),
    cancel: Option<&AtomicBool>,
) -> Option<(IntervalSet, IntervalSet)> {
    let cancelled = || cancel.is_some_and(|c| c.load(Ordering::Relaxed));
    let d = e - s;
    let k = sched.problem.step_of[a];
    // Its own step's check, against the steps before it: what the scheduler
    // accepted when it placed it (handover limits of an optional activity apply
    // only then).
    let own = sched.state_after(k - 1);
    let (own_p1, own_both) = accepted_starts(&own, a, d);
    // Against every other placement, handover limits waived (as for a mandatory
    // activity): they applied at its step.
    let mut waived = sched.problem.clone();
    std::sync::Arc::make_mut(&mut waived.acts[a]).mandatory = true;
    let problem = &waived;
    let mut state = crate::scheduler::State::replayed(problem, &sched.steps[..k - 1]);
    for (i, step) in sched.steps[k..].iter().enumerate() {
        if i % CANCEL_EVERY == 0 && cancelled() {
            return None;
        }
        let b = step.activity;
        let Some((sb, eb)) = step.outcome.placement() else {
            continue;
        };
        // Each later placement must still pass every check without this activity
        // (its dependencies on it are checked once it is placed again).
        let scope = Scope {
            skip_deps: (0..problem.acts[b].after.len())
                .filter(|&i| problem.acts[b].after[i].target == a)
                .collect(),
            skip_reqs: Vec::new(),
            skip_end_effects: false,
            skip_data_capacity: false,
        };
        let fits = if problem.acts[b].held {
            state.replay(step)
        } else {
            state.fitting(b, sb, eb - sb, &scope)
        };
        match fits {
            Some(ev) => {
                if !problem.acts[b].held {
                    state.apply(step.step, &ev.placement);
                }
            }
            None => {
                // A later placement does not hold without this activity (its
                // generated pieces relied on it): only the scheduled start is
                // known to keep every constraint.
                let only = IntervalSet::single(s, s);
                return Some((only.clone(), only));
            }
        }
    }
    let (all_p1, all_both) = accepted_starts(&state, a, d);
    let mut temporal = all_p1.intersect(&own_p1);
    let mut both = all_both.intersect(&own_both);
    // Its effects may be what a placed requirement relied on: with it moved, every
    // requirement must still see its value.
    if let (Some(lo), Some(hi)) = (temporal.first(), temporal.intervals().last().map(|i| i.hi)) {
        let act = &problem.acts[a];
        let mut states: Vec<usize> = act.effects.iter().map(|e| e.state).collect();
        states.sort_unstable();
        states.dedup();
        for st in states {
            let own: Vec<(i64, usize)> = act
                .effects
                .iter()
                .filter(|e| e.state == st)
                .map(|e| (if e.at == EffectAt::Start { 0 } else { d }, e.value))
                .collect();
            let ok = state.states[st].requirements_hold_with(&own, usize::MAX, a, lo, hi);
            temporal = temporal.intersect(&ok);
            both = both.intersect(&ok);
        }
    }
    // Placed dependents keep their dependency on this activity's end.
    for (b, act) in problem.acts.iter().enumerate() {
        let Some((sb, _)) = sched.placement(b) else {
            continue;
        };
        for dep in act.after.iter().filter(|x| x.target == a) {
            let hi = sb - dep.min_delay - d;
            let lo = dep.max_delay.map_or(i64::MIN, |m| sb - m - d);
            temporal = temporal.clip(lo, hi);
            both = both.clip(lo, hi);
        }
    }
    Some((temporal, both))
}
