//! The engine's one error type.

/// Everything that can go wrong in the engine. Scheduling failures are not errors:
/// they are data in the step trace and in explanations.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The plan (or another input document) is invalid; `path` names the JSON path.
    #[error("{path}: {reason}")]
    Invalid {
        /// JSON path of the offending value, e.g. `activities[3].windows[0].end`.
        path: String,
        /// Why it is invalid.
        reason: String,
    },
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A query named an activity the plan does not have.
    #[error("no activity with id `{0}`")]
    UnknownActivity(String),
}

impl Error {
    /// An [`Error::Invalid`] at `path`.
    pub fn invalid(path: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::Invalid {
            path: path.into(),
            reason: reason.into(),
        }
    }
}

/// A non-fatal remark about a plan, with the JSON path it concerns.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Warning {
    /// JSON path, e.g. `activities[4]`.
    pub path: String,
    /// What is suspicious and what follows from it.
    pub message: String,
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.path, self.message)
    }
}
