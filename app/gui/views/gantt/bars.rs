//! Drawing the Gantt's rows: each row's label, the flexibility layer behind
//! its bars, and the bars themselves: culled to the time range shown,
//! merged below a pixel, skipped when hidden under earlier ones of their
//! colour, faded or outlined with the search and filters, outlined when
//! they are the current step's activity, the selection, a culprit or a
//! dispatchable neighbour, and labelled when there is room.

use std::sync::Arc;

use eframe::egui::{self, Align2, Color32, FontId, Painter, Pos2, Rect, Stroke, StrokeKind};
use solscope_engine::Flex;

use super::hover::{Hovered, hover_of};
use super::layout::{Bar, Row};
use crate::gui::theme::{
    BAR_FONT_SIZE, BAR_ROUNDING, CULPRIT_STROKE, CURRENT_STROKE, DIMMED, HATCH_GAP, HATCH_STROKE,
    LABEL_MIN_WIDTH, LANE_GAP, LANE_HEIGHT, MARKER_WIDTH, MATCH_STROKE, NEIGHBOUR_STROKE,
    SELECTION_STROKE, WINDOW_FILL, WINDOW_HATCH,
};
use crate::gui::views::{Look, Model, ViewCache, flex};
use crate::state::Listed;
use crate::state::execution::ExecutionRun;

/// What drawing the rows needs from the frame, and what it collects: the
/// bar under the pointer, how each activity bar looked, and where each
/// placed bar was drawn (what a drag picks up).
pub(super) struct Canvas<'a, 'm> {
    m: &'a Model<'m>,
    painter: Painter,
    timeline: Rect,
    font: FontId,
    pointer: Option<Pos2>,
    flex_layer: Option<&'a Flex>,
    /// The search and filters, when they select anything.
    listed: Option<Arc<Listed>>,
    /// The selected activity's neighbours in the minimum dispatchable network.
    neighbours: Vec<usize>,
    /// The culprits of the selected activity's energy or peak-power failure.
    culprits: &'a [usize],
    /// The activity of the step shown (of the looked-at cycle's run in
    /// execution mode).
    current: Option<usize>,
    /// Schedule mode (its activity bars say what happened on hover).
    schedule: bool,
    /// What hovering the bar under the pointer shows.
    pub(super) hovered: Option<Hovered>,
    /// How each activity bar drawn looked with the search and filters.
    pub(super) looks: Vec<(usize, Look)>,
    /// Where each placed bar was drawn.
    pub(super) drawn: Vec<(usize, Rect)>,
}

/// A run of overlapping window bars of one colour, none of them marked: a
/// lone one is drawn as any bar, two or more as one window bar over their
/// union (hatching and outlines stacked up thousands deep in an overflow
/// lane of pending or failed activities' windows cost a frame and show
/// nothing more).
struct Windows<'r> {
    /// The first bar, where it is drawn and how it looks.
    first: (&'r Bar, Rect, Look, Color32),
    /// The union so far.
    span: (f64, f64),
    /// More than the first joined it.
    many: bool,
}

/// One row's bars as they are drawn, left to right.
struct Strip<'r> {
    /// The row's top and height.
    y: f32,
    h: f32,
    /// The row follows the step slider: its current activity is outlined,
    /// its activity bars say what happened on hover.
    steps: bool,
    /// The activity outlined as current in this row.
    current: Option<usize>,
    /// Its bars are labelled where they have room.
    bar_labels: bool,
    /// Bars narrower than a pixel merged so far (one colour).
    merged: Option<(f64, f64, Color32)>,
    /// The contiguous span `[lo, hi]` that the last bars of one colour
    /// painted: a bar of that colour inside it is hidden under earlier ones,
    /// as in an overflow lane holding thousands of failed activities'
    /// windows, so it is skipped unless it is marked.
    painted: (f64, f64, Color32),
    /// Bars the search and filters leave out are context: a run of
    /// overlapping ones is drawn once, as their union, so an overflow lane of
    /// windows stays faded instead of stacking back up to full colour
    /// (`outline`: windows).
    faded: Option<(f64, f64, Color32, bool)>,
    /// The run of overlapping window bars so far.
    windows: Option<Windows<'r>>,
}

