//! Gantt rows as of the current step: generated awake and heating rows, comm
//! passes, scheduled activities packed into lanes, failed ones, and pending ones
//! drawn as their allowed windows. Bars narrower than a pixel are merged, bars
//! outside the view culled, so 10k activities stay fluid.
//!
//! In execution mode: the cycles and broken limits as markers, the executed
//! awake periods, each activity's executed bar over a thin bar of where the
//! first cycle predicted it, and the looked-at cycle's run as of the step shown.
//!
//! `layout` builds the rows (`execution` those of execution mode), kept
//! between frames in [`GanttRows`]; `bars` draws them, `ruler` the time
//! around them, `hover` the tooltips, `drag` what dragging does and `tune`
//! the tuned schedule over the original.

mod bars;
mod drag;
mod execution;
mod hover;
mod layout;
mod ruler;
#[cfg(test)]
mod tests;
mod tune;

pub use drag::BarDrag;
pub use ruler::ruler_ui;

use eframe::egui::{self, Color32, Pos2, Rect, Sense};

use crate::gui::theme::LANE_GAP;
use crate::gui::views::{Model, ViewCache, flex};
use crate::state::Command;
use crate::state::execution::ExecutionRun;
use crate::state::{Mode, Status};
use bars::Canvas;
use layout::Row;

/// What the rows were built for: revision, grouping, palette, the
/// flexibility layer, the failed rows unfolded and, in execution mode, the
/// step, the actuals, cycle, its step, and which parts were derived.
#[derive(Clone, Copy, Debug, PartialEq)]
struct RowsKey {
    revision: u64,
    step: usize,
    by_resource: bool,
    palette: Color32,
    /// The flexibility layer was shown (how far each bar's layer reaches).
    flex: bool,
    /// The failed and skipped activities have a row each however many.
    unfold: bool,
    exec: Option<(u64, usize, usize, bool, bool)>,
}

/// The rows, kept between frames: building them sorts and packs every
/// activity, which at 10k activities costs more than drawing them. In
/// schedule mode they are laid out once per schedule, the generated rows
/// too (each bar knows the steps it is drawn after), so moving the step
/// builds nothing.
#[derive(Clone, Debug)]
pub struct GanttRows {
    key: RowsKey,
    rows: Vec<Row>,
}

impl GanttRows {
    /// The rows drawn after step `k`, top to bottom.
    fn shown(&self, k: usize) -> Vec<&Row> {
        self.rows.iter().filter(|r| r.shown_at(k)).collect()
    }
}

/// The Gantt chart.
pub fn gantt_ui(ui: &mut egui::Ui, m: &Model<'_>, cache: &mut ViewCache, cmds: &mut Vec<Command>) {
    let Some(run) = execution_ui(ui, m) else {
        return;
    };
    if run.is_some() {
        execution::legend_ui(ui, m);
    } else if m.flex_shown() {
        flex::legend_ui(ui, m);
    }
    if run.is_none() && cache.gantt_revealed != Some(m.nav.selected) {
        // A failed or skipped activity selected (from the list, a search, a
        // link) is shown in a row of its own.
        let k = m.nav.step;
        if m.nav
            .selected
            .is_some_and(|a| matches!(m.status(a, k), Status::Failed | Status::Skipped))
        {
            cache.failed_unfolded = true;
        }
    }
    let gantt = rows_of(m, run, cache);
    let k = m.nav.step;
    fold_ui(ui, &gantt.rows, k, cache);
    let rows = gantt.shown(k);
    let height: f32 = rows.iter().map(|r| r.height + LANE_GAP).sum::<f32>() + 4.0;
    let (rect, response) = ui.allocate_exact_size(
        egui::vec2(ui.available_width(), height),
        Sense::click_and_drag(),
    );
    // No hover text while a bar is dragged or a question is asked (it would
    // cover the popup's buttons).
    let quiet = cache.drag.is_some() || m.messages.pin.is_some() || m.messages.confirm.is_some();
    response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Image, true, "Gantt chart"));
    // Share the plots' data area (last frame) so one time is one x everywhere.
    let timeline = ruler::timeline_of(rect, cache);
    let painter = ui.painter_at(rect);
    ruler::sol_lines(&painter, m, rect, timeline);
    reveal_ui(ui, m, cache, &rows, (rect.top(), timeline));
    let mut canvas = Canvas::new(
        m,
        cache,
        painter.clone(),
        (timeline, response.hover_pos()),
        run,
    );
    canvas.rows_ui(ui, &rows, rect);
    if run.is_none() {
        tune::overlay(&painter, m, &rows, rect.top(), timeline);
    }
    ruler::time_lines(&painter, m, run, timeline);
    hover::tooltip_ui(m, &response, canvas.hovered.take(), quiet, cmds);
    let frame = (&painter, timeline);
    drag::drag_ui(ui, m, cache, &response, frame, &canvas.drawn, cmds);
    drag::pan_zoom(ui, m, &response, cache.drag.is_some(), timeline, cmds);
    cache.gantt = Some(gantt);
    cache.bars = canvas.drawn;
    cache.looks = canvas.looks;
}

