//! Execution mode's Monte Carlo panel (under the Gantt and plots): the
//! campaign's runs and seed, Run and Cancel with a progress bar, and once a
//! summary exists for the plan as it is, the runs that broke a limit by kind,
//! the lowest and handover state of charge across runs as histograms with
//! their limits, and the activities lost most often. Per activity (in the
//! execution inspector): its completed / aborted / not-run shares as a
//! stacked bar (small in the activity list, larger in the inspector), its
//! start across runs, why it was lost across runs, and the first runs that
//! lost it, to open. With "Compare policies" a campaign runs the same runs
//! under replan, dispatch and fixed, and the panel shows them side by side:
//! per policy the runs that broke a limit and the median lowest state of
//! charge, and per activity lost in some run under some policy its three
//! stacked bars (the rest of the app details the replan campaign).

use std::cmp::Reverse;

use eframe::egui::{self, RichText, Sense, Stroke};
use egui_plot::{Bar, BarChart, Plot, VLine};
use solscope_engine::{
    ActivitySummary, Distribution, LostSummary, MJ_PER_WH, Predictor, Summary, format_wh,
};

use super::{CampaignModel, Model};
use crate::gui::theme::{
    BAR_OUTLINE_STROKE, CAMPAIGN_FIELD_WIDTH, HISTOGRAM_HEIGHT, LIMIT_LINE_STROKE,
    SHARE_BAR_HEIGHT, SHARE_BAR_LARGE_HEIGHT, SHARE_BAR_WIDTH, SHARE_MIN_WIDTH,
};
use crate::state::execution::ActualsSource;
use crate::state::montecarlo::{Bin, COMPARED, CampaignResult, MAX_RUNS, StopReason, total_runs};
use crate::state::{Command, TextBuffers, UiCommand};

/// How many of the activities lost most often the panel lists.
const MOST_LOST_SHOWN: usize = 5;

/// Width of one policy's stacked bar in the comparison (px).
const COMPARE_BAR_WIDTH: f32 = 52.0;

/// Height of the comparison's scrolled list of activities (px).
const COMPARE_LIST_HEIGHT: f32 = 120.0;

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
                    compare_ui(ui, m, result, cmds);
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

/// A comparison of the policies over the same runs: per policy the runs that
/// broke a limit and the median lowest state of charge; per activity that
/// some policy lost in some run, its completed / aborted / not-run shares
/// under each policy (click its name to select it).
fn compare_ui(ui: &mut egui::Ui, m: &Model<'_>, result: &CampaignResult, cmds: &mut Vec<Command>) {
    let compared = result.compared();
    let runs = result.runs();
    ui.columns(2, |cols| {
        let ui = &mut cols[0];
        ui.label(
            RichText::new(format!(
                "The same {runs} runs (seed {}) under each policy",
                result.seed
            ))
            .strong(),
        )
        .on_hover_text(
            "Run i draws the same durations under every policy, so the campaigns compare \
             run by run",
        );
        for s in compared {
            let line = policy_line(s);
            let label = if s.limits.runs_breaking > 0 {
                ui.colored_label(m.theme.error, line)
            } else {
                ui.label(line)
            };
            label.on_hover_text(policy_details(s));
        }
        ui.colored_label(
            m.theme.muted,
            "The histograms, the activity list's bars and the inspector show the replan \
             campaign; Compare policies off runs it alone.",
        );
        let Some(ui) = cols.get_mut(1) else {
            return;
        };
        compare_activities_ui(ui, m, compared, runs, cmds);
    });
}

/// `dispatch: 3 of 20 runs broke a limit (15%) · median lowest state of
/// charge 812.4 Wh`.
fn policy_line(s: &Summary) -> String {
    let lowest = format!(
        "median lowest state of charge {}",
        wh_text(s.lowest_soc.p50)
    );
    let breaking = s.limits.runs_breaking;
    if breaking == 0 {
        format!("{}: no run broke a limit · {lowest}", s.policy.name())
    } else {
        format!(
            "{}: {breaking} of {} runs broke a limit ({}) · {lowest}",
            s.policy.name(),
            s.runs,
            percent(breaking, s.runs)
        )
    }
}

