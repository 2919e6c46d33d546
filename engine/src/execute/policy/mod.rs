//! The execution policies, each an [`Executive`](super::sim::Executive) the
//! simulation loop asks at every cycle: `replan`, the onboard scheduler run again
//! at each cycle (docs/format.md §10); `fixed`, every activity at its scheduled time like a
//! time-tagged sequence; and `dispatch`, the flexible plan executed by its start
//! and skip conditions. Neither of the last two reschedules: the schedule (and
//! its flexible form) is made once, at `horizon.start` ([`Prepared`]), and the
//! generated awake and heating periods run as scheduled.

mod dispatch;
mod fixed;
mod replan;

use std::borrow::Cow;

pub(super) use replan::Replan;

use super::sim::{CycleSchedule, Next, Sim};
use super::{Actuals, Execution, Trigger};
use crate::error::Error;
use crate::flex::{Flex, FlexOptions, flex_with};
use crate::model::Plan;
use crate::scheduler::{Problem, RunOutcomes, run_outcomes, schedule};
use dispatch::Dispatch;
use fixed::Fixed;

/// How activities are started while the plan executes.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    PartialOrd,
    Ord,
    Hash,
    serde::Serialize,
    serde::Deserialize,
)]
#[serde(rename_all = "snake_case")]
pub enum Policy {
    /// The onboard scheduler runs again at every cycle (docs/format.md §10).
    #[default]
    Replan,
    /// Every activity at its scheduled start, skipped if the guard does not let it
    /// start then.
    Fixed,
    /// The flexible schedule: each activity by its start and skip conditions.
    Dispatch,
}

impl Policy {
    /// The name on the command line and in documents.
    pub fn name(self) -> &'static str {
        match self {
            Policy::Replan => "replan",
            Policy::Fixed => "fixed",
            Policy::Dispatch => "dispatch",
        }
    }

    /// Whether this is the default, [`Policy::Replan`].
    pub fn is_replan(&self) -> bool {
        *self == Policy::Replan
    }
}

/// What a non-replanning policy needs once per plan: the schedule's outcomes and,
/// for dispatch, the flexible form.
#[derive(Clone, Debug)]
pub(crate) struct Prepared {
    outcomes: RunOutcomes,
    flex: Option<Flex>,
}

impl Prepared {
    /// The schedule of `plan` (and its flexible form for [`Policy::Dispatch`]).
    pub(crate) fn new(plan: &Plan, policy: Policy) -> Result<Self, Error> {
        if policy != Policy::Dispatch {
            return Ok(Self {
                outcomes: run_outcomes(plan)?,
                flex: None,
            });
        }
        // Dispatch needs the schedule for its flexible form: its outcomes are
        // the recorded run's, replayed, not a second run.
        let sched = schedule(plan)?;
        let outcomes = RunOutcomes::of(&sched);
        debug_assert_eq!(
            Some(&outcomes),
            run_outcomes(plan).ok().as_ref(),
            "the outcomes replayed from the schedule differ from a run's"
        );
        let flex = Some(flex_with(plan, &sched, FlexOptions { free_slack: false }));
        Ok(Self { outcomes, flex })
    }

    /// One execution under the policy this is for (dispatch when it has the
    /// flexible form, fixed otherwise).
    pub(crate) fn execute(
        &self,
        problem: &Problem,
        plan: &Plan,
        actuals: &Actuals,
    ) -> Result<Execution, Error> {
        let sim = Sim::new(problem, plan, actuals);
        let outcomes = &self.outcomes;
        match &self.flex {
            Some(flex) => sim.run(problem, plan, &Dispatch { outcomes, flex }),
            None => sim.run(problem, plan, &Fixed { outcomes }),
        }
    }
}

/// The one cycle of a policy that schedules once: the plan itself, as
/// scheduled at `horizon.start`.
fn scheduled_once<'p>(plan: &'p Plan, outcomes: &'p RunOutcomes) -> CycleSchedule<'p> {
    CycleSchedule {
        activity_of: (0..plan.activities.len()).collect(),
        dropped: Vec::new(),
        outcomes: Cow::Borrowed(outcomes),
        start: None,
        #[cfg(debug_assertions)]
        fingerprint: crate::execute::sim::fingerprint(plan),
    }
}

/// No cycle after the first.
fn no_next(problem: &Problem) -> Next {
    Next {
        time: problem.h1,
        trigger: Trigger::Period,
    }
}
