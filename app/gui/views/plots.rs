//! State of charge, peak power and data volume as of the current step, on the
//! shared time axis; clicking a plot lists the consumers at that time.

use eframe::egui::{self, RichText};
use egui_plot::{HLine, Line, Plot, PlotPoints, VLine};
use solscope_engine::{
    Consumer, energy_consumers, format_plan_time, format_watts, format_wh, peak_users,
};

use super::{Model, ViewCache};
use crate::gui::commands::Command;
use crate::gui::theme::{LABEL_WIDTH, PLOT_HEIGHT};

fn plot_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    cache: &mut ViewCache,
    id: &str,
    series: &[[f64; 2]],
    limits: &[(&str, f64)],
    cmds: &mut Vec<Command>,
) {
    let color = m.theme.scheduled;
    let limit_color = m.theme.limit;
    let axis = m.nav.axis;
    let probe = m.nav.probe;
    let width = cache
        .plot_x
        .map_or(f64::from(ui.available_width()), |(l, r)| f64::from(r - l));
    let points: PlotPoints = decimate(series, axis.start, axis.end, width)
        .into_iter()
        .collect();
    let local = m.doc.plan.local_time;
    let resp = Plot::new(id)
        .x_axis_formatter(move |mark, _range| {
            let t = mark.value.round() as i64;
            format_plan_time(&local, t)
        })
        .height(PLOT_HEIGHT)
        .allow_zoom(false)
        .allow_drag(false)
        .allow_scroll(false)
        .allow_double_click_reset(false)
        .include_y(0.0)
        .y_axis_label(id)
        .y_axis_min_width(LABEL_WIDTH - 30.0)
        .show(ui, |plot_ui| {
            plot_ui.set_plot_bounds_x(axis.start..=axis.end);
            // egui_plot's own aggregation fills bands between buckets, which draws
            // a step function as shaded triangles; `decimate` did the thinning.
            plot_ui.line(Line::new(id, points).color(color).allow_band(false));
            for &(name, y) in limits {
                plot_ui.hline(HLine::new(name, y).color(limit_color));
            }
            if let Some(t) = probe {
                plot_ui.vline(VLine::new("probe", t as f64));
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
/// vertical stroke from its lowest to its highest value (ordered to continue from
/// the previous point). Dense step segments otherwise make a path that turns back
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
            let x = group[0][0];
            let prev = out.last().map_or(group[0][1], |p| p[1]);
            if (prev - lo).abs() <= (prev - hi).abs() {
                out.extend([[x, lo], [x, hi]]);
            } else {
                out.extend([[x, hi], [x, lo]]);
            }
        }
        i = j;
    }
    out
}

/// The three plots and the consumers at the probed time.
pub fn plots_ui(ui: &mut egui::Ui, m: &Model<'_>, cache: &mut ViewCache, cmds: &mut Vec<Command>) {
    let plan = &m.doc.plan;
    let sv = m.step_view;
    let mut soc_limits = vec![
        ("min_soc", plan.battery.min_soc),
        ("capacity", plan.battery.capacity),
    ];
    if let Some(h) = plan.handover.and_then(|h| h.min_soc) {
        soc_limits.push(("handover min_soc", h));
    }
    ui.label(RichText::new(format!("State of charge (Wh) after step {}", sv.step)).strong());
    plot_ui(
        ui,
        m,
        cache,
        "State of charge (Wh)",
        &sv.soc,
        &soc_limits,
        cmds,
    );
    ui.label(RichText::new("Peak power (W)").strong());
    let peak_limits: Vec<(&str, f64)> = plan
        .power
        .max_peak
        .map(|p| ("max_peak", p))
        .into_iter()
        .collect();
    plot_ui(ui, m, cache, "Peak power (W)", &sv.peak, &peak_limits, cmds);
    ui.label(RichText::new("Data volume (Mbit)").strong());
    let data_limits: Vec<(&str, f64)> = plan
        .data
        .capacity
        .map(|c| ("capacity", c))
        .into_iter()
        .collect();
    plot_ui(
        ui,
        m,
        cache,
        "Data volume (Mbit)",
        &sv.data,
        &data_limits,
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
    use super::decimate;

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
        assert!(out.len() <= 2 * (width as usize + 3), "{}", out.len());
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
