#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]
//! One scenario per failure kind of the published Crosscheck figures, with the
//! phase, failure step, conflicts and culprits worked out by hand in comments.

use serde_json::{Value, json};
use solscope_engine::{
    Category, ExplainOptions, Explanation, Phase, Phase2Reason, Plan, Schedule, energy_consumers,
    explain, load_plan, partial_schedule, peak_users, schedule, valid_intervals_at,
};

fn plan(extra: Value, activities: Value) -> Plan {
    let mut p = json!({
        "format": "solscope.plan/1",
        "horizon": { "start": 0, "end": 10000 },
        "battery": { "capacity": 1000.0, "initial": 1000.0, "min_soc": 0.0 },
        "power": { "rtg": 0.0, "asleep": 0.0, "awake": 0.0 },
        "activities": activities
    });
    for (k, v) in extra.as_object().expect("object") {
        p[k] = v.clone();
    }
    load_plan(&p.to_string()).expect("valid").plan
}

fn explain_one(plan: &Plan, id: &str) -> (Schedule, Explanation) {
    let s = schedule(plan).expect("schedules");
    let opts = ExplainOptions {
        activity: Some(id.into()),
        no_suggestions: false,
    };
    let mut ex = explain(plan, &s, &opts).expect("explains");
    (s, ex.remove(0))
}

fn culprits(plan: &Plan, ex: &Explanation) -> Vec<(String, usize, &'static str)> {
    ex.culprits
        .iter()
        .map(|c| {
            (
                plan.activities[c.activity].id.clone(),
                c.step,
                c.blame.name(),
            )
        })
        .collect()
}

fn c(id: &str, step: usize, cat: &'static str) -> (String, usize, &'static str) {
    (id.to_string(), step, cat)
}

#[test]
fn uhf_pass_against_the_window() {
    let p = plan(
        json!({}),
        json!([
            { "id": "uhf_pass", "priority": 1, "duration": 600, "awake": "any", "comm_kind": "uhf",
              "windows": [ { "start": 1000, "end": 1000 } ] },
            // Execution allows [1100, 1400]; the pass [1000, 1600) forbids starts in
            // (700, 1600). Alone (k = 0) it fits, after step 1 it does not.
            { "id": "obs", "priority": 2, "duration": 300, "awake": "any", "uhf_interactions": [],
              "windows": [ { "start": 1100, "end": 1400 } ] }
        ]),
    );
    let (_, ex) = explain_one(&p, "obs");
    assert_eq!(ex.phase, Some(Phase::ValidIntervals));
    assert_eq!(ex.failure_step, Some(1));
    assert_eq!(ex.conflicts, vec![vec![Category::Execution, Category::Uhf]]);
    assert_eq!(culprits(&p, &ex), vec![c("uhf_pass", 1, "uhf")]);
    // Relaxing the window: 700 is the allowed start nearest the preferred 1100.
    let witness = |cats: &[Category]| {
        ex.relaxations
            .iter()
            .find(|r| r.categories == cats)
            .map(|r| r.witness)
    };
    assert_eq!(witness(&[Category::Execution]), Some(700));
    assert_eq!(witness(&[Category::Uhf]), Some(1100));
    // A verified suggestion widens the window to 700.
    assert!(
        ex.suggestions
            .iter()
            .any(|s| s.description.contains("start at 700")),
        "{:?}",
        ex.suggestions
    );
}

#[test]
fn dependency_window_and_unit_resource_conflict_together() {
    let p = plan(
        json!({}),
        json!([
            { "id": "drive", "priority": 1, "duration": 2000, "awake": "any", "resources": ["mobility"],
              "windows": [ { "start": 0, "end": 0 } ] },
            { "id": "arm_task", "priority": 2, "duration": 600, "awake": "any", "resources": ["arm"],
              "windows": [ { "start": 2000, "end": 2000 } ] },
            // Execution [1500, 2400]; after drive: >= 2000; arm busy [2000, 2600):
            // starts (1800, 2600) forbidden. Every pair intersects, all three do not.
            // k = 0: drive pending (excluded), arm free -> fits. k = 1: [2000, 2400]
            // fits. k = 2: fails.
            { "id": "img", "priority": 3, "duration": 200, "awake": "any", "resources": ["arm"],
              "windows": [ { "start": 1500, "end": 2400 } ], "after": [ { "activity": "drive" } ] }
        ]),
    );
    let (_, ex) = explain_one(&p, "img");
    assert_eq!(ex.phase, Some(Phase::ValidIntervals));
    assert_eq!(ex.failure_step, Some(2));
    assert_eq!(
        ex.conflicts,
        vec![vec![
            Category::Execution,
            Category::Dependency,
            Category::UnitResource
        ]]
    );
    let mut blamed = culprits(&p, &ex);
    blamed.sort();
    assert_eq!(
        blamed,
        vec![
            c("arm_task", 2, "unit_resource"),
            c("drive", 1, "dependency")
        ]
    );
    let witness = |cats: &[Category]| {
        ex.relaxations
            .iter()
            .find(|r| r.categories == cats)
            .map(|r| r.witness)
    };
    assert_eq!(witness(&[Category::Execution]), Some(2600));
    assert_eq!(witness(&[Category::Dependency]), Some(1500));
    assert_eq!(witness(&[Category::UnitResource]), Some(2000));
}

