//! What execution mode's views read: the execution, the looked-at cycle's run
//! and the Monte Carlo campaign, each as far as it is derived for the plan
//! revision and actuals shown.

use super::execution::{ActualsSource, CycleRun, ExecutionRun};
use super::montecarlo::{CampaignResult, Progress, Stopped};
use super::ui::StepView;

/// What execution mode draws, each part once it is derived for the current plan
/// revision and actuals (`None` meanwhile).
#[derive(Clone, Copy, Debug)]
pub struct ExecModel<'a> {
    /// Where the actual durations come from.
    pub source: &'a ActualsSource,
    /// Bumped whenever the source changes.
    pub actuals_rev: u64,
    /// The execution, or why there is none.
    pub run: Option<&'a Result<std::sync::Arc<ExecutionRun>, String>>,
    /// The cycle looked at (clamped to the execution's cycles).
    pub cycle: usize,
    /// Its scheduler run with the step trace.
    pub cycle_run: Option<&'a CycleRun>,
    /// The step shown inside that run (clamped to its steps).
    pub step: usize,
    /// The run's profiles after that step.
    pub view: Option<&'a StepView>,
    /// Why the selected activity did not complete (when it did not).
    pub loss: Option<&'a Result<solscope_engine::Loss, String>>,
    /// The Monte Carlo campaign.
    pub campaign: CampaignModel<'a>,
}

/// What the Monte Carlo panel draws: the last campaign of the plan as it is,
/// the one running, and what became of one that stopped or no longer applies.
#[derive(Clone, Copy, Debug, Default)]
pub struct CampaignModel<'a> {
    /// The last campaign finished on the plan as it is (or why it failed).
    pub result: Option<&'a Result<CampaignResult, String>>,
    /// The campaign running.
    pub running: Option<Progress>,
    /// `(seed, runs)` of the last campaign finished when the plan was edited
    /// since (its summary is not shown).
    pub stale: Option<(u64, u64)>,
    /// The last campaign that stopped before its summary.
    pub stopped: Option<&'a Stopped>,
}

impl<'a> CampaignModel<'a> {
    /// The summary of the plan as it is, when there is one.
    pub fn ready(&self) -> Option<&'a CampaignResult> {
        self.result.and_then(|r| r.as_ref().ok())
    }
}

impl<'a> ExecModel<'a> {
    /// The execution, when derived without error.
    pub fn ready(&self) -> Option<&'a ExecutionRun> {
        self.run.and_then(|r| r.as_ref().ok()).map(AsRef::as_ref)
    }

    /// The cycle's run, when it could be repeated.
    pub fn schedule(&self) -> Option<&'a solscope_engine::Schedule> {
        self.cycle_run.and_then(|c| c.schedule.as_ref().ok())
    }
}
