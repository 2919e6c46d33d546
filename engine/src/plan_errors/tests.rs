use super::*;
use crate::load::{load_plan, planner_words};

#[test]
fn plan_errors_reads_a_plan_that_does_not_parse_piece_by_piece() {
    let plan = r#"{"format":"solscope.plan/1","horizon":{"start":0,"end":100},
        "battery":{"capacity":10.0,"initial":"full","min_soc":1.0},
        "power":{"rtg":10.0,"asleep":1.0,"awake":2.0},"activities":[
        {"id":"a","priority":"high","duration":10},
        {"id":"b","priority":2,"duration":10},
        {"id":"c","priority":3,"duration":10,"awake":{"any":null}},
        {"id":"d","priority":4,"duration":10.5}]}"#;
    let errors: Vec<String> = plan_errors(plan).iter().map(|e| e.to_string()).collect();
    let first = load_plan(plan).expect_err("invalid").to_string();
    assert_eq!(errors[0], first, "led by load_plan's error");
    let paths: Vec<&str> = errors
        .iter()
        .map(|e| e.split(": ").next().unwrap_or(""))
        .collect();
    assert_eq!(
        paths,
        [
            // The shape check goes first in `load_plan`.
            "activities[2].awake",
            "battery.initial",
            "activities[0].priority",
            "activities[3].duration"
        ]
    );
    // Valid: none; not JSON: the one error.
    let valid = include_str!("../../../assets/examples/pitfall.json");
    assert!(plan_errors(valid).is_empty());
    assert_eq!(plan_errors("{").len(), 1);
    // Parsed: every semantic error.
    let bad = valid.replace("\"energy_rate\": 20.0", "\"energy_rate\": -20.0");
    let errors: Vec<String> = plan_errors(&bad).iter().map(|e| e.to_string()).collect();
    assert_eq!(
        errors,
        [
            "activities[0].energy_rate: must be >= 0 (got -20)",
            "activities[1].energy_rate: must be >= 0 (got -20)"
        ]
    );
}

/// A small valid plan with `activities` as given.
fn plan_with(activities: &str) -> String {
    format!(
        r#"{{"format":"solscope.plan/1","horizon":{{"start":0,"end":1000}},
        "battery":{{"capacity":10.0,"initial":5.0,"min_soc":1.0}},
        "power":{{"rtg":10.0,"asleep":1.0,"awake":2.0}},"activities":[{activities}]}}"#
    )
}

fn listed(text: &str) -> Vec<String> {
    plan_errors(text).iter().map(|e| e.to_string()).collect()
}

#[test]
fn type_errors_in_one_activity_and_an_unknown_id_are_listed_in_one_pass() {
    let text = plan_with(
        r#"{"id":"a","priority":1,"duration":10},
        {"id":"b","priority":"high","duration":"ten","after":[{"activity":"nobody"}]},
        {"id":"c","priority":3,"duration":10,"after":[{"activity":"ghost"},{"activity":"b"}]}"#,
    );
    assert_eq!(
        listed(&text),
        [
            "activities[1].priority: must be a whole number (got the text \"high\")",
            "activities[1].duration: must be a whole number of seconds or { \"min\": m, \"max\": M } \
             (got the text \"ten\")",
            // Checked on the activities that parsed (`b` did not: its id is
            // still known), then on the `after` written in the one that did not.
            "activities[2].after[0].activity: unknown activity \"ghost\"",
            "activities[1].after[0].activity: unknown activity \"nobody\"",
        ]
    );
    // The first is the one `load_plan` gives, in the same words.
    assert_eq!(
        load_plan(&text).expect_err("invalid").to_string(),
        listed(&text)[0]
    );
}

#[test]
fn semantic_errors_of_the_activities_that_parsed_keep_their_file_paths() {
    let text = plan_with(
        r#"{"id":"a","priority":true,"duration":10},
        {"id":"b","priority":2,"duration":-5},
        {"id":"b","priority":3,"duration":10,"windows":[{"start":50,"end":"x","cutoff":7.5}]},
        {"id":"b","priority":4,"duration":10}"#,
    );
    assert_eq!(
        listed(&text),
        [
            "activities[0].priority: must be a whole number (got true)",
            // Inside a field, by name.
            "activities[2].windows[0].cutoff: must be a whole number of seconds (got 7.5)",
            "activities[2].windows[0].end: must be a whole number of seconds (got the text \"x\")",
            "activities[1].duration: must be > 0 (got -5)",
            "activities[3].id: duplicate id \"b\" (first at activities[1])",
        ]
    );
}

#[test]
fn unknown_and_missing_fields_do_not_stop_the_reading() {
    let text = plan_with(
        r#"{"id":"a","prio":1,"duration":10,"sequence_engines":-1,"awake":"sometimes","mandatory":"no"}"#,
    );
    let errors = listed(&text);
    assert_eq!(errors.len(), 5, "{errors:#?}");
    assert!(errors[0].starts_with("activities[0].prio: unknown field `prio`"));
    assert_eq!(
        &errors[1..],
        [
            // In the format's field order.
            "activities[0]: missing field `priority`",
            "activities[0].mandatory: must be true or false (got the text \"no\")",
            "activities[0].sequence_engines: must be a whole number >= 0 (got -1)",
            "activities[0].awake: unknown variant `sometimes`, expected one of `required`, `forbidden`, `any`",
        ]
    );
}

#[test]
fn planner_words_name_no_rust_type() {
    for (path, serde, words) in [
        (
            "horizon.end",
            "invalid type: floating point `1e23`, expected i64",
            "must be a whole number of seconds (got 1e23)",
        ),
        (
            "battery.capacity",
            "invalid type: string \"NaN\", expected f64",
            "must be a number (got the text \"NaN\")",
        ),
        (
            "activities[0].resources[1]",
            "invalid type: integer `3`, expected a string",
            "must be text in double quotes (got 3)",
        ),
        (
            "activities[0].windows",
            "invalid type: map, expected a sequence",
            "must be a list [ … ] (got an object)",
        ),
        (
            "horizon",
            "invalid type: null, expected struct Horizon",
            "must be an object { … } (got null)",
        ),
        ("x", "unknown field `y`", "unknown field `y`"),
    ] {
        let said = planner_words(path, serde);
        assert_eq!(said, words);
        for rust in ["i64", "u32", "f64", "invalid type"] {
            assert!(!said.contains(rust), "{said}");
        }
    }
}