#[test]
fn unsatisfied_state_requirement() {
    let p = plan(
        json!({ "states": { "arm": { "values": ["stowed", "unstowed"], "initial": "stowed" } } }),
        json!([
            { "id": "unstow", "priority": 1, "duration": 500, "awake": "any",
              "windows": [ { "start": 1000, "end": 1000 } ],
              "effects": [ { "state": "arm", "value": "unstowed" } ] },
            { "id": "stow", "priority": 2, "duration": 500, "awake": "any",
              "windows": [ { "start": 3000, "end": 3000 } ],
              "effects": [ { "state": "arm", "value": "stowed" } ] },
            // Unstowed on [1500, 3500): a 1600 s task fits only at starts 1500..1900,
            // but its window starts at 2000. k = 0: the requirement is excluded
            // (unstow pending); k = 1: unstowed from 1500 on, fits; k = 2: fails.
            { "id": "task", "priority": 3, "duration": 1600, "awake": "any",
              "windows": [ { "start": 2000, "end": 4000 } ],
              "requires": [ { "state": "arm", "value": "unstowed" } ] }
        ]),
    );
    let (_, ex) = explain_one(&p, "task");
    assert_eq!(ex.phase, Some(Phase::ValidIntervals));
    assert_eq!(ex.failure_step, Some(2));
    assert_eq!(
        ex.conflicts,
        vec![vec![Category::Execution, Category::StateRequirement]]
    );
    assert_eq!(culprits(&p, &ex), vec![c("stow", 2, "state_requirement")]);
}

#[test]
fn state_of_charge() {
    // 144 W for 100 s = 4 Wh; 72 W for 100 s = 2 Wh. Battery 10 -> 6 after big; x
    // would take it to 4 < 5.
    let p = plan(
        json!({ "battery": { "capacity": 10.0, "initial": 10.0, "min_soc": 5.0 } }),
        json!([
            { "id": "big", "priority": 1, "duration": 100, "awake": "any", "energy_rate": 144.0,
              "windows": [ { "start": 0, "end": 0 } ] },
            { "id": "x", "priority": 2, "duration": 100, "awake": "any", "energy_rate": 72.0,
              "windows": [ { "start": 500, "end": 900 } ] }
        ]),
    );
    let (s, ex) = explain_one(&p, "x");
    assert_eq!(ex.phase, Some(Phase::Placement));
    assert_eq!(ex.failure_step, Some(1));
    assert!(!ex.reasons.is_empty());
    for r in &ex.reasons {
        // Lowest charge 4 Wh = 14_400_000 mJ, reached at the end of x.
        assert_eq!(
            r.reason,
            Phase2Reason::MinSoc {
                at: r.probe + 100,
                soc_mj: 14_400_000
            }
        );
    }
    assert_eq!(culprits(&p, &ex), vec![c("big", 1, "min_soc")]);
    assert!(
        ex.suggestions
            .iter()
            .any(|s| s.description == "Lower the minimum state of charge to 4 Wh")
    );
    // The plot query: energy used up to 1000 after step 1 (the full run has x failed).
    let (from, users) = energy_consumers(&s, 1, 1000, false);
    assert_eq!(from, 0);
    assert_eq!(users.len(), 1);
    assert_eq!(users[0].amount, 144_000 * 100);
}

#[test]
fn peak_power() {
    let p = plan(
        json!({ "power": { "rtg": 0.0, "asleep": 10.0, "awake": 10.0, "max_peak": 100.0 } }),
        json!([
            { "id": "heater", "priority": 1, "duration": 1000, "awake": "any", "peak_power": 60.0,
              "windows": [ { "start": 0, "end": 0 } ] },
            // 10 + 60 + 40 = 110 W > 100 W at every start in [0, 500].
            { "id": "y", "priority": 2, "duration": 100, "awake": "any", "peak_power": 40.0,
              "windows": [ { "start": 0, "end": 500 } ] }
        ]),
    );
    let (s, ex) = explain_one(&p, "y");
    assert_eq!(ex.phase, Some(Phase::Placement));
    assert_eq!(ex.failure_step, Some(1));
    assert!(ex.reasons.iter().all(|r| matches!(
        r.reason,
        Phase2Reason::MaxPeakPower {
            peak_mw: 110_000,
            ..
        }
    )));
    assert_eq!(culprits(&p, &ex), vec![c("heater", 1, "max_peak_power")]);
    assert!(
        ex.suggestions
            .iter()
            .any(|s| s.description == "Raise the peak power limit to 110 W")
    );
    let users = peak_users(&s, 2, 50);
    assert_eq!(users.len(), 1);
    assert_eq!(users[0].amount, 60_000);
}

