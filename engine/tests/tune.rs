//! Priority tuning: on random small plans the exact mode's result equals a
//! brute-force enumeration done here (every permutation, realised with
//! priorities of this file's own, scored from `montecarlo`'s run records with
//! this file's own objective); the tuned plan differs only in priorities,
//! keeps every dependency's order and every pinned priority, and is never worse
//! on the tuning sample; the output is byte-identical on one and two threads;
//! the hand-built A-blocks-B case and the case where only the uncertain
//! duration makes an order better (`order-matters.json`) are fixed.
#![allow(clippy::panic, clippy::unwrap_used, clippy::expect_used)]

#[path = "gen/mod.rs"]
mod plangen;

use std::sync::atomic::AtomicBool;

use proptest::prelude::*;
use serde_json::{Value, json};
use solscope_engine::{
    Duration, DurationModel, Mode, Plan, Score, Stop, TuneOptions, Tuning, ValueMeasure, campaign,
    campaign_runs, load_plan, load_plan_file, tune, tuning_json, validate,
};

fn asset(path: &str) -> Plan {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(path);
    load_plan_file(&p).expect("bundled plan").plan
}

/// The step order the scheduler derives from the plan's priorities.
fn step_order(plan: &Plan) -> Vec<usize> {
    let mut o: Vec<usize> = (0..plan.activities.len()).collect();
    o.sort_by_key(|&i| (plan.activities[i].priority, i));
    o
}

fn pos(order: &[usize], a: usize) -> usize {
    order.iter().position(|&x| x == a).unwrap()
}

fn id_pos(plan: &Plan, order: &[usize], id: &str) -> usize {
    let a = plan.activities.iter().position(|x| x.id == id).unwrap();
    pos(order, a)
}

/// This file's objective, as a tuple compared greater-is-better: runs without
/// a broken limit, mandatory completions, value (integer values only), or the
/// completions in original step order, and minus the order changes.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Key(i64, u64, Vec<i64>, i64);

/// Scores `order` (plan indices in step order) of `plan` on runs `0..runs` of
/// `seed`: realised by giving place `k` priority `k`.
fn oracle_key(plan: &Plan, order: &[usize], seed: u64, runs: u64) -> Key {
    let mut p = plan.clone();
    for (k, &a) in order.iter().enumerate() {
        p.activities[a].priority = k as i64;
    }
    assert_eq!(step_order(&p), order);
    let runs = if plan.activities.iter().any(|a| a.duration_model.is_some()) {
        runs
    } else {
        1
    };
    let c = campaign(&p, seed, runs, "oracle").unwrap();
    let idx: Vec<u64> = (0..runs).collect();
    let records = campaign_runs(&p, &c, &idx, &|| {}, None).unwrap().unwrap();
    let done = |a: usize| {
        records
            .iter()
            .filter(|r| r.outcomes.as_bytes()[a] == b'c')
            .count() as u64
    };
    let breaking = records.iter().filter(|r| !r.violations.is_empty()).count() as i64;
    let mandatory = (0..plan.activities.len())
        .filter(|&a| plan.activities[a].mandatory)
        .map(done)
        .sum();
    let original = step_order(plan);
    let value = if plan.activities.iter().any(|a| a.value.is_some()) {
        vec![
            (0..plan.activities.len())
                .map(|a| plan.activities[a].value.unwrap_or(0.0) as i64 * done(a) as i64)
                .sum(),
        ]
    } else {
        original.iter().map(|&a| done(a) as i64).collect()
    };
    let mut changes = 0;
    for i in 0..order.len() {
        for j in i + 1..order.len() {
            if pos(&original, order[i]) > pos(&original, order[j]) {
                changes += 1;
            }
        }
    }
    Key(-breaking, mandatory, value, -changes)
}

/// The tuner's score in this file's terms.
fn key_of(s: &Score) -> Key {
    let value = match &s.value {
        ValueMeasure::Total(v) => vec![(v / 1_000_000) as i64],
        ValueMeasure::StepOrder(c) => c.iter().map(|&x| x as i64).collect(),
    };
    Key(
        -(s.runs_breaking as i64),
        s.mandatory_completed,
        value,
        -(s.changes as i64),
    )
}

/// Every permutation of `0..n`.
fn permutations(n: usize) -> Vec<Vec<usize>> {
    if n == 0 {
        return vec![Vec::new()];
    }
    let mut out = Vec::new();
    for p in permutations(n - 1) {
        for k in 0..=p.len() {
            let mut q = p.clone();
            q.insert(k, n - 1);
            out.push(q);
        }
    }
    out
}

