//! The activity list: search (Ctrl+F), filters by status, unit resource and
//! sol, the rows as of the step shown; and what the search and filters select
//! ([`Listed`]), kept between frames for the list, the Gantt's highlight and
//! the app's Up/Down and next/previous match.

use std::collections::BTreeSet;
use std::sync::Arc;

use eframe::egui::{self, RichText};
use solscope_engine::{Plan, RunOutcome};

use super::gantt::window_spans;
use super::{Model, Status, ViewCache, Widgets, shortcut_button, status_at, widgets};
use crate::gui::commands::{Command, UiCommand};
use crate::gui::document::Analysis;
use crate::gui::state::{ListFilter, Mode, Navigation, StatusFilter};
use crate::gui::theme::{SHARE_BAR_HEIGHT, SHARE_BAR_WIDTH};

/// What the search and filters select, for one key.
#[derive(Clone, Debug)]
pub struct Listed {
    key: ListKey,
    /// The activities the list shows, in step order.
    pub shown: Vec<usize>,
    /// Per plan activity: shown (what the Gantt highlights when `active`).
    pub matches: Vec<bool>,
    /// Whether anything is filtered out (the Gantt dims what does not match).
    pub active: bool,
    /// Bumped each time the list is computed again (the list re-scrolls to
    /// the selection then).
    pub generation: u64,
}

impl Listed {
    /// Whether activity `a` is shown.
    pub fn shows(&self, a: usize) -> bool {
        self.matches.get(a).copied().unwrap_or(false)
    }
}

/// What a [`Listed`] was computed for: the filter as it applies (the status
/// only in schedule mode), and the step only when the status or sol filter
/// depends on it, so stepping with a search alone costs nothing.
#[derive(Clone, Debug, PartialEq, Eq)]
struct ListKey {
    revision: u64,
    step: usize,
    filter: ListFilter,
}

impl ListKey {
    fn of(nav: &Navigation, revision: u64) -> Self {
        let mut filter = nav.filter.clone();
        filter.search = filter.search.trim().to_lowercase();
        if nav.mode == Mode::Execution {
            filter.status = None;
        }
        let step = if filter.status.is_some() || filter.sol.is_some() {
            nav.step
        } else {
            0
        };
        Self {
            revision,
            step,
            filter,
        }
    }
}

/// What searching and the filters' menus need of one plan revision, derived
/// once: each activity's id and name in lower case, the unit resources, the
/// sols of the horizon.
#[derive(Clone, Debug)]
pub struct SearchIndex {
    revision: u64,
    /// Per activity: `id` and `name` in lower case, joined by a character no
    /// one types.
    text: Vec<String>,
    /// Every unit resource some activity holds, sorted.
    pub resources: Vec<String>,
    /// The sols the horizon touches, first to last.
    pub sols: std::ops::RangeInclusive<i64>,
}

impl SearchIndex {
    fn of(plan: &Plan, revision: u64) -> Self {
        let text = plan
            .activities
            .iter()
            .map(|a| match &a.name {
                Some(n) => format!("{}\u{1}{}", a.id.to_lowercase(), n.to_lowercase()),
                None => a.id.to_lowercase(),
            })
            .collect();
        let resources: BTreeSet<&str> = plan
            .activities
            .iter()
            .flat_map(|a| a.resources.iter().map(String::as_str))
            .collect();
        let clock = &plan.local_time;
        let (lo, hi) = (plan.horizon.start, plan.horizon.end);
        Self {
            revision,
            text,
            resources: resources.into_iter().map(String::from).collect(),
            sols: clock.sol(lo)..=clock.sol((hi - 1).max(lo)),
        }
    }
}

impl ViewCache {
    /// The search index of plan revision `revision` (derived when it changes).
    pub fn search_index(&mut self, plan: &Plan, revision: u64) -> Arc<SearchIndex> {
        match &self.search {
            Some(ix) if ix.revision == revision => Arc::clone(ix),
            _ => {
                let ix = Arc::new(SearchIndex::of(plan, revision));
                self.search = Some(Arc::clone(&ix));
                ix
            }
        }
    }

