//! Small drawn pieces more than one view uses: the valid starts per
//! constraint on the time axis (the schedule and execution inspectors), and
//! an activity's completed / aborted / not-run shares as a stacked bar (the
//! activity list, the Monte Carlo panel and the inspector).

use eframe::egui::{self, Pos2, Rect, Sense, Stroke};
use solscope_engine::{ActivitySummary, CategoryIntervals};

use super::Model;
use super::text::percent;
use crate::gui::help;
use crate::gui::theme::{
    BAR_OUTLINE_STROKE, LABEL_WIDTH, SHARE_MIN_WIDTH, SOL_LINE_STROKE, TICK_GAP, TRACK_FONT_SIZE,
    TRACK_LINE_STROKE, TRACK_ROW_GAP, TRACK_ROW_HEIGHT,
};
use crate::gui::time_axis::ticks;

/// One row per category with its valid starts, then their intersection,
/// over a time axis in LMST (the shared time range). As wide as the part of
/// the panel in view, whatever the content beside it: a wide panel's
/// horizontal scroll never cuts the strip at the right edge.
pub fn intervals_ui(ui: &mut egui::Ui, m: &Model<'_>, cats: &[CategoryIntervals]) {
    let row_h = TRACK_ROW_HEIGHT;
    let n = cats.len() + 1;
    let axis_h = TRACK_FONT_SIZE + 2.0 * TRACK_ROW_GAP;
    // The visible width left of the scroll bar (the panel's content may be
    // wider than its view), never more than the layout offers.
    let in_view = ui.clip_rect().right() - ui.cursor().left() - ui.spacing().scroll.bar_width;
    let width = ui.available_width().min(in_view).max(1.0);
    let (rect, resp) = ui.allocate_exact_size(
        egui::vec2(width, n as f32 * (row_h + TRACK_ROW_GAP) + axis_h),
        Sense::hover(),
    );
    resp.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Image, true, STRIP_LABEL));
    // The row under the pointer says what its rule is.
    if let Some(pos) = resp.hover_pos() {
        let row = ((pos.y - rect.top()) / (row_h + TRACK_ROW_GAP)).max(0.0) as usize;
        let text = cats
            .get(row)
            .map_or(help::ALL_TOGETHER, |c| help::category(c.category));
        resp.on_hover_text(text);
    }
    let painter = ui.painter_at(rect);
    let label_w = LABEL_WIDTH.min(rect.width() / 3.0);
    let rows_bottom = rect.top() + n as f32 * (row_h + TRACK_ROW_GAP);
    let track = Rect::from_min_max(
        Pos2::new(rect.left() + label_w, rect.top()),
        Pos2::new(rect.right(), rows_bottom),
    );
    let axis = m.nav.axis;
    let font = egui::FontId::proportional(TRACK_FONT_SIZE);
    let mut inter =
        solscope_engine::IntervalSet::single(m.doc.plan.horizon.start, m.doc.plan.horizon.end);
    let draw = |i: usize, name: &str, set: &solscope_engine::IntervalSet, color: egui::Color32| {
        let y = rect.top() + i as f32 * (row_h + TRACK_ROW_GAP);
        painter.text(
            Pos2::new(rect.left(), y + row_h / 2.0),
            egui::Align2::LEFT_CENTER,
            name,
            font.clone(),
            m.theme.muted,
        );
        painter.line_segment(
            [
                Pos2::new(track.left(), y + row_h / 2.0),
                Pos2::new(track.right(), y + row_h / 2.0),
            ],
            Stroke::new(TRACK_LINE_STROKE, m.theme.muted),
        );
        for iv in set.intervals() {
            let x0 = axis.x(iv.lo as f64, track).max(f64::from(track.left())) as f32;
            let x1 = axis
                .x(iv.hi as f64 + 1.0, track)
                .min(f64::from(track.right())) as f32;
            if x1 >= x0 {
                painter.rect_filled(
                    Rect::from_min_max(Pos2::new(x0, y), Pos2::new(x1.max(x0 + 1.0), y + row_h)),
                    1.0,
                    color,
                );
            }
        }
    };
    for (i, c) in cats.iter().enumerate() {
        inter = inter.intersect(&c.valid);
        draw(i, c.category.name(), &c.valid, m.theme.valid);
    }
    draw(cats.len(), "all together", &inter, m.theme.current);
    time_axis_ui(ui, m, &painter, track, rect.bottom());
}

