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
    /// How far it reaches with its flexibility layer (whiskers and free
    /// slack; `[start, end]` without one): the layer is drawn while that is in
    /// view. The layer is drawn inside the bar's lane, so lanes are packed by
    /// `[start, end]` alone.
    pub(super) extent: (f64, f64),
    /// Where an activity could have run, not where it ran (a failed, skipped,
    /// pending or never-run activity's window): drawn hatched and outlined, so
    /// a window over the whole plan does not read as a bar across the chart.
    pub(super) outline: bool,
    /// The steps `[from, until)` after which it is drawn (schedule mode lays
    /// the rows out once per schedule: a placement from its step on, a
    /// window while its activity is pending or once it failed).
    pub(super) steps: (usize, usize),
}

impl Bar {
    /// Whether it is drawn after step `k`.
    pub(super) fn shown_at(&self, k: usize) -> bool {
        self.steps.0 <= k && k < self.steps.1
    }
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
            steps: (0, usize::MAX),
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
    /// The one activity the row is for (a failed or skipped activity's own
    /// row): its label names it, for screen readers too.
    pub(super) activity: Option<usize>,
    /// Its bars are labelled where they have room (not in a folded row of
    /// overlapping windows, whose labels would cover each other).
    pub(super) bar_labels: bool,
    /// The steps of the failed or skipped activities folded into it, sorted.
    pub(super) folded: Vec<usize>,
    /// The steps `[from, until)` after which any of its bars is drawn.
    pub(super) steps_shown: (usize, usize),
    /// With bars sorted by start: the latest end of each bar and those
    /// before it, so the bars in a time range are found by bisection.
    pub(super) reach: Vec<f64>,
    /// The same for the ends of the bars' extents (with their flexibility
    /// layers), and how far any extent starts before its bar: the layers in
    /// a time range are found by bisection too.
    pub(super) extent_reach: Vec<f64>,
    pub(super) lead: f64,
}

impl Row {
    pub(super) fn new(label: String, bars: Vec<Bar>) -> Self {
        let steps_shown = bars.iter().fold((usize::MAX, 0), |(lo, hi), b| {
            (lo.min(b.steps.0), hi.max(b.steps.1))
        });
        // With the bars sorted by start, the latest end of each bar and those
        // before it (for bisection); else nothing.
        let sorted = bars.windows(2).all(|w| w[0].start <= w[1].start);
        let running_max = |end: fn(&Bar) -> f64| -> Vec<f64> {
            if !sorted {
                return Vec::new();
            }
            bars.iter()
                .scan(f64::NEG_INFINITY, |r, b| {
                    *r = r.max(end(b));
                    Some(*r)
                })
                .collect()
        };
        let reach = running_max(|b| b.end);
        let extent_reach = running_max(|b| b.extent.1);
        let lead = bars
            .iter()
            .map(|b| b.start - b.extent.0)
            .fold(0.0, f64::max);
        Self {
            label,
            bars,
            steps_shown,
            reach,
            extent_reach,
            lead,
            height: LANE_HEIGHT,
            steps: true,
            activity: None,
            bar_labels: true,
            folded: Vec::new(),
        }
    }

    /// Whether any of its bars is drawn after step `k` (a row without bars,
    /// such as an empty awake row, is always drawn).
    pub(super) fn shown_at(&self, k: usize) -> bool {
        self.bars.is_empty() || (self.steps_shown.0 <= k && k < self.steps_shown.1)
    }

    /// Its bars that may meet `[t0, t1]` (plan seconds): found by bisection
    /// when they are sorted by start, else all of them.
    pub(super) fn bars_in(&self, t0: f64, t1: f64) -> &[Bar] {
        if self.reach.len() != self.bars.len() {
            return &self.bars;
        }
        let first = self.reach.partition_point(|&r| r < t0);
        let last = self.bars.partition_point(|b| b.start <= t1);
        self.bars.get(first..last.max(first)).unwrap_or_default()
    }

