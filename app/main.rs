//! `solscope`: explainable scheduling workstation for rover activity plans.
//!
//! `solscope [PLAN]` opens the desktop app (on the bundled default plan without an
//! argument). Command line: `solscope schedule|explain|execute|montecarlo|flex|check PLAN`, and
//! `solscope screenshot PLAN --out FILE.png` for headless rendering. Invalid input
//! prints a path-named message on standard error, nothing on standard output, and
//! exits with status 2. The commands live in the library's `cli` module.

use std::process::ExitCode;

use clap::Parser;
use solscope::cli::{Cli, Failure};

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return solscope::cli::failure::usage(&e),
    };
    match cli.command {
        Some(command) => solscope::cli::run(command),
        None => run_app(cli.plan.as_deref()),
    }
}

/// Opens the desktop app.
fn run_app(plan: Option<&std::path::Path>) -> ExitCode {
    let app = match solscope::gui::SolscopeApp::opening(plan) {
        Ok(app) => app,
        Err(e) => return Failure::Input(e).report(),
    };
    match solscope::gui::run(app) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => Failure::Output(format!("the window could not be opened: {e}")).report(),
    }
}
