//! solscope engine: the plan model, timelines, the greedy scheduler with a full
//! per-step trace, and the explainer. No GUI dependencies.
//!
//! Data flow: JSON text → [`load_plan`] (strict serde + semantic validation, with
//! warnings) → [`Plan`] → [`schedule`] (compiles the plan to fixed-point
//! [`Problem`] and runs the greedy scheduler) → [`Schedule`] (step trace) →
//! [`explain()`] ([`Explanation`]s, failures as data) → the documents
//! ([`schedule_document`], [`explain_document`]; as CSV, [`schedule_csv`] and a
//! Monte Carlo campaign's [`runs_csv`]) and the text ([`explain_text`]).
//! [`tune()`] searches the priorities that keep the most of what matters when
//! durations vary, scoring orders on Monte Carlo samples ([`Tuning`],
//! [`tuning_document`]). Units and times read the same everywhere through the
//! `units` functions re-exported here ([`format_wh`], [`format_plan_time`], ...).
#![deny(missing_docs)]

mod edit;
mod error;
mod execute;
mod explain;
mod flex;
mod generate;
mod load;
mod model;
mod plan_errors;
mod report;
mod scheduler;
mod sentence;
mod timeline;
mod tune;
mod units;
mod validate;

pub use edit::apply_edit;
pub use error::{Error, Warning};
pub use execute::{
    ACTUALS_FORMAT, ActivityRun, ActivitySummary, Actuals, Campaign, Cause, CauseCount, Cycle,
    CyclePlan, Distribution, Dropped, Event, ExecuteOptions, ExecutedProfile, Execution, Guard,
    LimitSummary, Loss, LossRecord, LostSummary, MONTECARLO_FORMAT, MONTECARLO_RUNS_FORMAT,
    PairSummary, Policy, Predictor, Quantiles, RunOutcome, RunRecord, RunsDoc, Summary, Trigger,
    Violation, ViolationKind, campaign, campaign_runs, campaign_with, execute, execute_with,
    load_actuals, loss, loss_line, losses, merge_files, merge_parts, read_runs, run_record,
    sample_actuals, sample_run, summarize,
};
pub use explain::{
    Blame, Consumer, Culprit, ExplainOptions, Explanation, Phase, REASON_RANGES_MAX, ReasonRange,
    Relaxation, Suggestion, energy_consumers, explain, explain_each, explain_rendered,
    explain_text, explanation_notes, explanation_notes_and_lead, explanation_text, involved,
    minimal_conflicts, peak_users, reason_line, reasons_in_reading_order, suggestion_description,
    suggestion_line, verified_suggestions,
};
pub use flex::{
    Bound, Constraint, Controllability, DispatchEdge, EventBounds, Flex, FlexActivity, FlexOptions,
    FreeSlack, OrderKind, StartCondition, TimePoint, Wait, constraint_line, flex, flex_text,
    flex_with, free_slack_each, free_slack_of, time_point_name,
};
pub use generate::{Profile, add_duration_models, generate_plan, generate_plan_with};
pub use load::{
    LoadedPlan, MAX_PLAN_BYTES, load_plan, load_plan_file, load_plan_limited, read_plan_text,
};
pub use model::{
    Activity, AwakeMode, Battery, CycleStart, Data, Dependency, Duration, DurationModel, EffectAt,
    ExecutionSection, Handover, Horizon, LocalTime, MARS_SOL, OperablePeriod, PLAN_FORMAT, Plan,
    Power, PreheatEntry, Sleep, StateDef, StateEffect, StateRequirement, ThermalZone, Window,
};
pub use plan_errors::plan_errors;
pub use report::{
    ActivityEntry, BoundEntry, BoundsEntry, ChangedEntry, ConditionEntry, ConstraintEntry,
    ControllabilityEntry, CulpritEntry, CycleEntry, DroppedEntry, EXECUTION_FORMAT, EdgeEntry,
    EditEntry, EventEntry, ExecutionDoc, ExplainDoc, ExplanationEntry, FLEX_FORMAT, FlexDoc,
    FlexEntry, FlexSummary, GeneratedEntry, PointEntry, RelaxationEntry, RunEntry, ScheduleDoc,
    SuggestionEntry, SummaryEntry, TimedValue, ViolationEntry, WaitEntry, WhyEntry,
    execution_document, explain_document, explanation_entry, flex_document, runs_csv, schedule_csv,
    schedule_document,
};
pub use report::{
    ChangeEntry, CountsEntry, CountsPair, DifferenceEntry, PairEntry, SampleEntry, ScoreEntry,
    ScoresEntry, SearchEntry, TUNING_FORMAT, TunedActivityEntry, TuningDoc, VerdictEntry,
    WhyChangeEntry, tuning_document, tuning_json,
};
pub use scheduler::{
    Act, Category, CategoryIntervals, FailurePhase, Generated, GeneratedKind, Outcome,
    PartialSchedule, Phase2Reason, Placement, Problem, Profiles, ReasonKind, RunOutcomes, Schedule,
    State, Step, StepTrace, Try, partial_schedule, reschedule, run_outcomes, schedule,
    valid_intervals_at,
};
pub use timeline::{Interval, IntervalSet};
#[doc(hidden)]
pub use tune::OrderScorer;
pub use tune::{
    ActivityCounts, Change, ChangeWhy, Counts, Mode, Moved, Sample, Score, Scores, Stop,
    TuneOptions, TuneProgress, Tuning, ValueMeasure, change_line, first_difference_line,
    score_line, tune,
};
pub use units::{
    BIT_PER_MBIT, LMST_SECONDS_PER_SOL, MJ_PER_WH, MW_PER_W, ParseUnitError, Unit,
    format_document_time, format_lmst, format_local, format_mbit, format_mbit_value,
    format_plan_time, format_span, format_time_difference, format_time_of_day, format_watts,
    format_wh, format_wh_value, lmst_of_day, lmst_sentence, mbit, parse_local, parse_mbit,
    parse_span, parse_time_difference, parse_time_of_day, parse_watts, parse_wh,
    time_of_day_of_lmst, watts, wh,
};
pub use validate::{validate, validate_all};
