//! Scoring an order on a sample of executions (the objective of
//! docs/format.md §12), and the evidence of its losses.

use std::cmp::Ordering;
use std::collections::BTreeMap;
use std::sync::atomic::AtomicBool;

use crate::error::Error;
use crate::execute::{Policy, RunRecord, campaign_with, runs_of};
use crate::explain::{ExplainOptions, Phase, explain, involved};
use crate::model::Plan;
use crate::scheduler::{Outcome, schedule};

/// The score of an order on a sample. Scores compare by the objective:
/// greater is better (fewer runs breaking a limit, then more mandatory
/// completions, then more value, then fewer order changes).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Score {
    /// Runs in which the executed profile broke a limit.
    pub runs_breaking: u64,
    /// Completions of mandatory activities, summed over the runs.
    pub mandatory_completed: u64,
    /// The value completed.
    pub value: ValueMeasure,
    /// Pairs of activities whose relative order differs from the original.
    pub changes: u64,
}

/// Item 3 of the objective.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ValueMeasure {
    /// The value completed, summed over runs, in millionths of the plan's
    /// `value` unit (some activity of the plan has a `value`).
    Total(i128),
    /// No activity has a `value`: the completions of each activity, in the
    /// original step order, compared lexicographically.
    StepOrder(Vec<u64>),
}

impl ValueMeasure {
    /// The value completed in the plan's unit (`None` for
    /// [`ValueMeasure::StepOrder`]).
    pub fn total(&self) -> Option<f64> {
        match self {
            ValueMeasure::Total(v) => Some(*v as f64 / MICRO as f64),
            ValueMeasure::StepOrder(_) => None,
        }
    }
}

impl Ord for ValueMeasure {
    fn cmp(&self, other: &Self) -> Ordering {
        match (self, other) {
            (ValueMeasure::Total(a), ValueMeasure::Total(b)) => a.cmp(b),
            (ValueMeasure::StepOrder(a), ValueMeasure::StepOrder(b)) => a.cmp(b),
            // One plan has one measure: never compared across.
            (ValueMeasure::Total(_), ValueMeasure::StepOrder(_)) => Ordering::Greater,
            (ValueMeasure::StepOrder(_), ValueMeasure::Total(_)) => Ordering::Less,
        }
    }
}

impl PartialOrd for ValueMeasure {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Score {
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .runs_breaking
            .cmp(&self.runs_breaking)
            .then_with(|| self.mandatory_completed.cmp(&other.mandatory_completed))
            .then_with(|| self.value.cmp(&other.value))
            .then_with(|| other.changes.cmp(&self.changes))
    }
}

impl PartialOrd for Score {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// Millionths: the unit tuning sums `value` in.
pub(crate) const MICRO: i128 = 1_000_000;

/// An activity's `value` in millionths (nearest).
pub(crate) fn micro(value: Option<f64>) -> i128 {
    value.map_or(0, |v| (v * MICRO as f64).round() as i128)
}

/// Runs in which an activity completed, was aborted, did not run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    /// Runs in which it completed.
    pub completed: u64,
    /// Runs in which it was aborted.
    pub aborted: u64,
    /// Runs in which it did not run.
    pub not_run: u64,
}

impl Counts {
    /// Runs in which it did not complete.
    pub fn lost(&self) -> u64 {
        self.aborted + self.not_run
    }
}

/// A sample of executions: runs `0..runs` of the seed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sample {
    /// The seed.
    pub seed: u64,
    /// Runs (1 for a plan without `duration_model`: the nominal execution).
    pub runs: u64,
}

/// An order's evaluation on a sample.
#[derive(Clone, Debug)]
pub(crate) struct Eval {
    pub score: Score,
    /// Per activity (file order).
    pub counts: Vec<Counts>,
    /// With the losses explained: the evidence.
    pub evidence: Option<Evidence>,
}

/// Why activities were lost under one order, as solscope knows it.
#[derive(Clone, Debug, Default)]
pub(crate) struct Evidence {
    /// Per activity: its loss causes over the runs, most frequent first, each
    /// with its culprits (plan indices), most frequent first.
    pub causes: Vec<Vec<CauseRuns>>,
    /// Per activity the first cycle (the predicted schedule) did not place:
    /// the explainer's answer.
    pub predicted: Vec<Option<FirstFailure>>,
}

/// One loss cause of an activity and the runs it accounts for.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct CauseRuns {
    pub cause: String,
    pub runs: u64,
    pub culprits: Vec<(usize, u64)>,
}

