//! Headless rendering of the real UI to PNG (egui_kittest with wgpu; on a machine
//! without a GPU, Mesa's lavapipe or llvmpipe renders it in software).

use std::path::Path;

use eframe::egui;
use egui_kittest::Harness;

use crate::gui::{Command, SolscopeApp};

/// What to show before rendering.
#[derive(Clone, Debug, Default)]
pub struct View {
    /// Step to show (default: the last).
    pub step: Option<usize>,
    /// Activity id to select.
    pub select: Option<String>,
    /// Time to probe on the plots.
    pub probe: Option<i64>,
}

/// A kittest harness driving the app at `size` (points), in the view asked for.
pub fn harness(
    mut app: SolscopeApp,
    size: egui::Vec2,
    view: &View,
) -> Result<Harness<'static, SolscopeApp>, String> {
    if let Some(k) = view.step {
        app.apply(Command::SetStep(k));
    }
    if let Some(id) = &view.select {
        let a = app
            .doc
            .plan
            .activities
            .iter()
            .position(|x| &x.id == id)
            .ok_or_else(|| format!("no activity with id `{id}`"))?;
        app.apply(Command::Select(Some(a)));
    }
    if let Some(t) = view.probe {
        app.apply(Command::ProbePlot(Some(t)));
    }
    let mut harness = Harness::builder()
        .with_size(size)
        .with_pixels_per_point(1.0)
        .with_max_steps(16)
        .build_ui_state(|ui, app: &mut SolscopeApp| app.frame_ui(ui), app);
    harness.run_steps(4);
    Ok(harness)
}

/// Renders the app to a PNG file.
pub fn render_png(
    app: SolscopeApp,
    size: egui::Vec2,
    view: &View,
    out: &Path,
) -> Result<(), String> {
    let mut harness = harness(app, size, view)?;
    let image = harness.render()?;
    image
        .save(out)
        .map_err(|e| format!("{}: {e}", out.display()))
}

/// The one place that builds snapshot options for the regression tests: reference
/// PNGs live in `screenshots/`, compared with a small threshold.
pub fn snapshot_options() -> egui_kittest::SnapshotOptions {
    egui_kittest::SnapshotOptions::new()
        .output_path(concat!(env!("CARGO_MANIFEST_DIR"), "/screenshots"))
        .threshold(1.0)
        .max_failed_pixels(100)
}

/// Size of the screenshot views (points).
pub const SNAPSHOT_SIZE: [f32; 2] = [1400.0, 900.0];
