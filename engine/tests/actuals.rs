//! The `solscope.actuals/1` document: strict reading with path-named errors, and
//! sampling from `duration_model`s (deterministic per seed, inside each range).

#![allow(clippy::panic, clippy::unwrap_used, clippy::expect_used)]
use serde_json::json;
use solscope_engine::{Actuals, Error, Plan, load_actuals, load_plan, sample_actuals};

fn plan() -> Plan {
    let text = json!({
        "format": "solscope.plan/1",
        "horizon": { "start": 0, "end": 30000 },
        "battery": { "capacity": 1000.0, "initial": 900.0, "min_soc": 100.0 },
        "power": { "rtg": 100.0, "asleep": 10.0, "awake": 60.0 },
        "activities": [
            { "id": "drive", "priority": 1, "duration": 3600,
              "duration_model": { "min": 2400, "max": 4200 } },
            { "id": "arm", "priority": 2, "duration": 600,
              "duration_model": { "min": 600, "max": 600 } },
            { "id": "flex", "priority": 3, "duration": { "min": 300, "max": 900 } },
            { "id": "fixed", "priority": 4, "duration": 100 }
        ]
    })
    .to_string();
    match load_plan(&text) {
        Ok(loaded) => loaded.plan,
        Err(e) => panic!("test plan: {e}"),
    }
}

fn refused(text: &str) -> (String, String) {
    match load_actuals(text, &plan()) {
        Err(Error::Invalid { path, reason }) => (path, reason),
        other => panic!("expected a path-named error for {text}, got {other:?}"),
    }
}

#[test]
fn reads_a_valid_document() {
    let text =
        r#"{ "format": "solscope.actuals/1", "durations": { "drive": 4000, "fixed": 150 } }"#;
    let actuals = load_actuals(text, &plan()).expect("valid");
    assert_eq!(actuals.durations.get("drive"), Some(&4000));
    assert_eq!(actuals.durations.get("fixed"), Some(&150));
    assert_eq!(actuals.durations.len(), 2);
}

#[test]
fn refuses_bad_documents_at_their_path() {
    let (path, reason) =
        refused(r#"{ "format": "solscope.actuals/1", "durations": { "rover": 10 } }"#);
    assert_eq!(
        (path.as_str(), reason.as_str()),
        ("durations.rover", "unknown activity \"rover\"")
    );
    let (path, _) = refused(r#"{ "format": "solscope.actuals/1", "durations": { "drive": 0 } }"#);
    assert_eq!(path, "durations.drive");
    let (path, _) =
        refused(r#"{ "format": "solscope.actuals/1", "durations": { "drive": 99999 } }"#);
    assert_eq!(path, "durations.drive");
    let (path, reason) =
        refused(r#"{ "format": "solscope.actuals/1", "durations": { "flex": 400 } }"#);
    assert_eq!(path, "durations.flex");
    assert!(reason.contains("expanding"), "{reason}");
    let (path, _) = refused(r#"{ "format": "solscope.plan/1", "durations": {} }"#);
    assert_eq!(path, "format");
    let (path, _) =
        refused(r#"{ "format": "solscope.actuals/1", "durations": { "drive": 4000.5 } }"#);
    assert_eq!(path, "durations.drive");
    let (path, reason) = refused(r#"{ "format": "solscope.actuals/1", "durations": {}, "x": 1 }"#);
    assert_eq!(path, "x");
    assert!(reason.contains("unknown field"), "{reason}");
    let (path, _) = refused(r#"{ "format": "solscope.actuals/1", "durations": {} } trailing"#);
    assert_eq!(path, "$");
}

#[test]
fn sampling_is_deterministic_and_inside_each_model() {
    let plan = plan();
    let mut seen = std::collections::BTreeSet::new();
    for seed in 0..200 {
        let a: Actuals = sample_actuals(&plan, seed);
        assert_eq!(
            a,
            sample_actuals(&plan, seed),
            "seed {seed} is not reproducible"
        );
        // Only activities with a model are listed, each inside its range.
        assert_eq!(a.durations.keys().collect::<Vec<_>>(), ["arm", "drive"]);
        let drive = a.durations["drive"];
        assert!((2400..=4200).contains(&drive), "seed {seed}: {drive}");
        assert_eq!(a.durations["arm"], 600);
        seen.insert(drive);
        // A sample reads back as a valid actuals document for the plan.
        let text = serde_json::to_string(&a).expect("serialises");
        assert_eq!(load_actuals(&text, &plan).expect("valid"), a);
    }
    // 200 draws from 1,801 values: far from constant.
    assert!(
        seen.len() > 150,
        "only {} distinct drive durations",
        seen.len()
    );
}
