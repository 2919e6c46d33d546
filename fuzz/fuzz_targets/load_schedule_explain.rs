//! Fuzz target: any bytes → load → (if valid) schedule → explain. Must never panic.
//! Work is bounded so that slow-but-correct inputs are not reported as hangs.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(loaded) = solscope_engine::load_plan(text) else {
        return;
    };
    let plan = &loaded.plan;
    if plan.activities.len() > 24 || plan.horizon.end - plan.horizon.start > 200_000 {
        return;
    }
    let Ok(schedule) = solscope_engine::schedule(plan) else {
        return;
    };
    let opts = solscope_engine::ExplainOptions {
        activity: None,
        no_suggestions: true,
    };
    let _ = solscope_engine::explain(plan, &schedule, &opts);
    let _ = solscope_engine::schedule_document(&loaded, &schedule, "fuzz");
});