/// The predicted run's failure of an activity.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct FirstFailure {
    /// Cause key, as a run's loss names it (`placement/min_soc`, ...).
    pub cause: String,
    /// The activity placed at the failure step (what took its place).
    pub took_place: Option<usize>,
    /// The explainer's culprits (the first few) and the dependency or group
    /// member that blocked it.
    pub culprits: Vec<usize>,
}

impl Evidence {
    /// The activities to blame for `a`'s losses, most often first: the
    /// predicted run's (what took its place, then its culprits) and those
    /// named across the runs.
    pub fn blockers(&self, a: usize) -> Vec<usize> {
        let mut counts: BTreeMap<usize, u64> = BTreeMap::new();
        for c in self.causes.get(a).into_iter().flatten() {
            for &(x, k) in &c.culprits {
                *counts.entry(x).or_default() += k;
            }
        }
        let mut out: Vec<usize> = Vec::new();
        if let Some(Some(f)) = self.predicted.get(a) {
            out.extend(f.took_place);
            out.extend(f.culprits.iter().copied());
        }
        let mut named: Vec<(usize, u64)> = counts.into_iter().collect();
        named.sort_by(|x, y| y.1.cmp(&x.1).then(x.0.cmp(&y.0)));
        out.extend(named.into_iter().map(|(x, _)| x));
        let mut seen = Vec::new();
        out.retain(|&x| {
            x != a && !seen.contains(&x) && {
                seen.push(x);
                true
            }
        });
        out
    }

    /// `a`'s most frequent cause and its most named culprit.
    pub fn top(&self, a: usize) -> Option<(&str, Option<usize>)> {
        if let Some(c) = self.causes.get(a).and_then(|c| c.first()) {
            return Some((&c.cause, c.culprits.first().map(|x| x.0)));
        }
        self.predicted.get(a)?.as_ref().map(|f| {
            (
                f.cause.as_str(),
                f.took_place.or(f.culprits.first().copied()),
            )
        })
    }

    /// Runs in which `a` was lost to `cause`.
    pub fn runs_of(&self, a: usize, cause: &str) -> u64 {
        self.causes
            .get(a)
            .into_iter()
            .flatten()
            .filter(|c| c.cause == cause)
            .map(|c| c.runs)
            .sum()
    }
}

/// What scoring needs of the plan besides an order.
#[derive(Clone, Debug)]
pub(crate) struct Scorer<'p> {
    pub plan: &'p Plan,
    /// The original step order.
    pub original: &'p [usize],
    /// Values in millionths when some activity has one.
    values: Option<Vec<i128>>,
    name: String,
}

impl<'p> Scorer<'p> {
    pub fn new(plan: &'p Plan, original: &'p [usize], name: &str) -> Self {
        let values = plan
            .activities
            .iter()
            .any(|a| a.value.is_some())
            .then(|| plan.activities.iter().map(|a| micro(a.value)).collect());
        Self {
            plan,
            original,
            values,
            name: name.to_string(),
        }
    }

    /// Whether the plan gives values (else the step order measures value).
    pub fn has_values(&self) -> bool {
        self.values.is_some()
    }

    /// The plan with `priorities` (by plan index).
    pub fn with_priorities(&self, priorities: &[i64]) -> Plan {
        let mut plan = self.plan.clone();
        for (a, &p) in plan.activities.iter_mut().zip(priorities) {
            a.priority = p;
        }
        plan
    }

    /// Runs `sample` on `plan` (the plan with an order's priorities) and scores
    /// it, with `changes` order changes; with `evidence`, the losses are
    /// explained too. `Ok(None)` when cancelled.
    pub fn evaluate(
        &self,
        plan: &Plan,
        sample: Sample,
        changes: u64,
        evidence: bool,
        cancel: Option<&AtomicBool>,
    ) -> Result<Option<Eval>, Error> {
        let campaign = campaign_with(plan, sample.seed, sample.runs, &self.name, Policy::Replan)?;
        let indices: Vec<u64> = (0..sample.runs).collect();
        let Some(records) = runs_of(plan, &campaign, &indices, &|| {}, cancel, evidence)? else {
            return Ok(None);
        };
        let counts = counts(plan.activities.len(), &records);
        let score = self.score(&records, &counts, changes);
        let evidence = if evidence {
            Some(Evidence {
                causes: causes(plan.activities.len(), &records),
                predicted: predicted(plan)?,
            })
        } else {
            None
        };
        Ok(Some(Eval {
            score,
            counts,
            evidence,
        }))
    }

