//! One plot of a profile on the shared time axis: its series thinned to
//! the pixels shown, limit lines with their labels, vertical marks, the
//! probe, and the violation points of what a failed activity would have
//! caused; and what the three plots are.

use eframe::egui::{self, Color32, RichText};
use egui_plot::{
    GridInput, GridMark, HLine, Line, LineStyle, MarkerShape, Plot, PlotPoint, PlotPoints, PlotUi,
    Points, Text, VLine,
};
use solscope_engine::Unit;

use super::execution::value_at;
use crate::gui::theme::{
    CYCLE_LINE_STROKE, LABEL_WIDTH, LIMIT_FONT_SIZE, OTHER_VIOLATION_RADIUS, PLOT_HEIGHT, TICK_GAP,
    VALUE_GRID_GAP, VIOLATION_RADIUS,
};
use crate::gui::time_axis::{TimeAxis, tick_label, ticks};
use crate::gui::views::{Model, ViewCache};
use crate::state::Command;
use crate::state::{OverlayPlot, OverlayReason, StepView, WouldCause};

/// One line on a plot.
pub(super) struct Series<'a> {
    pub(super) name: String,
    pub(super) points: &'a [[f64; 2]],
    pub(super) color: Color32,
    pub(super) dashed: bool,
    /// Line width, when not egui_plot's default.
    pub(super) width: Option<f32>,
}

/// Which of a [`StepView`]'s series.
pub(super) type Pick = fn(&StepView) -> &[[f64; 2]];

/// A vertical line across a plot at a time.
pub(super) struct Mark {
    pub(super) name: String,
    pub(super) t: f64,
    pub(super) color: Color32,
}

/// What one plot shows.
pub(super) struct Chart<'a> {
    /// Its name, also its y-axis label (one of [`SOC`], [`PEAK`], [`DATA`]).
    pub(super) id: &'static str,
    /// Its lines.
    pub(super) series: Vec<Series<'a>>,
    /// Its horizontal limit lines: name and value.
    pub(super) limits: Vec<(&'static str, f64)>,
    /// Its vertical marks.
    pub(super) marks: Vec<Mark>,
    /// The failed activity whose violations are marked on it (the shown
    /// reason's filled and labelled, the others' hollow), and which plot
    /// this is.
    pub(super) overlay: Option<(&'a WouldCause, OverlayPlot)>,
}

/// One plot (see [`Chart`]) over the shared time axis; a click probes the
/// time under the pointer.
pub(super) fn plot_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    cache: &mut ViewCache,
    chart: &Chart<'_>,
    cmds: &mut Vec<Command>,
) {
    let Chart {
        id,
        series,
        limits,
        marks,
        overlay,
    } = chart;
    // The failed activity's reasons on this plot, with whether it is the
    // one whose profile is drawn.
    let violations: Vec<(&OverlayReason, bool)> = overlay
        .map(|(w, plot)| {
            w.reasons
                .iter()
                .enumerate()
                .filter(|(_, r)| r.plot == plot)
                .map(|(i, r)| (r, i == w.shown))
                .collect()
        })
        .unwrap_or_default();
    let highest_violation = violations.iter().map(|v| v.0.value).fold(0.0, f64::max);
    let unit = unit_of(id);
    let axis = m.nav.axis;
    let probe = m.nav.probe;
    let width = cache
        .plot_x
        .map_or(f64::from(ui.available_width()), |(l, r)| f64::from(r - l));
    let lines = lines_of(series, axis, width);
    let plot = plot_of(m, id, width, limits, highest_violation);
    let resp = plot.show(ui, |plot_ui| {
        plot_ui.set_plot_bounds_x(axis.start..=axis.end);
        // egui_plot's own aggregation fills bands between buckets, which draws
        // a step function as shaded triangles; `decimate` did the thinning.
        for line in lines {
            plot_ui.line(line);
        }
        limits_ui(plot_ui, m, limits, unit);
        for mark in marks {
            plot_ui.vline(
                VLine::new(mark.name.as_str(), mark.t)
                    .color(mark.color)
                    .width(CYCLE_LINE_STROKE),
            );
        }
        if let Some(t) = probe {
            plot_ui.vline(VLine::new("probe", t as f64));
        }
        violations_ui(plot_ui, m, &violations);
        plot_ui.pointer_coordinate()
    });
    let frame = resp.transform.frame();
    cache.plot_x = Some((frame.left(), frame.right()));
    if resp.response.hovered() {
        if let Some(text) = resp.inner.and_then(|p| readout(m, series, unit, p.x)) {
            egui::Tooltip::for_widget(&resp.response)
                .at_pointer()
                .gap(12.0)
                .show(|ui| ui.label(text));
        }
    }
    if resp.response.clicked() {
        if let Some(p) = resp.inner {
            cmds.push(Command::ProbePlot(Some(p.x.round() as i64)));
        }
    }
}

