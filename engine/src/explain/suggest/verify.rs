//! Verification: a candidate is kept only when the edited plan, rescheduled,
//! places the activity; numeric limits are searched to the least relaxation that
//! does.

use super::{Candidate, round3};
use crate::edit::apply_edit;
use crate::explain::Suggestion;
use crate::model::Plan;
use crate::scheduler::{Schedule, schedule};

/// The candidates that make activity `a` schedule, each once, with the activities
/// they make fail; fewest side effects first (stable: candidate order breaks ties).
pub(super) fn verified(
    plan: &Plan,
    sched: &Schedule,
    a: usize,
    candidates: Vec<Candidate>,
) -> Vec<Suggestion> {
    let mut out: Vec<Suggestion> = Vec::new();
    for c in candidates {
        if out.iter().any(|s| s.target == c.target && s.set == c.set) {
            continue;
        }
        let Ok(edited) = apply_edit(plan, &c.target, &c.set) else {
            continue;
        };
        if let Some(side_effects) = reschedule_outcome(&edited, a, sched) {
            out.push(Suggestion {
                description: c.description,
                target: c.target,
                set: c.set,
                side_effects,
            });
        }
    }
    out.sort_by_key(|s| s.side_effects.len());
    out
}

/// Reschedules `plan` and reports whether activity `a` is scheduled, with the
/// activities scheduled in `before` that are not any more.
fn reschedule_outcome(plan: &Plan, a: usize, before: &Schedule) -> Option<Vec<usize>> {
    let after = schedule(plan).ok()?;
    after.placement(a)?;
    Some(
        before
            .steps
            .iter()
            .filter(|s| s.outcome.placement().is_some() && after.placement(s.activity).is_none())
            .map(|s| s.activity)
            .collect(),
    )
}

/// The least relaxation of a numeric plan limit (from `current`, which fails) that
/// makes activity `a` schedule. `needed` is what the failure's numbers call for;
/// knock-on effects on earlier steps can ask for less or more, so the value is
/// binary-searched between `current` and `needed` when `needed` works, else between
/// `needed` and `loosest`, to a resolution of 0.001.
pub(super) fn tune_limit(
    plan: &Plan,
    a: usize,
    make: &dyn Fn(f64) -> Candidate,
    current: f64,
    needed: f64,
    loosest: f64,
) -> Option<Candidate> {
    let works = |v: f64| {
        let c = make(v);
        apply_edit(plan, &c.target, &c.set)
            .ok()
            .and_then(|p| schedule(&p).ok())
            .is_some_and(|s| s.placement(a).is_some())
    };
    let (mut bad, mut good) = if works(needed) {
        (current, needed)
    } else if works(loosest) {
        (needed, loosest)
    } else {
        return None;
    };
    for _ in 0..48 {
        let mid = round3((bad + good) / 2.0);
        if (good - bad).abs() <= 0.001 || mid == bad || mid == good {
            break;
        }
        if works(mid) {
            good = mid;
        } else {
            bad = mid;
        }
    }
    Some(make(good))
}
