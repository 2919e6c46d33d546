//! Planner-facing sentences for explanations. Pure formatting: no decisions here.

use super::{Culprit, Explanation, Phase, ReasonRange};
use crate::model::Plan;
use crate::scheduler::{Category, Phase2Reason, Problem, Schedule};
use crate::sentence::{range, span, spans, time};
use crate::timeline::IntervalSet;
use crate::units::{format_watts, format_wh};

fn describe_set(problem: &Problem, set: &IntervalSet) -> String {
    let ivs = set.intervals();
    if ivs.is_empty() {
        return "no start at all".into();
    }
    let shown: Vec<String> = ivs
        .iter()
        .take(3)
        .map(|iv| {
            if iv.lo == iv.hi {
                format!("only {}", time(&problem.clock, iv.lo))
            } else if iv.lo <= problem.h0 && iv.hi >= problem.h1 {
                "any start".into()
            } else if iv.lo <= problem.h0 {
                format!("starts up to {}", time(&problem.clock, iv.hi))
            } else if iv.hi >= problem.h1 {
                format!("starts from {}", time(&problem.clock, iv.lo))
            } else {
                format!("starts {}", range(&problem.clock, iv.lo, iv.hi))
            }
        })
        .collect();
    let more = if ivs.len() > 3 {
        format!(" and {} more ranges", ivs.len() - 3)
    } else {
        String::new()
    };
    format!("{}{more}", shown.join(", "))
}

fn category_phrase(c: Category) -> &'static str {
    match c {
        Category::Execution => "its windows and the plan bounds",
        Category::Dependency => "its dependencies",
        Category::UnitResource => "its unit resources (used by other activities)",
        Category::SequenceEngines => "the free sequence engines",
        Category::StateRequirement => "its required states",
        Category::StateEffect => "what its state changes would break",
        Category::DataVolume => "the data storage limits",
        Category::Uhf => "the UHF/comm passes it may not overlap",
    }
}

/// A suggestion as one line: its description, and the activities it would make
/// fail (` (then fails: a, b)`) when there are any.
pub fn suggestion_line(plan: &Plan, s: &super::Suggestion) -> String {
    let description = suggestion_description(plan, &s.description);
    if s.side_effects.is_empty() {
        return description;
    }
    let ids: Vec<&str> = s
        .side_effects
        .iter()
        .map(|&x| plan.activities[x].id.as_str())
        .collect();
    format!("{description} (then fails: {})", ids.join(", "))
}

/// A suggestion's description as a planner reads it: the times a widened
/// window would reach said in sol time (LMST) with their plan second
/// (`Widen window 1 of B to end at Sol 0 00:09:44 (t=600)`); the edit itself
/// (and the description in the JSON document) keeps the plan seconds.
pub fn suggestion_description(plan: &Plan, description: &str) -> String {
    // "Allow Z heating from 14:05:30 local time (every sol)": a local time of
    // day in plan seconds after midnight, said on the LMST clock.
    if let Some((head, tail)) = description
        .split_once(" heating from ")
        .filter(|_| description.starts_with("Allow "))
    {
        if let Some((clock, rest)) = tail.split_once(" local time") {
            if let Ok(tod) = crate::units::parse_clock_seconds(clock) {
                let lmst = crate::units::lmst_of_day(plan.local_time.sol_length, tod);
                return format!(
                    "{head} heating from {} LMST{rest}",
                    crate::units::format_time_of_day(lmst)
                );
            }
        }
    }
    if !description.starts_with("Widen window ") {
        return description.to_string();
    }
    let mut out = String::with_capacity(description.len() + 32);
    let mut rest = description;
    while let Some(i) = rest.find(" at ") {
        out.push_str(&rest[..i + 4]);
        rest = &rest[i + 4..];
        let n = rest
            .bytes()
            .enumerate()
            .take_while(|&(k, b)| b.is_ascii_digit() || (k == 0 && b == b'-'))
            .count();
        if let Ok(t) = rest[..n].parse::<i64>() {
            out.push_str(&crate::units::format_plan_time(&plan.local_time, t));
            rest = &rest[n..];
        }
    }
    out.push_str(rest);
    out
}