#[test]
fn preheat_operability() {
    let p = plan(
        json!({ "local_time": { "sol_length": 10000, "offset": 0 },
                "thermal_zones": { "arm": { "preheat": [ { "from": 0, "duration": 800 } ],
                    "preheat_power": 40.0, "maintenance_power": 10.0,
                    "operable": [ { "from": 1000, "to": 5000 } ] } } }),
        json!([
            // Preheat would start at s - 800 in [400, 900]: before the operable 1000.
            { "id": "z", "priority": 1, "duration": 100, "awake": "any", "thermal_zones": ["arm"],
              "windows": [ { "start": 1200, "end": 1700 } ] }
        ]),
    );
    let (s, ex) = explain_one(&p, "z");
    assert_eq!(ex.phase, Some(Phase::Placement));
    assert_eq!(ex.failure_step, Some(0));
    assert!(ex.culprits.is_empty());
    assert!(ex
        .reasons
        .iter()
        .all(|r| matches!(r.reason, Phase2Reason::PreheatOperability { zone: 0, preheat_start } if preheat_start == r.probe - 800)));
    assert!(
        ex.suggestions
            .iter()
            .any(|s| s.description.starts_with("Allow arm heating from")),
        "{:?}",
        ex.suggestions
    );
    // The inspector queries.
    let v = valid_intervals_at(&s, 0, 0, None);
    assert_eq!(v.len(), Category::ALL.len());
    let partial = partial_schedule(&s, 0);
    assert_eq!(partial.pending, vec![0]);
}

#[test]
fn dependency_and_group_phases() {
    let p = plan(
        json!({}),
        json!([
            { "id": "a", "priority": 1, "duration": 100, "awake": "any", "windows": [ { "start": 9950, "end": 9950 } ] },
            { "id": "b", "priority": 2, "duration": 100, "awake": "any", "after": [ { "activity": "a" } ] },
            { "id": "g1", "priority": 3, "duration": 100, "awake": "any", "group": "g" },
            { "id": "g2", "priority": 4, "duration": 100, "awake": "any", "group": "g" }
        ]),
    );
    let (_, ex) = explain_one(&p, "b");
    assert_eq!(ex.phase, Some(Phase::Dependency));
    assert_eq!(ex.failure_step, Some(1));
    assert_eq!(culprits(&p, &ex), vec![c("a", 1, "dependency")]);
    let (_, ex) = explain_one(&p, "g2");
    assert_eq!(ex.phase, Some(Phase::Group));
    assert_eq!(ex.failure_step, Some(3));
    assert_eq!(culprits(&p, &ex), vec![c("g1", 3, "group")]);
    assert!(
        ex.suggestions
            .iter()
            .any(|s| s.set.get("group") == Some(&Value::Null))
    );
}

/// An activity that depends on one later in the step order fails before
/// that one is tried: the note says so (not that it did not get scheduled),
/// and scheduling it first, by priority, is a verified suggestion.
#[test]
fn a_dependency_later_in_step_order_is_said_so_and_moved_first() {
    let p = plan(
        json!({}),
        json!([
            { "id": "img", "priority": 2, "duration": 100, "awake": "any",
              "after": [ { "activity": "drive" } ] },
            { "id": "drive", "priority": 5, "duration": 1000, "awake": "any" }
        ]),
    );
    let (s, ex) = explain_one(&p, "img");
    assert_eq!(ex.phase, Some(Phase::Dependency));
    // drive is placed, at step 2, after img failed at step 1.
    assert!(s.placement(1).is_some());
    let notes = solscope_engine::explanation_notes(&p, &s.problem, &ex);
    assert_eq!(
        notes[0],
        "img must come after drive, but drive comes later in step order (priority 5), so it \
         cannot have run first; img cannot be scheduled."
    );
    assert!(notes.iter().all(|n| !n.contains("did not get scheduled")));
    let first = ex
        .suggestions
        .iter()
        .find(|x| x.target == "activity:drive")
        .expect("the reordering is suggested");
    assert_eq!(
        first.description,
        "Schedule drive before img by giving it priority 1"
    );
    assert_eq!(first.set["priority"], json!(1));
    assert!(first.side_effects.is_empty());
    // Verified: with it, img schedules.
    let mut moved = p.clone();
    moved.activities[1].priority = 1;
    assert!(schedule(&moved).unwrap().placement(0).is_some());
    // The drop names why, too.
    assert!(ex.suggestions.iter().any(|x| x.description
        == "Drop the dependency of img on drive (which comes later in step order)"));
}

#[test]
fn a_dependency_is_loosened_before_it_is_dropped() {
    let p = plan(
        json!({}),
        json!([
            { "id": "drive", "priority": 1, "duration": 1000, "awake": "any", "windows": [ { "start": 0, "end": 0 } ] },
            { "id": "arm", "priority": 2, "duration": 500, "awake": "any", "resources": ["arm"],
              "windows": [ { "start": 1000, "end": 1000 } ] },
            // Within 200 s of the drive's end (1000..1200) the arm is busy until 1500.
            { "id": "img", "priority": 3, "duration": 100, "awake": "any", "resources": ["arm"],
              "after": [ { "activity": "drive", "max_delay": 200 } ] }
        ]),
    );
    let (_, ex) = explain_one(&p, "img");
    assert_eq!(
        ex.conflicts,
        vec![vec![Category::Dependency, Category::UnitResource]]
    );
    let first = &ex.suggestions[0];
    assert_eq!(
        first.description,
        "Loosen the dependency of img on drive to a delay of 0..500 s after it ends"
    );
    assert_eq!(
        first.set["after"],
        json!([{ "activity": "drive", "max_delay": 500 }])
    );
    assert!(first.side_effects.is_empty());
}

