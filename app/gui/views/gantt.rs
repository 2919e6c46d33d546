//! Gantt rows as of the current step: generated awake and heating rows, comm
//! passes, scheduled activities packed into lanes, failed ones, and pending ones
//! drawn as their allowed windows. Bars narrower than a pixel are merged, bars
//! outside the view culled, so 10k activities stay fluid.
//!
//! In execution mode: the cycles and broken limits as markers, the executed
//! awake periods, each activity's executed bar over a thin bar of where the
//! first cycle predicted it, and the looked-at cycle's run as of the step shown.

use eframe::egui::{
    self, Align2, Color32, FontId, Pos2, Rect, RichText, Sense, Stroke, StrokeKind,
};
use solscope_engine::{FailurePhase, GeneratedKind, Outcome, RunOutcome, Schedule, format_span};

use super::flex::{self, Slack};
use super::text::{trigger_text, violation_text};
use super::{Look, Model, Status, ViewCache, status_at};
use crate::gui::commands::Command;
use crate::gui::document::Analysis;
use crate::gui::execution::{CycleRun, ExecutionRun};
use crate::gui::state::Mode;
use crate::gui::theme::{
    BAR_FONT_SIZE, BAR_ROUNDING, BASELINE_HEIGHT, CULPRIT_STROKE, CURRENT_STROKE,
    CYCLE_LINE_STROKE, DIMMED, GHOST_STROKE, HATCH_GAP, HATCH_STROKE, LABEL_MIN_WIDTH, LABEL_WIDTH,
    LANE_GAP, LANE_HEIGHT, MARKER_WIDTH, MATCH_STROKE, NEIGHBOUR_STROKE, PROBE_LINE_STROKE,
    RULER_HEIGHT, SELECTION_STROKE, SOL_LINE_STROKE, TICK_GAP, TICK_LENGTH, WINDOW_FILL,
    WINDOW_HATCH,
};
use crate::gui::time_axis::ticks;

/// One bar.
#[derive(Clone, Debug)]
struct Bar {
    start: f64,
    end: f64,
    color: Color32,
    activity: Option<usize>,
    label: String,
    /// Hover text instead of `label start–end`.
    tip: Option<String>,
    /// Clicking it looks at this scheduling cycle.
    cycle: Option<usize>,
    /// Drawn at least `MARKER_WIDTH` wide, never merged or hidden.
    marker: bool,
    /// The bar of `activity`'s placement (schedule mode): it carries the
    /// flexibility layer and can be dragged.
    placed: bool,
    /// What it takes in its lane: `[start, end]`, or with the flexibility layer
    /// its whiskers and free slack too.
    extent: (f64, f64),
    /// Where an activity could have run, not where it ran (a failed, skipped,
    /// pending or never-run activity's window): drawn hatched and outlined, so
    /// a window over the whole plan does not read as a bar across the chart.
    outline: bool,
}

impl Bar {
    fn new(start: f64, end: f64, color: Color32, activity: Option<usize>, label: String) -> Self {
        Self {
            start,
            end,
            color,
            activity,
            label,
            tip: None,
            cycle: None,
            marker: false,
            placed: false,
            extent: (start, end),
            outline: false,
        }
    }

    /// A window bar (see `outline`).
    fn window(start: i64, end: i64, color: Color32, activity: usize, label: String) -> Self {
        Self {
            outline: true,
            ..Self::new(start as f64, end as f64, color, Some(activity), label)
        }
    }
}

/// One row: a label and its bars.
#[derive(Clone, Debug)]
struct Row {
    label: String,
    bars: Vec<Bar>,
    /// Its height (points).
    height: f32,
    /// Its bars follow the step slider (the current step's activity is outlined).
    steps: bool,
}

impl Row {
    fn new(label: String, bars: Vec<Bar>) -> Self {
        Self {
            label,
            bars,
            height: LANE_HEIGHT,
            steps: true,
        }
    }
}

/// Packs items spanning `span` into as few lanes as possible (by start; first
/// lane that is free), at most `max_lanes` (the last takes the overflow); at
/// least one lane.
fn lanes<T>(mut items: Vec<T>, span: impl Fn(&T) -> (f64, f64), max_lanes: usize) -> Vec<Vec<T>> {
    items.sort_by(|a, b| {
        let (a, b) = (span(a), span(b));
        a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1))
    });
    let mut lanes: Vec<(f64, Vec<T>)> = Vec::new();
    for item in items {
        let (start, end) = span(&item);
        let n = lanes.len();
        let free = lanes.iter().position(|l| l.0 <= start);
        match free {
            Some(i) => {
                lanes[i].0 = end;
                lanes[i].1.push(item);
            }
            None if n < max_lanes => lanes.push((end, vec![item])),
            None => {
                if let Some(last) = lanes.last_mut() {
                    last.0 = last.0.max(end);
                    last.1.push(item);
                }
            }
        }
    }
    if lanes.is_empty() {
        lanes.push((0.0, Vec::new()));
    }
    lanes.into_iter().map(|(_, items)| items).collect()
}

/// The label of lane `i` of a group: the group's on the first.
fn lane_label(i: usize, label: &str) -> String {
    if i == 0 {
        label.to_string()
    } else {
        String::new()
    }
}

/// Packs bars into as few lanes as possible (by start; first lane that is free).
fn pack(bars: Vec<Bar>, label: &str, max_lanes: usize) -> Vec<Row> {
    lanes(bars, |b| b.extent, max_lanes)
        .into_iter()
        .enumerate()
        .map(|(i, bars)| Row::new(lane_label(i, label), bars))
        .collect()
}

