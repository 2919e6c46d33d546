//! Open, save and export, the file dialogs and the typed-path prompt, the
//! unsaved-changes question, and the repair view of a plan file that did not
//! load.

use std::path::{Path, PathBuf};

use super::super::repair::{self, Repair};
use super::super::{AppState, Command, Dialog, PathPrompt, Pending, UiCommand, tour};

impl AppState {
    /// The file commands given by name: a dialog asked of the host, a save, or
    /// quitting (each guarded when there are unsaved changes).
    pub(super) fn run_file(&mut self, cmd: UiCommand) {
        match cmd {
            UiCommand::Open => self.dialog = Some(Dialog::Open),
            UiCommand::Save => match self.doc.path.clone() {
                Some(p) => self.save_to(&p),
                None => self.dialog = Some(Dialog::SaveAs),
            },
            UiCommand::SaveAs => self.dialog = Some(Dialog::SaveAs),
            UiCommand::ExportSchedule => self.dialog = Some(Dialog::ExportSchedule),
            UiCommand::ExportScheduleCsv => self.dialog = Some(Dialog::ExportScheduleCsv),
            UiCommand::ExportPng => self.dialog = Some(Dialog::ExportPng),
            UiCommand::OpenActuals => self.dialog = Some(Dialog::OpenActuals),
            UiCommand::CancelOpen => self.cancel_opening(),
            UiCommand::Quit => {
                if self.doc.dirty {
                    self.ui.messages.confirm = Some(Pending::Quit);
                } else {
                    self.quit_now = true;
                }
            }
            // Given by `run` for the file commands only.
            _ => {}
        }
    }

    /// Opens a plan file (guarded when there are unsaved changes).
    pub(super) fn open(&mut self, path: PathBuf) {
        if self.doc.dirty {
            self.ui.messages.confirm = Some(Pending::Open(path));
        } else {
            self.open_now(&path);
        }
    }

    /// No file dialog could be shown for `dialog`: asks for a typed path,
    /// proposing one.
    pub(super) fn ask_path(&mut self, dialog: Dialog, why: String) {
        self.ui.text.path_text = self.suggested_path(dialog).display().to_string();
        self.ui.messages.path_prompt = Some(PathPrompt { dialog, why });
    }

    /// "Save and open" / "Save and quit": saves (asking where when the plan
    /// has no file), then goes on with what waited.
    pub(super) fn save_and_continue(&mut self) {
        let pending = self.ui.messages.confirm.take();
        match self.doc.path.clone() {
            Some(p) => {
                self.save_to(&p);
                if !self.doc.dirty {
                    self.go_on(pending);
                }
            }
            None => {
                self.ui.messages.after_save = pending;
                self.dialog = Some(Dialog::SaveAs);
            }
        }
    }

    /// Carries out what waited for the unsaved-changes question.
    pub(super) fn go_on(&mut self, pending: Option<Pending>) {
        match pending {
            Some(Pending::Open(p)) => self.open_now(&p),
            Some(Pending::OpenTutorial) => self.open_tutorial(),
            Some(Pending::Quit) => self.quit_now = true,
            None => {}
        }
    }

    /// Opens, saves or exports at `path`, chosen for `dialog`.
    pub(super) fn chosen(&mut self, dialog: Dialog, path: PathBuf) {
        self.ui.messages.path_prompt = None;
        let path = if dialog.saves() && path.extension().is_none() {
            path.with_extension(dialog.extension())
        } else {
            path
        };
        match dialog {
            Dialog::Open => self.apply(Command::Open(path)),
            Dialog::OpenActuals => self.apply(Command::OpenActuals(path)),
            Dialog::SaveAs => {
                self.save_to(&path);
                let after = self.ui.messages.after_save.take();
                if !self.doc.dirty {
                    self.go_on(after);
                }
            }
            Dialog::ExportSchedule => self.export_schedule_to(&path),
            Dialog::ExportScheduleCsv => self.export_csv_to(&path),
            Dialog::ExportPng => self.png_to = Some(path),
        }
    }