impl<'r> Strip<'r> {
    fn new(row: &Row, y: f32, current: Option<usize>) -> Self {
        Self {
            y,
            h: row.height,
            steps: row.steps,
            current: if row.steps { current } else { None },
            bar_labels: row.bar_labels,
            merged: None,
            painted: (f64::INFINITY, f64::NEG_INFINITY, Color32::TRANSPARENT),
            faded: None,
            windows: None,
        }
    }

    /// The row's rect from `x0` to `x1`, at least a pixel wide.
    fn rect(&self, x0: f64, x1: f64) -> Rect {
        Rect::from_min_max(
            Pos2::new(x0 as f32, self.y),
            Pos2::new((x1 as f32).max(x0 as f32 + 1.0), self.y + self.h),
        )
    }

    /// Draws the thin bars merged so far.
    fn flush_merged(&mut self, painter: &Painter) {
        if let Some((x0, x1, c)) = self.merged.take() {
            painter.rect_filled(self.rect(x0, x1), BAR_ROUNDING, c);
        }
    }

    /// Draws the run of faded bars so far.
    fn flush_faded(&mut self, painter: &Painter) {
        if let Some((x0, x1, c, outline)) = self.faded.take() {
            let r = self.rect(x0, x1);
            if outline {
                window_bar(painter, r, c);
            } else {
                painter.rect_filled(r, BAR_ROUNDING, c);
            }
        }
    }

    /// Adds a thin bar: merged with those before it in its pixel column.
    fn merge(&mut self, painter: &Painter, (x0, x1): (f64, f64), color: Color32) {
        match self.merged {
            Some((a, b, c)) if c == color && x0 <= b + 1.0 => {
                self.merged = Some((a, b.max(x1), c));
            }
            _ => {
                self.flush_merged(painter);
                self.merged = Some((x0, x1, color));
            }
        }
    }

    /// Adds a faded bar: one with the run before it when they overlap.
    fn fade(&mut self, painter: &Painter, (x0, x1): (f64, f64), color: Color32, outline: bool) {
        match self.faded {
            Some((a, b, c, o)) if c == color && o == outline && x0 <= b => {
                self.faded = Some((a, b.max(x1), c, o));
            }
            _ => {
                self.flush_faded(painter);
                self.faded = Some((x0, x1, color, outline));
            }
        }
    }
}

impl<'a, 'm> Canvas<'a, 'm> {
    /// Ready to draw on `painter`, over `timeline`, with the pointer at
    /// `pointer`.
    pub(super) fn new(
        m: &'a Model<'m>,
        cache: &ViewCache,
        painter: Painter,
        (timeline, pointer): (Rect, Option<Pos2>),
        run: Option<&ExecutionRun>,
    ) -> Self {
        let flex_layer = m.flex_layer();
        let current = match run {
            Some(_) => m
                .exec
                .cycle_run
                .and_then(|c| c.activity_of_step(m.exec.step)),
            None => m.activity_of_step(m.nav.step),
        };
        Self {
            m,
            painter,
            timeline,
            font: FontId::proportional(BAR_FONT_SIZE),
            pointer,
            flex_layer,
            listed: cache.listed.clone().filter(|l| l.active),
            neighbours: match (flex_layer, m.nav.selected) {
                (Some(f), Some(a)) => flex::neighbours(f, a),
                _ => Vec::new(),
            },
            culprits: m.would_cause.map_or(&[], |w| w.culprits.as_slice()),
            current,
            schedule: run.is_none(),
            hovered: None,
            looks: Vec::new(),
            drawn: Vec::new(),
        }
    }

