//! A plan file opened on a worker: read, validated, scheduled and its view
//! prepared off the frame, so a plan of 10,000 activities never holds the
//! window. Meanwhile the plan open before stays and the window answers (its
//! menus, Quit, and Cancel, which drops the open); the progress line
//! ([`super::Messages::opening`]) names the file, the plan once its name is
//! read, and what the worker is doing.

use std::path::{Path, PathBuf};

use serde::de::IgnoredAny;
use solscope_engine::Error;

use super::document::{Analysis, Document};
use super::job::{Job, Lost, Signal};
use super::{AppState, Pending};

/// What opening a file gives: its text and the app on it (or why the plan
/// in it did not load, for the repair view), or why the file could not be
/// read.
type Opened = Result<(String, Result<Box<AppState>, Error>), String>;

/// A plan file being opened on a worker.
#[derive(Debug)]
pub(super) struct Opening {
    job: Job<u64, Opened>,
    path: PathBuf,
}

/// The few fields of a plan the progress line names, read before the plan
/// is validated.
#[derive(serde::Deserialize)]
struct Outline {
    #[serde(default)]
    name: Option<String>,
    #[serde(default)]
    activities: Vec<IgnoredAny>,
}

/// Opens `path` as `AppState::from_text` does, saying on `signal` what it
/// is doing: `" (NAME): scheduling 10000 activities"` (without a name:
/// `": scheduling …"`), read after the file's name on the progress line.
fn open_file(path: &Path, signal: &Signal) -> Opened {
    signal.say(": reading the file");
    let text = solscope_engine::read_plan_text(path, solscope_engine::MAX_PLAN_BYTES)
        .map_err(|e| e.to_string())?;
    // A text that is no plan says so in the validation below.
    let (named, n) = match serde_json::from_str::<Outline>(&text) {
        Ok(o) => (o.name.map(|n| format!(" ({n})")), o.activities.len()),
        Err(_) => (None, 0),
    };
    let named = named.unwrap_or_default();
    signal.say(format!("{named}: validating {n} activities"));
    let state = Document::from_text(&text, Some(path.to_path_buf())).and_then(|doc| {
        signal.say(format!("{named}: scheduling {n} activities"));
        let analysis = Analysis::of(&doc.plan)?;
        signal.say(format!("{named}: preparing the view"));
        Ok(Box::new(AppState::from_analysis(doc, analysis)))
    });
    Ok((text, state))
}

impl AppState {
    /// The app on the bundled default plan, opening `path` (if given) on a
    /// worker as the desktop app does: the first frame comes at once, with
    /// the open's progress line.
    pub fn opening(path: Option<&Path>) -> Result<Self, Error> {
        let mut app = Self::with_default_plan()?;
        app.background = true;
        if let Some(p) = path {
            app.open_now(p);
        }
        Ok(app)
    }

    /// Starts opening `path` on a worker (another open under way is dropped).
    pub(super) fn open_on_worker(&mut self, path: &Path) {
        self.opens += 1;
        let owned = path.to_path_buf();
        let job = Job::spawn(self.opens, move |s: &Signal| open_file(&owned, s));
        self.opening = Some(Opening {
            job,
            path: path.to_path_buf(),
        });
        self.ui.messages.opening = Some(self.opening_line());
    }

    /// Drops the open under way, if any: the plan open before stays.
    pub(super) fn cancel_opening(&mut self) {
        self.opening = None;
        self.ui.messages.opening = None;
    }

    /// Before a frame: takes the opened plan when the worker is done (as the
    /// plan, or in the repair view, or its error said), else refreshes the
    /// progress line. Whether an open is still under way.
    pub(super) fn reap_opening(&mut self) -> bool {
        let Some(opening) = &self.opening else {
            return false;
        };
        let Some(result) = opening.job.poll() else {
            self.ui.messages.opening = Some(self.opening_line());
            return true;
        };
        let path = opening.path.clone();
        self.cancel_opening();
        match result {
            Ok(Ok((_, Ok(_)))) if self.doc.dirty => {
                // Edited while it opened: those edits are not dropped
                // unasked ("Discard and open" opens it again).
                self.ui.messages.confirm = Some(Pending::Open(path));
            }
            Ok(Ok((text, state))) => self.opened(&path, text, state.map(|s| *s)),
            Ok(Err(e)) => {
                self.ui.messages.error = Some(format!("Could not open {}: {e}", path.display()));
            }
            Err(Lost) => {
                self.ui.messages.error = Some(format!(
                    "Could not open {}: the worker stopped without a result",
                    path.display()
                ));
            }
        }
        false
    }

    /// The progress line of the open under way: "Opening plan.json (NAME):
    /// scheduling 10000 activities… 3 s".
    fn opening_line(&self) -> String {
        let Some(o) = &self.opening else {
            return String::new();
        };
        let file = o
            .path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| o.path.display().to_string());
        let secs = o.job.elapsed().as_secs();
        format!("Opening {file}{}… {secs} s", o.job.note())
    }
}
