//! Monte Carlo: many executions with actual durations drawn from the
//! `duration_model`s, summarised per activity, per pair and per plan, with the
//! reasons for each loss counted across runs and the uncertain duration that best
//! predicts it.
//!
//! Run `r` of a campaign seeded with `s` draws its durations from stream `r` of
//! the generator seeded with `s` ([`sample_run`]), so a run's record does not
//! depend on which machine, thread or shard ran it. Records are the unit of work:
//! [`campaign_runs`] runs any subset of run indices (in parallel, collected in
//! index order), and [`summarize`] makes the summary from the records alone, so
//! shards merged give exactly the summary of one machine.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::actuals::sample_run;
use super::{
    Cause, ExecuteOptions, Policy, Prefix, RunOutcome, ViolationKind, execute_with, losses,
};
use crate::error::Error;
use crate::model::Plan;
use crate::units::{MJ_PER_WH, wh};

mod check;

pub use check::read_runs;

/// The value of `format` in a Monte Carlo summary.
pub const MONTECARLO_FORMAT: &str = "solscope.montecarlo/1";
/// The value of `format` in a document of run records (a shard's output).
pub const MONTECARLO_RUNS_FORMAT: &str = "solscope.montecarlo-runs/1";

/// What every run of a campaign shares: the plan's identity and the first
/// cycle's prediction.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Campaign {
    /// Plan name.
    pub plan: String,
    /// FNV-1a hash of the plan's canonical JSON (hex): parts of different plans
    /// are not merged.
    pub plan_hash: String,
    /// The campaign seed.
    pub seed: u64,
    /// Number of runs in the whole campaign.
    pub runs: u64,
    /// Activity ids, in file order.
    pub activities: Vec<String>,
    /// Whether each activity is mandatory.
    pub mandatory: Vec<bool>,
    /// The first cycle's placement of each activity (the prediction).
    pub predicted: Vec<Option<(i64, i64)>>,
    /// Indices of the activities with a `duration_model`, in file order.
    pub uncertain: Vec<usize>,
    /// How the runs start activities (absent: `replan`).
    #[serde(default, skip_serializing_if = "Policy::is_replan")]
    pub policy: Policy,
}

/// One run: everything the summary needs.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunRecord {
    /// Run index.
    pub run: u64,
    /// Actual durations of the uncertain activities (in `Campaign::uncertain`
    /// order).
    pub durations: Vec<i64>,
    /// Per activity: `c` completed, `a` aborted, `n` not run.
    pub outcomes: String,
    /// Actual `[start, end)` per activity (`null`: not run).
    pub spans: Vec<Option<(i64, i64)>>,
    /// Lowest executed state of charge (mJ) and its time.
    pub lowest_soc: (i64, i64),
    /// Executed state of charge at the handover (mJ).
    pub handover_soc: Option<i64>,
    /// Limits broken (`min_soc`, `max_peak_power`, `data_capacity`,
    /// `handover_soc`).
    pub violations: Vec<String>,
    /// Why each predicted activity that did not complete was lost.
    pub losses: Vec<LossRecord>,
}

/// One loss in one run.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LossRecord {
    /// Activity index.
    pub activity: usize,
    /// The cause key ([`Cause::key`]).
    pub cause: String,
    /// The time of the cycle that decided it.
    pub cycle_time: Option<i64>,
    /// Culprit activity indices.
    pub culprits: Vec<usize>,
}

/// A document of run records: one shard's share of a campaign (or all of it).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunsDoc {
    /// Always [`MONTECARLO_RUNS_FORMAT`].
    pub format: String,
    /// The campaign.
    pub campaign: Campaign,
    /// `(i, k)`: the runs whose index is `i` modulo `k`.
    pub shard: (u64, u64),
    /// The records, by run index.
    pub records: Vec<RunRecord>,
}