/// What the plot reads at time `x` (the hovered one): the time, and each
/// series' value there (named when there are several), not the pointer's
/// height; `None` where no series has a value.
pub(super) fn readout(m: &Model<'_>, series: &[Series<'_>], unit: Unit, x: f64) -> Option<String> {
    let t = x.round() as i64;
    let values: Vec<String> = series
        .iter()
        .filter_map(|s| {
            let v = value_at(s.points, t as f64)?;
            Some(if series.len() == 1 {
                unit.format(v)
            } else {
                format!("{}: {}", s.name, unit.format(v))
            })
        })
        .collect();
    (!values.is_empty()).then(|| format!("{}\n{}", m.time(t), values.join("\n")))
}

/// The series as lines, each thinned to what `width` pixels show of the
/// time range (see [`decimate`]).
fn lines_of<'s>(series: &'s [Series<'_>], axis: TimeAxis, width: f64) -> Vec<Line<'s>> {
    series
        .iter()
        .map(|s| {
            let points: PlotPoints = decimate(s.points, axis.start, axis.end, width)
                .into_iter()
                .collect();
            let line = Line::new(s.name.as_str(), points)
                .color(s.color)
                .allow_band(false);
            let line = match s.width {
                Some(w) => line.width(w),
                None => line,
            };
            if s.dashed {
                line.style(LineStyle::dashed_loose())
            } else {
                line
            }
        })
        .collect()
}

/// The plot `id` with the Gantt's time ticks, value grid and time ruler,
/// its value range from 0 up to room above its highest limit line and
/// violation.
fn plot_of(
    m: &Model<'_>,
    id: &str,
    width: f64,
    limits: &[(&str, f64)],
    highest_violation: f64,
) -> Plot<'static> {
    let local = m.doc.plan.local_time;
    // The Gantt ruler's ticks: round local times, sol boundaries thicker.
    Plot::new(id)
        .x_grid_spacer(move |input| {
            let shown = TimeAxis::new(input.bounds.0, input.bounds.1);
            ticks(&shown, width, &local, TICK_GAP)
                .into_iter()
                .map(|t| GridMark {
                    value: t.t,
                    step_size: t.step,
                })
                .collect()
        })
        .x_axis_formatter(move |mark, _range| {
            tick_label(&local, mark.value.round() as i64, mark.step_size)
        })
        .y_grid_spacer(value_grid)
        // No ruler at the pointer's height: the readout (see `readout`) is
        // the profiles' values at the hovered time.
        .show_y(false)
        .height(PLOT_HEIGHT)
        .allow_zoom(false)
        .allow_drag(false)
        .allow_scroll(false)
        .allow_double_click_reset(false)
        .include_y(0.0)
        // Room above the highest limit for its label.
        .include_y(limits.iter().map(|l| l.1).fold(0.0, f64::max) * LIMIT_HEADROOM)
        .include_y(highest_violation * LIMIT_HEADROOM)
        .y_axis_label(id)
        .y_axis_min_width(LABEL_WIDTH - 30.0)
}

/// The limit lines, each with its name and value at its right end: above
/// it, or below when another limit's label sits just above.
fn limits_ui(plot_ui: &mut PlotUi<'_>, m: &Model<'_>, limits: &[(&str, f64)], unit: Unit) {
    let limit_color = m.theme.limit;
    let axis = m.nav.axis;
    let span = plot_ui.plot_bounds().height();
    for &(name, y) in limits {
        plot_ui.hline(HLine::new(name, y).color(limit_color));
        let crowded = limits
            .iter()
            .any(|&(_, other)| other > y && other - y < span * LIMIT_LABEL_ROOM);
        let anchor = if crowded {
            egui::Align2::RIGHT_TOP
        } else {
            egui::Align2::RIGHT_BOTTOM
        };
        plot_ui.text(
            Text::new(
                name,
                PlotPoint::new(axis.end - axis.span() * LIMIT_LABEL_INSET, y),
                RichText::new(format!("{name} {}", unit.format(y))).size(LIMIT_FONT_SIZE),
            )
            .anchor(anchor)
            .color(limit_color),
        );
    }
}

/// The violation points of what the failed activity would have caused on
/// this plot: the other reasons' first, hollow, so the shown one (filled
/// and labelled) is drawn over them.
fn violations_ui(plot_ui: &mut PlotUi<'_>, m: &Model<'_>, violations: &[(&OverlayReason, bool)]) {
    let axis = m.nav.axis;
    let others: Vec<[f64; 2]> = violations
        .iter()
        .filter(|v| !v.1)
        .map(|v| [v.0.at as f64, v.0.value])
        .collect();
    if !others.is_empty() {
        plot_ui.points(
            Points::new("other starts' violations", others)
                .shape(MarkerShape::Circle)
                .filled(false)
                .radius(OTHER_VIOLATION_RADIUS)
                .color(m.theme.would_cause),
        );
    }
    for (r, _) in violations.iter().filter(|v| v.1) {
        let at = PlotPoint::new(r.at as f64, r.value);
        plot_ui.points(
            Points::new("violation", vec![[r.at as f64, r.value]])
                .shape(MarkerShape::Circle)
                .radius(VIOLATION_RADIUS)
                .color(m.theme.would_cause),
        );
        // The label below the point (a line down, clear of the limit
        // labels next to the limit it breaks), on the side with more room.
        let anchor = if r.at as f64 > axis.start + axis.span() / 2.0 {
            egui::Align2::RIGHT_TOP
        } else {
            egui::Align2::LEFT_TOP
        };
        plot_ui.text(
            Text::new(
                "violation",
                at,
                RichText::new(format!("\n  {}  ", r.label)).size(LIMIT_FONT_SIZE),
            )
            .anchor(anchor)
            .color(m.theme.would_cause),
        );
    }
}

