//! How a command ends: what it prints on standard output, or why it printed
//! nothing, as an exit status and one line on standard error.

use std::io::Write;
use std::process::ExitCode;

/// Exit status for invalid input.
pub const EXIT_INVALID: u8 = 2;

/// Why a command printed nothing (or stopped printing).
#[derive(Debug)]
pub enum Failure {
    /// The input is invalid (exit status 2).
    Input(solscope_engine::Error),
    /// The input is invalid in each of these ways (exit status 2; one line
    /// each, the first the one [`Failure::Input`] would give).
    Inputs(Vec<solscope_engine::Error>),
    /// The output could not be made (exit status 1).
    Output(String),
    /// Standard output could not be written (exit status 1, said on standard
    /// error; a reader that stopped early is no failure: exit status 0, nothing
    /// said).
    Stdout(std::io::Error),
}

impl From<solscope_engine::Error> for Failure {
    fn from(e: solscope_engine::Error) -> Self {
        Failure::Input(e)
    }
}

impl Failure {
    /// Says what went wrong on standard error and gives the exit status.
    pub fn report(self) -> ExitCode {
        match self {
            Failure::Input(err) => {
                say(&format!("error: {err}"));
                ExitCode::from(EXIT_INVALID)
            }
            Failure::Inputs(errors) => {
                for err in errors {
                    say(&format!("error: {err}"));
                }
                ExitCode::from(EXIT_INVALID)
            }
            Failure::Output(what) => {
                say(&format!("error: {what}"));
                ExitCode::FAILURE
            }
            // A reader that stopped early (`| head`) wants no more: the output
            // ends quietly, as when `head` closes any tool's output.
            Failure::Stdout(e) if e.kind() == std::io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
            Failure::Stdout(e) => {
                say(&format!(
                    "error: could not write the output to standard output: {e}"
                ));
                ExitCode::FAILURE
            }
        }
    }
}

/// Writes one line on standard error. Standard error is where failures are
/// reported: when it cannot be written itself (`2>/dev/full`, a closed
/// terminal) there is nowhere left to report that, so the write's failure is
/// dropped here and the exit status alone carries what went wrong.
pub fn say(line: &str) {
    let mut err = std::io::stderr().lock();
    let written = writeln!(err, "{line}").and_then(|()| err.flush());
    if written.is_err() {
        // Unreportable (see above): the caller's exit status stands for it.
    }
}

/// Writes a command's whole output on standard output.
pub fn print(text: &str) -> Result<(), Failure> {
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(Failure::Stdout)
}

/// The document as pretty JSON with a final newline.
pub fn to_json<T: serde::Serialize>(value: &T) -> Result<String, Failure> {
    serde_json::to_string_pretty(value)
        .map(|text| text + "\n")
        .map_err(|e| Failure::Output(format!("could not write the document as JSON: {e}")))
}

/// Ends a command line that clap answered itself: the help or version text on
/// standard output (exit status 0; 1 with a message when it could not be
/// written, 0 when the reader stopped early, as for any output), or a usage
/// error on standard error (exit status 2, whether or not it could be written).
pub fn usage(e: &clap::Error) -> ExitCode {
    let code = u8::try_from(e.exit_code()).unwrap_or(EXIT_INVALID);
    if e.use_stderr() {
        // On standard error: if it cannot be written, the status alone says it.
        if e.print().is_err() {
            // Unreportable (see `say`): the usage error's status stands for it.
        }
        return ExitCode::from(code);
    }
    let printed = e.print().and_then(|()| std::io::stdout().flush());
    match printed {
        Ok(()) => ExitCode::from(code),
        Err(err) => Failure::Stdout(err).report(),
    }
}
