//! Inspector queries over a finished run: the valid starts of any activity at any
//! step, and the partial schedule after a step.

use super::{CategoryIntervals, Generated, Schedule, Scope};

/// Valid starts per category of activity `a` against the state after step `k`,
/// for duration `d` (its shortest duration when `None`): the inspector's view of
/// any activity at any step.
pub fn valid_intervals_at(
    sched: &Schedule,
    a: usize,
    k: usize,
    d: Option<i64>,
) -> Vec<CategoryIntervals> {
    let d = d.unwrap_or(sched.problem.acts[a].dur_min);
    sched.state_after(k).phase1(a, d, &Scope::default())
}

/// The partial schedule after step `k`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PartialSchedule {
    /// `(activity, start, end)` placed in steps `1..=k`, in step order.
    pub placed: Vec<(usize, i64, i64)>,
    /// Activities failed or skipped in steps `1..=k`.
    pub failed: Vec<usize>,
    /// Activities of steps after `k`, in step order.
    pub pending: Vec<usize>,
    /// Generated activities alive after step `k`.
    pub generated: Vec<Generated>,
}

/// The partial schedule after step `k` (0 = nothing placed yet).
pub fn partial_schedule(sched: &Schedule, k: usize) -> PartialSchedule {
    let mut p = PartialSchedule {
        placed: Vec::new(),
        failed: Vec::new(),
        pending: Vec::new(),
        generated: sched.generated_after(k).copied().collect(),
    };
    for s in &sched.steps {
        if s.step > k {
            p.pending.push(s.activity);
        } else if let Some((start, end)) = s.outcome.placement() {
            p.placed.push((s.activity, start, end));
        } else {
            p.failed.push(s.activity);
        }
    }
    p
}
