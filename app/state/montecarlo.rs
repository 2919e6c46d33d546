//! Monte Carlo campaigns of the open plan (execution mode): one campaign's
//! summary with, per activity and cause, the first runs that lost it
//! ([`CampaignResult`]), and what the panel says about a campaign that is
//! running or did not finish ([`Progress`], [`Stopped`]). A campaign can also
//! compare the execution policies: the same runs under replan, dispatch and
//! fixed, one after the other ([`COMPARED`]). Built from the plan,
//! never edited; the app runs a campaign on a worker (`derived::CampaignCache`)
//! and shows its result only for the plan revision it ran on.

use std::sync::atomic::AtomicBool;

use solscope_engine::{
    ActivitySummary, MJ_PER_WH, Plan, Policy, Summary, campaign_runs, campaign_with, summarize,
};

/// The policies a comparison runs, in this order: the replanning executive
/// first (its campaign is the one the panel, the activity list and the
/// inspector detail), then the flexible schedule's dispatcher, then the
/// schedule executed as it is.
pub const COMPARED: [Policy; 3] = [Policy::Replan, Policy::Dispatch, Policy::Fixed];

/// The most runs the app runs in one campaign: every run's record (a few kB
/// on the bundled plan) is held until the summary is made, and 20,000 runs of
/// the bundled plan take minutes. The command line has no such limit, and
/// shards a campaign across machines.
pub const MAX_RUNS: u64 = 20_000;

/// How many runs the app keeps per activity and cause to open (the lowest run
/// indices).
pub const LOST_RUNS_KEPT: usize = 8;

/// Bins of a histogram of the app's (the summary's twenty equal bins cut
/// through the limit).
const BINS: i128 = 20;

/// The narrowest bin (mJ: 0.1 Wh), so that runs all alike still show a bar.
const MIN_BIN_MJ: i128 = 360_000;

/// One bar of a histogram over the runs: `[from, to)` in Wh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bin {
    /// Lower edge (Wh).
    pub from: f64,
    /// Upper edge (Wh), not included.
    pub to: f64,
    /// Runs in it.
    pub runs: u64,
    /// Every value in it is below the limit.
    pub below: bool,
}

/// A finished campaign: the engine's summary, per activity and cause the
/// first runs in which the activity was lost to it, and histograms of the
/// lowest and handover state of charge with a bin edge at their limit.
#[derive(Clone, Debug, PartialEq)]
pub struct CampaignResult {
    /// The campaign seed (run `i` is `sample_run(plan, seed, i)`).
    pub seed: u64,
    /// The summary (`solscope.montecarlo/1`).
    pub summary: Summary,
    /// The lowest state of charge of the runs, binned with an edge at
    /// `battery.min_soc` (so a bar is all below it or all at or above it).
    pub lowest_bins: Vec<Bin>,
    /// The state of charge at the handover, binned with an edge at
    /// `handover.min_soc` (empty without a handover).
    pub handover_bins: Vec<Bin>,
    /// Per plan activity: per cause key, the first [`LOST_RUNS_KEPT`] runs
    /// that lost it to that cause, in the summary's cause order.
    lost_runs: Vec<Vec<(String, Vec<u64>)>>,
    /// `(activity, runs that lost it)` of every activity lost in some run,
    /// most runs first (then plan order).
    most_lost: Vec<(usize, u64)>,
    /// In a comparison, the summary of each policy of [`COMPARED`] over the
    /// same runs (the first is `summary`); empty otherwise.
    compared: Vec<Summary>,
}

impl CampaignResult {
    /// Runs `runs` runs of `plan` seeded with `seed` under the replanning
    /// executive and summarises them; with `compare`, then the same runs
    /// under each other policy of [`COMPARED`], one campaign after the other.
    /// `progress` is called after each run (from worker threads): `runs`
    /// times per policy. `Ok(None)` when `cancel` was set before every run
    /// was done.
    pub fn of(
        plan: &Plan,
        seed: u64,
        runs: u64,
        compare: bool,
        progress: &(dyn Fn() + Sync),
        cancel: Option<&AtomicBool>,
    ) -> Result<Option<Self>, String> {
        let Some(mut result) = Self::of_replan(plan, seed, runs, progress, cancel)? else {
            return Ok(None);
        };
        if compare {
            let mut compared = vec![result.summary.clone()];
            for policy in COMPARED.into_iter().skip(1) {
                let Some(s) = policy_summary(plan, seed, runs, policy, progress, cancel)? else {
                    return Ok(None);
                };
                compared.push(s);
            }
            result.compared = compared;
        }
        Ok(Some(result))
    }

