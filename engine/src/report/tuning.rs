//! The tuning document (`solscope.tuning/1`, docs/format.md section 12).

use serde::Serialize;
use serde_json::{Map, Value, json};

use super::explain::EditEntry;
use crate::model::Plan;
use crate::tune::{ChangeWhy, Counts, Moved, Sample, Score, Tuning, ValueMeasure, change_line};

/// The value of `format` in every tuning document.
pub const TUNING_FORMAT: &str = "solscope.tuning/1";

/// `solscope.tuning/1`.
#[derive(Clone, Debug, Serialize)]
pub struct TuningDoc {
    /// Always [`TUNING_FORMAT`].
    pub format: &'static str,
    /// Plan name.
    pub plan: String,
    /// `value` (some activity has a `value`) or `step_order` (none has: the
    /// original step order measures value).
    pub measure: &'static str,
    /// The sample the search scored orders on.
    pub tuning_sample: SampleEntry,
    /// The sample the result is confirmed on.
    pub held_out_sample: SampleEntry,
    /// Scores of the original and the tuned order on both samples.
    pub scores: ScoresEntry,
    /// The tuned order against the original on the held-out sample.
    pub held_out: VerdictEntry,
    /// Every activity in file order.
    pub activities: Vec<TunedActivityEntry>,
    /// The activities whose priority changed, in file order.
    pub changes: Vec<ChangeEntry>,
    /// The edits that turn the plan into the tuned plan (one per change).
    pub edits: Vec<EditEntry>,
    /// The search.
    pub search: SearchEntry,
}

/// A sample: runs `0..runs` of `seed`.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct SampleEntry {
    /// Seed.
    pub seed: u64,
    /// Runs.
    pub runs: u64,
}

/// Scores on both samples.
#[derive(Clone, Debug, Serialize)]
pub struct ScoresEntry {
    /// On the tuning sample.
    pub tuning: PairEntry,
    /// On the held-out sample.
    pub held_out: PairEntry,
}

/// The original's and the tuned order's score on one sample.
#[derive(Clone, Debug, Serialize)]
pub struct PairEntry {
    /// The original order's.
    pub original: ScoreEntry,
    /// The tuned order's.
    pub tuned: ScoreEntry,
}

/// One score, item by item of the objective.
#[derive(Clone, Debug, Serialize)]
pub struct ScoreEntry {
    /// Runs that broke a limit.
    pub runs_breaking_limits: u64,
    /// Completions of mandatory activities over the runs.
    pub mandatory_completions: u64,
    /// Value completed over the runs (measure `value` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub value_completed: Option<f64>,
    /// Pairs of activities in another relative order than the original.
    pub order_changes: u64,
}

/// How the tuned order fares on the held-out sample.
#[derive(Clone, Debug, Serialize)]
pub struct VerdictEntry {
    /// `better`, `same` or `worse` by the objective.
    pub verdict: &'static str,
    /// Not worse.
    pub no_worse: bool,
    /// Fewer runs breaking a limit (original minus tuned).
    pub fewer_runs_breaking_limits: i64,
    /// More mandatory completions (tuned minus original).
    pub more_mandatory_completions: i64,
    /// More value completed (tuned minus original; measure `value`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub more_value_completed: Option<f64>,
    /// Measure `step_order`: the first activity in the original step order
    /// whose completions differ, with both counts.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub first_difference: Option<DifferenceEntry>,
}

/// The first activity (original step order) completed a different number of
/// times.
#[derive(Clone, Debug, Serialize)]
pub struct DifferenceEntry {
    /// Activity id.
    pub activity: String,
    /// Completions with the original order.
    pub original: u64,
    /// Completions with the tuned order.
    pub tuned: u64,
}

/// One activity: priorities and outcomes before and after.
#[derive(Clone, Debug, Serialize)]
pub struct TunedActivityEntry {
    /// Activity id.
    pub id: String,
    /// Priority in the plan.
    pub priority_before: i64,
    /// Tuned priority.
    pub priority_after: i64,
    /// Outcomes on the tuning sample.
    pub tuning: CountsPair,
    /// Outcomes on the held-out sample.
    pub held_out: CountsPair,
}