/// The runs breaking each limit and the lowest state of charge's spread.
fn policy_details(s: &Summary) -> String {
    let kinds: Vec<String> = s
        .limits
        .by_kind
        .iter()
        .map(|(k, n)| format!("{k} {n}"))
        .collect();
    let d = &s.lowest_soc;
    let mut text = format!(
        "Lowest state of charge per run: 5–95% {} – {}, all within {} – {}",
        wh_text(d.p05),
        wh_text(d.p95),
        wh_text(d.min),
        wh_text(d.max)
    );
    if !kinds.is_empty() {
        text.push_str(&format!("\nRuns breaking each limit: {}", kinds.join(", ")));
    }
    text
}

/// Whether activity `a` was lost in some run under some policy (and run in
/// some run under some policy: never run under any is listed apart).
fn differs(compared: &[Summary], a: usize) -> bool {
    let of = || compared.iter().filter_map(|s| s.activities.get(a));
    of().any(|x| x.aborted + x.not_run > 0) && of().any(|x| x.completed + x.aborted > 0)
}

/// Where activity `a` comes in the comparison's list: the largest difference
/// between the policies' completed runs first, then the most runs lost
/// under some policy, then plan order.
fn compare_order(compared: &[Summary], a: usize) -> (Reverse<u64>, Reverse<u64>, usize) {
    let of = || compared.iter().filter_map(|s| s.activities.get(a));
    let most = of().map(|x| x.completed).max().unwrap_or(0);
    let least = of().map(|x| x.completed).min().unwrap_or(0);
    let lost = of().map(|x| x.aborted + x.not_run).max().unwrap_or(0);
    (Reverse(most - least), Reverse(lost), a)
}

/// Per activity that some policy lost in some run: a stacked bar per policy
/// (in the order of [`COMPARED`]) and its name, to select.
fn compare_activities_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    compared: &[Summary],
    runs: u64,
    cmds: &mut Vec<Command>,
) {
    let n = m.doc.plan.activities.len();
    let mut listed: Vec<usize> = (0..n).filter(|&a| differs(compared, a)).collect();
    listed.sort_by_key(|&a| compare_order(compared, a));
    let never = (0..n)
        .filter(|&a| {
            compared.iter().all(|s| {
                s.activities
                    .get(a)
                    .is_none_or(|x| x.completed + x.aborted == 0)
            })
        })
        .count();
    let always = n - listed.len() - never;
    ui.label(RichText::new("Per activity lost in some run").strong())
        .on_hover_text(
            "Completed / aborted / not run under each policy; the activities whose \
             completed runs differ most between the policies first",
        );
    let row_height = ui.spacing().interact_size.y;
    ui.horizontal(|ui| {
        for p in COMPARED {
            ui.add_sized(
                [COMPARE_BAR_WIDTH, row_height],
                egui::Label::new(RichText::new(p.name()).color(m.theme.muted)),
            );
        }
    });
    egui::ScrollArea::vertical()
        .id_salt("mc_compare")
        .max_height(COMPARE_LIST_HEIGHT)
        .auto_shrink([false, true])
        .show_rows(ui, row_height, listed.len(), |ui, rows| {
            for &a in &listed[rows] {
                ui.horizontal(|ui| {
                    for s in compared {
                        let Some(x) = s.activities.get(a) else {
                            continue;
                        };
                        let size = egui::vec2(COMPARE_BAR_WIDTH, SHARE_BAR_HEIGHT);
                        let text = format!("{}, {}", s.policy.name(), shares_text(x, runs));
                        labelled_share_bar(ui, m, x, runs, size, text);
                    }
                    let id = m.doc.plan.activities.get(a).map_or("?", |x| x.id.as_str());
                    if ui
                        .selectable_label(m.nav.selected == Some(a), id)
                        .on_hover_text("Select it (the inspector details the replan campaign)")
                        .clicked()
                    {
                        cmds.push(Command::Select(Some(a)));
                    }
                });
            }
        });
    if listed.is_empty() {
        ui.label("No policy lost an activity in any run.");
    }
    ui.colored_label(
        m.theme.muted,
        format!("{always} completed in every run under every policy; {never} never ran"),
    );
}

