//! The eframe host around [`SolscopeApp`]: persistence, the window close guard,
//! the file dialogs the app asks for, PNG export, and [`run`].

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{self, Receiver, Sender};

use eframe::egui;

use super::app::SolscopeApp;
use crate::state::{Command, Dialog, Persisted, UiCommand};

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
            app.restore_persisted(p);
        }
        // On a workstation, verifying suggestions must not stall a click.
        app.background = true;
        Self {
            app,
            png_errors: mpsc::channel(),
        }
    }

    /// Shows the file dialog the app asked for and carries out its choice; with
    /// no file dialog service, the app asks for a typed path instead.
    fn show_dialog(&mut self, dialog: Dialog) {
        if let Some(why) = no_dialog_service() {
            self.app.apply(Command::AskPath { dialog, why });
            return;
        }
        let suggested = self.app.suggested_path(dialog);
        let mut fd = rfd::FileDialog::new().add_filter(filter_name(dialog), &[dialog.extension()]);
        let (dir, name) = dialog_start(dialog, &suggested, has_session_bus());
        if let Some(dir) = dir {
            fd = fd.set_directory(dir);
        }
        if let Some(name) = name {
            fd = fd.set_file_name(name);
        }
        let asked = std::time::Instant::now();
        let chosen = if dialog.saves() {
            fd.save_file()
        } else {
            fd.pick_file()
        };
        match chosen {
            Some(path) => self.app.apply(Command::Chosen { dialog, path }),
            // Nobody closes a dialog that fast: none was shown (the portal and
            // zenity both failed).
            None if asked.elapsed() < DIALOG_FAILED_WITHIN => self.app.apply(Command::AskPath {
                dialog,
                why: "The file dialog closed at once: no desktop file dialog answered \
                      (xdg-desktop-portal or zenity)."
                    .into(),
            }),
            None => self.app.apply(Command::DialogCancelled),
        }
    }

    /// Renders the next frame into `path` as PNG; a failure is shown by the app.
    fn export_png(&self, ctx: &egui::Context, path: PathBuf) {
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

/// Where the file dialog for `dialog` starts, given the suggested path (an
/// absolute one: `AppState::suggested_path`): the folder and file name
/// to give rfd. The desktop portal (`portal`: a D-Bus session bus is there)
/// takes the folder and the name apart; zenity, rfd's other way, takes no
/// folder, so the whole path goes in its file name (a folder ending in `/`
/// for the open dialogs).
pub fn dialog_start(
    dialog: Dialog,
    suggested: &Path,
    portal: bool,
) -> (Option<PathBuf>, Option<String>) {
    let (dir, name) = if dialog.saves() {
        (
            suggested.parent().map(Path::to_path_buf),
            suggested
                .file_name()
                .map(|n| n.to_string_lossy().into_owned()),
        )
    } else {
        (Some(suggested.to_path_buf()), None)
    };
    if portal {
        return (dir, name);
    }
    let whole = match (dir, name) {
        (Some(d), Some(n)) => d.join(n).to_string_lossy().into_owned(),
        (Some(d), None) => {
            let d = d.to_string_lossy().into_owned();
            if d.ends_with('/') { d } else { format!("{d}/") }
        }
        (None, n) => n.unwrap_or_default(),
    };
    (None, Some(whole))
}

/// Whether a D-Bus session bus is there for the desktop portal.
fn has_session_bus() -> bool {
    std::env::var_os("DBUS_SESSION_BUS_ADDRESS").is_some_and(|a| !a.is_empty())
        || std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| Path::new(&d).join("bus").exists())
}

/// A file dialog that returns with nothing sooner than this was never shown.
const DIALOG_FAILED_WITHIN: std::time::Duration = std::time::Duration::from_millis(300);

/// The file type filter's name in the dialog.
fn filter_name(dialog: Dialog) -> &'static str {
    match dialog {
        Dialog::Open | Dialog::SaveAs => "solscope plan",
        Dialog::OpenActuals => "solscope actuals",
        Dialog::ExportSchedule => "schedule JSON",
        Dialog::ExportScheduleCsv => "schedule CSV",
        Dialog::ExportPng => "PNG",
    }
}

/// Why no file dialog can be shown, if none can: rfd asks the desktop portal
/// over the D-Bus session bus, then zenity; with neither a session bus nor
/// zenity on the `PATH` nothing answers.
fn no_dialog_service() -> Option<String> {
    no_dialog_service_in(
        std::env::var_os("PATH"),
        std::env::var_os("DBUS_SESSION_BUS_ADDRESS"),
        std::env::var_os("XDG_RUNTIME_DIR"),
    )
}

/// [`no_dialog_service`] for these values of `PATH`,
/// `DBUS_SESSION_BUS_ADDRESS` and `XDG_RUNTIME_DIR`.
fn no_dialog_service_in(
    path: Option<OsString>,
    bus: Option<OsString>,
    runtime: Option<OsString>,
) -> Option<String> {
    let zenity =
        path.is_some_and(|p| std::env::split_paths(&p).any(|d| d.join("zenity").is_file()));
    let bus = bus.is_some_and(|a| !a.is_empty())
        || runtime.is_some_and(|d| Path::new(&d).join("bus").exists());
    (!zenity && !bus).then(|| {
        "No file dialog is available here (no D-Bus session bus for the desktop portal, \
         and no zenity)."
            .into()
    })
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
            self.show_dialog(dialog);
        }
        if let Some(path) = self.app.take_png_request() {
            self.export_png(ui.ctx(), path);
        }
        if self.app.quit_confirmed() {
            ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
        }
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        eframe::set_value(storage, eframe::APP_KEY, &self.app.persisted);
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
    super::screenshot::write_png(&buf, path)
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
    fn no_session_bus_and_no_zenity_means_no_file_dialog() {
        let dir = std::env::temp_dir().join(format!("solscope-zenity-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let empty = Some(dir.clone().into_os_string());
        let why = no_dialog_service_in(empty.clone(), None, None).expect("no service");
        assert!(why.contains("zenity"), "{why}");
        // An empty bus address is no bus; a runtime directory without a bus
        // socket neither.
        assert!(no_dialog_service_in(empty.clone(), Some("".into()), empty.clone()).is_some());
        assert!(no_dialog_service_in(empty.clone(), Some("unix:path=/x".into()), None).is_none());
        std::fs::write(dir.join("bus"), "").expect("bus");
        assert!(no_dialog_service_in(None, None, empty.clone()).is_none());
        std::fs::remove_file(dir.join("bus")).expect("clean up");
        std::fs::write(dir.join("zenity"), "").expect("zenity");
        assert!(no_dialog_service_in(empty, None, None).is_none());
        std::fs::remove_dir_all(&dir).expect("clean up");
    }

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
