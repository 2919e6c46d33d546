//! Execution mode's controls above the Gantt: where the actual durations
//! come from (with the execution's summary), the cycle slider, and the step
//! slider inside the looked-at cycle's scheduler run. The execution
//! inspector is `inspector::execution`.

use eframe::egui::{self, RichText};
use solscope_engine::{Outcome, format_wh};

use super::text::{kind_name, trigger_text};
use super::{Model, step_row_ui};
use crate::gui::theme::{CYCLE_SLIDER_WIDTH, SEED_FIELD_WIDTH};
use crate::state::execution::ExecutionRun;
use crate::state::{Command, UiCommand};

/// Actuals: the source in use, nominal / open / sample, and the execution's
/// summary.
pub fn actuals_ui(ui: &mut egui::Ui, m: &Model<'_>, seed: &mut String, cmds: &mut Vec<Command>) {
    ui.horizontal_wrapped(|ui| {
        ui.label(RichText::new("Actuals:").strong());
        ui.label(m.exec.source.describe());
        super::command_button(ui, UiCommand::NominalActuals, true, cmds);
        super::command_button(ui, UiCommand::OpenActuals, true, cmds);
        let label = ui.label("Seed");
        let field = ui
            .add(egui::TextEdit::singleline(seed).desired_width(SEED_FIELD_WIDTH))
            .labelled_by(label.id)
            .on_hover_text("Draw the actual durations from the duration models with this seed");
        let enter = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        if ui.button("Sample").clicked() || enter {
            match seed.trim().parse::<u64>() {
                Ok(seed) => cmds.push(Command::SampleActuals { seed, run: 0 }),
                Err(_) => cmds.push(Command::ShowError(
                    "Seed: enter a whole number from 0 to 18446744073709551615".into(),
                )),
            }
        }
        ui.separator();
        match m.exec.run {
            None => {
                ui.spinner();
                ui.label("executing the plan…");
            }
            Some(Err(e)) => {
                ui.colored_label(m.theme.error, format!("Could not execute the plan: {e}"));
            }
            Some(Ok(run)) => summary_ui(ui, m, run),
        }
    });
}

/// `4 completed, 1 aborted, 0 not run · lowest 825.6 Wh at … · limits: …`.
fn summary_ui(ui: &mut egui::Ui, m: &Model<'_>, run: &ExecutionRun) {
    let (completed, aborted, not_run) = run.counts();
    ui.label(format!(
        "{completed} completed, {aborted} aborted, {not_run} not run"
    ));
    let (low, at) = run.execution.lowest_soc;
    ui.label(format!("lowest {} at {}", format_wh(low), m.time(at)));
    if let Some(h) = run.execution.handover_soc {
        ui.label(format!("handover {}", format_wh(h)));
    }
    let v = run.execution.violations.len();
    if v == 0 {
        ui.label("no limit broken");
    } else {
        let names: Vec<&str> = run
            .execution
            .violations
            .iter()
            .map(|v| kind_name(v.kind))
            .collect();
        ui.colored_label(
            m.theme.error,
            format!("{v} limit(s) broken: {}", names.join(", ")),
        );
    }
}

/// The cycle slider: which cycle, when, why, from what state of charge.
pub fn cycles_ui(ui: &mut egui::Ui, m: &Model<'_>, cmds: &mut Vec<Command>) {
    let Some(run) = m.exec.ready() else {
        return;
    };
    let cycles = &run.execution.cycles;
    let k = m.exec.cycle;
    ui.horizontal_wrapped(|ui| {
        super::command_button(ui, UiCommand::PreviousCycle, k > 0, cmds);
        super::command_button(ui, UiCommand::NextCycle, k + 1 < cycles.len(), cmds);
        let mut c = k;
        ui.spacing_mut().slider_width = CYCLE_SLIDER_WIDTH;
        let slider = egui::Slider::new(&mut c, 0..=cycles.len().saturating_sub(1)).text("Cycle");
        if ui.add(slider).changed() {
            cmds.push(Command::SetCycle(c));
        }
        if let Some(cycle) = cycles.get(k) {
            let placed = cycle.placed();
            let failed = cycle.failed().len();
            ui.label(format!(
                "cycle {k} of {}: at {}, {}, from {} — {placed} placed, {failed} not, {} dropped",
                cycles.len(),
                m.time(cycle.time),
                trigger_text(m, cycle.trigger),
                format_wh(cycle.soc),
                cycle.dropped.len()
            ));
        }
    });
}

/// The step slider inside the looked-at cycle's scheduler run.
pub fn cycle_steps_ui(ui: &mut egui::Ui, m: &Model<'_>, cmds: &mut Vec<Command>) {
    if m.exec.ready().is_none() {
        return;
    }
    let k = m.exec.cycle;
    let Some(cr) = m.exec.cycle_run else {
        ui.horizontal(|ui| {
            ui.spinner();
            ui.label(format!("scheduling cycle {k} again for its step trace…"));
        });
        return;
    };
    if let Err(e) = &cr.schedule {
        ui.colored_label(
            m.theme.error,
            format!("Could not schedule cycle {k} again: {e}"),
        );
        return;
    }
    let what = |j: usize| match cr.activity_of_step(j) {
        None => format!("cycle {k}, before step 1: nothing placed"),
        Some(a) => {
            let outcome = match cr.step_of(a).filter(|s| s.step <= j).map(|s| &s.outcome) {
                Some(Outcome::Scheduled { start, end }) => {
                    format!("placed {}–{}", m.time(*start), m.time(*end))
                }
                Some(Outcome::Failed(_)) => "failed".into(),
                Some(Outcome::Skipped { .. }) => "skipped".into(),
                None => String::new(),
            };
            format!("cycle {k}, step {j}: {} — {outcome}", m.label(a))
        }
    };
    let failed: Vec<usize> = match &cr.schedule {
        Ok(s) => super::failed_steps(&s.steps).map(|(j, _)| j).collect(),
        Err(_) => Vec::new(),
    };
    step_row_ui(ui, m, (cr.steps(), m.exec.step), &failed, what, cmds);
}
