//! A comparison of the execution policies over the same runs in the Monte
//! Carlo panel: per policy the runs that broke a limit and the median
//! lowest state of charge; per activity that some policy lost in some run,
//! its completed / aborted / not-run shares under each policy.

use std::cmp::Reverse;

use eframe::egui::{self, RichText};
use solscope_engine::Summary;

use crate::gui::theme::SHARE_BAR_HEIGHT;
use crate::gui::views::Model;
use crate::gui::views::text::{percent, wh_text};
use crate::gui::views::widgets::{labelled_share_bar, shares_text};
use crate::state::Command;
use crate::state::montecarlo::{COMPARED, CampaignResult};

/// Width of one policy's stacked bar in the comparison (px).
const COMPARE_BAR_WIDTH: f32 = 52.0;

/// Height of the comparison's scrolled list of activities (px).
const COMPARE_LIST_HEIGHT: f32 = 120.0;

/// A comparison of the policies over the same runs: per policy the runs that
/// broke a limit and the median lowest state of charge; per activity that
/// some policy lost in some run, its completed / aborted / not-run shares
/// under each policy (click its name to select it).
pub(super) fn compare_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    result: &CampaignResult,
    cmds: &mut Vec<Command>,
) {
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
