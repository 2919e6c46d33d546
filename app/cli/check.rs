//! `solscope check`: validates a plan and prints its warnings, or every error
//! it has.

use super::args::CheckArgs;
use super::failure::Failure;

/// The plan's warnings, one a line, and a last line saying it is valid; an
/// invalid plan fails with its first error, or with `--all-errors` with every
/// error found in one pass ([`solscope_engine::plan_errors`]), led by that one.
pub fn run(args: &CheckArgs, limit: usize) -> Result<String, Failure> {
    let text = solscope_engine::read_plan_text(&args.plan, limit)?;
    let loaded = match solscope_engine::load_plan_limited(&text, limit) {
        Ok(loaded) => loaded,
        // Past the app's limit the text is not read again: the one error.
        Err(first) if !args.all_errors || text.len() > solscope_engine::MAX_PLAN_BYTES => {
            return Err(first.into());
        }
        Err(first) => {
            let mut errors = solscope_engine::plan_errors(&text);
            if errors.first().map(ToString::to_string) != Some(first.to_string()) {
                errors.insert(0, first);
            }
            return Err(Failure::Inputs(errors));
        }
    };
    let mut out = String::new();
    for w in &loaded.warnings {
        out.push_str(&format!("warning: {w}\n"));
    }
    out.push_str(&format!(
        "ok: {} is a valid plan with {} activities and {} warning(s)\n",
        args.plan.display(),
        loaded.plan.activities.len(),
        loaded.warnings.len()
    ));
    Ok(out)
}