    /// What the search and filters of `nav` select at plan revision
    /// `revision`: computed when the filter, the revision or (for the status
    /// and sol filters) the step changes, else the last result.
    pub fn listed(
        &mut self,
        plan: &Plan,
        analysis: &Analysis,
        nav: &Navigation,
        revision: u64,
    ) -> Arc<Listed> {
        let key = ListKey::of(nav, revision);
        if let Some(l) = self.listed.as_ref().filter(|l| l.key == key) {
            return Arc::clone(l);
        }
        let index = self.search_index(plan, revision);
        let generation = self.listed.as_ref().map_or(0, |l| l.generation + 1);
        let listed = Arc::new(compute(plan, analysis, &index, key, generation));
        self.listed = Some(Arc::clone(&listed));
        listed
    }
}

/// The plan time where sol `sol` starts (local midnight).
fn sol_start(plan: &Plan, sol: i64) -> i64 {
    let clock = &plan.local_time;
    let t0 = plan.horizon.start;
    let midnight = t0 - clock.time_of_day(t0);
    midnight.saturating_add((sol - clock.sol(t0)).saturating_mul(clock.sol_length.max(1)))
}

/// Whether activity `a` is in sol `[from, to)` as of step `k`: its bar when
/// placed by then, else any of its windows.
fn in_sol(plan: &Plan, analysis: &Analysis, a: usize, k: usize, (from, to): (i64, i64)) -> bool {
    let touches = |lo: i64, hi: i64| lo < to && (hi > from || (hi == lo && lo >= from));
    match status_at(analysis, a, k) {
        Status::Scheduled(s, e) => touches(s, e),
        _ => window_spans(plan, &plan.activities[a])
            .iter()
            .any(|&(lo, hi)| touches(lo, hi)),
    }
}

fn compute(
    plan: &Plan,
    analysis: &Analysis,
    index: &SearchIndex,
    key: ListKey,
    generation: u64,
) -> Listed {
    let f = &key.filter;
    let sol = f.sol.map(|s| (sol_start(plan, s), sol_start(plan, s + 1)));
    let k = key.step;
    let keep = |a: usize| {
        let act = &plan.activities[a];
        (f.search.is_empty() || index.text[a].contains(&f.search))
            && f.resource
                .as_ref()
                .is_none_or(|r| act.resources.iter().any(|x| x == r))
            && f.status.is_none_or(|s| {
                matches!(
                    (s, status_at(analysis, a, k)),
                    (StatusFilter::Scheduled, Status::Scheduled(..))
                        | (StatusFilter::Failed, Status::Failed)
                        | (StatusFilter::Skipped, Status::Skipped)
                        | (StatusFilter::Pending, Status::Pending)
                )
            })
            && sol.is_none_or(|span| in_sol(plan, analysis, a, k, span))
    };
    let shown: Vec<usize> = analysis
        .schedule
        .steps
        .iter()
        .map(|s| s.activity)
        .filter(|&a| keep(a))
        .collect();
    let mut matches = vec![false; plan.activities.len()];
    for &a in &shown {
        matches[a] = true;
    }
    Listed {
        active: key.filter.active(),
        key,
        shown,
        matches,
        generation,
    }
}

/// The search field, the match buttons and count, and the filters' menus.
fn search_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    w: &mut Widgets<'_>,
    listed: &Listed,
    cmds: &mut Vec<Command>,
) {
    let ctx = ui.ctx().clone();
    let key = |cmd: UiCommand| {
        cmd.kb_shortcut()
            .map_or(String::new(), |s| ctx.format_shortcut(&s))
    };
    ui.horizontal(|ui| {
        let label = ui.label(UiCommand::Search.label()).on_hover_text(format!(
            "Activity id or name, any case ({}); Enter or {}: next match, Shift+Enter or {}: \
             previous",
            key(UiCommand::Search),
            key(UiCommand::NextMatch),
            key(UiCommand::PreviousMatch)
        ));
        let mut search = m.nav.filter.search.clone();
        let field = ui
            .add(
                egui::TextEdit::singleline(&mut search)
                    .hint_text("id or name")
                    .desired_width(ui.available_width()),
            )
            .labelled_by(label.id);
        if std::mem::take(&mut w.text.focus_search) {
            field.request_focus();
            // Ctrl+F again selects what was typed, to type over it.
            if let Some(mut state) = egui::TextEdit::load_state(ui.ctx(), field.id) {
                let all = egui::text::CCursorRange::two(
                    egui::text::CCursor::new(0),
                    egui::text::CCursor::new(search.chars().count()),
                );
                state.cursor.set_char_range(Some(all));
                state.store(ui.ctx(), field.id);
            }
        }
        if field.changed() {
            cmds.push(Command::SetFilter(search));
        }
        if field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter)) {
            let back = ui.input(|i| i.modifiers.shift);
            cmds.push(
                if back {
                    UiCommand::PreviousMatch
                } else {
                    UiCommand::NextMatch
                }
                .into(),
            );
            // The field keeps the keyboard: Enter again goes on.
            field.request_focus();
        }
    });
    ui.horizontal_wrapped(|ui| {
        let any = !listed.shown.is_empty();
        shortcut_button(ui, UiCommand::PreviousMatch, any, cmds);
        shortcut_button(ui, UiCommand::NextMatch, any, cmds);
        let n = m.doc.plan.activities.len();
        let shown = listed.shown.len();
        let at = m
            .nav
            .selected
            .and_then(|a| listed.shown.iter().position(|&b| b == a));
        let text = match (listed.active, at) {
            (false, _) => format!("{n} activities"),
            (true, Some(i)) => format!("{} of {shown} ({n} in all)", i + 1),
            (true, None) => format!("{shown} of {n} shown"),
        };
        ui.label(RichText::new(text).color(m.theme.muted));
    });
    filters_ui(ui, m, w.cache, cmds);
}