/// The activities lost in the most runs (click to select), for the
/// inspector while nothing is selected.
pub fn most_lost_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    result: &CampaignResult,
    cmds: &mut Vec<Command>,
) {
    let s = &result.summary;
    let runs = s.runs;
    let lost = result.most_lost();
    if lost.is_empty() {
        ui.label("Every activity the first cycle placed completed in every run.");
        return;
    }
    ui.label(RichText::new(format!("Lost most often across the {runs} runs")).strong())
        .on_hover_text("Activities the first cycle placed that did not complete in some runs");
    for &(a, n) in lost.iter().take(MOST_LOST_SHOWN) {
        ui.horizontal(|ui| {
            if let Some(x) = result.activity(a) {
                share_bar(
                    ui,
                    m,
                    x,
                    runs,
                    egui::vec2(SHARE_BAR_WIDTH, SHARE_BAR_HEIGHT),
                );
            }
            let id = m.doc.plan.activities.get(a).map_or("?", |x| x.id.as_str());
            if ui
                .link(format!("{id}: lost in {}", percent(n, runs)))
                .on_hover_text(format!("Lost in {n} of {runs} runs; click to select it"))
                .clicked()
            {
                cmds.push(Command::Select(Some(a)));
            }
        });
    }
    if lost.len() > MOST_LOST_SHOWN {
        ui.colored_label(
            m.theme.muted,
            format!(
                "and {} more (the bars in the activity list)",
                lost.len() - MOST_LOST_SHOWN
            ),
        );
    }
}

/// A value in Wh for reading.
fn wh_text(x: f64) -> String {
    format_wh((x * MJ_PER_WH).round() as i128)
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
        .x_axis_formatter(|mark, _| format!("{:.0} Wh", mark.value))
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

/// `k` of `n` as a percentage, never rounded to 0 % or 100 % unless exact.
pub fn percent(k: u64, n: u64) -> String {
    if n == 0 {
        return "–".into();
    }
    if (k * 100) % n == 0 {
        return format!("{}%", k * 100 / n);
    }
    let p = k as f64 * 100.0 / n as f64;
    if p < 0.1 {
        "<0.1%".into()
    } else if p > 99.9 {
        ">99.9%".into()
    } else if !(10.0..=90.0).contains(&p) {
        format!("{p:.1}%")
    } else {
        format!("{p:.0}%")
    }
}

/// An activity's completed / aborted / not-run shares of `runs` as a stacked
/// bar of `size`, its numbers on hover (and as its accessibility label).
pub fn share_bar(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    s: &ActivitySummary,
    runs: u64,
    size: egui::Vec2,
) -> egui::Response {
    labelled_share_bar(ui, m, s, runs, size, shares_text(s, runs))
}

/// [`share_bar`] with `text` on hover and as its accessibility label.
fn labelled_share_bar(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    s: &ActivitySummary,
    runs: u64,
    size: egui::Vec2,
    text: String,
) -> egui::Response {
    let (rect, resp) = ui.allocate_exact_size(size, Sense::hover());
    resp.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Image, true, &text));
    if ui.is_rect_visible(rect) {
        let painter = ui.painter_at(rect);
        let total = runs.max(1) as f32;
        let mut x = rect.left();
        for (n, color) in [
            (s.completed, m.theme.scheduled),
            (s.aborted, m.theme.aborted),
            (s.not_run, m.theme.failed),
        ] {
            let w = rect.width() * n as f32 / total;
            if n > 0 {
                let r = egui::Rect::from_min_max(
                    egui::pos2(x, rect.top()),
                    egui::pos2((x + w).max(x + SHARE_MIN_WIDTH), rect.bottom()),
                );
                painter.rect_filled(r, 0.0, color);
            }
            x += w;
        }
        painter.rect_stroke(
            rect,
            0.0,
            Stroke::new(BAR_OUTLINE_STROKE, m.theme.muted),
            egui::StrokeKind::Inside,
        );
    }
    resp.on_hover_text(text)
}

/// `drive: completed 180 (90%), aborted 0, not run 20 (10%) of 200 runs`.
fn shares_text(s: &ActivitySummary, runs: u64) -> String {
    let part = |n: u64| {
        if n == 0 {
            "0".to_string()
        } else {
            format!("{n} ({})", percent(n, runs))
        }
    };
    format!(
        "{}: completed {}, aborted {}, not run {} of {runs} runs",
        s.id,
        part(s.completed),
        part(s.aborted),
        part(s.not_run)
    )
}