/// One range of failing starts in short form, with its numbers:
/// `min_soc for starts 100–200: SOC 633.2 Wh at 1500 (10:25:00)`.
///
/// `shown` is the duration the text around the line is for (an explanation's,
/// or a step's): a range tried at another duration of an expanding activity
/// names its own (`min_soc for starts 100–200, lasting 15 min: …`).
pub fn reason_line(plan: &Plan, problem: &Problem, r: &ReasonRange, shown: i64) -> String {
    let detail = match &r.reason {
        Phase2Reason::MinSoc { at: t, soc_mj } => {
            format!(
                "SOC {} at {}",
                format_wh(i128::from(*soc_mj)),
                time(&problem.clock, *t)
            )
        }
        Phase2Reason::MaxPeakPower { at: t, peak_mw } => {
            format!(
                "peak {} at {}",
                format_watts(*peak_mw),
                time(&problem.clock, *t)
            )
        }
        Phase2Reason::HandoverSoc { soc_mj } => {
            format!("SOC {} at handover", format_wh(i128::from(*soc_mj)))
        }
        Phase2Reason::PreheatOutsidePlan {
            zone,
            preheat_start,
        }
        | Phase2Reason::PreheatOperability {
            zone,
            preheat_start,
        } => format!(
            "{} preheat from {}",
            problem.zone_names[*zone],
            time(&problem.clock, *preheat_start)
        ),
        Phase2Reason::ForcedSleep { sleep: Some(x) }
        | Phase2Reason::MinSleep { sleep: x }
        | Phase2Reason::MinAwake { sleep: Some(x) } => {
            format!("manual sleep {}", plan.activities[*x].id)
        }
        Phase2Reason::ForcedSleep { sleep: None } => "an awake period".to_string(),
        Phase2Reason::MinAwake { sleep: None } => "the plan bounds".to_string(),
    };
    format!(
        "{} for starts {}{}: {detail}",
        r.reason.kind().name(),
        range(&problem.clock, r.first, r.last),
        lasting(r, shown)
    )
}

/// The indices of `ex.reasons` in the order a planner reads them: those for
/// the explanation's own duration (the one its lead note names) first, then
/// those the duration search tried at other durations, each group in its
/// recorded order.
pub fn reasons_in_reading_order(ex: &Explanation) -> Vec<usize> {
    let (mut own, other): (Vec<usize>, Vec<usize>) =
        (0..ex.reasons.len()).partition(|&i| ex.reasons[i].duration == ex.duration);
    own.extend(other);
    own
}

/// `, lasting 15 min` when `r` was tried at another duration than `shown`.
fn lasting(r: &ReasonRange, shown: i64) -> String {
    if r.duration == shown {
        String::new()
    } else {
        format!(", lasting {}", span(r.duration))
    }
}

/// The plain-language notes of an explanation.
pub fn explanation_notes(plan: &Plan, problem: &Problem, ex: &Explanation) -> Vec<String> {
    explanation_notes_and_lead(plan, problem, ex).0
}

