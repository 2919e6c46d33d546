//! `solscope schedule`: the schedule JSON (solscope.schedule/1).

use super::args::ScheduleArgs;
use super::failure::{Failure, to_json};
use super::{default_name, load};

/// The schedule document of the plan.
pub fn run(args: &ScheduleArgs, limit: usize) -> Result<String, Failure> {
    let loaded = load(&args.plan, limit)?;
    let schedule = solscope_engine::schedule(&loaded.plan)?;
    let doc = solscope_engine::schedule_document(&loaded, &schedule, &default_name(&args.plan));
    to_json(&doc)
}
