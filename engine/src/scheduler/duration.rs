//! Choosing the duration of an expanding activity: the longest in `[min, max]`
//! with a passing start (docs/semantics.md). Binary search where feasibility is
//! downward closed in the duration, a head/tail split where only the backward
//! min_awake extension near the plan end breaks that, and otherwise a scan down
//! from an upper bound: the longest duration that passes without the checks of
//! the activity's end effects (the only part of phase 1 an effect at the end
//! makes non-monotone), itself found by binary search or the split.

use super::problem::{Act, Problem};
use super::state::State;
use super::trace::Category;
use super::{Part, Scope, try_duration};
use crate::model::{AwakeMode, EffectAt};
use crate::timeline::{Interval, IntervalSet};

/// Whether the activity has a state effect at its end (which moves with the
/// duration, so that a shorter duration can fail where a longer one fits).
fn has_end_effect(act: &Act) -> bool {
    act.effects.iter().any(|e| e.at == EffectAt::End)
}

/// What can make a shorter duration fail where a longer one fits.
struct Breaks {
    /// A state effect at the activity's end, which moves with the duration.
    end_effect: bool,
    /// An awake period that may need extending backwards from the activity's
    /// end (docs/semantics.md, min_awake extension near the plan end).
    backward: bool,
    /// Being awake draws less than sleeping (`power.awake < power.asleep`): a
    /// longer awake need charges more.
    awake_charges: bool,
}

fn breaks(problem: &Problem, a: usize) -> Breaks {
    let act = &problem.acts[a];
    let awake = act.awake == AwakeMode::Required;
    Breaks {
        end_effect: has_end_effect(act),
        backward: awake
            && problem.min_awake > 0
            && act
                .windows
                .iter()
                .any(|w| w.end - problem.wake + problem.min_awake > problem.h1),
        awake_charges: awake && problem.awake < problem.asleep,
    }
}

/// Whether "fits with duration d" implies "fits with every shorter duration" for
/// this activity: true unless it has an effect at its end, its awake period could
/// need extending backwards from its end, or being awake charges the battery
/// ([`Breaks`]).
pub(super) fn duration_monotone(problem: &Problem, a: usize) -> bool {
    let b = breaks(problem, a);
    !b.end_effect && !b.backward && !b.awake_charges
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
    (!has_end_effect(&problem.acts[a]))
        .then(|| split_point(problem, a))
        .flatten()
}

/// [`head_tail_split`] without the condition on end effects: where the split
/// holds once the state_effect category is left out.
fn split_point(problem: &Problem, a: usize) -> Option<i64> {
    let act = &problem.acts[a];
    (act.awake == AwakeMode::Required && problem.min_awake > 0 && problem.awake >= problem.asleep)
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
///
/// With `scope.skip_end_effects`, the same for the activity without the checks
/// of its end effects ([`longest_bound`]).
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
        let part = Part {
            only: Some(only),
            bare: true,
            found_only: true,
            ..Part::default()
        };
        try_duration(state, a, d, scope, span, part).found.is_some()
    };
    let best = longest_passing(act.dur_min, top, |d| fits(d, (i64::MIN, head_end)));
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
    (act.dur_min..=top)
        .rev()
        .find(|&d| fits(state, a, d, scope, span))
}

/// Whether some start passes with duration `d` (an outcome-only search).
fn fits(state: &State<'_>, a: usize, d: i64, scope: &Scope, span: (i64, i64)) -> bool {
    let part = Part {
        bare: true,
        found_only: true,
        ..Part::default()
    };
    try_duration(state, a, d, scope, span, part).found.is_some()
}

/// The longest duration with a passing start, for an activity whose
/// feasibility is not monotone in the duration and is not split at the plan end
/// ([`head_tail_split`]): the durations from [`longest_bound`] down, longest
/// first. `None` if none has one.
///
/// Only durations that can pass phase 1 are searched: a duration `d` needs a
/// start `s` that passes without the end-effect checks, and such starts lie
/// among those passing with `dur_min` (the rest is monotone); it also needs
/// `s + d` to be a time the end effects can take ([`State::end_effect_times`]).
/// So `d` lies in `ends - starts`, the differences of the two sets, and the scan
/// skips every other duration: a requirement near the plan end that no end
/// effect may reach leaves the durations that end before it, not the whole range.
pub(super) fn longest_scanned(
    state: &State<'_>,
    a: usize,
    scope: &Scope,
    span: (i64, i64),
) -> Option<i64> {
    let act = &state.problem.acts[a];
    let top = longest_bound(state, a, scope, span);
    if top < act.dur_min {
        return None;
    }
    phase1_durations(state, a, scope, span, top)
        .intervals()
        .iter()
        .rev()
        .flat_map(|iv| (iv.lo..=iv.hi).rev())
        .find(|&d| fits(state, a, d, scope, span))
}

