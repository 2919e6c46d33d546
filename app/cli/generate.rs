//! `solscope generate`: a random plan (every feature) on standard output.

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
    let plan = solscope_engine::generate_plan_with(
        args.profile.into(),
        args.activities,
        args.sols,
        args.seed,
    );
    to_json(&plan)
}
