//! Failure steps in one replay of the run.
//!
//! The scheduler is greedy and never moves a placed activity, so the partial
//! schedule after step k is exactly the prefix of the full run. The replay probes
//! every failed activity whose failure step is still unknown against the state
//! after each step k (with the spec's inclusion rule for dependencies and
//! requirements); the first k at which a probe fails is the failure step — exact,
//! with no monotonicity assumption. The replay is event-driven: after a passing
//! probe a target keeps its placement (the witness) and is looked at again only at
//! the first step that could disturb it ([`next_check`]).

use super::floors::Floors;
use super::spending::Spending;
use crate::model::AwakeMode;
use crate::scheduler::{
    Detail, Evaluated, FailurePhase, Outcome, Problem, Schedule, Scope, State, Step, StepTrace,
    run_step,
};

/// The inclusion rule precomputed: for each `(state, value)`, the steps of the
/// activities with an effect setting it, sorted, so that an activity's thresholds
/// cost O(log N) per requirement instead of a scan of the plan.
struct Inclusion<'a> {
    problem: &'a Problem,
    setters: std::collections::HashMap<(usize, usize), Vec<usize>>,
}

/// For one activity: the last step before it of any activity that could satisfy
/// each dependency / requirement (0 when none). Entry `j` is excluded at step `k`
/// iff `k < threshold[j]`.
struct Thresholds {
    deps: Vec<usize>,
    reqs: Vec<usize>,
}

impl<'a> Inclusion<'a> {
    fn new(problem: &'a Problem) -> Self {
        let mut setters: std::collections::HashMap<(usize, usize), Vec<usize>> =
            std::collections::HashMap::new();
        for (x, act) in problem.acts.iter().enumerate() {
            for e in &act.effects {
                setters
                    .entry((e.state, e.value))
                    .or_default()
                    .push(problem.step_of[x]);
            }
        }
        for v in setters.values_mut() {
            v.sort_unstable();
            v.dedup();
        }
        Self { problem, setters }
    }

    fn thresholds(&self, a: usize) -> Thresholds {
        let act = &self.problem.acts[a];
        let mine = self.problem.step_of[a];
        let deps = act
            .after
            .iter()
            .map(|d| {
                let t = self.problem.step_of[d.target];
                if d.target != a && t < mine { t } else { 0 }
            })
            .collect();
        // The activity's own step is never "before" it, so `< mine` excludes it.
        let reqs = act
            .requires
            .iter()
            .map(|req| {
                self.setters
                    .get(&(req.state, req.value))
                    .map_or(0, |steps| {
                        let below = steps.partition_point(|&x| x < mine);
                        if below == 0 { 0 } else { steps[below - 1] }
                    })
            })
            .collect();
        Thresholds { deps, reqs }
    }
}

impl Thresholds {
    fn scope_at(&self, k: usize) -> Scope {
        let pending = |t: &usize| k < *t;
        Scope {
            skip_deps: (0..self.deps.len())
                .filter(|&j| pending(&self.deps[j]))
                .collect(),
            skip_reqs: (0..self.reqs.len())
                .filter(|&j| pending(&self.reqs[j]))
                .collect(),
            skip_end_effects: false,
            skip_data_capacity: false,
        }
    }
}

/// What applying one scheduled step changes, for deciding which witnesses it can
/// disturb ([`next_check`]).
struct Applied {
    act: usize,
    /// Footprint `[lo, hi)` of the placement.
    lo: i64,
    hi: i64,
}

/// Per-step effects of the run, precomputed by one replay: what each scheduled step
/// touches, and running totals of the energy (mJ, absolute) and data (bit) that
/// steps 1..=k add, so that "the budget left at step k is used up at step j" is a
/// binary search.
struct RunEffects {
    applied: Vec<Option<Applied>>,
    energy: Vec<i128>,
    data: Vec<i128>,
    handover: Vec<i128>,
    /// Per group, the steps that scheduled a member, ascending.
    group_steps: Vec<Vec<usize>>,
    /// How far the wake/sleep and preheat rules can couple two placements: the
    /// widening of a witness's footprint in [`next_check`].
    reach: i64,
    /// Over the steps, `(lowest lo, highest hi)` of the applied footprints per
    /// node of a complete binary tree (leaves from `leaves`): the first step after
    /// `k` whose footprint meets a span, without a scan of every step.
    tree: Vec<(i64, i64)>,
    leaves: usize,
    /// Per state: the steps whose activity has an effect on it, and those whose
    /// activity has an effect on it or requires it, ascending.
    effect_steps: Vec<Vec<usize>>,
    touch_steps: Vec<Vec<usize>>,
    /// The charge each placing step changes, by step and by the time its
    /// changes start at (the footprint's start).
    spending: Spending,
    /// The lowest levels after each placing step.
    floors: Floors,
}

