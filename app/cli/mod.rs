//! The command line: `solscope schedule|explain|execute|montecarlo|flex|tune|check|generate|screenshot`.
//!
//! [`args`] holds every flag (the clap types); [`run`] hands a parsed command to its
//! module, one per command, and ends it through [`failure`]: a command makes its
//! whole output first and prints it only once it has succeeded, so that a failure
//! prints nothing on standard output (`explain` streams its output, once the plan
//! has loaded and scheduled), or with `--output FILE` writes it to that file,
//! whole or not at all ([`crate::write`]). Invalid input prints a path-named
//! message on standard error and exits with status 2; an output that could not
//! be made or written exits with status 1 (a reader that stopped early: status
//! 0, quietly).

pub mod args;
mod bounds;
mod check;
mod execute;
mod explain;
pub mod failure;
mod flex;
mod generate;
mod montecarlo;
mod progress;
mod schedule;
mod screenshot;
mod tune;

use std::path::Path;
use std::process::ExitCode;

pub use args::{Cli, Command};
pub use failure::{EXIT_INVALID, Failure};

/// Runs a command to completion: its output on standard output, or a message on
/// standard error; returns the exit status.
pub fn run(command: Command) -> ExitCode {
    match dispatch(command) {
        Ok(code) => code,
        Err(failure) => failure.report(),
    }
}

/// Runs a command; the commands that print one output make it whole before it
/// is printed, or written to `--output FILE` (whole or not at all).
fn dispatch(command: Command) -> Result<ExitCode, Failure> {
    let output = command.output().map(Path::to_path_buf);
    if let Some(path) = &output {
        // Checked first, so that a long run does not end in nothing.
        crate::write::check_target(path).map_err(|e| unwritable(path, &e))?;
    }
    let text = match command {
        Command::Screenshot(args) => return screenshot::run(&args),
        Command::Explain(args) => {
            explain::run(&args, args.input.bytes()?, output.as_deref())?;
            return Ok(ExitCode::SUCCESS);
        }
        Command::Schedule(args) => schedule::run(&args, args.input.bytes()?)?,
        Command::Execute(args) => execute::run(&args, args.input.bytes()?)?,
        Command::Montecarlo(args) => montecarlo::run(&args)?,
        Command::Flex(args) => flex::run(&args, args.input.bytes()?)?,
        Command::Tune(args) => tune::run(&args, args.input.bytes()?)?,
        Command::Check(args) => check::run(&args, args.input.bytes()?)?,
        Command::Generate(args) => generate::run(&args)?,
    };
    match &output {
        Some(path) => {
            crate::write::write_whole(path, text.as_bytes()).map_err(|e| unwritable(path, &e))?
        }
        None => failure::print(&text)?,
    }
    Ok(ExitCode::SUCCESS)
}

/// A file that could not be written (exit status 1), named.
fn unwritable(path: &Path, e: &std::io::Error) -> Failure {
    Failure::Output(format!("{}: could not write: {e}", path.display()))
}

/// Reads and loads a plan file of at most `limit` bytes, within the command
/// line's limit on the duration searches ([`bounds::heated_search`]).
fn load(plan: &Path, limit: usize) -> Result<solscope_engine::LoadedPlan, solscope_engine::Error> {
    let text = solscope_engine::read_plan_text(plan, limit)?;
    let loaded = solscope_engine::load_plan_limited(&text, limit)?;
    bounds::heated_search(&loaded.plan)?;
    Ok(loaded)
}

/// The plan's display name when the file does not give one: the file name.
fn default_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}
