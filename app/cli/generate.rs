//! `solscope generate`: a random plan (every feature) on standard output,
//! optionally with uncertain durations (`--uncertain`).

use super::args::GenerateArgs;
use super::failure::{Failure, to_json};

/// The generated plan as JSON.
pub fn run(args: &GenerateArgs) -> Result<String, Failure> {
    if args.activities > 1_000_000 || args.sols > 1000 {
        return Err(Failure::Input(solscope_engine::Error::invalid(
            "--activities/--sols",
            "at most 1000000 activities and 1000 sols",
        )));
    }
    if args.sols == 0 {
        return Err(Failure::Input(solscope_engine::Error::invalid(
            "--sols",
            "must be at least 1 (got 0)",
        )));
    }
    if let Some(share) = args.uncertain
        && !(0.0..=1.0).contains(&share)
    {
        return Err(Failure::Input(solscope_engine::Error::invalid(
            "--uncertain",
            format!("must be a share from 0 to 1 (got {share})"),
        )));
    }
    let plan = solscope_engine::generate_plan_with(
        args.profile.into(),
        args.activities,
        args.sols,
        args.seed,
    );
    let plan = match args.uncertain {
        Some(share) => solscope_engine::add_duration_models(plan, share, args.seed),
        None => plan,
    };
    to_json(&plan)
}
