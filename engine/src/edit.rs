//! Edits in the spec's edit format, applied to a plan and validated again.

use serde_json::Value;

use crate::error::Error;
use crate::load::load_plan;
use crate::model::Plan;

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