    /// Every row in view, top to bottom from `rect`'s top, labelled at its
    /// left (the label kept to the label column; a row of one activity's
    /// label is given to screen readers too). Rows scrolled out of view are
    /// skipped: a chart of thousands of rows costs what its visible ones do.
    pub(super) fn rows_ui(&mut self, ui: &egui::Ui, rows: &[&Row], rect: Rect) {
        let clip = self.painter.clip_rect();
        let labels = self
            .painter
            .with_clip_rect(clip.intersect(Rect::from_x_y_ranges(
                rect.left()..=self.timeline.left() - 2.0,
                rect.y_range(),
            )));
        let mut offset = 0.0_f32;
        // The lanes of a group carry its label: drawn on the first one.
        let mut above = "";
        for &row in rows {
            let y = rect.top() + offset;
            offset += row.height + LANE_GAP;
            let first = row.label != above;
            above = &row.label;
            if y + row.height < clip.top() || y > clip.bottom() {
                continue;
            }
            if first && !row.label.is_empty() {
                let r = labels.text(
                    Pos2::new(rect.left() + 2.0, y + row.height / 2.0),
                    Align2::LEFT_CENTER,
                    &row.label,
                    self.font.clone(),
                    self.m.theme.muted,
                );
                if let Some(a) = row.activity {
                    let id = ui.scope_id().with(("gantt row", a));
                    let resp =
                        ui.interact(r.intersect(labels.clip_rect()), id, egui::Sense::hover());
                    resp.widget_info(|| {
                        egui::WidgetInfo::labeled(egui::Role::Label, true, &row.label)
                    });
                    // The label column may cut a long id.
                    resp.on_hover_text(&row.label);
                }
            }
            self.flex_ui(row, y);
            let mut strip = Strip::new(row, y, self.current);
            let (axis, k) = (self.m.nav.axis, self.m.nav.step);
            for bar in row.bars_in(axis.start, axis.end) {
                if bar.shown_at(k) {
                    self.bar_ui(&mut strip, bar);
                }
            }
            self.flush_windows(&mut strip);
            strip.flush_merged(&self.painter);
            strip.flush_faded(&self.painter);
        }
    }

    /// The flexibility layer behind a row's placed bars.
    fn flex_ui(&self, row: &Row, y: f32) {
        let Some(f) = self.flex_layer else {
            return;
        };
        let (m, axis, h) = (self.m, self.m.nav.axis, row.height);
        let k = m.nav.step;
        let in_view = row.extents_in(axis.start, axis.end);
        let mut faded = self.painter.clone();
        faded.multiply_opacity(DIMMED);
        // The plain and the faded layers' whiskers, each joined across the lane.
        let (mut plain_whiskers, mut faded_whiskers) = Default::default();
        for bar in in_view.iter().filter(|b| b.placed && b.shown_at(k)) {
            if bar.extent.1 < axis.start || bar.extent.0 > axis.end {
                continue;
            }
            // A layer narrower than a pixel is under its bar (drawn a pixel
            // wide at least): nothing of it would show.
            if axis.x(bar.extent.1, self.timeline) - axis.x(bar.extent.0, self.timeline) < 1.0 {
                continue;
            }
            if let Some(fa) = bar.activity.and_then(|a| f.activity(a)) {
                let d = (bar.end - bar.start) as i64;
                // Faded with its bar when the search leaves it out.
                let left_out = self.listed.as_ref().is_some_and(|l| !l.shows(fa.activity))
                    && m.nav.selected != Some(fa.activity);
                let (painter, whiskers) = if left_out {
                    (&faded, &mut faded_whiskers)
                } else {
                    (&self.painter, &mut plain_whiskers)
                };
                flex::underlay(painter, m, fa, d, axis, self.timeline, y, h, whiskers);
            }
        }
        let mid = y + h / 2.0;
        faded_whiskers.flush(&faded, m, mid, h);
        plain_whiskers.flush(&self.painter, m, mid, h);
    }

    /// How `bar` looks against the search and filters.
    fn look(&self, bar: &Bar) -> Look {
        match (bar.activity, &self.listed) {
            (Some(a), Some(l)) if l.shows(a) => Look::Highlighted,
            // The selection is never faded, filtered out or not.
            (Some(a), Some(_)) if Some(a) == self.m.nav.selected => Look::Plain,
            (Some(_), Some(_)) => Look::Dimmed,
            _ => Look::Plain,
        }
    }

