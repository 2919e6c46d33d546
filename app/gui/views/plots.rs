//! State of charge, peak power and data volume as of the current step, on the
//! shared time axis; clicking a plot lists the consumers at that time. In
//! execution mode: the executed profiles over the first cycle's prediction and
//! the looked-at cycle's run as of the step shown, with the broken limits, and
//! the executed and predicted values at the time clicked.

use eframe::egui::{self, Color32, RichText};
use egui_plot::{
    GridInput, GridMark, HLine, HoverPosition, Line, LineStyle, MarkerShape, Plot, PlotPoint,
    PlotPoints, Points, Text, VLine,
};
use solscope_engine::{
    Consumer, MJ_PER_WH, MW_PER_W, ViolationKind, energy_consumers, format_local, format_span,
    format_watts, format_wh, peak_users,
};

use super::text::kind_name;
use super::{Model, ViewCache};
use crate::gui::commands::Command;
use crate::gui::execution::ExecutionRun;
use crate::gui::state::{Mode, OverlayPlot, OverlayReason, StepView, WouldCause};
use crate::gui::theme::{
    CYCLE_LINE_STROKE, LABEL_WIDTH, LIMIT_FONT_SIZE, OTHER_VIOLATION_RADIUS, PLOT_HEIGHT, TICK_GAP,
    VALUE_GRID_GAP, VIOLATION_RADIUS, WOULD_CAUSE_STROKE,
};
use crate::gui::time_axis::{TimeAxis, tick_label, ticks};

/// One line on a plot.
struct Series<'a> {
    name: String,
    points: &'a [[f64; 2]],
    color: Color32,
    dashed: bool,
    /// Line width, when not egui_plot's default.
    width: Option<f32>,
}

/// Which of a [`StepView`]'s series.
type Pick = fn(&StepView) -> &[[f64; 2]];

/// A vertical line across a plot at a time.
struct Mark {
    name: String,
    t: f64,
    color: Color32,
}

/// One plot: its series over the shared time axis, horizontal limit lines,
/// vertical marks and the violation points of what a failed activity would
/// have caused on it (`overlay`: the shown reason's filled and labelled, the
/// others' hollow).
#[allow(clippy::too_many_arguments)]
fn plot_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    cache: &mut ViewCache,
    id: &str,
    series: &[Series<'_>],
    limits: &[(&str, f64)],
    marks: &[Mark],
    overlay: Option<(&WouldCause, OverlayPlot)>,
    cmds: &mut Vec<Command>,
) {
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
    let limit_color = m.theme.limit;
    let unit = unit_of(id);
    let axis = m.nav.axis;
    let probe = m.nav.probe;
    let width = cache
        .plot_x
        .map_or(f64::from(ui.available_width()), |(l, r)| f64::from(r - l));
    let lines: Vec<Line<'_>> = series
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
        .collect();
    let local = m.doc.plan.local_time;
    // The Gantt ruler's ticks: round local times, sol boundaries thicker.
    let plot = Plot::new(id)
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
        .label_formatter(move |hover| {
            let (t, value) = match hover {
                HoverPosition::NearDataPoint { position, .. }
                | HoverPosition::Elsewhere { position } => (position.x, position.y),
            };
            Some(format!(
                "{}\n{value:.1} {unit}",
                format_local(&local, t.round() as i64)
            ))
        })
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
        .y_axis_min_width(LABEL_WIDTH - 30.0);
    let resp = plot.show(ui, |plot_ui| {
        plot_ui.set_plot_bounds_x(axis.start..=axis.end);
        // egui_plot's own aggregation fills bands between buckets, which draws
        // a step function as shaded triangles; `decimate` did the thinning.
        for line in lines {
            plot_ui.line(line);
        }
        let span = plot_ui.plot_bounds().height();
        for &(name, y) in limits {
            plot_ui.hline(HLine::new(name, y).color(limit_color));
            // The limit's name and value, at the right end of its line: above
            // it, or below when another limit's label sits just above.
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
                    RichText::new(format!("{name} {y} {unit}")).size(LIMIT_FONT_SIZE),
                )
                .anchor(anchor)
                .color(limit_color),
            );
        }
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
        // The other reasons' violations first, hollow, so the shown one is
        // drawn over them.
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
        plot_ui.pointer_coordinate()
    });
    let frame = resp.transform.frame();
    cache.plot_x = Some((frame.left(), frame.right()));
    if resp.response.clicked() {
        if let Some(p) = resp.inner {
            cmds.push(Command::ProbePlot(Some(p.x.round() as i64)));
        }
    }
}

