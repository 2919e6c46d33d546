//! Choosing the duration of an expanding activity: the longest in `[min, max]`
//! with a passing start (docs/semantics.md). Binary search where feasibility is
//! downward closed in the duration, a head/tail split where only the backward
//! min_awake extension near the plan end breaks that, and a scan otherwise.

use super::problem::{Act, Problem};
use super::state::State;
use super::trace::Category;
use super::{Scope, try_duration};
use crate::model::{AwakeMode, EffectAt};
use crate::timeline::IntervalSet;

/// Whether the activity has a state effect at its end (which moves with the
/// duration, so that a shorter duration can fail where a longer one fits).
fn has_end_effect(act: &Act) -> bool {
    act.effects.iter().any(|e| e.at == EffectAt::End)
}

/// Whether "fits with duration d" implies "fits with every shorter duration" for
/// this activity: true unless it has an effect at its end (which moves with the
/// duration), its awake period could need extending backwards from its end
/// (docs/semantics.md, min_awake extension near the plan end), or being awake
/// draws less than sleeping (`power.awake < power.asleep`).
pub(super) fn duration_monotone(problem: &Problem, a: usize) -> bool {
    let act = &problem.acts[a];
    let end_effect = has_end_effect(act);
    let backward = act.awake == AwakeMode::Required
        && problem.min_awake > 0
        && act
            .windows
            .iter()
            .any(|w| w.end - problem.wake + problem.min_awake > problem.h1);
    // An awake period that draws less than sleep charges the battery: a longer
    // awake need can then pass where a shorter one runs out of energy.
    let awake_charges = act.awake == AwakeMode::Required && problem.awake < problem.asleep;
    !end_effect && !backward && !awake_charges
}

/// For an expanding activity whose only break of monotonicity is the backward
/// min_awake extension near the plan end: the last start of the "head", the starts
/// for which fitting with a duration implies fitting with every shorter one.
///
/// Why: for a start `s` with `s - wakeup + min_awake <= horizon.end`, the merged
/// period `Q1` of any duration starts at or before `s - wakeup`, so the extension
/// (when needed) is the forward one, `[Q1.start, Q1.start + min_awake)`. Merging
/// never moves `Q1.start` differently for a longer need with the same start (a
/// period merged at the front is merged for both), so a shorter duration's `Q1`,
/// extension and `Q2` are subsets of the longer one's: its awake need, merge and
/// min_awake checks pass whenever the longer one's do, its preheats are the same
/// (same start), and every load piece (activity, awake extra, maintenance) covers
/// a subset of the seconds with at most the same power, which can only raise the
/// capped state of charge and lower the peak. That needs `awake >= asleep` (an
/// awake period must not charge) and no effect at the end (the only phase-1
/// category that is not monotone in the duration). `None` when that does not hold.
pub(super) fn head_tail_split(problem: &Problem, a: usize) -> Option<i64> {
    let act = &problem.acts[a];
    let end_effect = has_end_effect(act);
    (!end_effect
        && act.awake == AwakeMode::Required
        && problem.min_awake > 0
        && problem.awake >= problem.asleep)
        .then(|| problem.h1 - problem.min_awake + problem.wake)
}

/// The longest duration with a passing start, for an activity split at `head_end`
/// ([`head_tail_split`]); `None` if no duration in `[dur_min, dur_max]` has one.
///
/// Head starts (`<= head_end`) are downward closed in the duration, so the longest
/// duration with a passing head start is found by binary search. A tail start
/// (`> head_end`) needs `s + d + shutdown <= horizon.end`, so only durations below
/// `min_awake - wakeup - shutdown` have any; those longer than the head's result
/// are scanned, longest first, over the tail starts only.
pub(super) fn longest_split(
    state: &State<'_>,
    a: usize,
    scope: &Scope,
    span: (i64, i64),
    head_end: i64,
) -> Option<i64> {
    let problem = state.problem;
    let act = &problem.acts[a];
    let top = longest_monotone(state, a, scope, span);
    let fits = |d: i64, only: (i64, i64)| {
        try_duration(state, a, d, scope, span, Some(only), false)
            .found
            .is_some()
    };
    let (mut lo, mut hi) = (act.dur_min, top);
    let mut best = None;
    while lo <= hi {
        let mid = lo + (hi - lo) / 2;
        if fits(mid, (i64::MIN, head_end)) {
            best = Some(mid);
            lo = mid + 1;
        } else {
            hi = mid - 1;
        }
    }
    let tail_top = top.min(problem.min_awake - problem.wake - problem.shut - 1);
    let floor = best.map_or(act.dur_min, |b| b + 1);
    (floor..=tail_top)
        .rev()
        .find(|&d| fits(d, (head_end.saturating_add(1), i64::MAX)))
        .or(best)
}

/// The longest duration with a passing start, by trying every duration down from
/// the longest the monotone categories allow (debug cross-check).
#[cfg(debug_assertions)]
pub(super) fn longest_by_scan(
    state: &State<'_>,
    a: usize,
    scope: &Scope,
    span: (i64, i64),
) -> Option<i64> {
    let act = &state.problem.acts[a];
    let top = longest_monotone(state, a, scope, span);
    (act.dur_min..=top).rev().find(|&d| {
        try_duration(state, a, d, scope, span, None, false)
            .found
            .is_some()
    })
}

/// The longest duration for which the duration-monotone phase-1 categories (all but
/// state_effect) leave a start in some window; below `dur_min` if none.
pub(super) fn longest_monotone(
    state: &State<'_>,
    a: usize,
    scope: &Scope,
    span: (i64, i64),
) -> i64 {
    let act = &state.problem.acts[a];
    let fits = |d: i64| {
        let others = state
            .phase1_in(a, d, scope, span.0, span.1)
            .iter()
            .filter(|c| c.category != Category::Execution && c.category != Category::StateEffect)
            .fold(IntervalSet::single(span.0, span.1), |acc, c| {
                acc.intersect(&c.valid)
            });
        act.windows.iter().any(|w| {
            let r = state.window_range(a, w, d);
            !others.clip(r.lo, r.hi).is_empty()
        })
    };
    let (mut lo, mut hi) = (act.dur_min, act.dur_max);
    let mut best = act.dur_min - 1;
    while lo <= hi {
        let mid = lo + (hi - lo) / 2;
        if fits(mid) {
            best = mid;
            lo = mid + 1;
        } else {
            hi = mid - 1;
        }
    }
    best
}