fn rows(m: &Model<'_>, k: usize) -> Vec<Row> {
    let plan = &m.doc.plan;
    let problem = &m.analysis.schedule.problem;
    let t = &m.theme;
    let mut rows = Vec::new();
    // Generated activities alive after step k.
    let mut awake = Vec::new();
    let mut heat: Vec<Vec<Bar>> = vec![Vec::new(); problem.zone_names.len()];
    for g in m.analysis.schedule.generated_after(k) {
        match g.kind {
            GeneratedKind::Awake => awake.push(Bar::new(
                g.start as f64,
                g.end as f64,
                t.awake,
                None,
                "awake".into(),
            )),
            GeneratedKind::Preheat { zone, activity } => heat[zone].push(Bar::new(
                g.start as f64,
                g.end as f64,
                t.preheat,
                Some(activity),
                format!("preheat {}", plan.activities[activity].id),
            )),
            GeneratedKind::Maintenance { zone, activity } => heat[zone].push(Bar::new(
                g.start as f64,
                g.end as f64,
                t.maintenance,
                Some(activity),
                format!("maint. {}", plan.activities[activity].id),
            )),
        }
    }
    // Wakeup and shutdown drawn over the start and end of each awake period.
    let (wake, shut) = (problem.wake as f64, problem.shut as f64);
    let mut edges = Vec::new();
    for bar in &awake {
        for (start, end, label) in [
            (bar.start, bar.start + wake, "wakeup"),
            (bar.end - shut, bar.end, "shutdown"),
        ] {
            if end > start {
                edges.push(Bar::new(start, end, t.wake, None, label.into()));
            }
        }
    }
    awake.sort_by(|a, b| a.start.total_cmp(&b.start));
    edges.sort_by(|a, b| a.start.total_cmp(&b.start));
    awake.extend(edges);
    rows.push(Row::new("Awake".into(), awake));
    for (z, bars) in heat.into_iter().enumerate() {
        rows.extend(pack(bars, &format!("Heat: {}", problem.zone_names[z]), 3));
    }
    let (mut comm, mut scheduled, mut failed, mut pending) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    // With the flexibility layer, a placed bar takes its whiskers and free slack
    // in its lane, so no other bar hides them.
    let flex = m.flex_layer();
    for (a, act) in plan.activities.iter().enumerate() {
        let label = act.id.clone();
        match m.status(a, k) {
            Status::Scheduled(s, e) => {
                let color = if act.comm_kind.is_some() {
                    t.comm
                } else {
                    t.scheduled
                };
                let mut bar = Bar::new(s as f64, e as f64, color, Some(a), label);
                bar.placed = true;
                if let Some(fa) = flex.and_then(|f| f.activity(a)) {
                    bar.extent = flex::envelope(fa, e - s);
                }
                if act.comm_kind.is_some() {
                    comm.push(bar);
                } else {
                    scheduled.push(bar);
                }
            }
            status => {
                let color = match status {
                    Status::Failed => t.failed,
                    Status::Skipped => t.skipped,
                    _ => t.pending,
                };
                let bars = window_spans(plan, act)
                    .into_iter()
                    .map(|(lo, hi)| Bar::window(lo, hi, color, a, label.clone()));
                if status == Status::Pending {
                    pending.extend(bars);
                } else {
                    failed.extend(bars);
                }
            }
        }
    }
    rows.extend(pack(comm, "Comm passes", 2));
    if m.persisted.by_resource {
        rows.extend(by_resource(plan, scheduled));
    } else {
        rows.extend(pack(scheduled, "Scheduled", 64));
    }
    rows.extend(pack(failed, "Failed / skipped", 8));
    rows.extend(pack(pending, "Pending (windows)", 8));
    rows
}

/// Where an activity that is not placed is drawn: each window, from its start to
/// its end plus the longest duration (clipped to the horizon), or the whole
/// horizon without windows.
pub(super) fn window_spans(
    plan: &solscope_engine::Plan,
    act: &solscope_engine::Activity,
) -> Vec<(i64, i64)> {
    let clip = |(lo, hi): (i64, i64)| (lo.max(plan.horizon.start), hi.min(plan.horizon.end));
    match &act.windows {
        Some(windows) => windows
            .iter()
            .map(|w| clip((w.start, w.end.saturating_add(act.duration.max()))))
            .filter(|(lo, hi)| lo < hi)
            .collect(),
        None => vec![(plan.horizon.start, plan.horizon.end)],
    }
}

/// Where the Gantt draws an activity.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Extent {
    /// As a bar `[start, end]`: placed, or in execution mode run (or
    /// predicted).
    Bar(i64, i64),
    /// As its windows (not placed, or never run): see [`window_spans`].
    Windows(Vec<(i64, i64)>),
}

/// Where the Gantt draws activity `a`: in schedule mode (`run` none) as of step
/// `k`, in execution mode where it ran, else where it was predicted.
pub fn extent(
    plan: &solscope_engine::Plan,
    analysis: &Analysis,
    run: Option<&ExecutionRun>,
    k: usize,
    a: usize,
) -> Option<Extent> {
    let act = plan.activities.get(a)?;
    let bar = match run {
        None => match status_at(analysis, a, k) {
            Status::Scheduled(s, e) => Some((s, e)),
            _ => None,
        },
        Some(run) => run.activity(a).and_then(|r| r.actual.or(r.predicted)),
    };
    Some(match bar {
        Some((s, e)) => Extent::Bar(s, e),
        None => Extent::Windows(window_spans(plan, act)),
    })
}

/// Scheduled bars in one row per unit resource (resource names in order; an
/// activity holding several appears in each of their rows), then those holding
/// none in packed lanes. A unit resource is held by one activity at a time, so
/// each resource needs one row.
fn by_resource(plan: &solscope_engine::Plan, scheduled: Vec<Bar>) -> Vec<Row> {
    let mut groups: std::collections::BTreeMap<&str, Vec<Bar>> = std::collections::BTreeMap::new();
    let mut none = Vec::new();
    for mut bar in scheduled {
        let held = bar
            .activity
            .and_then(|a| plan.activities.get(a))
            .map(|act| act.resources.as_slice())
            .unwrap_or_default();
        if held.is_empty() {
            none.push(bar);
            continue;
        }
        // One row per resource with the flexibility layer too: a whisker
        // reaching past the next bar on the resource runs under it.
        bar.extent = (bar.start, bar.end);
        for r in held {
            groups.entry(r.as_str()).or_default().push(bar.clone());
        }
    }
    let mut rows: Vec<Row> = groups
        .into_iter()
        .flat_map(|(r, bars)| pack(bars, &format!("Resource: {r}"), 2))
        .collect();
    rows.extend(pack(none, "No resource", 64));
    rows
}

