//! Execution mode's Monte Carlo panel (under the Gantt and plots): the
//! campaign's runs and seed, Run and Cancel with a progress bar, and once a
//! summary exists for the plan as it is, the runs that broke a limit by kind
//! and the lowest and handover state of charge across runs as histograms
//! with their limits. With "Compare policies" a campaign runs the same runs
//! under replan, dispatch and fixed, and the panel shows them side by side:
//! per policy the runs that broke a limit and the median lowest state of
//! charge, and per activity lost in some run under some policy its three
//! stacked bars (the rest of the app details the replan campaign). The
//! campaign's view of one activity is the execution inspector's
//! (`inspector::montecarlo`). The comparison of the policies is `compare`.

mod compare;

use eframe::egui::{self, RichText, Stroke};
use egui_plot::{Bar, BarChart, Plot, VLine};
use solscope_engine::{Distribution, format_wh_value};

use super::text::{percent, wh_text};
use super::{CampaignModel, Model};
use crate::gui::theme::{
    BAR_OUTLINE_STROKE, CAMPAIGN_FIELD_WIDTH, HISTOGRAM_HEIGHT, LIMIT_LINE_STROKE,
};
use crate::state::TextBuffers;
use crate::state::montecarlo::{Bin, CampaignResult, MAX_RUNS, StopReason, total_runs};
use crate::state::{Command, UiCommand};

/// The Monte Carlo panel under the Gantt and plots (execution mode): the
/// controls and progress in its header (shown folded too), the plan-wide
/// results in its body.
pub fn campaign_panel_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    text: &mut TextBuffers,
    cmds: &mut Vec<Command>,
) {
    let id = ui.make_persistent_id("monte_carlo");
    egui::collapsing_header::CollapsingState::load_with_default_open(ui.ctx(), id, true)
        .show_header(ui, |ui| {
            ui.label(RichText::new("Monte Carlo").strong());
            controls_ui(ui, m, text, cmds);
        })
        .body(|ui| {
            let c = m.exec.campaign;
            status_ui(ui, m, &c);
            match c.result {
                None => {}
                Some(Err(e)) => {
                    ui.colored_label(m.theme.error, format!("The campaign failed: {e}"));
                }
                Some(Ok(result)) if !result.compared().is_empty() => {
                    compare::compare_ui(ui, m, result, cmds);
                }
                Some(Ok(result)) => summary_ui(ui, m, result),
            }
        });
}

/// Runs, seed, Run and Cancel, and the campaign's progress or headline.
fn controls_ui(ui: &mut egui::Ui, m: &Model<'_>, text: &mut TextBuffers, cmds: &mut Vec<Command>) {
    let c = m.exec.campaign;
    let running = c.running.is_some();
    let uncertain = m
        .doc
        .plan
        .activities
        .iter()
        .any(|a| a.duration_model.is_some());
    let runs_label = ui.label("Runs");
    let runs = ui
        .add(
            egui::TextEdit::singleline(&mut text.campaign_runs_text)
                .desired_width(CAMPAIGN_FIELD_WIDTH),
        )
        .labelled_by(runs_label.id)
        .on_hover_text(format!("How many executions to run (1 to {MAX_RUNS})"));
    let seed_label = ui.label("Campaign seed");
    let seed = ui
        .add(
            egui::TextEdit::singleline(&mut text.campaign_seed_text)
                .desired_width(CAMPAIGN_FIELD_WIDTH),
        )
        .labelled_by(seed_label.id)
        .on_hover_text(
            "Run i draws its durations from stream i of this seed: \
             the same seed gives the same runs on any machine",
        );
    let enter =
        (runs.lost_focus() || seed.lost_focus()) && ui.input(|i| i.key_pressed(egui::Key::Enter));
    let compare = m.persisted.compare_policies;
    let toggle = UiCommand::ToggleComparePolicies;
    let mut checked = compare;
    if ui
        .add_enabled(!running, egui::Checkbox::new(&mut checked, toggle.label()))
        .on_hover_text(
            "Run the same runs under each execution policy, one after the other: replan (the \
             onboard scheduler again at every cycle), dispatch (each activity by the flexible \
             schedule's start and skip conditions) and fixed (each activity at its scheduled \
             start), and show them side by side",
        )
        .changed()
    {
        cmds.push(toggle.into());
    }
    let run = ui
        .add_enabled(uncertain && !running, egui::Button::new("Run"))
        .on_hover_text(
            "Execute the plan once per run with durations drawn from its duration models",
        )
        .on_disabled_hover_text(if running {
            "A campaign is running"
        } else {
            "The plan has no duration_model: every run would be the nominal execution"
        });
    if run.clicked() || (enter && uncertain && !running) {
        let parsed = (
            text.campaign_runs_text.trim().parse::<u64>(),
            text.campaign_seed_text.trim().parse::<u64>(),
        );
        match parsed {
            (Ok(runs), Ok(seed)) if (1..=MAX_RUNS).contains(&runs) => {
                cmds.push(if compare {
                    Command::ComparePolicies { runs, seed }
                } else {
                    Command::RunCampaign { runs, seed }
                });
            }
            (_, Ok(_)) => cmds.push(Command::ShowError(format!(
                "Runs: enter a whole number from 1 to {MAX_RUNS}"
            ))),
            (_, Err(_)) => cmds.push(Command::ShowError(
                "Campaign seed: enter a whole number from 0 to 18446744073709551615".into(),
            )),
        }
    }
    super::command_button(ui, UiCommand::CancelCampaign, running, cmds);
    ui.separator();
    if let Some(p) = c.running {
        let total = p.total();
        let share = if total == 0 {
            0.0
        } else {
            p.done as f32 / total as f32
        };
        let what = match (p.cancelling, p.policy()) {
            (true, _) => format!("cancelling… {} / {total} runs", p.done),
            (false, None) => format!("{} / {} runs (seed {})", p.done, p.runs, p.seed),
            (false, Some((policy, done))) => format!(
                "{}: {done} / {} runs (seed {}; replan, dispatch, fixed in turn)",
                policy.name(),
                p.runs,
                p.seed
            ),
        };
        let bar = ui.add(egui::ProgressBar::new(share).text(what));
        if c.result.is_some() {
            bar.on_hover_text("The last campaign's results stay shown until this one is done");
        }
    } else if let Some(result) = c.ready() {
        headline_ui(ui, m, result);
    } else if !uncertain {
        ui.colored_label(
            m.theme.muted,
            "This plan has no duration_model: every run would be the nominal execution.",
        );
    }
}