    /// One bar of the row `s`, when it is in the time range shown.
    fn bar_ui<'r>(&mut self, s: &mut Strip<'r>, bar: &'r Bar) {
        let axis = self.m.nav.axis;
        if bar.end < axis.start || bar.start > axis.end {
            return;
        }
        let look = self.look(bar);
        if let Some(a) = bar.activity {
            self.looks.push((a, look));
        }
        let color = if look == Look::Dimmed {
            bar.color.gamma_multiply(DIMMED)
        } else {
            bar.color
        };
        let timeline = self.timeline;
        let mut x0 = axis.x(bar.start, timeline).max(f64::from(timeline.left()));
        let mut x1 = axis.x(bar.end, timeline).min(f64::from(timeline.right()));
        if bar.marker {
            let w = f64::from(MARKER_WIDTH);
            if x1 - x0 < w {
                let c = (x0 + x1) / 2.0;
                (x0, x1) = (c - w / 2.0, c + w / 2.0);
            }
        } else if !self.stands_alone(s, bar, look, color, (x0, x1)) {
            return;
        }
        let r = Rect::from_min_max(Pos2::new(x0 as f32, s.y), Pos2::new(x1 as f32, s.y + s.h));
        if bar.outline && look == Look::Plain && !self.marked(s, bar) {
            self.window_run(s, (bar, r, look, color), (x0, x1));
            self.hover(bar, r, s.steps);
            return;
        }
        self.flush_windows(s);
        self.paint_bar(bar, r, look, color, s.current);
        if s.bar_labels {
            self.label_ui(bar, r, look, s.h);
        }
        self.hover(bar, r, s.steps);
    }

    /// Whether `bar` is outlined: the current step's activity, the
    /// selection, a culprit or a neighbour.
    fn marked(&self, s: &Strip<'_>, bar: &Bar) -> bool {
        bar.activity.is_some_and(|a| {
            Some(a) == s.current
                || Some(a) == self.m.nav.selected
                || self.culprits.contains(&a)
                || self.neighbours.contains(&a)
        })
    }

    /// Adds an unmarked window bar drawn at `first.1` (`[x0, x1]`) to the
    /// row's run of overlapping ones of its colour, or starts a new run.
    fn window_run<'r>(
        &mut self,
        s: &mut Strip<'r>,
        first: (&'r Bar, Rect, Look, Color32),
        (x0, x1): (f64, f64),
    ) {
        if let Some(w) = s.windows.as_mut() {
            if w.first.3 == first.3 && x0 < w.span.1 {
                w.span.1 = w.span.1.max(x1);
                w.many = true;
                return;
            }
        }
        self.flush_windows(s);
        s.windows = Some(Windows {
            first,
            span: (x0, x1),
            many: false,
        });
    }

    /// Draws the row's run of window bars so far: a lone one as itself,
    /// several as one window bar over their union.
    fn flush_windows(&mut self, s: &mut Strip<'_>) {
        let Some(w) = s.windows.take() else {
            return;
        };
        let (bar, r, look, color) = w.first;
        if w.many {
            window_bar(&self.painter, s.rect(w.span.0, w.span.1), color);
            return;
        }
        self.paint_bar(bar, r, look, color, s.current);
        if s.bar_labels {
            self.label_ui(bar, r, look, s.h);
        }
    }

    /// Whether a bar (not a marker) at `[x0, x1]` is drawn on its own; else
    /// it joined the row's run of faded bars or its merged thin ones, or is
    /// hidden under the bars painted before it.
    fn stands_alone(
        &mut self,
        s: &mut Strip<'_>,
        bar: &Bar,
        look: Look,
        color: Color32,
        (x0, x1): (f64, f64),
    ) -> bool {
        let marked = bar.activity.is_some()
            && (bar.activity == s.current || bar.activity == self.m.nav.selected);
        let neighbour = bar.activity.is_some_and(|a| self.neighbours.contains(&a));
        if look == Look::Dimmed && !marked && !neighbour {
            let r = s.rect(x0, x1);
            if let Some(a) = bar.activity.filter(|_| bar.placed) {
                // Still picked up by a drag.
                self.drawn.push((a, r));
            }
            self.hover(bar, r, s.steps);
            s.fade(&self.painter, (x0, x1), color, bar.outline);
            return false;
        }
        s.flush_faded(&self.painter);
        let (lo, hi, painted_color) = s.painted;
        if color == painted_color && lo <= x0 && x1 <= hi && !marked {
            return false;
        }
        s.painted = if color == painted_color && x0 <= hi && lo <= x1 {
            (lo.min(x0), hi.max(x1), color)
        } else {
            (x0, x1, color)
        };
        if x1 - x0 < 1.0 {
            s.merge(&self.painter, (x0, x1), color);
            return false;
        }
        s.flush_merged(&self.painter);
        true
    }

    /// A bar drawn on its own at `r`: filled (hatched, a window), outlined
    /// as a search match, the current activity, the selection, a culprit or
    /// a neighbour; a placed bar is kept for a drag.
    fn paint_bar(
        &mut self,
        bar: &Bar,
        r: Rect,
        look: Look,
        color: Color32,
        current: Option<usize>,
    ) {
        let (painter, theme) = (&self.painter, &self.m.theme);
        if bar.outline {
            window_bar(painter, r, color);
        } else {
            painter.rect_filled(r, BAR_ROUNDING, color);
        }
        if look == Look::Highlighted {
            outline(painter, r, MATCH_STROKE, theme.highlight);
        }
        let is_current = bar.activity.is_some() && bar.activity == current;
        let is_selected = bar.activity.is_some() && bar.activity == self.m.nav.selected;
        if is_current {
            outline(painter, r, CURRENT_STROKE, theme.current);
        }
        if is_selected {
            outline(painter, r, SELECTION_STROKE, theme.selection);
        }
        if let Some(a) = bar.activity.filter(|_| bar.placed) {
            self.drawn.push((a, r));
            if self.culprits.contains(&a) && !is_selected {
                outline(painter, r, CULPRIT_STROKE, theme.culprit);
            }
            if self.neighbours.contains(&a) && !is_selected {
                outline(painter, r, NEIGHBOUR_STROKE, theme.neighbour);
            }
        }
    }

    /// The bar's label inside it, when it fits.
    fn label_ui(&self, bar: &Bar, r: Rect, look: Look, h: f32) {
        if r.width() < LABEL_MIN_WIDTH || h < LANE_HEIGHT {
            return;
        }
        let label = if look == Look::Dimmed {
            self.m.theme.label.gamma_multiply(DIMMED * 2.0)
        } else {
            self.m.theme.label
        };
        let text = self
            .painter
            .layout_no_wrap(bar.label.clone(), self.font.clone(), label);
        if text.size().x + 4.0 <= r.width() {
            self.painter.galley(
                Pos2::new(r.left() + 2.0, r.center().y - text.size().y / 2.0),
                text,
                label,
            );
        }
    }

    /// The bar drawn at `r` is what hovering shows when the pointer is on it
    /// (the last bar drawn under the pointer wins).
    fn hover(&mut self, bar: &Bar, r: Rect, steps: bool) {
        if self.pointer.is_some_and(|p| r.contains(p)) {
            let steps = steps && self.schedule;
            self.hovered = hover_of(self.m, bar, steps, self.flex_layer).or(self.hovered.take());
        }
    }
}

