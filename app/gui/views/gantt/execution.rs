//! The Gantt's rows in execution mode: the cycles and broken limits as
//! markers, the executed awake periods, each activity's executed bar over a
//! thin bar of where the first cycle predicted it, and the looked-at
//! cycle's run as of the step shown; and the legend of their colours.

use eframe::egui::{self, RichText};
use solscope_engine::{GeneratedKind, Outcome, RunOutcome, Schedule};

use super::layout::{Bar, Row, lane_label, lanes, pack};
use crate::gui::theme::BASELINE_HEIGHT;
use crate::gui::views::Model;
use crate::gui::views::text::{trigger_text, violation_text};
use crate::state::execution::{CycleRun, ExecutionRun};
use crate::state::window_spans;

/// The rows of execution mode: cycle markers, broken limits, the executed awake
/// periods, executed activities over their prediction, those never placed, and
/// the looked-at cycle's run as of the step shown.
pub(super) fn execution_rows(m: &Model<'_>, run: &ExecutionRun) -> Vec<Row> {
    let t = &m.theme;
    let ex = &run.execution;
    let mut rows = marker_rows(m, run);
    let awake = ex
        .profile
        .awake
        .iter()
        .map(|&(a, b)| Bar::new(a as f64, b as f64, t.awake, None, "awake".into()))
        .collect();
    rows.push(Row {
        steps: false,
        ..Row::new("Awake".into(), awake)
    });
    rows.extend(executed_rows(m, run));
    if let (Some(cr), Some(sched)) = (m.exec.cycle_run, m.exec.schedule()) {
        rows.extend(cycle_rows(m, cr, sched));
    }
    rows
}

/// The cycle markers (click one to look at it) and the broken limits.
fn marker_rows(m: &Model<'_>, run: &ExecutionRun) -> Vec<Row> {
    let t = &m.theme;
    let ex = &run.execution;
    let mut rows = Vec::new();
    let cycles = ex
        .cycles
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let color = if k == m.exec.cycle {
                t.current
            } else {
                t.cycle
            };
            let mut bar = Bar::new(c.time as f64, c.time as f64, color, None, String::new());
            bar.tip = Some(format!(
                "cycle {k} at {}, {}, from {} (click to look at it)",
                m.time(c.time),
                trigger_text(m, c.trigger),
                solscope_engine::format_wh(c.soc)
            ));
            bar.cycle = Some(k);
            bar.marker = true;
            bar
        })
        .collect();
    rows.push(marker_row("Cycles", cycles));
    if !ex.violations.is_empty() {
        let marks = ex
            .violations
            .iter()
            .map(|v| {
                let end = v.worst.1.max(v.time);
                let mut bar = Bar::new(v.time as f64, end as f64, t.limit, None, String::new());
                bar.tip = Some(violation_text(m, v));
                bar.marker = true;
                bar
            })
            .collect();
        rows.push(marker_row("Limits broken", marks));
    }
    rows
}

/// Each activity: its executed bar (or, not run, a faint one where it was
/// predicted) over a thin bar of its prediction, packed by their union; the
/// activities never placed as their windows.
fn executed_rows(m: &Model<'_>, run: &ExecutionRun) -> Vec<Row> {
    let plan = &m.doc.plan;
    let t = &m.theme;
    let ex = &run.execution;
    let mut rows = Vec::new();
    let mut items: Vec<(Bar, Option<Bar>)> = Vec::new();
    let mut never = Vec::new();
    for (a, r) in ex.activities.iter().enumerate() {
        let act = &plan.activities[a];
        let id = act.id.clone();
        let predicted = r.predicted.map(|(s, e)| {
            let mut bar = Bar::new(s as f64, e as f64, t.predicted, Some(a), String::new());
            bar.tip = Some(format!(
                "{id}: predicted {}–{} (cycle 0)",
                m.time(s),
                m.time(e)
            ));
            bar
        });
        let was = r.predicted.map_or(String::new(), |(s, e)| {
            format!(" (predicted {}–{})", m.time(s), m.time(e))
        });
        let main = match (r.outcome, r.actual, r.predicted) {
            (RunOutcome::NotRun, _, None) => {
                for (lo, hi) in window_spans(plan, act) {
                    let mut bar = Bar::window(lo, hi, t.not_run, a, id.clone());
                    bar.tip = Some(format!("{id}: not run, never placed (its window)"));
                    never.push(bar);
                }
                continue;
            }
            (RunOutcome::NotRun, _, Some((s, e))) | (_, None, Some((s, e))) => {
                let mut bar = Bar::new(s as f64, e as f64, t.not_run, Some(a), id.clone());
                bar.tip = Some(format!("{id}: not run{was}"));
                bar
            }
            (outcome, Some((s, e)), _) => {
                let (color, what) = match outcome {
                    RunOutcome::Aborted => (t.aborted, "aborted"),
                    _ if act.comm_kind.is_some() => (t.comm, "completed"),
                    _ => (t.scheduled, "completed"),
                };
                let mut bar = Bar::new(s as f64, e as f64, color, Some(a), id.clone());
                bar.tip = Some(format!(
                    "{id}: {what}, ran {}–{}{was}",
                    m.time(s),
                    m.time(e)
                ));
                bar
            }
            (_, None, None) => continue,
        };
        items.push((main, predicted));
    }
    let span = |(main, pred): &(Bar, Option<Bar>)| match pred {
        Some(p) => (main.start.min(p.start), main.end.max(p.end)),
        None => (main.start, main.end),
    };
    for (i, lane) in lanes(items, span, 64).into_iter().enumerate() {
        let (main, pred): (Vec<Bar>, Vec<Option<Bar>>) = lane.into_iter().unzip();
        rows.push(Row {
            steps: false,
            ..Row::new(lane_label(i, "Executed"), main)
        });
        rows.push(Row {
            height: BASELINE_HEIGHT,
            steps: false,
            ..Row::new(String::new(), pred.into_iter().flatten().collect())
        });
    }
    if !never.is_empty() {
        rows.extend(
            pack(never, "Never placed", 8)
                .into_iter()
                .map(|r| Row { steps: false, ..r }),
        );
    }
    rows
}

