//! Candidates for a `placement` failure: one builder per phase-2 reason kind that
//! a plan limit or a field can relax, from the numbers of the start that came
//! closest to passing.

use rayon::prelude::*;
use serde_json::{Value, json};

use super::verify::{Runs, tune_limit, tune_seconds};
use super::{Candidate, floor3};
use crate::explain::Explanation;
use crate::model::{AwakeMode, Plan};
use crate::scheduler::{Phase2Reason, Schedule};
use crate::units::{format_time_of_day, watts, wh};

/// The closest numbers per reason kind over every failing range of starts.
#[derive(Default)]
struct Closest {
    /// Highest lowest state of charge (mJ).
    soc: Option<i64>,
    /// Highest state of charge at handover (mJ).
    handover_soc: Option<i64>,
    /// Lowest peak power (mW).
    peak: Option<i64>,
    /// The first preheat outside its zone's operable periods: zone, start.
    operability: Option<(usize, i64)>,
    /// The longest preheat that would have to start before the plan (s).
    before_plan: Option<i64>,
    /// The earliest start that found no room for an awake period of `min_awake`
    /// in the plan.
    no_room_awake: Option<i64>,
    /// A wake/sleep conflict with the activity's own awake mode (an awake period
    /// over an activity that must run asleep, or a manual sleep over one that
    /// must run awake).
    forced_sleep: bool,
    /// The manual sleeps (activities that must run asleep) in the way of the
    /// awake period the activity needs, sorted.
    sleeps: Vec<usize>,
    /// Merging for `min_sleep` runs through a manual sleep.
    min_sleep: bool,
    /// Extending to `min_awake` runs into a manual sleep.
    min_awake_sleep: bool,
}

impl Closest {
    fn of(ex: &Explanation) -> Self {
        let mut c = Closest::default();
        for r in &ex.reasons {
            match r.reason {
                Phase2Reason::MinSoc { soc_mj, .. } => c.soc = c.soc.max(Some(soc_mj)),
                Phase2Reason::HandoverSoc { soc_mj } => {
                    c.handover_soc = c.handover_soc.max(Some(soc_mj))
                }
                Phase2Reason::MaxPeakPower { peak_mw, .. } => {
                    c.peak = Some(c.peak.map_or(peak_mw, |p| p.min(peak_mw)))
                }
                Phase2Reason::PreheatOperability {
                    zone,
                    preheat_start,
                } => {
                    c.operability.get_or_insert((zone, preheat_start));
                }
                Phase2Reason::PreheatOutsidePlan { preheat_start, .. } => {
                    let length = r.probe.saturating_sub(preheat_start);
                    c.before_plan = c.before_plan.max(Some(length));
                }
                Phase2Reason::MinAwake { sleep: None } => {
                    c.no_room_awake = Some(c.no_room_awake.map_or(r.first, |f| f.min(r.first)));
                }
                Phase2Reason::ForcedSleep { sleep } => {
                    c.forced_sleep = true;
                    c.sleeps.extend(sleep);
                }
                Phase2Reason::MinSleep { sleep } => {
                    c.min_sleep = true;
                    c.sleeps.push(sleep);
                }
                Phase2Reason::MinAwake { sleep: Some(f) } => {
                    c.min_awake_sleep = true;
                    c.sleeps.push(f);
                }
            }
        }
        c.sleeps.sort_unstable();
        c.sleeps.dedup();
        c
    }
}

