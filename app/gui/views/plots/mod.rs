//! State of charge, peak power and data volume as of the current step, on the
//! shared time axis; clicking a plot lists the consumers at that time. In
//! execution mode: the executed profiles over the first cycle's prediction and
//! the looked-at cycle's run as of the step shown, with the broken limits, and
//! the executed and predicted values at the time clicked.
//!
//! `plot` draws one plot, `would_cause` what a failed activity would have
//! caused over it, `execution` the plots of execution mode.

mod execution;
mod plot;
#[cfg(test)]
mod tests;
mod would_cause;

use eframe::egui::{self, RichText};
use solscope_engine::{Consumer, energy_consumers, format_watts, format_wh, peak_users};

use crate::gui::theme::WOULD_CAUSE_STROKE;
use crate::gui::views::{Model, ViewCache};
use crate::state::Command;
use crate::state::{Mode, OverlayPlot};
use plot::{Chart, DATA, PEAK, SOC, Series, limits, plot_ui};
use would_cause::{would_cause_label, would_cause_name};

/// The three plots and the consumers at the probed time.
pub fn plots_ui<'a>(
    ui: &mut egui::Ui,
    m: &'a Model<'_>,
    cache: &mut ViewCache,
    cmds: &mut Vec<Command>,
) {
    if m.nav.mode == Mode::Execution {
        if let Some(run) = m.exec.ready() {
            execution::execution_plots_ui(ui, m, run, cache, cmds);
        }
        return;
    }
    let sv = m.step_view;
    let [soc_limits, peak_limits, data_limits] = limits(m);
    let one = |name: &str, points| Series {
        name: name.into(),
        points,
        color: m.theme.scheduled,
        dashed: false,
        width: None,
    };
    // What the selected failed activity would have caused: the shown
    // reason's profile dashed on its plot, every reason's violation marked.
    let overlay = |plot: OverlayPlot| m.would_cause.map(|w| (w, plot));
    let with_overlay = |base: Series<'a>, plot: OverlayPlot| -> Vec<Series<'a>> {
        let mut series = vec![base];
        if let Some((w, r)) = m
            .would_cause
            .and_then(|w| w.shown().map(|r| (w, r)))
            .filter(|(_, r)| r.plot == plot)
        {
            series.push(Series {
                name: would_cause_name(m, w, r),
                points: &w.points,
                color: m.theme.would_cause,
                dashed: true,
                width: Some(WOULD_CAUSE_STROKE),
            });
        }
        series
    };
    ui.label(RichText::new(format!("State of charge (Wh) after step {}", sv.step)).strong());
    would_cause_label(ui, m, m.would_cause, OverlayPlot::Soc, cmds);
    let soc = Chart {
        id: SOC,
        series: with_overlay(one(SOC, &sv.soc), OverlayPlot::Soc),
        limits: soc_limits,
        marks: Vec::new(),
        overlay: overlay(OverlayPlot::Soc),
    };
    plot_ui(ui, m, cache, &soc, cmds);
    ui.label(RichText::new(PEAK).strong());
    would_cause_label(ui, m, m.would_cause, OverlayPlot::Peak, cmds);
    let peak = Chart {
        id: PEAK,
        series: with_overlay(one(PEAK, &sv.peak), OverlayPlot::Peak),
        limits: peak_limits,
        marks: Vec::new(),
        overlay: overlay(OverlayPlot::Peak),
    };
    plot_ui(ui, m, cache, &peak, cmds);
    ui.label(RichText::new(DATA).strong());
    let data = Chart {
        id: DATA,
        series: vec![one(DATA, &sv.data)],
        limits: data_limits,
        marks: Vec::new(),
        overlay: None,
    };
    plot_ui(ui, m, cache, &data, cmds);
    match m.nav.probe {
        Some(t) => consumers_ui(ui, m, t, cmds),
        None => {
            ui.label("Click a plot to list the energy and peak-power users at that time.");
        }
    }
}

/// The energy and peak-power users at the probed time `t` (energy since the
/// battery was last full, when asked).
fn consumers_ui(ui: &mut egui::Ui, m: &Model<'_>, t: i64, cmds: &mut Vec<Command>) {
    let sv = m.step_view;
    ui.horizontal(|ui| {
        ui.label(RichText::new(format!("At {}", m.time(t))).strong());
        let mut since = m.nav.since_full;
        if ui.checkbox(&mut since, "since last full battery").changed() {
            cmds.push(Command::SetSinceFull(since));
        }
        if ui.button("Clear probe").clicked() {
            cmds.push(Command::ProbePlot(None));
        }
    });
    let (from, energy) = energy_consumers(&m.analysis.schedule, sv.step, t, m.nav.since_full);
    let peak = peak_users(&m.analysis.schedule, sv.step, t);
    let energy = merge_by_who(m, &energy);
    let peak = merge_by_who(m, &peak);
    ui.columns(2, |cols| {
        cols[0].label(
            RichText::new(format!("Energy used {} to {}", m.time(from), m.time(t))).strong(),
        );
        egui::Grid::new("energy_users")
            .num_columns(2)
            .striped(true)
            .show(&mut cols[0], |ui| {
                for (who, amount) in energy.iter().take(12) {
                    ui.label(format_wh(i128::from(*amount)));
                    ui.label(who);
                    ui.end_row();
                }
            });
        if energy.len() > 12 {
            cols[0].label(format!("and {} more", energy.len() - 12));
        }
        cols[1].label(RichText::new("Peak-power users").strong());
        egui::Grid::new("peak_users")
            .num_columns(2)
            .striped(true)
            .show(&mut cols[1], |ui| {
                for (who, amount) in peak.iter().take(12) {
                    ui.label(format_watts(*amount));
                    ui.label(who);
                    ui.end_row();
                }
            });
    });
}

/// Sums consumers that read the same (e.g. several awake periods), ranked.
fn merge_by_who(m: &Model<'_>, list: &[Consumer]) -> Vec<(String, i64)> {
    let mut out: Vec<(String, i64)> = Vec::new();
    for c in list {
        let who = match (c.activity, c.kind) {
            (Some(a), "activity") => m.doc.plan.activities[a].id.clone(),
            (Some(a), kind) => format!("{kind} for {}", m.doc.plan.activities[a].id),
            (None, _) => "rover awake (above asleep draw)".to_string(),
        };
        match out.iter_mut().find(|x| x.0 == who) {
            Some(x) => x.1 = x.1.saturating_add(c.amount),
            None => out.push((who, c.amount)),
        }
    }
    out.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    out
}
