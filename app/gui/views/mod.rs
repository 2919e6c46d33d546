//! The views. Each `*_ui` function reads the [`Model`] and pushes commands; the
//! only state written while drawing is widget state ([`Widgets`]: text buffers and
//! what the views keep between frames).
//!
//! The views see the app only through this interface: they import the state's
//! types (`crate::state`, read-only through the model) and the gui's `theme`,
//! `time_axis`, `shortcuts` and `help`, never the frame or the host.

mod axis;
mod controls;
mod dialogs;
mod editor;
mod execution;
mod flex;
mod gantt;
mod inspector;
mod list;
mod model;
mod montecarlo;
mod opening;
mod plots;
mod repair;
mod steps;
mod text;
mod toolbar;
mod tour;
mod tune;
mod widgets;

pub use model::{Look, Model, ViewCache, Widgets};
pub use tour::TourAnchors;

use eframe::egui;

use crate::gui::theme::{
    CENTRAL_MIN_WIDTH, INSPECTOR_MIN_WIDTH, INSPECTOR_WIDTH, LIST_MIN_WIDTH, LIST_WIDTH,
};
use crate::state::{Command, Mode};

// What the views below share: the state's types they read, and the controls
// and the step slider that several of them draw.
#[cfg(test)]
use crate::state::ExecModel;
use crate::state::{CampaignModel, Status, failed_steps};
use controls::{command_button, shortcut_button};
use steps::step_row_ui;

/// Files dropped on the window are opened (guarded by the unsaved-changes check).
pub fn dropped_files(ui: &mut egui::Ui, cmds: &mut Vec<Command>) {
    let dropped: Vec<egui::DroppedFileHandle> = ui.input(|i| i.raw.dropped_files.clone());
    for f in dropped {
        cmds.push(Command::Open(f.path().to_path_buf()));
    }
}

/// The whole window.
pub fn layout_ui(ui: &mut egui::Ui, m: &Model<'_>, w: &mut Widgets<'_>, cmds: &mut Vec<Command>) {
    if let Some(r) = &m.messages.repair {
        // A plan file that did not load: repaired in its own view.
        repair::repair_ui(ui, m, r, w.text, cmds);
        return;
    }
    w.cache.tour_anchors = TourAnchors::default();
    let top = egui::Panel::top("toolbar").show(ui, |ui| {
        toolbar::toolbar_ui(ui, m, cmds);
        match m.nav.mode {
            Mode::Schedule => steps::steps_ui(ui, m, cmds),
            Mode::Execution => {
                execution::actuals_ui(ui, m, &mut w.text.seed_text, cmds);
                execution::cycles_ui(ui, m, cmds);
                execution::cycle_steps_ui(ui, m, cmds);
            }
        }
        opening::opening_ui(ui, m, cmds);
    });
    w.cache.tour_anchors.top = Some(top.response.rect);
    // The side panels are dragged to any width that leaves the Gantt and
    // plots theirs; what they hold scrolls inside them (a wide line never
    // widens a panel over its neighbour).
    let total = ui.available_width();
    let list_width = m.persisted.list_width.unwrap_or(LIST_WIDTH);
    let inspector_width = m.persisted.inspector_width.unwrap_or(INSPECTOR_WIDTH);
    let widest = |other: f32, min: f32| (total - other - CENTRAL_MIN_WIDTH).max(min);
    let list = egui::Panel::left("activities")
        .resizable(true)
        .default_size(list_width)
        .size_range(LIST_MIN_WIDTH..=widest(inspector_width, LIST_MIN_WIDTH))
        .show(ui, |ui| {
            list::activities_ui(ui, m, w, cmds);
        });
    w.cache.tour_anchors.list = Some(list.response.rect);
    let anchors = &mut w.cache.tour_anchors;
    let inspector = egui::Panel::right("inspector")
        .resizable(true)
        .default_size(inspector_width)
        .size_range(INSPECTOR_MIN_WIDTH..=widest(list.response.rect.width(), INSPECTOR_MIN_WIDTH))
        .show(ui, |ui| {
            egui::ScrollArea::both()
                .auto_shrink([false; 2])
                .show(ui, |ui| {
                    inspector::inspector_ui(ui, m, w.text, anchors, cmds);
                });
        });
    w.cache.tour_anchors.inspector = Some(inspector.response.rect);
    let widths = [list.response.rect.width(), inspector.response.rect.width()];
    if (list_width - widths[0]).abs() >= 1.0 || (inspector_width - widths[1]).abs() >= 1.0 {
        cmds.push(Command::SetPanelWidths(widths));
    }
    if m.nav.mode == Mode::Execution {
        // Under the Gantt and plots, between the side panels.
        egui::Panel::bottom("monte_carlo")
            .resizable(false)
            .show(ui, |ui| {
                montecarlo::campaign_panel_ui(ui, m, w.text, cmds);
            });
    }
    if m.tune.open {
        // Under the Gantt and plots (above the Monte Carlo panel).
        egui::Panel::bottom("tune")
            .resizable(true)
            .default_size(tune::PANEL_HEIGHT)
            .show(ui, |ui| {
                egui::ScrollArea::vertical()
                    .auto_shrink([false; 2])
                    .show(ui, |ui| {
                        tune::tune_panel_ui(ui, m, &mut w.text.tune, cmds);
                    });
            });
    }
    let central = egui::CentralPanel::default().show(ui, |ui| {
        axis::axis_ui(ui, m, &mut w.text.range_text, cmds);
        gantt::ruler_ui(ui, m, w.cache);
        egui::ScrollArea::vertical()
            .auto_shrink([false; 2])
            .show(ui, |ui| {
                gantt::gantt_ui(ui, m, w.cache, cmds);
                plots::plots_ui(ui, m, w.cache, cmds);
            });
    });
    // Over the foot of the Gantt and plots: showing or dismissing it moves
    // nothing under it.
    dialogs::banner_ui(ui, m, central.response.rect, cmds);
    tour::tour_ui(ui, m, &w.cache.tour_anchors, cmds);
    dialogs::confirm_ui(ui, m, cmds);
    dialogs::pin_ui(ui, m, cmds);
    dialogs::path_prompt_ui(ui, m, &mut w.text.path_text, cmds);
}
