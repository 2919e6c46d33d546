//! What the selected failed activity would have caused, over the state of
//! charge and peak-power plots: the line above a plot that names the dashed
//! profile of the reason shown (with Previous / Next reason when there are
//! several) or the hollow circles of the others'.

use eframe::egui::{self, RichText};
use solscope_engine::format_span;

use crate::gui::views::Model;
use crate::state::Command;
use crate::state::{OverlayPlot, OverlayReason, WouldCause};

/// The name of the line of what `w`'s activity would have caused at reason
/// `r`'s start.
pub(super) fn would_cause_name(m: &Model<'_>, w: &WouldCause, r: &OverlayReason) -> String {
    let id = m
        .doc
        .plan
        .activities
        .get(w.activity)
        .map_or("", |a| a.id.as_str());
    format!("{id} if placed at {}", m.time(r.start))
}

/// The lines above a plot that say what the selected failed activity would
/// have caused on it (their accessible names too): the dashed profile of the
/// reason shown when it is on this plot, with Previous / Next reason to go
/// through the others when there are several; the hollow circles of the
/// others' violations otherwise.
pub(super) fn would_cause_label(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    w: Option<&WouldCause>,
    plot: OverlayPlot,
    cmds: &mut Vec<Command>,
) {
    let Some(w) = w else {
        return;
    };
    let n = w.reasons.len();
    let on_plot = w.reasons.iter().filter(|r| r.plot == plot).count();
    match w.shown().filter(|r| r.plot == plot) {
        Some(r) => {
            let profile = if w.points.is_empty() {
                "(no profile: it could not be placed there)"
            } else {
                "Dashed:"
            };
            ui.label(
                RichText::new(format!(
                    "{profile} {} for {}: {} at {}",
                    would_cause_name(m, w, r),
                    format_span(r.duration),
                    r.label,
                    m.time(r.at)
                ))
                .color(m.theme.would_cause),
            );
            if n > 1 {
                ui.horizontal_wrapped(|ui| {
                    let go = |index: usize| Command::ShowReason {
                        activity: w.activity,
                        index,
                    };
                    if ui
                        .add_enabled(w.shown > 0, egui::Button::new("Previous reason"))
                        .clicked()
                    {
                        cmds.push(go(w.shown - 1));
                    }
                    ui.label(
                        RichText::new(format!(
                            "reason {} of {n} on energy or peak power: starts {} to {}",
                            w.shown + 1,
                            m.time(r.first),
                            m.time(r.last)
                        ))
                        .color(m.theme.would_cause),
                    );
                    if ui
                        .add_enabled(w.shown + 1 < n, egui::Button::new("Next reason"))
                        .clicked()
                    {
                        cmds.push(go(w.shown + 1));
                    }
                })
                .response
                .on_hover_text(crate::gui::help::OVERLAY_REASONS);
            }
            if on_plot > 1 {
                ui.label(
                    RichText::new(format!(
                        "Hollow circles: where the other {} reason(s) on this plot would \
                         break the limit, each at its own start",
                        on_plot - 1
                    ))
                    .color(m.theme.would_cause),
                );
            }
        }
        None if on_plot > 0 => {
            ui.label(
                RichText::new(format!(
                    "Hollow circles: where {on_plot} reason(s) of {} on this plot would break \
                     the limit (Next reason draws each one's profile)",
                    m.doc
                        .plan
                        .activities
                        .get(w.activity)
                        .map_or("", |a| a.id.as_str()),
                ))
                .color(m.theme.would_cause),
            );
        }
        None => {}
    }
}
