//! What hovering the Gantt shows: a bar's tooltip (an activity's outcome
//! by the step shown, a marker's details, the flexibility layer's line) and
//! what clicking it does, or the chart's hint where no bar is.

use eframe::egui;
use solscope_engine::{FailurePhase, Outcome, format_span};

use super::layout::Bar;
use crate::gui::views::{Model, Status, flex};
use crate::state::Command;

/// What hovering a bar shows, and what clicking it does.
pub(super) struct Hovered {
    text: String,
    click: Option<Command>,
}

/// What hovering `bar` shows and what clicking it does (`steps`: a schedule
/// row following the step slider, whose activity bars say what happened), if
/// anything.
pub(super) fn hover_of(
    m: &Model<'_>,
    bar: &Bar,
    steps: bool,
    flex_layer: Option<&solscope_engine::Flex>,
) -> Option<Hovered> {
    let click = match (bar.activity, bar.cycle) {
        (Some(a), _) => Some(Command::Select(Some(a))),
        (None, Some(c)) => Some(Command::SetCycle(c)),
        (None, None) => None,
    };
    if click.is_none() && bar.tip.is_none() {
        return None;
    }
    let mut text = bar.tip.clone().unwrap_or_else(|| match bar.activity {
        Some(a) if steps => activity_tip(m, a, bar),
        _ => format!(
            "{} {}–{}",
            bar.label,
            m.time(bar.start as i64),
            m.time(bar.end as i64)
        ),
    });
    let fa = flex_layer
        .filter(|_| bar.placed)
        .and_then(|f| bar.activity.and_then(|a| f.activity(a)));
    if let Some(fa) = fa {
        text.push_str(&format!(
            "\n{}; drag to try another start",
            flex::hover_line(m, fa)
        ));
    }
    Some(Hovered { text, click })
}

/// What hovering activity `a`'s bar says in schedule mode: who it is, what
/// happened to it by the step shown and when, its duration and unit resources,
/// and for a failure the one-line reason.
fn activity_tip(m: &Model<'_>, a: usize, bar: &Bar) -> String {
    let act = &m.doc.plan.activities[a];
    let span = format!("{} – {}", m.time(bar.start as i64), m.time(bar.end as i64));
    let k = m.nav.step;
    let what = match m.status(a, k) {
        Status::Scheduled(s, e) => format!("scheduled {span} ({})", format_span(e - s)),
        Status::Failed => {
            let why = match m.analysis.step(a).map(|s| &s.outcome) {
                Some(Outcome::Failed(FailurePhase::Dependency { on })) => format!(
                    "its dependency {} was not placed",
                    m.doc.plan.activities[*on].id
                ),
                Some(Outcome::Failed(FailurePhase::ValidIntervals)) => {
                    "no start satisfies its constraints together".to_string()
                }
                _ => "every valid start breaks a power, energy or sleep limit".to_string(),
            };
            format!("failed: {why}\nwindow {span}")
        }
        Status::Skipped => {
            format!("skipped: another member of its group was placed\nwindow {span}")
        }
        Status::Pending => format!("pending (its step is after step {k})\nwindow {span}"),
    };
    let mut out = format!("{}\n{what}", m.label(a));
    if !matches!(m.status(a, k), Status::Scheduled(..)) {
        let d = &act.duration;
        out.push_str(&if d.min() == d.max() {
            format!("\nlasts {}", format_span(d.max()))
        } else {
            format!(
                "\nlasts {} to {}",
                format_span(d.min()),
                format_span(d.max())
            )
        });
    }
    if !act.resources.is_empty() {
        out.push_str(&format!("\nholds {}", act.resources.join(", ")));
    }
    out
}

/// The tooltip of the bar under the pointer and its click, or the chart's
/// hint where no bar is; nothing while `quiet` (a bar dragged or a question
/// asked: it would cover the popup's buttons).
pub(super) fn tooltip_ui(
    m: &Model<'_>,
    response: &egui::Response,
    hovered: Option<Hovered>,
    quiet: bool,
    cmds: &mut Vec<Command>,
) {
    // Shown where no bar is under the pointer (a bar shows its own tooltip).
    let hint = if m.flex_layer().is_some() {
        "Click a bar to inspect it; drag a scheduled bar to try another start; drag \
         elsewhere to pan; Ctrl+wheel to zoom"
    } else {
        "Click a bar to inspect it; drag to pan; Ctrl+wheel to zoom"
    };
    match hovered.filter(|_| !quiet) {
        Some(h) => {
            response.clone().on_hover_text_at_pointer(h.text);
            if response.clicked() {
                if let Some(c) = h.click {
                    cmds.push(c);
                }
            }
        }
        None if !quiet => {
            response.clone().on_hover_text(hint);
        }
        None => {}
    }
}