/// The rows of execution mode: cycle markers, broken limits, the executed awake
/// periods, executed activities over their prediction, those never placed, and
/// the looked-at cycle's run as of the step shown.
fn execution_rows(m: &Model<'_>, run: &ExecutionRun) -> Vec<Row> {
    let plan = &m.doc.plan;
    let t = &m.theme;
    let ex = &run.execution;
    let mut rows = Vec::new();
    let cycles = ex
        .cycles
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let color = if k == m.exec.cycle {
                t.current
            } else {
                t.cycle
            };
            let mut bar = Bar::new(c.time as f64, c.time as f64, color, None, String::new());
            bar.tip = Some(format!(
                "cycle {k} at {}, {}, from {} (click to look at it)",
                m.time(c.time),
                trigger_text(m, c.trigger),
                solscope_engine::format_wh(c.soc)
            ));
            bar.cycle = Some(k);
            bar.marker = true;
            bar
        })
        .collect();
    rows.push(marker_row("Cycles", cycles));
    if !ex.violations.is_empty() {
        let marks = ex
            .violations
            .iter()
            .map(|v| {
                let end = v.worst.1.max(v.time);
                let mut bar = Bar::new(v.time as f64, end as f64, t.limit, None, String::new());
                bar.tip = Some(violation_text(m, v));
                bar.marker = true;
                bar
            })
            .collect();
        rows.push(marker_row("Limits broken", marks));
    }
    let awake = ex
        .profile
        .awake
        .iter()
        .map(|&(a, b)| Bar::new(a as f64, b as f64, t.awake, None, "awake".into()))
        .collect();
    rows.push(Row {
        steps: false,
        ..Row::new("Awake".into(), awake)
    });
    // Each activity: its executed bar (or, not run, a faint one where it was
    // predicted) over a thin bar of its prediction, packed by their union.
    let mut items: Vec<(Bar, Option<Bar>)> = Vec::new();
    let mut never = Vec::new();
    for (a, r) in ex.activities.iter().enumerate() {
        let act = &plan.activities[a];
        let id = act.id.clone();
        let predicted = r.predicted.map(|(s, e)| {
            let mut bar = Bar::new(s as f64, e as f64, t.predicted, Some(a), String::new());
            bar.tip = Some(format!(
                "{id}: predicted {}–{} (cycle 0)",
                m.time(s),
                m.time(e)
            ));
            bar
        });
        let was = r.predicted.map_or(String::new(), |(s, e)| {
            format!(" (predicted {}–{})", m.time(s), m.time(e))
        });
        let main = match (r.outcome, r.actual, r.predicted) {
            (RunOutcome::NotRun, _, None) => {
                for (lo, hi) in window_spans(plan, act) {
                    let mut bar = Bar::window(lo, hi, t.not_run, a, id.clone());
                    bar.tip = Some(format!("{id}: not run, never placed (its window)"));
                    never.push(bar);
                }
                continue;
            }
            (RunOutcome::NotRun, _, Some((s, e))) | (_, None, Some((s, e))) => {
                let mut bar = Bar::new(s as f64, e as f64, t.not_run, Some(a), id.clone());
                bar.tip = Some(format!("{id}: not run{was}"));
                bar
            }
            (outcome, Some((s, e)), _) => {
                let (color, what) = match outcome {
                    RunOutcome::Aborted => (t.aborted, "aborted"),
                    _ if act.comm_kind.is_some() => (t.comm, "completed"),
                    _ => (t.scheduled, "completed"),
                };
                let mut bar = Bar::new(s as f64, e as f64, color, Some(a), id.clone());
                bar.tip = Some(format!(
                    "{id}: {what}, ran {}–{}{was}",
                    m.time(s),
                    m.time(e)
                ));
                bar
            }
            (_, None, None) => continue,
        };
        items.push((main, predicted));
    }
    let span = |(main, pred): &(Bar, Option<Bar>)| match pred {
        Some(p) => (main.start.min(p.start), main.end.max(p.end)),
        None => (main.start, main.end),
    };
    for (i, lane) in lanes(items, span, 64).into_iter().enumerate() {
        let (main, pred): (Vec<Bar>, Vec<Option<Bar>>) = lane.into_iter().unzip();
        rows.push(Row {
            steps: false,
            ..Row::new(lane_label(i, "Executed"), main)
        });
        rows.push(Row {
            height: BASELINE_HEIGHT,
            steps: false,
            ..Row::new(String::new(), pred.into_iter().flatten().collect())
        });
    }
    if !never.is_empty() {
        rows.extend(
            pack(never, "Never placed", 8)
                .into_iter()
                .map(|r| Row { steps: false, ..r }),
        );
    }
    if let (Some(cr), Some(sched)) = (m.exec.cycle_run, m.exec.schedule()) {
        rows.extend(cycle_rows(m, run, cr, sched));
    }
    rows
}

/// A row of markers (never merged; hover for what they mark).
fn marker_row(label: &str, bars: Vec<Bar>) -> Row {
    Row {
        steps: false,
        ..Row::new(label.into(), bars)
    }
}

/// The looked-at cycle's run as of the step shown: its awake periods, what it
/// placed, and what it could not place (drawn as their windows).
fn cycle_rows(m: &Model<'_>, run: &ExecutionRun, cr: &CycleRun, sched: &Schedule) -> Vec<Row> {
    let t = &m.theme;
    let k = m.exec.cycle;
    let plan = &m.doc.plan;
    let cycle_plan = run.execution.cycles.get(k).and_then(|c| c.plan.as_ref());
    let mut rows = Vec::new();
    let awake = sched
        .generated_after(m.exec.step)
        .filter(|g| g.kind == GeneratedKind::Awake)
        .map(|g| Bar::new(g.start as f64, g.end as f64, t.awake, None, "awake".into()))
        .collect();
    rows.push(Row::new(format!("Cycle {k}: awake"), awake));
    let (mut placed, mut failed) = (Vec::new(), Vec::new());
    // By cycle-plan index: the run's own activity -> step index, O(1) each.
    for (i, &a) in cr.activity_of.iter().enumerate() {
        let act = &plan.activities[a];
        let Some(step) = sched.step_of(i).filter(|st| st.step <= m.exec.step) else {
            continue;
        };
        match step.outcome {
            Outcome::Scheduled { start, end } => {
                let color = if act.comm_kind.is_some() {
                    t.comm
                } else {
                    t.scheduled
                };
                let bar = Bar::new(start as f64, end as f64, color, Some(a), act.id.clone());
                placed.push(bar);
            }
            Outcome::Failed(_) | Outcome::Skipped { .. } => {
                let color = if matches!(step.outcome, Outcome::Failed(_)) {
                    t.failed
                } else {
                    t.skipped
                };
                // The windows the cycle gave it (from the cycle's time on).
                let spans = cycle_plan
                    .and_then(|p| p.activities.get(i).map(|x| window_spans(p, x)))
                    .unwrap_or_else(|| window_spans(plan, act));
                failed.extend(
                    spans
                        .into_iter()
                        .map(|(lo, hi)| Bar::window(lo, hi, color, a, act.id.clone())),
                );
            }
        }
    }
    rows.extend(pack(placed, &format!("Cycle {k}: placed"), 16));
    if !failed.is_empty() {
        rows.extend(pack(failed, &format!("Cycle {k}: failed"), 4));
    }
    rows
}

