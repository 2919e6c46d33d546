//! The `solscope.explain/1` document.

use serde::Serialize;
use serde_json::{Value, json};

use crate::explain::{Explanation, ReasonRange, explanation_notes};
use crate::model::Plan;
use crate::scheduler::{Phase2Reason, Problem, Schedule};
use crate::units::{watts, wh};

/// `solscope.explain/1` document; see the spec and docs/semantics.md for additions.
#[derive(Clone, Debug, Serialize)]
pub struct ExplainDoc {
    /// Always `solscope.explain/1`.
    pub format: &'static str,
    /// One entry per explained activity, in step order.
    pub explanations: Vec<ExplanationEntry>,
}

/// One explanation in the document (fields in the spec's order, then additions).
#[derive(Clone, Debug, Serialize)]
pub struct ExplanationEntry {
    /// Activity id.
    pub activity: String,
    /// `scheduled`, `failed` or `skipped`.
    pub status: &'static str,
    /// Its step.
    pub step: usize,
    /// Earliest failing step (null when scheduled).
    pub failure_step: Option<usize>,
    /// Failure phase (null when scheduled).
    pub phase: Option<&'static str>,
    /// Minimal conflicting category sets.
    pub conflicts: Vec<Vec<&'static str>>,
    /// Phase-2 failures by range of starts.
    pub reasons: Vec<Value>,
    /// Placed activities to blame.
    pub culprits: Vec<CulpritEntry>,
    /// Plain-language notes.
    pub notes: Vec<String>,
    /// Verified suggestions.
    pub suggestions: Vec<SuggestionEntry>,
    /// Duration the intervals are for.
    pub duration: i64,
    /// Valid starts per category (`[lo, hi]`, inclusive).
    pub valid_intervals: serde_json::Map<String, Value>,
    /// Their intersection within the windows.
    pub intersection: Vec<[i64; 2]>,
    /// Minimal relaxations with a witness start.
    pub relaxations: Vec<RelaxationEntry>,
    /// When no single suggestion works: two edits that together make the
    /// activity schedule (verified), if a pair tried does. Absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub together: Option<Vec<SuggestionEntry>>,
}

/// A culprit in the document.
#[derive(Clone, Debug, Serialize)]
pub struct CulpritEntry {
    /// Activity id.
    pub activity: String,
    /// Category or reason kind.
    pub category: &'static str,
    /// The step that placed it.
    pub step: usize,
}

/// A suggestion in the document.
#[derive(Clone, Debug, Serialize)]
pub struct SuggestionEntry {
    /// Plain-language description.
    pub description: String,
    /// The edit.
    pub edit: EditEntry,
    /// Ids of activities that newly fail with the edit.
    pub side_effects: Vec<String>,
}

/// An edit: replace top-level fields of the target object.
#[derive(Clone, Debug, Serialize)]
pub struct EditEntry {
    /// `plan` or `activity:ID`.
    pub target: String,
    /// The replacement fields (`null` removes a field).
    pub set: serde_json::Map<String, Value>,
}

/// A relaxation in the document.
#[derive(Clone, Debug, Serialize)]
pub struct RelaxationEntry {
    /// Categories to relax.
    pub categories: Vec<&'static str>,
    /// A start that only they block.
    pub witness: i64,
}

fn reason_value(problem: &Problem, r: &ReasonRange) -> Value {
    let mut v = json!({ "kind": r.reason.kind().name(), "start": r.first, "end": r.last, "duration": r.duration });
    let extra = match &r.reason {
        Phase2Reason::MinSoc { at, soc_mj } => {
            json!({ "at": at, "soc": wh(i128::from(*soc_mj)) })
        }
        Phase2Reason::HandoverSoc { soc_mj } => json!({ "soc": wh(i128::from(*soc_mj)) }),
        Phase2Reason::MaxPeakPower { at, peak_mw } => {
            json!({ "at": at, "peak": watts(*peak_mw) })
        }
        Phase2Reason::PreheatOutsidePlan {
            zone,
            preheat_start,
        }
        | Phase2Reason::PreheatOperability {
            zone,
            preheat_start,
        } => {
            json!({ "zone": problem.zone_names[*zone], "preheat_start": preheat_start })
        }
        Phase2Reason::ForcedSleep { .. }
        | Phase2Reason::MinSleep { .. }
        | Phase2Reason::MinAwake { .. } => json!({}),
    };
    if let (Some(o), Some(e)) = (v.as_object_mut(), extra.as_object()) {
        o.extend(e.clone());
    }
    v
}

/// Builds the explanation document.
pub fn explain_document(
    plan: &Plan,
    schedule: &Schedule,
    explanations: &[Explanation],
) -> ExplainDoc {
    ExplainDoc {
        format: "solscope.explain/1",
        explanations: explanations
            .iter()
            .map(|ex| explanation_entry(plan, schedule, ex))
            .collect(),
    }
}

/// One explanation as the document lists it (for a caller that writes the
/// document one explanation at a time).
pub fn explanation_entry(plan: &Plan, schedule: &Schedule, ex: &Explanation) -> ExplanationEntry {
    let problem = &schedule.problem;
    let id = |a: usize| plan.activities[a].id.clone();
    let entry = |s: &crate::explain::Suggestion| SuggestionEntry {
        description: s.description.clone(),
        edit: EditEntry {
            target: s.target.clone(),
            set: s.set.clone(),
        },
        side_effects: s.side_effects.iter().map(|&a| id(a)).collect(),
    };
    {
        ExplanationEntry {
            activity: id(ex.activity),
            status: ex.outcome.status(),
            step: ex.step,
            failure_step: ex.failure_step,
            phase: ex.phase.map(|p| p.name()),
            conflicts: ex
                .conflicts
                .iter()
                .map(|c| c.iter().map(|x| x.name()).collect())
                .collect(),
            reasons: ex
                .reasons
                .iter()
                .map(|r| reason_value(problem, r))
                .collect(),
            culprits: ex
                .culprits
                .iter()
                .map(|c| CulpritEntry {
                    activity: id(c.activity),
                    category: c.blame.name(),
                    step: c.step,
                })
                .collect(),
            notes: explanation_notes(plan, problem, ex),
            suggestions: ex.suggestions.iter().map(entry).collect(),
            together: ex
                .together
                .as_ref()
                .filter(|pair| !pair.is_empty())
                .map(|pair| pair.iter().map(entry).collect()),
            duration: ex.duration,
            valid_intervals: ex
                .categories
                .iter()
                .map(|c| {
                    let v: Vec<[i64; 2]> =
                        c.valid.intervals().iter().map(|i| [i.lo, i.hi]).collect();
                    (c.category.name().to_string(), json!(v))
                })
                .collect(),
            intersection: ex
                .intersection
                .intervals()
                .iter()
                .map(|i| [i.lo, i.hi])
                .collect(),
            relaxations: ex
                .relaxations
                .iter()
                .map(|r| RelaxationEntry {
                    categories: r.categories.iter().map(|c| c.name()).collect(),
                    witness: r.witness,
                })
                .collect(),
        }
    }
}
