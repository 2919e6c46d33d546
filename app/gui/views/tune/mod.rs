//! The "Tune priorities" panel (under the Gantt and plots, when shown): the
//! search's settings (from the command line's defaults), Tune and Cancel
//! with its progress (orders scored of the budget, the best score so far),
//! and once a result exists for the plan as it is, its objective on the
//! held-out sample before and after, Apply (one undoable edit of the
//! priorities), the Gantt overlay toggle and Dismiss; then the changes with
//! their reasons and each activity's completed share before and after
//! (`result`).

mod result;

use eframe::egui::{self, Color32, RichText};

use super::Model;
use super::controls::command_button;
use crate::gui::theme::Theme;
use crate::state::tune::{
    BUDGET_LABEL, CONFIRM_RUNS_LABEL, CONFIRM_SEED_LABEL, PINNED_LABEL, RUNS_LABEL, SEED_LABEL,
    TuneResult, TuneRunning, TuneText,
};
use crate::state::{Command, UiCommand};

/// The panel's height when it opens (it can be resized; its body scrolls).
pub const PANEL_HEIGHT: f32 = 330.0;
/// Width of the number fields.
const NUMBER_WIDTH: f32 = 48.0;
/// Width of the pinned ids field.
const PINNED_WIDTH: f32 = 180.0;
/// Width of the progress bar.
const PROGRESS_WIDTH: f32 = 180.0;

/// The colour of the tuned order's share bars and of the tuned schedule on
/// the Gantt (a violet no other layer uses).
pub fn tuned_color(theme: &Theme) -> Color32 {
    if theme.dark {
        Color32::from_rgb(175, 125, 255)
    } else {
        Color32::from_rgb(120, 60, 200)
    }
}

/// The panel: its controls in the header, the result in the body.
pub fn tune_panel_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    text: &mut TuneText,
    cmds: &mut Vec<Command>,
) {
    ui.horizontal_wrapped(|ui| {
        ui.label(RichText::new("Priority tuning").strong())
            .on_hover_text(
                "Search the priorities (the order in which the scheduler considers the \
                 activities) that complete more of what matters over the executions the \
                 duration models make likely; the result is confirmed on a held-out sample",
            );
        controls_ui(ui, m, text, cmds);
    });
    if let Some(p) = &m.tune.running {
        progress_ui(ui, m, p);
    }
    if m.tune.interrupted && m.tune.running.is_none() && m.tune.result.is_none() {
        ui.colored_label(
            m.theme.muted,
            "The plan was edited while the search ran: it was stopped (tune again)",
        );
    }
    match m.tune.result {
        None if m.tune.stale => {
            ui.colored_label(
                m.theme.muted,
                "The plan was edited after the last tuning: its result no longer applies",
            );
        }
        None => {}
        Some(Err(e)) => {
            ui.colored_label(m.theme.error, e);
        }
        Some(Ok(r)) => {
            summary_ui(ui, m, r, cmds);
            result::result_ui(ui, m, r, cmds);
        }
    }
}

/// The settings, Tune and Cancel.
fn controls_ui(ui: &mut egui::Ui, m: &Model<'_>, text: &mut TuneText, cmds: &mut Vec<Command>) {
    let running = m.tune.running.is_some();
    let mut enter = false;
    let mut field = |ui: &mut egui::Ui, label: &str, value: &mut String, width: f32, hover| {
        let l = ui.label(label);
        let r = ui
            .add(egui::TextEdit::singleline(value).desired_width(width))
            .labelled_by(l.id)
            .on_hover_text(hover);
        enter |= r.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
    };
    field(
        ui,
        RUNS_LABEL,
        &mut text.runs,
        NUMBER_WIDTH,
        "Runs of the tuning sample, on which the search scores each order",
    );
    field(
        ui,
        SEED_LABEL,
        &mut text.seed,
        NUMBER_WIDTH,
        "Run i draws the durations the Monte Carlo campaign of this seed draws in run i",
    );
    field(
        ui,
        CONFIRM_RUNS_LABEL,
        &mut text.confirm_runs,
        NUMBER_WIDTH,
        "Runs of the held-out sample the result is confirmed on (at least the tuning runs)",
    );
    field(
        ui,
        CONFIRM_SEED_LABEL,
        &mut text.confirm_seed,
        NUMBER_WIDTH,
        "Seed of the held-out sample (another than the tuning seed)",
    );
    field(
        ui,
        BUDGET_LABEL,
        &mut text.budget,
        NUMBER_WIDTH,
        "Orders the search may score on the tuning sample, the original's included",
    );
    // The pinned ids, Tune and Cancel on a line of their own.
    ui.end_row();
    field(
        ui,
        PINNED_LABEL,
        &mut text.pinned,
        PINNED_WIDTH,
        "Activities that keep their priority and place (ids, separated by commas or spaces)",
    );
    if let Some(a) = m.nav.selected
        && let Some(act) = m.doc.plan.activities.get(a)
    {
        let pinned = text
            .pinned
            .split(|c: char| c == ',' || c.is_whitespace())
            .any(|s| s == act.id);
        if ui
            .add_enabled(!pinned, egui::Button::new("Pin selected"))
            .on_hover_text(format!("Add {} to the pinned ids", act.id))
            .clicked()
        {
            if !text.pinned.trim().is_empty() {
                text.pinned.push_str(", ");
            }
            text.pinned.push_str(&act.id);
        }
    }
    let tune = ui
        .add_enabled(!running, egui::Button::new("Tune"))
        .on_hover_text("Search, then confirm on the held-out sample")
        .on_disabled_hover_text("A search is running");
    if tune.clicked() || (enter && !running) {
        match text.parse() {
            Ok(settings) => cmds.push(Command::RunTune(settings)),
            Err(e) => cmds.push(Command::ShowError(e)),
        }
    }
    command_button(ui, UiCommand::CancelTune, running, cmds);
}

