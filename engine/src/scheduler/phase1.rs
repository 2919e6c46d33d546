//! Phase 1 of a scheduling step: the valid starts of each constraint category
//! (execution, dependency, unit resources, sequence engines, state requirements and
//! effects, data volume, UHF) as interval sets, and the point version of the same
//! checks for one start.

use super::Scope;
use super::cells::{cells, concave_feasible};
use super::phase2::worth_halving;
use super::problem::{Act, Dep, Win};
use super::state::State;
use super::trace::{Category, CategoryIntervals};
use crate::model::{AwakeMode, EffectAt};
use crate::timeline::{Interval, IntervalSet, atomic_valid, claimable_valid, cumulative_valid};

impl State<'_> {
    /// Valid starts of every phase-1 category for activity `a` with duration `d`.
    pub fn phase1(&self, a: usize, d: i64, scope: &Scope) -> Vec<CategoryIntervals> {
        self.phase1_in(a, d, scope, self.problem.h0, self.problem.h1)
    }

    /// Whether start `s` with duration `d` satisfies every phase-1 category but
    /// execution: the point version of [`State::phase1_in`] (which debug builds
    /// check it against), stopping at the first category that fails.
    pub(super) fn phase1_point(&self, a: usize, s: i64, d: i64, scope: &Scope) -> bool {
        let ok = self.phase1_point_unchecked(a, s, d, scope);
        debug_assert_eq!(
            ok,
            self.phase1_in(a, d, scope, s, s)
                .iter()
                .filter(|c| c.category != Category::Execution)
                .all(|c| c.valid.contains(s)),
            "phase1_point disagrees with phase1_in at {s}"
        );
        ok
    }

    fn phase1_point_unchecked(&self, a: usize, s: i64, d: i64, scope: &Scope) -> bool {
        let problem = self.problem;
        let act = &problem.acts[a];
        let e = s.saturating_add(d);
        // dependency
        let in_range = |x: &Dep| {
            self.dependency_range(x)
                .is_some_and(|(lo, hi)| lo <= s && s <= hi)
        };
        if !scope.deps(act).all(in_range) {
            return false;
        }
        // unit_resource
        if act.resources.iter().any(|&r| self.busy[r].overlaps(s, e)) {
            return false;
        }
        // sequence_engines
        if let (Some(cap), true) = (problem.engines, act.engines > 0) {
            if self
                .engines
                .max_on(s, e)
                .is_some_and(|(v, _)| v > cap - act.engines)
            {
                return false;
            }
        }
        // uhf
        if self.uhf_busy(a, s, e).next().is_some() {
            return false;
        }
        // state_requirement
        if !scope
            .reqs(act)
            .all(|r| self.states[r.state].requirement_holds(r.value, d, s))
        {
            return false;
        }
        // state_effect, data_volume: as phase 1 does them, where they can
        // take a start away (an activity without effects, or one that
        // neither fills the store nor meets the handover data limit, passes).
        let effects = !act.effects.is_empty();
        let data = (act.data > 0 && problem.data_cap.is_some() && !scope.skip_data_capacity)
            || (!act.mandatory
                && problem.handover_time.is_some()
                && problem.handover_data.is_some());
        [
            (Category::StateEffect, effects),
            (Category::DataVolume, data),
        ]
        .into_iter()
        .filter(|&(_, binds)| binds)
        .all(|(c, _)| self.category_valid(c, a, d, scope, s, s).contains(s))
    }

    /// Phase 1 restricted to starts in `[lo, hi]`.
    pub(crate) fn phase1_in(
        &self,
        a: usize,
        d: i64,
        scope: &Scope,
        lo: i64,
        hi: i64,
    ) -> Vec<CategoryIntervals> {
        Category::ALL
            .iter()
            .map(|&category| CategoryIntervals {
                category,
                valid: self.category_valid(category, a, d, scope, lo, hi),
            })
            .collect()
    }

    /// The starts in `[lo, hi]` that pass every phase-1 category but
    /// execution (which each window's range stands for): the intersection of
    /// [`State::phase1_in`]'s sets, which debug builds check it against. Each
    /// category is asked only over the starts the ones before it left, from
    /// their first to their last, and none once they leave nothing.
    pub(super) fn phase1_others(
        &self,
        a: usize,
        d: i64,
        scope: &Scope,
        lo: i64,
        hi: i64,
    ) -> IntervalSet {
        let mut valid = IntervalSet::single(lo, hi);
        for &category in &Category::ALL[1..] {
            let (Some(first), Some(last)) = (valid.first(), valid.last()) else {
                break;
            };
            valid = valid.intersect(&self.category_valid(category, a, d, scope, first, last));
        }
        #[cfg(debug_assertions)]
        debug_assert_eq!(
            valid,
            super::outside_execution(&self.phase1_in(a, d, scope, lo, hi), (lo, hi)),
            "phase 1 narrowed category by category differs from its sets"
        );
        valid
    }

    /// The data-volume category of activity `a` with duration `d` over starts
    /// in `[lo, hi]`.
    pub(super) fn data_category(&self, a: usize, d: i64, lo: i64, hi: i64) -> IntervalSet {
        self.category_valid(Category::DataVolume, a, d, &Scope::default(), lo, hi)
    }

    /// The valid starts in `[lo, hi]` of one phase-1 category.
    fn category_valid(
        &self,
        category: Category,
        a: usize,
        d: i64,
        scope: &Scope,
        lo: i64,
        hi: i64,
    ) -> IntervalSet {
        let problem = self.problem;
        let act = &problem.acts[a];
        let all = || IntervalSet::single(lo, hi);
        match category {
            Category::Execution => act
                .windows
                .iter()
                .map(|w| self.window_range(a, w, d))
                .collect(),
            Category::Dependency => {
                let mut dep = all();
                for x in scope.deps(act) {
                    match self.dependency_range(x) {
                        Some((lo, hi)) => dep = dep.clip(lo, hi),
                        None => dep = IntervalSet::empty(),
                    }
                }
                dep
            }
            Category::UnitResource => {
                let mut res = all();
                for &r in &act.resources {
                    res = res.intersect(&self.busy[r].valid(d, lo, hi));
                }
                res
            }
            Category::SequenceEngines => match problem.engines {
                Some(cap) if act.engines > 0 => {
                    claimable_valid(&self.engines, cap - act.engines, d, lo, hi)
                }
                _ => all(),
            },
            Category::StateRequirement => {
                let mut req = all();
                for r in scope.reqs(act) {
                    req =
                        req.intersect(&self.states[r.state].requirement_valid(r.value, d, lo, hi));
                }
                req
            }
            Category::StateEffect => {
                let mut eff = all();
                for (st, own) in effects_by_state(act, d, false) {
                    let valid = if scope.skip_end_effects {
                        self.states[st].start_effects_valid(&own, lo, hi)
                    } else {
                        self.states[st].effect_valid(&own, lo, hi)
                    };
                    eff = eff.intersect(&valid);
                }
                eff
            }
            Category::DataVolume => {
                let mut data = all();
                if let (true, Some(cap), false) =
                    (act.data > 0, problem.data_cap, scope.skip_data_capacity)
                {
                    data = self.data_valid(act.data, d, cap, lo, hi);
                }
                // The handover limit binds every optional activity, even one producing
                // nothing, once the placed activities have exceeded it.
                if let (false, Some(ht), Some(max)) =
                    (act.mandatory, problem.handover_time, problem.handover_data)
                {
                    let range = (problem.h0, ht);
                    data = data.intersect(&cumulative_valid(
                        self.produced,
                        max,
                        act.data,
                        d,
                        range,
                        (lo, hi),
                    ));
                }
                data
            }
            Category::Uhf => atomic_valid(self.uhf_busy(a, lo, hi.saturating_add(d)), d, lo, hi),
        }
    }

    /// The starts a dependency allows, `[target end + min_delay, target end +
    /// max_delay]`; `None` while its target is not placed.
    fn dependency_range(&self, x: &Dep) -> Option<(i64, i64)> {
        let (_, end) = self.placed[x.target]?;
        let lo = end.saturating_add(x.min_delay);
        let hi = x.max_delay.map_or(i64::MAX, |m| end.saturating_add(m));
        Some((lo, hi))
    }

    /// The placed intervals overlapping `[from, to)` that activity `a` may not
    /// overlap on UHF grounds: comm activities of a kind it does not allow,
    /// and, for a comm activity, activities that do not allow its kind.
    fn uhf_busy(&self, a: usize, from: i64, to: i64) -> impl Iterator<Item = (i64, i64)> + '_ {
        let problem = self.problem;
        let act = &problem.acts[a];
        let comms = self
            .comms
            .overlapping(from, to)
            .filter(move |c| !act.allows(c.2.0))
            .map(|c| (c.0, c.1));
        let restricted = act.comm.into_iter().flat_map(move |kind| {
            self.restricted
                .overlapping(from, to)
                .filter(move |r| !problem.acts[r.2].allows(kind))
                .map(|r| (r.0, r.1))
        });
        comms.chain(restricted)
    }

    /// The times `t` in `[lo, hi]` at which activity `a`'s effects at its end break
    /// no placed requirement. An end effect at `s + d` holds until the next placed
    /// effect whatever `s` and `d` are, so a start `s` with duration `d` passes the
    /// end-effect part of state_effect exactly when `s + d` is among these (the
    /// start effects are checked apart, `Scope::skip_end_effects`).
    pub(super) fn end_effect_times(&self, a: usize, lo: i64, hi: i64) -> IntervalSet {
        let act = &self.problem.acts[a];
        let mut out = IntervalSet::single(lo, hi);
        for (st, own) in effects_by_state(act, 0, true) {
            out = out.intersect(&self.states[st].effect_valid(&own, lo, hi));
        }
        out
    }

    /// The execution range of window `w` of activity `a` for duration `d`: the
    /// window, its cutoff, the plan bounds, and for an activity that needs the rover
    /// awake room for the wakeup before and the shutdown after it.
    pub fn window_range(&self, a: usize, w: &Win, d: i64) -> Interval {
        let problem = self.problem;
        let (wake, shut) = if problem.acts[a].awake == AwakeMode::Required {
            (problem.wake, problem.shut)
        } else {
            (0, 0)
        };
        // The rover already awake at the start of a cycle needs no wakeup there.
        let first = match problem.awake0 {
            Some((w0, _)) if wake > 0 => w0.saturating_add(wake).max(problem.h0),
            _ => problem.h0.saturating_add(wake),
        };
        let lo = w.start.max(first);
        let mut hi = w.end.min(problem.h1.saturating_sub(d).saturating_sub(shut));
        if let Some(c) = w.cutoff {
            hi = hi.min(c.saturating_sub(d));
        }
        Interval::new(lo, hi)
    }

    /// Starts where adding `rate` bit/s over `[s, s + d)` keeps the volume <= `cap`.
    fn data_valid(&self, rate: i64, d: i64, cap: i128, lo: i64, hi: i64) -> IntervalSet {
        let margin = |s: i64| self.data.check(&[(s, s + d, rate)], None).min + cap;
        // While everything stored so far and this activity's volume fit in
        // the store together, every start fits: no levels needed (until the
        // store can fill, a placement derives no data levels at all).
        let energy = i128::from(rate) * i128::from(d);
        if self.data.lowest_bound() - energy >= -cap {
            #[cfg(debug_assertions)]
            for s in [lo, lo + (hi - lo) / 2, hi] {
                debug_assert!(margin(s) >= 0, "data volume bound wrong at {s}");
            }
            return IntervalSet::single(lo, hi);
        }
        if lo == hi {
            return if margin(lo) >= 0 {
                IntervalSet::single(lo, lo)
            } else {
                IntervalSet::empty()
            };
        }
        // Starts the added volume cannot push over the cap even in the worst case
        // need no search; debug builds check them exactly.
        let sure = self
            .data
            .surely_at_least(lo, hi, energy, -cap)
            .map_or_else(IntervalSet::empty, |(a, b)| IntervalSet::single(a, b));
        #[cfg(debug_assertions)]
        for iv in sure.intervals() {
            for s in [iv.lo, iv.lo + (iv.hi - iv.lo) / 2, iv.hi] {
                debug_assert!(margin(s) >= 0, "data bound wrong at {s}");
            }
        }
        let rest = IntervalSet::single(lo, hi).subtract(&sure);
        if rest.is_empty() {
            return sure;
        }
        // The rest is searched over spans of starts, as the phase-2 search
        // goes over them: a span where the bound on the lowest level (the
        // volume at its highest, negated) with the added volume proves every
        // start overflows is skipped whole, a span with few breakpoints is
        // split into cells; in between, it is halved. A full store then costs
        // about the places where the volume could still fit, not every cell
        // of the horizon.
        let fails = |a: i64, b: i64| self.data.drain_bound(a, b.saturating_add(d), energy) < -cap;
        let rate_points = self.data.rate().points();
        let splits = |a: i64, b: i64| worth_halving(rate_points, a, b, b.saturating_add(d));
        let mut feasible = sure.intervals().to_vec();
        let mut spans: Vec<(i64, i64)> = rest.intervals().iter().map(|iv| (iv.lo, iv.hi)).collect();
        while let Some((a, b)) = spans.pop() {
            if fails(a, b) {
                continue;
            }
            if splits(a, b) {
                let mid = a + (b - a) / 2;
                spans.push((a, mid));
                spans.push((mid + 1, b));
                continue;
            }
            feasible.extend(self.data_cells(&margin, d, a, b));
        }
        #[cfg(debug_assertions)]
        {
            let mut all = sure.intervals().to_vec();
            for iv in rest.intervals() {
                all.extend(self.data_cells(&margin, d, iv.lo, iv.hi));
            }
            debug_assert_eq!(
                IntervalSet::from_intervals(feasible.clone()),
                IntervalSet::from_intervals(all),
                "skipping spans changed the data category"
            );
        }
        IntervalSet::from_intervals(feasible)
    }

    /// The starts in `[lo, hi]` whose data `margin` (concave between the
    /// breakpoints a piece of length `d` can reach) is not negative, cell by
    /// cell.
    fn data_cells(&self, margin: &dyn Fn(i64) -> i128, d: i64, lo: i64, hi: i64) -> Vec<Interval> {
        // Only breakpoints that a piece starting in [lo, hi] can reach split cells
        // (the breakpoints are sorted).
        let near = self.data.breakpoints_in(lo, hi + d + 1);
        let mut points: Vec<i64> = Vec::with_capacity(near.len() * 4);
        // One sorted run per shift (`cells` merges the runs).
        for shift in [0, 1, 1 - d, -d] {
            points.extend(near.iter().map(|&x| x + shift));
        }
        cells(&IntervalSet::single(lo, hi), points)
            .into_iter()
            .filter_map(|(a, b)| concave_feasible(a, b, margin).0)
            .collect()
    }
}

/// The activity's effects grouped by the state they change (states in order),
/// each group as `(offset, value)` sorted, with offset 0 for an effect at the
/// start and `end` for one at the end; with `ends_only`, the effects at the end
/// alone.
fn effects_by_state(act: &Act, end: i64, ends_only: bool) -> Vec<(usize, Vec<(i64, usize)>)> {
    let kept = |at: EffectAt| !ends_only || at == EffectAt::End;
    let mut states: Vec<usize> = act
        .effects
        .iter()
        .filter(|e| kept(e.at))
        .map(|e| e.state)
        .collect();
    states.sort_unstable();
    states.dedup();
    states
        .into_iter()
        .map(|st| {
            let mut own: Vec<(i64, usize)> = act
                .effects
                .iter()
                .filter(|e| e.state == st && kept(e.at))
                .map(|e| (if e.at == EffectAt::Start { 0 } else { end }, e.value))
                .collect();
            own.sort_unstable();
            (st, own)
        })
        .collect()
}
