//! What the activity list's search and filters select ([`Listed`]), kept
//! between frames for the list, the Gantt's highlight and the reducer's
//! Up/Down and next/previous match, from a [`SearchIndex`] made once per plan
//! revision.

use std::collections::BTreeSet;
use std::sync::Arc;

use solscope_engine::Plan;

use super::document::Analysis;
use super::extent::window_spans;
use super::status::{Status, status_at};
use super::ui::{ListFilter, Mode, Navigation, StatusFilter};

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
    /// Which opened plan it lists (one number per plan opened in the
    /// process): the list of a plan just opened starts at its top.
    pub opened: u64,
}

/// Plans opened so far in the process (each one's [`Listed::opened`]).
static OPENED: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

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

/// What the search and filters selected last, and the search index of the
/// plan revision they searched: computed again only when the key changes.
#[derive(Clone, Debug, Default)]
pub struct ListCache {
    /// What the search and filters select (see [`ListCache::listed`]).
    listed: Option<Arc<Listed>>,
    /// Lower-case ids and names, resources and sols of one plan revision.
    search: Option<Arc<SearchIndex>>,
    /// This plan's [`Listed::opened`] (0 until first listed).
    opened: u64,
}

impl ListCache {
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
        if self.opened == 0 {
            self.opened = OPENED.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        }
        let mut listed = compute(plan, analysis, &index, key, generation);
        listed.opened = self.opened;
        let listed = Arc::new(listed);
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
        opened: 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::state::{AppState, Command, ListFilter, UiCommand};

    fn ids(app: &mut AppState) -> Vec<String> {
        let listed = app.listed();
        listed
            .shown
            .iter()
            .map(|&a| app.doc.plan.activities[a].id.clone())
            .collect()
    }

    #[test]
    fn search_matches_id_or_name_ignoring_case_in_step_order() {
        let mut app = AppState::with_default_plan().expect("default plan");
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
        let mut app = AppState::with_default_plan().expect("default plan");
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
        app.apply(UiCommand::ShowExecution.into());
        assert_eq!(ids(&mut app).len(), app.doc.plan.activities.len());
    }

    #[test]
    fn the_list_is_computed_once_per_filter_revision_and_step() {
        let mut app = AppState::with_default_plan().expect("default plan");
        app.apply(Command::SetFilter("meda".into()));
        let first = app.listed();
        // A search does not depend on the step: stepping keeps the result.
        app.apply(Command::SetStep(3));
        let again = app.listed();
        assert!(Arc::ptr_eq(&first, &again));
        // A status filter does.
        let status = ListFilter {
            search: "meda".into(),
            status: Some(StatusFilter::Scheduled),
            ..ListFilter::default()
        };
        app.apply(Command::SetListFilter(status));
        let a = app.listed();
        app.apply(Command::SetStep(4));
        let b = app.listed();
        assert!(!Arc::ptr_eq(&a, &b));
        assert!(b.generation > a.generation);
    }
}
