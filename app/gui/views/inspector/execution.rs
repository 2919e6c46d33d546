//! The inspector in execution mode: for the selected activity what happened
//! to it (outcome, predicted against actual times, the cycle that dispatched
//! it, what held it back, why it was lost), across the Monte Carlo
//! campaign's runs when there is one, and what the looked-at cycle's run did
//! with it; then the looked-at cycle itself and the limits broken.

use eframe::egui::{self, RichText};
use solscope_engine::{
    Dropped, Event, FailurePhase, Guard, Outcome, ReasonRange, RunOutcome, format_time_difference,
    format_wh, loss_line, reason_line, wh,
};

use super::montecarlo;
use crate::gui::views::text::{trigger_text, violation_text};
use crate::gui::views::{Model, widgets};
use crate::state::Command;
use crate::state::execution::ExecutionRun;

/// How many of a failed step's reasons the inspector lists.
const REASONS_SHOWN: usize = 4;

/// The inspector in execution mode: the selected activity's execution, then its
/// step in the looked-at cycle's run, then the cycle itself.
pub(super) fn inspector_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    a: Option<usize>,
    cmds: &mut Vec<Command>,
) {
    let Some(run) = m.exec.ready() else {
        ui.label("The execution is not available yet.");
        return;
    };
    match a {
        None => {
            ui.label("Select an activity in the list or on the Gantt chart.");
            if let Some(result) = m.exec.campaign.ready() {
                ui.separator();
                montecarlo::most_lost_ui(ui, m, result, cmds);
            }
        }
        Some(a) => {
            activity_run_ui(ui, m, run, a, cmds);
            ui.separator();
            cycle_step_ui(ui, m, a, cmds);
        }
    }
    ui.separator();
    cycle_ui(ui, m, run, cmds);
    if !run.execution.violations.is_empty() {
        ui.separator();
        ui.label(RichText::new("Limits broken").strong());
        for v in &run.execution.violations {
            ui.colored_label(m.theme.error, violation_text(m, v));
        }
    }
}

/// What happened to activity `a`.
fn activity_run_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    run: &ExecutionRun,
    a: usize,
    cmds: &mut Vec<Command>,
) {
    ui.label(RichText::new(m.label(a)).strong());
    if m.exec.campaign.ready().is_some() {
        // Across the campaign's runs first, then this one execution.
        montecarlo::activity_ui(ui, m, a, cmds);
        ui.separator();
        ui.label(
            RichText::new(format!("In this execution ({})", m.exec.source.describe())).strong(),
        );
    }
    let Some(r) = run.activity(a) else {
        return;
    };
    let act = &m.doc.plan.activities[a];
    let (outcome, color) = match r.outcome {
        RunOutcome::Completed => ("completed".to_string(), m.theme.scheduled),
        RunOutcome::Aborted => (
            format!(
                "aborted: ran past its duration {} s and was stopped (actual duration {} s)",
                act.duration.max(),
                r.duration
            ),
            m.theme.aborted,
        ),
        RunOutcome::NotRun => ("not run: it never started".to_string(), m.theme.error),
    };
    ui.colored_label(color, RichText::new(format!("Outcome: {outcome}")).strong());
    if r.outcome != RunOutcome::Completed {
        loss_ui(ui, m, run, cmds);
    }
    egui::Grid::new("execution_times")
        .num_columns(2)
        .striped(true)
        .show(ui, |ui| {
            ui.label("Predicted (cycle 0)");
            ui.label(r.predicted.map_or("not placed".into(), |p| span(m, p)));
            ui.end_row();
            ui.label("Actual");
            ui.label(r.actual.map_or("did not start".into(), |p| span(m, p)));
            ui.end_row();
            if let (Some(p), Some(x)) = (r.predicted, r.actual) {
                ui.label("Start, end");
                ui.label(format!(
                    "{}, {}",
                    format_time_difference(x.0 - p.0),
                    format_time_difference(x.1 - p.1)
                ));
                ui.end_row();
            }
            ui.label("Actual duration");
            let would = if r.outcome == RunOutcome::NotRun {
                "would have been "
            } else {
                ""
            };
            ui.label(format!(
                "{would}{} s (planned {} s)",
                r.duration,
                act.duration.max()
            ));
            ui.end_row();
        });
    if let Some(c) = r.cycle {
        ui.horizontal_wrapped(|ui| {
            let at = run.execution.cycles.get(c).map_or(0, |x| x.time);
            ui.label(format!("Dispatched by cycle {c} (at {})", m.time(at)));
            if c != m.exec.cycle && ui.button(format!("Show cycle {c}")).clicked() {
                cmds.push(Command::SetCycle(c));
            }
        });
    }
    if r.outcome == RunOutcome::NotRun {
        not_run_ui(ui, m, run, (a, r.last_cycle), cmds);
    }
    held_ui(ui, m, run, a);
}

