//! The views. Each `*_ui` function reads the [`Model`] and pushes commands; the
//! only state written while drawing is widget state ([`Widgets`]: text buffers and
//! what the views keep between frames).
//!
//! The views see the app only through this interface: they import the lower
//! modules (`commands`, `document`, `state`, `theme`, `time_axis`), never the app,
//! its derived-value cache or the host.

mod execution;
mod flex;
mod gantt;
pub use gantt::{BarDrag, Extent, GanttRows, extent};
mod editor;
mod inspector;
mod list;
pub use list::{Listed, SearchIndex};
mod montecarlo;
mod plots;
mod repair;
mod text;
mod tour;
pub use tour::TourAnchors;
mod widgets;

use eframe::egui::{self, RichText};
use solscope_engine::{Outcome, Suggestion, parse_local};

use crate::gui::commands::{Command, UiCommand};
use crate::gui::document::{Analysis, Document};
use crate::gui::execution::{ActualsSource, CycleRun, ExecutionRun};
use crate::gui::montecarlo::{CampaignResult, Progress, Stopped};
use crate::gui::state::{
    MIN_STEPS_SHOWN, Messages, Mode, Navigation, Pending, Persisted, StepView, StepWindow,
    TextBuffers,
};
use crate::gui::theme::{
    FAILURE_TICK_HEIGHT, FAILURE_TICK_STROKE, INSPECTOR_WIDTH, LIST_WIDTH, MESSAGE_MARGIN,
    PROMPT_WIDTH, RANGE_FIELD_WIDTH, STEP_LABEL_MIN_WIDTH, STEP_PICK_POINTS, STEP_SLIDER_WIDTH,
    Theme,
};
use crate::gui::time_axis::TimeAxis;

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
    /// Why the selected activity could not be explained, if that happened.
    pub explanation_error: Option<&'a str>,
    /// Valid intervals of the selected activity at its own step (full horizon).
    pub valid: Option<&'a [solscope_engine::CategoryIntervals]>,
    /// What the selected activity, failed on energy or peak power, would have
    /// caused at its explanation's start (drawn over the plots, its culprits
    /// highlighted on the Gantt).
    pub would_cause: Option<&'a crate::gui::state::WouldCause>,
    /// The flexible schedule of this revision, or why there is none, once
    /// derived (`None` meanwhile).
    pub flex: Option<&'a Result<std::sync::Arc<solscope_engine::Flex>, String>>,
    /// Where its free slack stands (computed on a worker, filled in as it
    /// goes), once the flexible schedule is derived.
    pub free_slack: Option<crate::gui::state::FreeSlackProgress>,
    /// Where the user is: step, selection, visible range, probe.
    pub nav: &'a Navigation,
    /// The outcome banner, the error and the unsaved-changes question.
    pub messages: &'a Messages,
    /// What execution mode draws.
    pub exec: ExecModel<'a>,
}

/// What execution mode draws, each part once it is derived for the current plan
/// revision and actuals (`None` meanwhile).
#[derive(Clone, Copy, Debug)]
pub struct ExecModel<'a> {
    /// Where the actual durations come from.
    pub source: &'a ActualsSource,
    /// Bumped whenever the source changes.
    pub actuals_rev: u64,
    /// The execution, or why there is none.
    pub run: Option<&'a Result<std::sync::Arc<ExecutionRun>, String>>,
    /// The cycle looked at (clamped to the execution's cycles).
    pub cycle: usize,
    /// Its scheduler run with the step trace.
    pub cycle_run: Option<&'a CycleRun>,
    /// The step shown inside that run (clamped to its steps).
    pub step: usize,
    /// The run's profiles after that step.
    pub view: Option<&'a StepView>,
    /// Why the selected activity did not complete (when it did not).
    pub loss: Option<&'a Result<solscope_engine::Loss, String>>,
    /// The Monte Carlo campaign.
    pub campaign: CampaignModel<'a>,
}

/// What the Monte Carlo panel draws: the last campaign of the plan as it is,
/// the one running, and what became of one that stopped or no longer applies.
#[derive(Clone, Copy, Debug, Default)]
pub struct CampaignModel<'a> {
    /// The last campaign finished on the plan as it is (or why it failed).
    pub result: Option<&'a Result<CampaignResult, String>>,
    /// The campaign running.
    pub running: Option<Progress>,
    /// `(seed, runs)` of the last campaign finished when the plan was edited
    /// since (its summary is not shown).
    pub stale: Option<(u64, u64)>,
    /// The last campaign that stopped before its summary.
    pub stopped: Option<&'a Stopped>,
}

