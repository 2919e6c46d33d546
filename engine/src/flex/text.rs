//! Sentences a planner reads about a flexible schedule (`solscope flex --text`).

use super::{Bound, Constraint, Controllability, Flex, OrderKind, TimePoint};
use crate::model::Plan;
use crate::sentence::{between, range_or_time, span, spans, time};
use crate::timeline::IntervalSet;

/// An event as read: `drive's end`, `the horizon start`.
pub fn time_point_name(plan: &Plan, e: TimePoint) -> String {
    match e {
        TimePoint::Origin => "the horizon start".to_string(),
        TimePoint::Start(a) => format!("{} starts", plan.activities[a].id),
        TimePoint::End(a) => format!("{} ends", plan.activities[a].id),
    }
}

/// A constraint as read.
pub fn constraint_line(plan: &Plan, c: &Constraint) -> String {
    let id = |a: usize| plan.activities[a].id.as_str();
    match c {
        Constraint::Horizon { act } => format!("{} stays inside the horizon", id(*act)),
        Constraint::Window { act, window } => {
            format!("{} starts inside its window {}", id(*act), window + 1)
        }
        Constraint::Cutoff { act, window } => {
            format!(
                "{} ends by the cutoff of its window {}",
                id(*act),
                window + 1
            )
        }
        Constraint::Duration { act } => match plan.activities[*act].duration_model {
            Some(m) => format!("{} lasts {}", id(*act), spans(m.min, m.max)),
            None => format!("{} lasts as scheduled", id(*act)),
        },
        Constraint::Dependency { act, on } => format!("{} starts after {} ends", id(*act), id(*on)),
        Constraint::Order {
            first,
            second,
            kind,
        } => {
            let why = match kind {
                OrderKind::Resource(r) => format!("both use {r}"),
                OrderKind::Uhf => "UHF interactions".to_string(),
                OrderKind::Sleep => "a manual sleep".to_string(),
                OrderKind::State(s) => format!("state {s}"),
                OrderKind::Engines => "sequence engines".to_string(),
                OrderKind::PeakPower => "peak power".to_string(),
            };
            format!("{} before {} ({why})", id(*first), id(*second))
        }
    }
}

fn bound_line(plan: &Plan, b: &Bound) -> String {
    let what = time_point_name(plan, b.event);
    match b.offset {
        0 => format!("when {what}"),
        o if o > 0 => format!("{} after {what}", span(o)),
        o => format!("{} before {what}", span(-o)),
    }
}

fn set_line(plan: &Plan, set: &IntervalSet) -> String {
    if set.is_empty() {
        return "none".to_string();
    }
    let clock = &plan.local_time;
    set.intervals()
        .iter()
        .map(|iv| range_or_time(clock, iv.lo, iv.hi))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The whole flexible schedule as text.
pub fn flex_text(plan: &Plan, flex: &Flex) -> String {
    let clock = &plan.local_time;
    let mut out = String::new();
    push(
        &mut out,
        format!(
            "{} placed activities; {} network edges, {} in the minimum dispatchable network.",
            flex.activities.len(),
            flex.network_edges,
            flex.dispatchable.len()
        ),
    );
    match &flex.controllability {
        Controllability::Certain => {
            push(
                &mut out,
                "No uncertain durations: the network is the schedule's.".to_string(),
            );
        }
        Controllability::Controllable { waits, .. } => {
            push(
                &mut out,
                format!(
                    "Dynamically controllable: every outcome of the uncertain durations can be met ({} waits).",
                    waits.len()
                ),
            );
        }
        Controllability::NotControllable { constraints, .. } => {
            push(
                &mut out,
                "NOT dynamically controllable. The constraints that make it so:".to_string(),
            );
            for c in constraints {
                push(&mut out, format!("  - {}", constraint_line(plan, c)));
            }
        }
    }
    for fa in &flex.activities {
        let id = &plan.activities[fa.activity].id;
        let s = fa.start;
        out.push('\n');
        push(
            &mut out,
            format!(
                "{id}: scheduled at {}; may start {} ({} earlier, {} later).",
                time(clock, s.nom),
                between(clock, s.lb, s.ub),
                span(s.nom - s.lb),
                span(s.ub - s.nom)
            ),
        );
        for b in &fa.condition.after {
            push(
                &mut out,
                format!("  starts no earlier than {}", bound_line(plan, b)),
            );
        }
        for b in &fa.condition.within {
            push(
                &mut out,
                format!("  starts no later than {}", bound_line(plan, b)),
            );
        }
        if let Controllability::Controllable { waits, tightened } = &flex.controllability {
            if let Some(&(_, lb, ub)) = tightened.iter().find(|t| t.0 == fa.activity) {
                if (lb, ub) != (s.lb, s.ub) {
                    push(
                        &mut out,
                        format!(
                            "  whatever the uncertain durations: {}",
                            between(clock, lb, ub)
                        ),
                    );
                }
            }
            for w in waits.iter().filter(|w| w.activity == fa.activity) {
                push(
                    &mut out,
                    format!(
                        "  waits until {} ends or {} after it starts",
                        plan.activities[w.on].id,
                        span(w.offset)
                    ),
                );
            }
        }
        if let (Some(free), Some(p1)) = (&fa.free_slack, &fa.free_slack_phase1) {
            push(
                &mut out,
                format!(
                    "  free slack (every check, others fixed): {}",
                    set_line(plan, free)
                ),
            );
            let extra = p1.subtract(free);
            if !extra.is_empty() {
                push(
                    &mut out,
                    format!(
                        "  also free of temporal conflicts, but breaking energy, power, wake/sleep or heating: {}",
                        set_line(plan, &extra)
                    ),
                );
            }
        }
    }
    // Its sentences say times as the document does: in LMST here.
    crate::units::lmst_sentence(clock, &out)
}

fn push(out: &mut String, line: String) {
    out.push_str(&line);
    out.push('\n');
}