/// What the execution rows' colours mean.
fn legend_ui(ui: &mut egui::Ui, m: &Model<'_>) {
    let t = &m.theme;
    ui.horizontal_wrapped(|ui| {
        let colored = |text: &str, color| RichText::new(text).color(color);
        ui.label(colored("Executed:", t.muted));
        ui.label(colored("completed", t.scheduled));
        ui.label(colored("aborted", t.aborted));
        ui.label(colored("not run", t.failed));
        ui.label(colored(
            "· thin bar below: predicted by cycle 0 ·",
            t.predicted,
        ));
        ui.label(colored(&format!("cycle {}", m.exec.cycle), t.current));
        ui.label(colored("· hover a mark or bar for details", t.muted));
    });
}

/// What the rows were built for: revision, step, grouping, palette and, in
/// execution mode, the actuals, cycle, its step, and which parts were derived.
#[derive(Clone, Copy, Debug, PartialEq)]
struct RowsKey {
    revision: u64,
    step: usize,
    by_resource: bool,
    palette: Color32,
    /// The flexibility layer was shown (it widens what a bar takes in a lane).
    flex: bool,
    exec: Option<(u64, usize, usize, bool, bool)>,
}

/// The rows as of one step, kept between frames: building them sorts and packs
/// every activity, which at 10k activities costs more than drawing them.
#[derive(Clone, Debug)]
pub struct GanttRows {
    key: RowsKey,
    rows: Vec<Row>,
}

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

/// What hovering a bar shows, and what clicking it does.
struct Hovered {
    text: String,
    click: Option<Command>,
}

/// What hovering `bar` shows and what clicking it does (`steps`: a schedule
/// row following the step slider, whose activity bars say what happened), if
/// anything.
fn hover_of(
    m: &Model<'_>,
    bar: &Bar,
    steps: bool,
    flex_layer: Option<&solscope_engine::Flex>,
) -> Option<Hovered> {
    let click = match (bar.activity, bar.cycle) {
        (Some(a), _) => Some(Command::Select(Some(a))),
        (None, Some(c)) => Some(Command::SetCycle(c)),
        (None, None) => None,
    };
    if click.is_none() && bar.tip.is_none() {
        return None;
    }
    let mut text = bar.tip.clone().unwrap_or_else(|| match bar.activity {
        Some(a) if steps => activity_tip(m, a, bar),
        _ => format!(
            "{} {}–{}",
            bar.label,
            m.time(bar.start as i64),
            m.time(bar.end as i64)
        ),
    });
    let fa = flex_layer
        .filter(|_| bar.placed)
        .and_then(|f| bar.activity.and_then(|a| f.activity(a)));
    if let Some(fa) = fa {
        text.push_str(&format!(
            "\n{}; drag to try another start",
            flex::hover_line(m, fa)
        ));
    }
    Some(Hovered { text, click })
}