/// Whether `order` keeps the original relative order of every pair linked by
/// `after`, and every pinned activity's place.
fn allowed(plan: &Plan, order: &[usize], pinned: &[usize]) -> bool {
    let original = step_order(plan);
    let deps = plan.activities.iter().enumerate().all(|(a, act)| {
        act.after.iter().all(|d| {
            let t = plan
                .activities
                .iter()
                .position(|x| x.id == d.activity)
                .unwrap();
            (pos(&original, t) < pos(&original, a)) == (pos(order, t) < pos(order, a))
        })
    });
    deps && pinned.iter().all(|&p| pos(order, p) == pos(&original, p))
}

fn options(runs: u64, budget: u64) -> TuneOptions<'static> {
    TuneOptions {
        runs,
        seed: 5,
        confirm_runs: runs,
        confirm_seed: 6,
        budget,
        ..TuneOptions::default()
    }
}

/// What every tuning keeps: only priorities change, dependencies keep their
/// order, pinned activities their priority, and the tuned order is never worse
/// on the tuning sample.
fn check_invariants(plan: &Plan, t: &Tuning, pinned: &[usize]) {
    let mut only_priorities = t.tuned_plan.clone();
    for (a, b) in only_priorities.activities.iter_mut().zip(&plan.activities) {
        a.priority = b.priority;
    }
    assert_eq!(&only_priorities, plan, "only priorities change");
    let order = step_order(&t.tuned_plan);
    assert_eq!(order, t.tuned, "the tuned plan realises the tuned order");
    assert!(allowed(plan, &order, pinned), "dependencies and pins kept");
    for &p in pinned {
        assert_eq!(
            t.tuned_plan.activities[p].priority,
            plan.activities[p].priority
        );
    }
    assert!(t.tuning_scores.tuned >= t.tuning_scores.original);
    assert!(t.evaluations <= t.budget);
    for c in &t.changes {
        assert_ne!(c.before, c.after);
        assert_eq!(t.tuned_plan.activities[c.activity].priority, c.after);
    }
}

/// A generated plan with durations made uncertain and values given, by the
/// draws: `models[i]` gives activity `i` (fixed durations only) a model
/// `[d/2, 2d]`; `values[i]` gives it a whole value, when `with_values`.
fn uncertain(text: &str, models: &[bool], values: &[u8], with_values: bool) -> Option<Plan> {
    let mut v: Value = serde_json::from_str(text).ok()?;
    let acts = v["activities"].as_array_mut()?;
    for (i, a) in acts.iter_mut().enumerate() {
        if let Some(d) = a["duration"].as_i64()
            && models.get(i).copied().unwrap_or(false)
        {
            a["duration_model"] = json!({"min": (d / 2).max(1), "max": d * 2});
        }
        if with_values {
            a["value"] = json!(f64::from(values.get(i).copied().unwrap_or(0) % 10));
        }
    }
    load_plan(&v.to_string()).ok().map(|l| l.plan)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// Exact mode returns the optimum of a brute-force enumeration.
    #[test]
    fn exact_mode_equals_brute_force(
        text in plangen::small_plan_text(),
        models in proptest::collection::vec(any::<bool>(), 6),
        values in proptest::collection::vec(any::<u8>(), 6),
        with_values in any::<bool>(),
    ) {
        let Some(plan) = uncertain(&text, &models, &values, with_values) else {
            return Ok(());
        };
        let n = plan.activities.len();
        prop_assume!(n <= 5);
        let t = tune(&plan, &options(3, 10_000)).unwrap();
        prop_assert_eq!(t.mode, Mode::Exact);
        prop_assert_eq!(t.stop, Stop::Finished);
        check_invariants(&plan, &t, &[]);
        let best = permutations(n)
            .into_iter()
            .filter(|o| allowed(&plan, o, &[]))
            .map(|o| oracle_key(&plan, &o, 5, 3))
            .max()
            .unwrap();
        prop_assert_eq!(&key_of(&t.tuning_scores.tuned), &best);
        prop_assert_eq!(&oracle_key(&plan, &t.tuned, 5, 3), &best);
    }

    /// With pins (priorities made distinct, so that every order keeping the
    /// pinned places is realisable): the same, over the orders that keep them.
    #[test]
    fn exact_mode_with_pins_equals_brute_force(
        text in plangen::small_plan_text(),
        models in proptest::collection::vec(any::<bool>(), 6),
        pin in 0usize..6,
    ) {
        let Some(mut plan) = uncertain(&text, &models, &[], false) else {
            return Ok(());
        };
        let n = plan.activities.len();
        prop_assume!((2..=5).contains(&n));
        for (k, a) in step_order(&plan).into_iter().enumerate() {
            plan.activities[a].priority = 10 * k as i64 - 7;
        }
        let pinned = vec![pin % n];
        let mut o = options(3, 10_000);
        o.pinned = vec![plan.activities[pin % n].id.clone()];
        let t = tune(&plan, &o).unwrap();
        check_invariants(&plan, &t, &pinned);
        let best = permutations(n)
            .into_iter()
            .filter(|o| allowed(&plan, o, &pinned))
            .map(|o| oracle_key(&plan, &o, 5, 3))
            .max()
            .unwrap();
        prop_assert_eq!(&key_of(&t.tuning_scores.tuned), &best);
    }
}

