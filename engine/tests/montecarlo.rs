//! Monte Carlo: byte-identical on 1 and 2 threads, shards merge into exactly the
//! one-machine summary, run `i` replays as one execution sampled with stream
//! `i` (the campaign resumes each run from the nominal run's shared prefix; a run
//! from the start gives the same record), and on a hand-built plan where one duration decides the outcome the
//! summary finds that duration and its threshold.
#![allow(clippy::panic, clippy::unwrap_used, clippy::expect_used)]

use serde_json::json;
use solscope_engine::{
    Campaign, MONTECARLO_RUNS_FORMAT, Plan, RunOutcome, RunRecord, RunsDoc, campaign,
    campaign_runs, execute, load_plan, load_plan_file, merge_parts, run_record, sample_run,
    summarize,
};

/// A drive of 2400..6000 s, then optional science that fits only when the drive
/// ends by 6200 (its window's last start that meets the cutoff), and a
/// mandatory stow after the science.
fn plan() -> Plan {
    let v = json!({
        "format": "solscope.plan/1",
        "name": "one duration decides",
        "horizon": { "start": 0, "end": 20000 },
        "battery": { "capacity": 2000.0, "initial": 1500.0, "min_soc": 500.0 },
        "power": { "rtg": 110.0, "asleep": 25.0, "awake": 150.0 },
        "activities": [
            { "id": "drive", "priority": 1, "duration": 3600,
              "duration_model": { "min": 2400, "max": 6000 },
              "windows": [{ "start": 1000, "end": 1000 }],
              "resources": ["mobility"], "energy_rate": 150.0 },
            { "id": "imaging", "priority": 2, "duration": 600,
              "duration_model": { "min": 300, "max": 900 },
              "windows": [{ "start": 9000, "end": 12000 }],
              "resources": ["mast"], "energy_rate": 20.0 },
            { "id": "science", "priority": 3, "mandatory": false, "duration": 1800,
              "windows": [{ "start": 4600, "end": 7000, "cutoff": 8000 }],
              "resources": ["arm"], "after": [{ "activity": "drive" }],
              "energy_rate": 40.0 }
        ]
    });
    load_plan(&v.to_string()).expect("valid").plan
}

fn all_runs(plan: &Plan, c: &Campaign) -> Vec<RunRecord> {
    let indices: Vec<u64> = (0..c.runs).collect();
    campaign_runs(plan, c, &indices, &|| {}, None)
        .unwrap()
        .unwrap()
}

fn summary_json(plan: &Plan, c: &Campaign) -> String {
    serde_json::to_string_pretty(&summarize(c, &all_runs(plan, c))).unwrap()
}

#[test]
fn one_duration_decides_and_the_summary_finds_it() {
    let plan = plan();
    let c = campaign(&plan, 11, 300, "plan").unwrap();
    let records = all_runs(&plan, &c);
    // Independently: science is lost exactly when the drive ends after 6200.
    for r in &records {
        let drive = r.durations[0];
        let lost = r.outcomes.as_bytes()[2] != b'c';
        assert_eq!(lost, 1000 + drive > 6200, "run {}: drive {drive}", r.run);
    }
    let s = summarize(&c, &records);
    let science = &s.activities[2];
    let lost = science.lost.as_ref().expect("science is lost in some runs");
    let expected = records.iter().filter(|r| r.durations[0] > 5200).count() as u64;
    assert_eq!(lost.runs, expected);
    assert_eq!(science.not_run, expected);
    let p = lost.predictor.as_ref().expect("a predictor");
    assert_eq!(p.activity, "drive");
    assert_eq!(p.direction, "above");
    // The best threshold lies between the longest kept drive and the shortest
    // lost one: the largest drawn duration <= 5200.
    let kept_max = records
        .iter()
        .map(|r| r.durations[0])
        .filter(|&d| d <= 5200)
        .max()
        .unwrap();
    assert_eq!(p.threshold, kept_max);
    assert_eq!((p.lost_when, p.runs_when), (expected, expected));
    assert!((p.accuracy - 1.0).abs() < 1e-12);
    // The cause, counted over the lost runs.
    assert_eq!(lost.causes.len(), 1);
    assert_eq!(lost.causes[0].runs, expected);
    assert!(
        lost.causes[0].cause.starts_with("valid_intervals"),
        "{:?}",
        lost.causes
    );
    // Imaging never depends on the drive: always completed, never lost.
    assert_eq!(s.activities[1].completed, 300);
    assert!(s.activities[1].lost.is_none());
}