/// Outcome counts with the original and the tuned order.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct CountsPair {
    /// With the original order.
    pub before: CountsEntry,
    /// With the tuned order.
    pub after: CountsEntry,
}

/// Runs in which an activity completed, was aborted, did not run.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct CountsEntry {
    /// Completed.
    pub completed: u64,
    /// Aborted.
    pub aborted: u64,
    /// Not run.
    pub not_run: u64,
}

/// A changed priority.
#[derive(Clone, Debug, Serialize)]
pub struct ChangeEntry {
    /// Activity id.
    pub id: String,
    /// Priority in the plan.
    pub priority_before: i64,
    /// Tuned priority.
    pub priority_after: i64,
    /// Why, from the evidence.
    pub why: WhyChangeEntry,
}

/// Why a priority changed, as data and as a sentence.
#[derive(Clone, Debug, Serialize)]
pub struct WhyChangeEntry {
    /// `ahead` (it now comes ahead of `of`), `after` (after `of`) or
    /// `renumbered` (its relative order is unchanged).
    pub moved: &'static str,
    /// The activity it moved past.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub of: Option<String>,
    /// The activity whose losses the move removed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub activity: Option<String>,
    /// Runs of the tuning sample that activity was lost in, originally.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lost_before: Option<u64>,
    /// ... and with the tuned order.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lost_after: Option<u64>,
    /// Its most frequent loss cause originally.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cause: Option<String>,
    /// The culprit most named for that cause.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub culprit: Option<String>,
    /// Runs lost to that cause with the tuned order.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cause_after: Option<u64>,
    /// Runs breaking a limit, originally and tuned.
    pub runs_breaking_limits: (u64, u64),
    /// One sentence for planners.
    pub text: String,
}

/// The search's budget and use.
#[derive(Clone, Debug, Serialize)]
pub struct SearchEntry {
    /// `exact` or `evidence`.
    pub mode: &'static str,
    /// Activities that can move.
    pub movable: usize,
    /// Orders it may score.
    pub budget: u64,
    /// Orders it scored on the tuning sample.
    pub evaluations: u64,
    /// It ended before it was done (budget or cancel).
    pub stopped_early: bool,
    /// `finished`, `budget` or `cancelled`.
    pub stop: &'static str,
}

fn sample(s: Sample) -> SampleEntry {
    SampleEntry {
        seed: s.seed,
        runs: s.runs,
    }
}

fn score(s: &Score) -> ScoreEntry {
    ScoreEntry {
        runs_breaking_limits: s.runs_breaking,
        mandatory_completions: s.mandatory_completed,
        value_completed: s.value.total(),
        order_changes: s.changes,
    }
}

fn counts(c: Counts) -> CountsEntry {
    CountsEntry {
        completed: c.completed,
        aborted: c.aborted,
        not_run: c.not_run,
    }
}

fn signed(x: u64) -> i64 {
    i64::try_from(x).unwrap_or(i64::MAX)
}

fn verdict(plan: &Plan, t: &Tuning) -> VerdictEntry {
    let (o, n) = (&t.held_out_scores.original, &t.held_out_scores.tuned);
    let first_difference = match (&o.value, &n.value) {
        (ValueMeasure::StepOrder(a), ValueMeasure::StepOrder(b)) => a
            .iter()
            .zip(b)
            .zip(&t.original)
            .find(|((x, y), _)| x != y)
            .map(|((&x, &y), &act)| DifferenceEntry {
                activity: plan.activities[act].id.clone(),
                original: x,
                tuned: y,
            }),
        _ => None,
    };
    let more_value_completed = match (o.value.total(), n.value.total()) {
        (Some(a), Some(b)) => Some(b - a),
        _ => None,
    };
    VerdictEntry {
        verdict: match n.cmp(o) {
            std::cmp::Ordering::Greater => "better",
            std::cmp::Ordering::Equal => "same",
            std::cmp::Ordering::Less => "worse",
        },
        no_worse: t.held_out_no_worse(),
        fewer_runs_breaking_limits: signed(o.runs_breaking) - signed(n.runs_breaking),
        more_mandatory_completions: signed(n.mandatory_completed) - signed(o.mandatory_completed),
        more_value_completed,
        first_difference,
    }
}