/// Every view names the same culprits: the text's "Involved" line lists exactly
/// `involved(ex)`, which the app's clickable list also shows (the
/// inspector used to list ten where the text named six).
#[test]
fn text_and_app_name_the_same_culprits() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let text = std::fs::read_to_string(root.join("assets/default-plan.json")).expect("read");
    let plan = load_plan(&text).expect("valid").plan;
    let s = schedule(&plan).expect("schedules");
    let opts = ExplainOptions {
        activity: None,
        no_suggestions: true,
    };
    let all = explain(&plan, &s, &opts).expect("explains");
    let many = all
        .iter()
        .find(|ex| ex.culprits.len() > solscope_engine::involved(ex).len())
        .expect("an explanation with more culprits than a view names");
    let named: Vec<String> = solscope_engine::involved(many)
        .iter()
        .map(|c| {
            format!(
                "{} (step {}",
                plan.activities[c.activity].display_name(),
                c.step
            )
        })
        .collect();
    let notes = solscope_engine::explanation_notes(&plan, &s.problem, many);
    let line = notes
        .iter()
        .find(|n| n.starts_with("Involved: "))
        .expect("an Involved line");
    assert_eq!(line.matches(" (step ").count(), named.len(), "{line}");
    for n in &named {
        assert!(line.contains(n.as_str()), "{n} missing from {line}");
    }
}

/// `preheat_outside_plan`: the window [100, 500] closes before an 800 s preheat
/// fits after the plan start, so every start fails; moving the window to open at
/// 800 fixes it (this failure once got no suggestion).
#[test]
fn preheat_outside_plan_suggests_a_later_window() {
    let p = plan(
        json!({ "local_time": { "sol_length": 10000, "offset": 0 },
                "thermal_zones": { "arm": { "preheat": [ { "from": 0, "duration": 800 } ],
                    "preheat_power": 40.0, "maintenance_power": 10.0 } } }),
        json!([
            { "id": "z", "priority": 1, "duration": 100, "awake": "any", "thermal_zones": ["arm"],
              "windows": [ { "start": 100, "end": 500 } ] }
        ]),
    );
    let (_, ex) = explain_one(&p, "z");
    assert_eq!(ex.phase, Some(Phase::Placement));
    assert!(
        ex.reasons
            .iter()
            .all(|r| matches!(r.reason, Phase2Reason::PreheatOutsidePlan { zone: 0, .. }))
    );
    let fix = ex
        .suggestions
        .iter()
        .find(|s| {
            s.description
                .starts_with("Move the windows of z to open no earlier than 800")
        })
        .unwrap_or_else(|| panic!("{:?}", ex.suggestions));
    assert_eq!(fix.set["windows"], json!([{ "start": 800, "end": 1200 }]));
}

/// `min_awake` with no room: the plan is 3000 s long and asks for awake periods of
/// 5000 s, so no start of the activity can have one; shortening `min_awake` to
/// what fits from its wakeup to the plan end fixes it.
#[test]
fn min_awake_without_room_suggests_a_shorter_one() {
    let p = plan(
        json!({ "horizon": { "start": 0, "end": 3000 },
                "sleep": { "wakeup_duration": 100, "shutdown_duration": 100, "min_awake": 5000 } }),
        json!([
            { "id": "m", "priority": 1, "duration": 200, "awake": "required",
              "windows": [ { "start": 500, "end": 900 } ] }
        ]),
    );
    let (_, ex) = explain_one(&p, "m");
    assert_eq!(ex.phase, Some(Phase::Placement));
    assert!(
        ex.reasons
            .iter()
            .all(|r| matches!(r.reason, Phase2Reason::MinAwake { sleep: None }))
    );
    let fix = ex
        .suggestions
        .iter()
        .find(|s| {
            s.description
                .starts_with("Shorten the minimum awake period to 2600 s")
        })
        .unwrap_or_else(|| panic!("{:?}", ex.suggestions));
    assert_eq!(fix.set["sleep"]["min_awake"], json!(2600));
}

/// The suggestion of `ex` whose description starts with `prefix`.
fn fix<'a>(ex: &'a Explanation, prefix: &str) -> &'a solscope_engine::Suggestion {
    ex.suggestions
        .iter()
        .find(|s| s.description.starts_with(prefix))
        .unwrap_or_else(|| panic!("no {prefix:?} in {:#?}", ex.suggestions))
}

/// `forced_sleep` against an awake period: `a` keeps the rover awake over
/// [1000, 4000) and `b` must run asleep inside it, so every start of `b` fails;
/// letting `b` run awake fixes it.
#[test]
fn forced_sleep_suggests_running_awake_or_asleep() {
    let p = plan(
        json!({}),
        json!([
            { "id": "a", "priority": 1, "duration": 3000, "awake": "required",
              "windows": [ { "start": 1000, "end": 1000 } ] },
            { "id": "b", "priority": 2, "duration": 500, "awake": "forbidden",
              "windows": [ { "start": 1500, "end": 2000 } ] }
        ]),
    );
    let (_, ex) = explain_one(&p, "b");
    assert_eq!(ex.phase, Some(Phase::Placement));
    assert!(
        ex.reasons
            .iter()
            .all(|r| matches!(r.reason, Phase2Reason::ForcedSleep { sleep: None }))
    );
    let f = fix(&ex, "Let b run awake or asleep");
    assert_eq!(f.set["awake"], json!("any"));
    assert!(f.side_effects.is_empty());
}

