//! Fixed point errs on the safe side: on random plans whose energy,
//! power and data figures carry more decimals than the scheduler's units (mW,
//! mJ, bit), every placement of the schedule is checked again by the independent
//! oracle in exact integer arithmetic on the plan's own decimals (nW, nJ,
//! millibit): state of charge, handover limits, peak power and data volume. With
//! rounding to nearest the scheduler accepted placements that end up to 0.01 Wh
//! below `min_soc`; rounding every figure to its safe side (docs/semantics.md,
//! "Numbers") must leave none.
#![allow(clippy::panic, clippy::unwrap_used, clippy::expect_used)]

mod oracle;
#[path = "gen/mod.rs"]
mod plangen;

use std::sync::atomic::{AtomicUsize, Ordering};

use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};
use serde_json::Value;
use solscope_engine::{load_plan, schedule, schedule_document};

/// Seven decimals: finer than mW, mJ (1/3600000 Wh) and bit, exact in the
/// oracle's units.
const DECIMALS: i32 = 7;

/// A small deterministic generator for the perturbations.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
}

/// `x` moved by less than half a unit of the scheduler's resolution, to a
/// decimal of `DECIMALS` places (kept non-negative unless `signed`).
fn fine(x: f64, rng: &mut Rng, signed: bool) -> f64 {
    let scale = 10f64.powi(DECIMALS);
    let delta = (rng.next() % 9_999) as i64 - 4_999;
    let mut m = (x * scale).round() as i64 + delta;
    if !signed {
        m = m.abs();
    }
    m as f64 / scale
}

/// Every energy, power and data figure of the plan moved to a finer decimal.
fn perturb(text: &str, seed: u64) -> String {
    let mut v: Value = serde_json::from_str(text).unwrap();
    let mut rng = Rng(seed | 1);
    let touch = |x: &mut Value, signed: bool, rng: &mut Rng| {
        if let Some(f) = x.as_f64() {
            *x = serde_json::json!(fine(f, rng, signed));
        }
    };
    for key in ["rtg", "asleep", "awake", "max_peak"] {
        if let Some(x) = v["power"].get_mut(key) {
            touch(x, false, &mut rng);
        }
    }
    for key in ["capacity", "initial", "min_soc"] {
        if let Some(x) = v["battery"].get_mut(key) {
            touch(x, false, &mut rng);
        }
    }
    for key in ["capacity", "initial"] {
        if let Some(x) = v.get_mut("data").and_then(|d| d.get_mut(key)) {
            touch(x, false, &mut rng);
        }
    }
    for key in ["min_soc", "max_data_volume"] {
        if let Some(x) = v.get_mut("handover").and_then(|d| d.get_mut(key)) {
            touch(x, false, &mut rng);
        }
    }
    if let Some(zones) = v.get_mut("thermal_zones").and_then(Value::as_object_mut) {
        for z in zones.values_mut() {
            for key in ["preheat_power", "maintenance_power"] {
                if let Some(x) = z.get_mut(key) {
                    touch(x, false, &mut rng);
                }
            }
        }
    }
    if let Some(acts) = v["activities"].as_array_mut() {
        for a in acts {
            for (key, signed) in [
                ("energy_rate", false),
                ("peak_power", false),
                ("data_rate", true),
            ] {
                if let Some(x) = a.get_mut(key) {
                    touch(x, signed, &mut rng);
                }
            }
        }
    }
    v.to_string()
}

#[test]
fn no_placement_breaks_a_limit_in_exact_arithmetic() {
    let cases = 1024;
    let mut runner = TestRunner::new(Config {
        cases,
        failure_persistence: None,
        max_shrink_iters: 300,
        ..Config::default()
    });
    let checked = AtomicUsize::new(0);
    let result = runner.run(&(plangen::plan_text(), any::<u64>()), |(text, seed)| {
        let text = perturb(&text, seed);
        // A perturbation may make the battery or data figures inconsistent.
        let Ok(loaded) = load_plan(&text) else {
            return Ok(());
        };
        let sched = schedule(&loaded.plan).unwrap();
        let doc = serde_json::to_value(schedule_document(&loaded, &sched, "plan")).unwrap();
        oracle::check_valid_with(&loaded.plan, &doc, oracle::problem::Units::Exact)
            .map_err(|e| TestCaseError::fail(format!("{e}\nplan:\n{text}")))?;
        checked.fetch_add(1, Ordering::Relaxed);
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    let checked = checked.into_inner();
    assert!(
        checked * 2 >= cases as usize,
        "only {checked} of {cases} perturbed plans loaded"
    );
}
