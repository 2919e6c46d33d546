//! The reducer: [`AppState::apply`] carries out one command, the only place
//! that changes the state (the views push commands while drawing; the frame
//! applies them after). Grouped by area: `file` (open, save, export, the file
//! dialogs, the repair view), `edit` (edits, undo, the activity list's
//! changes, pins), `steps` (steps, selection, links and history, revealing
//! the selection), `execution` (actuals, cycles, the Monte Carlo campaign),
//! `tour` (the guided tour), `tune` (priority tuning).

mod edit;
mod execution;
mod file;
mod steps;
mod tour;
mod tune;

use super::{AppState, Command, UiCommand};

#[cfg(test)]
pub(in crate::state) use file::write_json;

impl AppState {
    /// Carries out one command.
    pub fn apply(&mut self, cmd: Command) {
        match cmd {
            Command::Ui(cmd) => self.run(cmd),
            Command::SetStep(k) => self.set_step(k),
            Command::Play(on) => self.play(on),
            Command::SetCycle(k) => self.set_cycle(k),
            Command::SetCycleStep(k) => {
                self.ui.nav.cycle_step = k;
                self.follow_step();
            }
            Command::SetStepsShown(w) => self.ui.nav.steps_shown = w,
            Command::OpenActuals(path) => self.open_actuals(path),
            Command::SampleActuals { seed, run } => {
                let source = super::ActualsSource::Sampled { seed, run };
                self.use_actuals(source, "Could not sample actuals");
            }
            Command::RunCampaign { runs, seed } => self.run_campaign(runs, seed, false),
            Command::ComparePolicies { runs, seed } => self.run_campaign(runs, seed, true),
            Command::Select(a) => self.follow(|app| app.ui.nav.selected = a),
            Command::GoToFailureStep(a) => self.go_to_failure_step(a),
            Command::SetAxis(axis) => {
                self.ui.nav.axis = axis;
                self.ui.nav.axis.clamp(self.bounds());
                self.ui.sync_range_text(&self.doc.plan.local_time);
            }
            Command::ProbePlot(t) => self.ui.nav.probe = t,
            Command::SetSinceFull(on) => self.ui.nav.since_full = on,
            Command::SetPanelWidths([list, inspector]) => {
                self.persisted.list_width = Some(list);
                self.persisted.inspector_width = Some(inspector);
            }
            Command::ShowReason { activity, index } => {
                self.ui.nav.overlay_reason = Some((activity, index));
            }
            Command::Edit {
                target,
                set,
                description,
            } => self.edit(&target, &set, &description),
            Command::Open(path) => self.open(path),
            Command::SaveTo(path) => self.save_to(&path),
            Command::Chosen { dialog, path } => self.chosen(dialog, path),
            Command::DialogCancelled => {
                self.ui.messages.path_prompt = None;
                self.ui.messages.after_save = None;
            }
            Command::AskPath { dialog, why } => self.ask_path(dialog, why),
            Command::SaveAndContinue => self.save_and_continue(),
            Command::ExportScheduleTo(path) => self.export_schedule_to(&path),
            Command::SetDark(dark) => self.persisted.light = !dark,
            Command::GroupByResource(on) => self.persisted.by_resource = on,
            Command::SetFilter(f) => self.ui.nav.filter.search = f,
            Command::SetListFilter(f) => self.ui.nav.filter = f,
            Command::RepairJump(i) => self.repair_jump(i),
            Command::RepairPickId(id) => self.repair_pick_id(&id),
            Command::ShowError(e) => self.ui.messages.error = Some(e),
            Command::OfferPin { activity, start } => {
                self.ui.messages.pin = Some(super::PinOffer { activity, start });
            }
            Command::DismissPin => self.ui.messages.pin = None,
            Command::Pin { activity, start } => self.pin(activity, start),
            Command::DismissBanner => self.ui.messages.banner = None,
            Command::DismissError => self.ui.messages.error = None,
            Command::ConfirmDiscard(yes) => {
                let pending = self.ui.messages.confirm.take();
                if yes {
                    self.go_on(pending);
                }
            }
            Command::TourPage(k) => self.tour_page(k),
            Command::RunTune(settings) => self.start_tune(settings),
        }
    }

    /// Carries out a command given by name.
    fn run(&mut self, cmd: UiCommand) {
        use UiCommand as U;
        match cmd {
            U::Open
            | U::Save
            | U::SaveAs
            | U::ExportSchedule
            | U::ExportScheduleCsv
            | U::ExportPng
            | U::OpenActuals
            | U::CancelOpen
            | U::Quit => self.run_file(cmd),
            U::RecheckRepair => self.recheck_repair(),
            U::ReplaceAtError => self.replace_at_error(),
            U::UndoRepair => self.undo_repair(),
            U::CancelRepair => self.cancel_repair(),
            U::Undo | U::Redo | U::AddActivity | U::DuplicateActivity | U::DeleteActivity => {
                self.run_edit(cmd);
            }
            U::FirstStep
            | U::PreviousStep
            | U::NextStep
            | U::LastStep
            | U::NextFailure
            | U::PreviousFailure
            | U::SelectPrevious
            | U::SelectNext
            | U::NextMatch
            | U::PreviousMatch
            | U::Back
            | U::Forward
            | U::ZoomStepsIn
            | U::ZoomStepsOut
            | U::AllSteps => self.run_steps(cmd),
            U::Search => self.ui.text.focus_search = true,
            U::ClearFilters => self.ui.nav.filter = Default::default(),
            U::GuidedTour => self.guided_tour(),
            U::EndTour => {
                self.ui.messages.tour = None;
                self.persisted.tour_dismissed = true;
            }
            U::ResetTour => self.persisted.tour_dismissed = false,
            U::ShowSchedule
            | U::ShowExecution
            | U::NominalActuals
            | U::PreviousCycle
            | U::NextCycle
            | U::CancelCampaign => self.run_execution(cmd),
            U::ToggleFlex => self.toggle_flex(),
            U::TunePriorities
            | U::CancelTune
            | U::ApplyTuning
            | U::DismissTuning
            | U::ToggleTuneOverlay => self.run_tune(cmd),
            U::ToggleComparePolicies => {
                self.persisted.compare_policies = !self.persisted.compare_policies;
            }
        }
    }
}