/// The status, unit resource and sol menus and "Clear filters".
fn filters_ui(ui: &mut egui::Ui, m: &Model<'_>, cache: &mut ViewCache, cmds: &mut Vec<Command>) {
    let index = cache.search_index(&m.doc.plan, m.revision);
    let f = &m.nav.filter;
    let set = |cmds: &mut Vec<Command>, change: &dyn Fn(&mut ListFilter)| {
        let mut next = f.clone();
        change(&mut next);
        if next != *f {
            cmds.push(Command::SetListFilter(next));
        }
    };
    egui::Grid::new("list_filters")
        .num_columns(2)
        .show(ui, |ui| {
            if m.nav.mode == Mode::Schedule {
                let shown = f.status.map_or("Any status", StatusFilter::label);
                let options = StatusFilter::ALL.map(|s| (s, s.label().to_string()));
                let hover = "As of the step shown";
                if let Some(pick) = choice_ui(ui, "Status", shown, &f.status, options, hover) {
                    set(cmds, &|x| x.status = pick);
                }
            }
            let shown = f.resource.as_deref().unwrap_or("Any resource");
            let options = index.resources.iter().map(|r| (r.clone(), r.clone()));
            let hover = "Unit resources held";
            if let Some(pick) = choice_ui(ui, "Resource", shown, &f.resource, options, hover) {
                set(cmds, &|x| x.resource = pick.clone());
            }
            let sol_text = |s: i64| format!("Sol {s}");
            let shown = f.sol.map_or("Any sol".to_string(), sol_text);
            let options = index.sols.clone().map(|s| (s, sol_text(s)));
            let hover = "Placed in that sol (as of the step shown), or, not placed, a window \
                         touching it";
            if let Some(pick) = choice_ui(ui, "Sol", &shown, &f.sol, options, hover) {
                set(cmds, &|x| x.sol = pick);
            }
        });
    if f.active() {
        super::command_button(ui, UiCommand::ClearFilters, true, cmds);
    }
}

/// One row of the filters: `name`'s label and a menu of `Any <name>` and
/// each `(value, text)` of `options`, `current` marked, `shown` on the closed
/// menu. The choice picked this frame, if any (`Some(None)`: any).
fn choice_ui<T: PartialEq>(
    ui: &mut egui::Ui,
    name: &str,
    shown: &str,
    current: &Option<T>,
    options: impl IntoIterator<Item = (T, String)>,
    hover: &str,
) -> Option<Option<T>> {
    let mut pick = None;
    let label = ui.label(name);
    let any = format!("Any {}", name.to_lowercase());
    egui::ComboBox::from_id_salt(format!("{}_filter", name.to_lowercase()))
        .selected_text(shown)
        .show_ui(ui, |ui| {
            if ui.selectable_label(current.is_none(), any).clicked() {
                pick = Some(None);
            }
            for (value, text) in options {
                let on = current.as_ref() == Some(&value);
                if ui.selectable_label(on, text).clicked() {
                    pick = Some(Some(value));
                }
            }
        })
        .response
        .labelled_by(label.id)
        .on_hover_text(hover);
    ui.end_row();
    pick
}

