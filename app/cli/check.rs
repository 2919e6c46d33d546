//! `solscope check`: validates a plan and prints its warnings.

use super::args::CheckArgs;
use super::failure::Failure;
use super::load;

/// The plan's warnings, one a line, and a last line saying it is valid.
pub fn run(args: &CheckArgs, limit: usize) -> Result<String, Failure> {
    let loaded = load(&args.plan, limit)?;
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