    /// Where a file chosen for `dialog` is proposed: beside the plan (or in the
    /// working directory), named after it (`plan.json`, `plan-schedule.csv`,
    /// `plan.png`); a directory for the dialogs that open a file.
    pub fn suggested_path(&self, dialog: Dialog) -> PathBuf {
        let dir = self
            .doc
            .path
            .as_deref()
            .and_then(Path::parent)
            .map(Path::to_path_buf)
            .unwrap_or_default();
        // The plan's folder as a whole path (a plan opened by a relative one,
        // `solscope plan.json`, has an empty parent): the file dialogs take
        // no relative folder.
        let dir = std::path::absolute(&dir)
            .or_else(|_| std::env::current_dir())
            .unwrap_or(dir);
        let stem = self.doc.file_stem();
        let name = match dialog {
            Dialog::Open | Dialog::OpenActuals => return dir.join(""),
            Dialog::SaveAs => format!("{stem}.json"),
            Dialog::ExportSchedule => format!("{stem}-schedule.json"),
            Dialog::ExportScheduleCsv => format!("{stem}-schedule.csv"),
            Dialog::ExportPng => format!("{stem}.png"),
        };
        dir.join(name)
    }

    /// Opens `path` now: as the plan when it loads (the tour offered with the
    /// tutorial plan), else in the repair view, or its error shown. With
    /// `background` (the desktop app) on a worker, the plan open staying
    /// until it is in.
    pub(in crate::state) fn open_now(&mut self, path: &Path) {
        if self.background {
            self.open_on_worker(path);
            return;
        }
        let text = match solscope_engine::read_plan_text(path, solscope_engine::MAX_PLAN_BYTES) {
            Ok(t) => t,
            Err(e) => {
                self.ui.messages.error = Some(format!("Could not open {}: {e}", path.display()));
                return;
            }
        };
        let state = Self::from_text(&text, Some(path.to_path_buf()));
        self.opened(path, text, state);
    }

    /// Takes the plan read from `path` (its `text`, and the app on it or why
    /// it did not load): as the plan (the tour offered with the tutorial
    /// plan), else in the repair view, or its error shown.
    pub(in crate::state) fn opened(
        &mut self,
        path: &Path,
        text: String,
        state: Result<Self, solscope_engine::Error>,
    ) {
        match state {
            Ok(fresh) => {
                self.become_(fresh);
                // The guided tour opens with the tutorial plan.
                self.offer_tour = tour::is_tutorial(&self.doc.plan);
            }
            Err(e) => {
                // Keep the current plan; repair the file's text in the repair
                // view (every error listed), or say what is wrong when there
                // is nothing to repair in it.
                let repair = Repair::new(Some(path.to_path_buf()), &text);
                if repair.errors.is_empty() {
                    self.ui.messages.error =
                        Some(format!("Could not open {}: {e}", path.display()));
                    return;
                }
                self.ui.messages.repair = Some(repair);
                self.ui.messages.error = None;
                self.ui.text.repair_text = text;
                self.repair_jump(0);
            }
        }
    }

    /// Takes `fresh` (a plan just opened) as the app, keeping the settings,
    /// the mode and how derived values are computed; its file goes first in
    /// Recent.
    pub(super) fn become_(&mut self, mut fresh: Self) {
        fresh.persisted = std::mem::take(&mut self.persisted);
        fresh.background = self.background;
        // The mode stays; the actuals were for the other plan.
        fresh.ui.nav.mode = self.ui.nav.mode;
        if let Some(p) = fresh.doc.path.clone() {
            fresh.persisted.remember(&p);
        }
        *self = fresh;
    }

    /// Repair view: puts the value typed for the error looked at in place of
    /// the text at its path, then checks again.
    pub(super) fn replace_at_error(&mut self) {
        let text = &mut self.ui.text.repair_text;
        let at = self
            .ui
            .messages
            .repair
            .as_ref()
            .and_then(|r| r.errors.get(r.selected?))
            .and_then(|e| repair::locate(text, &e.path));
        if let Some(span) = at {
            let before = text.clone();
            text.replace_range(span, &self.ui.text.repair_value);
            if let Some(r) = self.ui.messages.repair.as_mut() {
                r.undo.push(before);
            }
        }
        self.recheck_repair();
    }

    /// Repair view: puts `id` (as a JSON string) in place of the value at the
    /// error looked at, as if typed there, and checks again.
    pub(super) fn repair_pick_id(&mut self, id: &str) {
        self.ui.text.repair_value = serde_json::Value::from(id).to_string();
        self.replace_at_error();
    }

