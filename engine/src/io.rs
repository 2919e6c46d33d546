//! Reading plans and writing schedule documents.

use serde::Serialize;
use serde_json::{Value, json};

use crate::error::{Error, Warning};
use crate::explain::{Explanation, ReasonRange, explanation_notes, suggestion_line};
use crate::model::Plan;
use crate::scheduler::{
    BIT_PER_MBIT, Generated, GeneratedKind, MJ_PER_WH, MW_PER_W, Outcome, Phase2Reason, Schedule,
};
use crate::validate::{check_json_shape, validate};

/// A plan that passed strict parsing and semantic validation, with its warnings.
#[derive(Clone, Debug)]
pub struct LoadedPlan {
    /// The plan.
    pub plan: Plan,
    /// Non-fatal remarks, in path order.
    pub warnings: Vec<Warning>,
}

/// Largest plan accepted (bytes): far above any real plan (a generated
/// 10,000-activity plan is about 4 MB), and a bound on the memory loading takes.
pub const MAX_PLAN_BYTES: usize = 32 * 1024 * 1024;

/// Parses and validates a plan from JSON text. Errors name the JSON path.
pub fn load_plan(text: &str) -> Result<LoadedPlan, Error> {
    if text.len() > MAX_PLAN_BYTES {
        return Err(Error::invalid(
            "$",
            format!(
                "the plan is {} bytes; plans are limited to {MAX_PLAN_BYTES} bytes",
                text.len()
            ),
        ));
    }
    let de = &mut serde_json::Deserializer::from_str(text);
    let typed: Result<Plan, _> = serde_path_to_error::deserialize(&mut *de);
    if typed.is_ok() {
        de.end()
            .map_err(|e| Error::invalid("$", format!("unexpected text after the plan: {e}")))?;
    }
    // serde's derived impls also accept arrays for structs (fields by position);
    // the format does not, and the shape error explains a failed parse better.
    if let Ok(doc) = serde_json::from_str::<serde_json::Value>(text) {
        check_json_shape(&doc)?;
    }
    let plan = typed.map_err(|e| {
        // Drop trailing unknown segments (`activities[3].?` when the input ends
        // inside an object key); the root is `$`.
        let path = e.path().to_string();
        let mut path = path.as_str();
        while let Some(p) = path.strip_suffix('?') {
            path = p.strip_suffix('.').unwrap_or(p);
        }
        let path = if path.is_empty() || path == "." {
            "$"
        } else {
            path
        };
        Error::invalid(path, e.into_inner().to_string())
    })?;
    let warnings = validate(&plan)?;
    Ok(LoadedPlan { plan, warnings })
}

/// Applies an edit in the spec's format (`target` is `"plan"` or `"activity:ID"`;
/// `set` replaces those top-level fields of the target, `null` removes one) and
/// validates the result. Errors name the JSON path in the edited plan.
pub fn apply_edit(
    plan: &Plan,
    target: &str,
    set: &serde_json::Map<String, Value>,
) -> Result<Plan, Error> {
    let mut v = serde_json::to_value(plan).map_err(|e| Error::invalid("$", e.to_string()))?;
    let obj = if target == "plan" {
        v.as_object_mut()
            .ok_or_else(|| Error::invalid("$", "plan is not an object"))?
    } else {
        let id = target
            .strip_prefix("activity:")
            .ok_or_else(|| Error::invalid("edit.target", format!("unknown target \"{target}\"")))?;
        v.get_mut("activities")
            .and_then(Value::as_array_mut)
            .and_then(|acts| {
                acts.iter_mut()
                    .find(|a| a.get("id").and_then(Value::as_str) == Some(id))
            })
            .and_then(Value::as_object_mut)
            .ok_or_else(|| Error::UnknownActivity(id.to_string()))?
    };
    for (k, x) in set {
        if x.is_null() {
            obj.remove(k);
        } else {
            obj.insert(k.clone(), x.clone());
        }
    }
    load_plan(&v.to_string()).map(|loaded| loaded.plan)
}

/// Reads and loads a plan file.
pub fn load_plan_file(path: &std::path::Path) -> Result<LoadedPlan, Error> {
    let io = |source| Error::Io {
        path: path.display().to_string(),
        source,
    };
    let size = std::fs::metadata(path).map_err(io)?.len();
    if size > MAX_PLAN_BYTES as u64 {
        return Err(Error::invalid(
            "$",
            format!(
                "{} is {size} bytes; plans are limited to {MAX_PLAN_BYTES} bytes",
                path.display()
            ),
        ));
    }
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
        path: path.display().to_string(),
        source,
    })?;
    load_plan(&text)
}