/// The accessibility label of the valid-starts strip.
pub const STRIP_LABEL: &str = "Valid starts by constraint";

/// Under the valid-starts strip's `track`: a tick at each round LMST time of
/// day and sol start of the time range, labelled where there is room (each
/// label a node of its own for screen readers), down to `bottom`.
fn time_axis_ui(ui: &egui::Ui, m: &Model<'_>, painter: &egui::Painter, track: Rect, bottom: f32) {
    let axis = m.nav.axis;
    let font = egui::FontId::proportional(TRACK_FONT_SIZE);
    let clock = &m.doc.plan.local_time;
    for tick in ticks(&axis, f64::from(track.width()), clock, TICK_GAP) {
        let x = axis.x(tick.t, track) as f32;
        let colour = if tick.sol_start {
            m.theme.label
        } else {
            m.theme.muted
        };
        painter.line_segment(
            [
                Pos2::new(x, track.top()),
                Pos2::new(x, track.bottom() + TRACK_ROW_GAP),
            ],
            Stroke::new(SOL_LINE_STROKE, colour.gamma_multiply(0.4)),
        );
        if tick.label.is_empty() {
            continue;
        }
        let galley = painter.layout_no_wrap(tick.label.clone(), font.clone(), colour);
        // Kept inside the strip: a label past its right end is left out.
        let at = Pos2::new(x + 2.0, bottom - galley.size().y);
        if at.x + galley.size().x > track.right() {
            continue;
        }
        let r = Rect::from_min_size(at, galley.size());
        painter.galley(at, galley, colour);
        let id = ui.scope_id().with(("valid starts tick", tick.t.to_bits()));
        let resp = ui.interact(r, id, Sense::hover());
        resp.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Label, true, &tick.label));
    }
}

/// An activity's completed / aborted / not-run shares of `runs` as a stacked
/// bar of `size`, its numbers on hover (and as its accessibility label).
pub fn share_bar(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    s: &ActivitySummary,
    runs: u64,
    size: egui::Vec2,
) -> egui::Response {
    labelled_share_bar(ui, m, s, runs, size, shares_text(s, runs))
}

/// [`share_bar`] with `text` on hover and as its accessibility label.
pub fn labelled_share_bar(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    s: &ActivitySummary,
    runs: u64,
    size: egui::Vec2,
    text: String,
) -> egui::Response {
    let (rect, resp) = ui.allocate_exact_size(size, Sense::hover());
    resp.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Image, true, &text));
    if ui.is_rect_visible(rect) {
        let painter = ui.painter_at(rect);
        let total = runs.max(1) as f32;
        let mut x = rect.left();
        for (n, color) in [
            (s.completed, m.theme.scheduled),
            (s.aborted, m.theme.aborted),
            (s.not_run, m.theme.failed),
        ] {
            let w = rect.width() * n as f32 / total;
            if n > 0 {
                let r = egui::Rect::from_min_max(
                    egui::pos2(x, rect.top()),
                    egui::pos2((x + w).max(x + SHARE_MIN_WIDTH), rect.bottom()),
                );
                painter.rect_filled(r, 0.0, color);
            }
            x += w;
        }
        painter.rect_stroke(
            rect,
            0.0,
            Stroke::new(BAR_OUTLINE_STROKE, m.theme.muted),
            egui::StrokeKind::Inside,
        );
    }
    resp.on_hover_text(text)
}

/// `drive: completed 180 (90%), aborted 0, not run 20 (10%) of 200 runs`.
pub fn shares_text(s: &ActivitySummary, runs: u64) -> String {
    let part = |n: u64| {
        if n == 0 {
            "0".to_string()
        } else {
            format!("{n} ({})", percent(n, runs))
        }
    };
    format!(
        "{}: completed {}, aborted {}, not run {} of {runs} runs",
        s.id,
        part(s.completed),
        part(s.aborted),
        part(s.not_run)
    )
}