/// The campaign of `runs` runs of `plan` seeded with `seed`: runs the first
/// cycle for the prediction.
pub fn campaign(plan: &Plan, seed: u64, runs: u64, name: &str) -> Result<Campaign, Error> {
    campaign_with(plan, seed, runs, name, Policy::Replan)
}

/// [`campaign`] with another execution policy: the same samples (run `i` draws
/// from stream `i` of the seed whatever the policy), so that campaigns of the
/// three policies compare run by run.
pub fn campaign_with(
    plan: &Plan,
    seed: u64,
    runs: u64,
    name: &str,
    policy: Policy,
) -> Result<Campaign, Error> {
    let first = crate::scheduler::run_outcomes(plan)?;
    let text = serde_json::to_string(plan).map_err(|e| Error::invalid("$", e.to_string()))?;
    Ok(Campaign {
        plan: plan.name.clone().unwrap_or_else(|| name.to_string()),
        plan_hash: format!("{:016x}", fnv1a(text.as_bytes())),
        seed,
        runs,
        activities: plan.activities.iter().map(|a| a.id.clone()).collect(),
        mandatory: plan.activities.iter().map(|a| a.mandatory).collect(),
        predicted: first.placements,
        uncertain: plan
            .activities
            .iter()
            .enumerate()
            .filter(|(_, a)| a.duration_model.is_some())
            .map(|(i, _)| i)
            .collect(),
        policy,
    })
}

fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// Runs the campaign's runs `indices` (in parallel), in index order. `progress`
/// is called after each run; when `cancel` is set, the remaining runs are not
/// started and `Ok(None)` is returned.
pub fn campaign_runs(
    plan: &Plan,
    campaign: &Campaign,
    indices: &[u64],
    progress: &(dyn Fn() + Sync),
    cancel: Option<&AtomicBool>,
) -> Result<Option<Vec<RunRecord>>, Error> {
    runs_of(plan, campaign, indices, progress, cancel, true)
}

/// [`campaign_runs`], explaining the losses only when `explain_losses` is set:
/// without it every record's `losses` is empty, for a
/// caller that needs only the outcomes and the violations (priority tuning
/// scores many orders and explains the losses of a few).
pub(crate) fn runs_of(
    plan: &Plan,
    campaign: &Campaign,
    indices: &[u64],
    progress: &(dyn Fn() + Sync),
    cancel: Option<&AtomicBool>,
    explain_losses: bool,
) -> Result<Option<Vec<RunRecord>>, Error> {
    // Every run shares the nominal execution up to its first changed end; the
    // other policies share the schedule (and its flexible form).
    let problem = crate::scheduler::Problem::compile(plan)?;
    let policy = campaign.policy;
    if policy.is_replan() {
        chain_bound(plan, indices.len())?;
    }
    let options = ExecuteOptions { policy };
    let (prefix, prepared) = if policy.is_replan() {
        (Some(Prefix::nominal(&problem, plan)?), None)
    } else {
        (None, Some(super::policy::Prepared::new(plan, policy)?))
    };
    let records: Vec<Option<Result<RunRecord, Error>>> = indices
        .par_iter()
        .map(|&r| {
            if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                return None;
            }
            let actuals = sample_run(plan, campaign.seed, r);
            let ex = match (&prefix, &prepared) {
                (Some(prefix), _) => prefix.execute(&problem, plan, &actuals),
                (None, Some(prepared)) => prepared.execute(&problem, plan, &actuals),
                (None, None) => execute_with(plan, &actuals, options),
            };
            let record =
                ex.and_then(|ex| record_of(plan, campaign, r, &actuals, &ex, explain_losses));
            progress();
            Some(record)
        })
        .collect();
    let mut out = Vec::with_capacity(records.len());
    for r in records {
        match r {
            None => return Ok(None),
            Some(r) => out.push(r?),
        }
    }
    Ok(Some(out))
}

