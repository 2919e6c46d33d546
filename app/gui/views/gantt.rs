//! Gantt rows as of the current step: generated awake and heating rows, comm
//! passes, scheduled activities packed into lanes, failed ones, and pending ones
//! drawn as their allowed windows. Bars narrower than a pixel are merged, bars
//! outside the view culled, so 10k activities stay fluid.

use eframe::egui::{self, Align2, Color32, FontId, Pos2, Rect, Sense, Stroke, StrokeKind};
use solscope_engine::GeneratedKind;

use super::{Model, Status, ViewCache};
use crate::gui::commands::Command;
use crate::gui::theme::{
    BAR_FONT_SIZE, BAR_ROUNDING, CURRENT_STROKE, LABEL_MIN_WIDTH, LABEL_WIDTH, LANE_GAP,
    LANE_HEIGHT, PROBE_LINE_STROKE, SELECTION_STROKE,
};

/// One bar.
#[derive(Clone, Debug)]
struct Bar {
    start: f64,
    end: f64,
    color: Color32,
    activity: Option<usize>,
    label: String,
}

/// One row: a label and its bars.
#[derive(Clone, Debug)]
struct Row {
    label: String,
    bars: Vec<Bar>,
}

/// Packs bars into as few lanes as possible (by start; first lane that is free).
fn pack(mut bars: Vec<Bar>, label: &str, max_lanes: usize) -> Vec<Row> {
    bars.sort_by(|a, b| a.start.total_cmp(&b.start).then(a.end.total_cmp(&b.end)));
    let mut lanes: Vec<(f64, Vec<Bar>)> = Vec::new();
    for bar in bars {
        let n = lanes.len();
        let free = lanes.iter().position(|l| l.0 <= bar.start);
        match free {
            Some(i) => {
                lanes[i].0 = bar.end;
                lanes[i].1.push(bar);
            }
            None if n < max_lanes => lanes.push((bar.end, vec![bar])),
            None => {
                if let Some(last) = lanes.last_mut() {
                    last.0 = last.0.max(bar.end);
                    last.1.push(bar);
                }
            }
        }
    }
    if lanes.is_empty() {
        lanes.push((0.0, Vec::new()));
    }
    lanes
        .into_iter()
        .enumerate()
        .map(|(i, (_, bars))| Row {
            label: if i == 0 {
                label.to_string()
            } else {
                String::new()
            },
            bars,
        })
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
            GeneratedKind::Awake => awake.push(Bar {
                start: g.start as f64,
                end: g.end as f64,
                color: t.awake,
                activity: None,
                label: "awake".into(),
            }),
            GeneratedKind::Preheat { zone, activity } => heat[zone].push(Bar {
                start: g.start as f64,
                end: g.end as f64,
                color: t.preheat,
                activity: Some(activity),
                label: format!("preheat {}", plan.activities[activity].id),
            }),
            GeneratedKind::Maintenance { zone, activity } => heat[zone].push(Bar {
                start: g.start as f64,
                end: g.end as f64,
                color: t.maintenance,
                activity: Some(activity),
                label: format!("maint. {}", plan.activities[activity].id),
            }),
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
                edges.push(Bar {
                    start,
                    end,
                    color: t.wake,
                    activity: None,
                    label: label.into(),
                });
            }
        }
    }
    awake.sort_by(|a, b| a.start.total_cmp(&b.start));
    edges.sort_by(|a, b| a.start.total_cmp(&b.start));
    awake.extend(edges);
    rows.push(Row {
        label: "Awake".into(),
        bars: awake,
    });
    for (z, bars) in heat.into_iter().enumerate() {
        rows.extend(pack(bars, &format!("Heat: {}", problem.zone_names[z]), 3));
    }
    let (mut comm, mut scheduled, mut failed, mut pending) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (a, act) in plan.activities.iter().enumerate() {
        let label = act.id.clone();
        match m.status(a, k) {
            Status::Scheduled(s, e) => {
                let bar = Bar {
                    start: s as f64,
                    end: e as f64,
                    color: if act.comm_kind.is_some() {
                        t.comm
                    } else {
                        t.scheduled
                    },
                    activity: Some(a),
                    label,
                };
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
                let windows = act.windows.clone().unwrap_or_default();
                let (lo, hi) = match windows.first() {
                    Some(w) => (
                        w.start,
                        w.end
                            .saturating_add(act.duration.max())
                            .min(plan.horizon.end),
                    ),
                    None => (plan.horizon.start, plan.horizon.end),
                };
                let bar = Bar {
                    start: lo as f64,
                    end: hi as f64,
                    color,
                    activity: Some(a),
                    label,
                };
                if status == Status::Pending {
                    pending.push(bar);
                } else {
                    failed.push(bar);
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

/// The rows as of one step, kept between frames: building them sorts and packs
/// every activity, which at 10k activities costs more than drawing them.
#[derive(Clone, Debug)]
pub struct GanttRows {
    /// Plan revision, step, grouping and palette they were built for.
    key: (u64, usize, bool, Color32),
    rows: Vec<Row>,
}

/// The Gantt chart.
pub fn gantt_ui(ui: &mut egui::Ui, m: &Model<'_>, cache: &mut ViewCache, cmds: &mut Vec<Command>) {
    let k = m.nav.step;
    let key = (m.revision, k, m.persisted.by_resource, m.theme.scheduled);
    let rows = match cache.gantt.take() {
        Some(cached) if cached.key == key => cached.rows,
        _ => rows(m, k),
    };
    let height = rows.len() as f32 * (LANE_HEIGHT + LANE_GAP) + 4.0;
    let (rect, response) = ui.allocate_exact_size(
        egui::vec2(ui.available_width(), height),
        Sense::click_and_drag(),
    );
    let response =
        response.on_hover_text("Click a bar to inspect it; drag to pan; Ctrl+wheel to zoom");
    response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Image, true, "Gantt chart"));
    // Share the plots' data area (last frame) so one time is one x everywhere.
    let (left, right) = cache
        .plot_x
        .filter(|(l, r)| *l > rect.left() && *r <= rect.right() + 1.0 && r > l)
        .unwrap_or((rect.left() + LABEL_WIDTH, rect.right()));
    let timeline = Rect::from_min_max(Pos2::new(left, rect.top()), Pos2::new(right, rect.bottom()));
    let painter = ui.painter_at(rect);
    let axis = m.nav.axis;
    let bounds = (
        m.doc.plan.horizon.start as f64,
        m.doc.plan.horizon.end as f64,
    );
    let current = m.activity_of_step(k);
    let font = FontId::proportional(BAR_FONT_SIZE);
    let mut hovered: Option<(usize, String)> = None;
    let pointer = response.hover_pos();
    for (i, row) in rows.iter().enumerate() {
        let y = rect.top() + i as f32 * (LANE_HEIGHT + LANE_GAP);
        if !row.label.is_empty() {
            painter.text(
                Pos2::new(rect.left() + 2.0, y + LANE_HEIGHT / 2.0),
                Align2::LEFT_CENTER,
                &row.label,
                font.clone(),
                m.theme.muted,
            );
        }
        // Cull and merge: consecutive bars that fall in the same pixel column merge.
        let mut merged: Option<(f64, f64, Color32)> = None;
        let flush = |span: Option<(f64, f64, Color32)>| {
            if let Some((x0, x1, c)) = span {
                let r = Rect::from_min_max(
                    Pos2::new(x0 as f32, y),
                    Pos2::new((x1 as f32).max(x0 as f32 + 1.0), y + LANE_HEIGHT),
                );
                painter.rect_filled(r, BAR_ROUNDING, c);
            }
        };
        // The contiguous span `[lo, hi]` that the last bars of one colour painted:
        // a bar of that colour inside it is hidden under earlier ones, as in an
        // overflow lane holding thousands of failed activities' windows, so it is
        // skipped unless it is highlighted.
        let mut painted = (f64::INFINITY, f64::NEG_INFINITY, Color32::TRANSPARENT);
        for bar in &row.bars {
            if bar.end < axis.start || bar.start > axis.end {
                continue;
            }
            let x0 = axis.x(bar.start, timeline).max(f64::from(timeline.left()));
            let x1 = axis.x(bar.end, timeline).min(f64::from(timeline.right()));
            let marked = bar.activity.is_some()
                && (bar.activity == current || bar.activity == m.nav.selected);
            let (lo, hi, color) = painted;
            if bar.color == color && lo <= x0 && x1 <= hi && !marked {
                continue;
            }
            painted = if bar.color == color && x0 <= hi && lo <= x1 {
                (lo.min(x0), hi.max(x1), color)
            } else {
                (x0, x1, bar.color)
            };
            if x1 - x0 < 1.0 {
                merged = match merged {
                    Some((a, b, c)) if x0 <= b + 1.0 => Some((a, b.max(x1), c)),
                    other => {
                        flush(other);
                        Some((x0, x1, bar.color))
                    }
                };
                continue;
            }
            flush(merged.take());
            let r = Rect::from_min_max(
                Pos2::new(x0 as f32, y),
                Pos2::new(x1 as f32, y + LANE_HEIGHT),
            );
            painter.rect_filled(r, BAR_ROUNDING, bar.color);
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
            if r.width() >= LABEL_MIN_WIDTH {
                let text = painter.layout_no_wrap(bar.label.clone(), font.clone(), m.theme.label);
                if text.size().x + 4.0 <= r.width() {
                    painter.galley(
                        Pos2::new(r.left() + 2.0, r.center().y - text.size().y / 2.0),
                        text,
                        m.theme.label,
                    );
                }
            }
            if let (Some(p), Some(a)) = (pointer, bar.activity) {
                if r.contains(p) {
                    hovered = Some((
                        a,
                        format!(
                            "{} {}–{}",
                            bar.label,
                            m.time(bar.start as i64),
                            m.time(bar.end as i64)
                        ),
                    ));
                }
            }
        }
        flush(merged);
    }
    // The current time probe.
    if let Some(t) = m.nav.probe {
        let x = axis.x(t as f64, timeline) as f32;
        painter.vline(
            x,
            timeline.y_range(),
            Stroke::new(PROBE_LINE_STROKE, m.theme.current),
        );
    }
    if let Some((a, text)) = &hovered {
        response.clone().on_hover_text_at_pointer(text.clone());
        if response.clicked() {
            cmds.push(Command::Select(Some(*a)));
        }
    }
    // Pan by dragging, zoom with Ctrl+wheel (or pinch) about the pointer.
    if response.dragged() {
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
}

#[cfg(test)]
mod tests {
    use super::*;
    // The tests drive the whole app (test code only: the views themselves never
    // reach up into it).
    use crate::gui::SolscopeApp;

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
            nav: &app.ui.nav,
            messages: &app.ui.messages,
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
            assert_eq!(
                shape(&cached.rows),
                shape(&rows(&model(app), app.ui.nav.step))
            );
        };
        check(&mut app);
        for k in [0, 10, 35] {
            app.apply(Command::SetStep(k));
            check(&mut app);
        }
        app.apply(Command::GroupByResource(true));
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
}
