//! Property test: plans from the generator with `duration_model`s added
//! (`add_duration_models`, as `solscope generate --uncertain` makes them) are
//! valid plans that read back with their models, execute on sampled durations under
//! every policy, and run as a Monte Carlo campaign.
#![allow(clippy::panic, clippy::unwrap_used, clippy::expect_used)]

use proptest::prelude::*;
use solscope_engine::{
    ExecuteOptions, Policy, Profile, add_duration_models, campaign_runs, campaign_with,
    execute_with, generate_plan_with, load_plan, sample_actuals,
};

fn profile() -> impl Strategy<Value = Profile> {
    prop_oneof![
        Just(Profile::Standard),
        Just(Profile::Realistic),
        Just(Profile::Starved)
    ]
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 24,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn generated_plans_with_models_check_and_execute(
        profile in profile(),
        activities in 5usize..60,
        sols in 1usize..3,
        seed in 0u64..1000,
        share in 0.0f64..=1.0,
        run in 0u64..50,
    ) {
        let plan = add_duration_models(
            generate_plan_with(profile, activities, sols, seed), share, seed);
        let text = serde_json::to_string(&plan).expect("serialises");
        let loaded = load_plan(&text).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        // Read back with the same models (integers: exact through JSON).
        let models = |p: &solscope_engine::Plan| {
            p.activities.iter().map(|a| a.duration_model).collect::<Vec<_>>()
        };
        prop_assert_eq!(models(&loaded.plan), models(&plan));
        let actuals = sample_actuals(&plan, run);
        for policy in [Policy::Replan, Policy::Dispatch, Policy::Fixed] {
            let options = ExecuteOptions { policy };
            let ex = execute_with(&plan, &actuals, options)
                .map_err(|e| TestCaseError::fail(format!("{policy:?}: {e}")))?;
            prop_assert!(!ex.cycles.is_empty());
        }
        let campaign = campaign_with(&plan, seed, 3, "plan", Policy::Replan)
            .map_err(|e| TestCaseError::fail(format!("{e}")))?;
        let records = campaign_runs(&plan, &campaign, &[0, 1, 2], &|| {}, None)
            .map_err(|e| TestCaseError::fail(format!("{e}")))?
            .expect("not cancelled");
        prop_assert_eq!(records.len(), 3);
    }
}

/// A starved plan with duration models whose replanning cycles hold an
/// activity still executing: explaining a Monte Carlo run's losses keeps every
/// skipped witness fitting (the explainer's debug cross-check, "a skipped
/// witness stopped fitting", in `explain/replay.rs`). A held placement's
/// application drains charge like any other, and the explainer bounds what a
/// step can do to a witness's energy margin by that charge.
#[test]
fn loss_explanations_of_a_starved_plan_with_models_keep_their_witnesses() {
    let plan = add_duration_models(
        generate_plan_with(Profile::Starved, 35, 1, 563),
        0.9537207519273991,
        563,
    );
    let campaign = campaign_with(&plan, 563, 3, "plan", Policy::Replan).unwrap();
    let records = campaign_runs(&plan, &campaign, &[0, 1, 2], &|| {}, None)
        .unwrap()
        .expect("not cancelled");
    assert_eq!(records.len(), 3);
}