/// The most replanning work one process takes on for a campaign, in scheduler
/// steps: `runs` times `L * L` for the longest chain of `L` activities linked
/// by dependencies. Each end in such a chain triggers a cycle that schedules
/// the rest of the chain again, every step of it searched (a dependent's start
/// is never its window's preferred time), so a run costs about `L * L / 2`
/// searched steps (a 2,000-activity `meets` chain: 2,001 cycles, 13 s of CPU;
/// docs/performance.md, "Replanning chains and long horizons"). The bound keeps
/// a campaign of such a chain near a minute on two cores.
const MAX_CHAIN_WORK: u128 = 20_000_000;

/// Chains shorter than this never decide the bound: their cycles are few.
const MIN_BOUNDED_CHAIN: usize = 64;

/// Refuses a replanning campaign of `runs` runs in one process whose longest
/// dependency chain makes it cost more than [`MAX_CHAIN_WORK`] steps, naming
/// the chain's last activity.
fn chain_bound(plan: &Plan, runs: usize) -> Result<(), Error> {
    let Some((len, last)) = longest_chain(plan) else {
        return Ok(());
    };
    let per_run = (len as u128) * (len as u128);
    if len < MIN_BOUNDED_CHAIN || (runs as u128) * per_run <= MAX_CHAIN_WORK {
        return Ok(());
    }
    let most = MAX_CHAIN_WORK / per_run;
    Err(Error::invalid(
        format!("activities[{last}].after"),
        format!(
            "`{}` ends a chain of {len} activities linked by dependencies: replanning \
             schedules the rest of the chain again at each of its ends, so {runs} runs \
             in one process are more than this chain allows (at most {most}); ask for \
             fewer runs (--runs), split the campaign (--shard I/K), or use \
             --policy dispatch or fixed",
            plan.activities[last].id
        ),
    ))
}

/// The longest chain of activities linked by dependencies (`after`): its
/// length in activities and its last activity (the first in file order among
/// the longest), if the plan has activities. Dependencies that form a cycle
/// (a plan the loader refuses) are not followed.
fn longest_chain(plan: &Plan) -> Option<(usize, usize)> {
    let n = plan.activities.len();
    let ids = plan.index_by_id();
    let mut dependents: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut waiting = vec![0usize; n];
    for (i, a) in plan.activities.iter().enumerate() {
        for d in &a.after {
            if let Some(&j) = ids.get(d.activity.as_str()) {
                dependents[j].push(i);
                waiting[i] += 1;
            }
        }
    }
    let mut len = vec![1usize; n];
    let mut ready: Vec<usize> = (0..n).filter(|&i| waiting[i] == 0).collect();
    while let Some(j) = ready.pop() {
        for &i in &dependents[j] {
            len[i] = len[i].max(len[j] + 1);
            waiting[i] -= 1;
            if waiting[i] == 0 {
                ready.push(i);
            }
        }
    }
    let best = len.iter().copied().max()?;
    let last = len.iter().position(|&l| l == best)?;
    Some((best, last))
}

/// One run's record (executed from the start).
pub fn run_record(plan: &Plan, campaign: &Campaign, run: u64) -> Result<RunRecord, Error> {
    let actuals = sample_run(plan, campaign.seed, run);
    let options = ExecuteOptions {
        policy: campaign.policy,
    };
    let ex = execute_with(plan, &actuals, options)?;
    record_of(plan, campaign, run, &actuals, &ex, true)
}