#[test]
fn a_blocks_b_is_fixed() {
    let plan = asset("assets/examples/pitfall.json");
    let t = tune(&plan, &options(10, 100)).unwrap();
    check_invariants(&plan, &t, &[]);
    // One run: the plan has no duration_model.
    assert_eq!((t.tuning.runs, t.held_out.runs), (1, 1));
    assert_eq!(t.tuned, [1, 0], "B first");
    assert_eq!(
        t.counts
            .iter()
            .map(|c| c.tuning_after.completed)
            .collect::<Vec<_>>(),
        [1, 1]
    );
    assert_eq!(t.counts[1].tuning_before.completed, 0);
    let b = t.changes.iter().find(|c| c.activity == 1).unwrap();
    let line = solscope_engine::change_line(&plan, &b.why);
    assert!(
        line.starts_with("moved ahead of A: it was lost in 100% of runs"),
        "{line}"
    );
    assert!(line.contains("now in 0%"), "{line}");
}

#[test]
fn order_matters_example_is_fixed_only_the_uncertain_part_by_the_sample() {
    let plan = asset("assets/tuning-examples/order-matters.json");
    let t = tune(&plan, &options(40, 1000)).unwrap();
    check_invariants(&plan, &t, &[]);
    assert_eq!(t.mode, Mode::Exact);
    // supercam first, then the mosaic: both fit.
    assert!(id_pos(&plan, &t.tuned, "supercam_target") < id_pos(&plan, &t.tuned, "mastcam_mosaic"));
    // The scan, worth more, goes before the image once the drive can run long.
    assert!(id_pos(&plan, &t.tuned, "sherloc_scan") < id_pos(&plan, &t.tuned, "watson_image"));
    let s = plan
        .activities
        .iter()
        .position(|a| a.id == "sherloc_scan")
        .unwrap();
    let c = t.counts[s];
    assert!(
        c.tuning_before.completed < 40 && c.tuning_after.completed == 40,
        "{c:?}"
    );
    assert!(t.held_out_no_worse());
    // Deterministically (predicted durations) both orders of the two tie: the
    // tuned order keeps the original one, and only the mosaic moves.
    let mut certain = plan.clone();
    for a in &mut certain.activities {
        a.duration_model = None;
    }
    for order in [[1, 0, 2, 3, 4], [1, 0, 2, 4, 3]] {
        let k = oracle_key(&certain, &order, 5, 1);
        assert_eq!(k.2, vec![12], "every activity completes: {order:?}");
    }
    let t = tune(&certain, &options(40, 1000)).unwrap();
    assert!(id_pos(&plan, &t.tuned, "watson_image") < id_pos(&plan, &t.tuned, "sherloc_scan"));
    assert_eq!(t.tuned, [1, 0, 2, 3, 4]);
}

#[test]
fn output_is_byte_identical_on_one_and_two_threads() {
    let run = |k: usize, plan: &Plan, o: &TuneOptions<'_>| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(k)
            .build()
            .unwrap()
            .install(|| tuning_json(plan, &tune(plan, o).unwrap()))
    };
    let plan = asset("assets/tuning-examples/order-matters.json");
    let o = options(20, 1000);
    let one = run(1, &plan, &o);
    assert_eq!(one, run(2, &plan, &o));
    assert!(one.contains("\"format\": \"solscope.tuning/1\""));
    // Evidence mode.
    let plan = order_matters_and_more();
    let o = options(4, 40);
    let one = run(1, &plan, &o);
    assert_eq!(one, run(2, &plan, &o));
    assert!(one.contains("\"mode\": \"evidence\""), "{one}");
}

