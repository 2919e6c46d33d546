//! Semantic validation of plans (beyond what serde checks), with JSON paths.

use crate::error::{Error, Warning};
use crate::model::Plan;

/// Checks a parsed plan; returns its warnings or the first error.
pub fn validate(plan: &Plan) -> Result<Vec<Warning>, Error> {
    let _ = plan;
    Ok(Vec::new())
}