/// The record of run `run`, executed as `ex` with `actuals` (its losses
/// explained when `explain_losses` is set).
fn record_of(
    plan: &Plan,
    campaign: &Campaign,
    run: u64,
    actuals: &super::Actuals,
    ex: &super::Execution,
    explain_losses: bool,
) -> Result<RunRecord, Error> {
    let lost = if explain_losses {
        losses(plan, ex)?
    } else {
        Vec::new()
    };
    Ok(RunRecord {
        run,
        durations: campaign
            .uncertain
            .iter()
            .map(|&a| {
                actuals
                    .durations
                    .get(&plan.activities[a].id)
                    .copied()
                    .unwrap_or(plan.activities[a].duration.max())
            })
            .collect(),
        outcomes: ex
            .activities
            .iter()
            .map(|r| match r.outcome {
                RunOutcome::Completed => 'c',
                RunOutcome::Aborted => 'a',
                RunOutcome::NotRun => 'n',
            })
            .collect(),
        spans: ex.activities.iter().map(|r| r.actual).collect(),
        lowest_soc: (clamp64(ex.lowest_soc.0), ex.lowest_soc.1),
        handover_soc: ex.handover_soc.map(clamp64),
        violations: ex
            .violations
            .iter()
            .map(|v| v.kind.name().to_string())
            .collect(),
        losses: lost
            .iter()
            .map(|l| LossRecord {
                activity: l.activity,
                cause: l.cause.key(),
                cycle_time: l.cycle.map(|c| c.1),
                culprits: match &l.cause {
                    Cause::Failed { culprits, .. } => culprits.clone(),
                    _ => Vec::new(),
                },
            })
            .collect(),
    })
}

fn clamp64(x: i128) -> i64 {
    x.clamp(i128::from(i64::MIN), i128::from(i64::MAX)) as i64
}

impl ViolationKind {
    /// The name in documents.
    pub fn name(self) -> &'static str {
        match self {
            ViolationKind::MinSoc => "min_soc",
            ViolationKind::MaxPeakPower => "max_peak_power",
            ViolationKind::DataCapacity => "data_capacity",
            ViolationKind::HandoverSoc => "handover_soc",
        }
    }
}

/// `solscope.montecarlo/1`: the summary of a campaign.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    /// Always [`MONTECARLO_FORMAT`].
    pub format: &'static str,
    /// Plan name.
    pub plan: String,
    /// Campaign seed.
    pub seed: u64,
    /// Number of runs.
    pub runs: u64,
    /// The execution policy (absent: `replan`).
    #[serde(skip_serializing_if = "Policy::is_replan")]
    pub policy: Policy,
    /// Per activity, in file order.
    pub activities: Vec<ActivitySummary>,
    /// Pairs of activities that ran in parallel or swapped order in some run.
    pub pairs: Vec<PairSummary>,
    /// The lowest state of charge of each run (Wh).
    pub lowest_soc: Distribution,
    /// The state of charge at the handover of each run (Wh).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub handover_soc: Option<Distribution>,
    /// Runs that broke a limit, and by kind.
    pub limits: LimitSummary,
}

/// One activity across runs.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ActivitySummary {
    /// Activity id.
    pub id: String,
    /// Mandatory?
    pub mandatory: bool,
    /// The first cycle's start, when it placed it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub predicted_start: Option<i64>,
    /// Runs in which it completed.
    pub completed: u64,
    /// Runs in which it was aborted.
    pub aborted: u64,
    /// Runs in which it did not run.
    pub not_run: u64,
    /// Its actual start over the runs in which it started.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub start: Option<Quantiles>,
    /// For an activity the first cycle placed: the runs in which it did not
    /// complete, with the causes counted.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lost: Option<LostSummary>,
}

/// Nearest-rank quantiles of whole numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Quantiles {
    /// Smallest.
    pub min: i64,
    /// 5th percentile.
    pub p05: i64,
    /// Median.
    pub p50: i64,
    /// 95th percentile.
    pub p95: i64,
    /// Largest.
    pub max: i64,
}

/// Why a predicted activity was lost, across runs.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LostSummary {
    /// Runs in which it did not complete.
    pub runs: u64,
    /// Causes, most frequent first.
    pub causes: Vec<CauseCount>,
    /// The uncertain duration that best separates the runs that lost it from
    /// the others, when one does better than always guessing the majority.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub predictor: Option<Predictor>,
}

