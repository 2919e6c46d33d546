//! The eframe host around [`SolscopeApp`]: persistence, the window close guard,
//! the file dialogs the app asks for, PNG export, and [`run`].

use std::path::{Path, PathBuf};
use std::sync::mpsc::{self, Receiver, Sender};

use eframe::egui;

use super::app::{Dialog, SolscopeApp};
use super::commands::{Command, UiCommand};
use super::state::Persisted;

/// The eframe host: persistence, window close guard, file dialogs, PNG export.
#[derive(Debug)]
pub struct SolscopeHost {
    /// The app.
    pub app: SolscopeApp,
    /// Errors of PNG exports, reported by the screenshot callback (it runs after
    /// the frame) and shown by the app next frame.
    png_errors: (Sender<String>, Receiver<String>),
}

impl SolscopeHost {
    /// Wraps the app, restoring persisted settings.
    pub fn new(cc: &eframe::CreationContext<'_>, mut app: SolscopeApp) -> Self {
        if let Some(p) = cc
            .storage
            .and_then(|s| eframe::get_value::<Persisted>(s, eframe::APP_KEY))
        {
            app.persisted = p;
        }
        // On a workstation, verifying suggestions must not stall a click.
        app.background = true;
        Self {
            app,
            png_errors: mpsc::channel(),
        }
    }

    /// Shows the file dialog the app asked for and carries out its choice.
    fn show_dialog(&mut self, ctx: &egui::Context, dialog: Dialog) {
        match dialog {
            Dialog::Open => {
                if let Some(p) = plan_dialog().pick_file() {
                    self.app.apply(Command::Open(p));
                }
            }
            Dialog::OpenActuals => {
                if let Some(p) = rfd::FileDialog::new()
                    .add_filter("solscope actuals", &["json"])
                    .pick_file()
                {
                    self.app.apply(Command::OpenActuals(p));
                }
            }
            Dialog::SaveAs => {
                if let Some(p) = plan_dialog().save_file() {
                    self.app.apply(Command::SaveTo(with_extension(p, "json")));
                }
            }
            Dialog::ExportSchedule => {
                if let Some(p) = rfd::FileDialog::new()
                    .add_filter("schedule JSON", &["json"])
                    .save_file()
                {
                    self.app
                        .apply(Command::ExportScheduleTo(with_extension(p, "json")));
                }
            }
            Dialog::ExportPng => {
                if let Some(path) = rfd::FileDialog::new()
                    .add_filter("PNG", &["png"])
                    .save_file()
                    .map(|p| with_extension(p, "png"))
                {
                    let errors = self.png_errors.0.clone();
                    let repaint = ctx.clone();
                    ctx.request_screenshot(move |img: std::sync::Arc<egui::ColorImage>| {
                        if let Err(e) = save_color_image(&img, &path) {
                            let msg = format!("Could not write {}: {e}", path.display());
                            // The host owns the receiver for as long as the app runs.
                            if errors.send(msg).is_ok() {
                                repaint.request_repaint();
                            }
                        }
                    });
                }
            }
        }
    }
}

impl eframe::App for SolscopeHost {
    fn logic(&mut self, ctx: &egui::Context, _frame: &mut eframe::Frame) {
        if ctx.input(|i| i.viewport().close_requested())
            && !self.app.quit_confirmed()
            && self.app.doc.dirty
        {
            ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
            // Asks "discard unsaved changes?" (the plan is dirty).
            self.app.apply(UiCommand::Quit.into());
        }
    }

    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        while let Ok(e) = self.png_errors.1.try_recv() {
            self.app.push(Command::ShowError(e));
        }
        self.app.frame_ui(ui);
        if let Some(dialog) = self.app.take_dialog() {
            self.show_dialog(ui.ctx(), dialog);
        }
        if self.app.quit_confirmed() {
            ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
        }
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        eframe::set_value(storage, eframe::APP_KEY, &self.app.persisted);
    }
}

/// A dialog for plan files.
fn plan_dialog() -> rfd::FileDialog {
    rfd::FileDialog::new().add_filter("solscope plan", &["json"])
}

fn with_extension(p: PathBuf, ext: &str) -> PathBuf {
    if p.extension().is_some() {
        p
    } else {
        p.with_extension(ext)
    }
}

/// Writes an egui image as PNG.
pub fn save_color_image(img: &egui::ColorImage, path: &Path) -> Result<(), String> {
    let [w, h] = img.size;
    let rgba: Vec<u8> = img
        .pixels
        .iter()
        .flat_map(|c| c.to_srgba_unmultiplied())
        .collect();
    let buf = image::RgbaImage::from_raw(w as u32, h as u32, rgba).ok_or("bad image size")?;
    buf.save(path).map_err(|e| e.to_string())
}

/// Runs the desktop app.
pub fn run(app: SolscopeApp) -> Result<(), String> {
    let title = format!("solscope — {}", app.doc.title());
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title(title)
            .with_inner_size([1400.0, 900.0])
            .with_min_inner_size([900.0, 600.0])
            .with_drag_and_drop(true),
        ..Default::default()
    };
    eframe::run_native(
        "solscope",
        options,
        Box::new(|cc| Ok(Box::new(SolscopeHost::new(cc, app)))),
    )
    .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_png_that_cannot_be_written_is_an_error() {
        let img = egui::ColorImage::new([2, 2], vec![egui::Color32::RED; 4]);
        let path = std::env::temp_dir()
            .join(format!("solscope-png-{}", std::process::id()))
            .join("missing")
            .join("view.png");
        assert!(save_color_image(&img, &path).is_err());
        assert!(!path.exists());
    }
}