fn why_entry(plan: &Plan, w: &ChangeWhy) -> WhyChangeEntry {
    let id = |a: usize| plan.activities[a].id.clone();
    let (moved, of) = match w.moved {
        Moved::Ahead { of } => ("ahead", Some(id(of))),
        Moved::After { of } => ("after", Some(id(of))),
        Moved::Renumbered => ("renumbered", None),
    };
    let loss = w.activity.is_some();
    WhyChangeEntry {
        moved,
        of,
        activity: w.activity.map(id),
        lost_before: loss.then_some(w.lost_before),
        lost_after: loss.then_some(w.lost_after),
        cause: w.cause.clone(),
        culprit: w.culprit.map(id),
        cause_after: w.cause.as_ref().map(|_| w.cause_after),
        runs_breaking_limits: (w.breaking_before, w.breaking_after),
        text: change_line(plan, w),
    }
}

/// Builds the tuning document of `plan` (the input plan, as tuned by `t`).
pub fn tuning_document(plan: &Plan, t: &Tuning) -> TuningDoc {
    let measure = match t.tuning_scores.original.value {
        ValueMeasure::Total(_) => "value",
        ValueMeasure::StepOrder(_) => "step_order",
    };
    let activities = plan
        .activities
        .iter()
        .zip(&t.tuned_plan.activities)
        .zip(&t.counts)
        .map(|((a, b), c)| TunedActivityEntry {
            id: a.id.clone(),
            priority_before: a.priority,
            priority_after: b.priority,
            tuning: CountsPair {
                before: counts(c.tuning_before),
                after: counts(c.tuning_after),
            },
            held_out: CountsPair {
                before: counts(c.held_out_before),
                after: counts(c.held_out_after),
            },
        })
        .collect();
    let changes = t
        .changes
        .iter()
        .map(|c| ChangeEntry {
            id: plan.activities[c.activity].id.clone(),
            priority_before: c.before,
            priority_after: c.after,
            why: why_entry(plan, &c.why),
        })
        .collect();
    let edits = t
        .changes
        .iter()
        .map(|c| {
            let mut set = Map::new();
            set.insert("priority".into(), json!(c.after));
            EditEntry {
                target: format!("activity:{}", plan.activities[c.activity].id),
                set,
            }
        })
        .collect();
    TuningDoc {
        format: TUNING_FORMAT,
        plan: t.plan.clone(),
        measure,
        tuning_sample: sample(t.tuning),
        held_out_sample: sample(t.held_out),
        scores: ScoresEntry {
            tuning: PairEntry {
                original: score(&t.tuning_scores.original),
                tuned: score(&t.tuning_scores.tuned),
            },
            held_out: PairEntry {
                original: score(&t.held_out_scores.original),
                tuned: score(&t.held_out_scores.tuned),
            },
        },
        held_out: verdict(plan, t),
        activities,
        changes,
        edits,
        search: SearchEntry {
            mode: t.mode.name(),
            movable: t.movable,
            budget: t.budget,
            evaluations: t.evaluations,
            stopped_early: t.stop != crate::tune::Stop::Finished,
            stop: t.stop.name(),
        },
    }
}

/// The document as pretty JSON (what a command prints).
pub fn tuning_json(plan: &Plan, t: &Tuning) -> String {
    serde_json::to_string_pretty(&tuning_document(plan, t))
        .unwrap_or_else(|e| Value::String(e.to_string()).to_string())
}
