//! What survives restarts: the settings and recent files the host saves through
//! its storage, kept apart from the runtime state ([`UiState`](super::UiState)).

use std::path::PathBuf;

/// What survives restarts (saved through the host's storage).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Persisted {
    /// Recently opened files, newest first.
    pub recent: Vec<PathBuf>,
    /// Light theme instead of dark.
    pub light: bool,
    /// Gantt: scheduled activities in one row per unit resource instead of packed
    /// lanes.
    #[serde(default)]
    pub by_resource: bool,
    /// Gantt: the flexibility layer (slack whiskers, free slack, dispatchable
    /// neighbours) hidden.
    #[serde(default)]
    pub hide_flex: bool,
    /// Monte Carlo: Run compares the execution policies (replan, dispatch,
    /// fixed over the same runs) instead of running the replanning executive
    /// alone.
    #[serde(default)]
    pub compare_policies: bool,
    /// The guided tour was ended: it no longer opens by itself with the
    /// tutorial plan (Help > Guided tour still shows it; Help > Reset guided
    /// tour makes it open by itself again).
    #[serde(default)]
    pub tour_dismissed: bool,
    /// Width of the activity list panel (points), as last dragged.
    #[serde(default)]
    pub list_width: Option<f32>,
    /// Width of the inspector panel (points), as last dragged.
    #[serde(default)]
    pub inspector_width: Option<f32>,
}

impl Persisted {
    /// Puts `path` first in the recent files (at most ten), made absolute so
    /// it opens from any working directory (as given when the working directory
    /// cannot be read: then it is the best there is).
    pub fn remember(&mut self, path: &std::path::Path) {
        let path = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
        self.recent.retain(|p| *p != path);
        self.recent.insert(0, path);
        self.recent.truncate(10);
    }
}