/// The status mark and colour of activity `a` in the list.
fn mark(m: &Model<'_>, a: usize) -> (&'static str, egui::Color32) {
    match m.nav.mode {
        Mode::Schedule => match m.status(a, m.nav.step) {
            Status::Scheduled(..) => ("+", m.theme.scheduled),
            Status::Failed => ("x", m.theme.failed),
            Status::Skipped => ("-", m.theme.skipped),
            Status::Pending => (".", m.theme.muted),
        },
        Mode::Execution => match m.exec.ready().and_then(|r| r.activity(a)) {
            Some(r) => match r.outcome {
                RunOutcome::Completed => ("+", m.theme.scheduled),
                RunOutcome::Aborted => ("!", m.theme.aborted),
                RunOutcome::NotRun => ("x", m.theme.failed),
            },
            None => (".", m.theme.muted),
        },
    }
}

/// One row of the list: mark, step, id; clicking selects (in execution mode
/// with a campaign summarised, the activity's shares before it).
fn row_ui(ui: &mut egui::Ui, m: &Model<'_>, a: usize, cmds: &mut Vec<Command>) {
    let Some(step) = m.analysis.schedule.step_of(a) else {
        return;
    };
    let act = &m.doc.plan.activities[a];
    let (mark, color) = mark(m, a);
    let text = RichText::new(format!("{mark} {:>3} {}", step.step, act.id)).color(color);
    let button = egui::Button::new(text)
        .selected(m.nav.selected == Some(a))
        .frame(false);
    let shares = m
        .exec
        .campaign
        .ready()
        .and_then(|c| c.activity(a).map(|s| (s, c.runs())))
        .filter(|_| m.nav.mode == Mode::Execution);
    let resp = match shares {
        Some((s, runs)) => {
            ui.horizontal(|ui| {
                let size = egui::vec2(SHARE_BAR_WIDTH, SHARE_BAR_HEIGHT);
                widgets::share_bar(ui, m, s, runs, size);
                ui.add(button)
            })
            .inner
        }
        None => ui.add(button),
    };
    if resp.clicked() {
        cmds.push(Command::Select(Some(a)));
    }
}

