//! `solscope tune`: the priorities that complete more of what matters when
//! durations vary (solscope.tuning/1), and with `--write-plan` the tuned plan,
//! written whole or not at all. Ctrl+C stops the search; the best order found so
//! far is still confirmed and printed, marked as stopped early.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use serde_json::Value;
use solscope_engine::{Error, Plan, TuneOptions, Tuning};

use super::args::TuneArgs;
use super::failure::Failure;
use super::progress::Progress;

/// Set by Ctrl+C: the search stops at its next batch.
static CANCEL: AtomicBool = AtomicBool::new(false);

/// The tuning document; with `--write-plan`, also writes the tuned plan.
pub fn run(args: &TuneArgs, limit: usize) -> Result<String, Failure> {
    let text = solscope_engine::read_plan_text(&args.plan, limit)?;
    let plan = solscope_engine::load_plan_limited(&text, limit)?.plan;
    super::bounds::heated_search(&plan)?;
    if let Some(target) = &args.write_plan {
        check_target(target)?;
    }
    let cancel = catch_interrupt().then_some(&CANCEL);
    let progress = Progress::new(args.budget);
    let tick = |done: u64, _: &solscope_engine::Score| progress.set_position(done);
    let options = TuneOptions {
        runs: args.runs,
        seed: args.seed,
        confirm_runs: args.confirm_runs,
        confirm_seed: args.confirm_seed,
        budget: args.budget,
        pinned: args.pin.clone(),
        cancel,
        progress: Some(&tick),
    };
    let tuning = solscope_engine::tune(&plan, &options);
    progress.finish();
    let tuning = tuning.map_err(flag_named)?;
    if tuning.movable == 0 {
        return Err(Failure::Input(Error::invalid(
            args.plan.display().to_string(),
            "no activity can move (every one is pinned, alone, or fixed in the step order \
             by its dependencies): there is nothing to tune",
        )));
    }
    let mut out = solscope_engine::tuning_json(&plan, &tuning);
    out.push('\n');
    if let Some(target) = &args.write_plan {
        let tuned = tuned_plan_text(&text, &plan, &tuning, limit)?;
        crate::write::write_whole(target, tuned.as_bytes())
            .map_err(|e| Failure::Output(format!("{}: could not write: {e}", target.display())))?;
    }
    Ok(out)
}

/// Installs the Ctrl+C handler (once per process): the first interrupt stops
/// the search, a second one ends the process. Whether it is installed.
fn catch_interrupt() -> bool {
    ctrlc::set_handler(|| {
        if CANCEL.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
    })
    .is_ok()
}

/// The engine's option names as the command's flags.
fn flag_named(e: Error) -> Error {
    match e {
        Error::Invalid { path, reason } => {
            let flag = match path.as_str() {
                "runs" => "--runs".to_string(),
                "confirm_runs" => "--confirm-runs".to_string(),
                "confirm_seed" => "--confirm-seed".to_string(),
                "budget" => "--budget".to_string(),
                p if p.starts_with("pinned[") => "--pin".to_string(),
                _ => path,
            };
            Error::Invalid { path: flag, reason }
        }
        other => other,
    }
}

/// The file `--write-plan` writes must be writable as far as can be told
/// before the search starts, so that a long search does not end in nothing.
fn check_target(target: &Path) -> Result<(), Failure> {
    crate::write::check_target(target)
        .map_err(|e| Failure::Output(format!("{}: could not write: {e}", target.display())))
}

/// The input plan's JSON with the tuning's priorities set, and nothing else
/// changed; checked to load with exactly the tuned priorities.
fn tuned_plan_text(
    text: &str,
    plan: &Plan,
    tuning: &Tuning,
    limit: usize,
) -> Result<String, Failure> {
    let broken = |why: String| Failure::Output(format!("the tuned plan could not be made: {why}"));
    let mut value: Value = serde_json::from_str(text).map_err(|e| broken(e.to_string()))?;
    let activities = value
        .get_mut("activities")
        .and_then(Value::as_array_mut)
        .ok_or_else(|| broken("the plan has no activities array".into()))?;
    for change in &tuning.changes {
        let id = &plan.activities[change.activity].id;
        let activity = activities
            .iter_mut()
            .find(|a| a.get("id").and_then(Value::as_str) == Some(id.as_str()))
            .and_then(Value::as_object_mut)
            .ok_or_else(|| broken(format!("no activity \"{id}\" in the file")))?;
        activity.insert("priority".into(), Value::from(change.after));
    }
    let mut out = serde_json::to_string_pretty(&value).map_err(|e| broken(e.to_string()))?;
    out.push('\n');
    let reloaded = solscope_engine::load_plan_limited(&out, limit)
        .map_err(|e| broken(e.to_string()))?
        .plan;
    let priorities = |p: &Plan| p.activities.iter().map(|a| a.priority).collect::<Vec<_>>();
    if priorities(&reloaded) != priorities(&tuning.tuned_plan) {
        return Err(broken("its priorities are not the tuned ones".into()));
    }
    Ok(out)
}
