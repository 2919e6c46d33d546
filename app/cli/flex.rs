//! `solscope flex`: the flexible (dispatchable) form of a plan's schedule
//! (solscope.flex/1, or text).

use super::args::FlexArgs;
use super::failure::{Failure, to_json};
use super::{default_name, load};

/// The flexible schedule as JSON, or as text with `--text`.
pub fn run(args: &FlexArgs, limit: usize) -> Result<String, Failure> {
    let loaded = load(&args.plan, limit)?;
    let sched = solscope_engine::schedule(&loaded.plan)?;
    let opts = solscope_engine::FlexOptions {
        free_slack: args.free_slack,
    };
    let flex = solscope_engine::flex_with(&loaded.plan, &sched, opts);
    if args.text {
        Ok(solscope_engine::flex_text(&loaded.plan, &flex))
    } else {
        to_json(&solscope_engine::flex_document(
            &loaded.plan,
            &flex,
            &default_name(&args.plan),
        ))
    }
}
