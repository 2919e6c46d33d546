//! The guided tour: started on the tutorial plan (opening it, guarded when
//! there are unsaved changes), its pages giving the commands they show.

use super::super::{AppState, Pending, Tour, tour};

impl AppState {
    /// Help > Guided tour: on the tutorial plan it starts; else the bundled
    /// tutorial opens first (guarded when there are unsaved changes).
    pub(super) fn guided_tour(&mut self) {
        if tour::is_tutorial(&self.doc.plan) {
            self.start_tour();
        } else if self.doc.dirty {
            self.ui.messages.confirm = Some(Pending::OpenTutorial);
        } else {
            self.open_tutorial();
        }
    }

    /// Starts the guided tour on the plan open, following its first failure.
    pub(in crate::state) fn start_tour(&mut self) {
        let target = tour::first_failure(&self.analysis)
            .and_then(|a| self.doc.plan.activities.get(a))
            .map(|a| a.id.clone());
        self.ui.messages.tour = Some(Tour { page: 0, target });
        self.tour_page(0);
    }

    /// Shows page `k` of the guided tour (when it is shown) and gives the
    /// commands of that page.
    pub(super) fn tour_page(&mut self, k: usize) {
        let Some(t) = self.ui.messages.tour.as_mut() else {
            return;
        };
        t.page = k.min(tour::Page::ALL.len() - 1);
        let page = tour::Page::at(t.page);
        let target = t
            .target
            .as_ref()
            .and_then(|id| self.doc.plan.activities.iter().position(|a| &a.id == id));
        for cmd in tour::enter(page, &self.analysis, target) {
            self.apply(cmd);
        }
    }

    /// Opens the bundled tutorial plan (without a file: saving asks where)
    /// and starts the guided tour.
    pub(super) fn open_tutorial(&mut self) {
        match Self::from_text(tour::TUTORIAL_PLAN, None) {
            Ok(fresh) => {
                self.become_(fresh);
                self.start_tour();
            }
            Err(e) => {
                self.ui.messages.error = Some(format!("Could not open the tutorial plan: {e}"));
            }
        }
    }
}
