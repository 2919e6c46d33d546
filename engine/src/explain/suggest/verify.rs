//! Verification: a candidate is kept only when the edited plan, rescheduled,
//! places the activity; numeric limits are searched to the least relaxation that
//! does.

use rayon::prelude::*;

use super::{Candidate, round3};
use crate::edit::edited;
use crate::explain::Suggestion;
use crate::model::Plan;
use crate::scheduler::{Schedule, placement_after_edit, placements_if_placed, schedule};

/// The candidates that make activity `a` schedule, each once, with the activities
/// they make fail; fewest side effects first (stable: candidate order breaks ties).
///
/// A candidate is first checked by running the edited plan only up to `a`'s step
/// (the greedy run never looks ahead, so that decides whether `a` is placed); only
/// one that passes is run to the end for its side effects. Both runs reuse the
/// steps of `sched` that the edit cannot change. Candidates are verified in
/// parallel and collected in candidate order, so the result does not depend on
/// the number of threads.
pub(super) fn verified(
    plan: &Plan,
    sched: &Schedule,
    a: usize,
    candidates: Vec<Candidate>,
) -> Vec<Suggestion> {
    let mut unique: Vec<Candidate> = Vec::with_capacity(candidates.len());
    for c in candidates {
        if !unique
            .iter()
            .any(|u| u.target == c.target && u.set == c.set)
        {
            unique.push(c);
        }
    }
    let mut out: Vec<Suggestion> = unique
        .into_par_iter()
        .filter_map(|c| {
            let edited = edited(plan, &c.target, &c.set)?;
            let side_effects = side_effects(&edited, a, sched)?;
            Some(Suggestion {
                description: c.description,
                target: c.target,
                set: c.set,
                side_effects,
            })
        })
        .collect();
    out.sort_by_key(|s| s.side_effects.len());
    out
}

/// Whether activity `a` is placed in the run of the edited `plan` (only the steps
/// up to its own are run). Debug builds check it against a full run from scratch.
fn places(plan: &Plan, a: usize, before: &Schedule) -> bool {
    let placed = placement_after_edit(before, plan, a).ok().flatten();
    debug_assert_eq!(
        placed,
        schedule(plan).ok().and_then(|s| s.placement(a)),
        "the run up to the activity's step disagrees with a full run"
    );
    placed.is_some()
}

/// If activity `a` is placed in the run of the edited `plan`: the activities
/// scheduled in `before` that are not any more. The steps after `a`'s are run
/// only when it is placed, and only where `a`'s placement can change them
/// ([`placements_if_placed`], which debug builds check against a full run).
fn side_effects(plan: &Plan, a: usize, before: &Schedule) -> Option<Vec<usize>> {
    let after = placements_if_placed(before, plan, a).ok().flatten()?;
    Some(
        before
            .steps
            .iter()
            .filter(|s| s.outcome.placement().is_some() && after[s.activity].is_none())
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
    sched: &Schedule,
    a: usize,
    make: &dyn Fn(f64) -> Candidate,
    current: f64,
    needed: f64,
    loosest: f64,
) -> Option<Candidate> {
    let works = |v: f64| {
        let c = make(v);
        edited(plan, &c.target, &c.set).is_some_and(|p| places(&p, a, sched))
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