    /// The replanning executive's campaign with everything the panel and the
    /// inspector show of it.
    fn of_replan(
        plan: &Plan,
        seed: u64,
        runs: u64,
        progress: &(dyn Fn() + Sync),
        cancel: Option<&AtomicBool>,
    ) -> Result<Option<Self>, String> {
        let c =
            campaign_with(plan, seed, runs, "plan", Policy::Replan).map_err(|e| e.to_string())?;
        let indices: Vec<u64> = (0..runs).collect();
        let Some(records) =
            campaign_runs(plan, &c, &indices, progress, cancel).map_err(|e| e.to_string())?
        else {
            return Ok(None);
        };
        let summary = summarize(&c, &records);
        let mut lost_runs: Vec<Vec<(String, Vec<u64>)>> = summary
            .activities
            .iter()
            .map(|s| {
                s.lost.as_ref().map_or_else(Vec::new, |l| {
                    l.causes
                        .iter()
                        .map(|c| (c.cause.clone(), Vec::new()))
                        .collect()
                })
            })
            .collect();
        // Records come in run order: the first kept are the lowest indices.
        for r in &records {
            for loss in &r.losses {
                let Some(causes) = lost_runs.get_mut(loss.activity) else {
                    continue;
                };
                if let Some((_, list)) = causes.iter_mut().find(|(c, _)| *c == loss.cause) {
                    if list.len() < LOST_RUNS_KEPT {
                        list.push(r.run);
                    }
                }
            }
        }
        let mj = |x: f64| (x * MJ_PER_WH).round() as i128;
        let lowest: Vec<i128> = records.iter().map(|r| i128::from(r.lowest_soc.0)).collect();
        let handover: Vec<i128> = records
            .iter()
            .filter_map(|r| r.handover_soc.map(i128::from))
            .collect();
        let handover_min = plan.handover.as_ref().and_then(|h| h.min_soc).map(mj);
        let mut most_lost: Vec<(usize, u64)> = summary
            .activities
            .iter()
            .enumerate()
            .filter_map(|(a, x)| x.lost.as_ref().map(|l| (a, l.runs)))
            .collect();
        most_lost.sort_by(|x, y| y.1.cmp(&x.1).then(x.0.cmp(&y.0)));
        Ok(Some(Self {
            seed,
            summary,
            lowest_bins: bins(&lowest, Some(mj(plan.battery.min_soc))),
            handover_bins: bins(&handover, handover_min),
            lost_runs,
            most_lost,
            compared: Vec::new(),
        }))
    }

    /// In a comparison, each policy's summary over the same runs, in the
    /// order of [`COMPARED`]; empty for a campaign of the replanning executive
    /// alone.
    pub fn compared(&self) -> &[Summary] {
        &self.compared
    }

    /// The number of runs.
    pub fn runs(&self) -> u64 {
        self.summary.runs
    }

    /// Plan activity `a` across the runs.
    pub fn activity(&self, a: usize) -> Option<&ActivitySummary> {
        self.summary.activities.get(a)
    }

    /// `(activity, runs that lost it)` of every activity the first cycle
    /// placed that some run lost, most runs first.
    pub fn most_lost(&self) -> &[(usize, u64)] {
        &self.most_lost
    }

    /// The first runs in which activity `a` was lost to `cause` (lowest run
    /// indices first, at most [`LOST_RUNS_KEPT`]).
    pub fn lost_runs(&self, a: usize, cause: &str) -> &[u64] {
        self.lost_runs
            .get(a)
            .and_then(|c| c.iter().find(|(k, _)| k == cause))
            .map_or(&[], |(_, runs)| runs.as_slice())
    }
}

/// The summary of `runs` runs of `plan` seeded with `seed` under `policy`
/// (`None` when cancelled).
fn policy_summary(
    plan: &Plan,
    seed: u64,
    runs: u64,
    policy: Policy,
    progress: &(dyn Fn() + Sync),
    cancel: Option<&AtomicBool>,
) -> Result<Option<Summary>, String> {
    let c = campaign_with(plan, seed, runs, "plan", policy).map_err(|e| e.to_string())?;
    let indices: Vec<u64> = (0..runs).collect();
    let records = campaign_runs(plan, &c, &indices, progress, cancel).map_err(|e| e.to_string())?;
    Ok(records.map(|r| summarize(&c, &r)))
}

