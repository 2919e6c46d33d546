//! Priority tuning: the order (priorities) in which the greedy scheduler should
//! consider the activities so that what matters still runs when durations vary
//! (the tuning extension, docs/format.md §12; readings in docs/semantics.md,
//! "Priority tuning").
//!
//! An order is scored on a sample of executions exactly as `montecarlo` runs
//! them (run `i` of a seed draws the same durations whatever the order), under
//! the replanning executive ([`score`]). The orders considered keep every
//! pinned activity's place and every dependency pair's order, and are realised
//! by priorities only ([`order`]). With at most eight activities that can move,
//! every such order is scored (exact mode); otherwise a squeaky-wheel search
//! (from the mandatory-first order when that scores better than the original)
//! moves lost activities ahead of what took their place, or those after them,
//! from what the runs' losses and the predicted run's explanations say
//! ([`search`]). The best order is then confirmed on a held-out sample, and
//! every change says why from the evidence ([`why`], [`text`]).

mod baseline;
mod order;
mod score;
mod search;
mod text;
mod why;

use std::fmt;
use std::sync::atomic::AtomicBool;

#[doc(hidden)]
pub use baseline::OrderScorer;
pub use score::{Counts, Sample, Score, ValueMeasure};
pub use text::{change_line, first_difference_line, score_line};
pub use why::{ChangeWhy, Moved};

use crate::error::Error;
use crate::model::Plan;
use order::Rules;
use score::Scorer;
use search::Search;

/// What [`tune`] runs.
pub struct TuneOptions<'a> {
    /// Runs of the tuning sample (`N`, at least 1).
    pub runs: u64,
    /// Seed of the tuning sample (`S`).
    pub seed: u64,
    /// Runs of the held-out sample (`M >= N`).
    pub confirm_runs: u64,
    /// Seed of the held-out sample (not `seed`).
    pub confirm_seed: u64,
    /// Orders the search may score on the tuning sample, the original's
    /// included (at least 1).
    pub budget: u64,
    /// Ids of the activities that keep their priority (and place).
    pub pinned: Vec<String>,
    /// Set to stop the search: the best order found so far is kept (and
    /// confirmed).
    pub cancel: Option<&'a AtomicBool>,
    /// Called after each batch of orders scored: the evaluations done and the
    /// best score so far.
    pub progress: Option<TuneProgress<'a>>,
}

/// A progress callback: the orders scored so far and the best score.
pub type TuneProgress<'a> = &'a (dyn Fn(u64, &Score) + Sync);

/// The defaults of [`TuneOptions`] and of `solscope tune` (one set for both):
/// 20 runs of seed 1 to search, 40 held-out runs of seed 2, at most 60 orders
/// scored. They tune the bundled plan (70 activities, all movable) in about
/// 20 s on two cores; more runs and a larger budget search longer and better.
impl TuneOptions<'_> {
    /// Default runs of the tuning sample.
    pub const DEFAULT_RUNS: u64 = 20;
    /// Default seed of the tuning sample.
    pub const DEFAULT_SEED: u64 = 1;
    /// Default runs of the held-out sample.
    pub const DEFAULT_CONFIRM_RUNS: u64 = 40;
    /// Default seed of the held-out sample.
    pub const DEFAULT_CONFIRM_SEED: u64 = 2;
    /// Default number of orders scored.
    pub const DEFAULT_BUDGET: u64 = 60;
}

impl Default for TuneOptions<'_> {
    fn default() -> Self {
        Self {
            runs: Self::DEFAULT_RUNS,
            seed: Self::DEFAULT_SEED,
            confirm_runs: Self::DEFAULT_CONFIRM_RUNS,
            confirm_seed: Self::DEFAULT_CONFIRM_SEED,
            budget: Self::DEFAULT_BUDGET,
            pinned: Vec::new(),
            cancel: None,
            progress: None,
        }
    }
}

