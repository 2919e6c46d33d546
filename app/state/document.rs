//! The open plan with its undo history, and the analysis derived from it.
//!
//! `Document` is the model the user edits; `Analysis` is recomputed from it after
//! every accepted change (schedule + explanations), never edited directly.

use std::path::PathBuf;

use solscope_engine::{
    Error, ExplainOptions, Explanation, Plan, Schedule, Warning, explain, load_plan_limited,
    reschedule, schedule,
};

/// The open plan.
#[derive(Clone, Debug)]
pub struct Document {
    /// The plan as edited.
    pub plan: Plan,
    /// Where it was loaded from / saved to.
    pub path: Option<PathBuf>,
    /// Unsaved changes?
    pub dirty: bool,
    /// Loader warnings of the current plan.
    pub warnings: Vec<Warning>,
    /// Undo and redo history, each plan with its version number.
    undo: Vec<(Plan, u64)>,
    redo: Vec<(Plan, u64)>,
    /// The version of the plan shown (every accepted edit is a new one).
    version: u64,
    /// The last version number given out.
    versions: u64,
    /// The version last loaded or saved: back at it, nothing is unsaved.
    saved: Option<u64>,
}

impl Document {
    /// Loads a plan from JSON text. A bad plan is an error naming the JSON path.
    pub fn from_text(text: &str, path: Option<PathBuf>) -> Result<Self, Error> {
        Self::from_text_limited(text, path, solscope_engine::MAX_PLAN_BYTES)
    }

    /// [`Document::from_text`] with another size limit (`screenshot
    /// --max-input-mib`).
    pub fn from_text_limited(
        text: &str,
        path: Option<PathBuf>,
        limit: usize,
    ) -> Result<Self, Error> {
        let loaded = load_plan_limited(text, limit)?;
        Ok(Self {
            plan: loaded.plan,
            path,
            dirty: false,
            warnings: loaded.warnings,
            undo: Vec::new(),
            redo: Vec::new(),
            version: 0,
            versions: 0,
            saved: Some(0),
        })
    }

    /// The display title: plan name, else file name.
    pub fn title(&self) -> String {
        self.plan.name.clone().unwrap_or_else(|| {
            self.path
                .as_ref()
                .and_then(|p| p.file_name())
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_else(|| "untitled plan".into())
        })
    }

    /// A file name stem for what is saved or exported from this plan: its
    /// file's, else its name made file-safe, else `plan`.
    pub fn file_stem(&self) -> String {
        if let Some(stem) = self.path.as_deref().and_then(|p| p.file_stem()) {
            return stem.to_string_lossy().into_owned();
        }
        let safe: String = self
            .plan
            .name
            .as_deref()
            .unwrap_or("")
            .chars()
            .map(|c| {
                if c.is_alphanumeric() {
                    c.to_ascii_lowercase()
                } else {
                    '-'
                }
            })
            .collect();
        let safe = safe
            .split('-')
            .filter(|s| !s.is_empty())
            .collect::<Vec<_>>()
            .join("-");
        if safe.is_empty() { "plan".into() } else { safe }
    }

    /// Replaces the plan with an edited one (already validated), recording undo.
    /// An edit that changes nothing is not recorded: false.
    pub fn replace(&mut self, plan: Plan) -> bool {
        if plan == self.plan {
            return false;
        }
        self.versions += 1;
        let old = std::mem::replace(&mut self.plan, plan);
        self.undo.push((old, self.version));
        self.version = self.versions;
        self.redo.clear();
        self.refresh_dirty();
        self.refresh_warnings();
        true
    }

    /// Steps back one edit; false when there is none.
    pub fn undo(&mut self) -> bool {
        match self.undo.pop() {
            Some((prev, version)) => {
                let cur = std::mem::replace(&mut self.plan, prev);
                self.redo.push((cur, self.version));
                self.version = version;
                self.refresh_dirty();
                self.refresh_warnings();
                true
            }
            None => false,
        }
    }

    /// Re-applies an undone edit; false when there is none.
    pub fn redo(&mut self) -> bool {
        match self.redo.pop() {
            Some((next, version)) => {
                let cur = std::mem::replace(&mut self.plan, next);
                self.undo.push((cur, self.version));
                self.version = version;
                self.refresh_dirty();
                self.refresh_warnings();
                true
            }
            None => false,
        }
    }

    /// The plan as it is was written to `path`: nothing is unsaved, also after
    /// undoing and redoing back to it.
    pub fn mark_saved(&mut self, path: PathBuf) {
        self.path = Some(path);
        self.saved = Some(self.version);
        self.dirty = false;
    }

    /// The plan differs from its file (repaired from the file's text): unsaved
    /// until saved.
    pub fn mark_unsaved(&mut self) {
        self.saved = None;
        self.dirty = true;
    }

