//! The desktop app: a step-through schedule inspector hosting the engine in-process.
//!
//! Data flow per frame: the views (`views/*`, functions named `*_ui`) read the
//! [`Document`] and its [`Analysis`] and push [`Command`]s; after the frame
//! [`SolscopeApp::apply`] carries them out (edit → reschedule → explain → diff),
//! so the model never changes mid-draw. Per-frame widget state (text buffers,
//! hover) lives in [`UiState`]; what survives restarts (recent files, theme) in
//! [`Persisted`], saved through eframe storage.

pub mod commands;
pub mod document;
pub mod theme;
pub mod time_axis;
mod views;

use std::path::{Path, PathBuf};

use eframe::egui;
use solscope_engine::{Plan, Suggestion};

pub use commands::Command;
pub use document::{Analysis, Document, OutcomeDiff};
pub use theme::Theme;
pub use time_axis::TimeAxis;

/// The plan the app opens without arguments.
pub const DEFAULT_PLAN: &str = include_str!("../../assets/default-plan.json");

/// What survives restarts.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Persisted {
    /// Recently opened files, newest first.
    pub recent: Vec<PathBuf>,
    /// Light theme instead of dark.
    pub light: bool,
    /// Gantt: scheduled activities in one row per unit resource instead of packed
    /// lanes.
    #[serde(default)]
    pub by_resource: bool,
}

/// An action waiting for "discard unsaved changes?".
#[derive(Clone, Debug, PartialEq)]
pub enum Pending {
    /// Open this file.
    Open(PathBuf),
    /// Quit.
    Quit,
}

/// Profiles and lanes as of one step (cached: rebuilt when the step changes).
#[derive(Clone, Debug, Default)]
pub struct StepView {
    /// The step.
    pub step: usize,
    /// State of charge `[t, Wh]`.
    pub soc: Vec<[f64; 2]>,
    /// Peak power `[t, W]` (step function, given as pairs of points).
    pub peak: Vec<[f64; 2]>,
    /// Data volume `[t, Mbit]`.
    pub data: Vec<[f64; 2]>,
}

/// Per-frame and widget state.
#[derive(Clone, Debug)]
pub struct UiState {
    /// The step shown (0..=N).
    pub step: usize,
    /// Stepping automatically.
    pub playing: bool,
    /// Time of the last automatic step.
    pub last_tick: f64,
    /// The selected activity.
    pub selected: Option<usize>,
    /// The visible time range.
    pub axis: TimeAxis,
    /// The axis changed from outside the plots (push it into them).
    pub axis_changed: bool,
    /// Where the plots were clicked.
    pub probe: Option<i64>,
    /// Energy consumers since the last full battery.
    pub since_full: bool,
    /// Activity filter text.
    pub filter: String,
    /// The outcome of the last edit.
    pub banner: Option<OutcomeDiff>,
    /// The last error (bad file, bad edit).
    pub error: Option<String>,
    /// Waiting for "discard unsaved changes?".
    pub confirm: Option<Pending>,
    /// Quit was confirmed.
    pub quit_now: bool,
    /// Range text fields (start, end).
    pub range_text: [String; 2],
    /// Editor text buffers: field key → (text, error).
    pub editor: std::collections::BTreeMap<String, (String, Option<String>)>,
    /// The activity the editor buffers belong to.
    pub editor_for: Option<(Option<usize>, u64)>,
    /// Export the current view as PNG after this frame (the host does it).
    pub export_png: bool,
    /// Screen x range of the plots' data area last frame: the Gantt's timeline
    /// uses the same, so one time maps to one x everywhere.
    pub plot_x: Option<(f32, f32)>,
    /// The Gantt rows last built, with what they were built for.
    pub gantt: Option<views::GanttRows>,
}

/// A value derived for one activity at one plan revision (its explanation, valid
/// intervals, verified suggestions, or the worker computing them). It is read back
/// only for that activity and revision, so nothing stale is ever shown.
#[derive(Debug)]
struct Derived<T> {
    activity: usize,
    revision: u64,
    value: T,
}

