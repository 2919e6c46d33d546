//! Headless rendering of the real UI to PNG (egui_kittest with wgpu; on a machine
//! without a GPU, Mesa's lavapipe or llvmpipe renders it in software).

use std::path::Path;

use eframe::egui;
use egui_kittest::Harness;

use crate::gui::SolscopeApp;
use crate::state::Command;

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
    write_png(&image, out).map_err(|e| format!("{}: {e}", out.display()))
}

/// Writes an image as a PNG file, whole or not at all
/// ([`crate::write::write_whole`]).
pub fn write_png(image: &image::RgbaImage, out: &Path) -> Result<(), String> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    image
        .write_to(&mut bytes, image::ImageFormat::Png)
        .map_err(|e| format!("could not encode the image: {e}"))?;
    crate::write::write_whole(out, bytes.get_ref()).map_err(|e| format!("could not write: {e}"))
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

/// Without `XDG_RUNTIME_DIR`, the graphics stack probing for Wayland (Mesa,
/// libwayland) prints "XDG_RUNTIME_DIR is invalid or not set" twice on
/// standard error, though it renders. Run this same command again with a
/// private, empty runtime directory so it renders quietly: `Some(exit code)`
/// of that run. `None` when `XDG_RUNTIME_DIR` is set (render here), or when
/// the run could not be started (render here, as before, with those lines).
pub fn rerun_with_runtime_dir() -> Option<std::process::ExitCode> {
    use std::os::unix::fs::DirBuilderExt;
    if std::env::var_os("XDG_RUNTIME_DIR").is_some() {
        return None;
    }
    let exe = std::env::current_exe().ok()?;
    let dir = std::env::temp_dir().join(format!("solscope-runtime-{}", std::process::id()));
    std::fs::DirBuilder::new().mode(0o700).create(&dir).ok()?;
    let status = std::process::Command::new(exe)
        .args(std::env::args_os().skip(1))
        .env("XDG_RUNTIME_DIR", &dir)
        .status();
    if let Err(e) = std::fs::remove_dir_all(&dir) {
        eprintln!("warning: could not remove {}: {e}", dir.display());
    }
    match status {
        Ok(s) => Some(match s.code().and_then(|c| u8::try_from(c).ok()) {
            Some(c) => std::process::ExitCode::from(c),
            None => std::process::ExitCode::FAILURE,
        }),
        Err(_) => None,
    }
}