/// A row of markers (never merged; hover for what they mark).
fn marker_row(label: &str, bars: Vec<Bar>) -> Row {
    Row {
        steps: false,
        ..Row::new(label.into(), bars)
    }
}

/// The looked-at cycle's run as of the step shown: its awake periods, what it
/// placed, and what it could not place (drawn as their windows).
fn cycle_rows(m: &Model<'_>, cr: &CycleRun, sched: &Schedule) -> Vec<Row> {
    let t = &m.theme;
    let k = m.exec.cycle;
    let plan = &m.doc.plan;
    let cycle_plan = cr.plan.as_ref();
    let mut rows = Vec::new();
    let awake = sched
        .generated_after(m.exec.step)
        .filter(|g| g.kind == GeneratedKind::Awake)
        .map(|g| Bar::new(g.start as f64, g.end as f64, t.awake, None, "awake".into()))
        .collect();
    rows.push(Row::new(format!("Cycle {k}: awake"), awake));
    let (mut placed, mut failed) = (Vec::new(), Vec::new());
    // By cycle-plan index: the run's own activity -> step index, O(1) each.
    for (i, &a) in cr.activity_of.iter().enumerate() {
        let act = &plan.activities[a];
        let Some(step) = sched.step_of(i).filter(|st| st.step <= m.exec.step) else {
            continue;
        };
        match step.outcome {
            Outcome::Scheduled { start, end } => {
                let color = if act.comm_kind.is_some() {
                    t.comm
                } else {
                    t.scheduled
                };
                let bar = Bar::new(start as f64, end as f64, color, Some(a), act.id.clone());
                placed.push(bar);
            }
            Outcome::Failed(_) | Outcome::Skipped { .. } => {
                let color = if matches!(step.outcome, Outcome::Failed(_)) {
                    t.failed
                } else {
                    t.skipped
                };
                // The windows the cycle gave it (from the cycle's time on).
                let spans = cycle_plan
                    .and_then(|p| p.activities.get(i).map(|x| window_spans(p, x)))
                    .unwrap_or_else(|| window_spans(plan, act));
                failed.extend(
                    spans
                        .into_iter()
                        .map(|(lo, hi)| Bar::window(lo, hi, color, a, act.id.clone())),
                );
            }
        }
    }
    rows.extend(pack(placed, &format!("Cycle {k}: placed"), 16));
    if !failed.is_empty() {
        rows.extend(pack(failed, &format!("Cycle {k}: failed"), 4));
    }
    rows
}

/// What the execution rows' colours mean.
pub(super) fn legend_ui(ui: &mut egui::Ui, m: &Model<'_>) {
    let t = &m.theme;
    ui.horizontal_wrapped(|ui| {
        let colored = |text: &str, color| RichText::new(text).color(color);
        ui.label(colored("Executed:", t.muted));
        ui.label(colored("completed", t.scheduled));
        ui.label(colored("aborted", t.aborted));
        ui.label(colored("not run", t.failed));
        ui.label(colored(
            "· thin bar below: predicted by cycle 0 ·",
            t.predicted,
        ));
        ui.label(colored(&format!("cycle {}", m.exec.cycle), t.current));
        ui.label(colored("· hover a mark or bar for details", t.muted));
    });
}