/// `r` outlined outside in `color`.
fn outline(painter: &Painter, r: Rect, width: f32, color: Color32) {
    painter.rect_stroke(
        r,
        BAR_ROUNDING,
        Stroke::new(width, color),
        StrokeKind::Outside,
    );
}

/// A window bar: a faint fill, diagonal hatching and an outline in `color`.
fn window_bar(painter: &egui::Painter, r: Rect, color: Color32) {
    painter.rect_filled(r, BAR_ROUNDING, color.gamma_multiply(WINDOW_FILL));
    let hatch = painter.with_clip_rect(r.intersect(painter.clip_rect()));
    let stroke = Stroke::new(HATCH_STROKE, color.gamma_multiply(WINDOW_HATCH));
    // Lines x - y = const, HATCH_GAP apart, over the visible part only.
    let visible = r.intersect(painter.clip_rect());
    let mut x = visible.left() - r.height();
    while x < visible.right() {
        hatch.line_segment(
            [Pos2::new(x, r.bottom()), Pos2::new(x + r.height(), r.top())],
            stroke,
        );
        x += HATCH_GAP;
    }
    painter.rect_stroke(
        r,
        BAR_ROUNDING,
        Stroke::new(HATCH_STROKE, color),
        StrokeKind::Inside,
    );
}