/// Why activity `a`, never started, did not run: the last cycle whose plan
/// had it (`last_cycle`), and the cycle that dropped it.
fn not_run_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    run: &ExecutionRun,
    (a, last_cycle): (usize, Option<usize>),
    cmds: &mut Vec<Command>,
) {
    match last_cycle {
        Some(c) => {
            ui.horizontal_wrapped(|ui| {
                ui.label(format!("Last in the plan of cycle {c}"));
                if c != m.exec.cycle && ui.button(format!("Show cycle {c}")).clicked() {
                    cmds.push(Command::SetCycle(c));
                }
            });
        }
        None => {
            ui.label("No cycle's plan had it.");
        }
    }
    let dropped = run.execution.cycles.iter().enumerate().find_map(|(k, c)| {
        c.dropped
            .iter()
            .find(|(x, _)| *x == a)
            .map(|(_, why)| (k, why))
    });
    if let Some((k, why)) = dropped {
        ui.label(format!("Cycle {k} dropped it: {}", dropped_text(m, why)));
    }
}

/// Every time the dispatcher held activity `a` back, with why and by whom.
fn held_ui(ui: &mut egui::Ui, m: &Model<'_>, run: &ExecutionRun, a: usize) {
    let held: Vec<(usize, i64, Guard)> = run
        .execution
        .cycles
        .iter()
        .enumerate()
        .flat_map(|(k, c)| {
            c.events.iter().filter_map(move |e| match *e {
                Event::Held {
                    activity,
                    time,
                    guard,
                } if activity == a => Some((k, time, guard)),
                _ => None,
            })
        })
        .collect();
    if held.is_empty() {
        ui.label("The dispatcher never held it back.");
    } else {
        ui.label(RichText::new("Held back by the dispatch guard").strong());
        for (k, t, guard) in held {
            ui.label(format!(
                "at {} (cycle {k}): {}",
                m.time(t),
                guard_text(m, guard)
            ));
        }
    }
}

/// Why the selected activity did not complete: the explainer's answer at the
/// cycle that decided it, and what ran differently before then.
fn loss_ui(ui: &mut egui::Ui, m: &Model<'_>, run: &ExecutionRun, cmds: &mut Vec<Command>) {
    match m.exec.loss {
        None => {
            ui.horizontal(|ui| {
                ui.spinner();
                ui.label("finding out why (explaining the cycle that decided it)…");
            });
        }
        Some(Err(e)) => {
            ui.colored_label(m.theme.error, format!("Could not find out why: {e}"));
        }
        Some(Ok(loss)) => {
            ui.label(solscope_engine::lmst_sentence(
                &m.doc.plan.local_time,
                &loss_line(&m.doc.plan, &run.execution.problem, loss),
            ));
            if let Some((k, _)) = loss.cycle {
                if k != m.exec.cycle && ui.button(format!("Show cycle {k}")).clicked() {
                    cmds.push(Command::SetCycle(k));
                }
            }
        }
    }
}

/// What the looked-at cycle's run did with activity `a` (its step record).
fn cycle_step_ui(ui: &mut egui::Ui, m: &Model<'_>, a: usize, cmds: &mut Vec<Command>) {
    let k = m.exec.cycle;
    ui.label(RichText::new(format!("In cycle {k}'s scheduler run")).strong());
    let Some(cr) = m.exec.cycle_run else {
        ui.label("being scheduled again…");
        return;
    };
    let (Some(sched), Some(step)) = (m.exec.schedule(), cr.step_of(a)) else {
        ui.label("Not in this cycle's plan (it had started, ended, or could no longer run).");
        return;
    };
    let Some(plan) = cr.plan.as_ref() else {
        return;
    };
    ui.horizontal_wrapped(|ui| {
        let shown = if step.step <= m.exec.step {
            match &step.outcome {
                Outcome::Scheduled { start, end } => {
                    format!("placed {}", span(m, (*start, *end)))
                }
                Outcome::Failed(FailurePhase::Dependency { on }) => format!(
                    "failed: its dependency {} was not placed",
                    cr.plan_activity(*on)
                        .map_or("?", |x| m.doc.plan.activities[x].id.as_str())
                ),
                Outcome::Failed(FailurePhase::ValidIntervals) => {
                    "failed: no start satisfies its constraints together".into()
                }
                Outcome::Failed(FailurePhase::Placement) => {
                    "failed: every valid start breaks a power, energy or sleep limit".into()
                }
                Outcome::Skipped { by } => format!(
                    "skipped: {} of its group was placed",
                    cr.plan_activity(*by)
                        .map_or("?", |x| m.doc.plan.activities[x].id.as_str())
                ),
            }
        } else {
            "pending".into()
        };
        ui.label(format!("Step {} of {}: {shown}", step.step, cr.steps()));
        if step.step != m.exec.step && ui.button("Show its step").clicked() {
            cmds.push(Command::SetCycleStep(step.step));
        }
    });
    if step.step > m.exec.step {
        return;
    }
    let trace = cr.traces.get(step.step - 1);
    if let Some(trace) = trace.filter(|t| !t.categories.is_empty()) {
        ui.label(
            RichText::new(format!(
                "Valid starts per constraint (within its windows, cycle {k} step {})",
                step.step
            ))
            .strong(),
        )
        .on_hover_text(crate::gui::help::VALID_STARTS);
        widgets::intervals_ui(ui, m, &trace.categories);
    }
    let failing: Vec<ReasonRange> = trace
        .into_iter()
        .flat_map(|t| &t.tries)
        .filter_map(|t| {
            Some(ReasonRange {
                first: t.starts.lo,
                last: t.starts.hi,
                duration: t.duration,
                reason: t.reason.clone()?,
                probe: t.probe,
            })
        })
        .collect();
    if !failing.is_empty() && step.outcome.placement().is_none() {
        ui.label(RichText::new("Rejected starts").strong());
        for r in failing.iter().take(REASONS_SHOWN) {
            ui.label(solscope_engine::lmst_sentence(
                &plan.local_time,
                &reason_line(plan, &sched.problem, r, step.duration),
            ));
        }
        if failing.len() > REASONS_SHOWN {
            ui.label(format!("and {} more ranges", failing.len() - REASONS_SHOWN));
        }
    }
}