/// `forced_sleep` against a manual sleep: `s` must run asleep over [1000, 4000)
/// and `b` needs the rover awake inside it; letting either run awake or asleep
/// fixes it.
#[test]
fn forced_sleep_by_a_manual_sleep_suggests_either_activity_runs_awake() {
    let p = plan(
        json!({}),
        json!([
            { "id": "s", "priority": 1, "duration": 3000, "awake": "forbidden",
              "windows": [ { "start": 1000, "end": 1000 } ] },
            { "id": "b", "priority": 2, "duration": 500, "awake": "required",
              "windows": [ { "start": 1500, "end": 2000 } ] }
        ]),
    );
    let (_, ex) = explain_one(&p, "b");
    assert!(
        ex.reasons
            .iter()
            .all(|r| matches!(r.reason, Phase2Reason::ForcedSleep { sleep: Some(0) }))
    );
    fix(&ex, "Let b run awake or asleep");
    fix(&ex, "Let s run awake or asleep");
}

/// `min_sleep`: `q` is awake over [2000, 2500), `s` sleeps over [3000, 4000), and
/// `x` needs to be awake over [4100, 4300). With `min_sleep` 2000 the gap of 1600 s
/// after `q` must be merged, through `s`; with `min_sleep` 1600 it need not (a gap
/// of exactly `min_sleep` is allowed): the least shortening.
#[test]
fn min_sleep_suggests_the_least_shorter_one() {
    let p = plan(
        json!({ "sleep": { "min_sleep": 2000 } }),
        json!([
            { "id": "q", "priority": 1, "duration": 500, "awake": "required",
              "windows": [ { "start": 2000, "end": 2000 } ] },
            { "id": "s", "priority": 2, "duration": 1000, "awake": "forbidden",
              "windows": [ { "start": 3000, "end": 3000 } ] },
            { "id": "x", "priority": 3, "duration": 200, "awake": "required",
              "windows": [ { "start": 4100, "end": 4100 } ] }
        ]),
    );
    let (_, ex) = explain_one(&p, "x");
    assert!(
        ex.reasons
            .iter()
            .all(|r| matches!(r.reason, Phase2Reason::MinSleep { sleep: 1 })),
        "{:?}",
        ex.reasons
    );
    let f = fix(
        &ex,
        "Shorten the minimum sleep between awake periods to 1600 s",
    );
    assert_eq!(f.set["sleep"]["min_sleep"], json!(1600));
}

/// `min_awake` against a manual sleep: `x` wakes at 2500 and an awake period of
/// 2000 s would run into `s` at 3000; one of 500 s ends as `s` begins.
#[test]
fn min_awake_against_a_sleep_suggests_the_least_shorter_one() {
    let p = plan(
        json!({ "sleep": { "min_awake": 2000 } }),
        json!([
            { "id": "s", "priority": 1, "duration": 1000, "awake": "forbidden",
              "windows": [ { "start": 3000, "end": 3000 } ] },
            { "id": "x", "priority": 2, "duration": 200, "awake": "required",
              "windows": [ { "start": 2500, "end": 2500 } ] }
        ]),
    );
    let (_, ex) = explain_one(&p, "x");
    assert!(
        ex.reasons
            .iter()
            .all(|r| matches!(r.reason, Phase2Reason::MinAwake { sleep: Some(0) })),
        "{:?}",
        ex.reasons
    );
    let f = fix(&ex, "Shorten the minimum awake period to 500 s");
    assert_eq!(f.set["sleep"]["min_awake"], json!(500));
}

/// `unit_resource` alone: `a` holds `r` over [1000, 2000) and `b` must start in
/// [1200, 1500); releasing `r` from `b` fixes it.
#[test]
fn unit_resource_alone_suggests_releasing_the_resource() {
    let p = plan(
        json!({}),
        json!([
            { "id": "a", "priority": 1, "duration": 1000, "resources": ["r"],
              "windows": [ { "start": 1000, "end": 1000 } ] },
            { "id": "b", "priority": 2, "duration": 100, "resources": ["r", "cam"],
              "windows": [ { "start": 1200, "end": 1500 } ] }
        ]),
    );
    let (_, ex) = explain_one(&p, "b");
    assert_eq!(
        ex.conflicts,
        vec![vec![Category::Execution, Category::UnitResource]]
    );
    let f = fix(&ex, "Let b run without holding r");
    assert_eq!(f.set["resources"], json!(["cam"]));
}

/// `state_effect` alone: `a` requires `mode = idle` over [1000, 2000) and `b`
/// would set it to `busy` inside; dropping that effect fixes it.
#[test]
fn state_effect_alone_suggests_dropping_the_effect() {
    let p = plan(
        json!({ "states": { "mode": { "initial": "idle", "values": ["idle", "busy"] } } }),
        json!([
            { "id": "a", "priority": 1, "duration": 1000,
              "requires": [ { "state": "mode", "value": "idle" } ],
              "windows": [ { "start": 1000, "end": 1000 } ] },
            { "id": "b", "priority": 2, "duration": 100,
              "effects": [ { "state": "mode", "value": "busy", "at": "start" } ],
              "windows": [ { "start": 1200, "end": 1500 } ] }
        ]),
    );
    let (_, ex) = explain_one(&p, "b");
    assert_eq!(
        ex.conflicts,
        vec![vec![Category::Execution, Category::StateEffect]]
    );
    let f = fix(&ex, "Drop the effect of b that sets mode to busy");
    assert_eq!(f.set["effects"], json!([]));
}