    /// Unsaved unless the plan is the version last loaded or saved.
    fn refresh_dirty(&mut self) {
        self.dirty = self.saved != Some(self.version);
    }

    /// Whether undo / redo are possible.
    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty()
    }

    /// Whether redo is possible.
    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    fn refresh_warnings(&mut self) {
        // Every plan here passed validation (loading and edits validate); should
        // one not, say so where warnings are shown instead of showing none.
        self.warnings = match solscope_engine::validate(&self.plan) {
            Ok(warnings) => warnings,
            Err(e) => vec![Warning {
                path: "$".into(),
                message: format!("the plan does not validate: {e}"),
            }],
        };
    }
}

/// Everything derived from a plan: the run with its trace. Explanations are
/// computed on demand for the activity looked at (see `AppState`), so an edit
/// costs one reschedule.
#[derive(Clone, Debug)]
pub struct Analysis {
    /// The run (shared with the worker that verifies suggestions).
    pub schedule: std::sync::Arc<Schedule>,
}

impl Analysis {
    /// Schedules a plan.
    pub fn of(plan: &Plan) -> Result<Self, Error> {
        Ok(Self::from(schedule(plan)?))
    }

    /// Schedules an edited plan, reusing the steps of this analysis that the edit
    /// cannot change (the engine's `reschedule`; same result as [`Analysis::of`]).
    pub fn rerun(&self, plan: &Plan) -> Result<Self, Error> {
        Ok(Self::from(reschedule(&self.schedule, plan)?))
    }

    /// The step record of activity `a` (O(1): the schedule's own index).
    pub fn step(&self, a: usize) -> Option<&solscope_engine::Step> {
        self.schedule.step_of(a)
    }

    /// Explains activity `a` (without suggestions) if it did not schedule.
    pub fn explain(&self, plan: &Plan, a: usize) -> Result<Option<Explanation>, Error> {
        if self.placement(a).is_some() {
            return Ok(None);
        }
        let act = plan
            .activities
            .get(a)
            .ok_or_else(|| Error::UnknownActivity(format!("#{a}")))?;
        let opts = ExplainOptions {
            activity: Some(act.id.clone()),
            no_suggestions: true,
        };
        Ok(explain(plan, &self.schedule, &opts)?.pop())
    }

    /// Number of activities that did not schedule.
    pub fn failed(&self) -> usize {
        self.schedule
            .steps
            .iter()
            .filter(|s| s.outcome.placement().is_none())
            .count()
    }

    /// `(start, end)` of activity `a` if scheduled.
    pub fn placement(&self, a: usize) -> Option<(i64, i64)> {
        self.step(a)?.outcome.placement()
    }

    /// Number of steps.
    pub fn steps(&self) -> usize {
        self.schedule.steps.len()
    }
}

/// The edit that pins an activity at `start`: its windows become the one
/// window `[start, start]` with `start` preferred. The cutoff of the window it
/// was placed in (`placed`: its scheduled start) is kept when the activity's
/// shortest duration still ends by it; otherwise it is dropped, and returned
/// (the planner moved it past its cutoff on purpose and is told so).
pub fn pin_window(
    act: &solscope_engine::Activity,
    placed: Option<i64>,
    start: i64,
) -> (solscope_engine::Window, Option<i64>) {
    let cutoff = placed.and_then(|s| {
        act.windows
            .iter()
            .flatten()
            .find(|w| w.start <= s && s <= w.end)
            .and_then(|w| w.cutoff)
    });
    // A cutoff must come after the start (validation): a zero duration needs one
    // second.
    let fits = |c: i64| start.saturating_add(act.duration.min().max(1)) <= c;
    let (kept, dropped) = match cutoff {
        Some(c) if fits(c) => (Some(c), None),
        Some(c) => (None, Some(c)),
        None => (None, None),
    };
    let window = solscope_engine::Window {
        start,
        end: start,
        preferred: Some(start),
        cutoff: kept,
    };
    (window, dropped)
}

/// An id no activity of `plan` has: `base`, else `base_2`, `base_3`, ...
fn unused_id(plan: &Plan, base: &str) -> String {
    let taken = |id: &str| plan.activities.iter().any(|a| a.id == id);
    if !taken(base) {
        return base.to_string();
    }
    (2..)
        .map(|n| format!("{base}_{n}"))
        .find(|id| !taken(id))
        .unwrap_or_else(|| base.to_string())
}

/// A change of the plan's list of activities: the new list, the id to select
/// once it is applied, and what it did (the banner and undo).
#[derive(Clone, Debug, PartialEq)]
pub struct ActivitiesEdit {
    /// The activities after the change.
    pub activities: Vec<solscope_engine::Activity>,
    /// The activity to select (none after a delete).
    pub select: Option<String>,
    /// What it did.
    pub description: String,
}