/// The part of `series` (sorted by time) that `[start, end]` shows at `width`
/// pixels, with every pixel column holding more than two points replaced by one
/// vertical stroke through its lowest and highest values, starting and ending at
/// the values the column starts and ends with. Dense step segments otherwise make a path that turns back
/// on itself within a pixel, which the line tessellator draws as spikes and shading;
/// the envelope is what the eye sees at that zoom anyway, and it bounds the work
/// per frame by the width instead of the plan size.
pub(super) fn decimate(series: &[[f64; 2]], start: f64, end: f64, width: f64) -> Vec<[f64; 2]> {
    // (Written so that NaN bounds also return the series as it is.)
    let usable = end > start && width >= 1.0;
    if series.is_empty() || !usable {
        return series.to_vec();
    }
    let spp = (end - start) / width;
    // One point either side of the range, so that the line reaches the edges.
    let from = series.partition_point(|p| p[0] < start).saturating_sub(1);
    let to = (series.partition_point(|p| p[0] <= end) + 1).min(series.len());
    let column = |x: f64| ((x - start) / spp).floor();
    let mut out: Vec<[f64; 2]> = Vec::with_capacity(((width as usize) + 2) * 2);
    let mut i = from;
    while i < to {
        let c = column(series[i][0]);
        let mut j = i + 1;
        while j < to && column(series[j][0]) == c {
            j += 1;
        }
        let group = &series[i..j];
        if group.len() <= 2 {
            out.extend_from_slice(group);
        } else {
            let lo = group.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
            let hi = group.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max);
            // From the value the column starts with, to the nearer extreme, the
            // farther one, and the value it ends with: the stroke into the next
            // column leaves from where the series really is, so a step function
            // stays flat between columns instead of slanting.
            let x = group[0][0];
            let (first, last) = (group[0][1], group[group.len() - 1][1]);
            let (a, b) = if (first - lo).abs() <= (first - hi).abs() {
                (lo, hi)
            } else {
                (hi, lo)
            };
            out.extend([[x, first], [x, a], [x, b], [x, last]]);
        }
        i = j;
    }
    out
}

/// The three plots' names (also their y-axis labels) and limit lines.
pub(super) const SOC: &str = "State of charge (Wh)";

pub(super) const PEAK: &str = "Peak power (W)";

pub(super) const DATA: &str = "Data volume (Mbit)";

/// The visible value range reaches this far above the highest limit line.
const LIMIT_HEADROOM: f64 = 1.12;

/// A limit label ends this share of the visible time before the right edge
/// (its last glyph would be clipped at the edge).
const LIMIT_LABEL_INSET: f64 = 0.004;

/// Two limit labels closer than this share of the value range go on either
/// side of their lines.
const LIMIT_LABEL_ROOM: f64 = 0.12;

/// The unit of the plot with this id.
pub(super) fn unit_of(id: &str) -> Unit {
    match id {
        SOC => Unit::Wh,
        PEAK => Unit::W,
        _ => Unit::Mbit,
    }
}

/// Value grid lines 1, 2 or 5 times a power of ten apart, the finest that
/// keeps labels [`VALUE_GRID_GAP`] points apart (egui_plot's default steps by
/// tens, which on a short plot leaves a single label, `0`).
pub(super) fn value_grid(input: GridInput) -> Vec<GridMark> {
    let (lo, hi) = input.bounds;
    let span = hi - lo;
    if !(span.is_finite() && span > 0.0) {
        return Vec::new();
    }
    let wanted = span * f64::from(VALUE_GRID_GAP) / f64::from(PLOT_HEIGHT);
    let ten = 10f64.powf(wanted.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|k| k * ten)
        .find(|s| *s >= wanted)
        .unwrap_or(10.0 * ten);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last)
        .map(|k| GridMark {
            value: k as f64 * step,
            step_size: step,
        })
        .collect()
}

/// The limit lines of the three plots.
pub(super) fn limits(m: &Model<'_>) -> [Vec<(&'static str, f64)>; 3] {
    let plan = &m.doc.plan;
    let mut soc = vec![
        ("min_soc", plan.battery.min_soc),
        ("capacity", plan.battery.capacity),
    ];
    if let Some(h) = plan.handover.and_then(|h| h.min_soc) {
        soc.push(("handover min_soc", h));
    }
    let peak = plan
        .power
        .max_peak
        .map(|p| ("max_peak", p))
        .into_iter()
        .collect();
    let data = plan
        .data
        .capacity
        .map(|c| ("capacity", c))
        .into_iter()
        .collect();
    [soc, peak, data]
}