/// The candidates of every reason kind present, in a fixed order: state of
/// charge, handover state of charge, peak power, operability. Each kind's
/// builder is one entry of an ordered list run in parallel (the ones that
/// search a limit reschedule; each is answered by its own runs), collected in
/// list order, so the result does not depend on the threads.
pub(super) fn candidates(runs: &Runs<'_>, ex: &Explanation) -> Vec<Candidate> {
    let (plan, sched) = (runs.plan, runs.sched);
    let a = ex.activity;
    let closest = Closest::of(ex);
    type Builder<'b> = Box<dyn Fn() -> Vec<Candidate> + Send + Sync + 'b>;
    fn one<'b>(f: impl Fn() -> Option<Candidate> + Send + Sync + 'b) -> Builder<'b> {
        Box::new(move || f().into_iter().collect())
    }
    let mut builders: Vec<Builder<'_>> = Vec::new();
    if let Some(mj) = closest.soc {
        builders.push(one(move || lower_min_soc(runs, a, mj)));
    }
    if let Some(mj) = closest.handover_soc {
        builders.push(Box::new(move || handover_soc(runs, a, mj)));
    }
    if let Some(mw) = closest.peak {
        builders.push(one(move || raise_max_peak(runs, a, mw)));
    }
    if let Some((zone, preheat_start)) = closest.operability {
        builders.push(one(move || {
            extend_operable(plan, sched, zone, preheat_start)
        }));
    }
    if let Some(length) = closest.before_plan {
        builders.push(one(move || start_after_preheat(plan, a, length)));
    }
    if let Some(first) = closest.no_room_awake {
        builders.push(one(move || shorten_min_awake(plan, first)));
    }
    if closest.min_sleep {
        builders.push(one(move || tune_sleep(runs, a, "min_sleep")));
    }
    if closest.min_awake_sleep {
        builders.push(one(move || tune_sleep(runs, a, "min_awake")));
    }
    let mut out: Vec<Candidate> = builders.par_iter().flat_map_iter(|build| build()).collect();
    if closest.forced_sleep || closest.min_sleep || closest.min_awake_sleep {
        out.extend(any_awake(&plan.activities[a]));
        // A manual sleep in the way may run awake instead.
        for &f in closest.sleeps.iter().take(3) {
            out.extend(any_awake(&plan.activities[f]));
        }
    }
    out
}

/// `forced_sleep` and the manual sleeps in the way: let the activity run awake or
/// asleep (`awake: "any"`).
fn any_awake(activity: &crate::model::Activity) -> Option<Candidate> {
    (activity.awake != AwakeMode::Any).then(|| {
        Candidate::activity(
            activity,
            format!("Let {} run awake or asleep (awake: any)", activity.id),
            "awake",
            json!("any"),
        )
    })
}

/// `min_sleep` or `min_awake` against a manual sleep: the least shortening of
/// `sleep.<field>` (whole seconds) that makes activity `a` schedule.
fn tune_sleep(runs: &Runs<'_>, a: usize, field: &str) -> Option<Candidate> {
    let plan = runs.plan;
    let current = match field {
        "min_sleep" => plan.sleep.min_sleep,
        _ => plan.sleep.min_awake,
    };
    let make = |v: i64| {
        let mut sleep = serde_json::to_value(plan.sleep).unwrap_or(Value::Null);
        sleep[field] = json!(v);
        let what = match field {
            "min_sleep" => "minimum sleep between awake periods",
            _ => "minimum awake period",
        };
        Candidate::plan(format!("Shorten the {what} to {v} s"), "sleep", sleep)
    };
    tune_seconds(runs, a, &make, current)
}

/// `preheat_outside_plan`: let the activity start only once a preheat of `length`
/// seconds fits after the plan start (windows that open earlier move later, keeping
/// their length; an activity without windows gets one from then to the plan end).
fn start_after_preheat(plan: &Plan, a: usize, length: i64) -> Option<Candidate> {
    let activity = &plan.activities[a];
    let earliest = plan.horizon.start.saturating_add(length);
    let windows: Vec<Value> = match &activity.windows {
        None => vec![json!({ "start": earliest, "end": plan.horizon.end })],
        Some(windows) => windows
            .iter()
            .map(|w| {
                // A window that opens too early moves later, keeping its length
                // (within the plan); a cutoff it passes is dropped.
                let mut w = *w;
                if w.start < earliest {
                    let shift = earliest - w.start;
                    w.start = earliest;
                    w.end = w
                        .end
                        .saturating_add(shift)
                        .min(plan.horizon.end)
                        .max(earliest);
                    w.preferred = w
                        .preferred
                        .map(|p| p.saturating_add(shift).clamp(w.start, w.end));
                    w.cutoff = w.cutoff.filter(|&c| c > w.start);
                }
                serde_json::to_value(w).unwrap_or(Value::Null)
            })
            .collect(),
    };
    if windows.is_empty() {
        return None;
    }
    Some(Candidate::activity(
        activity,
        format!(
            "Move the windows of {} to open no earlier than {earliest}, once its {length} s preheat fits in the plan",
            activity.id
        ),
        "windows",
        Value::Array(windows),
    ))
}