/// One cause and how often.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CauseCount {
    /// The cause key.
    pub cause: String,
    /// Runs.
    pub runs: u64,
    /// Culprits named in those runs, most frequent first: `(id, runs)`.
    pub culprits: Vec<(String, u64)>,
}

/// "Lost in `lost_when` of the `runs_when` runs in which `activity` ran
/// `direction` `threshold` s; that covers `lost_when` of all lost runs."
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Predictor {
    /// The uncertain activity.
    pub activity: String,
    /// `above` (duration > threshold) or `at_or_below`.
    pub direction: &'static str,
    /// The threshold (s).
    pub threshold: i64,
    /// Runs on that side of the threshold.
    pub runs_when: u64,
    /// Of those, runs that lost the activity.
    pub lost_when: u64,
    /// Share of all runs the rule classifies right.
    pub accuracy: f64,
}

/// A pair of activities across runs.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct PairSummary {
    /// First activity id (file order).
    pub a: String,
    /// Second activity id.
    pub b: String,
    /// Runs in which they ran at the same time.
    pub parallel: u64,
    /// Runs in which both ran in the order opposite to the prediction.
    pub swapped: u64,
}

/// A distribution of a value in Wh over the runs.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Distribution {
    /// Smallest.
    pub min: f64,
    /// 5th percentile.
    pub p05: f64,
    /// Median.
    pub p50: f64,
    /// 95th percentile.
    pub p95: f64,
    /// Largest.
    pub max: f64,
    /// Twenty equal bins from `min` to `max`: `(from, to, runs)`.
    pub histogram: Vec<(f64, f64, u64)>,
}

/// Limits broken across runs.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct LimitSummary {
    /// Runs that broke at least one limit.
    pub runs_breaking: u64,
    /// Runs by limit kind.
    pub by_kind: BTreeMap<String, u64>,
}

/// The summary of `records` (every run of `campaign`, in any order).
pub fn summarize(campaign: &Campaign, records: &[RunRecord]) -> Summary {
    let mut records: Vec<&RunRecord> = records.iter().collect();
    records.sort_by_key(|r| r.run);
    let n = campaign.activities.len();
    let count = |a: usize, c: char| {
        records
            .iter()
            .filter(|r| r.outcomes.as_bytes().get(a) == Some(&(c as u8)))
            .count() as u64
    };
    let activities = (0..n)
        .map(|a| {
            let mut starts: Vec<i64> = records
                .iter()
                .filter_map(|r| r.spans.get(a).copied().flatten().map(|s| s.0))
                .collect();
            starts.sort_unstable();
            ActivitySummary {
                id: campaign.activities[a].clone(),
                mandatory: campaign.mandatory[a],
                predicted_start: campaign.predicted[a].map(|p| p.0),
                completed: count(a, 'c'),
                aborted: count(a, 'a'),
                not_run: count(a, 'n'),
                start: quantiles(&starts),
                lost: campaign.predicted[a]
                    .is_some()
                    .then(|| lost_summary(campaign, &records, a))
                    .flatten(),
            }
        })
        .collect();
    let mut lowest: Vec<i64> = records.iter().map(|r| r.lowest_soc.0).collect();
    lowest.sort_unstable();
    let mut handover: Vec<i64> = records.iter().filter_map(|r| r.handover_soc).collect();
    handover.sort_unstable();
    let mut by_kind: BTreeMap<String, u64> = BTreeMap::new();
    for r in &records {
        for v in &r.violations {
            *by_kind.entry(v.clone()).or_default() += 1;
        }
    }
    Summary {
        format: MONTECARLO_FORMAT,
        plan: campaign.plan.clone(),
        seed: campaign.seed,
        runs: records.len() as u64,
        policy: campaign.policy,
        activities,
        pairs: pairs(campaign, &records),
        lowest_soc: distribution(&lowest),
        handover_soc: (!handover.is_empty()).then(|| distribution(&handover)),
        limits: LimitSummary {
            runs_breaking: records.iter().filter(|r| !r.violations.is_empty()).count() as u64,
            by_kind,
        },
    }
}

