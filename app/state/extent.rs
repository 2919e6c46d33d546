//! Where an activity is drawn on the time axis: its bar once placed (or run),
//! else its windows. The Gantt draws it so; the reducer moves the time range to
//! show the selection by it, and the list's sol filter reads it.

use super::document::Analysis;
use super::execution::ExecutionRun;
use super::status::{Status, status_at};

/// Where an activity that is not placed is drawn: each window, from its start to
/// its end plus the longest duration (clipped to the horizon), or the whole
/// horizon without windows.
pub fn window_spans(
    plan: &solscope_engine::Plan,
    act: &solscope_engine::Activity,
) -> Vec<(i64, i64)> {
    let clip = |(lo, hi): (i64, i64)| (lo.max(plan.horizon.start), hi.min(plan.horizon.end));
    match &act.windows {
        Some(windows) => windows
            .iter()
            .map(|w| clip((w.start, w.end.saturating_add(act.duration.max()))))
            .filter(|(lo, hi)| lo < hi)
            .collect(),
        None => vec![(plan.horizon.start, plan.horizon.end)],
    }
}

/// Where the Gantt draws an activity.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Extent {
    /// As a bar `[start, end]`: placed, or in execution mode run (or
    /// predicted).
    Bar(i64, i64),
    /// As its windows (not placed, or never run): see [`window_spans`].
    Windows(Vec<(i64, i64)>),
}

/// Where the Gantt draws activity `a`: in schedule mode (`run` none) as of step
/// `k`, in execution mode where it ran, else where it was predicted.
pub fn extent(
    plan: &solscope_engine::Plan,
    analysis: &Analysis,
    run: Option<&ExecutionRun>,
    k: usize,
    a: usize,
) -> Option<Extent> {
    let act = plan.activities.get(a)?;
    let bar = match run {
        None => match status_at(analysis, a, k) {
            Status::Scheduled(s, e) => Some((s, e)),
            _ => None,
        },
        Some(run) => run.activity(a).and_then(|r| r.actual.or(r.predicted)),
    };
    Some(match bar {
        Some((s, e)) => Extent::Bar(s, e),
        None => Extent::Windows(window_spans(plan, act)),
    })
}
