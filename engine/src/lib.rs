//! solscope engine: the plan model, timelines, the greedy scheduler with a full
//! per-step trace, and (later) the explainer. No GUI dependencies.
//!
//! Data flow: JSON text → [`load_plan`] (strict serde + semantic validation, with
//! warnings) → [`Plan`] → [`schedule`] (compiles the plan to fixed-point
//! [`Problem`] and runs the greedy scheduler) → [`Schedule`] (step trace) →
//! [`schedule_document`] (the `solscope.schedule/1` JSON).
#![deny(missing_docs)]

mod error;
mod explain;
mod generate;
mod io;
mod model;
mod scheduler;
mod timeline;
mod validate;

pub use error::{Error, Warning};
pub use explain::*;
pub use generate::generate_plan;
pub use io::{
    ActivityEntry, ExplainDoc, GeneratedEntry, LoadedPlan, Profiles, ScheduleDoc, apply_edit,
    explain_document, explain_text, load_plan, load_plan_file, schedule_document,
};
pub use model::*;
pub use scheduler::*;
pub use timeline::{Interval, IntervalSet};
pub use validate::validate;