fn quantiles(sorted: &[i64]) -> Option<Quantiles> {
    let n = sorted.len();
    if n == 0 {
        return None;
    }
    // Nearest rank: the smallest value with at least q of the values at or below.
    let at = |q: u64| sorted[((q as usize * n).div_ceil(100)).clamp(1, n) - 1];
    Some(Quantiles {
        min: sorted[0],
        p05: at(5),
        p50: at(50),
        p95: at(95),
        max: sorted[n - 1],
    })
}

fn distribution(sorted_mj: &[i64]) -> Distribution {
    let q = quantiles(sorted_mj).unwrap_or(Quantiles {
        min: 0,
        p05: 0,
        p50: 0,
        p95: 0,
        max: 0,
    });
    let w = |x: i64| wh(i128::from(x));
    let (lo, hi) = (q.min, q.max);
    let bins = 20i128;
    let span = i128::from(hi) - i128::from(lo);
    let mut counts = [0u64; 20];
    for &x in sorted_mj {
        let k = if span == 0 {
            0
        } else {
            (((i128::from(x) - i128::from(lo)) * bins / span).min(bins - 1)) as usize
        };
        counts[k] += 1;
    }
    let edge = |k: i128| (i128::from(lo) + span * k / bins) as f64 / MJ_PER_WH;
    Distribution {
        min: w(q.min),
        p05: w(q.p05),
        p50: w(q.p50),
        p95: w(q.p95),
        max: w(q.max),
        histogram: (0..20)
            .map(|k| (edge(k as i128), edge(k as i128 + 1), counts[k]))
            .collect(),
    }
}

fn lost_summary(campaign: &Campaign, records: &[&RunRecord], a: usize) -> Option<LostSummary> {
    let lost: Vec<bool> = records
        .iter()
        .map(|r| r.outcomes.as_bytes().get(a) != Some(&b'c'))
        .collect();
    let runs = lost.iter().filter(|&&l| l).count() as u64;
    if runs == 0 {
        return None;
    }
    let mut causes: BTreeMap<String, (u64, BTreeMap<usize, u64>)> = BTreeMap::new();
    for r in records {
        for l in r.losses.iter().filter(|l| l.activity == a) {
            let e = causes.entry(l.cause.clone()).or_default();
            e.0 += 1;
            for &c in &l.culprits {
                *e.1.entry(c).or_default() += 1;
            }
        }
    }
    let mut causes: Vec<CauseCount> = causes
        .into_iter()
        .map(|(cause, (runs, culprits))| {
            let mut culprits: Vec<(String, u64)> = culprits
                .into_iter()
                .map(|(c, k)| (campaign.activities[c].clone(), k))
                .collect();
            culprits.sort_by(|x, y| y.1.cmp(&x.1).then_with(|| x.0.cmp(&y.0)));
            CauseCount {
                cause,
                runs,
                culprits,
            }
        })
        .collect();
    causes.sort_by(|x, y| y.runs.cmp(&x.runs).then_with(|| x.cause.cmp(&y.cause)));
    Some(LostSummary {
        runs,
        causes,
        predictor: predictor(campaign, records, &lost),
    })
}