/// `uhf` alone: the UHF pass `c` runs over [1000, 2000) and `b` interacts with no
/// comm kind; letting it overlap every kind fixes it.
#[test]
fn uhf_alone_suggests_allowing_the_interaction() {
    let p = plan(
        json!({}),
        json!([
            { "id": "c", "priority": 1, "duration": 1000, "comm_kind": "uhf",
              "windows": [ { "start": 1000, "end": 1000 } ] },
            { "id": "b", "priority": 2, "duration": 100, "uhf_interactions": [],
              "windows": [ { "start": 1200, "end": 1500 } ] }
        ]),
    );
    let (_, ex) = explain_one(&p, "b");
    assert_eq!(ex.conflicts, vec![vec![Category::Execution, Category::Uhf]]);
    let f = fix(&ex, "Let b overlap comm activities of every kind");
    assert_eq!(f.set["uhf_interactions"], Value::Null);
}

/// No single edit works: `b` must follow `a` (ending at 5100) but its window ends
/// at 2000, and `c` holds `r` over the whole plan. It first fails after step 1
/// (`c` alone: the dependency on the later `a` does not count yet), where its
/// window and the resource conflict: relaxing the window alone reaches only 10000,
/// where `r` is free but the plan has ended, and releasing `r` alone leaves the
/// order after `a`. Both together place it at 5100, and the notes say so.
#[test]
fn no_single_fix_names_a_pair_that_works() {
    let p = plan(
        json!({}),
        json!([
            { "id": "c", "priority": 1, "duration": 10000, "resources": ["r"],
              "windows": [ { "start": 0, "end": 0 } ] },
            { "id": "a", "priority": 1, "duration": 100,
              "windows": [ { "start": 5000, "end": 5000 } ] },
            { "id": "b", "priority": 3, "duration": 100, "resources": ["r"],
              "after": [ { "activity": "a" } ],
              "windows": [ { "start": 1000, "end": 2000 } ] }
        ]),
    );
    let (s, ex) = explain_one(&p, "b");
    assert_eq!(ex.phase, Some(Phase::ValidIntervals));
    assert!(ex.suggestions.is_empty(), "{:#?}", ex.suggestions);
    // Verified: with both edits `b` is placed, after `a`.
    let both = ex.together.as_deref().expect("pairs were tried");
    let mut edited = serde_json::to_value(&p).unwrap();
    for e in both {
        let b = edited["activities"]
            .as_array_mut()
            .unwrap()
            .iter_mut()
            .find(|x| x["id"] == "b")
            .unwrap();
        for (k, v) in &e.set {
            b[k] = v.clone();
        }
    }
    let edited = load_plan(&edited.to_string()).unwrap().plan;
    assert_eq!(schedule(&edited).unwrap().placement(2), Some((5100, 5200)));
    let pair = ex.together.as_deref().expect("pairs were tried");
    let names: Vec<&str> = pair.iter().map(|x| x.description.as_str()).collect();
    assert_eq!(
        names,
        vec![
            "Widen window 1 of b to end at 10000",
            "Let b run without holding r"
        ]
    );
    let notes = solscope_engine::explanation_notes(&p, &s.problem, &ex);
    assert!(
        notes.iter().any(|n| n
            == "No single change fixes this; these two together do: Widen window 1 of b to end at 10000; and Let b run without holding r."),
        "{notes:#?}"
    );
}

/// `explain_each` without suggestions hands on each explanation as soon as the
/// replay has passed it (before the replay ends), in step order, and exactly as
/// `explain` gives them.
#[test]
fn explanations_stream_in_step_order_as_the_replay_passes_them() {
    let plan = solscope_engine::generate_plan(300, 1, 5);
    let sched = schedule(&plan).unwrap();
    let opts = ExplainOptions {
        activity: None,
        no_suggestions: true,
    };
    let whole = explain(&plan, &sched, &opts).unwrap();
    assert!(whole.len() > 10, "a plan with failures");
    // (explanations handed on so far, steps replayed) at each hand-over.
    let log = std::cell::RefCell::new(Vec::new());
    let replayed = std::cell::Cell::new(0usize);
    let mut streamed = Vec::new();
    solscope_engine::explain_each(
        &plan,
        &sched,
        &opts,
        &mut |done, total| {
            assert!(done <= total);
            replayed.set(done);
        },
        &mut |ex| {
            log.borrow_mut().push(replayed.get());
            streamed.push(ex);
        },
    )
    .unwrap();
    assert_eq!(
        serde_json::to_string(&streamed).unwrap(),
        serde_json::to_string(&whole).unwrap()
    );
    let log = log.into_inner();
    assert!(
        log[0] < sched.steps.len(),
        "the first explanation waited for the whole replay"
    );
    for (ex, &at) in streamed.iter().zip(&log) {
        // Known once the replay has probed it at its failure step.
        assert!(
            ex.failure_step.is_none_or(|k| at > k),
            "handed on before its failure step was replayed"
        );
    }
    assert!(log.windows(2).all(|w| w[0] <= w[1]));
}

