//! Plain words for the scheduling terms the app shows, as hover help: one place,
//! so that every view explains a term the same way, for planners without a
//! scheduling background.

use solscope_engine::Category;

/// The step slider.
pub const STEP: &str = "The scheduler places activities one at a time, highest priority \
    first, and never moves one it has placed. Each of those turns is a step: step k shows \
    the plan after the first k activities were tried.";

/// The free slack being computed.
pub const FREE_SLACK_PROGRESS: &str = "Free slack tries each activity again at every start \
    with everything else where it is, one activity at a time: on a long plan that takes \
    minutes or more. The shading fills in as each activity is done, those nearest the time \
    range in view first; the selected activity's is computed on its own, ahead of the \
    rest, even with the layer off. The rest of the app works meanwhile. Turning the \
    flexibility layer off stops it, and an edit starts it again for the plan as it is.";

/// The step slider's zoom.
pub const STEP_ZOOM: &str = "On a long run the slider can span part of the steps: \
    \"Zoom steps in\" (or Ctrl+wheel over the slider) narrows it around the step shown, \
    the wheel over it moves it earlier or later, and it follows the step you go to. \
    Failures in the steps it spans are marked under it.";

/// The valid-starts tracks.
pub const VALID_STARTS: &str = "Each row shows, in green, the start times that one kind of \
    rule allows for this activity, given what was already placed at that step. It can \
    only start where every row is green at once (\"all together\").";

/// The explanation of a failure.
pub const WHY: &str = "It failed either because no start time passes every timing rule at \
    once (the rows above never overlap: a conflict), or because every start that does \
    would break a power, energy, sleep or heating limit.";

/// The failure step.
pub const FAILURE_STEP: &str = "The first step after which the activity could no longer \
    be placed anywhere: the activities placed up to that step are the ones that took its \
    room.";

/// The culprits.
pub const INVOLVED: &str = "The placed activities that hold what this one needed (a \
    resource, a state, the battery, the peak power) where it could have gone. Click one \
    to select it and see the step that placed it.";

/// The suggestions.
pub const SUGGESTIONS: &str = "Single changes to the plan that make this activity \
    schedule. Each one was tried by scheduling the whole plan again, and lists what else \
    it would change.";

/// The would-have-caused overlay's reasons.
pub const OVERLAY_REASONS: &str = "The scheduler tried this activity at many start times. \
    Each reason is a range of those starts that broke the same limit (the battery's minimum, \
    the minimum at handover, or the peak power). The dashed line is what one start of the \
    range would have done to the plot; Previous and Next go through the others.";

/// The flexibility section.
pub const FLEXIBILITY: &str = "How far this activity's start could move on board without \
    breaking the plan's timing rules (its start bounds), and the part of that where every \
    check, power and energy included, still passes with everything else where it is (its \
    free slack).";

/// The valid-starts row of `category`.
pub fn category(category: Category) -> &'static str {
    match category {
        Category::Execution => "Its windows, cutoff and the plan's start and end.",
        Category::Dependency => {
            "The activities it must come after: starts once they have ended (and within \
             any delay the plan sets)."
        }
        Category::UnitResource => {
            "Its unit resources (an instrument, the arm): starts where no placed activity \
             holds one of them for the whole duration."
        }
        Category::SequenceEngines => {
            "Sequence engines: starts where enough engines are free for the whole duration."
        }
        Category::StateRequirement => {
            "The states it needs (e.g. arm unstowed): starts where each holds the value it \
             needs for the whole duration."
        }
        Category::StateEffect => {
            "The states it changes: starts where its change would not break what placed \
             activities need."
        }
        Category::DataVolume => {
            "Onboard storage: starts where the data it produces still fits, before the \
             handover limit too."
        }
        Category::Uhf => "Communication passes: starts that do not overlap a pass it cannot share.",
    }
}

/// The "all together" row.
pub const ALL_TOGETHER: &str = "Where every row above is green at once: the starts left \
    for the power, energy, sleep and heating checks.";

/// The LMST clock every sol time reads in.
pub const LMST: &str = "Times read as Sol N hh:mm:ss in local mean solar time (LMST): a \
    24-hour Mars clock, midnight to midnight of each sol, whose second is a little longer \
    than an Earth second (the sol's length / 86,400). Plan seconds (t=...) are the plan's \
    own numbers; either can be typed.";
