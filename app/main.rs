//! `solscope`: explainable scheduling workstation for rover activity plans.
//!
//! Command line: `solscope schedule|explain|check PLAN`. Invalid input prints a
//! path-named message on standard error, nothing on standard output, and exits
//! with status 2.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser, Debug)]
#[command(
    name = "solscope",
    version,
    about = "Explainable scheduling for rover activity plans"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Schedule a plan and print the schedule JSON (solscope.schedule/1).
    Schedule {
        /// The plan file (solscope.plan/1 JSON).
        plan: PathBuf,
    },
    /// Explain why activities failed (all failed or skipped ones, or the one named)
    /// and print the explanation JSON (solscope.explain/1).
    Explain {
        /// The plan file (solscope.plan/1 JSON).
        plan: PathBuf,
        /// Explain this activity (by id), whatever its outcome.
        #[arg(long)]
        activity: Option<String>,
        /// Print planner-facing text instead of JSON.
        #[arg(long)]
        text: bool,
    },
    /// Validate a plan and print its warnings.
    Check {
        /// The plan file (solscope.plan/1 JSON).
        plan: PathBuf,
    },
}

/// Exit status for invalid input.
const EXIT_INVALID: u8 = 2;

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli.command) {
        Ok(text) => {
            let mut out = std::io::stdout().lock();
            if out
                .write_all(text.as_bytes())
                .and_then(|()| out.flush())
                .is_err()
            {
                return ExitCode::FAILURE;
            }
            ExitCode::SUCCESS
        }
        Err(err) => {
            eprintln!("error: {err}");
            ExitCode::from(EXIT_INVALID)
        }
    }
}

/// Runs a command to completion and returns everything it prints on standard output,
/// so that nothing is printed when it fails.
fn run(command: Command) -> Result<String, solscope_engine::Error> {
    match command {
        Command::Schedule { plan } => {
            let loaded = solscope_engine::load_plan_file(&plan)?;
            let schedule = solscope_engine::schedule(&loaded.plan)?;
            let doc = solscope_engine::schedule_document(&loaded, &schedule, &default_name(&plan));
            Ok(format!("{}\n", to_json(&doc)))
        }
        Command::Explain {
            plan,
            activity,
            text,
        } => {
            let loaded = solscope_engine::load_plan_file(&plan)?;
            let schedule = solscope_engine::schedule(&loaded.plan)?;
            let opts = solscope_engine::ExplainOptions {
                activity,
                no_suggestions: false,
            };
            let explanations = solscope_engine::explain(&loaded.plan, &schedule, &opts)?;
            if text {
                Ok(solscope_engine::explain_text(
                    &loaded.plan,
                    &schedule,
                    &explanations,
                ))
            } else {
                let doc = solscope_engine::explain_document(&loaded.plan, &schedule, &explanations);
                Ok(format!("{}\n", to_json(&doc)))
            }
        }
        Command::Check { plan } => {
            let loaded = solscope_engine::load_plan_file(&plan)?;
            let mut out = String::new();
            for w in &loaded.warnings {
                out.push_str(&format!("warning: {w}\n"));
            }
            out.push_str(&format!(
                "ok: {} is a valid plan with {} activities and {} warning(s)\n",
                plan.display(),
                loaded.plan.activities.len(),
                loaded.warnings.len()
            ));
            Ok(out)
        }
    }
}

/// The plan's display name when the file does not give one: the file name.
fn default_name(path: &std::path::Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

fn to_json<T: serde::Serialize>(value: &T) -> String {
    // Serialising plain data structures to a String cannot fail.
    serde_json::to_string_pretty(value).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
}