/// The part of `series` (sorted by time) that `[start, end]` shows at `width`
/// pixels, with every pixel column holding more than two points replaced by one
/// vertical stroke through its lowest and highest values, starting and ending at
/// the values the column starts and ends with. Dense step segments otherwise make a path that turns back
/// on itself within a pixel, which the line tessellator draws as spikes and shading;
/// the envelope is what the eye sees at that zoom anyway, and it bounds the work
/// per frame by the width instead of the plan size.
pub fn decimate(series: &[[f64; 2]], start: f64, end: f64, width: f64) -> Vec<[f64; 2]> {
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
const SOC: &str = "State of charge (Wh)";
const PEAK: &str = "Peak power (W)";
const DATA: &str = "Data volume (Mbit)";

/// The visible value range reaches this far above the highest limit line.
const LIMIT_HEADROOM: f64 = 1.12;
/// A limit label ends this share of the visible time before the right edge
/// (its last glyph would be clipped at the edge).
const LIMIT_LABEL_INSET: f64 = 0.004;
/// Two limit labels closer than this share of the value range go on either
/// side of their lines.
const LIMIT_LABEL_ROOM: f64 = 0.12;

/// The unit of the plot with this id.
fn unit_of(id: &str) -> &'static str {
    match id {
        SOC => "Wh",
        PEAK => "W",
        _ => "Mbit",
    }
}