    /// Its bars whose extent ([`Bar::extent`]) may meet `[t0, t1]`: found by
    /// bisection when they are sorted by start, else all of them.
    pub(super) fn extents_in(&self, t0: f64, t1: f64) -> &[Bar] {
        if self.extent_reach.len() != self.bars.len() {
            return &self.bars;
        }
        let first = self.extent_reach.partition_point(|&r| r < t0);
        let last = self.bars.partition_point(|b| b.start <= t1 + self.lead);
        self.bars.get(first..last.max(first)).unwrap_or_default()
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

/// Packs bars into lanes, each lane carrying the group's label (drawn once,
/// on the first lane drawn), at most `max_lanes` (the last takes the
/// overflow). A bar goes to the first lane where it overlaps nothing, taken
/// in the order the steps show them: those drawn from an earlier step first
/// (placements), those drawn until a later step first (pending windows),
/// then by start. So the bars drawn after any step fill the first lanes as
/// they would packed on their own (first fit), and a bar keeps its lane at
/// every step. Each lane's bars end up sorted by start.
pub(super) fn pack(mut bars: Vec<Bar>, label: &str, max_lanes: usize) -> Vec<Row> {
    bars.sort_by(|a, b| {
        a.steps
            .0
            .cmp(&b.steps.0)
            .then(b.steps.1.cmp(&a.steps.1))
            .then(a.start.total_cmp(&b.start))
            .then(a.end.total_cmp(&b.end))
    });
    // Each lane's spans by (start, index) → end, in whole seconds.
    let mut taken: Vec<std::collections::BTreeMap<(i64, usize), i64>> = Vec::new();
    let mut out: Vec<Vec<Bar>> = Vec::new();
    for (i, bar) in bars.into_iter().enumerate() {
        let (s, e) = (bar.start.floor() as i64, bar.end.ceil() as i64);
        let free = |lane: &std::collections::BTreeMap<(i64, usize), i64>| {
            let before = lane.range(..(s, usize::MAX)).next_back();
            let after = lane.range((s, 0)..).next();
            before.is_none_or(|(_, &end)| end <= s)
                && after.is_none_or(|(&(start, _), _)| start >= e)
        };
        let lane = match taken.iter().position(free) {
            Some(l) => l,
            None if taken.len() < max_lanes => {
                taken.push(std::collections::BTreeMap::new());
                out.push(Vec::new());
                taken.len() - 1
            }
            None => taken.len() - 1,
        };
        taken[lane].insert((s, i), e);
        out[lane].push(bar);
    }
    if out.is_empty() {
        out.push(Vec::new());
    }
    out.into_iter()
        .map(|mut lane| {
            lane.sort_by(|a, b| a.start.total_cmp(&b.start));
            Row::new(label.to_string(), lane)
        })
        .collect()
}

/// More failed or skipped activities than this are folded into one row
/// until unfolded.
pub(super) const FOLD_FAILED_OVER: usize = 12;

/// How many failed or skipped activities `rows` show after step `k` (folded
/// or in rows of their own).
pub(super) fn failed_shown(rows: &[Row], k: usize) -> usize {
    rows.iter()
        .map(|r| match r.activity {
            Some(_) => usize::from(r.shown_at(k)),
            None => r.folded.partition_point(|&s| s <= k),
        })
        .sum()
}

/// The rows of schedule mode as of step `k`, as drawn: the generated rows
/// and those of [`schedule_rows`] shown after `k`, with only their bars shown
/// then.
#[cfg(test)]
pub(super) fn rows(m: &Model<'_>, k: usize, unfold: bool) -> Vec<Row> {
    generated_rows(m)
        .into_iter()
        .chain(schedule_rows(m, unfold))
        .filter(|r| r.shown_at(k))
        .map(|r| {
            let bars = r.bars.into_iter().filter(|b| b.shown_at(k)).collect();
            Row { bars, ..r }
        })
        .collect()
}

/// The rows of schedule mode, laid out once per schedule (each bar drawn
/// from or until its activity's step): comm passes, scheduled activities
/// packed into lanes over the whole run (or one row per unit resource), so a
/// bar keeps its lane at every step; failed or skipped ones as their
/// windows, one row each (folded into one unlabelled row when there are more
/// than [`FOLD_FAILED_OVER`], unless `unfold`); and pending ones as their
/// windows. The generated rows are laid out the same way ([`generated_rows`]).
pub(super) fn schedule_rows(m: &Model<'_>, unfold: bool) -> Vec<Row> {
    let plan = &m.doc.plan;
    let t = &m.theme;
    let mut rows = Vec::new();
    let (mut comm, mut scheduled, mut failed, mut pending) =
        (Vec::new(), Vec::new(), Vec::<Vec<Bar>>::new(), Vec::new());
    // With the flexibility layer, how far a placed bar's whiskers and free
    // slack reach (drawn inside its lane, under the bars).
    let flex = m.flex_layer();
    for (a, act) in plan.activities.iter().enumerate() {
        let label = act.id.clone();
        // Its step (none: pending throughout).
        let step = m.analysis.step(a).map_or(usize::MAX, |s| s.step);
        let windows = |color| {
            window_spans(plan, act)
                .into_iter()
                .map(move |(lo, hi)| Bar::window(lo, hi, color, a, act.id.clone()))
        };
        pending.extend(windows(t.pending).map(|b| Bar {
            steps: (0, step),
            ..b
        }));
        match m.status(a, usize::MAX) {
            Status::Scheduled(s, e) => {
                let color = if act.comm_kind.is_some() {
                    t.comm
                } else {
                    t.scheduled
                };
                let mut bar = Bar::new(s as f64, e as f64, color, Some(a), label);
                bar.placed = true;
                bar.steps = (step, usize::MAX);
                if let Some(fa) = flex.and_then(|f| f.activity(a)) {
                    bar.extent = flex::envelope(fa, e - s);
                }
                if act.comm_kind.is_some() {
                    comm.push(bar);
                } else {
                    scheduled.push(bar);
                }
            }
            Status::Pending => {}
            status => {
                let color = if status == Status::Failed {
                    t.failed
                } else {
                    t.skipped
                };
                let bars = windows(color).map(|b| Bar {
                    steps: (step, usize::MAX),
                    ..b
                });
                failed.push(bars.collect());
            }
        }
    }
    rows.extend(pack(comm, "Comm passes", 2));
    if m.persisted.by_resource {
        rows.extend(by_resource(plan, scheduled));
    } else {
        rows.extend(pack(scheduled, "Scheduled", 64));
    }
    rows.extend(failed_rows(failed, unfold));
    rows.extend(pack(pending, "Pending (windows)", 8));
    rows
}

/// The failed or skipped activities' windows (each activity's bars), in
/// order of their first window: one row each, labelled with the activity's
/// id, or with more than [`FOLD_FAILED_OVER`] and not `unfold` one row
/// holding them all (`Failed / skipped`, its bars unlabelled).
fn failed_rows(mut failed: Vec<Vec<Bar>>, unfold: bool) -> Vec<Row> {
    failed.retain(|bars| !bars.is_empty());
    if failed.len() > FOLD_FAILED_OVER && !unfold {
        let mut steps: Vec<usize> = failed.iter().map(|bars| bars[0].steps.0).collect();
        steps.sort_unstable();
        let bars = failed.into_iter().flatten().collect();
        return pack(bars, "Failed / skipped", 1)
            .into_iter()
            .map(|r| Row {
                bar_labels: false,
                folded: steps.clone(),
                ..r
            })
            .collect();
    }
    failed.sort_by(|a, b| a[0].start.total_cmp(&b[0].start));
    failed
        .into_iter()
        .map(|mut bars| {
            bars.sort_by(|a, b| a.start.total_cmp(&b.start));
            let activity = bars[0].activity;
            Row {
                activity,
                ..Row::new(bars[0].label.clone(), bars)
            }
        })
        .collect()
}

/// The generated rows of schedule mode, laid out once per schedule like
/// [`schedule_rows`]: the awake periods with their wakeup and shutdown, and
/// each thermal zone's heating, every bar drawn while its generated activity
/// is alive (`[added_at, retired_at)`). Moving the step slider then formats no
/// label and packs no lane again (at 10,000 activities that was a tenth of a
/// drag frame), and a heater bar keeps its lane at every step. The awake row
/// and each zone's first lane are drawn at every step, empty or not.
pub(super) fn generated_rows(m: &Model<'_>) -> Vec<Row> {
    let plan = &m.doc.plan;
    let problem = &m.analysis.schedule.problem;
    let t = &m.theme;
    let mut rows = Vec::new();
    let mut awake = Vec::new();
    let mut heat: Vec<Vec<Bar>> = vec![Vec::new(); problem.zone_names.len()];
    for g in &m.analysis.schedule.generated {
        let (start, end) = (g.start as f64, g.end as f64);
        let steps = (g.added_at, g.retired_at.unwrap_or(usize::MAX));
        let (zone, activity, color, what) = match g.kind {
            GeneratedKind::Awake => {
                awake.push(Bar {
                    steps,
                    ..Bar::new(start, end, t.awake, None, "awake".into())
                });
                continue;
            }
            GeneratedKind::Preheat { zone, activity } => (zone, activity, t.preheat, "preheat"),
            GeneratedKind::Maintenance { zone, activity } => {
                (zone, activity, t.maintenance, "maint.")
            }
        };
        let label = format!("{what} {}", plan.activities[activity].id);
        heat[zone].push(Bar {
            steps,
            ..Bar::new(start, end, color, Some(activity), label)
        });
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
                edges.push(Bar {
                    steps: bar.steps,
                    ..Bar::new(start, end, t.wake, None, label.into())
                });
            }
        }
    }
    // Sorted by start, so that a frame finds the bars in view by bisection
    // (the row holds every period of every step); a wakeup after the period
    // it starts, so it is drawn over it. The periods alive after one step are
    // disjoint and each edge lies inside its own, so this is the drawing
    // order of periods first, edges over them.
    let mut bars: Vec<(bool, Bar)> = awake
        .into_iter()
        .map(|b| (false, b))
        .chain(edges.into_iter().map(|b| (true, b)))
        .collect();
    bars.sort_by(|(x, a), (y, b)| a.start.total_cmp(&b.start).then(x.cmp(y)));
    let awake = bars.into_iter().map(|(_, b)| b).collect();
    rows.push(always_shown(Row::new("Awake".into(), awake)));
    for (z, bars) in heat.into_iter().enumerate() {
        let mut lanes = pack(bars, &format!("Heat: {}", problem.zone_names[z]), 3).into_iter();
        rows.extend(lanes.next().map(always_shown));
        rows.extend(lanes);
    }
    rows
}

/// `row`, drawn after every step even while none of its bars is.
fn always_shown(row: Row) -> Row {
    Row {
        steps_shown: (0, usize::MAX),
        ..row
    }
}

/// Scheduled bars in one row per unit resource (resource names in order; an
/// activity holding several appears in each of their rows), then those holding
/// none in packed lanes. A unit resource is held by one activity at a time, so
/// each resource needs one row.
fn by_resource(plan: &solscope_engine::Plan, scheduled: Vec<Bar>) -> Vec<Row> {
    let mut groups: std::collections::BTreeMap<&str, Vec<Bar>> = std::collections::BTreeMap::new();
    let mut none = Vec::new();
    for bar in scheduled {
        let held = bar
            .activity
            .and_then(|a| plan.activities.get(a))
            .map(|act| act.resources.as_slice())
            .unwrap_or_default();
        if held.is_empty() {
            none.push(bar);
            continue;
        }
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
