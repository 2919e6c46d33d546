//! The guided tour of one failure on the tutorial plan: its pages (what each
//! says, in plain words, and what it points at) and the commands each page
//! gives when it is shown. The app keeps where the tour is
//! ([`super::Tour`], changed only by commands) and whether it was
//! dismissed ([`super::Persisted::tour_dismissed`]); the view draws
//! the page in a small window beside what it talks about.
//!
//! The tutorial plan is recognised by its content: a plan equal to the bundled
//! `assets/tutorial-plan.json`, wherever its file is (no file-name match, and
//! no field added to the plan format). The failure the tour follows is the
//! first activity that failed in the plan's schedule, picked when the tour
//! starts.

use solscope_engine::{Category, Explanation, Phase, Plan, Suggestion, format_local, involved};

use super::commands::{Command, UiCommand};
use super::document::Analysis;
use super::status::failed_steps;

/// The bundled tutorial plan (`assets/tutorial-plan.json`).
pub const TUTORIAL_PLAN: &str = include_str!("../../assets/tutorial-plan.json");

/// Whether `plan` is the bundled tutorial plan (as loaded, unedited).
pub fn is_tutorial(plan: &Plan) -> bool {
    solscope_engine::load_plan(TUTORIAL_PLAN).is_ok_and(|t| t.plan == *plan)
}

/// The first activity that failed in `analysis`'s schedule (in step order).
pub fn first_failure(analysis: &Analysis) -> Option<usize> {
    failed_steps(&analysis.schedule.steps)
        .next()
        .map(|(_, a)| a)
}

/// The pages of the tour, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Page {
    /// What a step is: the step slider.
    Steps,
    /// The failed activity, selected at the step that tried it.
    Failed,
    /// Why it failed: the inspector's explanation, at its failure step.
    Why,
    /// The activities involved.
    Involved,
    /// A verified suggestion, and applying it.
    Suggestion,
    /// Undo.
    Undo,
}

impl Page {
    /// Every page, in the order shown.
    pub const ALL: [Self; 6] = [
        Self::Steps,
        Self::Failed,
        Self::Why,
        Self::Involved,
        Self::Suggestion,
        Self::Undo,
    ];

    /// Page `k` (the last for a larger `k`).
    pub fn at(k: usize) -> Self {
        Self::ALL[k.min(Self::ALL.len() - 1)]
    }

    /// Its title.
    pub fn title(self) -> &'static str {
        match self {
            Self::Steps => "The scheduler works in steps",
            Self::Failed => "An activity that did not fit",
            Self::Why => "Why it did not fit",
            Self::Involved => "What took its place",
            Self::Suggestion => "A fix, checked before you see it",
            Self::Undo => "Nothing is lost",
        }
    }

    /// What it points at.
    pub fn anchor(self) -> Anchor {
        match self {
            Self::Steps => Anchor::StepSlider,
            Self::Failed => Anchor::List,
            Self::Why => Anchor::Why,
            Self::Involved => Anchor::Involved,
            Self::Suggestion => Anchor::Suggestions,
            Self::Undo => Anchor::Toolbar,
        }
    }
}

/// The part of the window a page talks about; its window is drawn beside it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Anchor {
    /// The step slider (top).
    StepSlider,
    /// The activity list (left).
    List,
    /// The inspector's "Why it did not schedule".
    Why,
    /// The inspector's Involved list.
    Involved,
    /// The inspector's suggestions.
    Suggestions,
    /// The toolbar's Undo and Redo (top left).
    Toolbar,
}

/// The commands page `page` gives when it is shown, for the failed activity
/// `target` (none when the plan has no failure): schedule mode (the tour is
/// about the schedule), then it selects the failure and moves the step slider
/// to where the page needs it.
pub fn enter(page: Page, analysis: &Analysis, target: Option<usize>) -> Vec<Command> {
    let mut cmds = vec![Command::Ui(UiCommand::ShowSchedule)];
    let Some(a) = target else {
        return cmds;
    };
    let own_step = analysis.schedule.step_of(a).map_or(0, |s| s.step);
    cmds.extend(match page {
        Page::Steps | Page::Undo => Vec::new(),
        Page::Failed => vec![Command::Select(Some(a)), Command::SetStep(own_step)],
        Page::Why | Page::Involved => vec![Command::GoToFailureStep(a)],
        Page::Suggestion => vec![Command::Select(Some(a)), Command::Ui(UiCommand::LastStep)],
    });
    cmds
}