    fn score(&self, records: &[RunRecord], counts: &[Counts], changes: u64) -> Score {
        let runs_breaking = records.iter().filter(|r| !r.violations.is_empty()).count() as u64;
        let mandatory_completed = self
            .plan
            .activities
            .iter()
            .zip(counts)
            .filter(|(a, _)| a.mandatory)
            .map(|(_, c)| c.completed)
            .sum();
        let value = match &self.values {
            Some(v) => ValueMeasure::Total(
                v.iter()
                    .zip(counts)
                    .map(|(&v, c)| v * i128::from(c.completed))
                    .sum(),
            ),
            None => ValueMeasure::StepOrder(
                self.original.iter().map(|&a| counts[a].completed).collect(),
            ),
        };
        Score {
            runs_breaking,
            mandatory_completed,
            value,
            changes,
        }
    }
}

fn counts(n: usize, records: &[RunRecord]) -> Vec<Counts> {
    let mut out = vec![Counts::default(); n];
    for r in records {
        for (c, o) in out.iter_mut().zip(r.outcomes.bytes()) {
            match o {
                b'c' => c.completed += 1,
                b'a' => c.aborted += 1,
                _ => c.not_run += 1,
            }
        }
    }
    out
}

/// Per cause key: runs, and runs per culprit.
type CauseTally<'r> = BTreeMap<&'r str, (u64, BTreeMap<usize, u64>)>;

fn causes(n: usize, records: &[RunRecord]) -> Vec<Vec<CauseRuns>> {
    let mut by: Vec<CauseTally<'_>> = vec![BTreeMap::new(); n];
    for r in records {
        for l in &r.losses {
            let Some(m) = by.get_mut(l.activity) else {
                continue;
            };
            let e = m.entry(l.cause.as_str()).or_default();
            e.0 += 1;
            for &c in &l.culprits {
                *e.1.entry(c).or_default() += 1;
            }
        }
    }
    by.into_iter()
        .map(|m| {
            let mut v: Vec<CauseRuns> = m
                .into_iter()
                .map(|(cause, (runs, culprits))| {
                    let mut culprits: Vec<(usize, u64)> = culprits.into_iter().collect();
                    culprits.sort_by(|x, y| y.1.cmp(&x.1).then(x.0.cmp(&y.0)));
                    CauseRuns {
                        cause: cause.to_string(),
                        runs,
                        culprits,
                    }
                })
                .collect();
            v.sort_by(|x, y| y.runs.cmp(&x.runs).then_with(|| x.cause.cmp(&y.cause)));
            v
        })
        .collect()
}

/// The explainer's answer for every activity the predicted schedule (the
/// first cycle's) did not place.
fn predicted(plan: &Plan) -> Result<Vec<Option<FirstFailure>>, Error> {
    let sched = schedule(plan)?;
    let opts = ExplainOptions {
        activity: None,
        no_suggestions: true,
    };
    let mut out = vec![None; plan.activities.len()];
    for ex in explain(plan, &sched, &opts)? {
        if matches!(ex.outcome, Outcome::Scheduled { .. }) {
            continue;
        }
        let detail: Vec<&str> = match ex.phase {
            Some(Phase::ValidIntervals) => ex
                .conflicts
                .first()
                .map(|cats| cats.iter().map(|c| c.name()).collect())
                .unwrap_or_default(),
            Some(Phase::Placement) => ex
                .reasons
                .first()
                .map(|r| vec![r.reason.kind().name()])
                .unwrap_or_default(),
            _ => Vec::new(),
        };
        let phase = ex.phase.map_or("skipped", |p| p.name());
        let cause = if detail.is_empty() {
            phase.to_string()
        } else {
            format!("{phase}/{}", detail.join("+"))
        };
        let took_place = ex
            .failure_step
            .filter(|&k| k > 0)
            .and_then(|k| sched.steps.get(k - 1))
            .map(|s| s.activity);
        let mut culprits: Vec<usize> = involved(&ex).iter().map(|c| c.activity).collect();
        culprits.extend(ex.blocked_by);
        if let Some(slot) = out.get_mut(ex.activity) {
            *slot = Some(FirstFailure {
                cause,
                took_place,
                culprits,
            });
        }
    }
    Ok(out)
}