impl<'a> CampaignModel<'a> {
    /// The summary of the plan as it is, when there is one.
    pub fn ready(&self) -> Option<&'a CampaignResult> {
        self.result.and_then(|r| r.as_ref().ok())
    }
}

impl<'a> ExecModel<'a> {
    /// The execution, when derived without error.
    pub fn ready(&self) -> Option<&'a ExecutionRun> {
        self.run.and_then(|r| r.as_ref().ok()).map(AsRef::as_ref)
    }

    /// The cycle's run, when it could be repeated.
    pub fn schedule(&self) -> Option<&'a solscope_engine::Schedule> {
        self.cycle_run.and_then(|c| c.schedule.as_ref().ok())
    }
}

/// What the views keep between frames (their own, not the app's).
#[derive(Clone, Debug, Default)]
pub struct ViewCache {
    /// Screen x range of the plots' data area last frame: the Gantt's timeline
    /// uses the same, so one time maps to one x everywhere.
    pub plot_x: Option<(f32, f32)>,
    /// The Gantt rows last built, with what they were built for.
    pub gantt: Option<GanttRows>,
    /// Where each placed activity's bar was drawn last frame (schedule mode,
    /// visible bars only): what a drag picks up.
    pub bars: Vec<(usize, egui::Rect)>,
    /// The bar being dragged, if any.
    pub drag: Option<BarDrag>,
    /// The activity list's rows wholly in view last frame.
    pub list_rows: std::ops::Range<usize>,
    /// The selection the activity list last scrolled to, and the
    /// [`Listed::generation`] it was in.
    pub list_selected: Option<(Option<usize>, u64)>,
    /// What the search and filters select (see [`ViewCache::listed`]).
    pub listed: Option<std::sync::Arc<Listed>>,
    /// Lower-case ids and names, resources and sols of one plan revision.
    pub search: Option<std::sync::Arc<SearchIndex>>,
    /// The selection the Gantt last scrolled its row into view for.
    pub gantt_revealed: Option<Option<usize>>,
    /// How each activity bar drawn last frame looked with the search and
    /// filters (every bar plain without them).
    pub looks: Vec<(usize, Look)>,
    /// Where the parts the guided tour points at were drawn this frame.
    pub tour_anchors: TourAnchors,
}

/// How the Gantt draws an activity's bar against the search and filters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Look {
    /// Nothing is filtered.
    Plain,
    /// It matches: outlined.
    Highlighted,
    /// It does not: faded.
    Dimmed,
}

impl ViewCache {
    /// Where activity `a`'s placement bar was drawn last frame.
    pub fn gantt_bar(&self, a: usize) -> Option<egui::Rect> {
        self.bars.iter().find(|(b, _)| *b == a).map(|(_, r)| *r)
    }
}

/// The state the views write while drawing, for one frame.
#[derive(Debug)]
pub struct Widgets<'a> {
    /// Text buffers of the range fields and the editor.
    pub text: &'a mut TextBuffers,
    /// What the views keep between frames.
    pub cache: &'a mut ViewCache,
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

/// Status of activity `a` after step `k` of `analysis`'s run.
pub fn status_at(analysis: &Analysis, a: usize, k: usize) -> Status {
    match analysis.step(a) {
        Some(st) if st.step <= k => match st.outcome {
            Outcome::Scheduled { start, end } => Status::Scheduled(start, end),
            Outcome::Failed(_) => Status::Failed,
            Outcome::Skipped { .. } => Status::Skipped,
        },
        _ => Status::Pending,
    }
}

impl Model<'_> {
    /// Status of activity `a` after step `k`.
    pub fn status(&self, a: usize, k: usize) -> Status {
        status_at(self.analysis, a, k)
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

    /// The flexible schedule, when derived without error.
    pub fn flex_ready(&self) -> Option<&'_ solscope_engine::Flex> {
        self.flex.and_then(|r| r.as_ref().ok()).map(AsRef::as_ref)
    }

    /// The flexible schedule when the Gantt shows its layer (schedule mode,
    /// not hidden, derived).
    pub fn flex_layer(&self) -> Option<&'_ solscope_engine::Flex> {
        let shown = self.nav.mode == Mode::Schedule && !self.persisted.hide_flex;
        self.flex_ready().filter(|_| shown)
    }

    /// Plan time as `Sol 413 14:15:00 (t=600)`.
    pub fn time(&self, t: i64) -> String {
        solscope_engine::format_plan_time(&self.doc.plan.local_time, t)
    }
}

