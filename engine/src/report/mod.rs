//! The output documents, built from the structured results: the schedule
//! (`solscope.schedule/1`), the explanation (`solscope.explain/1`), the
//! execution (`solscope.execution/1`), the flexible schedule (`solscope.flex/1`)
//! and priority tuning (`solscope.tuning/1`), and the CSV documents (the
//! schedule, a Monte Carlo campaign's runs) with their one CSV writer. Each is
//! built in one place; numbers go through `units`.

mod csv;
mod execution;
mod explain;
mod flex;
mod schedule;
mod tuning;

pub use csv::{runs_csv, schedule_csv};
pub use execution::{
    ChangedEntry, CycleEntry, DroppedEntry, EXECUTION_FORMAT, EventEntry, ExecutionDoc, RunEntry,
    SummaryEntry, TimedValue, ViolationEntry, WhyEntry, execution_document,
};
pub use explain::{
    CulpritEntry, EditEntry, ExplainDoc, ExplanationEntry, RelaxationEntry, SuggestionEntry,
    explain_document, explanation_entry,
};
pub use flex::{
    BoundEntry, BoundsEntry, ConditionEntry, ConstraintEntry, ControllabilityEntry, EdgeEntry,
    FLEX_FORMAT, FlexDoc, FlexEntry, FlexSummary, PointEntry, WaitEntry, flex_document,
};
pub use schedule::{ActivityEntry, GeneratedEntry, ScheduleDoc, schedule_document};
pub use tuning::{
    ChangeEntry, CountsEntry, CountsPair, DifferenceEntry, PairEntry, SampleEntry, ScoreEntry,
    ScoresEntry, SearchEntry, TUNING_FORMAT, TunedActivityEntry, TuningDoc, VerdictEntry,
    WhyChangeEntry, tuning_document, tuning_json,
};
