//! Planner-facing sentences for executions. Pure formatting: no decisions here.

use super::{Cause, Dropped, Loss, RunOutcome};
use crate::model::Plan;
use crate::scheduler::Problem;
use crate::sentence::{seconds, seconds_delta, time};

/// One sentence on why activity `loss.activity` did not complete in an
/// execution: "science was not run: at the cycle at 7000 (01:56:40), placement
/// failed (min_soc), involving drive. Before then drive ran 6000 s instead of
/// 3600 s (+2400 s)."
pub fn loss_line(plan: &Plan, problem: &Problem, loss: &Loss) -> String {
    let name = |a: usize| plan.activities[a].display_name().to_string();
    let me = name(loss.activity);
    let when = loss
        .cycle
        .map(|(_, t)| format!("at the cycle at {}", time(&problem.clock, t)))
        .unwrap_or_else(|| "in the last cycle".into());
    let mut line = match &loss.cause {
        Cause::Overran => format!(
            "{me} was aborted: it ran longer than its duration of {}.",
            seconds(plan.activities[loss.activity].duration.max())
        ),
        Cause::Held => format!(
            "{me} was not run: {when} it was due, but the dispatcher held it back and no later cycle placed it before its windows closed."
        ),
        Cause::Dropped(Dropped::GroupMemberRan(b)) => {
            format!("{me} was not run: {} of its group ran first.", name(*b))
        }
        Cause::Dropped(Dropped::DependencyPassed { on, end }) => format!(
            "{me} was not run: {} ended at {}, which leaves no start its dependency allows {when}.",
            name(*on),
            time(&problem.clock, *end)
        ),
        Cause::Dropped(Dropped::DependsOnDropped(b)) => format!(
            "{me} was not run: it depends on {}, which could no longer run.",
            name(*b)
        ),
        Cause::Failed {
            phase,
            detail,
            culprits,
        } => {
            let what = if detail.is_empty() {
                phase.name().to_string()
            } else {
                format!("{} ({})", phase.name(), detail.join(", "))
            };
            let who = if culprits.is_empty() {
                String::new()
            } else {
                let names: Vec<String> = culprits.iter().map(|&c| name(c)).collect();
                format!(", involving {}", names.join(", "))
            };
            let verb = if loss.outcome == RunOutcome::NotRun {
                "was not run"
            } else {
                "did not complete"
            };
            format!("{me} {verb}: {when} the scheduler could not place it: {what}{who}.")
        }
    };
    if !loss.changed.is_empty() {
        let parts: Vec<String> = loss
            .changed
            .iter()
            .map(|&(b, actual, planned)| {
                format!(
                    "{} ran {} instead of {} ({})",
                    name(b),
                    seconds(actual),
                    seconds(planned),
                    seconds_delta(actual - planned)
                )
            })
            .collect();
        line.push_str(&format!(" Before then {}.", parts.join("; ")));
    }
    line
}
