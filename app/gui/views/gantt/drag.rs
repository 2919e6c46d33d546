//! Dragging on the Gantt: with the flexibility layer, a placed bar dragged
//! to another start is previewed as a ghost snapping to its bounds and slack
//! edges, with a label saying where it is; dropped outside its slack, it is
//! offered to be pinned there. Dragging elsewhere pans the time range, and
//! Ctrl+wheel (or a pinch) zooms it about the pointer.

use eframe::egui::{self, Painter, Pos2, Rect, RichText, Stroke, StrokeKind};
use solscope_engine::{Flex, FlexActivity};

use crate::gui::theme::{BAR_ROUNDING, GHOST_STROKE};
use crate::gui::views::flex::{self, Slack};
use crate::gui::views::{Model, ViewCache};
use crate::state::Command;

/// A placed bar dragged to another start (schedule mode, with the flexibility
/// layer): previewed as a ghost; dropped outside its slack, offered to be
/// pinned there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BarDrag {
    activity: usize,
    /// The time under the pointer when it was pressed.
    grab: f64,
    /// Its scheduled start.
    start: i64,
    /// Its scheduled duration.
    duration: i64,
    /// Its lane on screen (top, height).
    y: f32,
    h: f32,
    /// The start it is dragged to.
    to: i64,
}

/// A bar's drag: picked up from the placed bars `drawn` this frame, its
/// ghost and label while it moves, the pin offered when it is dropped
/// outside its slack.
pub(super) fn drag_ui(
    ui: &egui::Ui,
    m: &Model<'_>,
    cache: &mut ViewCache,
    response: &egui::Response,
    (painter, timeline): (&Painter, Rect),
    drawn: &[(usize, Rect)],
    cmds: &mut Vec<Command>,
) {
    let flex_layer = m.flex_layer();
    if response.drag_started() {
        cache.drag = None;
        let press = ui.input(|i| i.pointer.press_origin());
        if let (Some(f), Some(p)) = (flex_layer, press) {
            cache.drag = pick_up(m, f, p, drawn, timeline, cmds);
        }
    }
    let dragging = cache.drag.is_some() && (response.dragged() || response.drag_stopped());
    if !dragging {
        cache.drag = None;
    }
    let drag_flex = cache.drag.and_then(|d| {
        flex_layer
            .and_then(|f| f.activity(d.activity))
            .map(|fa| (d, fa))
    });
    let Some((mut d, fa)) = drag_flex else {
        return;
    };
    let pointer = ui.input(|i| i.pointer.interact_pos());
    if let Some(p) = pointer {
        let axis = m.nav.axis;
        let per_px = axis.seconds_per_pixel(f64::from(timeline.width()));
        let moved = axis.t(f64::from(p.x), timeline) - d.grab;
        let (lo, hi) = (m.doc.plan.horizon.start, m.doc.plan.horizon.end);
        d.to =
            flex::snap(fa, d.start, moved, per_px).clamp(lo, hi.saturating_sub(d.duration).max(lo));
    }
    let kind = ghost_ui(ui, m, response, (painter, timeline), &d, fa, pointer);
    if response.drag_stopped() {
        cache.drag = None;
        if kind == Slack::Outside {
            cmds.push(Command::OfferPin {
                activity: d.activity,
                start: d.to,
            });
        }
    } else {
        cache.drag = Some(d);
    }
}

/// The drag of the placed bar pressed at `p`, if any (selecting it).
fn pick_up(
    m: &Model<'_>,
    f: &Flex,
    p: Pos2,
    drawn: &[(usize, Rect)],
    timeline: Rect,
    cmds: &mut Vec<Command>,
) -> Option<BarDrag> {
    let &(a, r) = drawn.iter().rev().find(|(_, r)| r.contains(p))?;
    let (fa, (s, e)) = f.activity(a).zip(m.analysis.placement(a))?;
    if m.nav.selected != Some(a) {
        cmds.push(Command::Select(Some(a)));
    }
    Some(BarDrag {
        activity: a,
        grab: m.nav.axis.t(f64::from(p.x), timeline),
        start: s,
        duration: e - s,
        y: r.top(),
        h: r.height(),
        to: fa.start.nom,
    })
}

/// The ghost of the dragged bar at its new start, outlined in the colour of
/// where that is, and the label saying so next to it: where it is.
fn ghost_ui(
    ui: &egui::Ui,
    m: &Model<'_>,
    response: &egui::Response,
    (painter, timeline): (&Painter, Rect),
    d: &BarDrag,
    fa: &FlexActivity,
    pointer: Option<Pos2>,
) -> Slack {
    let axis = m.nav.axis;
    let (kind, _) = flex::classify(fa, d.to);
    let color = match kind {
        Slack::Free => m.theme.valid,
        Slack::Bounds => m.theme.current,
        Slack::Outside => m.theme.error,
    };
    let x0 = axis.x(d.to as f64, timeline) as f32;
    let x1 = (axis.x((d.to + d.duration) as f64, timeline) as f32).max(x0 + 2.0);
    let ghost = Rect::from_min_max(Pos2::new(x0, d.y), Pos2::new(x1, d.y + d.h));
    painter.rect_filled(ghost, BAR_ROUNDING, m.theme.ghost);
    painter.rect_stroke(
        ghost,
        BAR_ROUNDING,
        Stroke::new(GHOST_STROKE, color),
        StrokeKind::Outside,
    );
    let text = flex::drag_text(m, fa, d.to);
    // The label next to the ghost, under the lane (the pointer stays free).
    let at = Pos2::new(
        pointer.map_or(ghost.left(), |p| p.x),
        ghost.bottom() + GHOST_STROKE,
    );
    egui::Tooltip::always_open(
        ui.ctx().clone(),
        ui.layer_id(),
        response.id,
        egui::PopupAnchor::Position(at),
    )
    .show(|ui| ui.label(RichText::new(text).color(color)));
    kind
}

/// Pan by dragging (unless a bar is dragged), zoom with Ctrl+wheel (or
/// pinch) about the pointer.
pub(super) fn pan_zoom(
    ui: &egui::Ui,
    m: &Model<'_>,
    response: &egui::Response,
    bar_dragged: bool,
    timeline: Rect,
    cmds: &mut Vec<Command>,
) {
    let axis = m.nav.axis;
    let bounds = (
        m.doc.plan.horizon.start as f64,
        m.doc.plan.horizon.end as f64,
    );
    if response.dragged() && !bar_dragged {
        let dt = -f64::from(response.drag_delta().x)
            * axis.seconds_per_pixel(f64::from(timeline.width()));
        let mut a = axis;
        a.pan(dt, bounds);
        cmds.push(Command::SetAxis(a));
    }
    if response.hovered() {
        let zoom = ui.input(|i| i.zoom_delta());
        if (zoom - 1.0).abs() > f32::EPSILON {
            if let Some(p) = response.hover_pos() {
                let mut a = axis;
                a.zoom_about(axis.t(f64::from(p.x), timeline), f64::from(zoom), bounds);
                cmds.push(Command::SetAxis(a));
            }
        }
    }
}
