//! The derived values' workers: results kept only for their key, bounded
//! memory, free slack filled in, stopped and resumed.

use solscope_engine::RunOutcome;

use super::super::execution::ActualsSource;
use super::execution::KEPT_CYCLE_RUNS;
use super::*;

fn plan() -> Plan {
    let text = include_str!("../../../assets/execution-examples/uncertain-drive.json");
    solscope_engine::load_plan(text).expect("example plan").plan
}

/// Reaps `cache` at `key` until its execution worker is done.
fn wait(cache: &mut ExecutionCache, key: ExecKey) {
    for _ in 0..2000 {
        cache.reap(key).expect("worker result");
        if cache.pending.is_none() {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    panic!("the worker never finished");
}

#[test]
fn an_execution_for_an_older_key_is_dropped() {
    let plan = plan();
    let mut cache = ExecutionCache::default();
    let old = ExecKey {
        revision: 0,
        actuals: 0,
    };
    let new = ExecKey {
        revision: 0,
        actuals: 1,
    };
    cache.request(&plan, &ActualsSource::Nominal, old, true);
    assert!(cache.busy());
    // The actuals changed while it ran: its result is not kept.
    wait(&mut cache, new);
    assert!(cache.run(old).is_none() && cache.run(new).is_none());
    cache.request(
        &plan,
        &ActualsSource::Sampled { seed: 7, run: 0 },
        new,
        true,
    );
    wait(&mut cache, new);
    let run = cache.run(new).expect("derived").as_ref().expect("executed");
    assert_eq!(run.actuals, solscope_engine::sample_actuals(&plan, 7));
    // The first cycle's run came with it; another cycle is derived on request.
    assert!(cache.cycle(new, 0).is_some());
    assert!(cache.cycle(new, 3).is_none());
    cache.request_cycle(new, 3, false);
    let three = cache.cycle(new, 3).expect("cycle 3");
    assert_eq!(three.index, 3);
    assert!(three.schedule.is_ok());
    cache.derive_view(new, 3, 1);
    assert_eq!(cache.view(new, 3, 1).map(|v| v.step), Some(1));
    assert!(cache.view(new, 3, 2).is_none());
    assert!(cache.cycle(old, 3).is_none(), "read back only for its key");
}

#[test]
fn at_most_a_bounded_number_of_cycle_runs_are_kept() {
    let plan = plan();
    let mut cache = ExecutionCache::default();
    let key = ExecKey {
        revision: 0,
        actuals: 0,
    };
    cache.request(&plan, &ActualsSource::Nominal, key, false);
    let n = match cache.run(key) {
        Some(Ok(run)) => run.execution.cycles.len(),
        _ => panic!("executed"),
    };
    assert!(n > KEPT_CYCLE_RUNS);
    for k in 0..n {
        cache.request_cycle(key, k, false);
        assert!(cache.cycle(key, k).is_some());
    }
    assert!(cache.cycles.len() <= KEPT_CYCLE_RUNS);
    assert!(cache.cycle(key, 0).is_some(), "the prediction is kept");
}

#[test]
fn why_an_activity_was_lost_is_explained_off_the_frame_for_its_key() {
    let mut plan = plan();
    plan.battery.min_soc = 950.0;
    let source = ActualsSource::File {
        path: "long.json".into(),
        text: r#"{"format": "solscope.actuals/1", "durations": {"drive": 6600}}"#.into(),
    };
    let key = ExecKey {
        revision: 0,
        actuals: 0,
    };
    let mut cache = ExecutionCache::default();
    cache.request(&plan, &source, key, false);
    let post = plan
        .activities
        .iter()
        .position(|a| a.id == "post_drive_imaging")
        .expect("activity");
    let drive = plan.activities.iter().position(|a| a.id == "drive");
    // A completed activity has nothing to explain.
    cache.request_loss(key, drive.expect("drive"), true);
    assert!(!cache.busy());
    cache.request_loss(key, post, true);
    for _ in 0..2000 {
        cache.reap(key).expect("worker result");
        if !cache.busy() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let loss = cache
        .loss(key, post)
        .expect("derived")
        .as_ref()
        .expect("explained");
    assert_eq!(loss.activity, post);
    assert_eq!(loss.outcome, RunOutcome::NotRun);
    let other = ExecKey {
        revision: 1,
        actuals: 0,
    };
    assert!(
        cache.loss(other, post).is_none(),
        "read back only for its key"
    );
}

/// Reaps `cache` at `revision` until no worker runs.
fn settle_flex(cache: &mut FlexCache, revision: u64) {
    for _ in 0..4000 {
        cache.reap(revision).expect("worker result");
        if !cache.busy() {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    panic!("the flex workers never finished");
}

#[test]
fn free_slack_fills_in_on_a_worker_stops_and_goes_on() {
    let text = include_str!("../../../assets/default-plan.json");
    let plan = solscope_engine::load_plan(text).expect("plan").plan;
    let analysis = Analysis::of(&plan).expect("scheduled");
    let mut cache = FlexCache::default();
    cache.request(&plan, &analysis, 0, true);
    settle_flex(&mut cache, 0);
    let p = cache.free_slack_progress(0).expect("first stage in");
    assert_eq!((p.done, p.running), (0, false));
    assert!(p.total > 0);
    // Started, then stopped at once: nothing is taken after the stop.
    cache.request_free_slack(0, 0.0);
    assert!(cache.busy() && cache.free_slack_progress(0).is_some_and(|p| p.running));
    cache.stop_free_slack();
    assert!(!cache.busy());
    let stopped = cache.free_slack_progress(0).expect("progress");
    assert!(!stopped.running && !stopped.complete());
    // Asked again, it goes on to the end.
    cache.request_free_slack(0, 0.0);
    settle_flex(&mut cache, 0);
    let done = cache.free_slack_progress(0).expect("progress");
    assert!(done.complete() && !done.running, "{done:?}");
    let flex = cache.get(0).expect("derived").as_ref().expect("computed");
    assert_eq!(**flex, solscope_engine::flex(&plan, &analysis.schedule));
    // Nothing left: no worker starts.
    cache.request_free_slack(0, 0.0);
    assert!(!cache.busy());
    // A newer revision drops the old worker and its values.
    cache.request(&plan, &analysis, 1, true);
    assert!(cache.get(1).is_none());
    settle_flex(&mut cache, 1);
    assert_eq!(cache.free_slack_progress(1).map(|p| p.done), Some(0));
}

#[test]
fn a_flexible_schedule_of_an_older_revision_is_dropped() {
    let plan = plan();
    let analysis = Analysis::of(&plan).expect("scheduled");
    let mut cache = FlexCache::default();
    cache.request(&plan, &analysis, 0, true);
    assert!(cache.busy());
    // One worker at a time: a request for a newer revision waits.
    cache.request(&plan, &analysis, 1, true);
    for _ in 0..2000 {
        cache.reap(1).expect("worker result");
        if !cache.busy() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    assert!(cache.get(0).is_none() && cache.get(1).is_none());
    cache.request(&plan, &analysis, 1, false);
    // In place, the free slack follows as the frame asks for it (shown).
    cache.fill_free_slack(1);
    let flex = cache.get(1).expect("derived").as_ref().expect("computed");
    assert_eq!(**flex, solscope_engine::flex(&plan, &analysis.schedule));
    assert!(cache.get(0).is_none(), "read back only for its revision");
}