/// What a page says, and the action it offers besides Back / Next / End tour.
#[derive(Clone, Debug, PartialEq)]
pub struct Text {
    /// Its paragraphs.
    pub paragraphs: Vec<String>,
    /// A button: its label and the command it gives.
    pub action: Option<(String, Command)>,
}

/// What the tour knows of the plan when it draws a page.
#[derive(Clone, Copy, Debug)]
pub struct Facts<'a> {
    /// The plan.
    pub plan: &'a Plan,
    /// Its schedule.
    pub analysis: &'a Analysis,
    /// The failed activity the tour follows, if the plan has one.
    pub target: Option<usize>,
    /// Its explanation, once derived (while it is selected).
    pub explanation: Option<&'a Explanation>,
    /// Its verified suggestions, once derived (while it is selected).
    pub suggestions: Option<&'a [Suggestion]>,
    /// Whether Undo has an edit to undo.
    pub can_undo: bool,
}

impl Facts<'_> {
    /// `id` of activity `a`.
    fn id(&self, a: usize) -> &str {
        self.plan.activities.get(a).map_or("", |x| x.id.as_str())
    }

    /// A time as planners read it: `Sol 0 10:13:08` (LMST).
    fn time(&self, t: i64) -> String {
        format_local(&self.plan.local_time, t)
    }
}