/// The search running: orders scored of the budget, the best score so far.
fn progress_ui(ui: &mut egui::Ui, m: &Model<'_>, p: &TuneRunning) {
    ui.horizontal_wrapped(|ui| {
        let share = if p.budget == 0 {
            0.0
        } else {
            (p.evaluations as f32 / p.budget as f32).min(1.0)
        };
        let what = if p.cancelling {
            format!(
                "cancelling: confirming the best order of {} scored…",
                p.evaluations
            )
        } else {
            format!(
                "{} / {} orders scored ({} s)",
                p.evaluations, p.budget, p.seconds
            )
        };
        ui.add(
            egui::ProgressBar::new(share)
                .desired_width(PROGRESS_WIDTH)
                .text(what.clone()),
        )
        .widget_info(|| egui::WidgetInfo::labeled(egui::Role::ProgressIndicator, true, &what));
        if let Some(best) = &p.best {
            ui.colored_label(
                m.theme.muted,
                format!(
                    "best so far on {} runs: {}",
                    p.runs,
                    solscope_engine::score_line(best, p.runs)
                ),
            );
        }
    });
}

/// How the search went, the objective before and after on the held-out
/// sample, and Apply, the overlay toggle and Dismiss.
fn summary_ui(ui: &mut egui::Ui, m: &Model<'_>, r: &TuneResult, cmds: &mut Vec<Command>) {
    let t = &r.tuning;
    let how = format!(
        "{} search on {} runs (seed {}): {} of {} orders scored, {}",
        t.mode.name(),
        t.tuning.runs,
        t.tuning.seed,
        t.evaluations,
        t.budget,
        match t.stop {
            solscope_engine::Stop::Finished => "finished",
            solscope_engine::Stop::Budget => "the budget ran out",
            solscope_engine::Stop::Cancelled => "cancelled",
        }
    );
    ui.label(how);
    match t.stop {
        solscope_engine::Stop::Finished => {}
        solscope_engine::Stop::Cancelled => {
            ui.colored_label(
                m.theme.aborted,
                "Stopped early (cancelled): the best order found until then, confirmed on \
                 the held-out sample",
            );
        }
        solscope_engine::Stop::Budget => {
            ui.colored_label(
                m.theme.aborted,
                "Stopped early (the budget ran out): the best order found within it; a \
                 larger budget may find a better one",
            );
        }
    }
    let held = t.held_out.runs;
    let score = |s| solscope_engine::score_line(s, held);
    ui.label(format!("Held-out, {held} runs (seed {}):", t.held_out.seed));
    egui::Grid::new("tune_objective")
        .num_columns(2)
        .show(ui, |ui| {
            ui.label("original");
            ui.label(score(&t.held_out_scores.original));
            ui.end_row();
            ui.label("tuned");
            ui.label(score(&t.held_out_scores.tuned));
            ui.end_row();
        });
    if let Some(line) = solscope_engine::first_difference_line(&m.doc.plan, t) {
        ui.label(line);
    }
    if t.changes.is_empty() {
        ui.label("The original order is the best found: no priority changes.");
    } else if t.held_out_no_worse() {
        ui.colored_label(
            m.theme.scheduled,
            "The tuned order is no worse than the original on the held-out sample.",
        );
    } else {
        ui.colored_label(
            m.theme.error,
            "The tuned order is worse than the original on the held-out sample: it fits \
             the tuning sample only (more runs may help).",
        );
    }
    ui.horizontal(|ui| {
        let apply = UiCommand::ApplyTuning;
        if ui
            .add_enabled(!t.changes.is_empty(), egui::Button::new(apply.label()))
            .on_hover_text("One edit of the priorities only: Undo restores every one")
            .clicked()
        {
            cmds.push(apply.into());
        }
        let overlay = UiCommand::ToggleTuneOverlay;
        let mut shown = m.tune.overlay;
        if ui
            .checkbox(&mut shown, overlay.label())
            .on_hover_text(
                "Each lane also shows where the tuned plan's predicted schedule places its \
                 activities (a thin bar under the original's; a cross where the tuned plan \
                 leaves one out)",
            )
            .changed()
        {
            cmds.push(overlay.into());
        }
        command_button(ui, UiCommand::DismissTuning, true, cmds);
    });
}
