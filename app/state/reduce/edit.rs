//! Edits of the plan: a field edit through the engine's `apply_edit`
//! (validated, then rescheduled with the outcome diff as the banner), undo and
//! redo, the activity list's changes, and pins.

use serde_json::{Map, Value};
use solscope_engine::Plan;

use super::super::document::{
    ActivitiesEdit, OutcomeDiff, add_activity, delete_activity, duplicate_activity, pin_window,
};
use super::super::{AppState, Command, UiCommand};

impl AppState {
    /// Undo, redo and the changes of the list of activities.
    pub(super) fn run_edit(&mut self, cmd: UiCommand) {
        match cmd {
            UiCommand::Undo => {
                let before = self.doc.plan.clone();
                if self.doc.undo() {
                    self.reanalyse(before, "Undo");
                }
            }
            UiCommand::Redo => {
                let before = self.doc.plan.clone();
                if self.doc.redo() {
                    self.reanalyse(before, "Redo");
                }
            }
            UiCommand::AddActivity => match add_activity(&self.doc.plan, self.ui.nav.selected) {
                Ok(edit) => self.edit_activities(edit),
                Err(e) => self.ui.messages.error = Some(e),
            },
            UiCommand::DuplicateActivity => {
                if let Some(edit) = self
                    .ui
                    .nav
                    .selected
                    .and_then(|a| duplicate_activity(&self.doc.plan, a))
                {
                    self.edit_activities(edit);
                }
            }
            UiCommand::DeleteActivity => {
                if let Some(edit) = self
                    .ui
                    .nav
                    .selected
                    .and_then(|a| delete_activity(&self.doc.plan, a))
                {
                    self.edit_activities(edit);
                }
            }
            // Given by `run` for the edit commands only.
            _ => {}
        }
    }

    /// Applies an edit in the spec's format (`target` `plan` or
    /// `activity:ID`): validated, rescheduled, undoable; a bad edit changes
    /// nothing and is shown.
    pub(super) fn edit(&mut self, target: &str, set: &Map<String, Value>, description: &str) {
        match solscope_engine::apply_edit(&self.doc.plan, target, set) {
            Ok(plan) => self.accept_plan(plan, description),
            Err(e) => self.ui.messages.error = Some(format!("{description}: not applied: {e}")),
        }
    }

    /// Pins activity `a` at `start` (one window `[start, start]`) through the
    /// edit path, so the plan is validated, rescheduled and undoable.
    pub(super) fn pin(&mut self, a: usize, start: i64) {
        self.ui.messages.pin = None;
        let Some(act) = self.doc.plan.activities.get(a) else {
            return;
        };
        let placed = self.analysis.placement(a).map(|p| p.0);
        let (window, dropped) = pin_window(act, placed, start);
        let mut description = format!(
            "Pin {} at {}",
            act.id,
            solscope_engine::format_plan_time(&self.doc.plan.local_time, start)
        );
        if let Some(c) = dropped {
            description.push_str(&format!(" (dropping its cutoff {c})"));
        }
        let windows = match serde_json::to_value([window]) {
            Ok(v) => v,
            Err(e) => {
                self.ui.messages.error = Some(format!("{description}: not applied: {e}"));
                return;
            }
        };
        let mut set = serde_json::Map::new();
        set.insert("windows".into(), windows);
        let target = format!("activity:{}", act.id);
        self.apply(Command::Edit {
            target,
            set,
            description,
        });
    }

    /// Takes `plan` as the plan edited (rescheduled, with its outcome diff),
    /// or says the edit changed nothing.
    fn accept_plan(&mut self, plan: Plan, description: &str) {
        let before = self.doc.plan.clone();
        if self.doc.replace(plan) {
            self.reanalyse(before, description);
        } else {
            // Nothing to reschedule or undo; the editor shows the plan again.
            self.ui.messages.banner = Some(OutcomeDiff::unchanged(description));
            self.ui.messages.error = None;
            self.ui.text.editor.clear();
        }
    }

    /// Reschedules the current plan and shows the outcome diff against `before`.
    fn reanalyse(&mut self, before: Plan, description: &str) {
        match self.analysis.rerun(&self.doc.plan) {
            Ok(analysis) => {
                self.ui.nav.selected = self.ui.nav.selected.and_then(|a| {
                    // The same activity by id (an activity added, deleted or
                    // undone moves the others); by place when its id changed.
                    let acts = &self.doc.plan.activities;
                    let id = &before.activities.get(a)?.id;
                    acts.iter()
                        .position(|x| &x.id == id)
                        .or_else(|| (acts.len() == before.activities.len()).then_some(a))
                });
                let old = std::mem::replace(&mut self.analysis, analysis);
                self.ui.messages.banner = Some(OutcomeDiff::between(
                    description,
                    (&before, &old),
                    (&self.doc.plan, &self.analysis),
                ));
                self.ui.messages.error = None;
                // An offer to pin was for the plan as it was.
                self.ui.messages.pin = None;
                self.revision += 1;
                let mut k = self.ui.nav.step.min(self.analysis.steps());
                if k == old.steps() {
                    k = self.analysis.steps();
                }
                self.set_step(k);
            }
            Err(e) => self.ui.messages.error = Some(format!("{description}: {e}")),
        }
    }

    /// Applies a change of the list of activities as a plan edit (validated,
    /// rescheduled, undoable) and selects what it names.
    fn edit_activities(&mut self, edit: ActivitiesEdit) {
        let ActivitiesEdit {
            activities,
            select,
            description,
        } = edit;
        let value = match serde_json::to_value(&activities) {
            Ok(v) => v,
            Err(e) => {
                self.ui.messages.error = Some(format!("{description}: not applied: {e}"));
                return;
            }
        };
        let mut set = serde_json::Map::new();
        set.insert("activities".into(), value);
        if self.edit_plan(set, description) {
            self.ui.nav.selected =
                select.and_then(|id| self.doc.plan.activities.iter().position(|a| a.id == id));
        }
    }

    /// Applies `set` to the plan's top level as one edit (validated,
    /// rescheduled, one undo step); whether the plan took it.
    pub(super) fn edit_plan(
        &mut self,
        set: serde_json::Map<String, serde_json::Value>,
        description: String,
    ) -> bool {
        let revision = self.revision;
        self.apply(Command::Edit {
            target: "plan".into(),
            set,
            description,
        });
        self.revision != revision
    }
}