/// [`explanation_notes`], and how many of them lead: why the activity failed
/// in one sentence, and for an expanding activity the duration that what
/// follows is for. The rest go through the conflicts or reasons one by one
/// (the app's inspector shows the lead above its list of reasons, the rest
/// below it).
pub fn explanation_notes_and_lead(
    plan: &Plan,
    problem: &Problem,
    ex: &Explanation,
) -> (Vec<String>, usize) {
    let name = |a: usize| plan.activities[a].display_name().to_string();
    let me = name(ex.activity);
    let mut notes = Vec::new();
    let mut lead = None;
    let Some(phase) = ex.phase else {
        notes.push(format!("{me} is scheduled (step {}).", ex.step));
        return (notes, 1);
    };
    let when = match ex.failure_step {
        Some(0) => "It cannot be scheduled even in an empty plan.".to_string(),
        Some(1) => "It first fails once the activity of step 1 is placed.".to_string(),
        Some(k) => format!("It first fails once the activities of steps 1–{k} are placed."),
        None => String::new(),
    };
    // An expanding activity fails at every duration; what follows (the
    // constraints' intervals, the reasons) is for the one its record has.
    let durations = problem
        .acts
        .get(ex.activity)
        .map(|act| (act.dur_min, act.dur_max))
        .filter(|(min, max)| {
            min != max && matches!(phase, Phase::ValidIntervals | Phase::Placement)
        });
    let for_duration = durations.map(|(min, max)| {
        let which = if ex.duration == min {
            format!("its shortest, {}", span(min))
        } else {
            format!("a duration of {}", span(ex.duration))
        };
        // The search's tries at other durations are listed too, each
        // naming its own.
        let except = if ex.reasons.iter().any(|r| r.duration != ex.duration) {
            ", except where a line names the duration it was tried at"
        } else {
            ""
        };
        format!(
            "{me} may last from {}, and no duration fits; what follows is for {which}{except}.",
            spans(min, max)
        )
    });
    match phase {
        Phase::Group => {
            let by = ex.blocked_by.map(name).unwrap_or_default();
            notes.push(format!(
                "{me} was skipped: {by}, from the same group, was already scheduled (only one of a group is kept)."
            ));
        }
        Phase::Dependency => {
            let by = ex.blocked_by.map(name).unwrap_or_default();
            // Depended on but not tried yet: later in the step order.
            let later = ex
                .blocked_by
                .filter(|&b| problem.step_of.get(b).is_some_and(|&k| k > ex.step));
            notes.push(match later {
                Some(b) => format!(
                    "{me} must come after {by}, but {by} comes later in step order (priority {}), \
                     so it cannot have run first; {me} cannot be scheduled.",
                    plan.activities[b].priority
                ),
                None => format!(
                    "{me} must come after {by}, which did not get scheduled, so {me} cannot be either."
                ),
            });
        }
        Phase::ValidIntervals => {
            notes.push(format!(
                "No start time of {me} satisfies all its constraints at once. {when}"
            ));
            notes.extend(for_duration);
            lead = Some(notes.len());
            for conflict in &ex.conflicts {
                let parts: Vec<String> = conflict
                    .iter()
                    .filter_map(|c| ex.categories.iter().find(|x| x.category == *c))
                    .map(|c| {
                        format!(
                            "{} allow {}",
                            category_phrase(c.category),
                            describe_set(problem, &c.valid)
                        )
                    })
                    .collect();
                notes.push(format!("These cannot hold together: {}.", parts.join("; ")));
            }
            for r in ex.relaxations.iter().take(4) {
                let cats: Vec<&str> = r.categories.iter().map(|c| category_phrase(*c)).collect();
                notes.push(format!(
                    "Without {} it could start at {}.",
                    cats.join(" and "),
                    time(&problem.clock, r.witness)
                ));
            }
        }
        Phase::Placement => {
            notes.push(format!(
                "Some start times pass every constraint on timing and resources, but each fails on power, sleep or heating. {when}"
            ));
            notes.extend(for_duration);
            lead = Some(notes.len());
            for r in reasons_in_reading_order(ex)
                .into_iter()
                .take(8)
                .map(|i| &ex.reasons[i])
            {
                let range = if r.first == r.last {
                    format!(
                        "At {}{}",
                        time(&problem.clock, r.first),
                        lasting(r, ex.duration)
                    )
                } else {
                    format!(
                        "For starts {}{}",
                        range(&problem.clock, r.first, r.last),
                        lasting(r, ex.duration)
                    )
                };
                let why = match &r.reason {
                    Phase2Reason::MinSoc { at: t, soc_mj } => format!(
                        "the battery would fall to {} at {}, below the {} minimum",
                        format_wh(i128::from(*soc_mj)),
                        time(&problem.clock, *t),
                        format_wh(problem.min_soc)
                    ),
                    Phase2Reason::HandoverSoc { soc_mj } => format!(
                        "the battery at handover would be {}, below the {} handover minimum",
                        format_wh(i128::from(*soc_mj)),
                        format_wh(problem.handover_soc.unwrap_or(0))
                    ),
                    Phase2Reason::MaxPeakPower { at: t, peak_mw } => format!(
                        "peak power would reach {} at {}, above the {} limit",
                        format_watts(*peak_mw),
                        time(&problem.clock, *t),
                        format_watts(problem.max_peak.unwrap_or(0))
                    ),
                    Phase2Reason::ForcedSleep { sleep } => match sleep {
                        Some(x) => format!(
                            "the rover would have to be awake during the manual sleep {}",
                            name(*x)
                        ),
                        None => {
                            "the rover is awake then, but this activity is a manual sleep".into()
                        }
                    },
                    Phase2Reason::MinSleep { sleep } => format!(
                        "the sleep between awake periods would be too short, and merging them would run through the manual sleep {}",
                        name(*sleep)
                    ),
                    Phase2Reason::MinAwake { sleep } => match sleep {
                        Some(x) => format!(
                            "the awake period cannot be made long enough without running into the manual sleep {}",
                            name(*x)
                        ),
                        None => {
                            "the awake period cannot be made long enough inside the plan".into()
                        }
                    },
                    Phase2Reason::PreheatOutsidePlan {
                        zone,
                        preheat_start,
                    } => format!(
                        "the {} preheat would have to start at {}, before the plan begins",
                        problem.zone_names[*zone],
                        time(&problem.clock, *preheat_start)
                    ),
                    Phase2Reason::PreheatOperability {
                        zone,
                        preheat_start,
                    } => format!(
                        "the {} preheat would start at {}, outside the times that zone may be heated",
                        problem.zone_names[*zone],
                        time(&problem.clock, *preheat_start)
                    ),
                };
                notes.push(format!("{range}, {why}."));
            }
            if ex.reasons.len() > 8 {
                notes.push(format!(
                    "({} more ranges of starts were tried.)",
                    ex.reasons.len() - 8
                ));
            }
            if let Some(before) = ex.reasons_joined {
                notes.push(format!(
                    "(The starts tried fell into {before} ranges; ranges of one duration failing for the same reason are joined across the starts between them that were not tried, so each range also spans starts outside the windows or ruled out by timing and resources.)"
                ));
            }
        }
    }
    match ex.together.as_deref() {
        Some([x, y]) => notes.push(format!(
            "No single change fixes this; these two together do: {}; and {}.",
            x.description, y.description
        )),
        Some(_) => notes.push(
            "No single change fixes this, and no pair of the changes tried does.".to_string(),
        ),
        None => {}
    }
    if !ex.culprits.is_empty() {
        let names: Vec<String> = involved(ex)
            .iter()
            .map(|c| format!("{} (step {}, {})", name(c.activity), c.step, c.blame.name()))
            .collect();
        notes.push(format!("Involved: {}.", names.join(", ")));
    }
    let lead = lead.unwrap_or(notes.len());
    (notes, lead)
}