/// What hovering activity `a`'s bar says in schedule mode: who it is, what
/// happened to it by the step shown and when, its duration and unit resources,
/// and for a failure the one-line reason.
fn activity_tip(m: &Model<'_>, a: usize, bar: &Bar) -> String {
    let act = &m.doc.plan.activities[a];
    let span = format!("{} – {}", m.time(bar.start as i64), m.time(bar.end as i64));
    let k = m.nav.step;
    let what = match m.status(a, k) {
        Status::Scheduled(s, e) => format!("scheduled {span} ({})", format_span(e - s)),
        Status::Failed => {
            let why = match m.analysis.step(a).map(|s| &s.outcome) {
                Some(Outcome::Failed(FailurePhase::Dependency { on })) => format!(
                    "its dependency {} was not placed",
                    m.doc.plan.activities[*on].id
                ),
                Some(Outcome::Failed(FailurePhase::ValidIntervals)) => {
                    "no start satisfies its constraints together".to_string()
                }
                _ => "every valid start breaks a power, energy or sleep limit".to_string(),
            };
            format!("failed: {why}\nwindow {span}")
        }
        Status::Skipped => {
            format!("skipped: another member of its group was placed\nwindow {span}")
        }
        Status::Pending => format!("pending (its step is after step {k})\nwindow {span}"),
    };
    let mut out = format!("{}\n{what}", m.label(a));
    if !matches!(m.status(a, k), Status::Scheduled(..)) {
        let d = &act.duration;
        out.push_str(&if d.min() == d.max() {
            format!("\nlasts {}", format_span(d.max()))
        } else {
            format!(
                "\nlasts {} to {}",
                format_span(d.min()),
                format_span(d.max())
            )
        });
    }
    if !act.resources.is_empty() {
        out.push_str(&format!("\nholds {}", act.resources.join(", ")));
    }
    out
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

/// The timeline part of `rect`: the plots' data area of the last frame (so one
/// time is one x on the ruler, the bars and the plots), else right of the labels.
fn timeline_of(rect: Rect, cache: &ViewCache) -> Rect {
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

/// The Gantt chart.
pub fn gantt_ui(ui: &mut egui::Ui, m: &Model<'_>, cache: &mut ViewCache, cmds: &mut Vec<Command>) {
    let k = m.nav.step;
    let run = match m.nav.mode {
        Mode::Schedule => None,
        Mode::Execution => match m.exec.run {
            Some(Ok(run)) => Some(run.as_ref()),
            Some(Err(_)) => {
                ui.label("No execution to draw (see the error above).");
                return;
            }
            None => {
                ui.horizontal(|ui| {
                    ui.spinner();
                    ui.label("executing the plan…");
                });
                return;
            }
        },
    };
    if run.is_some() {
        legend_ui(ui, m);
    } else if !m.persisted.hide_flex {
        flex::legend_ui(ui, m);
    }
    let key = RowsKey {
        revision: m.revision,
        step: k,
        by_resource: m.persisted.by_resource,
        palette: m.theme.scheduled,
        flex: m.flex_layer().is_some(),
        exec: run.map(|_| {
            (
                m.exec.actuals_rev,
                m.exec.cycle,
                m.exec.step,
                m.exec.cycle_run.is_some(),
                m.exec.view.is_some(),
            )
        }),
    };
    let rows = match cache.gantt.take() {
        Some(cached) if cached.key == key => cached.rows,
        _ => match run {
            Some(run) => execution_rows(m, run),
            None => rows(m, k),
        },
    };
    let height: f32 = rows.iter().map(|r| r.height + LANE_GAP).sum::<f32>() + 4.0;
    let (rect, response) = ui.allocate_exact_size(
        egui::vec2(ui.available_width(), height),
        Sense::click_and_drag(),
    );
    // No hover text while a bar is dragged or a question is asked (it would
    // cover the popup's buttons).
    let quiet = cache.drag.is_some() || m.messages.pin.is_some() || m.messages.confirm.is_some();
    // Shown where no bar is under the pointer (a bar shows its own tooltip).
    let hint = if m.flex_layer().is_some() {
        "Click a bar to inspect it; drag a scheduled bar to try another start; drag \
         elsewhere to pan; Ctrl+wheel to zoom"
    } else {
        "Click a bar to inspect it; drag to pan; Ctrl+wheel to zoom"
    };
    response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Image, true, "Gantt chart"));
    // Share the plots' data area (last frame) so one time is one x everywhere.
    let timeline = timeline_of(rect, cache);
    let painter = ui.painter_at(rect);
    let axis = m.nav.axis;
    // Sol boundaries as lines behind the rows (the ruler above labels them).
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
    let bounds = (
        m.doc.plan.horizon.start as f64,
        m.doc.plan.horizon.end as f64,
    );
    let current = match run {
        Some(_) => m
            .exec
            .cycle_run
            .and_then(|c| c.activity_of_step(m.exec.step)),
        None => m.activity_of_step(k),
    };
    let font = FontId::proportional(BAR_FONT_SIZE);
    let mut hovered: Option<Hovered> = None;
    let pointer = response.hover_pos();
    let flex_layer = m.flex_layer();
    if cache.gantt_revealed != Some(m.nav.selected) {
        // A new selection: its row scrolled into view (its time range was
        // moved to it when it was selected).
        cache.gantt_revealed = Some(m.nav.selected);
        if let Some(r) = m
            .nav
            .selected
            .and_then(|a| row_of(m, &rows, a, rect.top(), timeline))
        {
            ui.scroll_to_rect(r, None);
        }
    }
    // The search and filters: what they match outlined, the rest faded.
    let listed = cache.listed.clone().filter(|l| l.active);
    let mut looks: Vec<(usize, Look)> = Vec::new();
    // The selected activity's neighbours in the minimum dispatchable network.
    let neighbours: Vec<usize> = match (flex_layer, m.nav.selected) {
        (Some(f), Some(a)) => flex::neighbours(f, a),
        _ => Vec::new(),
    };
    // The culprits of the selected activity's energy or peak-power failure.
    let culprits: &[usize] = m.would_cause.map_or(&[], |w| w.culprits.as_slice());
    // Where each placed bar is drawn this frame (what a drag picks up).
    let mut drawn: Vec<(usize, Rect)> = Vec::new();
    let mut offset = 0.0_f32;
    for row in &rows {
        let y = rect.top() + offset;
        let h = row.height;
        offset += h + LANE_GAP;
        if !row.label.is_empty() {
            painter.text(
                Pos2::new(rect.left() + 2.0, y + h / 2.0),
                Align2::LEFT_CENTER,
                &row.label,
                font.clone(),
                m.theme.muted,
            );
        }
        // The flexibility layer, behind the row's bars.
        if let Some(f) = flex_layer {
            for bar in row.bars.iter().filter(|b| b.placed) {
                if bar.extent.1 < axis.start || bar.extent.0 > axis.end {
                    continue;
                }
                if let Some(fa) = bar.activity.and_then(|a| f.activity(a)) {
                    let d = (bar.end - bar.start) as i64;
                    // Faded with its bar when the search leaves it out.
                    let left_out = listed.as_ref().is_some_and(|l| !l.shows(fa.activity))
                        && m.nav.selected != Some(fa.activity);
                    if left_out {
                        let mut faded = painter.clone();
                        faded.multiply_opacity(DIMMED);
                        flex::underlay(&faded, m, fa, d, axis, timeline, y, h);
                    } else {
                        flex::underlay(&painter, m, fa, d, axis, timeline, y, h);
                    }
                }
            }
        }
        let current = if row.steps { current } else { None };
        // Cull and merge: consecutive bars that fall in the same pixel column merge.
        let mut merged: Option<(f64, f64, Color32)> = None;
        let flush = |span: Option<(f64, f64, Color32)>| {
            if let Some((x0, x1, c)) = span {
                let r = Rect::from_min_max(
                    Pos2::new(x0 as f32, y),
                    Pos2::new((x1 as f32).max(x0 as f32 + 1.0), y + h),
                );
                painter.rect_filled(r, BAR_ROUNDING, c);
            }
        };
        // The contiguous span `[lo, hi]` that the last bars of one colour painted:
        // a bar of that colour inside it is hidden under earlier ones, as in an
        // overflow lane holding thousands of failed activities' windows, so it is
        // skipped unless it is highlighted.
        let mut painted = (f64::INFINITY, f64::NEG_INFINITY, Color32::TRANSPARENT);
        // Bars the search and filters leave out are context: a run of
        // overlapping ones is drawn once, as their union, so an overflow lane
        // of windows stays faded instead of stacking back up to full colour.
        let mut faded: Option<(f64, f64, Color32, bool)> = None;
        let flush_faded = |run: Option<(f64, f64, Color32, bool)>| {
            if let Some((x0, x1, c, outline)) = run {
                let r = Rect::from_min_max(
                    Pos2::new(x0 as f32, y),
                    Pos2::new((x1 as f32).max(x0 as f32 + 1.0), y + h),
                );
                if outline {
                    window_bar(&painter, r, c);
                } else {
                    painter.rect_filled(r, BAR_ROUNDING, c);
                }
            }
        };
        for bar in &row.bars {
            if bar.end < axis.start || bar.start > axis.end {
                continue;
            }
            let look = match (bar.activity, &listed) {
                (Some(a), Some(l)) if l.shows(a) => Look::Highlighted,
                // The selection is never faded, filtered out or not.
                (Some(a), Some(_)) if Some(a) == m.nav.selected => Look::Plain,
                (Some(_), Some(_)) => Look::Dimmed,
                _ => Look::Plain,
            };
            if let Some(a) = bar.activity {
                looks.push((a, look));
            }
            let color = if look == Look::Dimmed {
                bar.color.gamma_multiply(DIMMED)
            } else {
                bar.color
            };
            let mut x0 = axis.x(bar.start, timeline).max(f64::from(timeline.left()));
            let mut x1 = axis.x(bar.end, timeline).min(f64::from(timeline.right()));
            if bar.marker {
                let w = f64::from(MARKER_WIDTH);
                if x1 - x0 < w {
                    let c = (x0 + x1) / 2.0;
                    (x0, x1) = (c - w / 2.0, c + w / 2.0);
                }
            } else {
                let marked = bar.activity.is_some()
                    && (bar.activity == current || bar.activity == m.nav.selected);
                let neighbour = bar.activity.is_some_and(|a| neighbours.contains(&a));
                if look == Look::Dimmed && !marked && !neighbour {
                    let r = Rect::from_min_max(
                        Pos2::new(x0 as f32, y),
                        Pos2::new((x1 as f32).max(x0 as f32 + 1.0), y + h),
                    );
                    if let Some(a) = bar.activity.filter(|_| bar.placed) {
                        // Still picked up by a drag.
                        drawn.push((a, r));
                    }
                    if pointer.is_some_and(|p| r.contains(p)) {
                        hovered =
                            hover_of(m, bar, row.steps && run.is_none(), flex_layer).or(hovered);
                    }
                    faded = match faded {
                        Some((a, b, c, o)) if c == color && o == bar.outline && x0 <= b => {
                            Some((a, b.max(x1), c, o))
                        }
                        other => {
                            flush_faded(other);
                            Some((x0, x1, color, bar.outline))
                        }
                    };
                    continue;
                }
                flush_faded(faded.take());
                let (lo, hi, painted_color) = painted;
                if color == painted_color && lo <= x0 && x1 <= hi && !marked {
                    continue;
                }
                painted = if color == painted_color && x0 <= hi && lo <= x1 {
                    (lo.min(x0), hi.max(x1), color)
                } else {
                    (x0, x1, color)
                };
                if x1 - x0 < 1.0 {
                    merged = match merged {
                        Some((a, b, c)) if c == color && x0 <= b + 1.0 => Some((a, b.max(x1), c)),
                        other => {
                            flush(other);
                            Some((x0, x1, color))
                        }
                    };
                    continue;
                }
                flush(merged.take());
            }
            let r = Rect::from_min_max(Pos2::new(x0 as f32, y), Pos2::new(x1 as f32, y + h));
            if bar.outline {
                window_bar(&painter, r, color);
            } else {
                painter.rect_filled(r, BAR_ROUNDING, color);
            }
            if look == Look::Highlighted {
                painter.rect_stroke(
                    r,
                    BAR_ROUNDING,
                    Stroke::new(MATCH_STROKE, m.theme.highlight),
                    StrokeKind::Outside,
                );
            }
            let is_current = bar.activity.is_some() && bar.activity == current;
            let is_selected = bar.activity.is_some() && bar.activity == m.nav.selected;
            if is_current {
                painter.rect_stroke(
                    r,
                    BAR_ROUNDING,
                    Stroke::new(CURRENT_STROKE, m.theme.current),
                    StrokeKind::Outside,
                );
            }
            if is_selected {
                painter.rect_stroke(
                    r,
                    BAR_ROUNDING,
                    Stroke::new(SELECTION_STROKE, m.theme.selection),
                    StrokeKind::Outside,
                );
            }
            if bar.placed {
                if let Some(a) = bar.activity {
                    drawn.push((a, r));
                    if culprits.contains(&a) && !is_selected {
                        painter.rect_stroke(
                            r,
                            BAR_ROUNDING,
                            Stroke::new(CULPRIT_STROKE, m.theme.culprit),
                            StrokeKind::Outside,
                        );
                    }
                    if neighbours.contains(&a) && !is_selected {
                        painter.rect_stroke(
                            r,
                            BAR_ROUNDING,
                            Stroke::new(NEIGHBOUR_STROKE, m.theme.neighbour),
                            StrokeKind::Outside,
                        );
                    }
                }
            }
            if r.width() >= LABEL_MIN_WIDTH && h >= LANE_HEIGHT {
                let label = if look == Look::Dimmed {
                    m.theme.label.gamma_multiply(DIMMED * 2.0)
                } else {
                    m.theme.label
                };
                let text = painter.layout_no_wrap(bar.label.clone(), font.clone(), label);
                if text.size().x + 4.0 <= r.width() {
                    painter.galley(
                        Pos2::new(r.left() + 2.0, r.center().y - text.size().y / 2.0),
                        text,
                        label,
                    );
                }
            }
            if pointer.is_some_and(|p| r.contains(p)) {
                hovered = hover_of(m, bar, row.steps && run.is_none(), flex_layer).or(hovered);
            }
        }
        flush(merged);
        flush_faded(faded);
    }
    // The looked-at cycle's time.
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
    // The current time probe (in execution mode the looked-at cycle has the
    // highlight colour).
    if let Some(t) = m.nav.probe {
        let x = axis.x(t as f64, timeline) as f32;
        let color = if run.is_some() {
            m.theme.muted
        } else {
            m.theme.current
        };
        painter.vline(x, timeline.y_range(), Stroke::new(PROBE_LINE_STROKE, color));
    }
    match hovered.filter(|_| !quiet) {
        Some(h) => {
            response.clone().on_hover_text_at_pointer(h.text);
            if response.clicked() {
                if let Some(c) = h.click {
                    cmds.push(c);
                }
            }
        }
        None if !quiet => {
            response.clone().on_hover_text(hint);
        }
        None => {}
    }
    // With the flexibility layer, dragging a placed bar tries another start.
    if response.drag_started() {
        cache.drag = None;
        let press = ui.input(|i| i.pointer.press_origin());
        if let (Some(f), Some(p)) = (flex_layer, press) {
            let hit = drawn.iter().rev().find(|(_, r)| r.contains(p));
            if let Some(&(a, r)) = hit {
                if let (Some(fa), Some((s, e))) = (f.activity(a), m.analysis.placement(a)) {
                    cache.drag = Some(BarDrag {
                        activity: a,
                        grab: axis.t(f64::from(p.x), timeline),
                        start: s,
                        duration: e - s,
                        y: r.top(),
                        h: r.height(),
                        to: fa.start.nom,
                    });
                    if m.nav.selected != Some(a) {
                        cmds.push(Command::Select(Some(a)));
                    }
                }
            }
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
    if let Some((mut d, fa)) = drag_flex {
        let pointer = ui.input(|i| i.pointer.interact_pos());
        if let Some(p) = pointer {
            let per_px = axis.seconds_per_pixel(f64::from(timeline.width()));
            let moved = axis.t(f64::from(p.x), timeline) - d.grab;
            let (lo, hi) = (m.doc.plan.horizon.start, m.doc.plan.horizon.end);
            d.to = flex::snap(fa, d.start, moved, per_px)
                .clamp(lo, hi.saturating_sub(d.duration).max(lo));
        }
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
    // Pan by dragging, zoom with Ctrl+wheel (or pinch) about the pointer.
    if response.dragged() && cache.drag.is_none() {
        let dt = -f64::from(response.drag_delta().x)
            * axis.seconds_per_pixel(f64::from(timeline.width()));
        let mut a = axis;
        a.pan(dt, bounds);
        cmds.push(Command::SetAxis(a));
    }
    if response.hovered() {
        let zoom = ui.input(|i| i.zoom_delta());
        if (zoom - 1.0).abs() > f32::EPSILON {
            if let Some(p) = pointer {
                let mut a = axis;
                a.zoom_about(axis.t(f64::from(p.x), timeline), f64::from(zoom), bounds);
                cmds.push(Command::SetAxis(a));
            }
        }
    }
    cache.gantt = Some(GanttRows { key, rows });
    cache.bars = drawn;
    cache.looks = looks;
}

/// Where activity `a`'s row is on screen (the Gantt's top at `top`), at its
/// bar when that is in view: its placement, else its first window, else any
/// bar of its own (not a heater's).
fn row_of(m: &Model<'_>, rows: &[Row], a: usize, top: f32, timeline: Rect) -> Option<Rect> {
    let id = &m.doc.plan.activities.get(a)?.id;
    let mut best: Option<(u8, Rect)> = None;
    let mut offset = 0.0_f32;
    for row in rows {
        let y = top + offset;
        offset += row.height + LANE_GAP;
        for bar in row.bars.iter().filter(|b| b.activity == Some(a)) {
            let rank = match (bar.placed, bar.outline) {
                (true, _) => 0,
                (_, true) => 1,
                _ if bar.label == *id => 2,
                _ => continue,
            };
            if best.is_some_and(|(r, _)| r <= rank) {
                continue;
            }
            let axis = m.nav.axis;
            let x0 = (axis.x(bar.start, timeline) as f32).clamp(timeline.left(), timeline.right());
            let x1 = (axis.x(bar.end, timeline) as f32).clamp(x0, timeline.right());
            let r = Rect::from_min_max(
                Pos2::new(x0, y),
                Pos2::new(x1.max(x0 + 1.0), y + row.height),
            );
            best = Some((rank, r));
        }
    }
    best.map(|(_, r)| r)
}

#[cfg(test)]
mod tests {
    use super::*;
    // The tests drive the whole app (test code only: the views themselves never
    // reach up into it).
    use crate::gui::SolscopeApp;

    #[test]
    fn an_unplaced_activity_is_drawn_over_each_of_its_windows() {
        let plan = solscope_engine::load_plan(
            r#"{"format":"solscope.plan/1","horizon":{"start":0,"end":1000},
                "battery":{"capacity":100.0,"initial":100.0,"min_soc":0.0},
                "power":{"rtg":100.0,"asleep":10.0,"awake":20.0},
                "activities":[
                  {"id":"two","priority":1,"duration":{"min":10,"max":50},
                   "windows":[{"start":100,"end":200},{"start":900,"end":990}]},
                  {"id":"none","priority":2,"duration":10}]}"#,
        )
        .expect("plan")
        .plan;
        // Start to end plus the longest duration, clipped to the horizon.
        assert_eq!(
            window_spans(&plan, &plan.activities[0]),
            [(100, 250), (900, 1000)]
        );
        assert_eq!(window_spans(&plan, &plan.activities[1]), [(0, 1000)]);
    }

    fn model(app: &SolscopeApp) -> Model<'_> {
        Model {
            doc: &app.doc,
            analysis: &app.analysis,
            theme: app.theme,
            step_view: &app.step_view,
            persisted: &app.persisted,
            suggestions: None,
            revision: app.revision,
            explanation: None,
            explanation_error: None,
            valid: None,
            would_cause: None,
            flex: None,
            free_slack: None,
            nav: &app.ui.nav,
            messages: &app.ui.messages,
            exec: crate::gui::views::ExecModel {
                source: &app.actuals,
                actuals_rev: 0,
                run: None,
                cycle: 0,
                cycle_run: None,
                step: 0,
                view: None,
                loss: None,
                campaign: crate::gui::views::CampaignModel::default(),
            },
        }
    }

    /// `(row label, activity ids)` of the activity bars drawn after the last step
    /// (a continuation lane carries its group's label; heating rows left out).
    fn layout(app: &SolscopeApp) -> Vec<(String, Vec<String>)> {
        let m = model(app);
        let mut group = String::new();
        rows(&m, app.analysis.steps())
            .into_iter()
            .map(|mut r| {
                if r.label.is_empty() {
                    r.label = group.clone();
                } else {
                    group = r.label.clone();
                }
                let ids = r
                    .bars
                    .iter()
                    .filter_map(|b| b.activity)
                    .map(|a| app.doc.plan.activities[a].id.clone())
                    .collect();
                (r.label, ids)
            })
            .filter(|r| !r.0.starts_with("Heat: "))
            .collect()
    }

    /// `(label, bar count)` per row.
    fn shape(rows: &[Row]) -> Vec<(String, usize)> {
        rows.iter()
            .map(|r| (r.label.clone(), r.bars.len()))
            .collect()
    }

    #[test]
    fn cached_rows_follow_the_step_the_plan_and_the_grouping() {
        let mut app = SolscopeApp::with_default_plan().expect("default plan");
        let ctx = egui::Context::default();
        let check = |app: &mut SolscopeApp| {
            let mut out = ctx.run_ui(egui::RawInput::default(), |ui| app.frame_ui(ui));
            out.textures_delta.clear();
            let cached = app.view_cache.gantt.clone().expect("rows kept");
            // The app's own model: with the flexible schedule, which widens
            // what a placed bar takes in its lane.
            let (m, _) = app.model_and_widgets();
            assert!(m.flex_layer().is_some());
            assert_eq!(shape(&cached.rows), shape(&rows(&m, m.nav.step)));
        };
        check(&mut app);
        for k in [0, 10, 35] {
            app.apply(Command::SetStep(k));
            check(&mut app);
        }
        app.apply(Command::GroupByResource(true));
        check(&mut app);
        app.apply(Command::GroupByResource(false));
        app.apply(crate::gui::UiCommand::ToggleFlex.into());
        let mut out = ctx.run_ui(egui::RawInput::default(), |ui| app.frame_ui(ui));
        out.textures_delta.clear();
        let (m, _) = app.model_and_widgets();
        assert!(m.flex_layer().is_none(), "hidden");
        let plain = shape(&rows(&m, m.nav.step));
        assert_eq!(
            shape(&app.view_cache.gantt.clone().expect("kept").rows),
            plain
        );
        app.apply(crate::gui::UiCommand::ToggleFlex.into());
        check(&mut app);
        let mut set = serde_json::Map::new();
        set.insert("mandatory".into(), serde_json::json!(false));
        let id = app.doc.plan.activities[0].id.clone();
        app.apply(Command::Edit {
            target: format!("activity:{id}"),
            set,
            description: "test".into(),
        });
        check(&mut app);
    }

    #[test]
    fn grouping_by_resource_gives_one_row_per_resource() {
        let mut app = SolscopeApp::with_default_plan().expect("default plan");
        let packed = layout(&app);
        assert!(packed.iter().any(|r| r.0 == "Scheduled"));
        assert!(!packed.iter().any(|r| r.0.starts_with("Resource: ")));
        app.apply(Command::GroupByResource(true));
        let grouped = layout(&app);
        assert!(!grouped.iter().any(|r| r.0 == "Scheduled"));
        let plan = &app.doc.plan;
        for (a, act) in plan.activities.iter().enumerate() {
            if app.analysis.placement(a).is_none() || act.comm_kind.is_some() {
                continue;
            }
            // Each scheduled activity appears in the row of every resource it holds,
            // or among those holding none.
            let rows_with: Vec<&str> = grouped
                .iter()
                .filter(|r| r.1.contains(&act.id))
                .map(|r| r.0.as_str())
                .collect();
            if act.resources.is_empty() {
                assert_eq!(rows_with, vec!["No resource"], "{}", act.id);
            } else {
                let want: Vec<String> = act
                    .resources
                    .iter()
                    .map(|r| format!("Resource: {r}"))
                    .collect();
                assert_eq!(rows_with.len(), want.len(), "{}: {rows_with:?}", act.id);
                assert!(rows_with.iter().all(|r| want.iter().any(|w| w == r)));
            }
        }
        // A unit resource is held by one activity at a time: one row each.
        let labels: Vec<&str> = grouped
            .iter()
            .map(|r| r.0.as_str())
            .filter(|l| l.starts_with("Resource: "))
            .collect();
        let mut unique = labels.clone();
        unique.dedup();
        assert_eq!(labels, unique, "a resource needed a second lane");
        assert!(labels.len() >= 3);
    }

    /// The app in execution mode after one frame (the execution derived in it).
    fn executed(mut app: SolscopeApp) -> SolscopeApp {
        app.apply(crate::gui::UiCommand::ShowExecution.into());
        let ctx = egui::Context::default();
        let mut out = ctx.run_ui(egui::RawInput::default(), |ui| app.frame_ui(ui));
        out.textures_delta.clear();
        app
    }

    #[test]
    fn execution_rows_show_every_activity_once_with_its_prediction() {
        let mut app = executed(SolscopeApp::with_default_plan().expect("default plan"));
        let run = app.execution_run().expect("executed");
        let n = app.doc.plan.activities.len();
        let cycles = run.execution.cycles.len();
        let runs = run.execution.activities.clone();
        let (m, _) = app.model_and_widgets();
        let run = m.exec.ready().expect("executed");
        let rows = execution_rows(&m, run);
        assert_eq!(rows[0].label, "Cycles");
        assert_eq!(rows[0].bars.len(), cycles);
        assert!(rows[0].bars.iter().all(|b| b.marker && b.cycle.is_some()));
        // Each activity once: an executed (or not run) bar with its prediction
        // below, or among those never placed.
        let mut main = vec![0; n];
        let mut predicted = vec![0; n];
        let mut never = vec![0; n];
        let mut group = String::new();
        for r in &rows {
            if !r.label.is_empty() {
                group = r.label.clone();
            }
            for b in &r.bars {
                let Some(a) = b.activity else { continue };
                match group.as_str() {
                    "Executed" if r.height < LANE_HEIGHT => predicted[a] += 1,
                    "Executed" => main[a] += 1,
                    "Never placed" => never[a] += 1,
                    _ => {}
                }
            }
        }
        for (a, r) in runs.iter().enumerate() {
            let placed = usize::from(r.predicted.is_some());
            assert_eq!(predicted[a], placed, "activity {a}");
            assert_eq!(main[a], placed, "activity {a}");
            assert_eq!(never[a], 1 - placed, "activity {a}");
        }
        assert!(
            never.iter().sum::<usize>() > 0,
            "the default plan has failures"
        );
        // The looked-at cycle's run follows.
        assert!(rows.iter().any(|r| r.label == "Cycle 0: placed"));
    }

    #[test]
    fn cached_execution_rows_follow_the_cycle_and_its_step() {
        let mut app = executed(SolscopeApp::with_default_plan().expect("default plan"));
        let ctx = egui::Context::default();
        let check = |app: &mut SolscopeApp| {
            let mut out = ctx.run_ui(egui::RawInput::default(), |ui| app.frame_ui(ui));
            out.textures_delta.clear();
            let cached = app.view_cache.gantt.clone().expect("rows kept");
            let (m, _) = app.model_and_widgets();
            let fresh = execution_rows(&m, m.exec.ready().expect("executed"));
            assert_eq!(shape(&cached.rows), shape(&fresh));
        };
        check(&mut app);
        for (cycle, step) in [(3, 10), (3, 0), (20, 40), (0, 70)] {
            app.apply(Command::SetCycle(cycle));
            app.apply(Command::SetCycleStep(step));
            check(&mut app);
        }
    }
}