/// A new activity after activity `after` (with its priority, so it comes next
/// in step order), or at the end (after every priority) when `None`: a
/// `new_activity` of 10 minutes over the whole horizon.
pub fn add_activity(plan: &Plan, after: Option<usize>) -> Result<ActivitiesEdit, String> {
    let id = unused_id(plan, "new_activity");
    let (at, priority) = match after.and_then(|a| plan.activities.get(a).map(|x| (a, x))) {
        Some((a, x)) => (a + 1, x.priority),
        None => (
            plan.activities.len(),
            plan.activities
                .iter()
                .map(|a| a.priority)
                .max()
                .map_or(1, |p| p.saturating_add(1)),
        ),
    };
    let new: solscope_engine::Activity = serde_json::from_value(serde_json::json!({
        "id": id, "priority": priority, "duration": 600
    }))
    .map_err(|e| format!("Add activity: {e}"))?;
    let mut activities = plan.activities.clone();
    activities.insert(at, new);
    Ok(ActivitiesEdit {
        activities,
        description: format!("Add activity {id}"),
        select: Some(id),
    })
}

/// A copy of activity `a` right after it, under a new id (`ID_copy`); the
/// name, when it has one, says it is a copy.
pub fn duplicate_activity(plan: &Plan, a: usize) -> Option<ActivitiesEdit> {
    let original = plan.activities.get(a)?;
    let mut copy = original.clone();
    copy.id = unused_id(plan, &format!("{}_copy", original.id));
    copy.name = original.name.as_ref().map(|n| format!("{n} (copy)"));
    let id = copy.id.clone();
    let mut activities = plan.activities.clone();
    activities.insert(a + 1, copy);
    Some(ActivitiesEdit {
        activities,
        description: format!("Duplicate {} as {id}", original.id),
        select: Some(id),
    })
}

/// Activity `a` deleted, with the `after` entries of the others that name it
/// (else the plan would not validate); the description names them.
pub fn delete_activity(plan: &Plan, a: usize) -> Option<ActivitiesEdit> {
    let gone = plan.activities.get(a)?;
    let mut dependents = Vec::new();
    let activities = plan
        .activities
        .iter()
        .enumerate()
        .filter(|&(i, _)| i != a)
        .map(|(_, x)| {
            let mut x = x.clone();
            let before = x.after.len();
            x.after.retain(|d| d.activity != gone.id);
            if x.after.len() != before {
                dependents.push(x.id.clone());
            }
            x
        })
        .collect();
    let mut description = format!("Delete {}", gone.id);
    if !dependents.is_empty() {
        description.push_str(&format!(
            " (and the dependencies of {} on it)",
            dependents.join(", ")
        ));
    }
    Some(ActivitiesEdit {
        activities,
        select: None,
        description,
    })
}

/// What an edit changed in the outcome, by activity id.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct OutcomeDiff {
    /// What the edit was.
    pub description: String,
    /// Failed before, scheduled now.
    pub newly_scheduled: Vec<String>,
    /// Scheduled before, not now.
    pub newly_failed: Vec<String>,
    /// Scheduled both times at different starts: `(id, old start, new start)`.
    pub moved: Vec<(String, i64, i64)>,
    /// The edit left the plan as it was (nothing rescheduled or recorded).
    pub unchanged: bool,
    /// The plan's clock after the edit, which the moves are said in.
    pub clock: solscope_engine::LocalTime,
}

impl OutcomeDiff {
    /// Compares two runs by activity id.
    pub fn between(
        description: &str,
        before: (&Plan, &Analysis),
        after: (&Plan, &Analysis),
    ) -> Self {
        let mut diff = OutcomeDiff {
            description: description.to_string(),
            clock: after.0.local_time,
            ..Default::default()
        };
        for st in &after.1.schedule.steps {
            let id = &after.0.activities[st.activity].id;
            let old = before
                .0
                .activities
                .iter()
                .position(|a| &a.id == id)
                .and_then(|i| before.1.placement(i));
            let new = st.outcome.placement();
            match (old, new) {
                (None, Some(_)) => diff.newly_scheduled.push(id.clone()),
                (Some(_), None) => diff.newly_failed.push(id.clone()),
                (Some(o), Some(n)) if o.0 != n.0 => diff.moved.push((id.clone(), o.0, n.0)),
                _ => {}
            }
        }
        diff
    }

    /// The banner of an edit that changed nothing.
    pub fn unchanged(description: &str) -> Self {
        Self {
            description: description.to_string(),
            unchanged: true,
            ..Self::default()
        }
    }

