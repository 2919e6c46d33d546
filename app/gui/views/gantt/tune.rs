//! The tuned schedule over the original (schedule mode, while a tuning
//! result is shown with its overlay on): in the row where each activity is
//! drawn, a thin bar under the original's where the tuned plan's predicted
//! schedule places it, and a cross where the tuned plan leaves out an
//! activity the original places.

use eframe::egui::{self, Painter, Pos2, Rect, Stroke};

use super::layout::Row;
use crate::gui::theme::LANE_GAP;
use crate::gui::views::Model;
use crate::gui::views::tune::tuned_color;

/// Share of a row's height the tuned bar takes, at its bottom.
const TUNED_SHARE: f32 = 0.38;
/// Stroke of the tuned bar's outline and of the cross.
const TUNED_STROKE: f32 = 1.5;

/// Draws the tuned schedule over `rows` (drawn from `top` on `timeline`).
pub(super) fn overlay(painter: &Painter, m: &Model<'_>, rows: &[&Row], top: f32, timeline: Rect) {
    let Some(r) = m.tune.overlay() else {
        return;
    };
    let n = m.doc.plan.activities.len();
    // Per activity, the row it is drawn in: its placement's, else its first
    // window's (rank, y, height).
    let mut at: Vec<Option<(u8, f32, f32)>> = vec![None; n];
    let mut y = top;
    let k = m.nav.step;
    for row in rows {
        for bar in row.bars.iter().filter(|b| b.shown_at(k)) {
            let Some(a) = bar.activity.filter(|&a| a < n) else {
                continue;
            };
            let rank = match (bar.placed, bar.outline) {
                (true, _) => 0,
                (_, true) => 1,
                _ => continue,
            };
            if at[a].is_none_or(|(r, _, _)| rank < r) {
                at[a] = Some((rank, y, row.height));
            }
        }
        y += row.height + LANE_GAP;
    }
    let axis = m.nav.axis;
    let x = |t: i64| axis.x(t as f64, timeline) as f32;
    let color = tuned_color(&m.theme);
    for (a, row) in at.iter().enumerate() {
        let Some((_, y, h)) = *row else {
            continue;
        };
        let strip = |x0: f32, x1: f32| {
            Rect::from_min_max(
                Pos2::new(x0, y + h * (1.0 - TUNED_SHARE)),
                Pos2::new(x1.max(x0 + 2.0), y + h),
            )
        };
        match r.tuned_placements.get(a).copied().flatten() {
            Some((s, e)) => {
                let (x0, x1) = (x(s), x(e));
                if x1 < timeline.left() || x0 > timeline.right() {
                    continue;
                }
                let bar = strip(x0, x1);
                painter.rect_filled(bar, 1.0, color.gamma_multiply(0.55));
                painter.rect_stroke(
                    bar,
                    1.0,
                    Stroke::new(TUNED_STROKE, color),
                    egui::StrokeKind::Inside,
                );
            }
            None => {
                // Placed by the original only: crossed out where it was.
                let Some((s, e)) = m.analysis.placement(a) else {
                    continue;
                };
                let c = Pos2::new((x(s) + x(e)) / 2.0, y + h / 2.0);
                if c.x < timeline.left() || c.x > timeline.right() {
                    continue;
                }
                let d = h * 0.4;
                let stroke = Stroke::new(TUNED_STROKE, m.theme.failed);
                painter.line_segment([c + egui::vec2(-d, -d), c + egui::vec2(d, d)], stroke);
                painter.line_segment([c + egui::vec2(-d, d), c + egui::vec2(d, -d)], stroke);
            }
        }
    }
}
