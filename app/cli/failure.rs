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
    /// The output could not be made (exit status 1).
    Output(String),
    /// Standard output could not be written (exit status 1; said on standard
    /// error unless the reader stopped early).
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
                eprintln!("error: {err}");
                ExitCode::from(EXIT_INVALID)
            }
            Failure::Output(what) => {
                eprintln!("error: {what}");
                ExitCode::FAILURE
            }
            // A reader that stopped early (`| head`) wants no more: not news.
            Failure::Stdout(e) if e.kind() == std::io::ErrorKind::BrokenPipe => ExitCode::FAILURE,
            Failure::Stdout(e) => {
                eprintln!("error: could not write the output to standard output: {e}");
                ExitCode::FAILURE
            }
        }
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
