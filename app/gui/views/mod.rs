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

use crate::gui::theme::{INSPECTOR_WIDTH, LIST_WIDTH};
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
        dialogs::banner_ui(ui, m, cmds);
    });
    w.cache.tour_anchors.top = Some(top.response.rect);
    let list = egui::Panel::left("activities")
        .resizable(true)
        .default_size(LIST_WIDTH)
        .show(ui, |ui| {
            list::activities_ui(ui, m, w, cmds);
        });
    w.cache.tour_anchors.list = Some(list.response.rect);
    let anchors = &mut w.cache.tour_anchors;
    let inspector = egui::Panel::right("inspector")
        .resizable(false)
        .exact_size(INSPECTOR_WIDTH)
        .show(ui, |ui| {
            egui::ScrollArea::vertical()
                .auto_shrink([false; 2])
                .show(ui, |ui| {
                    inspector::inspector_ui(ui, m, w.text, anchors, cmds);
                });
        });
    w.cache.tour_anchors.inspector = Some(inspector.response.rect);
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
    egui::CentralPanel::default().show(ui, |ui| {
        axis::axis_ui(ui, m, &mut w.text.range_text, cmds);
        gantt::ruler_ui(ui, m, w.cache);
        egui::ScrollArea::vertical()
            .auto_shrink([false; 2])
            .show(ui, |ui| {
                gantt::gantt_ui(ui, m, w.cache, cmds);
                plots::plots_ui(ui, m, w.cache, cmds);
            });
    });
    tour::tour_ui(ui, m, &w.cache.tour_anchors, cmds);
    dialogs::confirm_ui(ui, m, cmds);
    dialogs::pin_ui(ui, m, cmds);
    dialogs::path_prompt_ui(ui, m, &mut w.text.path_text, cmds);
}