impl fmt::Debug for TuneOptions<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("TuneOptions")
            .field("runs", &self.runs)
            .field("seed", &self.seed)
            .field("confirm_runs", &self.confirm_runs)
            .field("confirm_seed", &self.confirm_seed)
            .field("budget", &self.budget)
            .field("pinned", &self.pinned)
            .field("cancel", &self.cancel)
            .field("progress", &self.progress.is_some())
            .finish()
    }
}

/// Which search ran.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Every order the rules allow was scored (within the budget).
    Exact,
    /// The squeaky-wheel search driven by the losses' evidence.
    Evidence,
}

impl Mode {
    /// The name in documents.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Exact => "exact",
            Mode::Evidence => "evidence",
        }
    }
}

/// Why the search ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// Exact mode scored every order; evidence mode found nothing better in
    /// its last descents.
    Finished,
    /// The budget ran out first.
    Budget,
    /// The cancel flag was set.
    Cancelled,
}

impl Stop {
    /// The name in documents.
    pub fn name(self) -> &'static str {
        match self {
            Stop::Finished => "finished",
            Stop::Budget => "budget",
            Stop::Cancelled => "cancelled",
        }
    }
}

/// Scores of the original and the tuned order on one sample.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Scores {
    /// The original order's.
    pub original: Score,
    /// The tuned order's.
    pub tuned: Score,
}

/// One activity's outcomes before and after, on both samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ActivityCounts {
    /// Tuning sample, original order.
    pub tuning_before: Counts,
    /// Tuning sample, tuned order.
    pub tuning_after: Counts,
    /// Held-out sample, original order.
    pub held_out_before: Counts,
    /// Held-out sample, tuned order.
    pub held_out_after: Counts,
}

/// One priority changed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Change {
    /// Plan activity index.
    pub activity: usize,
    /// Its priority in the plan.
    pub before: i64,
    /// Its tuned priority.
    pub after: i64,
    /// Why, from the evidence.
    pub why: ChangeWhy,
}

/// The result of [`tune`].
#[derive(Clone, Debug)]
pub struct Tuning {
    /// The plan's name.
    pub plan: String,
    /// Which search ran.
    pub mode: Mode,
    /// Activities that can move (not pinned, not fixed by dependencies).
    pub movable: usize,
    /// The tuning sample.
    pub tuning: Sample,
    /// The held-out sample.
    pub held_out: Sample,
    /// The original step order (plan indices).
    pub original: Vec<usize>,
    /// The tuned step order.
    pub tuned: Vec<usize>,
    /// The tuned plan: the input with only priorities changed.
    pub tuned_plan: Plan,
    /// Scores on the tuning sample.
    pub tuning_scores: Scores,
    /// Scores on the held-out sample.
    pub held_out_scores: Scores,
    /// Per activity (file order).
    pub counts: Vec<ActivityCounts>,
    /// The priorities changed, in file order.
    pub changes: Vec<Change>,
    /// The budget.
    pub budget: u64,
    /// Orders scored on the tuning sample.
    pub evaluations: u64,
    /// Why the search ended.
    pub stop: Stop,
}

impl Tuning {
    /// Whether the tuned order is no worse than the original on the held-out
    /// sample.
    pub fn held_out_no_worse(&self) -> bool {
        self.held_out_scores.tuned >= self.held_out_scores.original
    }
}