impl RunEffects {
    /// The effects of the run's first `upto` steps: a probe asks about the
    /// steps before its target's own only (a witness is due again before
    /// that step or not at all), so the steps after the last target's are
    /// never read. Explaining one early failure (the app's inspector, `explain
    /// --activity`) then replays the run only that far.
    fn new(sched: &Schedule, upto: usize) -> Self {
        let problem = &sched.problem;
        let steps = &sched.steps[..upto.min(sched.steps.len())];
        let n = steps.len();
        let mut out = RunEffects {
            applied: Vec::with_capacity(n + 1),
            energy: Vec::with_capacity(n + 1),
            data: Vec::with_capacity(n + 1),
            handover: Vec::with_capacity(n + 1),
            group_steps: Vec::new(),
            tree: Vec::new(),
            leaves: 0,
            effect_steps: Vec::new(),
            touch_steps: Vec::new(),
            spending: Spending::new([]),
            floors: Floors::empty(),
            reach: {
                let preheat = problem
                    .zones
                    .iter()
                    .map(|z| z.longest_preheat())
                    .max()
                    .unwrap_or(0);
                problem.min_sleep.max(1)
                    + problem.wake
                    + problem.shut
                    + problem.min_awake
                    + preheat
                    + 2
            },
        };
        out.applied.push(None);
        out.energy.push(0);
        out.data.push(0);
        out.handover.push(0);
        let mut state = State::new(problem);
        let placing = steps
            .iter()
            .filter(|s| s.outcome.placement().is_some())
            .count();
        out.floors = Floors::grid(&state, placing);
        let mut spent = Vec::new();
        for step in steps {
            let (mut e, mut d, mut h) = (0, 0, 0);
            let mut applied = None;
            if let Some(ev) = state.replay(step) {
                if let Some((start, end)) = step.outcome.placement() {
                    let act = &problem.acts[step.activity];
                    let produced = i128::from(act.data.max(0));
                    e = ev.energy;
                    d = produced * i128::from(end - start);
                    if let Some(ht) = problem.handover_time {
                        h = produced * overlap((start, end), (problem.h0, ht));
                    }
                    let (lo, hi) = ev.footprint(problem);
                    applied = Some(Applied {
                        act: step.activity,
                        lo,
                        hi,
                    });
                    if let Some(g) = act.group {
                        if out.group_steps.len() <= g {
                            out.group_steps.resize(g + 1, Vec::new());
                        }
                        out.group_steps[g].push(step.step);
                    }
                }
            }
            if let Some(p) = &applied {
                let act = &problem.acts[step.activity];
                let j = out.applied.len();
                spent.push((j, p.lo, e));
                out.floors.record(&state, j);
                for e in &act.effects {
                    push_step(&mut out.effect_steps, e.state, j);
                    push_step(&mut out.touch_steps, e.state, j);
                }
                for r in &act.requires {
                    push_step(&mut out.touch_steps, r.state, j);
                }
            }
            out.applied.push(applied);
            let last = |v: &Vec<i128>| v.last().copied().unwrap_or(0);
            out.energy.push(last(&out.energy).saturating_add(e));
            out.data.push(last(&out.data).saturating_add(d));
            out.handover.push(last(&out.handover).saturating_add(h));
        }
        out.spending = Spending::new(spent);
        out.floors.finish();
        out.leaves = out.applied.len().next_power_of_two();
        out.tree = vec![(i64::MAX, i64::MIN); 2 * out.leaves];
        for (j, p) in out.applied.iter().enumerate() {
            if let Some(p) = p {
                out.tree[out.leaves + j] = (p.lo, p.hi);
            }
        }
        for i in (1..out.leaves).rev() {
            let (l, r) = (out.tree[2 * i], out.tree[2 * i + 1]);
            out.tree[i] = (l.0.min(r.0), l.1.max(r.1));
        }
        out
    }

