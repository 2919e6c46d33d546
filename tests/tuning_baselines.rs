//! The baselines of the tuning bench (`benches/scale/tuning.rs`, compiled in
//! here): their orders keep every dependency, the mandatory-first order puts
//! what mandatory activities need first, the hill climb spends its budget and
//! never ends below the original on the tuning sample, and a quick comparison
//! on a generated plan with duration models runs all three methods.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

#[allow(dead_code)]
#[path = "../benches/scale/tuning.rs"]
mod tuning;

use solscope_engine::{OrderScorer, Plan};

/// Whether `order` keeps every `before` pair of the scorer.
fn keeps_dependencies(s: &OrderScorer<'_>, order: &[usize]) -> bool {
    let mut pos = vec![usize::MAX; order.len()];
    for (k, &a) in order.iter().enumerate() {
        pos[a] = k;
    }
    (0..order.len()).all(|a| s.before(a).iter().all(|&b| pos[b] < pos[a]))
}

fn plan() -> Plan {
    tuning::generated(40, 2)
}

#[test]
fn random_orders_keep_the_dependencies_and_differ() {
    let plan = plan();
    let s = OrderScorer::new(&plan);
    assert!(
        (0..plan.activities.len()).any(|a| !s.before(a).is_empty()),
        "the plan has dependencies"
    );
    let mut rng = tuning::Rng::new(1);
    let orders: Vec<Vec<usize>> = (0..20)
        .map(|_| tuning::random_order(&s, &mut rng))
        .collect();
    for o in &orders {
        let mut sorted = o.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..plan.activities.len()).collect::<Vec<_>>());
        assert!(keeps_dependencies(&s, o));
        assert!(s.allows(o));
    }
    assert!(orders.iter().any(|o| o != &orders[0]), "random orders vary");
}

#[test]
fn mandatory_first_keeps_dependencies_and_puts_the_mandatory_first() {
    let plan = plan();
    let s = OrderScorer::new(&plan);
    let order = tuning::mandatory_first(&plan, &s);
    assert!(s.allows(&order));
    // Once an activity that no mandatory one needs is placed, no mandatory
    // activity follows.
    let needed = |a: usize| {
        let mut stack = vec![a];
        let mut seen = vec![false; plan.activities.len()];
        while let Some(x) = stack.pop() {
            if plan.activities[x].mandatory {
                return true;
            }
            for (y, seen_y) in seen.iter_mut().enumerate() {
                if !*seen_y && s.before(y).contains(&x) {
                    *seen_y = true;
                    stack.push(y);
                }
            }
        }
        false
    };
    let first_optional = order
        .iter()
        .position(|&a| !needed(a))
        .expect("the plan has optional activities");
    assert!(first_optional > 0);
    assert!(
        order[first_optional..]
            .iter()
            .all(|&a| !plan.activities[a].mandatory),
        "{order:?}"
    );
    // Within each part, the original order.
    let rank = |a: usize| s.original().iter().position(|&x| x == a).expect("listed");
    let head: Vec<usize> = order[..first_optional].iter().map(|&a| rank(a)).collect();
    let tail: Vec<usize> = order[first_optional..].iter().map(|&a| rank(a)).collect();
    assert!(head.windows(2).all(|w| w[0] < w[1]), "{head:?}");
    assert!(tail.windows(2).all(|w| w[0] < w[1]), "{tail:?}");
}

#[test]
fn hill_climb_spends_its_budget_and_keeps_the_best() {
    let plan = plan();
    let s = OrderScorer::new(&plan);
    let sample = s.sample(1, 3);
    let original = s.score(s.original(), sample).expect("scores");
    let climb = tuning::hill_climb(&s, sample, 12, original.clone(), 1).expect("climbs");
    assert_eq!(climb.evaluations, 12);
    assert!(climb.score >= original);
    assert!(s.allows(&climb.best));
    assert_eq!(s.score(&climb.best, sample).expect("scores"), climb.score);
    // The same seed climbs the same way.
    let again = tuning::hill_climb(&s, sample, 12, original, 1).expect("climbs");
    assert_eq!(again.best, climb.best);
}

#[test]
fn quick_comparison_runs_the_three_methods() {
    let plan = plan();
    let settings = tuning::Settings {
        runs: 3,
        confirm_runs: 4,
        budget: 6,
    };
    let row = tuning::compare("test", &plan, settings).expect("compares");
    assert_eq!(row.activities, 40);
    assert!(row.models > 0);
    assert!(row.tune_evaluations <= 6);
    let s = OrderScorer::new(&plan);
    let held = s.sample(2, 4);
    let original = s.score(s.original(), held).expect("scores");
    assert_eq!(row.original, tuning::Outcome::of(&original));
    for m in &row.methods {
        assert_eq!(
            m.gain.verdict,
            tuning::outcome_cmp(&m.held_out, &original),
            "{m:?}"
        );
    }
    // The mandatory-first order's held-out score is its order's.
    let first = tuning::mandatory_first(&plan, &s);
    assert_eq!(
        row.methods[2].held_out,
        s.score(&first, held).expect("scores")
    );
}
