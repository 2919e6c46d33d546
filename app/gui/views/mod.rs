//! The views. Each `*_ui` function reads the model and pushes commands; only
//! widget state in [`UiState`] is written while drawing.

mod gantt;
pub use gantt::GanttRows;
mod inspector;
mod plots;

use eframe::egui::{self, RichText};
use solscope_engine::{Outcome, Suggestion};

use super::{
    Analysis, Command, Derived, Document, Pending, Persisted, SolscopeApp, StepView, Theme,
    TimeAxis, UiState,
};
use crate::gui::theme::INSPECTOR_WIDTH;

/// Read-only view of the app for one frame.
pub struct Model<'a> {
    /// The open plan.
    pub doc: &'a Document,
    /// Its schedule and explanations.
    pub analysis: &'a Analysis,
    /// The palette.
    pub theme: Theme,
    /// Profiles as of the current step.
    pub step_view: &'a StepView,
    /// Persisted settings.
    pub persisted: &'a Persisted,
    /// Verified suggestions of the selected activity, when computed.
    pub suggestions: Option<&'a [Suggestion]>,
    /// Bumped on every accepted change of the plan.
    pub revision: u64,
    /// Explanation of the selected activity, when it did not schedule.
    pub explanation: Option<&'a solscope_engine::Explanation>,
    /// Valid intervals of the selected activity at its own step (full horizon).
    pub valid: Option<&'a [solscope_engine::CategoryIntervals]>,
}

/// Status of activity `a` as of step `k`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    /// Placed at `[start, end)` in a step <= k.
    Scheduled(i64, i64),
    /// Failed in a step <= k.
    Failed,
    /// Skipped in a step <= k.
    Skipped,
    /// Its step is after k.
    Pending,
}

impl Model<'_> {
    /// Status of activity `a` after step `k`.
    pub fn status(&self, a: usize, k: usize) -> Status {
        match self.analysis.step(a) {
            Some(st) if st.step <= k => match st.outcome {
                Outcome::Scheduled { start, end } => Status::Scheduled(start, end),
                Outcome::Failed(_) => Status::Failed,
                Outcome::Skipped { .. } => Status::Skipped,
            },
            _ => Status::Pending,
        }
    }

    /// The activity of step `k` (1-based).
    pub fn activity_of_step(&self, k: usize) -> Option<usize> {
        k.checked_sub(1)
            .and_then(|i| self.analysis.schedule.steps.get(i))
            .map(|s| s.activity)
    }

    /// `id — name` of activity `a`.
    pub fn label(&self, a: usize) -> String {
        let act = &self.doc.plan.activities[a];
        match &act.name {
            Some(n) => format!("{} — {n}", act.id),
            None => act.id.clone(),
        }
    }

    /// Plan time as `t (hh:mm:ss)`.
    pub fn time(&self, t: i64) -> String {
        format!("{t} ({})", self.doc.plan.local_time.format_hms(t))
    }
}

const UNDO: egui::KeyboardShortcut =
    egui::KeyboardShortcut::new(egui::Modifiers::COMMAND, egui::Key::Z);
const REDO: egui::KeyboardShortcut = egui::KeyboardShortcut::new(
    egui::Modifiers {
        shift: true,
        ..egui::Modifiers::COMMAND
    },
    egui::Key::Z,
);
const SAVE: egui::KeyboardShortcut =
    egui::KeyboardShortcut::new(egui::Modifiers::COMMAND, egui::Key::S);
const OPEN: egui::KeyboardShortcut =
    egui::KeyboardShortcut::new(egui::Modifiers::COMMAND, egui::Key::O);

/// Keyboard: undo/redo, save/open, and stepping (Left/Right, Home/End) when no
/// text field has focus.
pub fn shortcuts(ui: &mut egui::Ui, app: &SolscopeApp, cmds: &mut Vec<Command>) {
    if ui.input_mut(|i| i.consume_shortcut(&REDO)) {
        cmds.push(Command::Redo);
    } else if ui.input_mut(|i| i.consume_shortcut(&UNDO)) {
        cmds.push(Command::Undo);
    }
    if ui.input_mut(|i| i.consume_shortcut(&SAVE)) {
        cmds.push(Command::Save);
    }
    if ui.input_mut(|i| i.consume_shortcut(&OPEN)) {
        cmds.push(Command::OpenDialog);
    }
    if ui.ctx().egui_wants_keyboard_input() {
        return;
    }
    let (k, n) = (app.ui.step, app.analysis.steps());
    let (left, right, home, end) = ui.input(|i| {
        (
            i.key_pressed(egui::Key::ArrowLeft),
            i.key_pressed(egui::Key::ArrowRight),
            i.key_pressed(egui::Key::Home),
            i.key_pressed(egui::Key::End),
        )
    });
    if left && k > 0 {
        cmds.push(Command::SetStep(k - 1));
    }
    if right && k < n {
        cmds.push(Command::SetStep(k + 1));
    }
    if home {
        cmds.push(Command::SetStep(0));
    }
    if end {
        cmds.push(Command::SetStep(n));
    }
}

