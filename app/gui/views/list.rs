//! The activity list: search (Ctrl+F), filters by status, unit resource and
//! sol, the rows as of the step shown. What the search and filters select is
//! the state's ([`Listed`]: the frame puts it in the view cache before
//! drawing).

use eframe::egui::{self, RichText};
use solscope_engine::RunOutcome;

use super::{Model, ViewCache, Widgets, shortcut_button, widgets};
use crate::gui::shortcuts::kb_shortcut;
use crate::gui::theme::{SHARE_BAR_HEIGHT, SHARE_BAR_WIDTH};
use crate::state::{Command, ListFilter, Listed, Mode, Status, StatusFilter, UiCommand};

/// The search field, the match buttons and count, and the filters' menus.
fn search_ui(
    ui: &mut egui::Ui,
    m: &Model<'_>,
    w: &mut Widgets<'_>,
    listed: &Listed,
    cmds: &mut Vec<Command>,
) {
    let ctx = ui.ctx().clone();
    let key = |cmd: UiCommand| kb_shortcut(cmd).map_or(String::new(), |s| ctx.format_shortcut(&s));
    ui.horizontal(|ui| {
        let label = ui.label(UiCommand::Search.label()).on_hover_text(format!(
            "Activity id or name, any case ({}); Enter or {}: next match, Shift+Enter or {}: \
             previous",
            key(UiCommand::Search),
            key(UiCommand::NextMatch),
            key(UiCommand::PreviousMatch)
        ));
        let mut search = m.nav.filter.search.clone();
        let id = ui.make_persistent_id("list_search");
        if std::mem::take(&mut w.text.focus_search) {
            // Focused before the field is drawn, so it takes the keys typed
            // in the frame Ctrl+F came in; and Ctrl+F again selects what was
            // typed, to type over it.
            ui.memory_mut(|mem| mem.request_focus(id));
            let mut state = egui::TextEdit::load_state(ui.ctx(), id).unwrap_or_default();
            let all = egui::text::CCursorRange::two(
                egui::text::CCursor::new(0),
                egui::text::CCursor::new(search.chars().count()),
            );
            state.cursor.set_char_range(Some(all));
            state.store(ui.ctx(), id);
        }
        let field = ui
            .add(
                egui::TextEdit::singleline(&mut search)
                    .id(id)
                    .hint_text("id or name")
                    .desired_width(ui.available_width()),
            )
            .labelled_by(label.id);
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
    let Some(index) = cache.search.clone() else {
        return;
    };
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
    let Some(listed) = w.cache.listed.clone() else {
        return;
    };
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
    if cache.list_opened != listed.opened {
        // A plan just opened: its list starts at the top (or at its
        // selection, below), not where the plan before was scrolled.
        cache.list_opened = listed.opened;
        cache.list_selected = None;
        area = area.vertical_scroll_offset(0.0);
    }
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