    /// The first step in `[from, to)` whose applied footprint meets `[lo, hi)`
    /// (`to` when none): a descent that skips every subtree whose footprints all
    /// end by `lo` or start at `hi` or later.
    fn first_meeting(&self, from: usize, to: usize, lo: i64, hi: i64) -> usize {
        fn go(
            fx: &RunEffects,
            node: usize,
            nlo: usize,
            nhi: usize,
            q: (usize, usize, i64, i64),
        ) -> Option<usize> {
            let (from, to, lo, hi) = q;
            let (min_lo, max_hi) = fx.tree[node];
            if nhi <= from || to <= nlo || min_lo >= hi || max_hi <= lo {
                return None;
            }
            if nhi - nlo == 1 {
                return Some(nlo);
            }
            let mid = (nlo + nhi) / 2;
            go(fx, 2 * node, nlo, mid, q).or_else(|| go(fx, 2 * node + 1, mid, nhi, q))
        }
        if from >= to {
            return to;
        }
        go(self, 1, 0, self.leaves, (from, to, lo, hi)).unwrap_or(to)
    }

    /// The first step in `[from, to)` whose activity shares a state with `a`
    /// ([`share_state`]; `to` when none).
    fn first_sharing(&self, problem: &Problem, a: usize, from: usize, to: usize) -> usize {
        let act = &problem.acts[a];
        let first = |steps: Option<&Vec<usize>>| {
            steps
                .and_then(|s| s.get(s.partition_point(|&j| j < from)).copied())
                .unwrap_or(to)
        };
        // Another's effect on a state `a` requires or sets; another's effect or
        // requirement on a state `a` sets.
        let by_effect = act
            .requires
            .iter()
            .map(|r| r.state)
            .chain(act.effects.iter().map(|e| e.state))
            .map(|s| first(self.effect_steps.get(s)));
        let by_touch = act
            .effects
            .iter()
            .map(|e| first(self.touch_steps.get(e.state)));
        by_effect.chain(by_touch).fold(to, usize::min).min(to)
    }

    /// The first step after `k` at which the witness `ev` (passing against the
    /// state after step `k`, draining `drain`) can stop passing on the state of
    /// charge, by two rules: the lowest levels after each step ([`Floors`]),
    /// and the local budget ([`State::soc_budget`]): the first step by which
    /// the steps changing the rate before the budget's end have spent it, or
    /// those changing it before the handover time the handover margin, or
    /// after which some level is below the minimum without the witness (the
    /// budget's argument needs every level at or above it).
    fn soc_due(
        &self,
        state: &State<'_>,
        ev: &Evaluated,
        drain: &[(i64, i64, i64)],
        k: usize,
    ) -> usize {
        let problem = state.problem;
        let never = usize::MAX;
        let handover = problem.handover_soc_of(ev.placement.act).map(|h| h.1);
        let (lo, _) = ev.footprint(problem);
        let floors = self
            .floors
            .first_below(k, lo, problem.min_soc, ev.energy, handover)
            .unwrap_or(never);
        let local = state.soc_budget(ev, drain).map_or(0, |b| {
            let mut due = self.floors.first_unsure(k, problem.min_soc);
            due = due.min(
                self.spending
                    .first_over(k, b.until, b.budget)
                    .unwrap_or(never),
            );
            if let Some((t, margin)) = b.handover {
                if margin < 0 {
                    return 0;
                }
                due = due.min(self.spending.first_over(k, t, margin).unwrap_or(never));
            }
            due
        });
        floors.max(local)
    }

    /// The first step after `k` whose running total exceeds the total at `k` by
    /// more than `budget` (`len` when none).
    fn exhausted(sums: &[i128], k: usize, budget: i128) -> usize {
        let base = sums[k];
        k + sums[k..].partition_point(|&x| x.saturating_sub(base) <= budget)
    }
}

/// A placement known to fit a probe target after step `k`, and the first later
/// step that could change that.
struct Witness {
    /// The passing evaluation.
    ev: Evaluated,
    /// Its charge drain.
    drain: Vec<(i64, i64, i64)>,
    /// The step it is due to be looked at again (`usize::MAX`: not before its own).
    due: usize,
    /// Whether only its energy margin can have changed by then.
    soc_only: bool,
}

