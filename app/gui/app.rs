//! The frame around the state: [`SolscopeApp`] holds the [`AppState`] and what
//! only the egui side keeps (the palette, the views' cache between frames),
//! and draws one frame ([`SolscopeApp::frame_ui`]): prepare the state, take the
//! keys, draw the views from a read-only model, then apply the commands they
//! pushed.

use std::path::{Path, PathBuf};

use eframe::egui;

use super::shortcuts;
use super::theme::{self, Theme};
use super::views::{self, Look, Model, ViewCache, Widgets};
use crate::state::{AppState, Command, UiCommand};

/// The app: its state, and the egui side's palette and view cache.
pub struct SolscopeApp {
    /// Everything the commands change (no egui in it).
    pub state: AppState,
    /// The palette.
    pub theme: Theme,
    /// What the views keep between frames (built rows, the plots' x range).
    pub(crate) view_cache: ViewCache,
}

impl std::fmt::Debug for SolscopeApp {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SolscopeApp")
            .field("state", &self.state)
            .finish()
    }
}

/// The app reads as its state (`app.doc`, `app.apply(cmd)`): the frame adds
/// only the egui side.
impl std::ops::Deref for SolscopeApp {
    type Target = AppState;

    fn deref(&self) -> &AppState {
        &self.state
    }
}

impl std::ops::DerefMut for SolscopeApp {
    fn deref_mut(&mut self) -> &mut AppState {
        &mut self.state
    }
}

impl From<AppState> for SolscopeApp {
    fn from(state: AppState) -> Self {
        Self {
            state,
            theme: Theme::new(true),
            view_cache: ViewCache::default(),
        }
    }
}

impl SolscopeApp {
    /// Opens a plan from JSON text.
    pub fn from_text(text: &str, path: Option<PathBuf>) -> Result<Self, solscope_engine::Error> {
        AppState::from_text(text, path).map(Self::from)
    }

    /// [`SolscopeApp::from_text`] with another size limit (`screenshot
    /// --max-input-mib`).
    pub fn from_text_limited(
        text: &str,
        path: Option<PathBuf>,
        limit: usize,
    ) -> Result<Self, solscope_engine::Error> {
        AppState::from_text_limited(text, path, limit).map(Self::from)
    }

    /// The app on the bundled default plan.
    pub fn with_default_plan() -> Result<Self, solscope_engine::Error> {
        AppState::with_default_plan().map(Self::from)
    }

    /// Opens `path`, or the default plan when it cannot be read; the error, if any,
    /// is shown in the app.
    pub fn open_or_default(path: Option<&Path>) -> Result<Self, solscope_engine::Error> {
        AppState::open_or_default(path).map(Self::from)
    }

    /// The app on the bundled default plan, opening `path` (if given) on a
    /// worker: the first frame comes at once, with the open's progress line.
    pub fn opening(path: Option<&Path>) -> Result<Self, solscope_engine::Error> {
        AppState::opening(path).map(Self::from)
    }

    /// Draws one frame and applies the commands it produced.
    pub fn frame_ui(&mut self, ui: &mut egui::Ui) {
        // Plan files may hold any text: draw a box for a missing glyph, never panic.
        ui.ctx()
            .set_missing_glyph_policy(egui::epaint::text::MissingGlyphPolicy::Tofu);
        let fonts_set = egui::Id::unique("solscope_fonts_set");
        if !ui
            .ctx()
            .data(|d| d.get_temp::<bool>(fonts_set).unwrap_or(false))
        {
            // Once per context (comparing font definitions each frame is costly).
            ui.ctx().set_fonts(theme::fonts());
            ui.ctx().data_mut(|d| d.insert_temp(fonts_set, true));
        }
        ui.ctx().set_theme(if self.state.persisted.light {
            egui::Theme::Light
        } else {
            egui::Theme::Dark
        });
        self.theme = Theme::new(!self.state.persisted.light);
        self.state.start_offered_tour();
        let mut cmds = self.state.take_commands();
        if self.state.ui.messages.repair.is_none() {
            // The repair view edits text: no undo, stepping or saving of the
            // plan behind it.
            shortcuts::keys(ui, &mut cmds);
        }
        // Ctrl+F takes effect before the views are drawn: the search field
        // then has the keyboard in this very frame, and the keys typed after
        // Ctrl+F in it reach the field.
        let search = Command::from(UiCommand::Search);
        if cmds.contains(&search) {
            cmds.retain(|c| *c != search);
            self.state.apply(search);
        }
        views::dropped_files(ui, &mut cmds);
        let now = ui.input(|i| i.time);
        if let Some(after) = self.state.prepare(now, &mut cmds) {
            ui.ctx().request_repaint_after(after);
        }
        let (m, mut w) = self.model_and_widgets();
        views::layout_ui(ui, &m, &mut w, &mut cmds);
        if !cmds.is_empty() {
            // What the commands change is drawn next frame, even when no input
            // comes (a drop that offers a popup).
            ui.ctx().request_repaint();
        }
        for cmd in cmds {
            self.state.apply(cmd);
        }
        self.state.reveal_selection();
    }

    /// The read-only model the views draw and the widget state they may write,
    /// for one frame (only what was derived for the selected activity at this
    /// revision).
    pub(crate) fn model_and_widgets(&mut self) -> (Model<'_>, Widgets<'_>) {
        // What the search and filters select, for the list and the Gantt
        // alike, and the search index the list's menus read.
        self.view_cache.listed = Some(self.state.listed());
        self.view_cache.search = Some(self.state.search_index());
        let (s, text) = self.state.frame_reads();
        let m = Model {
            doc: s.doc,
            analysis: s.analysis,
            theme: self.theme,
            step_view: s.step_view,
            persisted: s.persisted,
            suggestions: s.suggestions,
            revision: s.revision,
            explanation: s.explanation,
            explanation_error: s.explanation_error,
            valid: s.valid,
            would_cause: s.would_cause,
            flex: s.flex,
            free_slack: s.free_slack,
            nav: s.nav,
            messages: s.messages,
            exec: s.exec,
            tune: s.tune,
        };
        let w = Widgets {
            text,
            cache: &mut self.view_cache,
        };
        (m, w)
    }

    /// Where activity `a`'s bar was drawn on the Gantt in the last frame (its
    /// placement's bar, in schedule mode), if it was.
    pub fn gantt_bar(&self, a: usize) -> Option<egui::Rect> {
        self.view_cache.gantt_bar(a)
    }

    /// How each activity bar the Gantt drew last frame looked against the
    /// search and filters (an activity with several bars appears once per
    /// bar).
    pub fn gantt_looks(&self) -> &[(usize, Look)] {
        &self.view_cache.looks
    }
}