/// At most about twenty equal bins of a round width over `values` (mJ), with
/// an edge at `limit`, so that every bin is all below it or all at or above.
fn bins(values: &[i128], limit: Option<i128>) -> Vec<Bin> {
    let (Some(&lo), Some(&hi)) = (values.iter().min(), values.iter().max()) else {
        return Vec::new();
    };
    let width = nice_width((hi - lo + 1 + BINS - 1) / BINS);
    // Edges on multiples of the width from the limit (or from zero).
    let anchor = limit.unwrap_or(0);
    let first = anchor + (lo - anchor).div_euclid(width) * width;
    let n = (hi - first) / width + 1;
    let mut counts = vec![0u64; usize::try_from(n).unwrap_or(0)];
    for &v in values {
        if let Some(c) = usize::try_from((v - first) / width)
            .ok()
            .and_then(|k| counts.get_mut(k))
        {
            *c += 1;
        }
    }
    let wh = |x: i128| x as f64 / MJ_PER_WH;
    counts
        .into_iter()
        .enumerate()
        .map(|(k, runs)| {
            let from = first + k as i128 * width;
            let to = from + width;
            Bin {
                from: wh(from),
                to: wh(to),
                runs,
                below: limit.is_some_and(|l| to <= l),
            }
        })
        .collect()
}

/// The smallest of 1, 2 and 5 times a power of ten of [`MIN_BIN_MJ`] that is
/// at least `at_least` (mJ), so that bin edges are round numbers of Wh.
fn nice_width(at_least: i128) -> i128 {
    let mut unit = MIN_BIN_MJ;
    loop {
        for k in [1, 2, 5] {
            if unit.saturating_mul(k) >= at_least {
                return unit.saturating_mul(k);
            }
        }
        if unit == i128::MAX {
            return unit;
        }
        unit = unit.saturating_mul(10);
    }
}

/// A campaign that is running.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    /// Its seed.
    pub seed: u64,
    /// Its number of runs (per policy in a comparison).
    pub runs: u64,
    /// It compares the policies of [`COMPARED`] (`runs` runs each, one
    /// policy after the other).
    pub compare: bool,
    /// Runs done so far (of every policy: at most [`Progress::total`]).
    pub done: u64,
    /// Cancel was asked for (the runs already started finish first).
    pub cancelling: bool,
}

impl Progress {
    /// The runs to do: `runs`, times three in a comparison.
    pub fn total(&self) -> u64 {
        total_runs(self.runs, self.compare)
    }

    /// In a comparison, the policy running and the runs done of it.
    pub fn policy(&self) -> Option<(Policy, u64)> {
        if !self.compare || self.runs == 0 {
            return None;
        }
        let k = usize::try_from(self.done / self.runs)
            .unwrap_or(usize::MAX)
            .min(COMPARED.len() - 1);
        let before = k as u64 * self.runs;
        COMPARED
            .get(k)
            .map(|&p| (p, self.done.saturating_sub(before).min(self.runs)))
    }
}

/// The runs of a campaign of `runs` runs: times three in a comparison.
pub fn total_runs(runs: u64, compare: bool) -> u64 {
    if compare {
        runs.saturating_mul(COMPARED.len() as u64)
    } else {
        runs
    }
}

/// Why a campaign stopped before its summary was made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopReason {
    /// The user cancelled it.
    Cancelled,
    /// The plan was edited while it ran: its summary would have been of the
    /// plan as it was.
    PlanEdited,
}

