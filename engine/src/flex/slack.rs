//! Free slack: the starts at which the scheduler's own checks accept an activity
//! with every other placement fixed.
//!
//! The state is the schedule's without the activity: the steps before its step as
//! recorded, the steps after it replayed (each re-deriving its wake/sleep and
//! heating without the activity). In that state the activity is checked at every
//! start as its step checks it (every window, phase 1, then phase 2 with the
//! wake/sleep and heating the move needs), and the dependencies of the placed
//! activities that depend on it bound its end.

use crate::scheduler::{Outcome, Schedule, accepted_starts};
use crate::timeline::IntervalSet;

/// The free slack of activity `a` (placed at `(s, e)`): the starts passing phase 1
/// and the dependents' dependencies, and the part of those that also passes phase 2.
pub(crate) fn free_slack(
    sched: &Schedule,
    a: usize,
    (s, e): (i64, i64),
) -> (IntervalSet, IntervalSet) {
    let problem = &sched.problem;
    let d = e - s;
    let k = problem.step_of[a];
    let mut state = sched.state_after(k - 1);
    for step in &sched.steps[k..] {
        let placed = matches!(step.outcome, Outcome::Scheduled { .. });
        if state.replay(step).is_none() && placed {
            // A later placement cannot be re-derived without this activity (its
            // generated pieces relied on it): only the scheduled start is known
            // to keep every constraint.
            let only = IntervalSet::single(s, s);
            return (only.clone(), only);
        }
    }
    let (mut temporal, mut both) = accepted_starts(&state, a, d);
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
    (temporal, both)
}