/// `order-matters.json` with six more activities, each on its own resource,
/// that fit anywhere: more than eight can move, so the evidence mode runs.
fn order_matters_and_more() -> Plan {
    let mut plan = asset("assets/tuning-examples/order-matters.json");
    let mut extra = plan.activities[0].clone();
    for k in 0..6 {
        extra.id = format!("extra_{k}");
        extra.name = None;
        extra.priority = 10 + k;
        extra.duration = Duration::Fixed(600);
        extra.windows = None;
        extra.resources = vec![format!("unit_{k}")];
        extra.energy_rate = 5.0;
        extra.value = Some(1.0);
        extra.duration_model = (k % 2 == 0).then_some(DurationModel { min: 300, max: 900 });
        plan.activities.push(extra.clone());
    }
    validate(&plan).unwrap();
    plan
}

#[test]
fn evidence_mode_keeps_the_rules_and_is_never_worse() {
    let plan = order_matters_and_more();
    let id = |x: &str| plan.activities.iter().position(|a| a.id == x).unwrap();
    for pinned in [vec![], vec![id("drive"), id("extra_3")]] {
        let mut o = options(4, 40);
        o.pinned = pinned
            .iter()
            .map(|&p: &usize| plan.activities[p].id.clone())
            .collect();
        let t = tune(&plan, &o).unwrap();
        assert_eq!(t.mode, Mode::Evidence);
        assert!(t.movable > 8);
        check_invariants(&plan, &t, &pinned);
        // Both fixes of the example are found from the evidence.
        assert!(
            id_pos(&plan, &t.tuned, "supercam_target") < id_pos(&plan, &t.tuned, "mastcam_mosaic")
        );
        assert!(id_pos(&plan, &t.tuned, "sherloc_scan") < id_pos(&plan, &t.tuned, "watson_image"));
        assert!(t.tuning_scores.tuned > t.tuning_scores.original);
    }
}

#[test]
fn cancel_keeps_the_original_and_says_so() {
    let plan = asset("assets/tuning-examples/order-matters.json");
    let stop = AtomicBool::new(true);
    let mut o = options(10, 1000);
    o.cancel = Some(&stop);
    let t = tune(&plan, &o).unwrap();
    assert_eq!(t.stop, Stop::Cancelled);
    assert_eq!(t.evaluations, 1);
    assert_eq!(t.tuned, t.original);
    assert!(t.changes.is_empty());
}

#[test]
fn options_and_values_are_checked_with_paths() {
    let plan = asset("assets/tuning-examples/order-matters.json");
    let err = |o: TuneOptions<'_>| tune(&plan, &o).unwrap_err().to_string();
    let mut o = options(10, 100);
    o.confirm_runs = 5;
    assert!(err(o).starts_with("confirm_runs: "));
    let mut o = options(10, 100);
    o.confirm_seed = o.seed;
    assert!(err(o).starts_with("confirm_seed: "));
    let mut o = options(10, 100);
    o.pinned = vec!["drive".into(), "rover".into()];
    assert_eq!(err(o), "pinned[1]: unknown activity \"rover\"");
    let mut v: Value = serde_json::to_value(&plan).unwrap();
    v["activities"][3]["value"] = json!(-1.0);
    let e = load_plan(&v.to_string()).unwrap_err().to_string();
    assert_eq!(e, "activities[3].value: must be >= 0 (got -1)");
    // A plan saved again keeps its values, and one without stays without.
    let back = serde_json::to_value(&plan).unwrap();
    assert_eq!(back["activities"][0]["value"], json!(2.0));
    assert!(back["activities"][2].get("value").is_none());
}

/// How long tuning takes on the bundled plan with default options (and what
/// it finds): `cargo test --release -p solscope-engine --test tune --
/// --ignored --nocapture`.
#[test]
#[ignore = "a measurement, minutes long"]
fn timing_on_the_bundled_plan() {
    let plan = asset("assets/tuning-examples/order-matters.json");
    let o = TuneOptions::default();
    println!("{}", tuning_json(&plan, &tune(&plan, &o).unwrap()));
    let plan = asset("assets/default-plan.json");
    let report = |n: u64, s: &Score| {
        eprintln!(
            "  {n} evaluations, best {:?}",
            (s.runs_breaking, s.mandatory_completed, s.changes)
        )
    };
    let o = TuneOptions {
        progress: Some(&report),
        ..TuneOptions::default()
    };
    let start = std::time::Instant::now();
    let t = tune(&plan, &o).unwrap();
    let took = start.elapsed();
    println!("{}", tuning_json(&plan, &t));
    println!(
        "default plan, {:?}: {:.1} s, {} evaluations, stop {:?}, {} threads",
        (o.runs, o.confirm_runs, o.budget),
        took.as_secs_f64(),
        t.evaluations,
        t.stop,
        rayon::current_num_threads()
    );
}