/// Files dropped on the window are opened (guarded by the unsaved-changes check).
pub fn dropped_files(ui: &mut egui::Ui, cmds: &mut Vec<Command>) {
    let dropped: Vec<egui::DroppedFileHandle> = ui.input(|i| i.raw.dropped_files.clone());
    for f in dropped {
        cmds.push(Command::Open(f.path().to_path_buf()));
    }
}

/// The whole window.
pub fn layout_ui(ui: &mut egui::Ui, app: &mut SolscopeApp, cmds: &mut Vec<Command>) {
    // Field by field (the UI state is borrowed mutably below): only what was
    // derived for the selected activity at this revision.
    let (selected, revision) = (app.ui.selected, app.revision);
    let m = Model {
        doc: &app.doc,
        analysis: &app.analysis,
        theme: app.theme,
        step_view: &app.step_view,
        persisted: &app.persisted,
        suggestions: selected
            .and_then(|a| Derived::get(&app.suggestions, a, revision))
            .map(Vec::as_slice),
        revision,
        explanation: selected
            .and_then(|a| Derived::get(&app.explanation, a, revision))
            .and_then(Option::as_ref),
        valid: selected
            .and_then(|a| Derived::get(&app.valid, a, revision))
            .map(Vec::as_slice),
    };
    let st = &mut app.ui;
    egui::Panel::top("toolbar").show(ui, |ui| {
        toolbar_ui(ui, &m, st, cmds);
        steps_ui(ui, &m, st, cmds);
        banner_ui(ui, &m, st, cmds);
    });
    egui::Panel::left("activities")
        .resizable(true)
        .default_size(230.0)
        .show(ui, |ui| {
            activities_ui(ui, &m, st, cmds);
        });
    egui::Panel::right("inspector")
        .resizable(false)
        .exact_size(INSPECTOR_WIDTH)
        .show(ui, |ui| {
            egui::ScrollArea::vertical()
                .auto_shrink([false; 2])
                .show(ui, |ui| {
                    inspector::inspector_ui(ui, &m, st, cmds);
                });
        });
    egui::CentralPanel::default().show(ui, |ui| {
        axis_ui(ui, &m, st, cmds);
        egui::ScrollArea::vertical()
            .auto_shrink([false; 2])
            .show(ui, |ui| {
                gantt::gantt_ui(ui, &m, st, cmds);
                plots::plots_ui(ui, &m, st, cmds);
            });
    });
    confirm_ui(ui, st, cmds);
}