/// Keyboard: the shortcuts of the [`UiCommand`]s (undo/redo, save/open), and
/// stepping (Left/Right, Home/End) when no text field has focus.
pub fn shortcuts(ui: &mut egui::Ui, cmds: &mut Vec<Command>) {
    let mut undo_redo = false;
    for cmd in UiCommand::WITH_MODIFIERS {
        let Some(shortcut) = cmd.kb_shortcut() else {
            continue;
        };
        // One of undo and redo per frame (redo is checked first).
        let is_undo_redo = matches!(cmd, UiCommand::Undo | UiCommand::Redo);
        if is_undo_redo && undo_redo {
            continue;
        }
        if ui.input_mut(|i| i.consume_shortcut(&shortcut)) {
            undo_redo |= is_undo_redo;
            cmds.push(cmd.into());
        }
    }
    if ui.ctx().egui_wants_keyboard_input() {
        return;
    }
    for cmd in UiCommand::PLAIN_KEYS {
        if let Some(shortcut) = cmd.kb_shortcut() {
            // Every press counts: five quick presses between two frames are five
            // steps (key repeats too).
            for _ in 0..ui.input(|i| presses(i, shortcut)) {
                cmds.push(cmd.into());
            }
        }
    }
}

/// How many times `shortcut` was pressed this frame, with exactly its modifiers
/// (Shift+Right is not also Right).
fn presses(input: &egui::InputState, shortcut: egui::KeyboardShortcut) -> usize {
    input
        .events
        .iter()
        .filter(|e| {
            matches!(e, egui::Event::Key { key, pressed: true, modifiers, .. }
                if *key == shortcut.logical_key && modifiers.matches_exact(shortcut.modifiers))
        })
        .count()
}

/// A button that gives `cmd` (its label is the command's).
fn command_button(ui: &mut egui::Ui, cmd: UiCommand, enabled: bool, cmds: &mut Vec<Command>) {
    if ui
        .add_enabled(enabled, egui::Button::new(cmd.label()))
        .clicked()
    {
        cmds.push(cmd.into());
    }
}

