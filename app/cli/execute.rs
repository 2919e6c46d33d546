//! `solscope execute`: one execution of a plan with actual durations
//! (solscope.execution/1).

use super::args::ExecuteArgs;
use super::failure::{Failure, to_json};
use super::{default_name, load};

/// The execution document; with `--write-actuals`, also writes the actual
/// durations used to that file.
pub fn run(args: &ExecuteArgs, limit: usize) -> Result<String, Failure> {
    let loaded = load(&args.plan, limit)?;
    let actuals = match (&args.actuals, args.sample) {
        (Some(path), _) => {
            let text = solscope_engine::read_plan_text(path, limit)?;
            solscope_engine::load_actuals(&text, &loaded.plan).map_err(|e| match e {
                solscope_engine::Error::Invalid { path: p, reason } => {
                    solscope_engine::Error::invalid(format!("{}: {p}", path.display()), reason)
                }
                other => other,
            })?
        }
        (None, Some(seed)) => solscope_engine::sample_run(&loaded.plan, seed, args.run),
        (None, None) => solscope_engine::Actuals::nominal(),
    };
    let options = solscope_engine::ExecuteOptions {
        policy: args.policy.into(),
    };
    let execution = solscope_engine::execute_with(&loaded.plan, &actuals, options)?;
    let losses = solscope_engine::losses(&loaded.plan, &execution)?;
    let doc = solscope_engine::execution_document(
        &loaded.plan,
        &execution,
        &actuals,
        &losses,
        &default_name(&args.plan),
    );
    let out = to_json(&doc)?;
    if let Some(path) = &args.write_actuals {
        let text = to_json(&actuals)?;
        crate::write::write_whole(path, text.as_bytes())
            .map_err(|e| Failure::Output(format!("{}: could not write: {e}", path.display())))?;
    }
    Ok(out)
}
