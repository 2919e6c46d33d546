//! Edits in the spec's edit format, applied to a plan and validated again.

use serde_json::Value;

use crate::error::Error;
use crate::load::load_plan;
use crate::model::{Activity, Plan};
use crate::validate::{
    LIMIT_SECTIONS, check_activity_shape, check_json_shape, validate, validate_limits,
};

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
    merge_set(obj, set);
    let mut out = load_plan(&v.to_string())?.plan;
    // A cycle's starting state is not part of the file format: it stays.
    out.cycle = plan.cycle.clone();
    Ok(out)
}

/// [`apply_edit`] for the explainer's own candidate edits of a valid `plan`, where
/// only whether the edit gives a valid plan matters, not why not: an edit re-reads
/// only what it changes from JSON (one activity, or the plan without its
/// activities) and validates the plan (only the edited limit sections when the
/// edit sets nothing else: no other check reads them), rather than writing and
/// re-reading the whole plan. Debug builds check the result against
/// [`apply_edit`].
pub(crate) fn edited(
    plan: &Plan,
    target: &str,
    set: &serde_json::Map<String, Value>,
) -> Option<Plan> {
    let quick = || -> Option<Plan> {
        let id = target.strip_prefix("activity:")?;
        let i = plan.activities.iter().position(|a| a.id == id)?;
        let mut v = serde_json::to_value(&plan.activities[i]).ok()?;
        let obj = v.as_object_mut()?;
        merge_set(obj, set);
        check_activity_shape(obj, "").ok()?;
        let activity: Activity = serde_json::from_value(v).ok()?;
        let mut out = plan.clone();
        out.activities[i] = activity;
        validate(&out).ok()?;
        Some(out)
    };
    // An edit of plan-wide fields re-reads the plan without its activities.
    let quick_plan = || -> Option<Plan> {
        if set.contains_key("activities") {
            return apply_edit(plan, target, set).ok();
        }
        let shell = plan.without_activities();
        let mut v = serde_json::to_value(&shell).ok()?;
        let obj = v.as_object_mut()?;
        merge_set(obj, set);
        check_json_shape(&v).ok()?;
        let mut out: Plan = serde_json::from_value(v).ok()?;
        out.activities = plan.activities.clone();
        // A cycle's starting state is not part of the file format: it stays.
        out.cycle = plan.cycle.clone();
        if set.keys().all(|k| LIMIT_SECTIONS.contains(&k.as_str())) {
            // Only limits changed, and the rest was valid (the explainer edits
            // the plan it explains, which is valid).
            validate_limits(&out).ok()?;
        } else {
            validate(&out).ok()?;
        }
        Some(out)
    };
    let out = if target == "plan" {
        quick_plan()
    } else {
        quick()
    };
    debug_assert_eq!(
        out,
        apply_edit(plan, target, set).ok(),
        "the quick edit disagrees with apply_edit"
    );
    out
}

/// The spec's `set`: each field replaces the object's, and `null` removes it.
fn merge_set(obj: &mut serde_json::Map<String, Value>, set: &serde_json::Map<String, Value>) {
    for (k, x) in set {
        if x.is_null() {
            obj.remove(k);
        } else {
            obj.insert(k.clone(), x.clone());
        }
    }
}