/// A File menu item that gives `cmd`; its shortcut, if any, is its tooltip (the
/// label stays the command's alone).
fn menu_item(ui: &mut egui::Ui, cmd: UiCommand, cmds: &mut Vec<Command>) {
    let mut resp = ui.button(cmd.label());
    if let Some(shortcut) = cmd.kb_shortcut() {
        resp = resp.on_hover_text(ui.ctx().format_shortcut(&shortcut));
    }
    if resp.clicked() {
        cmds.push(cmd.into());
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
pub fn layout_ui(ui: &mut egui::Ui, m: &Model<'_>, w: &mut Widgets<'_>, cmds: &mut Vec<Command>) {
    if let Some(r) = &m.messages.repair {
        // A plan file that did not load: repaired in its own view.
        repair::repair_ui(ui, m, r, w.text, cmds);
        return;
    }
    // What the search and filters select, for the list and the Gantt alike.
    w.cache.listed(&m.doc.plan, m.analysis, m.nav, m.revision);
    w.cache.tour_anchors = TourAnchors::default();
    let top = egui::Panel::top("toolbar").show(ui, |ui| {
        toolbar_ui(ui, m, cmds);
        match m.nav.mode {
            Mode::Schedule => steps_ui(ui, m, cmds),
            Mode::Execution => {
                execution::actuals_ui(ui, m, &mut w.text.seed_text, cmds);
                execution::cycles_ui(ui, m, cmds);
                execution::cycle_steps_ui(ui, m, cmds);
            }
        }
        banner_ui(ui, m, cmds);
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
    egui::CentralPanel::default().show(ui, |ui| {
        axis_ui(ui, m, &mut w.text.range_text, cmds);
        gantt::ruler_ui(ui, m, w.cache);
        egui::ScrollArea::vertical()
            .auto_shrink([false; 2])
            .show(ui, |ui| {
                gantt::gantt_ui(ui, m, w.cache, cmds);
                plots::plots_ui(ui, m, w.cache, cmds);
            });
    });
    tour::tour_ui(ui, m, &w.cache.tour_anchors, cmds);
    confirm_ui(ui, m, cmds);
    pin_ui(ui, m, cmds);
    path_prompt_ui(ui, m, &mut w.text.path_text, cmds);
}

/// "Pin it at this start and reschedule?" after a bar was dropped outside its
/// slack.
fn pin_ui(ui: &mut egui::Ui, m: &Model<'_>, cmds: &mut Vec<Command>) {
    let Some(offer) = m.messages.pin else {
        return;
    };
    let Some(act) = m.doc.plan.activities.get(offer.activity) else {
        return;
    };
    let placed = m.analysis.placement(offer.activity);
    let (_, dropped) = crate::gui::document::pin_window(act, placed.map(|p| p.0), offer.start);
    let modal = egui::Modal::new(egui::Id::unique("pin_offer")).show(ui.ctx(), |ui| {
        ui.heading("Move outside its slack");
        let now = placed.map_or("not placed".to_string(), |p| {
            format!("scheduled at {}", m.time(p.0))
        });
        ui.label(format!(
            "{} is {now}. A start at {} is outside its slack: only an edit of the plan \
             gets it there.",
            act.id,
            m.time(offer.start),
        ));
        ui.label(format!(
            "Pin it at {} and reschedule? Its windows become the one window [{t}, {t}].",
            m.time(offer.start),
            t = offer.start
        ));
        if let Some(c) = dropped {
            ui.colored_label(
                m.theme.error,
                format!(
                    "It would end after its window's cutoff {}: the cutoff is dropped.",
                    m.time(c)
                ),
            );
        }
        ui.label(RichText::new("Undo restores the plan.").color(m.theme.muted));
        ui.horizontal(|ui| {
            if ui.button("Pin and reschedule").clicked() {
                cmds.push(Command::Pin {
                    activity: offer.activity,
                    start: offer.start,
                });
            }
            if ui.button("Keep the schedule").clicked() {
                cmds.push(Command::DismissPin);
            }
        });
    });
    if modal.should_close() {
        cmds.push(Command::DismissPin);
    }
}

/// File actions, back/forward, undo/redo, theme, layers.
fn toolbar_ui(ui: &mut egui::Ui, m: &Model<'_>, cmds: &mut Vec<Command>) {
    ui.horizontal_wrapped(|ui| {
        ui.menu_button("File", |ui| {
            for cmd in [
                UiCommand::Open,
                UiCommand::Save,
                UiCommand::SaveAs,
                UiCommand::ExportSchedule,
                UiCommand::ExportScheduleCsv,
                UiCommand::ExportPng,
            ] {
                menu_item(ui, cmd, cmds);
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
            menu_item(ui, UiCommand::Quit, cmds);
        });
        ui.menu_button("Help", |ui| {
            let tour = UiCommand::GuidedTour;
            if ui
                .button(tour.label())
                .on_hover_text(
                    "A short tour of one failure on the tutorial plan: steps, why it failed, \
                     what took its place, a checked fix and undo",
                )
                .clicked()
            {
                cmds.push(tour.into());
            }
            let reset = UiCommand::ResetTour;
            if ui
                .add_enabled(m.persisted.tour_dismissed, egui::Button::new(reset.label()))
                .on_hover_text(
                    "The tour opens by itself again the next time the tutorial plan is opened",
                )
                .on_disabled_hover_text("The tour opens by itself with the tutorial plan")
                .clicked()
            {
                cmds.push(reset.into());
            }
        });
        shortcut_button(ui, UiCommand::Back, m.nav.history.can_back(), cmds);
        shortcut_button(ui, UiCommand::Forward, m.nav.history.can_forward(), cmds);
        command_button(ui, UiCommand::Undo, m.doc.can_undo(), cmds);
        command_button(ui, UiCommand::Redo, m.doc.can_redo(), cmds);
        let dark = !m.persisted.light;
        if ui
            .button(if dark { "Light theme" } else { "Dark theme" })
            .clicked()
        {
            cmds.push(Command::SetDark(!dark));
        }
        if m.nav.mode == Mode::Schedule {
            let cmd = UiCommand::ToggleFlex;
            let mut shown = !m.persisted.hide_flex;
            let mut resp = ui.checkbox(&mut shown, cmd.label());
            if let Some(shortcut) = cmd.kb_shortcut() {
                resp = resp.on_hover_text(format!(
                    "Gantt: slack whiskers [lb, ub], free slack shaded (green: every check \
                     passes; amber: temporal only), the selected activity's dispatchable \
                     neighbours outlined, and drag a bar to try another start ({})",
                    ui.ctx().format_shortcut(&shortcut)
                ));
            }
            if resp.changed() {
                cmds.push(cmd.into());
            }
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
        // The mode switch, at the right end (the other tools keep their place).
        ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
            for (cmd, mode) in [
                (UiCommand::ShowExecution, Mode::Execution),
                (UiCommand::ShowSchedule, Mode::Schedule),
            ] {
                mode_button(ui, cmd, m.nav.mode == mode, cmds);
            }
            ui.label("View");
        });
    });
}

/// One side of the mode switch: selected when its mode is shown; its shortcut
/// is its tooltip.
fn mode_button(ui: &mut egui::Ui, cmd: UiCommand, selected: bool, cmds: &mut Vec<Command>) {
    let mut resp = ui.selectable_label(selected, cmd.label());
    if let Some(shortcut) = cmd.kb_shortcut() {
        resp = resp.on_hover_text(ui.ctx().format_shortcut(&shortcut));
    }
    if resp.clicked() && !selected {
        cmds.push(cmd.into());
    }
}

/// The step slider and its buttons (schedule mode).
fn steps_ui(ui: &mut egui::Ui, m: &Model<'_>, cmds: &mut Vec<Command>) {
    let what = |k: usize| match m.activity_of_step(k) {
        None => "before step 1: nothing placed".to_string(),
        Some(a) => {
            let outcome = match m.status(a, k) {
                Status::Scheduled(s, e) => format!("scheduled {}–{}", m.time(s), m.time(e)),
                Status::Failed => "failed".into(),
                Status::Skipped => "skipped".into(),
                Status::Pending => String::new(),
            };
            format!("step {k}: {} — {outcome}", m.label(a))
        }
    };
    // While the step moves, the plots may show an earlier step for a few
    // frames (their profiles are derived off the frame): say so.
    let plots_at = m.step_view.step;
    let what = |k: usize| {
        let text = what(k);
        if plots_at == k {
            text
        } else {
            format!("{text} · plots of step {plots_at}, catching up")
        }
    };
    let failed: Vec<usize> = failed_steps(&m.analysis.schedule.steps)
        .map(|(k, _)| k)
        .collect();
    step_row_ui(ui, m, (m.analysis.steps(), m.nav.step), &failed, what, cmds);
}

/// The steps (1-based) at which an activity failed, with the activity (an index
/// into the run's plan).
pub fn failed_steps(steps: &[solscope_engine::Step]) -> impl Iterator<Item = (usize, usize)> + '_ {
    steps
        .iter()
        .filter(|s| matches!(s.outcome, Outcome::Failed(_)))
        .map(|s| (s.step, s.activity))
}

/// Step buttons, play, and the slider over steps `0..=n` at step `k` (`(n, k)`)
/// with a tick at each step in `failed` (sorted), and what the step shown did
/// (`what(k)`): of the plan's schedule, or in execution mode of the looked-at
/// cycle's run. The text follows the slider in the frame it moves.
///
/// On a run with more steps than the rail can show apart
/// ([`STEP_PICK_POINTS`] a step), the slider spans the steps of
/// [`Navigation::steps_shown`](crate::gui::state::Navigation::steps_shown)
/// (zoomed with buttons or Ctrl+wheel, moved with the wheel): one step of
/// 10,000 is picked with the mouse.
fn step_row_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    (n, k): (usize, usize),
    failed: &[usize],
    what: impl Fn(usize) -> String,
    cmds: &mut Vec<Command>,
) {
    let playing = m.nav.playing;
    let zoomable = n as f32 * STEP_PICK_POINTS > STEP_SLIDER_WIDTH;
    let (lo, hi) = if zoomable {
        m.nav.steps_shown.span(n)
    } else {
        (0, n)
    };
    ui.horizontal_wrapped(|ui| {
        command_button(ui, UiCommand::FirstStep, true, cmds);
        command_button(ui, UiCommand::PreviousStep, true, cmds);
        if ui.button(if playing { "Pause" } else { "Play" }).clicked() {
            cmds.push(Command::Play(!playing));
        }
        command_button(ui, UiCommand::NextStep, true, cmds);
        command_button(ui, UiCommand::LastStep, true, cmds);
        let has_before = failed.first().is_some_and(|&f| f < k);
        let has_after = failed.last().is_some_and(|&f| f > k);
        shortcut_button(ui, UiCommand::PreviousFailure, has_before, cmds);
        shortcut_button(ui, UiCommand::NextFailure, has_after, cmds);
        let mut k = k;
        ui.spacing_mut().slider_width = STEP_SLIDER_WIDTH;
        // Every step exactly (no rounding to "nice" numbers under the
        // pointer); a step outside the span stays as it is, its handle at the
        // end of the rail.
        let slider = egui::Slider::new(&mut k, lo..=hi)
            .text("Step")
            .smart_aim(false)
            .clamping(egui::SliderClamping::Edits);
        let resp = ui.add(slider);
        let shown =
            &failed[failed.partition_point(|&f| f < lo)..failed.partition_point(|&f| f <= hi)];
        failure_ticks(ui, m, resp.rect, (lo, hi), shown);
        if zoomable {
            step_wheel(ui, &resp, (lo, hi), n, m.nav.steps_shown, cmds);
        }
        let resp = resp.on_hover_text(format!(
            "{}\n\n{} failure(s), marked under the slider{}",
            crate::gui::help::STEP,
            failed.len(),
            if zoomable {
                format!("\n\n{}", crate::gui::help::STEP_ZOOM)
            } else {
                String::new()
            }
        ));
        if resp.changed() {
            cmds.push(match m.nav.mode {
                Mode::Schedule => Command::SetStep(k),
                Mode::Execution => Command::SetCycleStep(k),
            });
        }
        if zoomable {
            command_button(ui, UiCommand::ZoomStepsOut, (lo, hi) != (0, n), cmds);
            command_button(ui, UiCommand::ZoomStepsIn, hi - lo > MIN_STEPS_SHOWN, cmds);
            if (lo, hi) != (0, n) {
                command_button(ui, UiCommand::AllSteps, true, cmds);
                // One piece: it moves to the next line whole rather than wrap.
                let span = RichText::new(format!("steps {lo}–{hi} of {n}")).color(m.theme.muted);
                ui.add(egui::Label::new(span).extend())
                    .on_hover_text(crate::gui::help::STEP_ZOOM);
            }
        }
        // On the slider's line whenever a little room is left there: cut
        // with an ellipsis, the whole text on hover.
        let room = ui.available_size_before_wrap().x;
        let label = egui::Label::new(what(k)).truncate();
        if room >= STEP_LABEL_MIN_WIDTH {
            ui.scope(|ui| {
                ui.set_max_width(room);
                ui.add(label)
            });
        } else {
            ui.add(label);
        }
    });
}

/// Ctrl+wheel (or a pinch) over the step slider zooms its span about the step
/// under the pointer; the wheel moves it earlier or later.
fn step_wheel(
    ui: &egui::Ui,
    resp: &egui::Response,
    (lo, hi): (usize, usize),
    n: usize,
    window: StepWindow,
    cmds: &mut Vec<Command>,
) {
    if !resp.hovered() {
        return;
    }
    let (zoom, scroll, pointer) = ui.input(|i| {
        (
            i.zoom_delta(),
            i.smooth_scroll_delta(),
            i.pointer.hover_pos(),
        )
    });
    let (x0, x1) = step_rail(ui, resp.rect);
    let per_point = (hi - lo) as f32 / (x1 - x0).max(1.0);
    if (zoom - 1.0).abs() > f32::EPSILON {
        let at = pointer.map_or((lo + hi) / 2, |p| {
            let frac = ((p.x - x0) / (x1 - x0).max(1.0)).clamp(0.0, 1.0);
            lo + ((hi - lo) as f32 * frac).round() as usize
        });
        cmds.push(Command::SetStepsShown(window.zoomed(
            f64::from(zoom),
            at,
            n,
        )));
    } else {
        // Either wheel axis; content moving right shows earlier steps.
        let delta = if scroll.x.abs() > scroll.y.abs() {
            scroll.x
        } else {
            scroll.y
        };
        let by = (-delta * per_point).round() as i64;
        if by != 0 && (lo, hi) != (0, n) {
            cmds.push(Command::SetStepsShown(window.panned(by, n)));
        }
    }
}

/// Where the step slider's handle travels on screen (`x0`, `x1`): the rail is
/// the left part of the slider's rect, inset by the handle's radius as egui
/// lays it out.
fn step_rail(ui: &egui::Ui, rect: egui::Rect) -> (f32, f32) {
    let thickness = ui
        .text_style_height(&egui::TextStyle::Body)
        .max(ui.spacing().interact_size.y);
    let radius = thickness / 2.5;
    (
        rect.left() + radius,
        rect.left() + STEP_SLIDER_WIDTH - radius,
    )
}

/// A tick under the step slider's rail at each failed step in `failed`, the
/// failures among the steps `lo..=hi` the slider spans.
fn failure_ticks(
    ui: &egui::Ui,
    m: &Model<'_>,
    rect: egui::Rect,
    (lo, hi): (usize, usize),
    failed: &[usize],
) {
    if hi <= lo || failed.is_empty() {
        return;
    }
    let thickness = ui
        .text_style_height(&egui::TextStyle::Body)
        .max(ui.spacing().interact_size.y);
    let (x0, x1) = step_rail(ui, rect);
    let y = rect.center().y + thickness / 2.0;
    let painter = ui.painter();
    let stroke = egui::Stroke::new(FAILURE_TICK_STROKE, m.theme.failed);
    let mut last_x = f32::NEG_INFINITY;
    let span = (hi - lo) as f32;
    for &f in failed {
        let x = x0 + (x1 - x0) * ((f - lo) as f32 / span);
        // One tick per pixel column on long runs.
        if x - last_x >= 1.0 {
            painter.line_segment(
                [egui::pos2(x, y - FAILURE_TICK_HEIGHT), egui::pos2(x, y)],
                stroke,
            );
            last_x = x;
        }
    }
}

/// A button that gives `cmd`, its shortcut as its tooltip.
fn shortcut_button(ui: &mut egui::Ui, cmd: UiCommand, enabled: bool, cmds: &mut Vec<Command>) {
    let mut resp = ui.add_enabled(enabled, egui::Button::new(cmd.label()));
    if let Some(shortcut) = cmd.kb_shortcut() {
        resp = resp.on_hover_text(ui.ctx().format_shortcut(&shortcut));
        resp = resp.on_disabled_hover_text(ui.ctx().format_shortcut(&shortcut));
    }
    if resp.clicked() {
        cmds.push(cmd.into());
    }
}

/// The outcome of the last edit, and the last error.
fn banner_ui(ui: &mut egui::Ui, m: &Model<'_>, cmds: &mut Vec<Command>) {
    if let Some(diff) = &m.messages.banner {
        egui::Frame::new()
            .fill(m.theme.banner)
            .inner_margin(MESSAGE_MARGIN)
            .show(ui, |ui| {
                ui.horizontal_wrapped(|ui| {
                    ui.label(diff.summary());
                    if ui.button("Dismiss").clicked() {
                        cmds.push(Command::DismissBanner);
                    }
                });
            });
    }
    if let Some(err) = &m.messages.error {
        ui.horizontal_wrapped(|ui| {
            ui.label(RichText::new(err).color(m.theme.error));
            if ui.button("Dismiss error").clicked() {
                cmds.push(Command::DismissError);
            }
        });
    }
}

/// Zoom/pan controls and the exact range.
fn axis_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    range_text: &mut [String; 2],
    cmds: &mut Vec<Command>,
) {
    let axis = m.nav.axis;
    let bounds = (
        m.doc.plan.horizon.start as f64,
        m.doc.plan.horizon.end as f64,
    );
    ui.horizontal_wrapped(|ui| {
        ui.label("Time range");
        let l0 = ui.label("from");
        // The plan seconds of the range shown, on hover (the fields read either).
        let r0 = ui
            .add(egui::TextEdit::singleline(&mut range_text[0]).desired_width(RANGE_FIELD_WIDTH))
            .labelled_by(l0.id)
            .on_hover_text(format!("t={:.0} s", axis.start.round()));
        let l1 = ui.label("to");
        let r1 = ui
            .add(egui::TextEdit::singleline(&mut range_text[1]).desired_width(RANGE_FIELD_WIDTH))
            .labelled_by(l1.id)
            .on_hover_text(format!("t={:.0} s", axis.end.round()));
        let enter = ui.input(|i| i.key_pressed(egui::Key::Enter));
        if (r0.lost_focus() || r1.lost_focus()) && enter || ui.button("Apply range").clicked() {
            // "Sol 413 08:00" to "12:00": the end's sol defaults to the start's.
            let clock = &m.doc.plan.local_time;
            let from = parse_local(clock, &range_text[0], None);
            let to = parse_local(clock, &range_text[1], from.map(|t| clock.sol(t)));
            match (from, to) {
                (Some(a), Some(b)) if a < b => {
                    cmds.push(Command::SetAxis(TimeAxis::new(a as f64, b as f64)))
                }
                _ => cmds.push(Command::ShowError(
                    "Time range: enter a start before an end, each as a sol and local time \
                     (Sol 413 08:00, or 12:00 for the end in the start's sol) or in plan \
                     seconds"
                        .into(),
                )),
            }
        }
        if ui.button("Zoom in").clicked() {
            let mut axis = axis;
            axis.zoom_about((axis.start + axis.end) / 2.0, 2.0, bounds);
            cmds.push(Command::SetAxis(axis));
        }
        if ui.button("Zoom out").clicked() {
            let mut axis = axis;
            axis.zoom_about((axis.start + axis.end) / 2.0, 0.5, bounds);
            cmds.push(Command::SetAxis(axis));
        }
        if ui.button("Whole plan").clicked() {
            cmds.push(Command::SetAxis(TimeAxis::new(bounds.0, bounds.1)));
        }
    });
}

/// "Discard unsaved changes?", or save them first.
fn confirm_ui(ui: &mut egui::Ui, m: &Model<'_>, cmds: &mut Vec<Command>) {
    let Some(pending) = &m.messages.confirm else {
        return;
    };
    let (what, save_and) = match pending {
        Pending::Open(p) => (format!("open {}", p.display()), "Save and open"),
        Pending::OpenTutorial => (
            "open the tutorial plan for the guided tour".to_string(),
            "Save and open",
        ),
        Pending::Quit => ("quit".to_string(), "Save and quit"),
    };
    egui::Modal::new(egui::Id::unique("confirm_discard")).show(ui.ctx(), |ui| {
        ui.heading("Unsaved changes");
        ui.label(format!(
            "The plan has unsaved edits. Save them, or discard them and {what}?"
        ));
        if m.doc.path.is_none() {
            ui.label(RichText::new("It has no file yet: saving asks where.").color(m.theme.muted));
        }
        ui.horizontal(|ui| {
            if ui.button(save_and).clicked() {
                cmds.push(Command::SaveAndContinue);
            }
            if ui.button("Discard changes").clicked() {
                cmds.push(Command::ConfirmDiscard(true));
            }
            if ui.button("Keep editing").clicked() {
                cmds.push(Command::ConfirmDiscard(false));
            }
        });
    });
}

/// No file dialog could be shown: say why and take a typed path.
fn path_prompt_ui(ui: &mut egui::Ui, m: &Model<'_>, path: &mut String, cmds: &mut Vec<Command>) {
    let Some(prompt) = &m.messages.path_prompt else {
        return;
    };
    let dialog = prompt.dialog;
    let modal = egui::Modal::new(egui::Id::unique("path_prompt")).show(ui.ctx(), |ui| {
        ui.set_max_width(PROMPT_WIDTH);
        ui.heading(dialog.title());
        ui.add(egui::Label::new(prompt.why.as_str()).wrap());
        ui.label("Type the path of the file instead:");
        let label = ui.label("Path");
        let field = ui
            .add(egui::TextEdit::singleline(path).desired_width(PROMPT_WIDTH))
            .labelled_by(label.id);
        let enter = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        ui.horizontal(|ui| {
            let go = ui.button(dialog.action()).clicked() || enter;
            if go {
                if path.trim().is_empty() {
                    cmds.push(Command::ShowError(format!(
                        "{}: type a path",
                        dialog.title()
                    )));
                } else {
                    cmds.push(Command::Chosen {
                        dialog,
                        path: path.trim().into(),
                    });
                }
            }
            if ui.button("Cancel").clicked() {
                cmds.push(Command::DialogCancelled);
            }
        });
    });
    if modal.should_close() {
        cmds.push(Command::DialogCancelled);
    }
}
