//! The Gantt's time: the timeline it shares with the plots, the ruler above
//! its rows (round local times of day and labelled sol boundaries), the sol
//! boundaries behind the rows and the lines of the looked-at cycle and the
//! probe over them.

use eframe::egui::{self, Align2, FontId, Painter, Pos2, Rect, Sense, Stroke};

use crate::gui::theme::{
    BAR_FONT_SIZE, CYCLE_LINE_STROKE, LABEL_WIDTH, PROBE_LINE_STROKE, RULER_HEIGHT,
    SOL_LINE_STROKE, TICK_GAP, TICK_LENGTH,
};
use crate::gui::time_axis::ticks;
use crate::gui::views::{Model, ViewCache};
use crate::state::execution::ExecutionRun;

/// The timeline part of `rect`: the plots' data area of the last frame (so one
/// time is one x on the ruler, the bars and the plots), else right of the labels.
pub(super) fn timeline_of(rect: Rect, cache: &ViewCache) -> Rect {
    let (left, right) = cache
        .plot_x
        .filter(|(l, r)| *l > rect.left() && *r <= rect.right() + 1.0 && r > l)
        .unwrap_or((rect.left() + LABEL_WIDTH, rect.right()));
    Rect::from_min_max(Pos2::new(left, rect.top()), Pos2::new(right, rect.bottom()))
}

/// The Gantt's time ruler, above its scrolling rows so it stays in view: round
/// local times of day and labelled sol boundaries (`time_axis::ticks`).
pub fn ruler_ui(ui: &mut egui::Ui, m: &Model<'_>, cache: &ViewCache) {
    let (rect, _) = ui.allocate_exact_size(
        egui::vec2(ui.available_width(), RULER_HEIGHT),
        Sense::hover(),
    );
    let timeline = timeline_of(rect, cache);
    let painter = ui.painter_at(rect);
    let font = FontId::proportional(BAR_FONT_SIZE);
    let axis = m.nav.axis;
    let width = f64::from(timeline.width());
    for tick in ticks(&axis, width, &m.doc.plan.local_time, TICK_GAP) {
        let x = axis.x(tick.t, timeline) as f32;
        let (top, colour) = if tick.sol_start {
            (rect.top(), m.theme.label)
        } else {
            (rect.bottom() - TICK_LENGTH, m.theme.muted)
        };
        painter.line_segment(
            [Pos2::new(x, top), Pos2::new(x, rect.bottom())],
            Stroke::new(SOL_LINE_STROKE, colour),
        );
        if !tick.label.is_empty() {
            painter.text(
                Pos2::new(x + 2.0, rect.center().y),
                Align2::LEFT_CENTER,
                &tick.label,
                font.clone(),
                colour,
            );
        }
    }
    painter.text(
        Pos2::new(rect.left() + 2.0, rect.center().y),
        Align2::LEFT_CENTER,
        "local time",
        font,
        m.theme.muted,
    );
}

/// Sol boundaries as lines behind the rows in `rect` (the ruler above labels
/// them).
pub(super) fn sol_lines(painter: &Painter, m: &Model<'_>, rect: Rect, timeline: Rect) {
    let axis = m.nav.axis;
    for tick in ticks(
        &axis,
        f64::from(timeline.width()),
        &m.doc.plan.local_time,
        TICK_GAP,
    )
    .iter()
    .filter(|t| t.sol_start)
    {
        let x = axis.x(tick.t, timeline) as f32;
        painter.line_segment(
            [Pos2::new(x, rect.top()), Pos2::new(x, rect.bottom())],
            Stroke::new(SOL_LINE_STROKE, m.theme.muted.gamma_multiply(0.5)),
        );
    }
}

/// Over the rows: the looked-at cycle's time (execution mode), and the
/// probed time (in execution mode the looked-at cycle has the highlight
/// colour).
pub(super) fn time_lines(
    painter: &Painter,
    m: &Model<'_>,
    run: Option<&ExecutionRun>,
    timeline: Rect,
) {
    let axis = m.nav.axis;
    if let Some(run) = run {
        if let Some(c) = run.execution.cycles.get(m.exec.cycle) {
            let x = axis.x(c.time as f64, timeline) as f32;
            if timeline.x_range().contains(x) {
                painter.vline(
                    x,
                    timeline.y_range(),
                    Stroke::new(CYCLE_LINE_STROKE, m.theme.current),
                );
            }
        }
    }
    if let Some(t) = m.nav.probe {
        let x = axis.x(t as f64, timeline) as f32;
        let color = if run.is_some() {
            m.theme.muted
        } else {
            m.theme.current
        };
        painter.vline(x, timeline.y_range(), Stroke::new(PROBE_LINE_STROKE, color));
    }
}