/// Whether two activities share a state through effects on one side and effects or
/// requirements on the other (an effect's reach is not bounded in time).
fn share_state(problem: &Problem, a: usize, b: usize) -> bool {
    let touches = |x: usize, y: usize| {
        let (x, y) = (&problem.acts[x], &problem.acts[y]);
        x.effects.iter().any(|e| {
            y.requires.iter().any(|r| r.state == e.state)
                || y.effects.iter().any(|f| f.state == e.state)
        })
    };
    touches(a, b) || touches(b, a)
}

/// The first step after `k` that can change whether the witness `ev` of target `a`
/// (verified against the state after step `k`) still fits; the probe need not look
/// again before it. Sufficient conditions for "cannot change" (each placement
/// applied): the footprints, widened by the wake/sleep and preheat reach, are apart
/// (so every local category, the generated pieces and the peak power are
/// unchanged); no state is shared; the state of charge, data volume and handover
/// production move by at most the applied energy / data (capped and floored
/// integration is 1-Lipschitz) and the witness's margins cover the running total;
/// no scope threshold and no group member's placement comes first.
fn next_check(
    state: &State<'_>,
    fx: &RunEffects,
    th: &Thresholds,
    ev: &Evaluated,
    drain: &[(i64, i64, i64)],
    k: usize,
    until: usize,
) -> Due {
    let problem = state.problem;
    let a = ev.placement.act;
    let act = &problem.acts[a];
    let (s, d) = (ev.placement.start, ev.placement.duration);
    // Everything but the state of charge.
    let mut other = until;
    if let (Some(cap), true) = (problem.data_cap, act.data > 0) {
        let margin = cap + state.data.check(&[(s, s + d, act.data)], None).min;
        other = other.min(RunEffects::exhausted(&fx.data, k, margin));
    }
    if let (false, Some(ht), Some(max)) =
        (act.mandatory, problem.handover_time, problem.handover_data)
    {
        let margin = max
            - state.produced
            - i128::from(act.data.max(0)) * overlap((s, s + d), (problem.h0, ht));
        other = other.min(RunEffects::exhausted(&fx.handover, k, margin));
    }
    for &t in th.deps.iter().chain(&th.reqs) {
        if t > k {
            other = other.min(t);
        }
    }
    if let Some(steps) = act.group.and_then(|g| fx.group_steps.get(g)) {
        if let Some(&j) = steps.iter().find(|&&j| j > k) {
            other = other.min(j);
        }
    }
    // Only an activity that needs the rover awake (its awake period merges
    // with others near it) or heating (a heater on before it) is coupled to
    // placements beyond its footprint; any other one only to those that
    // overlap it (the placements' footprints hold everything they change).
    let (lo, hi) = ev.footprint(problem);
    let reach = if act.awake == AwakeMode::Required || !act.zones.is_empty() {
        fx.reach
    } else {
        1
    };
    let (lo, hi) = (lo.saturating_sub(reach), hi.saturating_add(reach));
    let end = other.min(fx.applied.len());
    let first = fx
        .first_meeting(k + 1, end, lo, hi)
        .min(fx.first_sharing(problem, a, k + 1, end));
    debug_assert_eq!(
        first,
        (k + 1..end)
            .find(|&j| {
                fx.applied[j]
                    .as_ref()
                    .is_some_and(|p| (p.lo < hi && lo < p.hi) || share_state(problem, a, p.act))
            })
            .unwrap_or(end),
        "disturbing step index"
    );
    if first < end {
        other = first;
    }
    // The state of charge: every later placement counted against the margin,
    // or (when that runs out first) the lowest levels after each step and the
    // local budget (`RunEffects::soc_due`).
    let mut soc = RunEffects::exhausted(&fx.energy, k, ev.margin);
    if soc < other {
        soc = soc.max(fx.soc_due(state, ev, drain, k));
    }
    Due {
        at: soc.min(other),
        soc_only: soc < other,
    }
}

/// When a witness is to be looked at again ([`next_check`]).
struct Due {
    /// The step.
    at: usize,
    /// Whether only the state of charge can have changed by then (nothing
    /// placed near it, no shared state, no scope or group change, data within
    /// its margins): a recheck of the energy margin decides then.
    soc_only: bool,
}

