//! The Monte Carlo campaign in the execution inspector: the activities lost
//! most often (nothing selected), or for the selected activity its
//! completed / aborted / not-run shares across the runs, its start across
//! them against the prediction, why it was lost (the predictor in one
//! sentence, each cause with its culprits) and the first runs that lost it,
//! to open.

use eframe::egui::{self, RichText};
use solscope_engine::{ActivitySummary, LostSummary, Predictor, format_time_difference};

use crate::gui::theme::{SHARE_BAR_HEIGHT, SHARE_BAR_LARGE_HEIGHT, SHARE_BAR_WIDTH};
use crate::gui::views::Model;
use crate::gui::views::text::percent;
use crate::gui::views::widgets::share_bar;
use crate::state::Command;
use crate::state::execution::ActualsSource;
use crate::state::montecarlo::CampaignResult;

/// How many of the activities lost most often the panel lists.
const MOST_LOST_SHOWN: usize = 5;

/// The activities lost in the most runs (click to select), for the
/// inspector while nothing is selected.
pub(super) fn most_lost_ui(
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

/// The selected activity across the campaign's runs: shares, start, why it
/// was lost, the first runs that lost it to open.
pub(super) fn activity_ui(ui: &mut egui::Ui, m: &Model<'_>, a: usize, cmds: &mut Vec<Command>) {
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
        Some(p) => format!("{} ({})", m.time(t), format_time_difference(t - p)),
        None => m.time(t),
    };
    if q.min == q.max {
        let when = match s.predicted_start {
            Some(p) => format!(", {},", format_time_difference(q.min - p)),
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