/// A campaign that stopped before its summary was made (nothing of it is
/// kept).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Stopped {
    /// Its seed.
    pub seed: u64,
    /// Its number of runs (per policy in a comparison).
    pub runs: u64,
    /// It compared the policies.
    pub compare: bool,
    /// Runs done when it stopped (of every policy).
    pub done: u64,
    /// Why.
    pub why: StopReason,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lost_runs_are_those_of_the_records() {
        let text = include_str!("../../assets/execution-examples/uncertain-drive.json");
        let plan = solscope_engine::load_plan(text).expect("example plan").plan;
        let result = CampaignResult::of(&plan, 1, 20, false, &|| {}, None)
            .expect("campaign")
            .expect("not cancelled");
        assert_eq!(result.runs(), 20);
        let c = solscope_engine::campaign(&plan, 1, 20, "plan").expect("campaign");
        let a = plan
            .activities
            .iter()
            .position(|x| x.id == "arm_science")
            .expect("activity");
        let lost = result.activity(a).and_then(|s| s.lost.as_ref());
        let cause = &lost.expect("lost in some runs").causes[0].cause;
        let runs = result.lost_runs(a, cause);
        assert!(!runs.is_empty() && runs.len() <= LOST_RUNS_KEPT);
        assert!(runs.windows(2).all(|w| w[0] < w[1]), "lowest first");
        for &r in runs {
            let record = solscope_engine::run_record(&plan, &c, r).expect("record");
            assert_ne!(record.outcomes.as_bytes()[a], b'c', "run {r} lost it");
        }
        assert!(result.lost_runs(a, "no such cause").is_empty());
    }

    #[test]
    fn histogram_bins_cut_through_the_limit_and_hold_every_run() {
        let wh = |x: i128| x * 3_600_000;
        let values = [wh(900), wh(950), wh(999), wh(1000), wh(1000), wh(1100)];
        let b = bins(&values, Some(wh(1000)));
        assert!(b.len() <= 21, "{}", b.len());
        assert_eq!(b.iter().map(|x| x.runs).sum::<u64>(), 6);
        // An edge at the limit: below it 3 runs, at or above it 3.
        let below: u64 = b.iter().filter(|x| x.below).map(|x| x.runs).sum();
        assert_eq!(below, 3);
        assert!(b.iter().any(|x| x.to == 1000.0 && x.below));
        assert!(b.iter().any(|x| x.from == 1000.0 && !x.below));
        assert!(b.windows(2).all(|w| w[0].to == w[1].from));
        // All alike: one bar of 0.1 Wh.
        let one = bins(&[wh(5), wh(5)], None);
        assert_eq!(one.len(), 1);
        assert_eq!(one[0].runs, 2);
        assert!((one[0].to - one[0].from - 0.1).abs() < 1e-9);
        assert!(bins(&[], Some(0)).is_empty());
    }

    #[test]
    fn a_comparison_counts_its_runs_policy_by_policy() {
        let p = |done| Progress {
            seed: 1,
            runs: 10,
            compare: true,
            done,
            cancelling: false,
        };
        assert_eq!(p(0).total(), 30);
        assert_eq!(p(0).policy(), Some((Policy::Replan, 0)));
        assert_eq!(p(9).policy(), Some((Policy::Replan, 9)));
        assert_eq!(p(10).policy(), Some((Policy::Dispatch, 0)));
        assert_eq!(p(25).policy(), Some((Policy::Fixed, 5)));
        assert_eq!(p(30).policy(), Some((Policy::Fixed, 10)));
        let single = Progress {
            compare: false,
            ..p(3)
        };
        assert_eq!((single.total(), single.policy()), (10, None));
    }

    #[test]
    fn a_comparison_summarises_each_policy_over_the_same_runs() {
        let text = include_str!("../../assets/execution-examples/uncertain-drive.json");
        let plan = solscope_engine::load_plan(text).expect("example plan").plan;
        let alone = CampaignResult::of(&plan, 1, 12, false, &|| {}, None)
            .expect("campaign")
            .expect("not cancelled");
        assert!(alone.compared().is_empty());
        let counted = std::sync::atomic::AtomicU64::new(0);
        let count = || {
            counted.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        };
        let both = CampaignResult::of(&plan, 1, 12, true, &count, None)
            .expect("campaign")
            .expect("not cancelled");
        assert_eq!(counted.into_inner(), 36, "each run once per policy");
        assert_eq!(both.summary, alone.summary, "replan's detail as alone");
        let policies: Vec<Policy> = both.compared().iter().map(|s| s.policy).collect();
        assert_eq!(policies, COMPARED);
        assert_eq!(both.compared()[0], alone.summary);
    }

    #[test]
    fn a_cancelled_campaign_has_no_result() {
        let text = include_str!("../../assets/execution-examples/uncertain-drive.json");
        let plan = solscope_engine::load_plan(text).expect("example plan").plan;
        let cancel = AtomicBool::new(true);
        let result = CampaignResult::of(&plan, 1, 20, true, &|| {}, Some(&cancel));
        assert_eq!(result, Ok(None));
    }
}