/// The selected activity across the campaign's runs: shares, start, why it
/// was lost, the first runs that lost it to open.
pub fn activity_ui(ui: &mut egui::Ui, m: &Model<'_>, a: usize, cmds: &mut Vec<Command>) {
    let Some(result) = m.exec.campaign.ready() else {
        return;
    };
    let Some(s) = result.activity(a) else {
        return;
    };
    let runs = result.runs();
    ui.label(RichText::new(format!("Across {runs} runs (seed {})", result.seed)).strong());
    let width = ui.available_width();
    share_bar(ui, m, s, runs, egui::vec2(width, SHARE_BAR_LARGE_HEIGHT));
    ui.horizontal_wrapped(|ui| {
        let part = |n: u64| format!("{n} ({})", percent(n, runs));
        ui.colored_label(
            m.theme.scheduled,
            format!("completed {}", part(s.completed)),
        );
        ui.colored_label(m.theme.aborted, format!("aborted {}", part(s.aborted)));
        ui.colored_label(m.theme.failed, format!("not run {}", part(s.not_run)));
    });
    start_ui(ui, m, s);
    match (&s.lost, s.predicted_start) {
        (Some(lost), _) => lost_ui(ui, m, result, a, lost, cmds),
        (None, Some(_)) => {
            ui.label("It completed in every run.");
        }
        (None, None) => {
            ui.label(if s.completed + s.aborted == 0 {
                "The first cycle did not place it, and no run started it."
            } else {
                "The first cycle did not place it; later cycles started it in some runs."
            });
        }
    }
}

/// Its start across the runs that started it, against the prediction.
fn start_ui(ui: &mut egui::Ui, m: &Model<'_>, s: &ActivitySummary) {
    let Some(q) = s.start else {
        return;
    };
    let started = s.completed + s.aborted;
    let vs = |t: i64| match s.predicted_start {
        Some(p) => format!("{} ({})", m.time(t), super::execution::slip(t - p)),
        None => m.time(t),
    };
    if q.min == q.max {
        let when = match s.predicted_start {
            Some(p) => format!(", {},", super::execution::slip(q.min - p)),
            None => String::new(),
        };
        ui.label(format!(
            "Started at {}{when} in each of the {started} runs that started it",
            m.time(q.min)
        ));
        return;
    }
    ui.label(format!("Start, in the {started} runs that started it"));
    egui::Grid::new("mc_start")
        .num_columns(2)
        .striped(true)
        .show(ui, |ui| {
            ui.label("Predicted (cycle 0)");
            ui.label(s.predicted_start.map_or("not placed".into(), |p| m.time(p)));
            ui.end_row();
            ui.label("Median");
            ui.label(vs(q.p50));
            ui.end_row();
            ui.label("90% between");
            ui.label(format!("{} and {}", m.time(q.p05), m.time(q.p95)));
            ui.end_row();
            ui.label("Earliest, latest");
            ui.label(format!("{}, {}", m.time(q.min), m.time(q.max)));
            ui.end_row();
        });
}

/// Why it was lost across runs: the predictor in one sentence, then each
/// cause with its runs, its culprits (click to select) and the first runs
/// that lost it to that cause (click to execute that run).
fn lost_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    result: &CampaignResult,
    a: usize,
    lost: &LostSummary,
    cmds: &mut Vec<Command>,
) {
    ui.label(RichText::new("Why it was lost, across runs").strong());
    let line = predictor_line(lost, result.runs());
    match &lost.predictor {
        Some(p) => ui.label(line).on_hover_text(format!(
            "This rule tells lost from kept runs right in {} of runs",
            percent(
                (p.accuracy * result.runs() as f64).round() as u64,
                result.runs()
            )
        )),
        None => ui.label(line),
    };
    let index = |id: &str| m.doc.plan.activities.iter().position(|x| x.id == id);
    for c in &lost.causes {
        ui.label(format!(
            "• {} — {} runs ({} of lost)",
            cause_text(&c.cause),
            c.runs,
            percent(c.runs, lost.runs)
        ))
        .on_hover_text(format!("cause key: {}", c.cause));
        ui.indent(("mc_cause", &c.cause), |ui| {
            if !c.culprits.is_empty() {
                ui.horizontal_wrapped(|ui| {
                    ui.label("involving");
                    for (id, n) in &c.culprits {
                        let link = ui.link(format!("{id} ({n})"));
                        if let Some(x) = index(id) {
                            if link.clicked() {
                                cmds.push(Command::Select(Some(x)));
                            }
                        }
                    }
                });
            }
            let runs = result.lost_runs(a, &c.cause);
            if !runs.is_empty() {
                ui.horizontal_wrapped(|ui| {
                    ui.label("open");
                    for &run in runs {
                        let source = ActualsSource::Sampled {
                            seed: result.seed,
                            run,
                        };
                        let shown = *m.exec.source == source;
                        if ui
                            .selectable_label(shown, format!("run {run}"))
                            .on_hover_text("Execute the plan with this run's durations")
                            .clicked()
                            && !shown
                        {
                            cmds.push(Command::SampleActuals {
                                seed: result.seed,
                                run,
                            });
                        }
                    }
                    if (runs.len() as u64) < c.runs {
                        ui.label(RichText::new("…").color(m.theme.muted));
                    }
                });
            }
        });
    }
}