/// File actions, undo/redo, theme, search.
fn toolbar_ui(ui: &mut egui::Ui, m: &Model<'_>, st: &mut UiState, cmds: &mut Vec<Command>) {
    ui.horizontal_wrapped(|ui| {
        ui.menu_button("File", |ui| {
            if ui.button("Open…").clicked() {
                cmds.push(Command::OpenDialog);
            }
            if ui.button("Save").clicked() {
                cmds.push(Command::Save);
            }
            if ui.button("Save as…").clicked() {
                cmds.push(Command::SaveAs(None));
            }
            if ui.button("Export schedule JSON…").clicked() {
                cmds.push(Command::ExportSchedule(None));
            }
            if ui.button("Export view as PNG…").clicked() {
                cmds.push(Command::ExportPng(None));
            }
            if !m.persisted.recent.is_empty() {
                ui.separator();
                ui.label("Recent");
                for p in &m.persisted.recent {
                    if ui.button(p.display().to_string()).clicked() {
                        cmds.push(Command::Open(p.clone()));
                    }
                }
            }
            ui.separator();
            if ui.button("Quit").clicked() {
                cmds.push(Command::Quit);
            }
        });
        if ui
            .add_enabled(m.doc.can_undo(), egui::Button::new("Undo"))
            .clicked()
        {
            cmds.push(Command::Undo);
        }
        if ui
            .add_enabled(m.doc.can_redo(), egui::Button::new("Redo"))
            .clicked()
        {
            cmds.push(Command::Redo);
        }
        let dark = !m.persisted.light;
        if ui
            .button(if dark { "Light theme" } else { "Dark theme" })
            .clicked()
        {
            cmds.push(Command::SetDark(!dark));
        }
        let mut by_resource = m.persisted.by_resource;
        if ui
            .checkbox(&mut by_resource, "Group by resource")
            .on_hover_text("Gantt: one row per unit resource instead of packed lanes")
            .changed()
        {
            cmds.push(Command::GroupByResource(by_resource));
        }
        ui.separator();
        let dirty = if m.doc.dirty { " (unsaved)" } else { "" };
        ui.label(RichText::new(format!("{}{dirty}", m.doc.title())).strong());
        let failed = m.analysis.failed();
        let n = m.doc.plan.activities.len();
        ui.label(format!("{} of {n} scheduled, {failed} not", n - failed));
        ui.separator();
        let label = ui.label("Search");
        let mut filter = st.filter.clone();
        if ui
            .add(egui::TextEdit::singleline(&mut filter).desired_width(140.0))
            .labelled_by(label.id)
            .changed()
        {
            st.filter = filter;
        }
    });
}

/// The step slider and its buttons.
fn steps_ui(ui: &mut egui::Ui, m: &Model<'_>, st: &mut UiState, cmds: &mut Vec<Command>) {
    let n = m.analysis.steps();
    ui.horizontal_wrapped(|ui| {
        if ui.button("|< First").clicked() {
            cmds.push(Command::SetStep(0));
        }
        if ui.button("< Previous").clicked() && st.step > 0 {
            cmds.push(Command::SetStep(st.step - 1));
        }
        if ui
            .button(if st.playing { "Pause" } else { "Play" })
            .clicked()
        {
            cmds.push(Command::Play(!st.playing));
        }
        if ui.button("Next >").clicked() && st.step < n {
            cmds.push(Command::SetStep(st.step + 1));
        }
        if ui.button("Last >|").clicked() {
            cmds.push(Command::SetStep(n));
        }
        let mut k = st.step;
        let slider = egui::Slider::new(&mut k, 0..=n).text("Step");
        if ui.add(slider).changed() {
            cmds.push(Command::SetStep(k));
        }
        let what = match m.activity_of_step(st.step) {
            None => "before step 1: nothing placed".to_string(),
            Some(a) => {
                let outcome = match m.status(a, st.step) {
                    Status::Scheduled(s, e) => format!("scheduled {}–{}", m.time(s), m.time(e)),
                    Status::Failed => "failed".into(),
                    Status::Skipped => "skipped".into(),
                    Status::Pending => String::new(),
                };
                format!("step {}: {} — {outcome}", st.step, m.label(a))
            }
        };
        ui.label(what);
    });
}

/// The outcome of the last edit, and the last error.
fn banner_ui(ui: &mut egui::Ui, m: &Model<'_>, st: &mut UiState, cmds: &mut Vec<Command>) {
    if let Some(diff) = &st.banner {
        egui::Frame::new()
            .fill(m.theme.banner)
            .inner_margin(4.0)
            .show(ui, |ui| {
                ui.horizontal_wrapped(|ui| {
                    ui.label(diff.summary());
                    if ui.button("Dismiss").clicked() {
                        cmds.push(Command::DismissBanner);
                    }
                });
            });
    }
    if let Some(err) = &st.error {
        ui.horizontal_wrapped(|ui| {
            ui.label(RichText::new(err).color(m.theme.error));
            if ui.button("Dismiss error").clicked() {
                cmds.push(Command::DismissError);
            }
        });
    }
}

