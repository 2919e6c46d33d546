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
        let (i, activity) = edited_activity(plan, target, set)?;
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
        if set.keys().all(|k| LIMIT_SECTIONS.contains(&k.as_str())) {
            let mut out = edited_limits(plan, set)?;
            out.activities = plan.activities.clone();
            return Some(out);
        }
        let mut out = edited_shell(plan, set)?;
        out.activities = plan.activities.clone();
        validate(&out).ok()?;
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

/// The activity that an edit of `target` (`"activity:ID"`) in `plan` gives,
/// read from JSON with its shape checked, and its index; `None` for another
/// target, an unknown id or a shape the format refuses. Whether the plan with
/// it is valid is left to the caller ([`validate`], or
/// `validate::ActivityEdits` for an edit that keeps the id).
pub(crate) fn edited_activity(
    plan: &Plan,
    target: &str,
    set: &serde_json::Map<String, Value>,
) -> Option<(usize, Activity)> {
    let id = target.strip_prefix("activity:")?;
    let i = plan.activities.iter().position(|a| a.id == id)?;
    Some((i, edit_activity(&plan.activities[i], set)?))
}

/// `activity` with the fields of `set` replaced (`null` removes one), read
/// back from JSON with its shape checked; `None` for a shape the format
/// refuses.
pub(crate) fn edit_activity(
    activity: &Activity,
    set: &serde_json::Map<String, Value>,
) -> Option<Activity> {
    let mut v = serde_json::to_value(activity).ok()?;
    let obj = v.as_object_mut()?;
    merge_set(obj, set);
    check_activity_shape(obj, "").ok()?;
    serde_json::from_value(v).ok()
}

/// The plan without its activities that an edit of `"plan"` gives, read from
/// JSON with its shape checked (not validated).
fn edited_shell(plan: &Plan, set: &serde_json::Map<String, Value>) -> Option<Plan> {
    let shell = plan.without_activities();
    let mut v = serde_json::to_value(&shell).ok()?;
    let obj = v.as_object_mut()?;
    merge_set(obj, set);
    check_json_shape(&v).ok()?;
    let mut out: Plan = serde_json::from_value(v).ok()?;
    // A cycle's starting state is not part of the file format: it stays.
    out.cycle = plan.cycle.clone();
    Some(out)
}

/// The plan without its activities that an edit of `"plan"` setting only
/// plan-wide limits ([`LIMIT_SECTIONS`]) gives, when the plan so edited is
/// valid. Only the limit sections are checked: no other check reads them, and
/// the rest of `plan` is valid (the explainer edits the plan it explains).
pub(crate) fn edited_limits(plan: &Plan, set: &serde_json::Map<String, Value>) -> Option<Plan> {
    debug_assert!(
        set.keys().all(|k| LIMIT_SECTIONS.contains(&k.as_str())),
        "an edit of more than the limits"
    );
    let out = edited_shell(plan, set)?;
    validate_limits(&out).ok()?;
    Some(out)
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