/// `solscope.schedule/1` document; see the spec. Built by [`schedule_document`].
#[derive(Clone, Debug, Serialize)]
pub struct ScheduleDoc {
    /// Always `solscope.schedule/1`.
    pub format: &'static str,
    /// Plan name.
    pub plan: String,
    /// Every activity, in step order.
    pub activities: Vec<ActivityEntry>,
    /// Generated activities alive at the end: awake periods by start, then heating
    /// by zone and start.
    pub generated: Vec<GeneratedEntry>,
    /// Loader warnings, as `path: message`.
    pub warnings: Vec<String>,
    /// Resource profiles as breakpoints.
    pub profiles: Profiles,
}

/// One activity's outcome in a schedule document.
#[derive(Clone, Debug, Serialize)]
pub struct ActivityEntry {
    /// Activity id.
    pub id: String,
    /// `scheduled`, `failed` or `skipped`.
    pub status: &'static str,
    /// Its step.
    pub step: usize,
    /// Start, when scheduled.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub start: Option<i64>,
    /// End, when scheduled.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub end: Option<i64>,
}

/// One generated activity in a schedule document.
#[derive(Clone, Debug, Serialize)]
pub struct GeneratedEntry {
    /// `awake`, `preheat` or `maintenance`.
    pub kind: &'static str,
    /// Zone name (heating only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub zone: Option<String>,
    /// The activity heated for (heating only).
    #[serde(rename = "for", skip_serializing_if = "Option::is_none")]
    pub for_activity: Option<String>,
    /// Start.
    pub start: i64,
    /// End.
    pub end: i64,
    /// Heater power in W (heating only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub power: Option<f64>,
    /// The step that created it (solscope addition).
    pub step: usize,
}

/// Resource profiles: `[t, value]` breakpoints.
#[derive(Clone, Debug, Serialize)]
pub struct Profiles {
    /// State of charge (Wh), linear between points.
    pub soc: Vec<(i64, f64)>,
    /// Total peak power (W), constant from each point to the next.
    pub peak_power: Vec<(i64, f64)>,
    /// Data volume (Mbit), linear between points.
    pub data_volume: Vec<(i64, f64)>,
}

/// Builds the schedule document of a run.
pub fn schedule_document(
    loaded: &LoadedPlan,
    schedule: &Schedule,
    default_name: &str,
) -> ScheduleDoc {
    let plan = &loaded.plan;
    let pb = &schedule.problem;
    let activities = schedule
        .steps
        .iter()
        .map(|st| {
            let (status, start, end) = match st.outcome {
                Outcome::Scheduled { start, end } => ("scheduled", Some(start), Some(end)),
                Outcome::Failed(_) => ("failed", None, None),
                Outcome::Skipped { .. } => ("skipped", None, None),
            };
            ActivityEntry {
                id: plan.activities[st.activity].id.clone(),
                status,
                step: st.step,
                start,
                end,
            }
        })
        .collect();
    let last = schedule.steps.len();
    let mut alive: Vec<&Generated> = schedule.generated_after(last).collect();
    let key = |g: &Generated| match g.kind {
        GeneratedKind::Awake => (0, 0, g.start, 0, 0),
        GeneratedKind::Preheat { zone, activity } => (1, zone, g.start, 0, activity),
        GeneratedKind::Maintenance { zone, activity } => (1, zone, g.start, 1, activity),
    };
    alive.sort_by_key(|g| key(g));
    let generated = alive
        .into_iter()
        .map(|g| {
            let (kind, heat) = match g.kind {
                GeneratedKind::Awake => ("awake", None),
                GeneratedKind::Preheat { zone, activity } => ("preheat", Some((zone, activity))),
                GeneratedKind::Maintenance { zone, activity } => {
                    ("maintenance", Some((zone, activity)))
                }
            };
            GeneratedEntry {
                kind,
                zone: heat.map(|(z, _)| pb.zone_names[z].clone()),
                for_activity: heat.map(|(_, a)| plan.activities[a].id.clone()),
                start: g.start,
                end: g.end,
                power: heat.map(|_| g.power_mw as f64 / MW_PER_W),
                step: g.added_at,
            }
        })
        .collect();
    let state = schedule.state_after(last);
    let soc = state
        .soc
        .profile()
        .into_iter()
        .map(|(t, l)| (t, l as f64 / MJ_PER_WH))
        .collect();
    let data_volume = state
        .data
        .profile()
        .into_iter()
        .map(|(t, l)| (t, -l as f64 / BIT_PER_MBIT + 0.0))
        .collect();
    let mut peak_power: Vec<(i64, f64)> = state
        .peak
        .points()
        .iter()
        .map(|&(t, v)| (t, v as f64 / MW_PER_W))
        .collect();
    if let Some(&(_, v)) = peak_power.last() {
        peak_power.push((pb.h1, v));
    }
    ScheduleDoc {
        format: "solscope.schedule/1",
        plan: plan
            .name
            .clone()
            .unwrap_or_else(|| default_name.to_string()),
        activities,
        generated,
        warnings: loaded.warnings.iter().map(ToString::to_string).collect(),
        profiles: Profiles {
            soc,
            peak_power,
            data_volume,
        },
    }
}

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