/// What page `page` says about `facts`.
pub fn text(page: Page, facts: &Facts<'_>) -> Text {
    let mut paragraphs = Vec::new();
    let mut action = None;
    let steps = facts.analysis.steps();
    // The steps the slider's red ticks mark.
    let failed = failed_steps(&facts.analysis.schedule.steps).count();
    let Some(a) = facts.target else {
        paragraphs.push(match page {
            Page::Steps => format!(
                "The scheduler takes the activities one at a time, most important first \
                 (lowest priority number), gives each the best start it can find, and never \
                 moves it afterwards. Each of those turns is a step; the slider at the top \
                 replays the {steps} steps of this plan."
            ),
            _ => "Every activity of this plan fits: there is no failure to follow. Open the \
                  tutorial plan (Help > Guided tour) to see one."
                .to_string(),
        });
        return Text { paragraphs, action };
    };
    let id = facts.id(a);
    let own_step = facts.analysis.schedule.step_of(a).map_or(0, |s| s.step);
    // Only its own explanation and suggestions: the user may have selected
    // another activity meanwhile.
    let ex = facts.explanation.filter(|e| e.activity == a);
    let reselect = "(Next or Back selects it again if you clicked elsewhere.)";
    let placed = facts.analysis.placement(a).map(|p| p.0);
    if let (Some(t), Page::Failed | Page::Why | Page::Involved) = (placed, page) {
        // A change made since (a suggestion applied) gave it room.
        paragraphs.push(format!(
            "{id} is scheduled now, at {}: a change made since gave it room. Undo (the last \
             page) takes the change back, and this page then shows the failure again.",
            facts.time(t)
        ));
        return Text { paragraphs, action };
    }
    match page {
        Page::Steps => {
            paragraphs.push(
                "The scheduler places the activities one at a time, most important first \
                 (lowest priority number). It gives each the best start it can find and \
                 never moves it afterwards. Each of those turns is a step."
                    .to_string(),
            );
            paragraphs.push(format!(
                "The slider at the top replays them: step 0 is the empty plan, step {steps} \
                 the finished schedule. Red ticks under it mark the steps where an activity \
                 could not be placed: {failed} in this plan. Drag it, or press Left and \
                 Right, to watch the schedule being built."
            ));
        }
        Page::Failed => {
            let act = &facts.plan.activities[a];
            let windows: Vec<String> = act
                .windows
                .iter()
                .flatten()
                .map(|w| format!("{} to {}", facts.time(w.start), facts.time(w.end)))
                .collect();
            paragraphs.push(format!(
                "At step {own_step} the scheduler tried {id} (\"{}\") and found no start \
                 for it.",
                act.display_name()
            ));
            let where_ = if windows.is_empty() {
                String::new()
            } else {
                format!(
                    " Its window, hatched on the chart, allows starts from {}.",
                    windows.join(", or ")
                )
            };
            paragraphs.push(format!(
                "It is selected now: red in the list on the left and on the chart.{where_} \
                 The inspector on the right says why."
            ));
        }
        Page::Why => {
            paragraphs.push(
                "The scheduler checks a start time in two rounds. First the timing and the \
                 resources: the activity's windows, the instruments and states that placed \
                 activities hold, what it must come after. The rows of \"Valid starts per \
                 constraint\" are green where each rule allows a start. Then, for the starts \
                 left, the power, the battery, sleep and heating."
                    .to_string(),
            );
            match ex {
                Some(ex) => {
                    paragraphs.push(match ex.phase {
                        Some(Phase::ValidIntervals) => {
                            let rules: Vec<&str> = ex
                                .conflicts
                                .first()
                                .map(|c| c.iter().map(|&x| rule_name(x)).collect())
                                .unwrap_or_default();
                            format!(
                                "{id} fails in the first round: no start time is green in \
                                 every row at once. {} rule each other out.",
                                sentence_list(&rules)
                            )
                        }
                        Some(Phase::Placement) => format!(
                            "{id} passes the first round, but every start left would break \
                             a limit of the second: the lines under \"Why it did not \
                             schedule\" say which, and the plots draw what it would have \
                             done."
                        ),
                        Some(Phase::Dependency) => {
                            format!("{id} must come after an activity that did not fit itself.")
                        }
                        Some(Phase::Group) => format!(
                            "{id} is one of a group of which only one is kept, and another \
                             one was."
                        ),
                        None => format!("{id} is scheduled now."),
                    });
                    if let Some(k) = ex.failure_step {
                        paragraphs.push(if k == 0 {
                            "It cannot fit even in an empty plan.".to_string()
                        } else {
                            format!(
                                "The slider now shows step {k}, its failure step: before \
                                 that step there was still room for it, after it there is \
                                 none."
                            )
                        });
                    }
                }
                None => paragraphs.push(format!("Select {id} to read why. {reselect}")),
            }
        }
        Page::Involved => match ex {
            Some(ex) => {
                let names: Vec<String> = involved(ex)
                    .iter()
                    .map(|c| format!("{} (placed at step {})", facts.id(c.activity), c.step))
                    .collect();
                if names.is_empty() {
                    paragraphs.push(format!("No placed activity is to blame for {id}."));
                } else {
                    paragraphs.push(format!(
                        "The Involved list names the activities already placed that hold \
                         what {id} needed where it could have gone: {}.",
                        names.join(", ")
                    ));
                    paragraphs.push(
                        "Click one to select it and see the step that placed it; Back in \
                         the toolbar returns here."
                            .to_string(),
                    );
                }
            }
            None => paragraphs.push(format!("Select {id} to see them. {reselect}")),
        },
        Page::Suggestion => {
            paragraphs.push(format!(
                "Each suggestion is one change to the plan that makes {id} fit. solscope \
                 tried every one by scheduling the whole plan again, and says what else \
                 would then stop fitting."
            ));
            match facts.suggestions {
                _ if placed.is_some() => paragraphs.push(format!(
                    "{id} is scheduled now, at {}: the banner at the foot of the chart lists what the \
                     change did to the other activities.",
                    placed.map(|t| facts.time(t)).unwrap_or_default()
                )),
                Some([first, ..]) => {
                    let windows = windows_of(facts, first);
                    paragraphs.push(format!(
                        "The first one: \"{}\"{windows}. Press its Apply button in the \
                         inspector, or the one here: the plan is scheduled again and the \
                         banner at the foot of the chart says what changed.",
                        first.description
                    ));
                    action = Some((
                        "Apply it".to_string(),
                        Command::Edit {
                            target: first.target.clone(),
                            set: first.set.clone(),
                            description: first.description.clone(),
                        },
                    ));
                }
                Some([]) => paragraphs.push(format!("No single change makes {id} fit.")),
                None => paragraphs.push("The suggestions are being checked…".to_string()),
            }
        }
        Page::Undo => {
            paragraphs.push(
                "Undo (in the toolbar, or Ctrl+Z) puts the plan back as it was; Redo \
                 (Ctrl+Shift+Z) makes the change again. \"(unsaved)\" beside the plan's name \
                 says it differs from its file."
                    .to_string(),
            );
            paragraphs.push(
                "That is the tour. Help > Guided tour shows it again; every term in the app \
                 explains itself when you hover over it."
                    .to_string(),
            );
            if facts.can_undo {
                action = Some(("Undo the change".to_string(), Command::Ui(UiCommand::Undo)));
            }
        }
    }
    Text { paragraphs, action }
}