/// The replay's lanes (one per thread) and the rendering in parallel do not
/// change the explanations or their order: on a plan of several replay blocks,
/// `explain_rendered` on 1, 2 and 3 threads renders what `explain` gives, in
/// the same order.
#[test]
fn explanations_do_not_depend_on_the_thread_count() {
    let plan = solscope_engine::generate_plan(1200, 3, 7);
    let sched = schedule(&plan).unwrap();
    let opts = ExplainOptions {
        activity: None,
        no_suggestions: true,
    };
    let whole: Vec<String> = explain(&plan, &sched, &opts)
        .unwrap()
        .iter()
        .map(|ex| serde_json::to_string(ex).unwrap())
        .collect();
    assert!(whole.len() > 100, "a plan with many failures");
    for threads in [1, 2, 3] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut rendered = Vec::new();
        pool.install(|| {
            solscope_engine::explain_rendered(
                &plan,
                &sched,
                &opts,
                |ex| serde_json::to_string(&ex).unwrap(),
                &mut |_, _| {},
                &mut |json| rendered.push(json),
            )
        })
        .unwrap();
        assert!(rendered == whole, "{threads} thread(s) changed the output");
    }
}

/// An empty `windows` list allows no start (the loader warns): removing it fixes
/// the failure.
#[test]
fn an_empty_windows_list_suggests_removing_it() {
    let p = plan(
        json!({}),
        json!([ { "id": "e", "priority": 1, "duration": 100, "windows": [] } ]),
    );
    let (_, ex) = explain_one(&p, "e");
    let f = fix(&ex, "Remove the empty windows list of e");
    assert_eq!(f.set["windows"], Value::Null);
    assert!(ex.together.is_none());
}

/// `handover_soc`: the optional `h` drains 200 Wh before the handover at 5000,
/// from 600 Wh, leaving 400 Wh against a handover minimum of 500 Wh: lowering
/// that minimum to 400 Wh, or making `h` mandatory, fixes it.
#[test]
fn handover_soc_suggests_a_lower_minimum_or_mandatory() {
    let p = plan(
        json!({ "battery": { "capacity": 1000.0, "initial": 600.0, "min_soc": 0.0 },
                "handover": { "time": 5000, "min_soc": 500.0 } }),
        json!([
            { "id": "h", "priority": 1, "duration": 3600, "energy_rate": 200.0,
              "mandatory": false, "windows": [ { "start": 0, "end": 0 } ] }
        ]),
    );
    let (_, ex) = explain_one(&p, "h");
    assert!(
        ex.reasons
            .iter()
            .all(|r| matches!(r.reason, Phase2Reason::HandoverSoc { .. })),
        "{:?}",
        ex.reasons
    );
    let f = fix(&ex, "Lower the handover state of charge to 400");
    assert_eq!(f.set["handover"]["min_soc"], json!(400.0));
    fix(&ex, "Make h mandatory");
}

/// `sequence_engines` alone: the plan has one engine, `a` holds it over
/// [1000, 2000) and `b` must start in [1200, 1500): a second engine fixes it.
#[test]
fn sequence_engines_alone_suggest_one_more() {
    let p = plan(
        json!({ "sequence_engines": 1 }),
        json!([
            { "id": "a", "priority": 1, "duration": 1000, "sequence_engines": 1,
              "windows": [ { "start": 1000, "end": 1000 } ] },
            { "id": "b", "priority": 2, "duration": 100, "sequence_engines": 1,
              "windows": [ { "start": 1200, "end": 1500 } ] }
        ]),
    );
    let (_, ex) = explain_one(&p, "b");
    assert_eq!(
        ex.conflicts,
        vec![vec![Category::Execution, Category::SequenceEngines]]
    );
    let f = fix(&ex, "Raise the number of sequence engines to 2");
    assert_eq!(f.set["sequence_engines"], json!(2));
}

/// `data_volume` alone: `a` stores 50 Mbit, and `b`, fixed at 3000, would add 60
/// to a 100 Mbit store: the least raise of the capacity is to 110 Mbit.
#[test]
fn data_volume_alone_suggests_the_least_larger_capacity() {
    let p = plan(
        json!({ "data": { "capacity": 100.0, "initial": 0.0 } }),
        json!([
            { "id": "a", "priority": 1, "duration": 1000, "data_rate": 0.05,
              "windows": [ { "start": 1000, "end": 1000 } ] },
            { "id": "b", "priority": 2, "duration": 1000, "data_rate": 0.06,
              "windows": [ { "start": 3000, "end": 3000 } ] }
        ]),
    );
    let (_, ex) = explain_one(&p, "b");
    assert_eq!(
        ex.conflicts,
        vec![vec![Category::Execution, Category::DataVolume]]
    );
    let f = fix(&ex, "Raise the data capacity to 110");
    let cap = f.set["data"]["capacity"].as_f64().unwrap();
    assert!((110.0..110.002).contains(&cap), "{cap}");
}

/// `data_volume` with more producers than it blames: twelve activities store
/// 1, 2, .., 12 Mbit (78 in all) before `b`, whose 30 Mbit would overflow a
/// 100 Mbit store. The conflict blames the ten that produced the most, largest
/// first, not every producer (which, when a store fills, made each failure's
/// explanation as long as the plan).
#[test]
fn data_volume_blames_the_ten_largest_producers() {
    let mut acts: Vec<Value> = (1..=12)
        .map(|k| {
            json!({ "id": format!("p{k}"), "priority": 1, "duration": 100,
                    "data_rate": 0.01 * f64::from(k),
                    "windows": [ { "start": 1000 + 200 * k, "end": 1000 + 200 * k } ] })
        })
        .collect();
    acts.push(
        json!({ "id": "b", "priority": 2, "duration": 1000, "data_rate": 0.03,
                      "windows": [ { "start": 5000, "end": 5000 } ] }),
    );
    let p = plan(
        json!({ "data": { "capacity": 100.0, "initial": 0.0 } }),
        Value::Array(acts),
    );
    let (_, ex) = explain_one(&p, "b");
    assert_eq!(
        ex.conflicts,
        vec![vec![Category::Execution, Category::DataVolume]]
    );
    let want: Vec<(String, usize, &str)> = (3..=12)
        .rev()
        .map(|k| c(&format!("p{k}"), k, "data_volume"))
        .collect();
    assert_eq!(culprits(&p, &ex), want);
}