impl<T> Derived<T> {
    /// The value in `slot` if it was derived for `activity` at `revision`.
    fn get(slot: &Option<Self>, activity: usize, revision: u64) -> Option<&T> {
        slot.as_ref()
            .filter(|d| d.activity == activity && d.revision == revision)
            .map(|d| &d.value)
    }
}

/// The app: document, derived analysis, UI state, and the command queue.
pub struct SolscopeApp {
    /// The open plan.
    pub doc: Document,
    /// Its schedule and explanations.
    pub analysis: Analysis,
    /// UI state.
    pub ui: UiState,
    /// Persisted settings.
    pub persisted: Persisted,
    /// The palette.
    pub theme: Theme,
    /// Profiles as of the current step.
    pub step_view: StepView,
    /// Verified suggestions of the selected activity, per plan revision.
    suggestions: Option<Derived<Vec<Suggestion>>>,
    /// Suggestions being verified on a worker thread (rescheduling once per
    /// candidate edit can take seconds on a big plan): activity, revision, result.
    pending: Option<Derived<std::sync::mpsc::Receiver<Vec<Suggestion>>>>,
    /// Verify suggestions on a worker thread (the desktop app); headless renders
    /// and tests compute them in the frame so that what they draw is settled.
    pub background: bool,
    /// Explanation of the selected activity, per plan revision.
    explanation: Option<Derived<Option<solscope_engine::Explanation>>>,
    /// Full valid intervals of the selected scheduled activity as it saw them.
    valid: Option<Derived<Vec<solscope_engine::CategoryIntervals>>>,
    /// Bumped on every accepted change of the plan.
    pub revision: u64,
    commands: Vec<Command>,
}

impl std::fmt::Debug for SolscopeApp {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SolscopeApp")
            .field("plan", &self.doc.title())
            .field("step", &self.ui.step)
            .finish()
    }
}

impl SolscopeApp {
    /// Opens a plan from JSON text.
    pub fn from_text(text: &str, path: Option<PathBuf>) -> Result<Self, solscope_engine::Error> {
        let doc = Document::from_text(text, path)?;
        let analysis = Analysis::of(&doc.plan)?;
        let axis = TimeAxis::new(doc.plan.horizon.start as f64, doc.plan.horizon.end as f64);
        let steps = analysis.steps();
        let mut app = Self {
            doc,
            analysis,
            ui: UiState {
                step: steps,
                playing: false,
                last_tick: 0.0,
                selected: None,
                axis,
                axis_changed: true,
                probe: None,
                since_full: false,
                filter: String::new(),
                banner: None,
                error: None,
                confirm: None,
                quit_now: false,
                range_text: [String::new(), String::new()],
                editor: Default::default(),
                editor_for: None,
                export_png: false,
                plot_x: None,
                gantt: None,
            },
            persisted: Persisted::default(),
            theme: Theme::new(true),
            step_view: StepView::default(),
            suggestions: None,
            pending: None,
            background: false,
            explanation: None,
            valid: None,
            revision: 0,
            commands: Vec::new(),
        };
        app.refresh_step_view();
        app.sync_range_text();
        Ok(app)
    }

    /// The app on the bundled default plan.
    pub fn with_default_plan() -> Result<Self, solscope_engine::Error> {
        Self::from_text(DEFAULT_PLAN, None)
    }

    /// Opens `path`, or the default plan when it cannot be read; the error, if any,
    /// is shown in the app.
    pub fn open_or_default(path: Option<&Path>) -> Result<Self, solscope_engine::Error> {
        let mut app = Self::with_default_plan()?;
        if let Some(p) = path {
            // The same path as File > Open: a bad file keeps the default plan and
            // shows its path-named error.
            app.open_now(p);
        }
        Ok(app)
    }

    /// Queues a command (views call this through their `&mut Vec<Command>`).
    pub fn push(&mut self, cmd: Command) {
        self.commands.push(cmd);
    }

