//! The flexible schedule in the views: the inspector's Flexibility section, the
//! Gantt's slack layer (free slack shaded behind a bar in two tones, whiskers
//! over the start bounds), and what dragging a bar to a start means.

use eframe::egui::{self, Painter, Pos2, Rect, RichText, Stroke};
use solscope_engine::{
    Bound, Controllability, Flex, FlexActivity, IntervalSet, TimePoint, constraint_line,
    format_span, time_point_name,
};

use super::Model;
use crate::gui::theme::{WHISKER_MIN_REACH, WHISKER_STROKE, WHISKER_TICK};
use crate::gui::time_axis::TimeAxis;
use crate::state::{Command, FLEX_LAYER_MAX_ACTIVITIES, FreeSlackProgress};

/// A bound as read: `10 min after zcam_tau_412 starts`, `when drive ends`.
pub fn bound_line(m: &Model<'_>, b: &Bound) -> String {
    let what = time_point_name(&m.doc.plan, b.event);
    match b.offset {
        0 => format!("when {what}"),
        o if o > 0 => format!("{} after {what}", format_span(o)),
        o => format!("{} before {what}", format_span(o.saturating_neg())),
    }
}

/// A set of starts as read: `57880 (09:25:05) to 58480 (09:35:05), …`.
pub fn set_line(m: &Model<'_>, set: &IntervalSet) -> String {
    if set.is_empty() {
        return "none".to_string();
    }
    set.intervals()
        .iter()
        .map(|iv| {
            if iv.lo == iv.hi {
                m.time(iv.lo)
            } else {
                format!("{} to {}", m.time(iv.lo), m.time(iv.hi))
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// When the activity is skipped under dispatch: once `min(ub, within...)` has
/// passed without it starting.
pub fn skip_line(m: &Model<'_>, fa: &FlexActivity) -> String {
    let ub = m.time(fa.start.ub);
    if fa.condition.within.is_empty() {
        return format!("Skipped if it has not started by {ub}.");
    }
    let mut times: Vec<String> = vec![ub];
    times.extend(fa.condition.within.iter().map(|b| bound_line(m, b)));
    let last = times.pop().unwrap_or_default();
    format!(
        "Skipped once the earliest of {} and {last} has passed without it starting.",
        times.join(", ")
    )
}

/// Activity `a`'s neighbours in the minimum dispatchable network, as the
/// engine lists them (`FlexActivity::neighbours`), except for an activity fixed
/// in time (rigid with the horizon start): the engine then lists every activity
/// adjacent to the horizon start, which is every other fixed or bounded one,
/// and the Gantt would outline half the plan. Such an activity starts on the
/// clock, so only what is rigidly tied to it is shown.
pub fn neighbours(flex: &Flex, a: usize) -> Vec<usize> {
    let Some(fa) = flex.activity(a) else {
        return Vec::new();
    };
    let leader = |e: TimePoint| flex.rigid.iter().find(|r| r.0 == e).map(|r| r.1);
    if leader(TimePoint::Start(a)) != Some(TimePoint::Origin) {
        return fa.neighbours.clone();
    }
    let own = [TimePoint::Start(a), TimePoint::End(a)];
    let mut out: Vec<usize> = flex
        .rigid
        .iter()
        .filter(|r| r.1 != TimePoint::Origin && own.contains(&r.1))
        .filter_map(|r| activity_of(r.0))
        .chain(
            flex.rigid
                .iter()
                .filter(|r| r.1 != TimePoint::Origin && own.contains(&r.0))
                .filter_map(|r| activity_of(r.1)),
        )
        .filter(|&b| b != a)
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// The activity of an event (none for the horizon start).
fn activity_of(e: TimePoint) -> Option<usize> {
    match e {
        TimePoint::Origin => None,
        TimePoint::Start(b) | TimePoint::End(b) => Some(b),
    }
}

/// Where a start lies in an activity's slack.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slack {
    /// In its free slack: every check passes with every other placement fixed.
    Free,
    /// Inside its start bounds `[lb, ub]` only: the network allows it, with
    /// other activities moving too.
    Bounds,
    /// Outside both: moving it there is an edit of the plan.
    Outside,
}

/// Where start `t` lies in `fa`'s slack, and whether it is at least free of
/// temporal conflicts (phase 1: wake/sleep, heating, power or energy may break).
pub fn classify(fa: &FlexActivity, t: i64) -> (Slack, bool) {
    let free = fa.free_slack.as_ref().is_some_and(|s| s.contains(t));
    let phase1 = fa.free_slack_phase1.as_ref().is_some_and(|s| s.contains(t));
    let kind = if free {
        Slack::Free
    } else if fa.start.lb <= t && t <= fa.start.ub {
        Slack::Bounds
    } else {
        Slack::Outside
    };
    (kind, phase1 && !free)
}

/// What a drag of `fa`'s bar to start `t` means, in one line.
pub fn drag_text(m: &Model<'_>, fa: &FlexActivity, t: i64) -> String {
    let id = &m.doc.plan.activities[fa.activity].id;
    let shift = t - fa.start.nom;
    let by = match shift {
        0 => "no shift".to_string(),
        s if s < 0 => format!("{} earlier", format_span(s.saturating_neg())),
        s => format!("{} later", format_span(s)),
    };
    let (kind, phase1) = classify(fa, t);
    let what = match kind {
        Slack::Free => "inside its free slack: every check passes, nothing else moves",
        Slack::Bounds => {
            "inside its bounds [lb, ub] only: dispatchable if other activities move too"
        }
        Slack::Outside => "outside its slack: release to pin it here and reschedule",
    };
    let note = if phase1 {
        " (free of temporal conflicts, but breaks energy, power, wake/sleep or heating)"
    } else {
        ""
    };
    format!("{id} at {} ({by}): {what}{note}", m.time(t))
}

/// Pixels within which a dragged start snaps to a bound or a free-slack edge.
const SNAP_PX: f64 = 6.0;

/// The start a drag by `moved` seconds from `start` means at `per_px` seconds a
/// pixel: the nearest of `lb`, `ub`, the scheduled start and the free slack's
/// edges within a few pixels, else the shift rounded to a step that reads well
/// at this zoom (1 s to 10 min).
pub fn snap(fa: &FlexActivity, start: i64, moved: f64, per_px: f64) -> i64 {
    let raw = start as f64 + moved;
    let near = SNAP_PX * per_px;
    let edges = fa
        .free_slack
        .iter()
        .chain(fa.free_slack_phase1.iter())
        .flat_map(|s| s.intervals().iter().flat_map(|iv| [iv.lo, iv.hi]));
    let best = [fa.start.lb, fa.start.ub, fa.start.nom]
        .into_iter()
        .chain(edges)
        .map(|c| (c, (c as f64 - raw).abs()))
        .filter(|&(_, dist)| dist <= near)
        .min_by(|a, b| a.1.total_cmp(&b.1));
    if let Some((c, _)) = best {
        return c;
    }
    let step = [1.0, 5.0, 10.0, 30.0, 60.0, 300.0, 600.0]
        .into_iter()
        .find(|&s| s >= per_px)
        .unwrap_or(600.0);
    start.saturating_add(((moved / step).round() * step) as i64)
}

/// The span of a bar with its flexibility: its whiskers `[lb, ub + d]` and its
/// free slack (both tones), as plan seconds; `d` is its scheduled duration.
pub fn envelope(fa: &FlexActivity, d: i64) -> (f64, f64) {
    let mut lo = fa.start.lb.min(fa.start.nom);
    let mut hi = fa.start.ub.max(fa.start.nom);
    for set in [&fa.free_slack, &fa.free_slack_phase1]
        .into_iter()
        .flatten()
    {
        if let (Some(a), Some(b)) = (set.intervals().first(), set.intervals().last()) {
            lo = lo.min(a.lo);
            hi = hi.max(b.hi);
        }
    }
    (lo as f64, hi.saturating_add(d) as f64)
}

/// The part of a lane's height the free slack band takes, at its bottom.
const SLACK_BAND: f32 = 0.4;

/// Draws `fa`'s slack behind its bar, inside its own lane `[y, y + h]`
/// (scheduled duration `d`; the bars of the lane are drawn over it): a band
/// along the lane's bottom where it can sit with every check passing (free
/// slack) and where only temporally (the phase-1 part); its whisker from
/// `lb` to `ub + d` with ticks at both ends is gathered into `whiskers`, drawn
/// with the lane's others over the bands.
#[allow(clippy::too_many_arguments)]
pub fn underlay(
    painter: &Painter,
    m: &Model<'_>,
    fa: &FlexActivity,
    d: i64,
    axis: TimeAxis,
    timeline: Rect,
    y: f32,
    h: f32,
    whiskers: &mut Whiskers,
) {
    let x = |t: i64| {
        axis.x(t as f64, timeline)
            .clamp(f64::from(timeline.left()), f64::from(timeline.right())) as f32
    };
    let shade = |set: &IntervalSet, color| {
        for iv in set.intervals() {
            let (x0, x1) = (x(iv.lo), x(iv.hi.saturating_add(d)));
            if x1 > x0 {
                let top = y + h * (1.0 - SLACK_BAND);
                let r = Rect::from_min_max(Pos2::new(x0, top), Pos2::new(x1, y + h));
                painter.rect_filled(r, 0.0, color);
            }
        }
    };
    if let (Some(free), Some(p1)) = (&fa.free_slack, &fa.free_slack_phase1) {
        shade(&p1.subtract(free), m.theme.slack_phase1);
        shade(free, m.theme.slack_free);
    }
    // Past its bar `[nom, nom + d]` by at least a little on one side.
    let reach = |a: i64, b: i64| x(b) - x(a) >= WHISKER_MIN_REACH;
    let seen = reach(fa.start.lb, fa.start.nom)
        || reach(
            fa.start.nom.saturating_add(d),
            fa.start.ub.saturating_add(d),
        );
    if fa.start.ub > fa.start.lb && seen {
        whiskers
            .spans
            .push((x(fa.start.lb), x(fa.start.ub.saturating_add(d))));
        // A tick only where the bound is in view (not where the line is cut).
        for t in [fa.start.lb, fa.start.ub.saturating_add(d)] {
            if axis.start <= t as f64 && t as f64 <= axis.end {
                whiskers.ticks.push(x(t));
            }
        }
    }
}

/// The whiskers of one lane's bars, gathered by [`underlay`] and drawn at
/// once by [`Whiskers::flush`]: lines that overlap are drawn as their union,
/// and a tick once per pixel column. A lane of a zoomed-out plan of
/// thousands of activities holds thousands of overlapping whiskers on one
/// line; drawn one by one they cost most of a frame's tessellation, and
/// looked the same.
#[derive(Debug, Default)]
pub struct Whiskers {
    /// `[x0, x1]` of each whisker line (screen x).
    spans: Vec<(f32, f32)>,
    /// The screen x of each end tick.
    ticks: Vec<f32>,
}

impl Whiskers {
    /// Draws what was gathered across a lane whose middle is at `mid`, and
    /// empties it.
    pub fn flush(&mut self, painter: &Painter, m: &Model<'_>, mid: f32, h: f32) {
        let stroke = Stroke::new(WHISKER_STROKE, m.theme.whisker);
        let tick = WHISKER_TICK.min(h) / 2.0;
        let line = |(x0, x1): (f32, f32)| {
            painter.line_segment([Pos2::new(x0, mid), Pos2::new(x1, mid)], stroke);
        };
        self.spans.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut run: Option<(f32, f32)> = None;
        for &(a, b) in &self.spans {
            match &mut run {
                Some(r) if a <= r.1 => r.1 = r.1.max(b),
                _ => run.replace((a, b)).into_iter().for_each(line),
            }
        }
        run.into_iter().for_each(line);
        self.ticks.sort_by(f32::total_cmp);
        let mut last = f32::NEG_INFINITY;
        for &xe in &self.ticks {
            if xe - last >= 1.0 {
                painter.line_segment(
                    [Pos2::new(xe, mid - tick), Pos2::new(xe, mid + tick)],
                    stroke,
                );
                last = xe;
            }
        }
        self.spans.clear();
        self.ticks.clear();
    }
}

/// What the flexibility layer's marks mean (over the Gantt in schedule mode),
/// or that it is being computed.
pub fn legend_ui(ui: &mut egui::Ui, m: &Model<'_>) {
    let t = &m.theme;
    ui.horizontal_wrapped(|ui| {
        ui.label(RichText::new("Flexibility:").color(t.muted));
        match m.flex {
            None => {
                ui.spinner();
                ui.label(RichText::new("computing the flexible schedule…").color(t.muted));
            }
            Some(Err(e)) => {
                ui.label(RichText::new(e).color(t.error));
            }
            Some(Ok(_)) => {
                ui.label(RichText::new("|–| start bounds [lb, ub]").color(t.whisker))
                    .on_hover_text("From the earliest start to the latest start plus the duration");
                ui.label(RichText::new(" free slack ").background_color(t.slack_free))
                    .on_hover_text("Every check passes with every other placement where it is");
                ui.label(RichText::new(" temporal only ").background_color(t.slack_phase1))
                    .on_hover_text(
                        "Free of temporal conflicts, but breaks energy, power, wake/sleep or heating",
                    );
                ui.label(RichText::new("selected's neighbours").color(t.neighbour))
                    .on_hover_text("Adjacent in the minimum dispatchable network");
                ui.label(RichText::new("· drag a bar to try another start").color(t.muted));
                free_slack_status_ui(ui, m);
            }
        }
    });
}

/// How far the free slack has come, while it is not all known: a long plan's
/// free slack takes minutes or more (one replay of the schedule per
/// activity), so the layer shows it as it fills in and says so.
fn free_slack_status_ui(ui: &mut egui::Ui, m: &Model<'_>) {
    let Some(p) = m.free_slack.filter(|p| !p.complete()) else {
        return;
    };
    if p.running {
        ui.spinner();
    }
    ui.label(RichText::new(free_slack_status(p)).color(m.theme.muted))
        .on_hover_text(crate::gui::help::FREE_SLACK_PROGRESS);
}

/// "free slack: 1,234 of 5,624 activities so far (2 min 10 s, about 8 min
/// left), nearest the time range in view first", or where it stopped.
pub fn free_slack_status(p: FreeSlackProgress) -> String {
    let spent = format_span(p.seconds as i64);
    if p.failed {
        return format!(
            "free slack: {} of {} activities known (its computation failed after {spent})",
            p.done, p.total
        );
    }
    if !p.running {
        return format!(
            "free slack: {} of {} activities known (stopped after {spent}; it goes on \
             while the layer is shown)",
            p.done, p.total
        );
    }
    // The rate so far (activities differ: a rough guide).
    let left = (p.done > 0 && p.seconds > 0).then(|| {
        let per = p.seconds as f64 / p.done as f64;
        format_span((per * (p.total - p.done) as f64).round() as i64)
    });
    match left {
        Some(left) => format!(
            "computing free slack: {} of {} activities so far ({spent}, about {left} left at \
             this rate), nearest the time range in view first",
            p.done, p.total
        ),
        None => format!(
            "computing free slack: {} of {} activities so far ({spent}), nearest the time \
             range in view first",
            p.done, p.total
        ),
    }
}

/// The hover text's flexibility part for a bar.
pub fn hover_line(m: &Model<'_>, fa: &FlexActivity) -> String {
    let s = fa.start;
    if s.lb == s.ub {
        return "fixed: no slack".to_string();
    }
    format!(
        "may start {} earlier, {} later (from {} to {})",
        format_span(s.nom - s.lb),
        format_span(s.ub - s.nom),
        m.time(s.lb),
        m.time(s.ub)
    )
}

/// The inspector's Flexibility section for activity `a` (when it is placed).
pub fn flex_section_ui(ui: &mut egui::Ui, m: &Model<'_>, a: usize, cmds: &mut Vec<Command>) {
    let flex: &Flex = match m.flex {
        None => {
            ui.label(RichText::new("Flexibility").strong())
                .on_hover_text(crate::gui::help::FLEXIBILITY);
            ui.horizontal(|ui| {
                ui.spinner();
                ui.label("computing the flexible schedule…");
            });
            return;
        }
        Some(Err(e)) => {
            ui.label(RichText::new("Flexibility").strong())
                .on_hover_text(crate::gui::help::FLEXIBILITY);
            ui.colored_label(m.theme.error, e);
            return;
        }
        Some(Ok(f)) => f,
    };
    let Some(fa) = flex.activity(a) else {
        return;
    };
    ui.label(RichText::new("Flexibility").strong())
        .on_hover_text(crate::gui::help::FLEXIBILITY);
    let s = fa.start;
    ui.label(format!("Scheduled at {}.", m.time(s.nom)));
    ui.label(format!(
        "May start from {} to {} ({} earlier, {} later).",
        m.time(s.lb),
        m.time(s.ub),
        format_span(s.nom - s.lb),
        format_span(s.ub - s.nom)
    ));
    let c = &fa.condition;
    if c.after.len() == 1 && c.after == c.within {
        ui.label(format!(
            "Starts exactly {} (tied rigidly to it).",
            bound_line(m, &c.after[0])
        ));
    } else {
        for b in &c.after {
            ui.label(format!("Starts no earlier than {}.", bound_line(m, b)));
        }
        for b in &c.within {
            ui.label(format!("Starts no later than {}.", bound_line(m, b)));
        }
        if c.after.is_empty() && c.within.is_empty() {
            ui.label("No other activity conditions its start.");
        }
    }
    ui.label(skip_line(m, fa));
    if fa.free_slack.is_none()
        && !m.flex_shown()
        && m.doc.plan.activities.len() > FLEX_LAYER_MAX_ACTIVITIES
    {
        ui.label(format!(
            "Its free slack is computed once the flexibility layer is on (it starts off on \
             plans of more than {FLEX_LAYER_MAX_ACTIVITIES} activities)."
        ))
        .on_hover_text(crate::gui::help::FREE_SLACK_PROGRESS);
    } else if fa.free_slack.is_none() {
        if let Some(p) = m.free_slack {
            ui.horizontal_wrapped(|ui| {
                if p.computing == Some(a) {
                    ui.spinner();
                    ui.label("Computing its free slack (one replay of the schedule)…")
                        .on_hover_text(crate::gui::help::FREE_SLACK_PROGRESS);
                    return;
                }
                if p.running {
                    ui.spinner();
                }
                ui.label(format!(
                    "Its free slack is not known yet; {}.",
                    free_slack_status(p)
                ))
                .on_hover_text(crate::gui::help::FREE_SLACK_PROGRESS);
            });
        }
    }
    if let (Some(free), Some(p1)) = (&fa.free_slack, &fa.free_slack_phase1) {
        ui.label(
            RichText::new(format!(
                "Free slack (every check, others fixed): {}",
                set_line(m, free)
            ))
            .color(m.theme.valid),
        );
        let extra = p1.subtract(free);
        if !extra.is_empty() {
            ui.label(format!(
                "Also free of temporal conflicts, but breaking energy, power, wake/sleep or heating: {}",
                set_line(m, &extra)
            ));
        }
    }
    controllability_ui(ui, m, flex, fa);
    let near = neighbours(flex, a);
    if !near.is_empty() {
        ui.label(RichText::new("Dispatchable neighbours (click to select)").strong());
        ui.horizontal_wrapped(|ui| {
            for &b in &near {
                if ui.link(&m.doc.plan.activities[b].id).clicked() {
                    cmds.push(Command::Select(Some(b)));
                }
            }
        });
    }
    ui.label(RichText::new("Drag its bar on the Gantt to try another start.").color(m.theme.muted));
}

/// The controllability verdict (when the plan has uncertain durations) and
/// this activity's waits and tightened bounds.
fn controllability_ui(ui: &mut egui::Ui, m: &Model<'_>, flex: &Flex, fa: &FlexActivity) {
    let plan = &m.doc.plan;
    match &flex.controllability {
        Controllability::Certain => {}
        Controllability::Controllable { tightened, waits } => {
            ui.label(
                "Dynamically controllable: every outcome of the uncertain durations can be met.",
            );
            if let Some(&(_, lb, ub)) = tightened.iter().find(|t| t.0 == fa.activity) {
                if (lb, ub) != (fa.start.lb, fa.start.ub) {
                    ui.label(format!(
                        "Whatever the uncertain durations: from {} to {}.",
                        m.time(lb),
                        m.time(ub)
                    ));
                }
            }
            for w in waits.iter().filter(|w| w.activity == fa.activity) {
                ui.label(format!(
                    "Waits until {} ends or {} after it starts.",
                    plan.activities[w.on].id,
                    format_span(w.offset)
                ));
            }
        }
        Controllability::NotControllable {
            activities,
            constraints,
        } if activities.contains(&fa.activity) => {
            ui.colored_label(
                m.theme.error,
                "NOT dynamically controllable. The constraints that make it so:",
            );
            for c in constraints {
                ui.label(format!("• {}", constraint_line(plan, c)));
            }
            ui.label("This activity is one of those involved.");
        }
        // The plan-wide verdict in full only where it applies: elsewhere one
        // line naming the activities involved, to select.
        Controllability::NotControllable { activities, .. } => {
            let names: Vec<&str> = activities
                .iter()
                .map(|&x| plan.activities[x].id.as_str())
                .collect();
            ui.label(format!(
                "The plan is not dynamically controllable, because of {}; this activity is not involved.",
                names.join(", ")
            ));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use solscope_engine::{EventBounds, StartCondition};

    /// Scheduled at 1000, may start 800..=1600, free slack 1000..=1200 and
    /// temporally free 900..=1300.
    fn activity() -> FlexActivity {
        FlexActivity {
            activity: 0,
            start: EventBounds {
                lb: 800,
                nom: 1000,
                ub: 1600,
            },
            end: EventBounds {
                lb: 900,
                nom: 1100,
                ub: 1700,
            },
            condition: StartCondition::default(),
            neighbours: Vec::new(),
            free_slack: Some(IntervalSet::single(1000, 1200)),
            free_slack_phase1: Some(IntervalSet::single(900, 1300)),
        }
    }

    #[test]
    fn a_start_is_free_within_bounds_or_outside() {
        let fa = activity();
        assert_eq!(classify(&fa, 1100), (Slack::Free, false));
        assert_eq!(classify(&fa, 1250), (Slack::Bounds, true));
        assert_eq!(classify(&fa, 1500), (Slack::Bounds, false));
        assert_eq!(classify(&fa, 799), (Slack::Outside, false));
        assert_eq!(classify(&fa, 1601), (Slack::Outside, false));
    }

    #[test]
    fn a_drag_snaps_to_edges_then_to_a_step_of_the_zoom() {
        let fa = activity();
        // 2 s a pixel: within 12 s of ub it is ub.
        assert_eq!(snap(&fa, 1000, 590.0, 2.0), 1600);
        assert_eq!(snap(&fa, 1000, 197.0, 2.0), 1200);
        // Elsewhere the shift is rounded to 5 s.
        assert_eq!(snap(&fa, 1000, 452.0, 2.0), 1450);
        // 40 s a pixel: a minute.
        assert_eq!(snap(&fa, 1000, 2020.0, 40.0), 3040);
    }

    #[test]
    fn the_envelope_holds_whiskers_and_free_slack() {
        let mut fa = activity();
        assert_eq!(envelope(&fa, 100), (800.0, 1700.0));
        fa.free_slack_phase1 = Some(IntervalSet::single(700, 2000));
        assert_eq!(envelope(&fa, 100), (700.0, 2100.0));
    }
}
