//! The schedule inspector's explanation of a failed activity: why it did
//! not schedule (its notes, conflicts and reasons, each energy or
//! peak-power reason drawable over its plot), the activities involved, and
//! the verified suggestions.

use eframe::egui::{self, RichText};
use solscope_engine::{
    Explanation, Phase, explanation_notes_and_lead, lmst_sentence, reason_line,
    reasons_in_reading_order, suggestion_description, suggestion_line,
};

use crate::gui::help;
use crate::gui::views::{Model, TourAnchors};
use crate::state::Command;

/// How many of the reasons (ranges of starts) are listed.
const REASONS_SHOWN: usize = 4;

/// Why activity `a` did not schedule: the failure step, the explanation's
/// notes, conflicts and reasons, and the activities involved.
pub(super) fn why_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    a: usize,
    ex: &Explanation,
    anchors: &mut TourAnchors,
    cmds: &mut Vec<Command>,
) {
    let why = ui
        .label(RichText::new("Why it did not schedule").strong())
        .on_hover_text(help::WHY);
    anchors.why = Some(why.rect);
    if let Some(k) = ex.failure_step {
        if ui
            .button(format!("Go to failure step {k}"))
            .on_hover_text(help::FAILURE_STEP)
            .clicked()
        {
            cmds.push(Command::GoToFailureStep(a));
        }
    }
    // Why, in a sentence (and the duration the rest is for), above the
    // conflicts and reasons; the notes that go through them one by one below.
    let problem = &m.analysis.schedule.problem;
    let (notes, lead) = explanation_notes_and_lead(&m.doc.plan, problem, ex);
    // The document's sentences, said in LMST.
    let notes: Vec<String> = notes
        .iter()
        .map(|n| lmst_sentence(&m.doc.plan.local_time, n))
        .collect();
    let lead = lead.min(notes.len());
    for note in &notes[..lead] {
        ui.label(note);
    }
    if ex.phase == Some(Phase::ValidIntervals) {
        for c in &ex.conflicts {
            let names: Vec<&str> = c.iter().map(|x| x.name()).collect();
            ui.label(format!("Conflict: {}", names.join(" + ")));
        }
    }
    reasons_ui(ui, m, a, ex, cmds);
    for note in &notes[lead..] {
        ui.label(note);
    }
    involved_ui(ui, m, ex, anchors, cmds);
}

/// The first reasons in reading order, each energy or peak-power one with
/// "Show on plot" when there are several to choose from; how many more.
fn reasons_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    a: usize,
    ex: &Explanation,
    cmds: &mut Vec<Command>,
) {
    for (i, r) in reasons_in_reading_order(ex)
        .into_iter()
        .take(REASONS_SHOWN)
        .map(|i| (i, &ex.reasons[i]))
    {
        let line = lmst_sentence(
            &m.doc.plan.local_time,
            &reason_line(&m.doc.plan, &m.analysis.schedule.problem, r, ex.duration),
        );
        // An energy or peak-power reason can be drawn over its plot (when
        // there is more than one to choose from).
        let overlay = m.would_cause.filter(|w| w.reasons.len() > 1).and_then(|w| {
            let j = w.reasons.iter().position(|o| o.reason == i)?;
            Some((w, j))
        });
        match overlay {
            Some((w, j)) => {
                ui.horizontal_wrapped(|ui| {
                    ui.label(line);
                    if ui
                        .selectable_label(w.shown == j, "Show on plot")
                        .on_hover_text(help::OVERLAY_REASONS)
                        .clicked()
                    {
                        cmds.push(Command::ShowReason {
                            activity: a,
                            index: j,
                        });
                    }
                });
            }
            None => {
                ui.label(line);
            }
        }
    }
    if ex.reasons.len() > REASONS_SHOWN {
        let more = ex.reasons.len() - REASONS_SHOWN;
        let text = if m.would_cause.is_some() {
            format!(
                "and {more} more range(s) of starts (Next reason on the plots goes \
                 through the energy and peak-power ones)"
            )
        } else {
            format!("and {more} more range(s) of starts")
        };
        ui.label(RichText::new(text).color(m.theme.muted));
    }
}

/// The activities involved in the failure (click to select and jump to its
/// step).
fn involved_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    ex: &Explanation,
    anchors: &mut TourAnchors,
    cmds: &mut Vec<Command>,
) {
    if ex.culprits.is_empty() {
        return;
    }
    let involved = ui
        .label(RichText::new("Involved (click to select and jump to its step)").strong())
        .on_hover_text(help::INVOLVED);
    anchors.involved = Some(involved.rect);
    for c in solscope_engine::involved(ex) {
        let text = format!(
            "{} (step {}, {})",
            m.doc.plan.activities[c.activity].id,
            c.step,
            c.blame.name()
        );
        if ui.link(text).clicked() {
            cmds.push(Command::Select(Some(c.activity)));
            cmds.push(Command::SetStep(c.step));
        }
    }
}

/// The verified suggestions (each with its Apply button), or that they are
/// being verified.
pub(super) fn suggestions_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    anchors: &mut TourAnchors,
    cmds: &mut Vec<Command>,
) {
    let suggestions = ui
        .label(RichText::new("Suggestions (verified by rescheduling)").strong())
        .on_hover_text(help::SUGGESTIONS);
    anchors.suggestions = Some(suggestions.rect);
    match m.suggestions {
        None => {
            ui.horizontal(|ui| {
                ui.spinner();
                ui.label("verifying candidate edits by rescheduling…");
            });
        }
        Some([]) => {
            ui.label("No single edit found that makes it schedule.");
        }
        Some(list) => {
            for s in list {
                ui.horizontal_wrapped(|ui| {
                    ui.label(suggestion_line(&m.doc.plan, s));
                    let description = suggestion_description(&m.doc.plan, &s.description);
                    if ui.button(format!("Apply: {description}")).clicked() {
                        cmds.push(Command::Edit {
                            target: s.target.clone(),
                            set: s.set.clone(),
                            description,
                        });
                    }
                });
            }
        }
    }
}