/// The looked-at cycle: when, why, from what, and what its dispatcher did.
fn cycle_ui(ui: &mut egui::Ui, m: &Model<'_>, run: &ExecutionRun, cmds: &mut Vec<Command>) {
    let k = m.exec.cycle;
    let Some(cycle) = run.execution.cycles.get(k) else {
        return;
    };
    egui::CollapsingHeader::new(format!("Cycle {k}"))
        .default_open(true)
        .show(ui, |ui| {
            ui.label(format!(
                "At {}, {}; started from {} ({:.0} % of capacity)",
                m.time(cycle.time),
                trigger_text(m, cycle.trigger),
                format_wh(cycle.soc),
                100.0 * wh(cycle.soc) / m.doc.plan.battery.capacity.max(f64::MIN_POSITIVE)
            ));
            let id = |a: usize| m.doc.plan.activities[a].id.as_str();
            if !cycle.dropped.is_empty() {
                ui.label(RichText::new("Left out (can no longer run)").strong());
                for (a, why) in &cycle.dropped {
                    if ui
                        .link(format!("{}: {}", id(*a), dropped_text(m, why)))
                        .clicked()
                    {
                        cmds.push(Command::Select(Some(*a)));
                    }
                }
            }
            if cycle.events.is_empty() {
                ui.label("The dispatcher started nothing before the next cycle.");
            } else {
                ui.label(RichText::new("Dispatch until the next cycle").strong());
                for e in &cycle.events {
                    let (a, text) = match *e {
                        Event::Started { activity, time } => (
                            activity,
                            format!("{} started {}", m.time(time), id(activity)),
                        ),
                        Event::Held {
                            activity,
                            time,
                            guard,
                        } => (
                            activity,
                            format!(
                                "{} held {}: {}",
                                m.time(time),
                                id(activity),
                                guard_text(m, guard)
                            ),
                        ),
                    };
                    if ui.link(text).clicked() {
                        cmds.push(Command::Select(Some(a)));
                    }
                }
            }
        });
}

/// Why the dispatcher held an activity back.
fn guard_text(m: &Model<'_>, guard: Guard) -> String {
    let id = |a: usize| m.doc.plan.activities[a].id.as_str();
    match guard {
        Guard::Dependency(b) => format!(
            "dependency: {} had not ended (or its delay not passed)",
            id(b)
        ),
        Guard::Resource(b) => format!("unit resource: {} was still executing", id(b)),
        Guard::Engines(b) => format!(
            "sequence engines: too few free while {} was executing",
            id(b)
        ),
        Guard::Skipped => "skip condition: its latest start passed first".to_string(),
        Guard::State(s, v) => {
            let (name, value) = m
                .doc
                .plan
                .states
                .iter()
                .nth(s)
                .map_or(("?", "?"), |(n, d)| {
                    (n.as_str(), d.values.get(v).map_or("?", String::as_str))
                });
            format!("state: {name} was not {value}")
        }
    }
}

/// Why a cycle left an activity out.
fn dropped_text(m: &Model<'_>, why: &Dropped) -> String {
    let id = |a: usize| m.doc.plan.activities[a].id.as_str();
    match *why {
        Dropped::GroupMemberRan(b) => format!("{} of its group ran", id(b)),
        Dropped::DependencyPassed { on, end } => format!(
            "its dependency {} ended at {}, leaving no start",
            id(on),
            m.time(end)
        ),
        Dropped::DependsOnDropped(b) => format!("it depends on {}, which can no longer run", id(b)),
    }
}

/// `start – end` of a span.
fn span(m: &Model<'_>, (s, e): (i64, i64)) -> String {
    format!("{} – {}", m.time(s), m.time(e))
}