    /// Repair view: the plan text as it was before the last replacement,
    /// checked again.
    pub(super) fn undo_repair(&mut self) {
        let Some(before) = self.ui.messages.repair.as_mut().and_then(|r| r.undo.pop()) else {
            return;
        };
        self.ui.text.repair_text = before;
        self.recheck_repair();
    }

    /// Repair view: leaves it; the plan open before stays.
    pub(super) fn cancel_repair(&mut self) {
        self.ui.messages.repair = None;
        self.ui.text.repair_text.clear();
        self.ui.text.repair_value.clear();
        self.ui.text.repair_cursor = None;
    }

    /// Repair view: checks the text again; with no error left it opens as the
    /// plan (unsaved: its file still holds the broken text), else the first
    /// error is looked at.
    pub(super) fn recheck_repair(&mut self) {
        let Some(repair) = self.ui.messages.repair.as_mut() else {
            return;
        };
        repair.errors = repair::check(&self.ui.text.repair_text);
        repair.ids = repair::activity_ids(&self.ui.text.repair_text);
        repair.checks += 1;
        repair.selected = None;
        if !repair.errors.is_empty() {
            self.repair_jump(0);
            return;
        }
        let path = repair.path.clone();
        match Self::from_text(&self.ui.text.repair_text, path) {
            Ok(mut fresh) => {
                fresh.doc.mark_unsaved();
                self.become_(fresh);
            }
            // It validates, yet does not schedule: said in the repair view.
            Err(e) => {
                if let Some(repair) = self.ui.messages.repair.as_mut() {
                    repair.errors = vec![repair::PlanError {
                        path: "$".into(),
                        reason: e.to_string(),
                    }];
                }
            }
        }
    }

    /// Repair view: looks at error `i`, its value put in the value field and
    /// selected in the text.
    pub(super) fn repair_jump(&mut self, i: usize) {
        let Some(repair) = self.ui.messages.repair.as_mut() else {
            return;
        };
        let Some(err) = repair.errors.get(i) else {
            return;
        };
        repair.selected = Some(i);
        let text = &self.ui.text.repair_text;
        let span = repair::locate(text, &err.path);
        self.ui.text.repair_value = span
            .as_ref()
            .and_then(|s| text.get(s.clone()))
            .unwrap_or("")
            .to_string();
        self.ui.text.repair_cursor = span.map(|s| repair::char_range(text, &s));
    }

    /// Saves the plan to `path` (it is then the plan's file, first in
    /// Recent); a failed write is shown and the plan stays unsaved.
    pub(super) fn save_to(&mut self, path: &Path) {
        match write_json(&self.doc.plan, path) {
            Ok(()) => {
                self.doc.mark_saved(path.to_path_buf());
                self.persisted.remember(path);
            }
            Err(e) => {
                self.ui.messages.error = Some(format!("Could not save {}: {e}", path.display()))
            }
        }
    }

    /// Writes the schedule JSON to `path`; a failed write is shown.
    pub(super) fn export_schedule_to(&mut self, path: &Path) {
        let loaded = solscope_engine::LoadedPlan {
            plan: self.doc.plan.clone(),
            warnings: self.doc.warnings.clone(),
        };
        let doc =
            solscope_engine::schedule_document(&loaded, &self.analysis.schedule, &self.doc.title());
        if let Err(e) = write_json(&doc, path) {
            self.ui.messages.error = Some(format!("Could not write {}: {e}", path.display()));
        }
    }

    /// Writes the schedule CSV to `path`; a failed write is shown.
    fn export_csv_to(&mut self, path: &Path) {
        let csv = solscope_engine::schedule_csv(&self.doc.plan, &self.analysis.schedule);
        if let Err(e) = crate::write::write_whole(path, csv.as_bytes()) {
            self.ui.messages.error = Some(format!("Could not write {}: {e}", path.display()));
        }
    }
}

/// Writes `value` as pretty JSON (with a final newline) to `path`. Nothing is
/// written when it cannot be serialised.
pub(in crate::state) fn write_json<T: serde::Serialize>(
    value: &T,
    path: &Path,
) -> Result<(), String> {
    let text =
        serde_json::to_string_pretty(value).map_err(|e| format!("cannot serialise it: {e}"))?;
    crate::write::write_whole(path, (text + "\n").as_bytes()).map_err(|e| e.to_string())
}
