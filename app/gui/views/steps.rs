//! The step slider (schedule mode, and inside a cycle's run in execution
//! mode): the step buttons, play, the slider zoomed over part of a long run,
//! the wheel over it, and the failure ticks under it.

use eframe::egui::{self, RichText};

use super::Model;
use super::controls::{command_button, shortcut_button};
use crate::gui::theme::{
    FAILURE_TICK_HEIGHT, FAILURE_TICK_STROKE, STEP_LABEL_MIN_WIDTH, STEP_PICK_POINTS,
    STEP_SLIDER_WIDTH,
};
use crate::state::{Command, MIN_STEPS_SHOWN, Mode, Status, StepWindow, UiCommand, failed_steps};

/// The step slider and its buttons (schedule mode).
pub(super) fn steps_ui(ui: &mut egui::Ui, m: &Model<'_>, cmds: &mut Vec<Command>) {
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

/// Step buttons, play, and the slider over steps `0..=n` at step `k` (`(n, k)`)
/// with a tick at each step in `failed` (sorted), and what the step shown did
/// (`what(k)`): of the plan's schedule, or in execution mode of the looked-at
/// cycle's run. The text follows the slider in the frame it moves.
///
/// On a run with more steps than the rail can show apart
/// ([`STEP_PICK_POINTS`] a step), the slider spans the steps of
/// [`Navigation::steps_shown`](crate::state::Navigation::steps_shown)
/// (zoomed with buttons or Ctrl+wheel, moved with the wheel): one step of
/// 10,000 is picked with the mouse.
pub(super) fn step_row_ui(
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
pub(super) fn step_wheel(
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
pub(super) fn step_rail(ui: &egui::Ui, rect: egui::Rect) -> (f32, f32) {
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
pub(super) fn failure_ticks(
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
