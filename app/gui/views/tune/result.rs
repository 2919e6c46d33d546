//! A tuning's detail: the changes with their reasons, and each activity's
//! completed share on the held-out sample as paired bars, the original's over
//! the tuned one's (the activities whose share moved first). Clicking an
//! activity selects it.

use eframe::egui::{self, Pos2, Rect, RichText, Sense, Stroke};

use super::super::Model;
use super::super::text::percent;
use super::tuned_color;
use crate::gui::theme::BAR_OUTLINE_STROKE;
use crate::state::Command;
use crate::state::tune::TuneResult;

/// Width of a share bar.
const BAR_WIDTH: f32 = 140.0;
/// Height of one of the paired bars.
const BAR_HEIGHT: f32 = 6.0;
/// Gap between the paired bars.
const BAR_GAP: f32 = 2.0;

/// The changes and the shares, side by side.
pub(super) fn result_ui(ui: &mut egui::Ui, m: &Model<'_>, r: &TuneResult, cmds: &mut Vec<Command>) {
    ui.columns(2, |cols| {
        if let [left, right] = cols {
            changes_ui(left, m, r, cmds);
            shares_ui(right, m, r, cmds);
        }
    });
}

/// Each priority changed, with why.
fn changes_ui(ui: &mut egui::Ui, m: &Model<'_>, r: &TuneResult, cmds: &mut Vec<Command>) {
    let n = r.tuning.changes.len();
    ui.label(RichText::new(format!("Changes ({n})")).strong());
    for (c, why) in r.tuning.changes.iter().zip(&r.reasons) {
        let id = m
            .doc
            .plan
            .activities
            .get(c.activity)
            .map_or("?", |a| a.id.as_str());
        let head = format!("{id}: priority {} → {}", c.before, c.after);
        if ui
            .selectable_label(m.nav.selected == Some(c.activity), head)
            .on_hover_text("Select it")
            .clicked()
        {
            cmds.push(Command::Select(Some(c.activity)));
        }
        ui.indent(("tune_why", c.activity), |ui| {
            // A sentence, not stretched to the column's width.
            ui.with_layout(egui::Layout::top_down(egui::Align::Min), |ui| {
                ui.add(egui::Label::new(RichText::new(why).color(m.theme.muted)).wrap());
            });
        });
    }
}

/// Per activity, its completed share before and after on the held-out
/// sample.
fn shares_ui(ui: &mut egui::Ui, m: &Model<'_>, r: &TuneResult, cmds: &mut Vec<Command>) {
    let t = &r.tuning;
    let runs = t.held_out.runs;
    ui.horizontal(|ui| {
        ui.label(RichText::new("Completed, held-out runs").strong());
        legend(ui, m.theme.predicted, "original");
        legend(ui, tuned_color(&m.theme), "tuned");
    });
    // The activities whose share moved first (the largest change first),
    // then the rest in file order.
    let mut order: Vec<usize> = (0..t.counts.len()).collect();
    let delta = |a: usize| {
        let c = &t.counts[a];
        i128::from(c.held_out_after.completed) - i128::from(c.held_out_before.completed)
    };
    order.sort_by_key(|&a| (delta(a) == 0, -delta(a).abs(), a));
    egui::Grid::new("tune_shares")
        .num_columns(3)
        .min_col_width(0.0)
        .show(ui, |ui| {
            for a in order {
                let Some(act) = m.doc.plan.activities.get(a) else {
                    continue;
                };
                let c = &t.counts[a];
                let (before, after) = (c.held_out_before.completed, c.held_out_after.completed);
                if ui
                    .selectable_label(m.nav.selected == Some(a), act.id.as_str())
                    .on_hover_text("Select it")
                    .clicked()
                {
                    cmds.push(Command::Select(Some(a)));
                }
                let text = format!(
                    "{}: completed {} → {} of {runs} held-out runs",
                    act.id,
                    percent(before, runs),
                    percent(after, runs)
                );
                paired_bars(ui, m, (before, after), runs, text);
                let moved = if after > before {
                    m.theme.valid
                } else if after < before {
                    m.theme.failed
                } else {
                    m.theme.muted
                };
                ui.colored_label(
                    moved,
                    format!("{} → {}", percent(before, runs), percent(after, runs)),
                );
                ui.end_row();
            }
        });
}

/// A swatch and its name.
fn legend(ui: &mut egui::Ui, color: egui::Color32, name: &str) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(10.0, BAR_HEIGHT), Sense::hover());
    ui.painter().rect_filled(rect, 0.0, color);
    ui.label(name);
}

/// The original's share over the tuned one's, `text` on hover and as the
/// accessibility label.
fn paired_bars(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    (before, after): (u64, u64),
    runs: u64,
    text: String,
) {
    let size = egui::vec2(BAR_WIDTH, BAR_HEIGHT * 2.0 + BAR_GAP);
    let (rect, resp) = ui.allocate_exact_size(size, Sense::hover());
    resp.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Image, true, &text));
    if ui.is_rect_visible(rect) {
        let painter = ui.painter_at(rect);
        let total = runs.max(1) as f32;
        for (i, (n, color)) in [(before, m.theme.predicted), (after, tuned_color(&m.theme))]
            .into_iter()
            .enumerate()
        {
            let top = rect.top() + i as f32 * (BAR_HEIGHT + BAR_GAP);
            let track = Rect::from_min_size(
                Pos2::new(rect.left(), top),
                egui::vec2(BAR_WIDTH, BAR_HEIGHT),
            );
            let w = BAR_WIDTH * n as f32 / total;
            if n > 0 {
                let fill = Rect::from_min_size(track.min, egui::vec2(w.max(1.0), BAR_HEIGHT));
                painter.rect_filled(fill, 0.0, color);
            }
            painter.rect_stroke(
                track,
                0.0,
                Stroke::new(BAR_OUTLINE_STROKE, m.theme.muted),
                egui::StrokeKind::Inside,
            );
        }
    }
    resp.on_hover_text(text);
}