/// `200 runs, seed 1: 98 broke a limit` (by kind in the panel's body); of a
/// comparison, `broke a limit: replan 82, dispatch 110, fixed 1 (200 runs
/// each, seed 1)`. Cut to the header's width, whole on hover and as its
/// accessibility label.
fn headline_ui(ui: &mut egui::Ui, m: &Model<'_>, result: &CampaignResult) {
    let s = &result.summary;
    let (text, broken) = if result.compared().is_empty() {
        let head = format!("{} runs, seed {}", s.runs, s.seed);
        let breaking = s.limits.runs_breaking;
        if breaking == 0 {
            (format!("{head}: no run broke a limit"), false)
        } else {
            let share = percent(breaking, s.runs);
            (format!("{head}: {breaking} broke a limit ({share})"), true)
        }
    } else {
        let counts: Vec<String> = result
            .compared()
            .iter()
            .map(|x| format!("{} {}", x.policy.name(), x.limits.runs_breaking))
            .collect();
        let text = format!(
            "Broke a limit: {} ({} runs each, seed {})",
            counts.join(", "),
            s.runs,
            s.seed
        );
        let broken = result.compared().iter().any(|x| x.limits.runs_breaking > 0);
        (text, broken)
    };
    let mut rich = RichText::new(text.clone());
    if broken {
        rich = rich.color(m.theme.error);
    }
    let resp = ui.add(egui::Label::new(rich).truncate());
    resp.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Label, true, &text));
    resp.on_hover_text(text);
}

/// What became of the last campaign that did not finish or no longer
/// applies, and what the panel is for before any campaign. Nothing here
/// changes when a campaign starts.
fn status_ui(ui: &mut egui::Ui, m: &Model<'_>, c: &CampaignModel<'_>) {
    if let Some(s) = c.stopped {
        let why = match s.why {
            StopReason::Cancelled => format!(
                "Cancelled after {} of {} runs ({}seed {}); nothing of it is kept.",
                s.done,
                total_runs(s.runs, s.compare),
                if s.compare {
                    format!("{} per policy, ", s.runs)
                } else {
                    String::new()
                },
                s.seed
            ),
            StopReason::PlanEdited => format!(
                "The plan was edited while the campaign ran ({} of {} runs done): it was \
                 stopped, as its summary would have been of the plan before the edit. Run it \
                 again.",
                s.done,
                total_runs(s.runs, s.compare)
            ),
        };
        ui.colored_label(m.theme.muted, why);
    }
    if let Some((seed, runs)) = c.stale {
        ui.colored_label(
            m.theme.error,
            format!(
                "The plan was edited after the last campaign ({runs} runs, seed {seed}): its \
                 summary no longer applies and is not shown. Run it again."
            ),
        );
    }
    // (Kept while a campaign runs: the panel's header, with Cancel, does not
    // move when Run is clicked.)
    if c.result.is_none() && c.stale.is_none() && c.stopped.is_none() {
        ui.colored_label(
            m.theme.muted,
            "Executes the plan once per run with durations drawn from its duration models, \
             and shows how often each activity completes, why it is lost, and the state of \
             charge across runs.",
        );
    }
}