    /// Draws one frame and applies the commands it produced.
    pub fn frame_ui(&mut self, ui: &mut egui::Ui) {
        // Plan files may hold any text: draw a box for a missing glyph, never panic.
        ui.ctx()
            .set_missing_glyph_policy(egui::epaint::text::MissingGlyphPolicy::Tofu);
        ui.ctx().set_theme(if self.persisted.light {
            egui::Theme::Light
        } else {
            egui::Theme::Dark
        });
        self.theme = Theme::new(!self.persisted.light);
        let mut cmds = std::mem::take(&mut self.commands);
        views::shortcuts(ui, self, &mut cmds);
        views::dropped_files(ui, &mut cmds);
        if self.ui.playing {
            let now = ui.input(|i| i.time);
            if now - self.ui.last_tick > 0.15 {
                self.ui.last_tick = now;
                if self.ui.step < self.analysis.steps() {
                    cmds.push(Command::SetStep(self.ui.step + 1));
                } else {
                    cmds.push(Command::Play(false));
                }
            }
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(150));
        }
        if let Some(a) = self.ui.selected {
            // Derived data, computed before drawing (never mid-draw).
            self.explanation_for(a);
            self.suggestions_for(a);
            self.valid_for(a);
        }
        self.reap_worker();
        if self.verifying().is_some() {
            // Poll the worker until its result is in.
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(50));
        }
        views::layout_ui(ui, self, &mut cmds);
        for cmd in cmds {
            self.apply(cmd);
        }
    }

    /// Carries out one command.
    pub fn apply(&mut self, cmd: Command) {
        let steps = self.analysis.steps();
        match cmd {
            Command::SetStep(k) => {
                self.ui.step = k.min(steps);
                self.refresh_step_view();
            }
            Command::Play(on) => {
                if on && self.ui.step >= steps {
                    self.ui.step = 0;
                    self.refresh_step_view();
                }
                self.ui.playing = on;
            }
            Command::Select(a) => self.ui.selected = a,
            Command::GoToFailureStep(a) => {
                self.ui.selected = Some(a);
                if let Some(k) = self.explanation_for(a).and_then(|e| e.failure_step) {
                    self.ui.step = k;
                    self.refresh_step_view();
                }
            }
            Command::SetAxis(axis) => {
                self.ui.axis = axis;
                self.ui.axis.clamp(self.bounds());
                self.ui.axis_changed = true;
                self.sync_range_text();
            }
            Command::ProbePlot(t) => self.ui.probe = t,
            Command::SetSinceFull(on) => self.ui.since_full = on,
            Command::Edit {
                target,
                set,
                description,
            } => match solscope_engine::apply_edit(&self.doc.plan, &target, &set) {
                Ok(plan) => self.accept_plan(plan, &description, true),
                Err(e) => self.ui.error = Some(format!("{description}: not applied: {e}")),
            },
            Command::Undo => {
                let before = self.doc.plan.clone();
                if self.doc.undo() {
                    self.reanalyse(before, "Undo");
                }
            }
            Command::Redo => {
                let before = self.doc.plan.clone();
                if self.doc.redo() {
                    self.reanalyse(before, "Redo");
                }
            }
            Command::Open(path) => {
                if self.doc.dirty {
                    self.ui.confirm = Some(Pending::Open(path));
                } else {
                    self.open_now(&path);
                }
            }
            Command::OpenDialog => {
                if let Some(p) = rfd::FileDialog::new()
                    .add_filter("solscope plan", &["json"])
                    .pick_file()
                {
                    self.apply(Command::Open(p));
                }
            }
            Command::Save => match self.doc.path.clone() {
                Some(p) => self.save_to(&p),
                None => self.apply(Command::SaveAs(None)),
            },
            Command::SaveAs(path) => {
                let path = path.or_else(|| {
                    rfd::FileDialog::new()
                        .add_filter("solscope plan", &["json"])
                        .save_file()
                        .map(|p| with_extension(p, "json"))
                });
                if let Some(p) = path {
                    self.save_to(&p);
                }
            }
            Command::ExportSchedule(path) => {
                let path = path.or_else(|| {
                    rfd::FileDialog::new()
                        .add_filter("schedule JSON", &["json"])
                        .save_file()
                        .map(|p| with_extension(p, "json"))
                });
                if let Some(p) = path {
                    let loaded = solscope_engine::LoadedPlan {
                        plan: self.doc.plan.clone(),
                        warnings: self.doc.warnings.clone(),
                    };
                    let doc = solscope_engine::schedule_document(
                        &loaded,
                        &self.analysis.schedule,
                        &self.doc.title(),
                    );
                    let text = serde_json::to_string_pretty(&doc).unwrap_or_default() + "\n";
                    if let Err(e) = std::fs::write(&p, text) {
                        self.ui.error = Some(format!("Could not write {}: {e}", p.display()));
                    }
                }
            }
            Command::ExportPng(_) => {
                // The host renders and writes it (it owns the renderer).
                self.ui.export_png = true;
            }
            Command::SetDark(dark) => self.persisted.light = !dark,
            Command::GroupByResource(on) => self.persisted.by_resource = on,
            Command::SetFilter(f) => self.ui.filter = f,
            Command::DismissBanner => self.ui.banner = None,
            Command::DismissError => self.ui.error = None,
            Command::ConfirmDiscard(yes) => {
                let pending = self.ui.confirm.take();
                if yes {
                    match pending {
                        Some(Pending::Open(p)) => self.open_now(&p),
                        Some(Pending::Quit) => self.ui.quit_now = true,
                        None => {}
                    }
                }
            }
            Command::Quit => {
                if self.doc.dirty {
                    self.ui.confirm = Some(Pending::Quit);
                } else {
                    self.ui.quit_now = true;
                }
            }
        }
    }

    /// Plan bounds as `f64`.
    pub fn bounds(&self) -> (f64, f64) {
        (
            self.doc.plan.horizon.start as f64,
            self.doc.plan.horizon.end as f64,
        )
    }

    /// Verified suggestions for activity `a`, computed once per plan revision from
    /// its explanation: in the frame, or with `background` on a worker thread (then
    /// `None` until they arrive; a result for an older revision is dropped). One
    /// worker at a time: a request made while another activity's (or an older
    /// revision's) worker runs waits for it to finish, so stepping through many
    /// activities does not pile up threads that each reschedule the plan.
    pub fn suggestions_for(&mut self, a: usize) -> Option<&[Suggestion]> {
        if self.background {
            self.reap_worker();
        }
        if self.cached_suggestions(a).is_none() && self.pending.is_none() {
            let revision = self.revision;
            match self.explanation_for(a).cloned() {
                Some(ex) if self.background => {
                    let (tx, rx) = std::sync::mpsc::channel();
                    let plan = self.doc.plan.clone();
                    let schedule = std::sync::Arc::clone(&self.analysis.schedule);
                    std::thread::spawn(move || {
                        let _ =
                            tx.send(solscope_engine::verified_suggestions(&plan, &schedule, &ex));
                    });
                    self.pending = Some(Derived {
                        activity: a,
                        revision,
                        value: rx,
                    });
                }
                ex => {
                    let value = ex.map_or_else(Vec::new, |ex| {
                        solscope_engine::verified_suggestions(
                            &self.doc.plan,
                            &self.analysis.schedule,
                            &ex,
                        )
                    });
                    self.suggestions = Some(Derived {
                        activity: a,
                        revision,
                        value,
                    });
                }
            }
        }
        self.cached_suggestions(a)
    }

    /// Takes a finished worker's result: kept when it is for the current revision,
    /// dropped otherwise.
    fn reap_worker(&mut self) {
        let Some(pending) = &self.pending else {
            return;
        };
        let value = match pending.value.try_recv() {
            Ok(list) => list,
            Err(std::sync::mpsc::TryRecvError::Empty) => return,
            Err(std::sync::mpsc::TryRecvError::Disconnected) => Vec::new(),
        };
        let (activity, revision) = (pending.activity, pending.revision);
        self.pending = None;
        if revision == self.revision {
            self.suggestions = Some(Derived {
                activity,
                revision,
                value,
            });
        }
    }

    /// The activity whose suggestions a worker is verifying, if any.
    pub fn verifying(&self) -> Option<usize> {
        self.pending.as_ref().map(|p| p.activity)
    }

    /// The explanation of activity `a` if it did not schedule (computed once per
    /// plan revision).
    pub fn explanation_for(&mut self, a: usize) -> Option<&solscope_engine::Explanation> {
        if Derived::get(&self.explanation, a, self.revision).is_none() {
            let value = self.analysis.explain(&self.doc.plan, a);
            self.explanation = Some(Derived {
                activity: a,
                revision: self.revision,
                value,
            });
        }
        Derived::get(&self.explanation, a, self.revision).and_then(Option::as_ref)
    }

    /// The valid intervals of activity `a` at its own step (over the whole
    /// horizon: the trace keeps them only within the window span).
    fn valid_for(&mut self, a: usize) {
        if Derived::get(&self.valid, a, self.revision).is_none() {
            let sched = &self.analysis.schedule;
            let value = sched
                .step_of(a)
                .map(|st| {
                    solscope_engine::valid_intervals_at(sched, a, st.step - 1, Some(st.duration))
                })
                .unwrap_or_default();
            self.valid = Some(Derived {
                activity: a,
                revision: self.revision,
                value,
            });
        }
    }

    /// Cached suggestions, if computed for this revision (views read these).
    pub fn cached_suggestions(&self, a: usize) -> Option<&[Suggestion]> {
        Derived::get(&self.suggestions, a, self.revision).map(Vec::as_slice)
    }

    fn accept_plan(&mut self, plan: Plan, description: &str, record: bool) {
        let before = self.doc.plan.clone();
        if record {
            self.doc.replace(plan);
        }
        self.reanalyse(before, description);
    }

    /// Reschedules the current plan and shows the outcome diff against `before`.
    fn reanalyse(&mut self, before: Plan, description: &str) {
        match self.analysis.rerun(&self.doc.plan) {
            Ok(analysis) => {
                let old = std::mem::replace(&mut self.analysis, analysis);
                self.ui.banner = Some(OutcomeDiff::between(
                    description,
                    (&before, &old),
                    (&self.doc.plan, &self.analysis),
                ));
                self.ui.error = None;
                self.revision += 1;
                self.ui.step = self.ui.step.min(self.analysis.steps());
                if self.ui.step == old.steps() {
                    self.ui.step = self.analysis.steps();
                }
                self.refresh_step_view();
            }
            Err(e) => self.ui.error = Some(format!("{description}: {e}")),
        }
    }

    fn open_now(&mut self, path: &Path) {
        let text = match std::fs::read_to_string(path) {
            Ok(t) => t,
            Err(e) => {
                self.ui.error = Some(format!("Could not open {}: {e}", path.display()));
                return;
            }
        };
        match Self::from_text(&text, Some(path.to_path_buf())) {
            Ok(mut fresh) => {
                fresh.persisted = std::mem::take(&mut self.persisted);
                fresh.background = self.background;
                fresh.persisted.recent.retain(|p| p != path);
                fresh.persisted.recent.insert(0, path.to_path_buf());
                fresh.persisted.recent.truncate(10);
                *self = fresh;
            }
            Err(e) => {
                // Keep the current plan; say what is wrong with the file.
                self.ui.error = Some(format!("Could not open {}: {e}", path.display()));
            }
        }
    }

    fn save_to(&mut self, path: &Path) {
        match std::fs::write(path, self.doc.to_json()) {
            Ok(()) => {
                self.doc.path = Some(path.to_path_buf());
                self.doc.dirty = false;
                self.persisted.recent.retain(|p| p != path);
                self.persisted.recent.insert(0, path.to_path_buf());
                self.persisted.recent.truncate(10);
            }
            Err(e) => self.ui.error = Some(format!("Could not save {}: {e}", path.display())),
        }
    }

    fn refresh_step_view(&mut self) {
        let k = self.ui.step;
        let state = self.analysis.schedule.state_after(k);
        let wh = solscope_engine::MJ_PER_WH;
        let soc = state
            .soc
            .profile()
            .into_iter()
            .map(|(t, l)| [t as f64, l as f64 / wh])
            .collect();
        let data = state
            .data
            .profile()
            .into_iter()
            .map(|(t, l)| [t as f64, -(l as f64) / solscope_engine::BIT_PER_MBIT])
            .collect();
        let mut peak = Vec::new();
        let pts = state.peak.points();
        for (i, &(t, v)) in pts.iter().enumerate() {
            let end = pts.get(i + 1).map_or(state.peak.end(), |p| p.0);
            let w = v as f64 / solscope_engine::MW_PER_W;
            peak.push([t as f64, w]);
            peak.push([end as f64, w]);
        }
        self.step_view = StepView {
            step: k,
            soc,
            peak,
            data,
        };
    }

    fn sync_range_text(&mut self) {
        self.ui.range_text = [
            format!("{:.0}", self.ui.axis.start),
            format!("{:.0}", self.ui.axis.end),
        ];
    }
}

