//! The guided tour's window: the page shown (`state::tour`), in a small window
//! beside what it talks about (not modal: the app stays usable under it), with
//! Back, Next and End tour; what it talks about is outlined when it is a part
//! of the inspector.

use eframe::egui::{self, Align2, Pos2, Rect, RichText, Stroke, StrokeKind};

use super::Model;
use crate::gui::theme::{
    TOUR_GAP, TOUR_OUTLINE, TOUR_OUTLINE_ROUNDING, TOUR_SECTION, TOUR_SECTION_GAP, TOUR_WIDTH,
};
use crate::state::tour::{self, Anchor, Facts, Page};
use crate::state::{Command, UiCommand};

/// Where the parts the tour points at were drawn this frame.
#[derive(Clone, Copy, Debug, Default)]
pub struct TourAnchors {
    /// The toolbar with the step slider (top panel).
    pub top: Option<Rect>,
    /// The activity list (left panel).
    pub list: Option<Rect>,
    /// The inspector (right panel).
    pub inspector: Option<Rect>,
    /// The inspector's "Why it did not schedule" heading.
    pub why: Option<Rect>,
    /// The inspector's Involved heading.
    pub involved: Option<Rect>,
    /// The inspector's Suggestions heading.
    pub suggestions: Option<Rect>,
}

/// The label of the tour's Back button.
pub const BACK: &str = "← Back";
/// The label of the tour's Next button.
pub const NEXT: &str = "Next →";

/// The guided tour's window, while the tour is shown.
pub fn tour_ui(ui: &egui::Ui, m: &Model<'_>, anchors: &TourAnchors, cmds: &mut Vec<Command>) {
    let Some(t) = &m.messages.tour else {
        return;
    };
    let n = Page::ALL.len();
    let k = t.page.min(n - 1);
    let page = Page::at(k);
    let target = t
        .target
        .as_ref()
        .and_then(|id| m.doc.plan.activities.iter().position(|a| &a.id == id));
    let facts = Facts {
        plan: &m.doc.plan,
        analysis: m.analysis,
        target,
        explanation: m.explanation,
        suggestions: m.suggestions.filter(|_| m.nav.selected == target),
        can_undo: m.doc.can_undo(),
    };
    let text = tour::text(page, &facts);
    let screen = ui.ctx().content_rect();
    let top = anchors.top.unwrap_or(screen);
    let inspector = anchors.inspector.unwrap_or(screen);
    // Beside the inspector, level with the section from `heading` down to
    // the next heading (or a little below it), which is outlined.
    let beside_inspector = |heading: Option<Rect>, next: Option<Rect>| {
        let y = heading.map_or(inspector.top(), |r| r.top());
        let section = heading.map(|h| {
            let bottom = next
                .map_or(h.bottom() + TOUR_SECTION, |n| n.top() - TOUR_SECTION_GAP)
                .min(inspector.bottom());
            Rect::from_x_y_ranges(inspector.x_range(), h.top()..=bottom.max(h.bottom()))
        });
        (
            Pos2::new(inspector.left() - TOUR_GAP, y),
            Align2::RIGHT_TOP,
            section,
        )
    };
    let (pos, pivot, outline) = match page.anchor() {
        Anchor::StepSlider => (
            Pos2::new(top.center().x, top.bottom() + TOUR_GAP),
            Align2::CENTER_TOP,
            None,
        ),
        Anchor::Toolbar => (
            Pos2::new(top.left() + TOUR_GAP, top.bottom() + TOUR_GAP),
            Align2::LEFT_TOP,
            None,
        ),
        Anchor::List => {
            let list = anchors.list.unwrap_or(screen);
            (
                Pos2::new(list.right() + TOUR_GAP, top.bottom() + TOUR_GAP),
                Align2::LEFT_TOP,
                None,
            )
        }
        Anchor::Why => beside_inspector(anchors.why, anchors.involved.or(anchors.suggestions)),
        Anchor::Involved => beside_inspector(anchors.involved, anchors.suggestions),
        Anchor::Suggestions => beside_inspector(anchors.suggestions, None),
    };
    // Only the part in view (the inspector scrolls).
    let outline = outline
        .map(|r| {
            r.shrink2(egui::vec2(TOUR_OUTLINE * 2.0, 0.0))
                .intersect(inspector)
        })
        .filter(|r| r.is_positive());
    if let Some(r) = outline {
        ui.ctx()
            .layer_painter(egui::LayerId::new(
                egui::Order::Foreground,
                egui::Id::unique("guided_tour_outline"),
            ))
            .rect_stroke(
                r,
                TOUR_OUTLINE_ROUNDING,
                Stroke::new(TOUR_OUTLINE, m.theme.tour),
                StrokeKind::Outside,
            );
    }
    egui::Window::new(format!("Guided tour ({} of {n})", k + 1))
        .id(egui::Id::unique("guided_tour"))
        .collapsible(false)
        .resizable(false)
        .pivot(pivot)
        .fixed_pos(pos)
        .default_width(TOUR_WIDTH)
        .max_width(TOUR_WIDTH)
        .show(ui.ctx(), |ui| {
            ui.label(RichText::new(page.title()).strong().color(m.theme.tour));
            for p in &text.paragraphs {
                ui.add(egui::Label::new(p.as_str()).wrap());
            }
            if let Some((label, cmd)) = &text.action {
                if ui.button(label.as_str()).clicked() {
                    cmds.push(cmd.clone());
                }
            }
            ui.separator();
            ui.horizontal(|ui| {
                if ui.add_enabled(k > 0, egui::Button::new(BACK)).clicked() {
                    cmds.push(Command::TourPage(k - 1));
                }
                if k + 1 < n && ui.button(NEXT).clicked() {
                    cmds.push(Command::TourPage(k + 1));
                }
                let end = UiCommand::EndTour;
                if ui
                    .button(end.label())
                    .on_hover_text("Help > Guided tour shows it again")
                    .clicked()
                {
                    cmds.push(end.into());
                }
            });
        });
}