/// Value grid lines 1, 2 or 5 times a power of ten apart, the finest that
/// keeps labels [`VALUE_GRID_GAP`] points apart (egui_plot's default steps by
/// tens, which on a short plot leaves a single label, `0`).
fn value_grid(input: GridInput) -> Vec<GridMark> {
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
fn limits(m: &Model<'_>) -> [Vec<(&'static str, f64)>; 3] {
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

/// The name of the line of what `w`'s activity would have caused at reason
/// `r`'s start.
fn would_cause_name(m: &Model<'_>, w: &WouldCause, r: &OverlayReason) -> String {
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
fn would_cause_label(
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

/// The three plots and the consumers at the probed time.
pub fn plots_ui<'a>(
    ui: &mut egui::Ui,
    m: &'a Model<'_>,
    cache: &mut ViewCache,
    cmds: &mut Vec<Command>,
) {
    if m.nav.mode == Mode::Execution {
        if let Some(run) = m.exec.ready() {
            execution_plots_ui(ui, m, run, cache, cmds);
        }
        return;
    }
    let sv = m.step_view;
    let [soc_limits, peak_limits, data_limits] = limits(m);
    let one = |name: &str, points| Series {
        name: name.into(),
        points,
        color: m.theme.scheduled,
        dashed: false,
        width: None,
    };
    // What the selected failed activity would have caused: the shown
    // reason's profile dashed on its plot, every reason's violation marked.
    let overlay = |plot: OverlayPlot| m.would_cause.map(|w| (w, plot));
    let with_overlay = |base: Series<'a>, plot: OverlayPlot| -> Vec<Series<'a>> {
        let mut series = vec![base];
        if let Some((w, r)) = m
            .would_cause
            .and_then(|w| w.shown().map(|r| (w, r)))
            .filter(|(_, r)| r.plot == plot)
        {
            series.push(Series {
                name: would_cause_name(m, w, r),
                points: &w.points,
                color: m.theme.would_cause,
                dashed: true,
                width: Some(WOULD_CAUSE_STROKE),
            });
        }
        series
    };
    ui.label(RichText::new(format!("State of charge (Wh) after step {}", sv.step)).strong());
    would_cause_label(ui, m, m.would_cause, OverlayPlot::Soc, cmds);
    plot_ui(
        ui,
        m,
        cache,
        SOC,
        &with_overlay(one(SOC, &sv.soc), OverlayPlot::Soc),
        &soc_limits,
        &[],
        overlay(OverlayPlot::Soc),
        cmds,
    );
    ui.label(RichText::new(PEAK).strong());
    would_cause_label(ui, m, m.would_cause, OverlayPlot::Peak, cmds);
    plot_ui(
        ui,
        m,
        cache,
        PEAK,
        &with_overlay(one(PEAK, &sv.peak), OverlayPlot::Peak),
        &peak_limits,
        &[],
        overlay(OverlayPlot::Peak),
        cmds,
    );
    ui.label(RichText::new(DATA).strong());
    plot_ui(
        ui,
        m,
        cache,
        DATA,
        &[one(DATA, &sv.data)],
        &data_limits,
        &[],
        None,
        cmds,
    );

    let Some(t) = m.nav.probe else {
        ui.label("Click a plot to list the energy and peak-power users at that time.");
        return;
    };
    ui.horizontal(|ui| {
        ui.label(RichText::new(format!("At {}", m.time(t))).strong());
        let mut since = m.nav.since_full;
        if ui.checkbox(&mut since, "since last full battery").changed() {
            cmds.push(Command::SetSinceFull(since));
        }
        if ui.button("Clear probe").clicked() {
            cmds.push(Command::ProbePlot(None));
        }
    });
    let (from, energy) = energy_consumers(&m.analysis.schedule, sv.step, t, m.nav.since_full);
    let peak = peak_users(&m.analysis.schedule, sv.step, t);
    let energy = merge_by_who(m, &energy);
    let peak = merge_by_who(m, &peak);
    ui.columns(2, |cols| {
        cols[0].label(
            RichText::new(format!("Energy used {} to {}", m.time(from), m.time(t))).strong(),
        );
        egui::Grid::new("energy_users")
            .num_columns(2)
            .striped(true)
            .show(&mut cols[0], |ui| {
                for (who, amount) in energy.iter().take(12) {
                    ui.label(format_wh(i128::from(*amount)));
                    ui.label(who);
                    ui.end_row();
                }
            });
        if energy.len() > 12 {
            cols[0].label(format!("and {} more", energy.len() - 12));
        }
        cols[1].label(RichText::new("Peak-power users").strong());
        egui::Grid::new("peak_users")
            .num_columns(2)
            .striped(true)
            .show(&mut cols[1], |ui| {
                for (who, amount) in peak.iter().take(12) {
                    ui.label(format_watts(*amount));
                    ui.label(who);
                    ui.end_row();
                }
            });
    });
}

/// Execution mode: each profile executed, as the first cycle predicted it, and
/// as the looked-at cycle's run has it after the step shown; the looked-at
/// cycle's time and the broken limits as vertical lines; at the time clicked,
/// the executed and predicted values.
fn execution_plots_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    run: &ExecutionRun,
    cache: &mut ViewCache,
    cmds: &mut Vec<Command>,
) {
    let [soc_limits, peak_limits, data_limits] = limits(m);
    let k = m.exec.cycle;
    let cycle_time = run.execution.cycles.get(k).map(|c| c.time as f64);
    // The looked-at cycle's run, unless it is the prediction itself.
    let last = m.exec.cycle_run.map_or(0, |c| c.steps());
    let cycle_view = m.exec.view.filter(|_| k != 0 || m.exec.step != last);
    let predicted = run.predicted.as_ref().ok();
    let series = |pick: Pick| {
        let mut out = vec![Series {
            name: "executed".into(),
            points: pick(&run.executed),
            color: m.theme.scheduled,
            dashed: false,
            width: None,
        }];
        if let Some(p) = predicted {
            out.push(Series {
                name: "predicted (cycle 0)".into(),
                points: pick(p),
                color: m.theme.predicted,
                dashed: true,
                width: None,
            });
        }
        if let Some(v) = cycle_view {
            out.push(Series {
                name: format!("cycle {k} after step {}", m.exec.step),
                points: pick(v),
                color: m.theme.current,
                dashed: false,
                width: None,
            });
        }
        out
    };
    let marks = |kinds: &[ViolationKind]| {
        let mut out: Vec<Mark> = cycle_time
            .map(|t| Mark {
                name: format!("cycle {k}"),
                t,
                color: m.theme.current,
            })
            .into_iter()
            .collect();
        for v in &run.execution.violations {
            if kinds.contains(&v.kind) {
                out.push(Mark {
                    name: format!("{} broken", kind_name(v.kind)),
                    t: v.time as f64,
                    color: m.theme.limit,
                });
            }
        }
        out
    };
    if let Err(e) = &run.predicted {
        ui.colored_label(m.theme.error, format!("No prediction to compare with: {e}"));
    }
    legend_ui(ui, SOC, &series(|v| &v.soc));
    let soc_marks = marks(&[ViolationKind::MinSoc, ViolationKind::HandoverSoc]);
    plot_ui(
        ui,
        m,
        cache,
        SOC,
        &series(|v| &v.soc),
        &soc_limits,
        &soc_marks,
        None,
        cmds,
    );
    legend_ui(ui, PEAK, &series(|v| &v.peak));
    let peak_marks = marks(&[ViolationKind::MaxPeakPower]);
    plot_ui(
        ui,
        m,
        cache,
        PEAK,
        &series(|v| &v.peak),
        &peak_limits,
        &peak_marks,
        None,
        cmds,
    );
    legend_ui(ui, DATA, &series(|v| &v.data));
    let data_marks = marks(&[ViolationKind::DataCapacity]);
    plot_ui(
        ui,
        m,
        cache,
        DATA,
        &series(|v| &v.data),
        &data_limits,
        &data_marks,
        None,
        cmds,
    );

    let Some(t) = m.nav.probe else {
        ui.label("Click a plot to compare the executed and predicted values at that time.");
        return;
    };
    ui.horizontal(|ui| {
        ui.label(RichText::new(format!("At {}", m.time(t))).strong());
        if ui.button("Clear probe").clicked() {
            cmds.push(Command::ProbePlot(None));
        }
    });
    let x = t as f64;
    /// A quantity of the probe table: its name, series and format.
    type Quantity = (&'static str, Pick, fn(f64) -> String);
    let rows: [Quantity; 3] = [
        (
            "State of charge",
            |v| &v.soc,
            |x| format_wh((x * MJ_PER_WH).round() as i128),
        ),
        (
            "Peak power",
            |v| &v.peak,
            |x| format_watts((x * MW_PER_W).round() as i64),
        ),
        ("Data volume", |v| &v.data, |x| format!("{x:.1} Mbit")),
    ];
    egui::Grid::new("execution_probe")
        .num_columns(4)
        .striped(true)
        .show(ui, |ui| {
            for h in ["", "executed", "predicted", "executed − predicted"] {
                ui.label(RichText::new(h).strong());
            }
            ui.end_row();
            for (name, pick, fmt) in rows {
                let done = value_at(pick(&run.executed), x);
                let plan = predicted.and_then(|p| value_at(pick(p), x));
                ui.label(name);
                ui.label(done.map_or_else(|| "–".into(), fmt));
                ui.label(plan.map_or_else(|| "–".into(), fmt));
                let diff = done.zip(plan).map(|(a, b)| a - b);
                ui.label(diff.map_or_else(|| "–".into(), fmt));
                ui.end_row();
            }
        });
}

/// A plot's title with its series in their colours (a legend that never covers
/// the data).
fn legend_ui(ui: &mut egui::Ui, title: &str, series: &[Series<'_>]) {
    ui.horizontal_wrapped(|ui| {
        ui.label(RichText::new(title).strong());
        for s in series {
            let stroke = if s.dashed { "- - -" } else { "——" };
            ui.label(RichText::new(format!("{stroke} {}", s.name)).color(s.color));
        }
    });
}

/// The value of a series (sorted by time, linear between points; at a jump,
/// the value after it) at `x`; `None` outside it.
fn value_at(series: &[[f64; 2]], x: f64) -> Option<f64> {
    let i = series.partition_point(|p| p[0] <= x);
    match (i.checked_sub(1).and_then(|j| series.get(j)), series.get(i)) {
        (Some(a), Some(b)) if b[0] > a[0] => {
            Some(a[1] + (b[1] - a[1]) * (x - a[0]) / (b[0] - a[0]))
        }
        (Some(a), _) => (a[0] == x || i < series.len()).then_some(a[1]),
        (None, _) => None,
    }
}

/// Sums consumers that read the same (e.g. several awake periods), ranked.
fn merge_by_who(m: &Model<'_>, list: &[Consumer]) -> Vec<(String, i64)> {
    let mut out: Vec<(String, i64)> = Vec::new();
    for c in list {
        let who = match (c.activity, c.kind) {
            (Some(a), "activity") => m.doc.plan.activities[a].id.clone(),
            (Some(a), kind) => format!("{kind} for {}", m.doc.plan.activities[a].id),
            (None, _) => "rover awake (above asleep draw)".to_string(),
        };
        match out.iter_mut().find(|x| x.0 == who) {
            Some(x) => x.1 = x.1.saturating_add(c.amount),
            None => out.push((who, c.amount)),
        }
    }
    out.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    out
}

#[cfg(test)]
mod tests {
    use super::{GridInput, PLOT_HEIGHT, VALUE_GRID_GAP, decimate, value_at, value_grid};

    #[test]
    fn value_grids_step_by_one_two_or_five_and_keep_labels_apart() {
        for (lo, hi) in [
            (0.0, 950.0),
            (0.0, 2700.0),
            (-3.0, 0.4),
            (0.0, 3.3e6),
            (500.0, 501.0),
        ] {
            let marks = value_grid(GridInput {
                bounds: (lo, hi),
                base_step_size: 0.0,
            });
            assert!(marks.len() >= 2, "{lo}..{hi}: {} marks", marks.len());
            let step = marks[1].value - marks[0].value;
            let ten = 10f64.powf(step.log10().floor());
            let k = (step / ten).round();
            assert!([1.0, 2.0, 5.0].contains(&k), "{lo}..{hi}: step {step}");
            let px = step / (hi - lo) * f64::from(PLOT_HEIGHT);
            assert!(
                px >= f64::from(VALUE_GRID_GAP) - 1e-9,
                "{lo}..{hi}: {px} px"
            );
            assert!(marks.iter().all(|m| lo <= m.value && m.value <= hi));
        }
        // The peak plot of the bundled plan: 0 to about 950 W gets 0, 200, ... 800.
        let marks = value_grid(GridInput {
            bounds: (0.0, 950.0),
            base_step_size: 0.0,
        });
        let values: Vec<f64> = marks.iter().map(|m| m.value).collect();
        assert_eq!(values, [0.0, 200.0, 400.0, 600.0, 800.0]);
        assert!(
            value_grid(GridInput {
                bounds: (1.0, 1.0),
                base_step_size: 0.0
            })
            .is_empty()
        );
    }

    #[test]
    fn values_between_points_are_linear_and_a_jump_takes_the_later_value() {
        let series = [[0.0, 10.0], [10.0, 20.0], [10.0, 5.0], [20.0, 5.0]];
        assert_eq!(value_at(&series, -1.0), None);
        assert_eq!(value_at(&series, 0.0), Some(10.0));
        assert_eq!(value_at(&series, 5.0), Some(15.0));
        assert_eq!(value_at(&series, 10.0), Some(5.0));
        assert_eq!(value_at(&series, 20.0), Some(5.0));
        assert_eq!(value_at(&series, 21.0), None);
        assert_eq!(value_at(&[], 0.0), None);
    }

    #[test]
    fn decimation_keeps_each_columns_envelope_and_time_order() {
        // A dense step function: 10,000 alternating steps over [0, 100,000).
        let mut series = Vec::new();
        for k in 0..10_000 {
            let (x, y) = (
                f64::from(k) * 10.0,
                f64::from(k % 7) * 3.0 + f64::from(k / 1000),
            );
            series.push([x, y]);
            series.push([x + 10.0, y]);
        }
        let (start, end, width) = (20_000.0, 80_000.0, 300.0);
        let out = decimate(&series, start, end, width);
        assert!(out.len() <= 4 * (width as usize + 3), "{}", out.len());
        // Between columns the line is flat (the series holds its value): no
        // slanted strokes at any zoom.
        for w in out.windows(2) {
            if w[0][0] != w[1][0] {
                assert_eq!(w[0][1], w[1][1], "slanted: {w:?}");
            }
        }
        assert!(out.windows(2).all(|w| w[0][0] <= w[1][0]), "time order");
        let spp = (end - start) / width;
        for c in 0..width as usize {
            let (a, b) = (start + c as f64 * spp, start + (c + 1) as f64 * spp);
            let inside = |p: &&[f64; 2]| p[0] >= a && p[0] < b;
            let ys = |v: &[[f64; 2]]| {
                let v: Vec<f64> = v.iter().filter(inside).map(|p| p[1]).collect();
                (
                    v.iter().copied().fold(f64::INFINITY, f64::min),
                    v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                )
            };
            assert_eq!(ys(&series), ys(&out), "column {c}");
        }
        // Sparse data is left exact.
        let sparse = vec![
            [0.0, 1.0],
            [50_000.0, 1.0],
            [50_000.0, 4.0],
            [90_000.0, 4.0],
        ];
        assert_eq!(decimate(&sparse, 0.0, 100_000.0, 800.0), sparse);
    }
}