fn reason_value(pb: &crate::scheduler::Problem, r: &ReasonRange) -> Value {
    let mut v =
        json!({ "kind": r.reason.kind(), "start": r.first, "end": r.last, "duration": r.duration });
    let extra = match &r.reason {
        Phase2Reason::MinSoc { at, soc_mj } => {
            json!({ "at": at, "soc": *soc_mj as f64 / MJ_PER_WH })
        }
        Phase2Reason::HandoverSoc { soc_mj } => json!({ "soc": *soc_mj as f64 / MJ_PER_WH }),
        Phase2Reason::MaxPeakPower { at, peak_mw } => {
            json!({ "at": at, "peak": *peak_mw as f64 / MW_PER_W })
        }
        Phase2Reason::PreheatOutsidePlan {
            zone,
            preheat_start,
        }
        | Phase2Reason::PreheatOperability {
            zone,
            preheat_start,
        } => {
            json!({ "zone": pb.zone_names[*zone], "preheat_start": preheat_start })
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
    let pb = &schedule.problem;
    let id = |a: usize| plan.activities[a].id.clone();
    let entries = explanations
        .iter()
        .map(|ex| ExplanationEntry {
            activity: id(ex.activity),
            status: match ex.outcome {
                Outcome::Scheduled { .. } => "scheduled",
                Outcome::Failed(_) => "failed",
                Outcome::Skipped { .. } => "skipped",
            },
            step: ex.step,
            failure_step: ex.failure_step,
            phase: ex.phase.map(|p| p.name()),
            conflicts: ex
                .conflicts
                .iter()
                .map(|c| c.iter().map(|x| x.name()).collect())
                .collect(),
            reasons: ex.reasons.iter().map(|r| reason_value(pb, r)).collect(),
            culprits: ex
                .culprits
                .iter()
                .map(|c| CulpritEntry {
                    activity: id(c.activity),
                    category: c.category,
                    step: c.step,
                })
                .collect(),
            notes: explanation_notes(plan, pb, ex),
            suggestions: ex
                .suggestions
                .iter()
                .map(|s| SuggestionEntry {
                    description: s.description.clone(),
                    edit: EditEntry {
                        target: s.target.clone(),
                        set: s.set.clone(),
                    },
                    side_effects: s.side_effects.iter().map(|&a| id(a)).collect(),
                })
                .collect(),
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
        })
        .collect();
    ExplainDoc {
        format: "solscope.explain/1",
        explanations: entries,
    }
}

/// Planner-facing text for a set of explanations.
pub fn explain_text(plan: &Plan, schedule: &Schedule, explanations: &[Explanation]) -> String {
    let pb = &schedule.problem;
    let mut out = String::new();
    for ex in explanations {
        let a = &plan.activities[ex.activity];
        out.push_str(&format!(
            "== {} ({}), step {}\n",
            a.display_name(),
            a.id,
            ex.step
        ));
        for n in explanation_notes(plan, pb, ex) {
            out.push_str(&format!("  {n}\n"));
        }
        for (i, s) in ex.suggestions.iter().enumerate() {
            out.push_str(&format!(
                "  suggestion {}: {}\n",
                i + 1,
                suggestion_line(plan, s)
            ));
        }
        out.push('\n');
    }
    out
}