    /// One line for the banner, its times in sol time (LMST).
    pub fn summary(&self) -> String {
        let clock = &self.clock;
        if self.unchanged {
            return format!(
                "{}: the plan is unchanged (nothing rescheduled, nothing to undo)",
                self.description
            );
        }
        let list = |v: &[String]| {
            if v.is_empty() {
                "none".to_string()
            } else {
                v.join(", ")
            }
        };
        format!(
            "{}: newly scheduled: {}; newly failed: {}; moved: {}",
            self.description,
            list(&self.newly_scheduled),
            list(&self.newly_failed),
            if self.moved.is_empty() {
                "none".into()
            } else {
                self.moved
                    .iter()
                    .map(|m| {
                        format!(
                            "{} ({} → {})",
                            m.0,
                            solscope_engine::format_plan_time(clock, m.1),
                            solscope_engine::format_plan_time(clock, m.2)
                        )
                    })
                    .collect::<Vec<_>>()
                    .join(", ")
            }
        )
    }
}

impl From<Schedule> for Analysis {
    fn from(schedule: Schedule) -> Self {
        Self {
            schedule: std::sync::Arc::new(schedule),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An activity of `duration` seconds with one window `[1000, 2000]`
    /// (cutoff 2600) and one `[5000, 6000]`.
    fn activity(duration: serde_json::Value) -> solscope_engine::Activity {
        serde_json::from_value(serde_json::json!({
            "id": "a",
            "priority": 1,
            "duration": duration,
            "windows": [
                {"start": 1000, "end": 2000, "cutoff": 2600},
                {"start": 5000, "end": 6000}
            ]
        }))
        .expect("activity")
    }

    fn pitfall() -> Plan {
        solscope_engine::load_plan(include_str!("../../assets/examples/pitfall.json"))
            .expect("pitfall")
            .plan
    }

    #[test]
    fn activities_are_added_duplicated_and_deleted_with_fresh_ids() {
        let plan = pitfall();
        let ids = |e: &ActivitiesEdit| -> Vec<String> {
            e.activities.iter().map(|a| a.id.clone()).collect()
        };
        let added = add_activity(&plan, Some(0)).expect("added");
        assert_eq!(ids(&added), ["A", "new_activity", "B"]);
        assert_eq!(added.activities[1].priority, plan.activities[0].priority);
        assert_eq!(added.select.as_deref(), Some("new_activity"));
        let mut twice = plan.clone();
        twice.activities = added.activities.clone();
        let again = add_activity(&twice, None).expect("added");
        assert_eq!(again.activities[3].id, "new_activity_2");
        assert_eq!(again.activities[3].priority, 3, "after every priority");
        let copy = duplicate_activity(&plan, 1).expect("copied");
        assert_eq!(ids(&copy), ["A", "B", "B_copy"]);
        assert_eq!(
            copy.activities[2],
            solscope_engine::Activity {
                id: "B_copy".into(),
                ..plan.activities[1].clone()
            }
        );
        // B depends on A in no plan here: make it, then delete A.
        let mut dep = plan.clone();
        dep.activities[1].after = vec![solscope_engine::Dependency {
            activity: "A".into(),
            meets: false,
            min_delay: None,
            max_delay: None,
        }];
        let deleted = delete_activity(&dep, 0).expect("deleted");
        assert_eq!(ids(&deleted), ["B"]);
        assert!(deleted.activities[0].after.is_empty());
        assert_eq!(
            deleted.description,
            "Delete A (and the dependencies of B on it)"
        );
        assert!(delete_activity(&plan, 5).is_none());
    }

    #[test]
    fn a_pin_keeps_the_cutoff_of_its_window_while_it_still_fits() {
        let act = activity(serde_json::json!(500));
        let (w, dropped) = pin_window(&act, Some(1500), 2100);
        assert_eq!(
            (w.start, w.end, w.preferred, w.cutoff, dropped),
            (2100, 2100, Some(2100), Some(2600), None)
        );
        // Past it: the cutoff goes, and the caller is told which.
        let (w, dropped) = pin_window(&act, Some(1500), 2200);
        assert_eq!((w.cutoff, dropped), (None, Some(2600)));
        // An expanding activity keeps it while its shortest duration fits.
        let act = activity(serde_json::json!({"min": 300, "max": 900}));
        assert_eq!(pin_window(&act, Some(1500), 2300).0.cutoff, Some(2600));
        // Placed in the window without a cutoff, or not placed: none.
        assert_eq!(
            pin_window(&act, Some(5500), 100),
            (pin_window(&act, None, 100).0, None)
        );
        assert_eq!(pin_window(&act, None, 100).0.cutoff, None);
    }
}
