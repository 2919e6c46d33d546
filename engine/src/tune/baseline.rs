//! Tuning's objective for orders chosen outside its search: what benchmarks
//! need to compare the search with baselines on equal terms (the same samples,
//! the same scoring, the same rules on orders). Not a planner's feature: hidden
//! from the documentation.

use super::order::Rules;
use super::score::{Sample, Score, Scorer};
use crate::error::Error;
use crate::model::Plan;

/// Scores orders of one plan (nothing pinned) exactly as [`tune`](super::tune)
/// scores them: executions under the replanning executive, the objective of
/// docs/format.md §12, changes counted against the plan's own order.
#[doc(hidden)]
#[derive(Clone, Debug)]
pub struct OrderScorer<'p> {
    plan: &'p Plan,
    rules: Rules,
    name: String,
    uncertain: bool,
}

impl<'p> OrderScorer<'p> {
    /// The scorer of `plan` (a valid plan).
    pub fn new(plan: &'p Plan) -> Self {
        Self {
            plan,
            rules: Rules::new(plan, &[]),
            name: plan.name.clone().unwrap_or_else(|| "plan".to_string()),
            uncertain: plan.activities.iter().any(|a| a.duration_model.is_some()),
        }
    }

    /// The sample [`tune`](super::tune) uses for `seed` and `runs`: one run
    /// (the nominal execution) when no activity has a `duration_model`.
    pub fn sample(&self, seed: u64, runs: u64) -> Sample {
        Sample {
            seed,
            runs: if self.uncertain { runs } else { 1 },
        }
    }

    /// The plan's own step order (plan indices).
    pub fn original(&self) -> &[usize] {
        &self.rules.original
    }

    /// The activities that must come before `a` in every order: one of each
    /// dependency pair it is in, the one the plan's order puts first.
    pub fn before(&self, a: usize) -> &[usize] {
        self.rules.before.get(a).map_or(&[], Vec::as_slice)
    }

    /// Whether tuning may consider `order`: a permutation that keeps every
    /// dependency pair's order and that priorities realise.
    pub fn allows(&self, order: &[usize]) -> bool {
        self.rules.keeps(order) && self.rules.priorities(self.plan, order).is_some()
    }

    /// The priorities (by plan index) that realise `order`, as
    /// [`tune`](super::tune) would set them.
    pub fn priorities(&self, order: &[usize]) -> Option<Vec<i64>> {
        self.rules.priorities(self.plan, order)
    }

    /// The score of `order` on `sample`.
    pub fn score(&self, order: &[usize], sample: Sample) -> Result<Score, Error> {
        if !self.rules.keeps(order) {
            return Err(Error::invalid(
                "$",
                "the order breaks a dependency pair or is no permutation",
            ));
        }
        let priorities = self
            .priorities(order)
            .ok_or_else(|| Error::invalid("$", "no priorities realise the order"))?;
        let scorer = Scorer::new(self.plan, &self.rules.original, &self.name);
        let plan = scorer.with_priorities(&priorities);
        scorer
            .evaluate(&plan, sample, self.rules.changes(order), false, None)?
            .map(|e| e.score)
            .ok_or_else(|| Error::invalid("$", "the scoring was cancelled"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tune::{TuneOptions, tune};

    /// The scorer agrees with `tune` on the original and the tuned order, on
    /// both samples, and refuses orders that break a dependency.
    #[test]
    fn scores_as_tune_does() {
        let plan = crate::generate::add_duration_models(
            crate::generate::generate_plan_with(crate::generate::Profile::Realistic, 40, 1, 3),
            0.3,
            3,
        );
        let options = TuneOptions {
            runs: 3,
            confirm_runs: 4,
            budget: 6,
            ..TuneOptions::default()
        };
        let t = tune(&plan, &options).expect("tunes");
        let s = OrderScorer::new(&plan);
        assert_eq!(s.original(), t.original.as_slice());
        let tuning = s.sample(options.seed, options.runs);
        let held = s.sample(options.confirm_seed, options.confirm_runs);
        assert_eq!(tuning, t.tuning);
        assert_eq!(held, t.held_out);
        assert_eq!(
            s.score(&t.original, tuning).expect("scores"),
            t.tuning_scores.original
        );
        assert_eq!(
            s.score(&t.tuned, tuning).expect("scores"),
            t.tuning_scores.tuned
        );
        assert_eq!(
            s.score(&t.tuned, held).expect("scores"),
            t.held_out_scores.tuned
        );
        assert_eq!(
            s.priorities(&t.tuned).expect("realised"),
            t.tuned_plan
                .activities
                .iter()
                .map(|a| a.priority)
                .collect::<Vec<_>>()
        );
        // An activity put before one it must follow is refused.
        let (a, b) = (0..plan.activities.len())
            .find_map(|a| s.before(a).first().map(|&b| (a, b)))
            .expect("the realistic plan has dependencies");
        let mut broken: Vec<usize> = t.original.clone();
        broken.retain(|&x| x != a);
        let at = broken.iter().position(|&x| x == b).expect("listed");
        broken.insert(at, a);
        assert!(!s.allows(&broken));
        assert!(s.score(&broken, tuning).is_err());
        assert!(s.allows(&t.original));
    }
}
