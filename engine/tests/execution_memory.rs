//! An execution's memory grows with its activities plus its cycles, not with
//! their product: it keeps per cycle only what its document and its loss
//! explanations read, and rebuilds a cycle's plan on demand. A plan of `N`
//! short activities replanned at every end has about `N` cycles, each
//! scheduling the activities not yet started; keeping each cycle's plan
//! would hold about `N * N / 2` activity copies.
//!
//! The measure is the process's peak resident memory (`VmHWM`), so this file
//! holds one test: its binary runs nothing else beside it.
#![allow(clippy::panic, clippy::unwrap_used, clippy::expect_used)]

use serde_json::json;
use solscope_engine::{Actuals, execute, load_plan};

/// The peak resident memory of this process so far (bytes), from
/// `/proc/self/status`; `None` where there is no such file.
fn peak_resident() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// `n` activities of ten seconds, one after the other, each with a long id
/// and a resource name (so that a copy of one costs what a real one does).
fn plan_text(n: usize) -> String {
    let activities: Vec<_> = (0..n)
        .map(|i| {
            json!({
                "id": format!("observation_with_a_descriptive_identifier_{i:04}"),
                "priority": i + 1,
                "duration": 10,
                "windows": [{ "start": 100 + 20 * i, "end": 100 + 20 * i }],
                "resources": [format!("instrument_{}", i % 7)],
                "energy_rate": 5.0,
            })
        })
        .collect();
    json!({
        "format": "solscope.plan/1",
        "horizon": { "start": 0, "end": 100 + 20 * n + 1000 },
        "battery": { "capacity": 5000.0, "initial": 4000.0, "min_soc": 500.0 },
        "power": { "rtg": 500.0, "asleep": 25.0, "awake": 150.0 },
        "activities": activities,
    })
    .to_string()
}

#[test]
fn an_execution_keeps_memory_linear_in_activities_plus_cycles() {
    const N: usize = 400;
    let plan = load_plan(&plan_text(N)).unwrap().plan;
    let Some(before) = peak_resident() else {
        // Not Linux: the peak cannot be read; the bound is still measured in
        // docs/performance.md.
        return;
    };
    let ex = execute(&plan, &Actuals::nominal()).unwrap();
    let after = peak_resident().unwrap();
    let cycles = ex.cycles.len();
    assert!(
        cycles > N,
        "a cycle at the start and at every end: {cycles}"
    );
    // Every cycle's plan kept would be about N * N / 2 activity copies, each
    // some hundreds of bytes with its strings: over 30 MB here.
    let one_plan = std::mem::size_of_val(&plan.activities[0]) * N;
    let grown = after.saturating_sub(before);
    assert!(
        grown < 12 * 1024 * 1024,
        "executing {N} activities over {cycles} cycles raised the peak by {grown} bytes \
         (one plan's activities: {one_plan} bytes of structs alone)"
    );
}