/// The windows a suggestion sets, in sol and local time: ` (its window
/// becomes Sol 0 10:03:24 to Sol 0 10:27:44)`; empty when it sets none.
fn windows_of(facts: &Facts<'_>, s: &Suggestion) -> String {
    let Some(windows) = s.set.get("windows").and_then(|w| w.as_array()) else {
        return String::new();
    };
    let spans: Vec<String> = windows
        .iter()
        .filter_map(|w| Some((w.get("start")?.as_i64()?, w.get("end")?.as_i64()?)))
        .map(|(a, b)| format!("{} to {}", facts.time(a), facts.time(b)))
        .collect();
    match spans.len() {
        0 => String::new(),
        1 => format!(" (its window becomes {})", spans[0]),
        _ => format!(" (its windows become {})", spans.join(", ")),
    }
}

/// A constraint category in plain words.
fn rule_name(category: Category) -> &'static str {
    match category {
        Category::Execution => "its window",
        Category::Dependency => "what it must come after",
        Category::UnitResource => "the instruments other activities hold",
        Category::SequenceEngines => "the free sequence engines",
        Category::StateRequirement => "the states it needs",
        Category::StateEffect => "the states it changes",
        Category::DataVolume => "the onboard storage",
        Category::Uhf => "the communication passes",
    }
}

/// "A, b and c".
fn sentence_list(items: &[&str]) -> String {
    let mut out = match items {
        [] => String::new(),
        [one] => (*one).to_string(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    };
    if let Some(c) = out.get(..1) {
        let upper = c.to_uppercase();
        out.replace_range(..1, &upper);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tutorial_is_recognised_by_its_content_and_not_once_edited() {
        let plan = solscope_engine::load_plan(TUTORIAL_PLAN).unwrap().plan;
        assert!(is_tutorial(&plan));
        let mut edited = plan.clone();
        edited.activities[0].priority += 1;
        assert!(!is_tutorial(&edited));
        let default = solscope_engine::load_plan(super::super::DEFAULT_PLAN)
            .unwrap()
            .plan;
        assert!(!is_tutorial(&default));
    }

    #[test]
    fn the_tour_follows_the_tutorials_window_conflict() {
        // The first failure of the tutorial is the sky flats, which the
        // panorama's mast keeps out of its whole window: a phase-1 conflict
        // with one culprit and verified suggestions, a clear first example.
        let plan = solscope_engine::load_plan(TUTORIAL_PLAN).unwrap().plan;
        let analysis = Analysis::of(&plan).unwrap();
        let a = first_failure(&analysis).unwrap();
        assert_eq!(plan.activities[a].id, "sky_flats_mast_busy");
        let ex = analysis.explain(&plan, a).unwrap().unwrap();
        assert_eq!(ex.phase, Some(Phase::ValidIntervals));
        let facts = Facts {
            plan: &plan,
            analysis: &analysis,
            target: Some(a),
            explanation: Some(&ex),
            suggestions: None,
            can_undo: false,
        };
        let why = text(Page::Why, &facts).paragraphs.join(" ");
        assert!(
            why.contains(
                "Its window and the instruments other activities hold rule each other out"
            ),
            "{why}"
        );
        let involved = text(Page::Involved, &facts).paragraphs.join(" ");
        assert!(
            involved.contains("zcam_pano (placed at step 3)"),
            "{involved}"
        );
        let failed = text(Page::Failed, &facts).paragraphs.join(" ");
        assert!(
            failed.contains("allows starts from Sol 0 10:13:08 to Sol 0 10:27:44"),
            "{failed}"
        );
        // Once a change gives it room, the pages about its failure say so.
        let widened = solscope_engine::apply_edit(
            &plan,
            "activity:sky_flats_mast_busy",
            &serde_json::from_str(r#"{"windows": [{"start": 37200, "end": 38700}]}"#).unwrap(),
        )
        .unwrap();
        let after = Analysis::of(&widened).unwrap();
        let now = Facts {
            plan: &widened,
            analysis: &after,
            ..facts
        };
        let failed = text(Page::Failed, &now).paragraphs.join(" ");
        assert!(
            failed.starts_with("sky_flats_mast_busy is scheduled now, at Sol 0 10:03:24"),
            "{failed}"
        );
        assert_eq!(
            enter(Page::Failed, &analysis, Some(a)),
            [
                Command::Ui(UiCommand::ShowSchedule),
                Command::Select(Some(a)),
                Command::SetStep(analysis.schedule.step_of(a).unwrap().step)
            ]
        );
    }

    #[test]
    fn lists_read_as_a_sentence() {
        assert_eq!(sentence_list(&["a"]), "A");
        assert_eq!(sentence_list(&["a", "b", "c"]), "A, b and c");
        assert_eq!(sentence_list(&[]), "");
    }
}