/// Searches the priorities of `plan` (a valid plan, as
/// [`load_plan`](crate::load_plan) gives it) that score best on the tuning
/// sample, and confirms them on the held-out one. The same plan and options
/// give the same result on any number of threads.
pub fn tune(plan: &Plan, options: &TuneOptions<'_>) -> Result<Tuning, Error> {
    check_options(options)?;
    let pinned = pinned(plan, &options.pinned)?;
    let name = plan.name.clone().unwrap_or_else(|| "plan".to_string());
    let uncertain = plan.activities.iter().any(|a| a.duration_model.is_some());
    let sample = |seed: u64, runs: u64| Sample {
        seed,
        runs: if uncertain { runs } else { 1 },
    };
    let tuning = sample(options.seed, options.runs);
    let held_out = sample(options.confirm_seed, options.confirm_runs);
    let rules = Rules::new(plan, &pinned);
    let scorer = Scorer::new(plan, &rules.original, &name);
    let Some(original) = scorer.evaluate(plan, tuning, 0, true, None)? else {
        return Err(Error::invalid("$", "the original order was not scored"));
    };
    if let Some(p) = options.progress {
        p(1, &original.score);
    }
    let movable = rules.movable().len();
    let mode = search::mode_for(movable);
    let mut search = Search::new(&scorer, &rules, tuning, options.budget, &original);
    search.cancel = options.cancel;
    search.progress = options.progress;
    match mode {
        Mode::Exact => search.exact()?,
        Mode::Evidence => search.evidence(original.clone(), options.seed)?,
    }
    let (tuned, tuned_score) = search.best.clone();
    let (evaluations, stop) = (search.evaluations, search.stop);
    let priorities = rules
        .priorities(plan, &tuned)
        .ok_or_else(|| Error::invalid("$", "the tuned order has no priorities"))?;
    let tuned_plan = scorer.with_priorities(&priorities);
    // The evidence of the tuned order, and both on the held-out sample.
    let run = |p: &Plan, s: Sample, changes: u64, evidence: bool| {
        scorer
            .evaluate(p, s, changes, evidence, None)?
            .ok_or_else(|| Error::invalid("$", "a confirmation run was cancelled"))
    };
    let changes_count = rules.changes(&tuned);
    let after = if tuned == rules.original {
        original.clone()
    } else {
        run(&tuned_plan, tuning, changes_count, true)?
    };
    debug_assert_eq!(
        after.score, tuned_score,
        "the tuned order scores as searched"
    );
    let held_before = run(plan, held_out, 0, false)?;
    let held_after = if tuned == rules.original {
        held_before.clone()
    } else {
        run(&tuned_plan, held_out, changes_count, false)?
    };
    let counts = (0..plan.activities.len())
        .map(|a| ActivityCounts {
            tuning_before: original.counts[a],
            tuning_after: after.counts[a],
            held_out_before: held_before.counts[a],
            held_out_after: held_after.counts[a],
        })
        .collect();
    let changes = plan
        .activities
        .iter()
        .zip(&priorities)
        .enumerate()
        .filter(|(_, (a, p))| a.priority != **p)
        .map(|(x, (a, &p))| Change {
            activity: x,
            before: a.priority,
            after: p,
            why: why::why(x, &rules.original, &tuned, &original, &after, tuning.runs),
        })
        .collect();
    Ok(Tuning {
        plan: name,
        mode,
        movable,
        tuning,
        held_out,
        original: rules.original.clone(),
        tuned,
        tuned_plan,
        tuning_scores: Scores {
            original: original.score,
            tuned: after.score,
        },
        held_out_scores: Scores {
            original: held_before.score,
            tuned: held_after.score,
        },
        counts,
        changes,
        budget: options.budget,
        evaluations,
        stop,
    })
}

fn check_options(o: &TuneOptions<'_>) -> Result<(), Error> {
    if o.runs == 0 {
        return Err(Error::invalid("runs", "must be at least 1"));
    }
    if o.confirm_runs < o.runs {
        return Err(Error::invalid(
            "confirm_runs",
            format!(
                "the held-out sample needs at least as many runs as the tuning sample (got {} < {})",
                o.confirm_runs, o.runs
            ),
        ));
    }
    if o.confirm_seed == o.seed {
        return Err(Error::invalid(
            "confirm_seed",
            format!(
                "the held-out sample needs another seed than the tuning sample (both {})",
                o.seed
            ),
        ));
    }
    if o.budget == 0 {
        return Err(Error::invalid(
            "budget",
            "must be at least 1 (the original order)",
        ));
    }
    Ok(())
}

/// The pinned activities' plan indices.
fn pinned(plan: &Plan, ids: &[String]) -> Result<Vec<usize>, Error> {
    ids.iter()
        .enumerate()
        .map(|(i, id)| {
            plan.activities
                .iter()
                .position(|a| &a.id == id)
                .ok_or_else(|| {
                    Error::invalid(format!("pinned[{i}]"), format!("unknown activity \"{id}\""))
                })
        })
        .collect()
}
