//! The two searches: every order (exact mode) or squeaky-wheel moves driven by
//! the evidence of the losses (evidence mode).

use std::collections::BTreeSet;
use std::sync::atomic::{AtomicBool, Ordering};

use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{RngCore, SeedableRng};
use rayon::prelude::*;

use super::order::Rules;
use super::score::{Eval, Sample, Score, Scorer};
use super::{Mode, Stop};
use crate::error::Error;

/// Candidates scored together (in parallel) before one is chosen: a constant,
/// so that the orders scored, and the result, do not depend on the threads.
const BATCH: usize = 8;

/// Restarts in a row that find nothing better before the search ends.
const RESTARTS: u64 = 3;

/// The search's state: what it has scored and the best order so far.
pub(crate) struct Search<'s, 'p> {
    pub scorer: &'s Scorer<'p>,
    pub rules: &'s Rules,
    pub sample: Sample,
    pub budget: u64,
    pub cancel: Option<&'s AtomicBool>,
    pub progress: Option<super::TuneProgress<'s>>,
    /// Orders scored on the tuning sample.
    pub evaluations: u64,
    /// Orders already scored.
    seen: BTreeSet<Vec<usize>>,
    /// The best order and its score.
    pub best: (Vec<usize>, Score),
    pub stop: Stop,
}

impl<'s, 'p> Search<'s, 'p> {
    pub fn new(
        scorer: &'s Scorer<'p>,
        rules: &'s Rules,
        sample: Sample,
        budget: u64,
        original: &Eval,
    ) -> Self {
        let mut seen = BTreeSet::new();
        seen.insert(rules.original.clone());
        Self {
            scorer,
            rules,
            sample,
            budget,
            cancel: None,
            progress: None,
            evaluations: 1,
            seen,
            best: (rules.original.clone(), original.score.clone()),
            stop: Stop::Finished,
        }
    }

    fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }

    fn left(&self) -> u64 {
        self.budget.saturating_sub(self.evaluations)
    }

    /// Scores `orders` (in parallel, results in order); `None` when cancelled.
    fn score_all(&mut self, orders: &[Vec<usize>]) -> Result<Option<Vec<Score>>, Error> {
        let scorer = self.scorer;
        let rules = self.rules;
        let (sample, cancel) = (self.sample, self.cancel);
        let results: Vec<Result<Option<Score>, Error>> = orders
            .par_iter()
            .map(|o| {
                let Some(pr) = rules.priorities(scorer.plan, o) else {
                    return Err(Error::invalid("$", "an order without priorities"));
                };
                let plan = scorer.with_priorities(&pr);
                Ok(scorer
                    .evaluate(&plan, sample, rules.changes(o), false, cancel)?
                    .map(|e| e.score))
            })
            .collect();
        let mut out = Vec::with_capacity(orders.len());
        for r in results {
            match r? {
                Some(s) => out.push(s),
                None => return Ok(None),
            }
        }
        self.evaluations += orders.len() as u64;
        for (o, s) in orders.iter().zip(&out) {
            self.seen.insert(o.clone());
            if *s > self.best.1 {
                self.best = (o.clone(), s.clone());
            }
        }
        if let Some(p) = self.progress {
            p(self.evaluations, &self.best.1);
        }
        Ok(Some(out))
    }

    /// Exact mode: every order the rules allow (the original first), within the
    /// budget; the best wins, ties to the one enumerated first.
    pub fn exact(&mut self) -> Result<(), Error> {
        let limit = usize::try_from(self.budget).unwrap_or(usize::MAX);
        let (orders, more) = self.rules.enumerate(limit);
        let orders: Vec<Vec<usize>> = orders
            .into_iter()
            .filter(|o| !self.seen.contains(o))
            .filter(|o| self.rules.priorities(self.scorer.plan, o).is_some())
            .collect();
        let mut at = 0;
        while at < orders.len() {
            if self.cancelled() {
                self.stop = Stop::Cancelled;
                return Ok(());
            }
            let take = (orders.len() - at).min(BATCH * 4).min(self.left() as usize);
            if take == 0 {
                self.stop = Stop::Budget;
                return Ok(());
            }
            if self.score_all(&orders[at..at + take])?.is_none() {
                self.stop = Stop::Cancelled;
                return Ok(());
            }
            at += take;
        }
        if more {
            self.stop = Stop::Budget;
        }
        Ok(())
    }

    /// Evidence mode: squeaky-wheel descents from the original (or the
    /// mandatory-first order, when it scores better) and from seeded
    /// perturbations of the best order.
    pub fn evidence(&mut self, original: Eval, seed: u64) -> Result<(), Error> {
        let mut current = (self.rules.original.clone(), original);
        // The mandatory-first order first (one evaluation): the descent starts
        // from it when it scores better than the original.
        if let Some(order) = self.mandatory_first() {
            if self.left() == 0 {
                self.stop = Stop::Budget;
                return Ok(());
            }
            let Some(scores) = self.score_all(std::slice::from_ref(&order))? else {
                self.stop = Stop::Cancelled;
                return Ok(());
            };
            if scores[0] > current.1.score {
                match self.with_evidence(&order)? {
                    Some(eval) => current = (order, eval),
                    None => {
                        self.stop = Stop::Cancelled;
                        return Ok(());
                    }
                }
            }
        }
        let mut restart = 0u64;
        let mut since_better = 0u64;
        loop {
            let before = self.best.1.clone();
            if let Some(stop) = self.descend(&mut current)? {
                self.stop = stop;
                return Ok(());
            }
            since_better = if self.best.1 > before {
                0
            } else {
                since_better + 1
            };
            if since_better > RESTARTS {
                self.stop = Stop::Finished;
                return Ok(());
            }
            // Restart from the best order, shaken by the search's own seed.
            // A shake that gives an order already scored draws again.
            let mut start = None;
            for _ in 0..8 {
                restart += 1;
                start = self.perturb(seed, restart);
                if start.is_some() {
                    break;
                }
            }
            let Some(start) = start else {
                self.stop = Stop::Finished;
                return Ok(());
            };
            if self.left() == 0 {
                self.stop = Stop::Budget;
                return Ok(());
            }
            if self.score_all(std::slice::from_ref(&start))?.is_none() {
                self.stop = Stop::Cancelled;
                return Ok(());
            }
            match self.with_evidence(&start)? {
                Some(eval) => current = (start, eval),
                None => {
                    self.stop = Stop::Cancelled;
                    return Ok(());
                }
            }
        }
    }

    /// The original order with every mandatory activity, and every activity
    /// one must follow, ahead of the rest, each part in the original order
    /// (dependency pairs keep their order: the first part holds every
    /// activity's predecessors). `None` when that is the original order, was
    /// scored already, or moves a pinned activity.
    fn mandatory_first(&self) -> Option<Vec<usize>> {
        let plan = self.scorer.plan;
        let n = self.rules.len();
        let mut first = vec![false; n];
        let mut stack: Vec<usize> = (0..n)
            .filter(|&a| plan.activities.get(a).is_some_and(|x| x.mandatory))
            .collect();
        while let Some(a) = stack.pop() {
            if !first[a] {
                first[a] = true;
                stack.extend(self.rules.before[a].iter().copied());
            }
        }
        let (head, tail): (Vec<usize>, Vec<usize>) =
            self.rules.original.iter().partition(|&&a| first[a]);
        let order: Vec<usize> = head.into_iter().chain(tail).collect();
        (order != self.rules.original
            && !self.seen.contains(&order)
            && self.rules.keeps(&order)
            && self.rules.priorities(plan, &order).is_some())
        .then_some(order)
    }

    /// The evaluation of `order` with its losses explained (not counted: the
    /// order was scored already).
    fn with_evidence(&self, order: &[usize]) -> Result<Option<Eval>, Error> {
        let Some(pr) = self.rules.priorities(self.scorer.plan, order) else {
            return Err(Error::invalid("$", "an order without priorities"));
        };
        let plan = self.scorer.with_priorities(&pr);
        self.scorer.evaluate(
            &plan,
            self.sample,
            self.rules.changes(order),
            true,
            self.cancel,
        )
    }

    /// One descent: moves from the evidence, in batches, the best improving
    /// one of a batch kept, until no move improves. `Some` when the budget or
    /// a cancel stopped it.
    fn descend(&mut self, current: &mut (Vec<usize>, Eval)) -> Result<Option<Stop>, Error> {
        loop {
            let candidates = self.moves(&current.0, &current.1);
            let mut improved = false;
            let mut at = 0;
            while at < candidates.len() {
                if self.cancelled() {
                    return Ok(Some(Stop::Cancelled));
                }
                let take = (candidates.len() - at).min(BATCH).min(self.left() as usize);
                if take == 0 {
                    return Ok(Some(Stop::Budget));
                }
                let batch = &candidates[at..at + take];
                let Some(scores) = self.score_all(batch)? else {
                    return Ok(Some(Stop::Cancelled));
                };
                // The best of the batch, the first on a tie.
                let mut pick: Option<usize> = None;
                for (i, s) in scores.iter().enumerate() {
                    if *s > current.1.score && pick.is_none_or(|p| *s > scores[p]) {
                        pick = Some(i);
                    }
                }
                if let Some(i) = pick {
                    let order = batch[i].clone();
                    match self.with_evidence(&order)? {
                        Some(eval) => *current = (order, eval),
                        None => return Ok(Some(Stop::Cancelled)),
                    }
                    improved = true;
                    break;
                }
                at += take;
            }
            if !improved {
                return Ok(None);
            }
        }
    }

    /// The moves the evidence suggests for `order`, in a fixed order: for each
    /// lost activity (most weighty first), ahead of each activity to blame
    /// that comes before it, or that activity after it; then one place up.
    /// Only orders the rules allow and not scored yet.
    fn moves(&self, order: &[usize], eval: &Eval) -> Vec<Vec<usize>> {
        let plan = self.scorer.plan;
        let Some(evidence) = &eval.evidence else {
            return Vec::new();
        };
        let mut lost: Vec<usize> = (0..order.len())
            .filter(|&a| eval.counts[a].lost() > 0)
            .collect();
        // Weight: mandatory first, then value lost (or, without values, the
        // original step order), then the runs lost.
        let has_values = self.scorer.has_values();
        lost.sort_by(|&x, &y| {
            let (ax, ay) = (&plan.activities[x], &plan.activities[y]);
            let lx = i128::from(eval.counts[x].lost());
            let ly = i128::from(eval.counts[y].lost());
            ay.mandatory.cmp(&ax.mandatory).then_with(|| {
                if has_values {
                    (super::score::micro(ay.value) * ly)
                        .cmp(&(super::score::micro(ax.value) * lx))
                        .then(self.rules.rank[x].cmp(&self.rules.rank[y]))
                } else {
                    self.rules.rank[x].cmp(&self.rules.rank[y])
                }
            })
        });
        if has_values {
            // Optional activities worth nothing gain nothing by moving.
            lost.retain(|&a| {
                plan.activities[a].mandatory || super::score::micro(plan.activities[a].value) > 0
            });
        }
        let mut out: Vec<Vec<usize>> = Vec::new();
        let push = |o: Option<Vec<usize>>, out: &mut Vec<Vec<usize>>| {
            if let Some(o) = o
                && !self.seen.contains(&o)
                && !out.contains(&o)
                && self.rules.keeps(&o)
                && self.rules.priorities(plan, &o).is_some()
            {
                out.push(o);
            }
        };
        for &a in &lost {
            for b in evidence.blockers(a) {
                push(Rules::ahead(order, a, b), &mut out);
                push(Rules::behind(order, b, a), &mut out);
            }
            if let Some(p) = order.iter().position(|&x| x == a)
                && p > 0
            {
                push(Rules::ahead(order, a, order[p - 1]), &mut out);
            }
        }
        out
    }

    /// The best order with a few random moves (seeded by the search seed and
    /// the restart), each kept only when the rules allow it and it is new.
    fn perturb(&self, seed: u64, restart: u64) -> Option<Vec<usize>> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(restart);
        let n = self.rules.len();
        if n < 2 {
            return None;
        }
        let free: Vec<usize> = (0..n).filter(|&a| !self.rules.pinned[a]).collect();
        if free.len() < 2 {
            return None;
        }
        let mut order = self.best.0.clone();
        let moves = 1 + (restart % 3);
        let mut done = 0;
        for _ in 0..64 {
            if done >= moves {
                break;
            }
            let a = free[(rng.next_u64() % free.len() as u64) as usize];
            let to = (rng.next_u64() % n as u64) as usize;
            let Some(from) = order.iter().position(|&x| x == a) else {
                continue;
            };
            if from == to {
                continue;
            }
            let mut o = order.clone();
            let x = o.remove(from);
            o.insert(to, x);
            if self.rules.keeps(&o) && self.rules.priorities(self.scorer.plan, &o).is_some() {
                order = o;
                done += 1;
            }
        }
        (done > 0 && !self.seen.contains(&order)).then_some(order)
    }
}

/// Which search runs: exact when at most this many activities can move.
pub(crate) const EXACT_MAX: usize = 8;

/// The mode for `movable` activities that can move.
pub(crate) fn mode_for(movable: usize) -> Mode {
    if movable <= EXACT_MAX {
        Mode::Exact
    } else {
        Mode::Evidence
    }
}