/// Appends step `j` to the list of state `s`.
fn push_step(lists: &mut Vec<Vec<usize>>, s: usize, j: usize) {
    if lists.len() <= s {
        lists.resize(s + 1, Vec::new());
    }
    if lists[s].last() != Some(&j) {
        lists[s].push(j);
    }
}

/// Length of the overlap of two half-open intervals.
fn overlap(a: (i64, i64), b: (i64, i64)) -> i128 {
    i128::from((a.1.min(b.1) - a.0.max(b.0)).max(0))
}

/// For each target `i` that fails, with its failure step `k`, the probe's step
/// record there and its tries and the state after step `k`: `build`s a value
/// (in parallel with the other targets probed at the same step) and hands it to
/// `on_failure(i, value)`, in order of the failure step, then of `i`;
/// `stepped(k)` once the steps up to `k` are replayed and their failures handed
/// on (at the end of each block of [`BLOCK_STEPS`]).
/// Targets that schedule at their own step (scheduled activities) get no call.
///
/// Each target is looked at only at the steps that can change its answer: after a
/// passing probe it keeps the placement found (its witness) and is due again at the
/// first later step that could disturb it ([`next_check`]); then a quick check of
/// the witness, and a search only when the witness stopped fitting.
///
/// Targets do not depend on one another, so they are dealt round-robin to one
/// lane per thread (at most [`MAX_LANES`]), each replaying the run on its own
/// state; the lanes go through the run in blocks of [`BLOCK_STEPS`] steps
/// together, and each block's failures are handed on in order before the next
/// block starts, so the values waiting at any time are one block's. A target's
/// probes, and so its value, do not depend on its lane: the output does not
/// depend on the number of threads.
pub(super) fn failure_probes<T: Send>(
    sched: &Schedule,
    targets: &[usize],
    build: impl Fn(usize, usize, Step, StepTrace, &State<'_>) -> T + Sync,
    mut on_failure: impl FnMut(usize, T),
    mut stepped: impl FnMut(usize),
) {
    let problem = &sched.problem;
    // Steps are 1-based: the last target's own step is `steps[upto - 1]`.
    let upto = targets
        .iter()
        .filter_map(|&a| problem.step_of.get(a).copied())
        .max()
        .unwrap_or(0);
    let fx = RunEffects::new(sched, upto);
    let inclusion = Inclusion::new(problem);
    let thresholds: Vec<Thresholds> = targets.iter().map(|&a| inclusion.thresholds(a)).collect();
    let open: Vec<usize> = (0..targets.len())
        .filter(|&i| sched.placement(targets[i]).is_none())
        .collect();
    let count = rayon::current_num_threads()
        .clamp(1, MAX_LANES)
        .min(open.len())
        .max(1);
    let mut lanes: Vec<Lane<'_>> = (0..count)
        .map(|l| Lane::new(problem, open.iter().copied().skip(l).step_by(count)))
        .collect();
    let ctx = LaneContext {
        sched,
        targets,
        fx: &fx,
        thresholds: &thresholds,
        build: &build,
    };
    let mut k = 0;
    while k < sched.steps.len() && lanes.iter().any(|l| !l.queue.is_empty()) {
        let end = (k + BLOCK_STEPS).min(sched.steps.len());
        let mut failed: Vec<(usize, usize, T)> = if lanes.len() > 1 {
            use rayon::prelude::*;
            lanes
                .par_iter_mut()
                .map(|lane| lane.run(&ctx, k, end))
                .reduce(Vec::new, |mut x, mut y| {
                    x.append(&mut y);
                    x
                })
        } else {
            lanes
                .iter_mut()
                .flat_map(|lane| lane.run(&ctx, k, end))
                .collect()
        };
        failed.sort_by_key(|&(step, i, _)| (step, i));
        for (_, i, value) in failed {
            on_failure(i, value);
        }
        stepped(end);
        k = end;
    }
}

/// The most lanes (replay states) [`failure_probes`] uses, however many threads
/// there are: each holds a full scheduler state.
const MAX_LANES: usize = 8;

/// Steps the lanes of [`failure_probes`] replay between two hand-overs: large
/// enough that the lanes rarely wait for one another, small enough that one
/// block's failures (the values waiting to be handed on) stay a small part of
/// the run's.
const BLOCK_STEPS: usize = 256;

/// What every lane of [`failure_probes`] reads.
struct LaneContext<'c, B> {
    sched: &'c Schedule,
    targets: &'c [usize],
    fx: &'c RunEffects,
    thresholds: &'c [Thresholds],
    build: &'c B,
}