/// The starts in `span` that pass phase 1 with the shortest duration and
/// without the checks of the end effects: those that pass phase 1 with any
/// duration are among them (those checks left out, phase 1 is monotone).
fn shortest_starts(state: &State<'_>, a: usize, scope: &Scope, span: (i64, i64)) -> IntervalSet {
    let act = &state.problem.acts[a];
    let relaxed = scope.without_end_effects();
    let others = state.phase1_others(a, act.dur_min, &relaxed, span.0, span.1);
    // One set made from every window's pieces (a union per window would be
    // quadratic in the windows).
    IntervalSet::from_intervals(
        act.windows
            .iter()
            .map(|w| state.window_range(a, w, act.dur_min))
            .flat_map(|r| others.clip(r.lo, r.hi).intervals().to_vec())
            .collect(),
    )
}

/// Whether some start of `starts` can pass the peak power check with some
/// duration: every placement runs the activity at its start, where the peak is
/// at least the placed one there plus the activity's own, less what being
/// awake saves against sleeping (heaters only add), whatever the duration.
fn peak_room(state: &State<'_>, a: usize, starts: &IntervalSet) -> bool {
    let problem = state.problem;
    let Some(max) = problem.max_peak else {
        return true;
    };
    let act = &problem.acts[a];
    let saves = if act.awake == AwakeMode::Required {
        (problem.awake - problem.asleep).min(0)
    } else {
        0
    };
    let floor = act.peak.saturating_add(saves);
    starts.intervals().iter().any(|iv| {
        state
            .peak
            .segments(iv.lo, iv.hi.saturating_add(1))
            .any(|(_, _, v)| v.saturating_add(floor) <= max)
    })
}

/// The durations in `[dur_min, top]` for which some start can pass phase 1
/// ([`longest_scanned`]): `ends - starts`, or all of them when those sets are
/// too fragmented for the differences to be worth computing.
fn phase1_durations(
    state: &State<'_>,
    a: usize,
    scope: &Scope,
    span: (i64, i64),
    top: i64,
) -> IntervalSet {
    let act = &state.problem.acts[a];
    let all = IntervalSet::single(act.dur_min, top);
    let starts = shortest_starts(state, a, scope, span);
    let (Some(first), Some(last)) = (starts.intervals().first(), starts.intervals().last()) else {
        return IntervalSet::empty();
    };
    let ends = state.end_effect_times(
        a,
        first.lo.saturating_add(act.dur_min),
        last.hi.saturating_add(top),
    );
    if starts
        .intervals()
        .len()
        .saturating_mul(ends.intervals().len())
        > 100_000
    {
        return all;
    }
    let mut diffs = Vec::new();
    for e in ends.intervals() {
        for s in starts.intervals() {
            diffs.push(Interval::new(
                e.lo.saturating_sub(s.hi),
                e.hi.saturating_sub(s.lo),
            ));
        }
    }
    IntervalSet::from_intervals(diffs).intersect(&all)
}

/// An upper bound on the longest duration with a passing start; below
/// `dur_min` if no duration has one.
///
/// Why: when the only break of monotonicity is an effect at the end (no awake
/// period that charges), the activity without the checks of its end effects is
/// monotone in the duration for each start (before the split,
/// [`head_tail_split`]): every other phase-1 category is, a start effect holds
/// until the activity's end at most (a longer run can only break more), and
/// phase 2 does not read states. Passing with duration `d` then implies passing
/// that relaxation with every shorter duration, so the longest duration that
/// passes it, found by binary search (or by the split search where the min_awake
/// extension near the plan end applies), bounds the answer; when none passes, the
/// activity fails at every duration. With an awake period that charges, only the
/// monotone phase-1 categories bound it.
fn longest_bound(state: &State<'_>, a: usize, scope: &Scope, span: (i64, i64)) -> i64 {
    let problem = state.problem;
    let act = &problem.acts[a];
    let b = breaks(problem, a);
    let top = longest_monotone(state, a, scope, span);
    if b.awake_charges {
        // Energy and peak power are not monotone in the duration then (a longer
        // awake period charges more and draws less): only a start with room for
        // the activity's peak bounds it, for any duration.
        let starts = shortest_starts(state, a, scope, span);
        return if peak_room(state, a, &starts) {
            top
        } else {
            act.dur_min - 1
        };
    }
    let relaxed = scope.without_end_effects();
    let longest = if b.backward {
        split_point(problem, a)
            .and_then(|head_end| longest_split(state, a, &relaxed, span, head_end))
    } else {
        longest_passing(act.dur_min, top, |d| fits(state, a, d, &relaxed, span))
    };
    longest.unwrap_or(act.dur_min - 1)
}

/// The largest `d` in `[lo, hi]` that `passes`, for a test that holds for every
/// duration below one that passes (downward closed): binary search. `None` if
/// none passes.
fn longest_passing(lo: i64, hi: i64, mut passes: impl FnMut(i64) -> bool) -> Option<i64> {
    let (mut lo, mut hi) = (lo, hi);
    let mut best = None;
    while lo <= hi {
        let mid = lo + (hi - lo) / 2;
        if passes(mid) {
            best = Some(mid);
            lo = mid + 1;
        } else {
            hi = mid - 1;
        }
    }
    best
}

/// The longest duration for which the duration-monotone phase-1 categories (all but
/// state_effect) leave a start in some window; below `dur_min` if none.
fn longest_monotone(state: &State<'_>, a: usize, scope: &Scope, span: (i64, i64)) -> i64 {
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
    longest_passing(act.dur_min, act.dur_max, fits).unwrap_or(act.dur_min - 1)
}