/// `min_awake` with no room in the plan: shorten `sleep.min_awake` so that an awake
/// period woken up for the earliest such start `first` fits before the plan end.
fn shorten_min_awake(plan: &Plan, first: i64) -> Option<Candidate> {
    let wake = first.saturating_sub(plan.sleep.wakeup_duration);
    let longest = plan.horizon.end.saturating_sub(wake);
    (0 < longest && longest < plan.sleep.min_awake).then(|| {
        let mut sleep = serde_json::to_value(plan.sleep).unwrap_or(Value::Null);
        sleep["min_awake"] = json!(longest);
        Candidate::plan(
            format!(
                "Shorten the minimum awake period to {longest} s, so that one woken up at {wake} fits in the plan"
            ),
            "sleep",
            sleep,
        )
    })
}

/// `min_soc`: the least lowering of `battery.min_soc` that makes it schedule.
fn lower_min_soc(runs: &Runs<'_>, a: usize, soc_mj: i64) -> Option<Candidate> {
    let plan = runs.plan;
    let make = |wh: f64| {
        Candidate::plan_section(
            format!("Lower the minimum state of charge to {wh} Wh"),
            "battery",
            &plan.battery,
            "min_soc",
            wh,
        )
    };
    let needed = floor3(wh(i128::from(soc_mj))).max(0.0);
    tune_limit(runs, a, &make, plan.battery.min_soc, needed, 0.0)
}

/// `handover_soc`: the least lowering of `handover.min_soc`, or making the
/// activity mandatory (handover limits bind only optional activities).
fn handover_soc(runs: &Runs<'_>, a: usize, soc_mj: i64) -> Vec<Candidate> {
    let plan = runs.plan;
    let Some(h) = plan.handover else {
        return Vec::new();
    };
    let activity = &plan.activities[a];
    let make = |wh: f64| {
        Candidate::plan_section(
            format!("Lower the handover state of charge to {wh} Wh"),
            "handover",
            &h,
            "min_soc",
            wh,
        )
    };
    let needed = floor3(wh(i128::from(soc_mj))).max(0.0);
    let current = h.min_soc.unwrap_or(0.0);
    let mut out: Vec<Candidate> = tune_limit(runs, a, &make, current, needed, 0.0)
        .into_iter()
        .collect();
    out.push(Candidate::activity(
        activity,
        format!(
            "Make {} mandatory (handover limits bind only optional activities)",
            activity.id
        ),
        "mandatory",
        json!(true),
    ));
    out
}

/// `max_peak_power`: the least raise of `power.max_peak`.
fn raise_max_peak(runs: &Runs<'_>, a: usize, peak_mw: i64) -> Option<Candidate> {
    let plan = runs.plan;
    let make = |w: f64| {
        Candidate::plan_section(
            format!("Raise the peak power limit to {w} W"),
            "power",
            &plan.power,
            "max_peak",
            w,
        )
    };
    let needed = watts(peak_mw).ceil();
    let current = plan.power.max_peak.unwrap_or(needed);
    tune_limit(runs, a, &make, current, needed, 1e6)
}

/// `preheat_operability`: extend the zone's operable period that starts nearest
/// after the preheat back to the preheat's start.
fn extend_operable(
    plan: &Plan,
    sched: &Schedule,
    zone: usize,
    preheat_start: i64,
) -> Option<Candidate> {
    let problem = &sched.problem;
    let name = &problem.zone_names[zone];
    let thermal = plan.thermal_zones.get(name)?;
    let tod = problem.clock.time_of_day(preheat_start);
    let mut zones = serde_json::to_value(&plan.thermal_zones).unwrap_or(Value::Null);
    let mut periods: Vec<Value> = thermal
        .operable
        .iter()
        .flatten()
        .filter_map(|p| serde_json::to_value(p).ok())
        .collect();
    let (i, next) = thermal
        .operable
        .iter()
        .flatten()
        .enumerate()
        .min_by_key(|(_, p)| (p.from - tod).rem_euclid(problem.clock.sol_length))?;
    periods[i] = json!({ "from": tod, "to": next.to });
    zones[name]["operable"] = Value::Array(periods);
    Some(Candidate::plan(
        format!(
            "Allow {name} heating from {} local time (every sol)",
            format_time_of_day(tod)
        ),
        "thermal_zones",
        zones,
    ))
}
