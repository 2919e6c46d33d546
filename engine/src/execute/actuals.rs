//! Actual durations of one execution (docs/format.md, "Actuals"): the `solscope.actuals/1` file, read with
//! path-named errors, or sampled from the plan's `duration_model`s.

use std::collections::BTreeMap;

use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{RngCore, SeedableRng};
use serde::{Deserialize, Serialize};

use crate::error::Error;
use crate::model::Plan;

/// The value of `format` in every actuals file.
pub const ACTUALS_FORMAT: &str = "solscope.actuals/1";

/// Actual durations by activity id; an activity not listed runs exactly its
/// `duration`.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Actuals {
    /// Must be [`ACTUALS_FORMAT`].
    pub format: String,
    /// Actual duration (s) by activity id (an id listed twice is refused, as
    /// a plan refuses a duplicate id).
    #[serde(deserialize_with = "unique_ids")]
    pub durations: BTreeMap<String, i64>,
}

/// Reads `durations`, refusing an id listed twice (a map would keep the last
/// silently).
fn unique_ids<'de, D: serde::Deserializer<'de>>(d: D) -> Result<BTreeMap<String, i64>, D::Error> {
    struct Durations;
    impl<'de> serde::de::Visitor<'de> for Durations {
        type Value = BTreeMap<String, i64>;
        fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str("a map from activity id to duration")
        }
        fn visit_map<M: serde::de::MapAccess<'de>>(
            self,
            mut m: M,
        ) -> Result<Self::Value, M::Error> {
            let mut out = BTreeMap::new();
            while let Some((id, d)) = m.next_entry::<String, i64>()? {
                if out.contains_key(&id) {
                    return Err(serde::de::Error::custom(format!(
                        "duplicate id \"{id}\" (each activity is listed at most once)"
                    )));
                }
                out.insert(id, d);
            }
            Ok(out)
        }
    }
    d.deserialize_map(Durations)
}

impl Actuals {
    /// No actual durations listed: every activity runs exactly its `duration`.
    pub fn nominal() -> Self {
        Self {
            format: ACTUALS_FORMAT.into(),
            durations: BTreeMap::new(),
        }
    }
}

/// Reads an actuals document for `plan`: strict JSON, known ids only, positive
/// whole durations.
pub fn load_actuals(text: &str, plan: &Plan) -> Result<Actuals, Error> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let de = &mut serde_json::Deserializer::from_str(text);
    let actuals: Actuals = serde_path_to_error::deserialize(&mut *de).map_err(|e| {
        let path = e.path().to_string();
        let path = if path == "." { "$".to_string() } else { path };
        Error::invalid(path, e.inner().to_string())
    })?;
    de.end()
        .map_err(|e| Error::invalid("$", format!("unexpected text after the document: {e}")))?;
    if actuals.format != ACTUALS_FORMAT {
        return Err(Error::invalid(
            "format",
            format!(
                "expected \"{ACTUALS_FORMAT}\", found \"{}\"",
                actuals.format
            ),
        ));
    }
    for (id, &d) in &actuals.durations {
        let path = format!("durations.{id}");
        let Some(act) = plan.activities.iter().find(|a| &a.id == id) else {
            return Err(Error::invalid(path, format!("unknown activity \"{id}\"")));
        };
        if d <= 0 {
            return Err(Error::invalid(path, "an actual duration must be > 0"));
        }
        if d > plan.horizon.end - plan.horizon.start {
            return Err(Error::invalid(path, "longer than the horizon"));
        }
        if act.duration.min() != act.duration.max() && d != act.duration.max() {
            return Err(Error::invalid(
                path,
                "an expanding activity has no uncertain duration (the scheduler picks it)",
            ));
        }
    }
    Ok(actuals)
}

/// One execution's actual durations drawn from the `duration_model`s: each
/// activity with a model gets an integer uniform in `[min, max]`, in file order,
/// from the ChaCha8 generator seeded with `seed` (the same seed gives the same
/// durations on every machine).
pub fn sample_actuals(plan: &Plan, seed: u64) -> Actuals {
    sample_run(plan, seed, 0)
}

/// The actual durations of Monte Carlo run `run` of a campaign seeded with
/// `seed`: stream `run` of the ChaCha8 generator seeded with `seed`, so each run
/// draws the same durations whichever machine, thread or shard runs it (run 0
/// is [`sample_actuals`]).
pub fn sample_run(plan: &Plan, seed: u64, run: u64) -> Actuals {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(run);
    let mut durations = BTreeMap::new();
    for a in &plan.activities {
        if let Some(m) = a.duration_model {
            durations.insert(a.id.clone(), uniform(&mut rng, m.min, m.max));
        }
    }
    Actuals {
        format: ACTUALS_FORMAT.into(),
        durations,
    }
}

/// An integer uniform in `[lo, hi]` (rejection sampling: exact, no modulo bias).
fn uniform(rng: &mut ChaCha8Rng, lo: i64, hi: i64) -> i64 {
    if hi <= lo {
        return lo;
    }
    let span = hi.abs_diff(lo) + 1;
    let zone = u64::MAX - (u64::MAX % span);
    loop {
        let x = rng.next_u64();
        if x < zone {
            return lo.saturating_add_unsigned(x % span);
        }
    }
}
