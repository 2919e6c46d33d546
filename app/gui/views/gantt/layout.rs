//! The Gantt's rows and lanes: bars packed into as few lanes as possible,
//! the rows of schedule mode as of a step (generated awake and heating
//! rows, comm passes, scheduled activities in lanes or one row per unit
//! resource, failed and pending ones as their windows), and where an
//! activity is drawn.

use eframe::egui::Color32;
use solscope_engine::GeneratedKind;

use crate::gui::theme::LANE_HEIGHT;
use crate::gui::views::{Model, flex};
use crate::state::{Status, window_spans};

/// One bar.
#[derive(Clone, Debug)]
pub(super) struct Bar {
    pub(super) start: f64,
    pub(super) end: f64,
    pub(super) color: Color32,
    pub(super) activity: Option<usize>,
    pub(super) label: String,
    /// Hover text instead of `label start–end`.
    pub(super) tip: Option<String>,
    /// Clicking it looks at this scheduling cycle.
    pub(super) cycle: Option<usize>,
    /// Drawn at least `MARKER_WIDTH` wide, never merged or hidden.
    pub(super) marker: bool,
    /// The bar of `activity`'s placement (schedule mode): it carries the
    /// flexibility layer and can be dragged.
    pub(super) placed: bool,
    /// What it takes in its lane: `[start, end]`, or with the flexibility layer
    /// its whiskers and free slack too.
    pub(super) extent: (f64, f64),
    /// Where an activity could have run, not where it ran (a failed, skipped,
    /// pending or never-run activity's window): drawn hatched and outlined, so
    /// a window over the whole plan does not read as a bar across the chart.
    pub(super) outline: bool,
}

impl Bar {
    pub(super) fn new(
        start: f64,
        end: f64,
        color: Color32,
        activity: Option<usize>,
        label: String,
    ) -> Self {
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
    pub(super) fn window(
        start: i64,
        end: i64,
        color: Color32,
        activity: usize,
        label: String,
    ) -> Self {
        Self {
            outline: true,
            ..Self::new(start as f64, end as f64, color, Some(activity), label)
        }
    }
}

/// One row: a label and its bars.
#[derive(Clone, Debug)]
pub(super) struct Row {
    pub(super) label: String,
    pub(super) bars: Vec<Bar>,
    /// Its height (points).
    pub(super) height: f32,
    /// Its bars follow the step slider (the current step's activity is outlined).
    pub(super) steps: bool,
}

impl Row {
    pub(super) fn new(label: String, bars: Vec<Bar>) -> Self {
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
pub(super) fn lanes<T>(
    mut items: Vec<T>,
    span: impl Fn(&T) -> (f64, f64),
    max_lanes: usize,
) -> Vec<Vec<T>> {
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
pub(super) fn lane_label(i: usize, label: &str) -> String {
    if i == 0 {
        label.to_string()
    } else {
        String::new()
    }
}

/// Packs bars into as few lanes as possible (by start; first lane that is free).
pub(super) fn pack(bars: Vec<Bar>, label: &str, max_lanes: usize) -> Vec<Row> {
    lanes(bars, |b| b.extent, max_lanes)
        .into_iter()
        .enumerate()
        .map(|(i, bars)| Row::new(lane_label(i, label), bars))
        .collect()
}

/// The rows of schedule mode after step `k`: the generated awake and
/// heating rows, comm passes, scheduled activities packed into lanes (or one
/// row per unit resource), failed or skipped ones and pending ones as their
/// windows.
pub(super) fn rows(m: &Model<'_>, k: usize) -> Vec<Row> {
    let plan = &m.doc.plan;
    let t = &m.theme;
    let mut rows = generated_rows(m, k);
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

/// The generated activities alive after step `k`: the awake periods with
/// their wakeup and shutdown, and each thermal zone's heating.
fn generated_rows(m: &Model<'_>, k: usize) -> Vec<Row> {
    let plan = &m.doc.plan;
    let problem = &m.analysis.schedule.problem;
    let t = &m.theme;
    let mut rows = Vec::new();
    // Generated activities alive after step k.
    let mut awake = Vec::new();
    let mut heat: Vec<Vec<Bar>> = vec![Vec::new(); problem.zone_names.len()];
    for g in m.analysis.schedule.generated_after(k) {
        let (start, end) = (g.start as f64, g.end as f64);
        let (zone, activity, color, what) = match g.kind {
            GeneratedKind::Awake => {
                awake.push(Bar::new(start, end, t.awake, None, "awake".into()));
                continue;
            }
            GeneratedKind::Preheat { zone, activity } => (zone, activity, t.preheat, "preheat"),
            GeneratedKind::Maintenance { zone, activity } => {
                (zone, activity, t.maintenance, "maint.")
            }
        };
        let label = format!("{what} {}", plan.activities[activity].id);
        heat[zone].push(Bar::new(start, end, color, Some(activity), label));
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
    rows
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
