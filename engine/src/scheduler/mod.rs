//! The greedy, non-backtracking scheduler and its step trace.

mod trace;

pub use trace::*;

use crate::error::Error;
use crate::model::Plan;

/// The result of a scheduling run: the full step trace.
#[derive(Clone, Debug)]
pub struct Schedule {
    /// One record per step, `steps[k - 1]` for step k.
    pub steps: Vec<Step>,
    /// Every generated activity that ever existed, with its lifetime in steps.
    pub generated: Vec<Generated>,
}

/// Schedules a validated plan.
pub fn schedule(plan: &Plan) -> Result<Schedule, Error> {
    let _ = plan;
    Err(Error::invalid("$", "scheduler not written yet"))
}
