use clap::Parser;

use super::*;
use crate::cli::{Cli, Command};

const ORDER_MATTERS: &str = include_str!("../../../assets/tuning-examples/order-matters.json");

fn plan() -> Plan {
    solscope_engine::load_plan(ORDER_MATTERS)
        .expect("example plan")
        .plan
}

#[test]
fn the_panel_starts_from_the_command_line_s_defaults() {
    let cli = Cli::try_parse_from(["solscope", "tune", "plan.json"]).expect("parses");
    let Some(Command::Tune(args)) = cli.command else {
        panic!("not tune");
    };
    let typed = TuneText::default().parse().expect("the defaults parse");
    assert_eq!(
        typed,
        TuneSettings {
            runs: args.runs,
            seed: args.seed,
            confirm_runs: args.confirm_runs,
            confirm_seed: args.confirm_seed,
            budget: args.budget,
            pinned: args.pin,
        }
    );
    assert_eq!(typed, TuneSettings::default());
}

#[test]
fn typed_settings_are_read_or_named_by_their_field() {
    let text = TuneText {
        pinned: " drive, watson_image  sherloc_scan,".into(),
        ..TuneText::default()
    };
    assert_eq!(
        text.parse().expect("parses").pinned,
        ["drive", "watson_image", "sherloc_scan"]
    );
    let bad = TuneText {
        budget: "lots".into(),
        ..TuneText::default()
    };
    let e = bad.parse().expect_err("not a number");
    assert!(e.starts_with("Budget: enter a whole number"), "{e}");
}

#[test]
fn the_engine_s_refusals_name_the_panel_s_fields() {
    let settings = TuneSettings {
        confirm_seed: DEFAULT_SEED,
        ..TuneSettings::default()
    };
    let e = TuneResult::of(&plan(), &settings, None, None).expect_err("same seeds");
    assert!(e.starts_with("Held-out seed: "), "{e}");
    let settings = TuneSettings {
        pinned: vec!["no_such".into()],
        ..TuneSettings::default()
    };
    let e = TuneResult::of(&plan(), &settings, None, None).expect_err("unknown id");
    assert_eq!(e, "Pinned ids: unknown activity \"no_such\"");
}

#[test]
fn a_result_carries_the_tuned_schedule_and_an_edit_of_priorities_only() {
    let plan = plan();
    let settings = TuneSettings {
        runs: 8,
        confirm_runs: 8,
        budget: 40,
        ..TuneSettings::default()
    };
    let r = TuneResult::of(&plan, &settings, None, None).expect("tunes");
    assert!(!r.tuning.changes.is_empty(), "the example's order matters");
    assert_eq!(r.reasons.len(), r.tuning.changes.len());
    assert!(!r.stopped_early());
    let tuned = solscope_engine::schedule(&r.tuning.tuned_plan).expect("schedules");
    let supercam = plan
        .activities
        .iter()
        .position(|a| a.id == "supercam_target")
        .expect("activity");
    assert_eq!(
        r.tuned_placements[supercam],
        tuned.step_of(supercam).and_then(|s| s.outcome.placement())
    );
    assert!(r.tuned_placements[supercam].is_some(), "placed once tuned");
    let (set, description) = r.edit(&plan).expect("an edit");
    let edited = solscope_engine::apply_edit(&plan, "plan", &set).expect("valid");
    assert_eq!(edited, r.tuning.tuned_plan, "only the priorities changed");
    for c in &r.tuning.changes {
        let id = &plan.activities[c.activity].id;
        assert!(
            description.contains(&format!("{id} {} → {}", c.before, c.after)),
            "{description}"
        );
    }
}

#[test]
fn cancelling_before_the_search_keeps_the_original_order_confirmed() {
    let cancel = AtomicBool::new(true);
    let settings = TuneSettings {
        runs: 4,
        confirm_runs: 4,
        ..TuneSettings::default()
    };
    let r = TuneResult::of(&plan(), &settings, Some(&cancel), None).expect("a result");
    assert!(r.stopped_early());
    assert_eq!(
        r.tuning.held_out_scores.original,
        r.tuning.held_out_scores.tuned
    );
}

#[test]
fn without_values_the_first_difference_in_step_order_is_said() {
    let settings = TuneSettings {
        runs: 8,
        confirm_runs: 8,
        budget: 40,
        ..TuneSettings::default()
    };
    let with_values = TuneResult::of(&plan(), &settings, None, None).expect("tunes");
    assert_eq!(
        solscope_engine::first_difference_line(&plan(), &with_values.tuning),
        None,
        "the plan's values decide"
    );
    let mut plain = plan();
    for a in &mut plain.activities {
        a.value = None;
    }
    let r = TuneResult::of(&plain, &settings, None, None).expect("tunes");
    let t = &r.tuning;
    let (solscope_engine::ValueMeasure::StepOrder(o), solscope_engine::ValueMeasure::StepOrder(n)) = (
        &t.held_out_scores.original.value,
        &t.held_out_scores.tuned.value,
    ) else {
        panic!("no values: step order");
    };
    let k = o
        .iter()
        .zip(n)
        .position(|(x, y)| x != y)
        .expect("a difference");
    let id = &plain.activities[t.original[k]].id;
    assert_eq!(
        solscope_engine::first_difference_line(&plain, t).as_deref(),
        Some(
            format!(
                "first difference in the original step order: {id} completes in {} of 8 runs \
                 instead of {}",
                n[k], o[k]
            )
            .as_str()
        )
    );
}