/// The activity list: search and filters, status as of the current step,
/// click to select; a selection made elsewhere (keys, the Gantt, a culprit,
/// Back) is scrolled into view, and one the filters hide is pinned above the
/// list.
pub(super) fn activities_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    w: &mut Widgets<'_>,
    cmds: &mut Vec<Command>,
) {
    ui.heading("Activities");
    let listed = w.cache.listed(&m.doc.plan, m.analysis, m.nav, m.revision);
    search_ui(ui, m, w, &listed, cmds);
    ui.separator();
    let cache = &mut *w.cache;
    let shown = &listed.shown;
    if let Some(a) = m.nav.selected.filter(|&a| !listed.shows(a)) {
        // Never lose the selection: the filters hide it, so it stays here.
        ui.label(RichText::new("Selected (hidden by the filters):").color(m.theme.muted));
        row_ui(ui, m, a, cmds);
        ui.separator();
    }
    if shown.is_empty() {
        ui.label(RichText::new("No activity matches.").color(m.theme.muted));
    }
    // Only the visible rows are laid out, so 10k activities stay cheap.
    let row_height = ui.spacing().interact_size.y;
    let mut area = egui::ScrollArea::vertical().auto_shrink([false; 2]);
    let now = (m.nav.selected, listed.generation);
    if cache.list_selected != Some(now) {
        // The list changed under the rows in view: they say nothing of it.
        let same_list = cache
            .list_selected
            .is_some_and(|(_, g)| g == listed.generation);
        cache.list_selected = Some(now);
        let row = m
            .nav
            .selected
            .and_then(|a| shown.iter().position(|&b| b == a));
        if let Some(i) = row.filter(|i| !(same_list && cache.list_rows.contains(i))) {
            // Rows are `row_height` apart plus the item spacing; put the row a
            // few rows below the top.
            let pitch = row_height + ui.spacing().item_spacing.y;
            area = area.vertical_scroll_offset((i.saturating_sub(3)) as f32 * pitch);
        }
    }
    area.show_rows(ui, row_height, shown.len(), |ui, rows| {
        // Whole rows in view (the first and last may be cut).
        cache.list_rows = rows.start + 1..rows.end.saturating_sub(1);
        for &a in &shown[rows] {
            row_ui(ui, m, a, cmds);
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gui::SolscopeApp;

    fn ids(app: &mut SolscopeApp) -> Vec<String> {
        let listed = app
            .view_cache
            .listed(&app.doc.plan, &app.analysis, &app.ui.nav, app.revision);
        listed
            .shown
            .iter()
            .map(|&a| app.doc.plan.activities[a].id.clone())
            .collect()
    }

    #[test]
    fn search_matches_id_or_name_ignoring_case_in_step_order() {
        let mut app = SolscopeApp::with_default_plan().expect("default plan");
        let all = ids(&mut app);
        assert_eq!(all.len(), app.doc.plan.activities.len());
        app.apply(Command::SetFilter("  MEDA ".into()));
        let meda = ids(&mut app);
        assert!(meda.len() >= 5, "{meda:?}");
        let plan = &app.doc.plan;
        for a in &plan.activities {
            let hit = a.id.to_lowercase().contains("meda")
                || a.name
                    .as_ref()
                    .is_some_and(|n| n.to_lowercase().contains("meda"));
            assert_eq!(meda.contains(&a.id), hit, "{}", a.id);
        }
        // In step order: a subsequence of the whole list.
        let mut rest = all.iter();
        assert!(meda.iter().all(|id| rest.any(|x| x == id)));
        // By name: "Drill core sample" is drill_core_413's name.
        app.apply(Command::SetFilter("core sample".into()));
        assert!(ids(&mut app).contains(&"drill_core_413".to_string()));
    }

    #[test]
    fn filters_combine_and_follow_the_step_shown() {
        let mut app = SolscopeApp::with_default_plan().expect("default plan");
        let failed = app.analysis.failed();
        let filter = |status, resource: Option<&str>, sol| ListFilter {
            status,
            resource: resource.map(String::from),
            sol,
            ..ListFilter::default()
        };
        app.apply(Command::SetListFilter(filter(
            Some(StatusFilter::Failed),
            None,
            None,
        )));
        let n_failed = ids(&mut app).len();
        let skipped = app
            .analysis
            .schedule
            .steps
            .iter()
            .filter(|s| s.outcome.status() == "skipped")
            .count();
        assert_eq!(n_failed + skipped, failed);
        // Before step 1 nothing failed yet: all pending.
        app.apply(Command::SetStep(0));
        assert!(ids(&mut app).is_empty());
        app.apply(Command::SetListFilter(filter(
            Some(StatusFilter::Pending),
            None,
            None,
        )));
        assert_eq!(ids(&mut app).len(), app.doc.plan.activities.len());
        app.apply(Command::SetStep(app.analysis.steps()));
        // Holding the arm, in sol 413.
        app.apply(Command::SetListFilter(filter(None, Some("arm"), Some(413))));
        let arm_413 = ids(&mut app);
        assert!(!arm_413.is_empty());
        let plan = app.doc.plan.clone();
        for id in &arm_413 {
            let a = plan
                .activities
                .iter()
                .find(|a| &a.id == id)
                .expect("activity");
            assert!(a.resources.iter().any(|r| r == "arm"), "{id}");
        }
        assert!(arm_413.contains(&"drill_core_413".to_string()));
        assert!(!arm_413.contains(&"arm_unstow_412".to_string()));
        // Execution mode has no schedule statuses to filter by: set aside.
        app.apply(Command::SetListFilter(filter(
            Some(StatusFilter::Failed),
            None,
            None,
        )));
        assert_eq!(ids(&mut app).len(), n_failed);
        app.apply(crate::gui::UiCommand::ShowExecution.into());
        assert_eq!(ids(&mut app).len(), app.doc.plan.activities.len());
    }

    #[test]
    fn the_list_is_computed_once_per_filter_revision_and_step() {
        let mut app = SolscopeApp::with_default_plan().expect("default plan");
        app.apply(Command::SetFilter("meda".into()));
        let first = app
            .view_cache
            .listed(&app.doc.plan, &app.analysis, &app.ui.nav, app.revision);
        // A search does not depend on the step: stepping keeps the result.
        app.apply(Command::SetStep(3));
        let again = app
            .view_cache
            .listed(&app.doc.plan, &app.analysis, &app.ui.nav, app.revision);
        assert!(Arc::ptr_eq(&first, &again));
        // A status filter does.
        let status = ListFilter {
            search: "meda".into(),
            status: Some(StatusFilter::Scheduled),
            ..ListFilter::default()
        };
        app.apply(Command::SetListFilter(status));
        let a = app
            .view_cache
            .listed(&app.doc.plan, &app.analysis, &app.ui.nav, app.revision);
        app.apply(Command::SetStep(4));
        let b = app
            .view_cache
            .listed(&app.doc.plan, &app.analysis, &app.ui.nav, app.revision);
        assert!(!Arc::ptr_eq(&a, &b));
        assert!(b.generation > a.generation);
    }
}
