//! Reading plans: strict parsing with JSON paths, then semantic validation.

use crate::error::{Error, Warning};
use crate::model::Plan;
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