/// The campaign's plan-wide results: the runs that broke a limit by kind,
/// and side by side the lowest and the handover state of charge.
fn summary_ui(ui: &mut egui::Ui, m: &Model<'_>, result: &CampaignResult) {
    let s = &result.summary;
    let limits = &s.limits;
    if limits.runs_breaking > 0 {
        let kinds: Vec<String> = limits
            .by_kind
            .iter()
            .map(|(k, n)| format!("{k} {n} ({})", percent(*n, s.runs)))
            .collect();
        ui.colored_label(
            m.theme.error,
            format!("Runs breaking each limit: {}", kinds.join(", ")),
        );
    }
    let handover = s.handover_soc.as_ref().zip(m.doc.plan.handover.as_ref());
    ui.columns(if handover.is_some() { 2 } else { 1 }, |cols| {
        let below = limits.by_kind.get("min_soc").copied().unwrap_or(0);
        histogram_ui(
            &mut cols[0],
            m,
            "mc_lowest_soc",
            "Lowest state of charge per run",
            &s.lowest_soc,
            &result.lowest_bins,
            Some(("min_soc", m.doc.plan.battery.min_soc, below)),
        );
        if let (Some((d, h)), Some(col)) = (handover, cols.get_mut(1)) {
            let below = limits.by_kind.get("handover_soc").copied().unwrap_or(0);
            histogram_ui(
                col,
                m,
                "mc_handover_soc",
                &format!("State of charge at the handover, {}", m.time(h.time)),
                d,
                &result.handover_bins,
                h.min_soc.map(|x| ("handover min_soc", x, below)),
            );
        }
    });
}

/// A distribution over the runs as a histogram (`bins`, with an edge at the
/// limit `(name, Wh, runs below it)`: the bars below it in the limit colour),
/// its quantiles, and the runs below the limit.
fn histogram_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    id: &str,
    title: &str,
    d: &Distribution,
    bins: &[Bin],
    limit: Option<(&str, f64, u64)>,
) {
    ui.label(RichText::new(title).strong());
    let bars: Vec<Bar> = bins
        .iter()
        .filter(|b| b.runs > 0)
        .map(|b| {
            let color = if b.below {
                m.theme.limit
            } else {
                m.theme.scheduled
            };
            Bar::new((b.from + b.to) / 2.0, b.runs as f64)
                .width(b.to - b.from)
                .fill(color)
                .stroke(Stroke::new(BAR_OUTLINE_STROKE, m.theme.muted))
                .name(format!("{} – {}", wh_text(b.from), wh_text(b.to)))
        })
        .collect();
    // The limit is on the axis when it is within one spread of the runs;
    // further away the line under the plot gives the margin.
    let reach = (d.max - d.min).max(1.0);
    let near = limit.filter(|&(_, l, _)| l >= d.min - reach && l <= d.max + reach);
    let mut plot = Plot::new(id)
        .height(HISTOGRAM_HEIGHT)
        .allow_zoom(false)
        .allow_drag(false)
        .allow_scroll(false)
        .allow_boxed_zoom(false)
        .allow_double_click_reset(false)
        .include_y(0.0)
        .x_axis_formatter(|mark, _| format_wh_value(mark.value, 0))
        .y_axis_label("runs");
    if let Some((_, l, _)) = near {
        plot = plot.include_x(l);
    }
    let limit_color = m.theme.limit;
    plot.show(ui, |p| {
        p.bar_chart(
            BarChart::new(title, bars).element_formatter(Box::new(|bar, _| {
                format!("{}: {} runs", bar.name, bar.value)
            })),
        );
        if let Some((name, l, _)) = near {
            p.vline(
                VLine::new(name, l)
                    .color(limit_color)
                    .width(LIMIT_LINE_STROKE),
            );
        }
    });
    ui.label(format!(
        "median {} · 5–95%: {} – {}",
        wh_text(d.p50),
        wh_text(d.p05),
        wh_text(d.p95)
    ))
    .on_hover_text(format!(
        "all runs within {} – {}",
        wh_text(d.min),
        wh_text(d.max)
    ));
    if let Some((name, l, below)) = limit {
        if below == 0 {
            ui.colored_label(
                m.theme.muted,
                format!(
                    "{name} {}: no run below (lowest {} above it)",
                    wh_text(l),
                    wh_text(d.min - l)
                ),
            );
        } else {
            ui.colored_label(
                m.theme.error,
                format!("{name} {}: {below} runs went below", wh_text(l)),
            );
        }
    }
}
