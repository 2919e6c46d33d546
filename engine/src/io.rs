//! Reading plans and writing schedule documents.

use crate::error::{Error, Warning};
use crate::model::Plan;
use crate::validate::validate;

/// A plan that passed strict parsing and semantic validation, with its warnings.
#[derive(Clone, Debug)]
pub struct LoadedPlan {
    /// The plan.
    pub plan: Plan,
    /// Non-fatal remarks, in path order.
    pub warnings: Vec<Warning>,
}

/// Parses and validates a plan from JSON text. Errors name the JSON path.
pub fn load_plan(text: &str) -> Result<LoadedPlan, Error> {
    let de = &mut serde_json::Deserializer::from_str(text);
    let plan: Plan = serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        let path = if path == "." { "$".to_string() } else { path };
        Error::invalid(path, inner.to_string())
    })?;
    let warnings = validate(&plan)?;
    Ok(LoadedPlan { plan, warnings })
}

/// Reads and loads a plan file.
pub fn load_plan_file(path: &std::path::Path) -> Result<LoadedPlan, Error> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
        path: path.display().to_string(),
        source,
    })?;
    load_plan(&text)
}

/// `solscope.schedule/1` document; see the spec. Built by [`schedule_document`].
#[derive(Clone, Debug, serde::Serialize)]
pub struct ScheduleDoc {
    /// Always `solscope.schedule/1`.
    pub format: &'static str,
    /// Plan name.
    pub plan: String,
}

/// Builds the schedule document of a run.
pub fn schedule_document(
    loaded: &LoadedPlan,
    schedule: &crate::scheduler::Schedule,
    default_name: &str,
) -> ScheduleDoc {
    let _ = schedule;
    ScheduleDoc {
        format: "solscope.schedule/1",
        plan: loaded
            .plan
            .name
            .clone()
            .unwrap_or_else(|| default_name.to_string()),
    }
}
