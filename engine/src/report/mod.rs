//! The output documents, built from the structured results: the schedule
//! (`solscope.schedule/1`) and the explanation (`solscope.explain/1`). Each is
//! built in one place; numbers go through `units`.

mod explain;
mod schedule;

pub use explain::{
    CulpritEntry, EditEntry, ExplainDoc, ExplanationEntry, RelaxationEntry, SuggestionEntry,
    explain_document,
};
pub use schedule::{ActivityEntry, GeneratedEntry, ScheduleDoc, schedule_document};