#[test]
fn byte_identical_on_one_and_two_threads() {
    let plan = plan();
    let c = campaign(&plan, 5, 120, "plan").unwrap();
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| summary_json(&plan, &c))
    };
    let one = on(1);
    assert_eq!(one, on(2));
    assert_eq!(one, on(2), "and again");
    // Another seed draws other durations.
    let other = campaign(&plan, 6, 120, "plan").unwrap();
    assert_ne!(one, summary_json(&plan, &other));
}

#[test]
fn shards_merge_into_the_one_machine_summary() {
    let plan = plan();
    let c = campaign(&plan, 3, 50, "plan").unwrap();
    let whole = summary_json(&plan, &c);
    let k = 3u64;
    let parts: Vec<RunsDoc> = (0..k)
        .rev()
        .map(|i| {
            let indices: Vec<u64> = (i..c.runs).step_by(k as usize).collect();
            let records = campaign_runs(&plan, &c, &indices, &|| {}, None)
                .unwrap()
                .unwrap();
            // Through JSON, as the parts travel between machines.
            let doc = RunsDoc {
                format: MONTECARLO_RUNS_FORMAT.into(),
                campaign: c.clone(),
                shard: (i, k),
                records,
            };
            serde_json::from_str(&serde_json::to_string(&doc).unwrap()).unwrap()
        })
        .collect();
    let (campaign2, records) = merge_parts(&parts).unwrap();
    assert_eq!(
        serde_json::to_string_pretty(&summarize(&campaign2, &records)).unwrap(),
        whole
    );
    // A missing shard, a duplicated one and another campaign's part are refused.
    assert!(merge_parts(&parts[..2]).is_err());
    let mut twice = parts.clone();
    twice.push(parts[0].clone());
    assert!(merge_parts(&twice).is_err());
    let mut foreign = parts.clone();
    foreign[1].campaign.seed = 4;
    assert!(merge_parts(&foreign).is_err());
}

#[test]
fn a_run_replays_as_one_sampled_execution() {
    let plan = plan();
    let c = campaign(&plan, 9, 20, "plan").unwrap();
    let records = all_runs(&plan, &c);
    for r in [&records[0], &records[7], &records[19]] {
        let ex = execute(&plan, &sample_run(&plan, 9, r.run)).unwrap();
        let spans: Vec<Option<(i64, i64)>> = ex.activities.iter().map(|a| a.actual).collect();
        assert_eq!(spans, r.spans);
        let outcomes: String = ex
            .activities
            .iter()
            .map(|a| match a.outcome {
                RunOutcome::Completed => 'c',
                RunOutcome::Aborted => 'a',
                RunOutcome::NotRun => 'n',
            })
            .collect();
        assert_eq!(outcomes, r.outcomes);
    }
}

#[test]
fn runs_resumed_from_the_nominal_prefix_equal_runs_from_the_start() {
    let bundled = load_plan_file(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../assets/default-plan.json"
    )))
    .unwrap()
    .plan;
    for (plan, runs) in [(plan(), 40u64), (bundled, 12)] {
        let c = campaign(&plan, 21, runs, "plan").unwrap();
        let resumed = all_runs(&plan, &c);
        for r in &resumed {
            assert_eq!(*r, run_record(&plan, &c, r.run).unwrap(), "run {}", r.run);
        }
    }
}