/// The activity list: search, status as of the current step, click to select.
fn activities_ui(ui: &mut egui::Ui, m: &Model<'_>, st: &mut UiState, cmds: &mut Vec<Command>) {
    ui.heading("Activities");
    let needle = st.filter.to_lowercase();
    let shown: Vec<&solscope_engine::Step> = m
        .analysis
        .schedule
        .steps
        .iter()
        .filter(|step| {
            let act = &m.doc.plan.activities[step.activity];
            needle.is_empty()
                || act.id.to_lowercase().contains(&needle)
                || act.display_name().to_lowercase().contains(&needle)
        })
        .collect();
    // Only the visible rows are laid out, so 10k activities stay cheap.
    let row_height = ui.spacing().interact_size.y;
    egui::ScrollArea::vertical()
        .auto_shrink([false; 2])
        .show_rows(ui, row_height, shown.len(), |ui, rows| {
            for step in &shown[rows] {
                let a = step.activity;
                let act = &m.doc.plan.activities[a];
                let (mark, color) = match m.status(a, st.step) {
                    Status::Scheduled(..) => ("+", m.theme.scheduled),
                    Status::Failed => ("x", m.theme.failed),
                    Status::Skipped => ("-", m.theme.skipped),
                    Status::Pending => (".", m.theme.muted),
                };
                let text =
                    RichText::new(format!("{mark} {:>3} {}", step.step, act.id)).color(color);
                let resp = ui.add(
                    egui::Button::new(text)
                        .selected(st.selected == Some(a))
                        .frame(false),
                );
                if resp.clicked() {
                    cmds.push(Command::Select(Some(a)));
                }
            }
        });
}

/// Zoom/pan controls and the exact range.
fn axis_ui(ui: &mut egui::Ui, m: &Model<'_>, st: &mut UiState, cmds: &mut Vec<Command>) {
    let bounds = (
        m.doc.plan.horizon.start as f64,
        m.doc.plan.horizon.end as f64,
    );
    ui.horizontal_wrapped(|ui| {
        ui.label("Time range (plan s)");
        let l0 = ui.label("from");
        let r0 = ui
            .add(egui::TextEdit::singleline(&mut st.range_text[0]).desired_width(80.0))
            .labelled_by(l0.id);
        let l1 = ui.label("to");
        let r1 = ui
            .add(egui::TextEdit::singleline(&mut st.range_text[1]).desired_width(80.0))
            .labelled_by(l1.id);
        let enter = ui.input(|i| i.key_pressed(egui::Key::Enter));
        if (r0.lost_focus() || r1.lost_focus()) && enter || ui.button("Apply range").clicked() {
            match (
                st.range_text[0].trim().parse::<f64>(),
                st.range_text[1].trim().parse::<f64>(),
            ) {
                (Ok(a), Ok(b)) if a < b => cmds.push(Command::SetAxis(TimeAxis::new(a, b))),
                _ => {
                    st.error =
                        Some("Time range: enter two numbers, start < end (plan seconds)".into())
                }
            }
        }
        if ui.button("Zoom in").clicked() {
            let mut axis = st.axis;
            axis.zoom_about((axis.start + axis.end) / 2.0, 2.0, bounds);
            cmds.push(Command::SetAxis(axis));
        }
        if ui.button("Zoom out").clicked() {
            let mut axis = st.axis;
            axis.zoom_about((axis.start + axis.end) / 2.0, 0.5, bounds);
            cmds.push(Command::SetAxis(axis));
        }
        if ui.button("Whole plan").clicked() {
            cmds.push(Command::SetAxis(TimeAxis::new(bounds.0, bounds.1)));
        }
        ui.label(format!(
            "{} – {}",
            m.doc.plan.local_time.format_hms(st.axis.start as i64),
            m.doc.plan.local_time.format_hms(st.axis.end as i64)
        ));
    });
}

/// "Discard unsaved changes?"
fn confirm_ui(ui: &mut egui::Ui, st: &mut UiState, cmds: &mut Vec<Command>) {
    let Some(pending) = &st.confirm else { return };
    let what = match pending {
        Pending::Open(p) => format!("open {}", p.display()),
        Pending::Quit => "quit".into(),
    };
    egui::Modal::new(egui::Id::unique("confirm_discard")).show(ui.ctx(), |ui| {
        ui.heading("Unsaved changes");
        ui.label(format!(
            "The plan has unsaved edits. Discard them and {what}?"
        ));
        ui.horizontal(|ui| {
            if ui.button("Discard changes").clicked() {
                cmds.push(Command::ConfirmDiscard(true));
            }
            if ui.button("Keep editing").clicked() {
                cmds.push(Command::ConfirmDiscard(false));
            }
        });
    });
}