/// One lane of [`failure_probes`]: its own replay of the run, and its targets'
/// witnesses and due steps.
struct Lane<'p> {
    state: State<'p>,
    /// Witness of target `i` (indexed by target), for this lane's targets.
    witness: std::collections::HashMap<usize, Witness>,
    /// (due step, target); a target is in the queue at most once.
    queue: std::collections::BinaryHeap<std::cmp::Reverse<(usize, usize)>>,
}

impl<'p> Lane<'p> {
    /// A lane for targets `mine`, each due at step 0.
    fn new(problem: &'p Problem, mine: impl Iterator<Item = usize>) -> Self {
        Self {
            state: State::new(problem),
            witness: std::collections::HashMap::new(),
            queue: mine.map(|i| std::cmp::Reverse((0, i))).collect(),
        }
    }

    /// Probes this lane's targets due at steps `from..to` (the lane's state is
    /// the one after step `from`) and replays those steps: `(failure step,
    /// target, value)` of the targets that failed.
    fn run<T: Send, B>(
        &mut self,
        ctx: &LaneContext<'_, B>,
        from: usize,
        to: usize,
    ) -> Vec<(usize, usize, T)>
    where
        B: Fn(usize, usize, Step, StepTrace, &State<'_>) -> T + Sync,
    {
        use std::cmp::Reverse;
        let (sched, targets) = (ctx.sched, ctx.targets);
        let mut failed = Vec::new();
        for k in from..to {
            if self.queue.is_empty() {
                break;
            }
            // Debug builds (the tests) check every skip against a full check.
            #[cfg(debug_assertions)]
            for (&i, w) in &self.witness {
                if w.due > k && k < sched.problem.step_of[targets[i]] {
                    let scope = ctx.thresholds[i].scope_at(k);
                    let p = &w.ev.placement;
                    debug_assert!(
                        self.state.fits(targets[i], p.start, p.duration, &scope),
                        "a skipped witness stopped fitting"
                    );
                }
            }
            // The targets due at this step, probed in parallel against the same
            // state; their results are taken in target order.
            let mut batch: Vec<(usize, Option<Witness>)> = Vec::new();
            while let Some(&Reverse((due, i))) = self.queue.peek() {
                if due > k {
                    break;
                }
                self.queue.pop();
                batch.push((i, self.witness.remove(&i)));
            }
            let state = &self.state;
            let probe = |(i, w): (usize, Option<Witness>)| {
                let a = targets[i];
                let probed = match probe_target(state, ctx.fx, &ctx.thresholds[i], a, w, k) {
                    Probed::Kept(w) => Ok(w),
                    Probed::Failed(step, trace) => Err((ctx.build)(i, k, step, trace, state)),
                };
                (i, probed)
            };
            let results: Vec<(usize, Result<Witness, T>)> = if batch.len() > 1 {
                use rayon::prelude::*;
                batch.into_par_iter().with_min_len(4).map(probe).collect()
            } else {
                batch.into_iter().map(probe).collect()
            };
            for (i, probed) in results {
                match probed {
                    Ok(w) => {
                        if w.due != usize::MAX {
                            self.queue.push(Reverse((w.due, i)));
                        }
                        self.witness.insert(i, w);
                    }
                    Err(value) => failed.push((k, i, value)),
                }
            }
            self.state.replay(&sched.steps[k]);
        }
        failed
    }
}

/// What probing one target at a step gave.
enum Probed {
    /// It still fits: its witness, due again at `due` (`usize::MAX`: not
    /// before its own step).
    Kept(Witness),
    /// It fails here: the failing probe's record and trace.
    Failed(Step, StepTrace),
}

/// Probes target activity `a` (thresholds `th`) against the state after step
/// `k`, starting from its witness `w`, if any.
///
/// A witness that still fits answers the probe without a search (the same
/// duration as before: a longer one could have become possible, but a probe
/// only asks whether the activity fails). A group member placed since skips
/// the activity, which no placement check sees; an unplaced dependency fails
/// the witness's phase-1 check. A witness rechecked on energy alone keeps its
/// drain (its retired awake periods are indices into an older state: not
/// rebuilt).
fn probe_target(
    state: &State<'_>,
    fx: &RunEffects,
    th: &Thresholds,
    a: usize,
    w: Option<Witness>,
    k: usize,
) -> Probed {
    let problem = state.problem;
    let until = problem.step_of[a];
    let scope = th.scope_at(k);
    let grouped = problem.acts[a]
        .group
        .is_some_and(|g| state.group_member[g].is_some());
    let kept = w.filter(|_| !grouped).and_then(|w| {
        let p = &w.ev.placement;
        if w.soc_only {
            let again = state.still_passing(&w.ev, &w.drain);
            debug_assert_eq!(
                again.as_ref().map(|e| e.margin),
                state
                    .fitting(a, p.start, p.duration, &scope)
                    .map(|e| e.margin),
                "a witness rechecked on energy alone"
            );
            if let Some(ev) = again {
                return Some((ev, Some(w.drain)));
            }
        } else if let Some(ev) = state.fitting(a, p.start, p.duration, &scope) {
            return Some((ev, None));
        }
        elsewhere(state, &scope, a, p.duration).map(|ev| (ev, None))
    });
    let (ev, drain) = match kept {
        Some(kept) => kept,
        None => {
            // Whether it fails does not depend on the span phase 1 covers
            // (phase 2 only looks inside the windows), so probe within the
            // window span, and redo the failing probe over the whole horizon
            // only when the relaxations need it (starts outside the windows).
            // The search asks for the outcome first: a probe that finds a
            // placement needs no tries, and the outcome-only search skips what
            // a bound proves to fail; only the failing probe, once per target,
            // records its tries.
            let probe = run_step(state, a, until, &scope, Detail::Intervals);
            match probe.found {
                Some(ev) => (sturdier_witness(state, &scope, &probe.trace, ev), None),
                None => {
                    let detail =
                        if probe.step.outcome == Outcome::Failed(FailurePhase::ValidIntervals) {
                            Detail::Horizon
                        } else {
                            Detail::Trace
                        };
                    let failed = run_step(state, a, until, &scope, detail);
                    debug_assert!(failed.found.is_none(), "outcome-only probe");
                    return Probed::Failed(failed.step, failed.trace);
                }
            }
        }
    };
    let drain = drain.unwrap_or_else(|| state.drain_of(&ev.placement));
    let next = next_check(state, fx, th, &ev, &drain, k, until);
    Probed::Kept(Witness {
        ev,
        drain,
        due: if next.at < until { next.at } else { usize::MAX },
        soc_only: next.soc_only,
    })
}

/// A witness that later placements are less likely to disturb than the
/// scheduler's choice `ev`: of the scheduler's start and the first and last
/// candidate starts of the probe (same duration), the one that fits with the
/// largest energy margin. Any placement that fits answers the probe; a larger
/// margin keeps the witness valid for more steps of the run (`next_check`).
fn sturdier_witness(
    state: &State<'_>,
    scope: &Scope,
    trace: &StepTrace,
    ev: Evaluated,
) -> Evaluated {
    let (a, d, chosen) = (ev.placement.act, ev.placement.duration, ev.placement.start);
    let ends = [trace.intersection.first(), trace.intersection.last()];
    ends.into_iter()
        .flatten()
        .filter(|&s| s != chosen)
        .filter_map(|s| state.fitting(a, s, d, scope))
        .fold(ev, |best, x| if x.margin > best.margin { x } else { best })
}

/// A placement of activity `a` with duration `d` at one of a few starts far from
/// where witnesses usually sit (the last and the middle start of each window's
/// range), if one fits: a probe whose witness stopped fitting is answered by any
/// placement that fits, and a point check costs far less than the search.
fn elsewhere(state: &State<'_>, scope: &Scope, a: usize, d: i64) -> Option<Evaluated> {
    let act = &state.problem.acts[a];
    act.windows.iter().find_map(|w| {
        let range = state.window_range(a, w, d);
        if range.is_empty() {
            return None;
        }
        [range.hi, range.lo + (range.hi - range.lo) / 2]
            .into_iter()
            .find_map(|s| state.fitting(a, s, d, scope))
    })
}
