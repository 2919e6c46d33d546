//! The plots in execution mode: each profile executed, as the first cycle
//! predicted it, and as the looked-at cycle's run has it after the step
//! shown, with the looked-at cycle's time and the broken limits as vertical
//! lines; at the time clicked, the executed and predicted values.

use eframe::egui::{self, RichText};
use solscope_engine::{
    MJ_PER_WH, MW_PER_W, ViolationKind, format_mbit_value, format_watts, format_wh,
};

use super::plot::{Chart, DATA, Mark, PEAK, Pick, SOC, Series, limits, plot_ui};
use crate::gui::views::text::kind_name;
use crate::gui::views::{Model, ViewCache};
use crate::state::Command;
use crate::state::execution::ExecutionRun;

/// Execution mode: each profile executed, as the first cycle predicted it, and
/// as the looked-at cycle's run has it after the step shown; the looked-at
/// cycle's time and the broken limits as vertical lines; at the time clicked,
/// the executed and predicted values.
pub(super) fn execution_plots_ui(
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
    let plots: [(&'static str, Pick, &[ViolationKind], _); 3] = [
        (
            SOC,
            |v| &v.soc,
            &[ViolationKind::MinSoc, ViolationKind::HandoverSoc],
            soc_limits,
        ),
        (
            PEAK,
            |v| &v.peak,
            &[ViolationKind::MaxPeakPower],
            peak_limits,
        ),
        (
            DATA,
            |v| &v.data,
            &[ViolationKind::DataCapacity],
            data_limits,
        ),
    ];
    for (id, pick, kinds, limits) in plots {
        legend_ui(ui, id, &series(pick));
        let chart = Chart {
            id,
            series: series(pick),
            limits,
            marks: marks(kinds),
            overlay: None,
        };
        plot_ui(ui, m, cache, &chart, cmds);
    }

    match m.nav.probe {
        Some(t) => probe_ui(ui, m, run, t, cmds),
        None => {
            ui.label("Click a plot to compare the executed and predicted values at that time.");
        }
    }
}

/// At the probed time `t`: the executed and predicted values and their
/// difference.
fn probe_ui(ui: &mut egui::Ui, m: &Model<'_>, run: &ExecutionRun, t: i64, cmds: &mut Vec<Command>) {
    let predicted = run.predicted.as_ref().ok();
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
        ("Data volume", |v| &v.data, |x| format_mbit_value(x, 1)),
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
pub(super) fn value_at(series: &[[f64; 2]], x: f64) -> Option<f64> {
    let i = series.partition_point(|p| p[0] <= x);
    match (i.checked_sub(1).and_then(|j| series.get(j)), series.get(i)) {
        (Some(a), Some(b)) if b[0] > a[0] => {
            Some(a[1] + (b[1] - a[1]) * (x - a[0]) / (b[0] - a[0]))
        }
        (Some(a), _) => (a[0] == x || i < series.len()).then_some(a[1]),
        (None, _) => None,
    }
}