/// The threshold on one uncertain duration that classifies the runs into lost
/// and kept best (most runs right; ties: the earlier activity, then the lower
/// threshold), when it beats always guessing the majority.
fn predictor(campaign: &Campaign, records: &[&RunRecord], lost: &[bool]) -> Option<Predictor> {
    let n = records.len() as u64;
    let total_lost = lost.iter().filter(|&&l| l).count() as u64;
    let majority = total_lost.max(n - total_lost);
    let mut best: Option<(u64, Predictor)> = None;
    for (k, &u) in campaign.uncertain.iter().enumerate() {
        let mut pts: Vec<(i64, bool)> = records
            .iter()
            .zip(lost)
            .filter_map(|(r, &l)| r.durations.get(k).map(|&d| (d, l)))
            .collect();
        pts.sort_unstable();
        // Splits after each distinct value: `below` = runs with d <= threshold.
        let (mut below, mut below_lost) = (0u64, 0u64);
        let mut i = 0;
        while i < pts.len() {
            let d = pts[i].0;
            while i < pts.len() && pts[i].0 == d {
                below += 1;
                below_lost += u64::from(pts[i].1);
                i += 1;
            }
            let (above, above_lost) = (n - below, total_lost - below_lost);
            // "lost iff above": right = lost above + kept below.
            let right_above = above_lost + (below - below_lost);
            let right_below = below_lost + (above - above_lost);
            for (right, direction, runs_when, lost_when) in [
                (right_above, "above", above, above_lost),
                (right_below, "at_or_below", below, below_lost),
            ] {
                if right <= majority || runs_when == 0 {
                    continue;
                }
                if best.as_ref().is_none_or(|(r, _)| right > *r) {
                    best = Some((
                        right,
                        Predictor {
                            activity: campaign.activities[u].clone(),
                            direction,
                            threshold: d,
                            runs_when,
                            lost_when,
                            accuracy: right as f64 / n as f64,
                        },
                    ));
                }
            }
        }
    }
    best.map(|(_, p)| p)
}

fn pairs(campaign: &Campaign, records: &[&RunRecord]) -> Vec<PairSummary> {
    let mut counts: BTreeMap<(usize, usize), (u64, u64)> = BTreeMap::new();
    for r in records {
        let ran: Vec<(usize, (i64, i64))> = r
            .spans
            .iter()
            .enumerate()
            .filter_map(|(a, s)| s.map(|s| (a, s)))
            .collect();
        for (i, &(a, (s1, e1))) in ran.iter().enumerate() {
            for &(b, (s2, e2)) in &ran[i + 1..] {
                let parallel = s1 < e2 && s2 < e1;
                let swapped = match (campaign.predicted[a], campaign.predicted[b]) {
                    (Some(pa), Some(pb)) => (pa.0 < pb.0 && s1 > s2) || (pa.0 > pb.0 && s1 < s2),
                    _ => false,
                };
                if parallel || swapped {
                    let e = counts.entry((a, b)).or_default();
                    e.0 += u64::from(parallel);
                    e.1 += u64::from(swapped);
                }
            }
        }
    }
    counts
        .into_iter()
        .map(|((a, b), (parallel, swapped))| PairSummary {
            a: campaign.activities[a].clone(),
            b: campaign.activities[b].clone(),
            parallel,
            swapped,
        })
        .collect()
}

/// Checks that `parts` are shards of one campaign covering every run exactly
/// once, every record consistent with its campaign header (see
/// [`read_runs`]), and returns the campaign and all records; errors name the
/// part by its index (`parts[2].records[4].outcomes`).
pub fn merge_parts(parts: &[RunsDoc]) -> Result<(Campaign, Vec<RunRecord>), Error> {
    let names: Vec<String> = (0..parts.len()).map(|i| format!("parts[{i}]")).collect();
    let named: Vec<(check::At<'_>, &RunsDoc)> = names
        .iter()
        .zip(parts)
        .map(|(name, doc)| (check::At::path(name), doc))
        .collect();
    check::merge_at(&named)
}

/// [`merge_parts`] of parts read from files: `(file name, part)`; errors name
/// the file and the JSON path in it (`part-3.json: records[4].outcomes`).
pub fn merge_files(parts: &[(String, RunsDoc)]) -> Result<(Campaign, Vec<RunRecord>), Error> {
    let named: Vec<(check::At<'_>, &RunsDoc)> = parts
        .iter()
        .map(|(name, doc)| (check::At::file(name), doc))
        .collect();
    check::merge_at(&named)
}