/// How many culprits a view for planners names.
const INVOLVED: usize = 6;

/// The culprits every view for planners names, in the explanation's order (the
/// text, and the app's clickable list): the first few. The JSON has them all.
pub fn involved(ex: &Explanation) -> &[Culprit] {
    &ex.culprits[..ex.culprits.len().min(INVOLVED)]
}

/// Planner-facing text for a set of explanations.
pub fn explain_text(plan: &Plan, schedule: &Schedule, explanations: &[Explanation]) -> String {
    explanations
        .iter()
        .map(|ex| explanation_text(plan, schedule, ex))
        .collect()
}

/// The text of one explanation, as [`explain_text`] prints it (for a caller that
/// writes explanations one at a time).
pub fn explanation_text(plan: &Plan, schedule: &Schedule, ex: &Explanation) -> String {
    let problem = &schedule.problem;
    let mut out = String::new();
    let a = &plan.activities[ex.activity];
    out.push_str(&format!(
        "== {} ({}), step {}\n",
        a.display_name(),
        a.id,
        ex.step
    ));
    for n in explanation_notes(plan, problem, ex) {
        out.push_str(&format!("  {n}\n"));
    }
    for (i, s) in ex.suggestions.iter().enumerate() {
        out.push_str(&format!(
            "  suggestion {}: {}\n",
            i + 1,
            suggestion_line(plan, s)
        ));
    }
    out.push('\n');
    // The notes are the document's sentences: said in LMST here.
    crate::units::lmst_sentence(&plan.local_time, &out)
}
