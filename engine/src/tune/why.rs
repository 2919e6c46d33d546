//! Why each priority changed, from the evidence of the original and the tuned
//! order on the tuning sample.

use super::score::{Counts, Eval};

/// How a changed activity moved, and what it moved past.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Moved {
    /// It now comes ahead of `of`, which came before it originally.
    Ahead {
        /// The activity it moved past (plan index).
        of: usize,
    },
    /// It now comes after `of`, which came after it originally.
    After {
        /// The activity it moved past (plan index).
        of: usize,
    },
    /// Its priority changed only to keep the order realised (its relative
    /// order to every other activity is the original).
    Renumbered,
}

/// Why one priority changed, as data (the sentence is
/// [`change_line`](crate::change_line)).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ChangeWhy {
    /// How it moved.
    pub moved: Moved,
    /// The activity whose losses the move removed (itself, when it moved
    /// ahead; the one it made room for, when it moved after), if any.
    pub activity: Option<usize>,
    /// Runs of the tuning sample in which that activity was lost (not
    /// completed) with the original order, and with the tuned one.
    pub lost_before: u64,
    /// See `lost_before`.
    pub lost_after: u64,
    /// Runs in the tuning sample.
    pub runs: u64,
    /// Its most frequent loss cause with the original order
    /// (`placement/min_soc`, ...), and the culprit most named for it.
    pub cause: Option<String>,
    /// See `cause`.
    pub culprit: Option<usize>,
    /// Runs lost to that cause with the tuned order.
    pub cause_after: u64,
    /// Runs breaking a limit with the original order and with the tuned one
    /// (the reason when no loss explains the move).
    pub breaking_before: u64,
    /// See `breaking_before`.
    pub breaking_after: u64,
}

/// The why of activity `x`'s change from `original` to `tuned` (orders), with
/// the two evaluations (losses explained).
pub(crate) fn why(
    x: usize,
    original: &[usize],
    tuned: &[usize],
    before: &Eval,
    after: &Eval,
    runs: u64,
) -> ChangeWhy {
    let pos = |order: &[usize]| {
        let mut p = vec![0; order.len()];
        for (k, &a) in order.iter().enumerate() {
            p[a] = k;
        }
        p
    };
    let (p0, p1) = (pos(original), pos(tuned));
    let lost = |c: &[Counts], a: usize| c.get(a).map_or(0, Counts::lost);
    // The activities it moved past, each way.
    let overtaken: Vec<usize> = (0..original.len())
        .filter(|&y| p0[y] < p0[x] && p1[y] > p1[x])
        .collect();
    let overtaking: Vec<usize> = (0..original.len())
        .filter(|&y| p0[y] > p0[x] && p1[y] < p1[x])
        .collect();
    let ev0 = before.evidence.as_ref();
    let top = |a: usize| ev0.and_then(|e| e.top(a)).map(|(c, u)| (c.to_string(), u));
    let after_runs = |a: usize, cause: &Option<String>| match (cause, after.evidence.as_ref()) {
        (Some(c), Some(e)) => e.runs_of(a, c),
        _ => 0,
    };
    let base = ChangeWhy {
        moved: Moved::Renumbered,
        activity: None,
        lost_before: 0,
        lost_after: 0,
        runs,
        cause: None,
        culprit: None,
        cause_after: 0,
        breaking_before: before.score.runs_breaking,
        breaking_after: after.score.runs_breaking,
    };
    // Moved ahead and lost less: its own loss went away.
    if !overtaken.is_empty() && lost(&after.counts, x) < lost(&before.counts, x) {
        let (cause, culprit) = top(x).unzip();
        let culprit = culprit.flatten();
        // Past the activity most to blame, else the nearest one passed.
        let blamed = ev0.map(|e| e.blockers(x)).unwrap_or_default();
        let of = blamed
            .iter()
            .copied()
            .find(|b| overtaken.contains(b))
            .or_else(|| overtaken.iter().copied().max_by_key(|&y| p0[y]))
            .unwrap_or(x);
        let cause_after = after_runs(x, &cause);
        return ChangeWhy {
            moved: Moved::Ahead { of },
            activity: Some(x),
            lost_before: lost(&before.counts, x),
            lost_after: lost(&after.counts, x),
            cause,
            culprit,
            cause_after,
            ..base
        };
    }
    // Moved after activities that lose less now: the one that gained most,
    // one that named it as culprit first.
    let blamed_x = |y: usize| ev0.is_some_and(|e| e.blockers(y).contains(&x));
    let gain = |y: usize| lost(&before.counts, y).saturating_sub(lost(&after.counts, y));
    if let Some(y) = overtaking
        .iter()
        .copied()
        .filter(|&y| gain(y) > 0)
        .max_by(|&a, &b| {
            (blamed_x(a), gain(a))
                .cmp(&(blamed_x(b), gain(b)))
                .then(p0[b].cmp(&p0[a]))
        })
    {
        let (cause, culprit) = top(y).unzip();
        let cause_after = after_runs(y, &cause);
        return ChangeWhy {
            moved: Moved::After { of: y },
            activity: Some(y),
            lost_before: lost(&before.counts, y),
            lost_after: lost(&after.counts, y),
            cause,
            culprit: culprit.flatten(),
            cause_after,
            ..base
        };
    }
    // No loss to point at: how it moved (the limits may say why).
    let moved = if let Some(&of) = overtaken.iter().max_by_key(|&&y| p0[y]) {
        Moved::Ahead { of }
    } else if let Some(&of) = overtaking.iter().min_by_key(|&&y| p0[y]) {
        Moved::After { of }
    } else {
        Moved::Renumbered
    };
    ChangeWhy { moved, ..base }
}