/// The least lowering of `battery.min_soc` for an optional activity of a plan
/// with a handover limit (realistic profile, 300 activities over 3 sols, seed
/// 7: its one such suggestion). The search runs each value it tries from the
/// run of the last value that failed, replaying the steps whose record shows no
/// rejected start able to pass now; with a handover limit the record bounds the
/// lowest state of charge of the starts the handover limit lets pass. Debug
/// builds compare every replayed step with a search (recording the bound of a
/// `min_soc` range 277 Wh too low makes this test panic there); here, the value
/// found must also place the activity when the plan is edited and scheduled
/// from scratch.
#[test]
fn a_min_soc_lowering_with_a_handover_limit_places_the_activity() {
    use solscope_engine::{Profile, apply_edit, generate_plan_with};
    let plan = generate_plan_with(Profile::Realistic, 300, 3, 7);
    assert!(
        plan.handover.as_ref().is_some_and(|h| h.min_soc.is_some()),
        "the realistic profile sets a handover state of charge"
    );
    let (_, ex) = explain_one(&plan, "s0_f17");
    let lowerings: Vec<_> = ex
        .suggestions
        .iter()
        .filter(|s| s.set.contains_key("battery"))
        .collect();
    assert_eq!(lowerings.len(), 1, "{:?}", ex.suggestions);
    for s in lowerings {
        let edited = apply_edit(&plan, &s.target, &s.set).expect("a valid edit");
        let again = schedule(&edited).expect("schedules");
        assert!(
            again.placement(ex.activity).is_some(),
            "'{}' does not place the activity",
            s.description
        );
    }
}

/// An expanding activity that fails at every duration: its explanation is
/// that of its shortest duration, and the notes say so.
#[test]
fn a_failed_expanding_activity_says_which_duration_it_explains() {
    let p = plan(
        json!({ "power": { "rtg": 0.0, "asleep": 10.0, "awake": 10.0, "max_peak": 100.0 } }),
        json!([
            { "id": "heater", "priority": 1, "duration": 1000, "awake": "any", "peak_power": 60.0,
              "windows": [ { "start": 0, "end": 0 } ] },
            // 10 + 60 + 40 = 110 W > 100 W wherever it overlaps the heater,
            // and every start in [0, 500] does, at every duration.
            { "id": "y", "priority": 2, "duration": { "min": 120, "max": 600 }, "awake": "any",
              "peak_power": 40.0, "windows": [ { "start": 0, "end": 500 } ] }
        ]),
    );
    let (s, ex) = explain_one(&p, "y");
    assert_eq!(ex.phase, Some(Phase::Placement));
    assert_eq!(ex.duration, 120);
    let (notes, lead) = solscope_engine::explanation_notes_and_lead(&p, &s.problem, &ex);
    // The binary search tried longer durations too; their reasons are kept,
    // and each names its duration.
    let others: Vec<_> = ex.reasons.iter().filter(|r| r.duration != 120).collect();
    assert!(!others.is_empty(), "{:?}", ex.reasons);
    assert_eq!(
        notes[lead - 1],
        "y may last from 2 min to 10 min, and no duration fits; what follows is for its \
         shortest, 2 min, except where a line names the duration it was tried at.",
        "{notes:#?}"
    );
    // The reasons for 2 min come first and name no duration; the others
    // follow, each with its own.
    let own = ex.reasons.len() - others.len();
    let reasons = &notes[lead..lead + ex.reasons.len().min(8)];
    for (i, n) in reasons.iter().enumerate() {
        assert!(n.starts_with("For starts") || n.starts_with("At "), "{n}");
        assert_eq!(i >= own, n.contains(", lasting "), "{i}: {n}");
    }
    for r in &others {
        let line = solscope_engine::reason_line(&p, &s.problem, r, ex.duration);
        let named = format!(", lasting {}:", solscope_engine::format_span(r.duration));
        assert!(line.contains(&named), "{line}");
    }
    let first_own = ex.reasons.iter().find(|r| r.duration == 120).expect("one");
    let line = solscope_engine::reason_line(&p, &s.problem, first_own, ex.duration);
    assert!(!line.contains("lasting"), "{line}");
    // The same failure with a fixed duration gets no such note.
    let mut fixed = p.clone();
    fixed.activities[1].duration = solscope_engine::Duration::Fixed(120);
    let (s, ex) = explain_one(&fixed, "y");
    assert_eq!(ex.phase, Some(Phase::Placement));
    let notes = solscope_engine::explanation_notes(&fixed, &s.problem, &ex);
    assert!(!notes.iter().any(|n| n.contains("may last")), "{notes:#?}");
}
