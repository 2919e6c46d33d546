//! What happened to an activity as of a step of a run, and the steps at which
//! an activity failed: read by the reducer (failure navigation, the list's
//! filters, revealing the selection) and by the views alike.

use solscope_engine::Outcome;

use super::document::Analysis;

/// Status of activity `a` as of step `k`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    /// Placed at `[start, end)` in a step <= k.
    Scheduled(i64, i64),
    /// Failed in a step <= k.
    Failed,
    /// Skipped in a step <= k.
    Skipped,
    /// Its step is after k.
    Pending,
}

/// Status of activity `a` after step `k` of `analysis`'s run.
pub fn status_at(analysis: &Analysis, a: usize, k: usize) -> Status {
    match analysis.step(a) {
        Some(st) if st.step <= k => match st.outcome {
            Outcome::Scheduled { start, end } => Status::Scheduled(start, end),
            Outcome::Failed(_) => Status::Failed,
            Outcome::Skipped { .. } => Status::Skipped,
        },
        _ => Status::Pending,
    }
}

/// The steps (1-based) at which an activity failed, with the activity (an index
/// into the run's plan).
pub fn failed_steps(steps: &[solscope_engine::Step]) -> impl Iterator<Item = (usize, usize)> + '_ {
    steps
        .iter()
        .filter(|s| matches!(s.outcome, Outcome::Failed(_)))
        .map(|s| (s.step, s.activity))
}