fn with_extension(p: PathBuf, ext: &str) -> PathBuf {
    if p.extension().is_some() {
        p
    } else {
        p.with_extension(ext)
    }
}

/// The eframe host: persistence, window close guard, PNG export.
#[derive(Debug)]
pub struct SolscopeHost {
    /// The app.
    pub app: SolscopeApp,
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
        Self { app }
    }
}

impl eframe::App for SolscopeHost {
    fn logic(&mut self, ctx: &egui::Context, _frame: &mut eframe::Frame) {
        if ctx.input(|i| i.viewport().close_requested())
            && !self.app.ui.quit_now
            && self.app.doc.dirty
        {
            ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
            self.app.ui.confirm = Some(Pending::Quit);
        }
    }

    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.app.frame_ui(ui);
        if std::mem::take(&mut self.app.ui.export_png) {
            if let Some(path) = rfd::FileDialog::new()
                .add_filter("PNG", &["png"])
                .save_file()
                .map(|p| with_extension(p, "png"))
            {
                ui.ctx()
                    .request_screenshot(move |img: std::sync::Arc<egui::ColorImage>| {
                        let _ = save_color_image(&img, &path);
                    });
            }
        }
        if self.app.ui.quit_now {
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
    fn opening_at_start_up_falls_back_to_the_default_plan_with_the_error() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let good = root.join("assets/examples/pitfall.json");
        let app = SolscopeApp::open_or_default(Some(&good)).expect("app");
        assert_eq!(app.doc.plan.activities.len(), 2);
        assert_eq!(app.doc.path.as_deref(), Some(good.as_path()));
        assert!(app.ui.error.is_none());
        let bad = root.join("tests/malformed/window-end-before-start.json");
        let app = SolscopeApp::open_or_default(Some(&bad)).expect("app");
        assert_eq!(
            app.doc.plan,
            SolscopeApp::with_default_plan().expect("default").doc.plan
        );
        let err = app.ui.error.expect("error shown");
        assert!(err.contains("windows[0].end"), "{err}");
    }

    #[test]
    fn step_view_series_are_monotone_in_time() {
        let app = SolscopeApp::with_default_plan().expect("default plan");
        for series in [&app.step_view.soc, &app.step_view.peak, &app.step_view.data] {
            assert!(
                series.windows(2).all(|w| w[0][0] <= w[1][0]),
                "time goes backwards"
            );
        }
        // A step function: consecutive pairs share x or y.
        assert!(
            app.step_view
                .peak
                .windows(2)
                .all(|w| w[0][0] == w[1][0] || w[0][1] == w[1][1])
        );
    }
}