/// With more failed or skipped activities than fit a glance, the button that
/// gives each its own row, or folds them into one again.
fn fold_ui(ui: &mut egui::Ui, rows: &[Row], k: usize, cache: &mut ViewCache) {
    let n = layout::failed_shown(rows, k);
    if n <= layout::FOLD_FAILED_OVER {
        return;
    }
    let text = if cache.failed_unfolded {
        format!("Fold the {n} failed and skipped activities into one row")
    } else {
        format!("Show each of the {n} failed and skipped activities in its own row")
    };
    if ui.button(text).clicked() {
        cache.failed_unfolded = !cache.failed_unfolded;
        ui.ctx().request_repaint();
    }
}

/// The execution drawn in execution mode (`Some(None)` in schedule mode),
/// or `None` when there is none yet or it failed, said in its place.
fn execution_ui<'a>(ui: &mut egui::Ui, m: &Model<'a>) -> Option<Option<&'a ExecutionRun>> {
    match m.nav.mode {
        Mode::Schedule => Some(None),
        Mode::Execution => match m.exec.run {
            Some(Ok(run)) => Some(Some(run.as_ref())),
            Some(Err(_)) => {
                ui.label("No execution to draw (see the error above).");
                None
            }
            None => {
                ui.horizontal(|ui| {
                    ui.spinner();
                    ui.label("executing the plan…");
                });
                None
            }
        },
    }
}

/// The rows to draw: those kept from the last frame when they were built
/// for the same, else built again (in schedule mode the generated rows
/// whenever the step moved).
fn rows_of(m: &Model<'_>, run: Option<&ExecutionRun>, cache: &mut ViewCache) -> GanttRows {
    let k = m.nav.step;
    let key = RowsKey {
        revision: m.revision,
        step: run.map_or(0, |_| k),
        by_resource: m.persisted.by_resource,
        palette: m.theme.scheduled,
        flex: m.flex_layer().is_some(),
        unfold: cache.failed_unfolded,
        exec: run.map(|_| {
            (
                m.exec.actuals_rev,
                m.exec.cycle,
                m.exec.step,
                m.exec.cycle_run.is_some(),
                m.exec.view.is_some(),
            )
        }),
    };
    let rows = match cache.gantt.take() {
        Some(cached) if cached.key == key => cached.rows,
        _ => match run {
            Some(run) => execution::execution_rows(m, run),
            None => {
                let mut rows = layout::generated_rows(m);
                rows.extend(layout::schedule_rows(m, cache.failed_unfolded));
                rows
            }
        },
    };
    GanttRows { key, rows }
}

/// A new selection: its row scrolled into view (its time range was moved to
/// it when it was selected).
fn reveal_ui(
    ui: &egui::Ui,
    m: &Model<'_>,
    cache: &mut ViewCache,
    rows: &[&Row],
    (top, timeline): (f32, Rect),
) {
    if cache.gantt_revealed == Some(m.nav.selected) {
        return;
    }
    cache.gantt_revealed = Some(m.nav.selected);
    if let Some(r) = m
        .nav
        .selected
        .and_then(|a| row_of(m, rows, a, top, timeline))
    {
        ui.scroll_to_rect(r, None);
    }
}

/// Where activity `a`'s row is on screen (the Gantt's top at `top`), at its
/// bar when that is in view: its placement, else its first window, else any
/// bar of its own (not a heater's).
fn row_of(m: &Model<'_>, rows: &[&Row], a: usize, top: f32, timeline: Rect) -> Option<Rect> {
    let id = &m.doc.plan.activities.get(a)?.id;
    let mut best: Option<(u8, Rect)> = None;
    let mut offset = 0.0_f32;
    for row in rows {
        let y = top + offset;
        offset += row.height + LANE_GAP;
        let k = m.nav.step;
        for bar in row
            .bars
            .iter()
            .filter(|b| b.activity == Some(a) && b.shown_at(k))
        {
            let rank = match (bar.placed, bar.outline) {
                (true, _) => 0,
                (_, true) => 1,
                _ if bar.label == *id => 2,
                _ => continue,
            };
            if best.is_some_and(|(r, _)| r <= rank) {
                continue;
            }
            let axis = m.nav.axis;
            let x0 = (axis.x(bar.start, timeline) as f32).clamp(timeline.left(), timeline.right());
            let x1 = (axis.x(bar.end, timeline) as f32).clamp(x0, timeline.right());
            let r = Rect::from_min_max(
                Pos2::new(x0, y),
                Pos2::new(x1.max(x0 + 1.0), y + row.height),
            );
            best = Some((rank, r));
        }
    }
    best.map(|(_, r)| r)
}