/// "Lost in 31% of runs; in 104 of the 104 lost runs arm_science ran longer
/// than 2397 s, and of the 110 runs in which it did, 104 lost it."
fn predictor_line(lost: &LostSummary, runs: u64) -> String {
    let head = format!(
        "Lost in {} of runs ({} of {runs})",
        percent(lost.runs, runs),
        lost.runs
    );
    match &lost.predictor {
        None => format!("{head}; no single uncertain duration tells the lost runs apart."),
        Some(p) => format!(
            "{head}; in {} of the {} lost runs {} ran {}, and of the {} runs in which it did, {} lost it.",
            p.lost_when,
            lost.runs,
            p.activity,
            side(p),
            p.runs_when,
            p.lost_when
        ),
    }
}

/// `longer than 2397 s` or `2397 s or less`.
fn side(p: &Predictor) -> String {
    if p.direction == "above" {
        format!("longer than {} s", p.threshold)
    } else {
        format!("{} s or less", p.threshold)
    }
}

/// A cause key (`placement/min_soc`, `dropped/group_member_ran`, `aborted`…)
/// in the words of the execution inspector's sentence.
fn cause_text(key: &str) -> String {
    match key {
        "aborted" => "aborted: it ran longer than its duration".into(),
        "held" => "held back by the dispatcher until it could no longer run".into(),
        "dropped/group_member_ran" => "not run: another member of its group ran first".into(),
        "dropped/dependency_passed" => "not run: its dependency ended leaving it no start".into(),
        "dropped/depends_on_dropped" => {
            "not run: it depends on an activity that could no longer run".into()
        }
        _ => match key.split_once('/') {
            Some((phase, detail)) => format!(
                "the scheduler could not place it: {phase} ({})",
                detail.split('+').collect::<Vec<_>>().join(", ")
            ),
            None => format!("the scheduler could not place it: {key}"),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentages_are_never_rounded_to_none_or_all() {
        assert_eq!(percent(0, 200), "0%");
        assert_eq!(percent(200, 200), "100%");
        assert_eq!(percent(1, 3), "33%");
        assert_eq!(percent(1, 2000), "<0.1%");
        assert_eq!(percent(1999, 2000), ">99.9%");
        assert_eq!(percent(1, 200), "0.5%");
        assert_eq!(percent(199, 200), "99.5%");
        assert_eq!(percent(3, 0), "–");
    }

    #[test]
    fn cause_keys_read_as_the_inspector_says_them() {
        assert_eq!(
            cause_text("placement/min_soc"),
            "the scheduler could not place it: placement (min_soc)"
        );
        assert_eq!(
            cause_text("valid_intervals/execution+unit_resource"),
            "the scheduler could not place it: valid_intervals (execution, unit_resource)"
        );
        assert_eq!(
            cause_text("dependency"),
            "the scheduler could not place it: dependency"
        );
        assert!(cause_text("aborted").starts_with("aborted"));
    }

    #[test]
    fn the_predictor_in_one_sentence() {
        let lost = LostSummary {
            runs: 104,
            causes: Vec::new(),
            predictor: Some(Predictor {
                activity: "arm_science".into(),
                direction: "above",
                threshold: 2397,
                runs_when: 110,
                lost_when: 104,
                accuracy: 0.98,
            }),
        };
        assert_eq!(
            predictor_line(&lost, 335),
            "Lost in 31% of runs (104 of 335); in 104 of the 104 lost runs arm_science ran \
             longer than 2397 s, and of the 110 runs in which it did, 104 lost it."
        );
    }
}
