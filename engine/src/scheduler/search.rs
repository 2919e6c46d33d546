//! Finding starts: phase-1 valid intervals per category, and the exact phase-2
//! search over cells between critical points.
//!
//! Phase 2 is exact at 1-second resolution without scanning every second. The
//! critical points are every fixed breakpoint (power, peak, heater, awake, sleep,
//! state changes, handover) shifted by every offset at which the candidate's
//! generated pieces start or end (0, d, -wakeup, d + shutdown, the min_awake
//! extensions, -preheat for every table duration), the merge thresholds
//! (`± min_sleep`), and the local times where the preheat table or operability
//! changes. Between two consecutive critical points the structure of the candidate
//! (which periods merge, which preheats exist, which segments its pieces overlap) is
//! fixed, so every structural and peak-power check is constant, and the lowest state
//! of charge is a concave function of the start (a minimum of linear functions and
//! of linear-minus-running-maximum terms). Each cell is therefore decided by a
//! handful of evaluations: its ends, and a binary search for the maximum and the
//! boundaries of the feasible part.

use super::Scope;
use super::problem::{Dep, Problem, Win};
use super::state::{Placement, State, uncovered};
use super::trace::{Category, CategoryIntervals, Phase2Reason, Try};
use crate::model::{AwakeMode, EffectAt};
use crate::timeline::{Interval, IntervalSet, atomic_valid, claimable_valid, cumulative_valid};

/// A candidate that passed the structural and peak checks, with its energy margin.
#[derive(Clone, Debug)]
pub struct Evaluated {
    /// The placement it would make.
    pub placement: Placement,
    /// `min(lowest soc - min_soc, handover soc - handover min)`; feasible iff >= 0.
    pub margin: i128,
    /// The energy reason when `margin < 0`.
    pub soc_reason: Option<Phase2Reason>,
    /// Total energy its load pieces change (mJ, absolute values): no time's state
    /// of charge moves by more than this when the placement is applied.
    pub energy: i128,
}

impl Evaluated {
    /// The span `[lo, hi)` of everything the placement touches or depends on
    /// directly: the activity, the awake period it needs or creates, its preheats.
    pub fn footprint(&self, pb: &Problem) -> (i64, i64) {
        let p = &self.placement;
        let e = p.start + p.duration;
        let (mut lo, mut hi) = (p.start, e);
        if pb.acts[p.act].awake == AwakeMode::Required {
            lo = lo.min(p.start - pb.wake);
            hi = hi.max(e + pb.shut);
        }
        if let Some((qa, qb)) = p.new_awake {
            lo = lo.min(qa);
            hi = hi.max(qb);
        }
        for &(_, ps, _) in &p.preheats {
            lo = lo.min(ps);
        }
        (lo, hi)
    }
}

impl State<'_> {
    /// Valid starts of every phase-1 category for activity `a` with duration `d`.
    pub fn phase1(&self, a: usize, d: i64, scope: &Scope) -> Vec<CategoryIntervals> {
        self.phase1_in(a, d, scope, self.pb.h0, self.pb.h1)
    }

    /// Whether activity `a` fits at start `s` with duration `d` (every phase-1
    /// category and phase 2), without searching: the explainer's quick re-check
    /// of a known placement.
    pub fn fits(&self, a: usize, s: i64, d: i64, scope: &Scope) -> bool {
        self.fitting(a, s, d, scope).is_some()
    }

    /// [`State::fits`], with the passing evaluation.
    pub fn fitting(&self, a: usize, s: i64, d: i64, scope: &Scope) -> Option<Evaluated> {
        let act = &self.pb.acts[a];
        let in_window = act
            .windows
            .iter()
            .any(|w| self.window_range(a, w, d).contains(s));
        if !in_window || !self.phase1_point(a, s, d, scope) {
            return None;
        }
        self.evaluate(a, s, d).ok().filter(|ev| ev.margin >= 0)
    }

    /// Whether start `s` with duration `d` satisfies every phase-1 category but
    /// execution: the point version of [`State::phase1_in`] (which debug builds
    /// check it against), stopping at the first category that fails.
    fn phase1_point(&self, a: usize, s: i64, d: i64, scope: &Scope) -> bool {
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
        let pb = self.pb;
        let act = &pb.acts[a];
        let e = s.saturating_add(d);
        let overlaps = |x: i64, y: i64| x < e && s < y;
        // dependency
        let in_range = |x: &Dep| {
            self.dependency_range(x)
                .is_some_and(|(lo, hi)| lo <= s && s <= hi)
        };
        if !act
            .after
            .iter()
            .enumerate()
            .all(|(k, x)| scope.skip_deps.contains(&k) || in_range(x))
        {
            return false;
        }
        // unit_resource
        if act
            .resources
            .iter()
            .any(|&r| self.busy[r].iter().any(|&(x, y)| overlaps(x, y)))
        {
            return false;
        }
        // sequence_engines
        if let (Some(cap), true) = (pb.engines, act.engines > 0) {
            if self
                .engines
                .max_on(s, e)
                .is_some_and(|(v, _)| v > cap - act.engines)
            {
                return false;
            }
        }
        // uhf
        if self.uhf_busy(a).any(|(x, y)| overlaps(x, y)) {
            return false;
        }
        // state_requirement, state_effect, data_volume: as phase 1 does them.
        self.phase1_states_data(a, d, scope, s, s)
            .iter()
            .all(|c| c.1.contains(s))
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
        let pb = self.pb;
        let act = &pb.acts[a];
        let all = || IntervalSet::single(lo, hi);
        let mut out = Vec::with_capacity(8);
        // execution
        let exec: IntervalSet = act
            .windows
            .iter()
            .map(|w| self.window_range(a, w, d))
            .collect();
        out.push((Category::Execution, exec));
        // dependency
        let mut dep = all();
        for (_, x) in act
            .after
            .iter()
            .enumerate()
            .filter(|(k, _)| !scope.skip_deps.contains(k))
        {
            match self.dependency_range(x) {
                Some((lo, hi)) => dep = dep.clip(lo, hi),
                None => dep = IntervalSet::empty(),
            }
        }
        out.push((Category::Dependency, dep));
        // unit_resource
        let mut res = all();
        for &r in &act.resources {
            res = res.intersect(&atomic_valid(&self.busy[r], d, lo, hi));
        }
        out.push((Category::UnitResource, res));
        // sequence_engines
        let eng = match pb.engines {
            Some(cap) if act.engines > 0 => {
                claimable_valid(&self.engines, cap - act.engines, d, lo, hi)
            }
            _ => all(),
        };
        out.push((Category::SequenceEngines, eng));
        out.extend(self.phase1_states_data(a, d, scope, lo, hi));
        // uhf
        let busy: Vec<(i64, i64)> = self.uhf_busy(a).collect();
        out.push((Category::Uhf, atomic_valid(&busy, d, lo, hi)));
        out.into_iter()
            .map(|(category, valid)| CategoryIntervals { category, valid })
            .collect()
    }

    /// The starts a dependency allows, `[target end + min_delay, target end +
    /// max_delay]`; `None` while its target is not placed.
    fn dependency_range(&self, x: &Dep) -> Option<(i64, i64)> {
        let (_, end) = self.placed[x.target]?;
        let lo = end.saturating_add(x.min_delay);
        let hi = x.max_delay.map_or(i64::MAX, |m| end.saturating_add(m));
        Some((lo, hi))
    }

    /// The placed intervals activity `a` may not overlap on UHF grounds: comm
    /// activities of a kind it does not allow, and, for a comm activity, activities
    /// that do not allow its kind.
    fn uhf_busy(&self, a: usize) -> impl Iterator<Item = (i64, i64)> + '_ {
        let pb = self.pb;
        let act = &pb.acts[a];
        let comms = self
            .comms
            .iter()
            .filter(move |c| !act.allows(c.2))
            .map(|c| (c.0, c.1));
        let restricted = act.comm.into_iter().flat_map(move |kind| {
            self.restricted
                .iter()
                .filter(move |r| !pb.acts[r.2].allows(kind))
                .map(|r| (r.0, r.1))
        });
        comms.chain(restricted)
    }

    /// The state_requirement, state_effect and data_volume categories of phase 1
    /// over starts in `[lo, hi]`.
    fn phase1_states_data(
        &self,
        a: usize,
        d: i64,
        scope: &Scope,
        lo: i64,
        hi: i64,
    ) -> [(Category, IntervalSet); 3] {
        let pb = self.pb;
        let act = &pb.acts[a];
        let all = || IntervalSet::single(lo, hi);
        // state_requirement
        let mut req = all();
        for (_, &(st, v)) in act
            .requires
            .iter()
            .enumerate()
            .filter(|(k, _)| !scope.skip_reqs.contains(k))
        {
            req = req.intersect(&self.states[st].requirement_valid(v, d, lo, hi));
        }
        // state_effect
        let mut eff = all();
        let mut states: Vec<usize> = act.effects.iter().map(|e| e.0).collect();
        states.sort_unstable();
        states.dedup();
        for st in states {
            let mut own: Vec<(i64, usize)> = act
                .effects
                .iter()
                .filter(|e| e.0 == st)
                .map(|e| (if e.2 == EffectAt::Start { 0 } else { d }, e.1))
                .collect();
            own.sort_unstable();
            eff = eff.intersect(&self.states[st].effect_valid(&own, lo, hi));
        }
        // data_volume
        let mut data = all();
        if let (true, Some(cap)) = (act.data > 0, pb.data_cap) {
            data = self.data_valid(act.data, d, cap, lo, hi);
        }
        // The handover limit binds every optional activity, even one producing
        // nothing, once the placed activities have exceeded it.
        if let (false, Some(ht), Some(max)) = (act.mandatory, pb.handover_time, pb.handover_data) {
            let range = (pb.h0, ht);
            data = data.intersect(&cumulative_valid(
                self.produced,
                max,
                act.data,
                d,
                range,
                (lo, hi),
            ));
        }
        [
            (Category::StateRequirement, req),
            (Category::StateEffect, eff),
            (Category::DataVolume, data),
        ]
    }

    /// The execution range of window `w` of activity `a` for duration `d`: the
    /// window, its cutoff, the plan bounds, and for an activity that needs the rover
    /// awake room for the wakeup before and the shutdown after it.
    pub fn window_range(&self, a: usize, w: &Win, d: i64) -> Interval {
        let pb = self.pb;
        let (wake, shut) = if pb.acts[a].awake == AwakeMode::Required {
            (pb.wake, pb.shut)
        } else {
            (0, 0)
        };
        let lo = w.start.max(pb.h0.saturating_add(wake));
        let mut hi = w.end.min(pb.h1.saturating_sub(d).saturating_sub(shut));
        if let Some(c) = w.cutoff {
            hi = hi.min(c.saturating_sub(d));
        }
        Interval::new(lo, hi)
    }

    /// Starts where adding `rate` bit/s over `[s, s + d)` keeps the volume <= `cap`.
    fn data_valid(&self, rate: i64, d: i64, cap: i128, lo: i64, hi: i64) -> IntervalSet {
        let margin = |s: i64| self.data.check(&[(s, s + d, rate)], None).min + cap;
        if lo == hi {
            return if margin(lo) >= 0 {
                IntervalSet::single(lo, lo)
            } else {
                IntervalSet::empty()
            };
        }
        // Only breakpoints that a piece starting in [lo, hi] can reach split cells
        // (the breakpoints are sorted).
        let all = self.data.breakpoints();
        let near =
            &all[all.partition_point(|&x| x < lo)..all.partition_point(|&x| x <= hi + d + 1)];
        let mut points: Vec<i64> = Vec::with_capacity(near.len() * 4);
        for &x in near {
            for o in [0, d] {
                points.extend([x - o, x - o + 1]);
            }
        }
        let mut feasible = Vec::new();
        for (a, b) in cells(&IntervalSet::single(lo, hi), points) {
            if let Some(iv) = concave_feasible(a, b, &margin).0 {
                feasible.push(iv);
            }
        }
        IntervalSet::from_intervals(feasible)
    }

    /// Phase 2 at start `s` with duration `d`: the generated activities and every
    /// check. `Err` is a structural or peak reason (constant within a cell).
    pub fn evaluate(&self, a: usize, s: i64, d: i64) -> Result<Evaluated, Phase2Reason> {
        self.evaluate_inner(a, s, d, true)
    }

    /// [`State::evaluate`]; without `soc`, only the structural and peak checks
    /// (the margin is then `i128::MAX` and there is no energy reason).
    fn evaluate_inner(
        &self,
        a: usize,
        s: i64,
        d: i64,
        soc: bool,
    ) -> Result<Evaluated, Phase2Reason> {
        let pb = self.pb;
        let act = &pb.acts[a];
        let e = s + d;
        let mut retire = Vec::new();
        let mut new_awake = None;
        match act.awake {
            AwakeMode::Forbidden => {
                if self.awake.iter().any(|p| p.0 < e && s < p.1) {
                    return Err(Phase2Reason::ForcedSleep { sleep: None });
                }
            }
            AwakeMode::Any => {}
            AwakeMode::Required => {
                let need = (s - pb.wake, e + pb.shut);
                if let Some(f) = self.sleep_overlapping(need) {
                    return Err(Phase2Reason::ForcedSleep { sleep: Some(f) });
                }
                if !self.awake.iter().any(|p| p.0 <= need.0 && need.1 <= p.1) {
                    let (q1, merged1) = self.merge(need);
                    if let Some(f) = self.sleep_overlapping(q1) {
                        return Err(Phase2Reason::MinSleep { sleep: f });
                    }
                    let (q2, merged2) = if q1.1 - q1.0 < pb.min_awake {
                        let ext = if q1.0 + pb.min_awake <= pb.h1 {
                            (q1.0, q1.0 + pb.min_awake)
                        } else if q1.1 - pb.min_awake >= pb.h0 {
                            (q1.1 - pb.min_awake, q1.1)
                        } else {
                            return Err(Phase2Reason::MinAwake { sleep: None });
                        };
                        let (q2, m2) = self.merge((ext.0.min(q1.0), ext.1.max(q1.1)));
                        if let Some(f) = self.sleep_overlapping(q2) {
                            return Err(Phase2Reason::MinAwake { sleep: Some(f) });
                        }
                        (q2, m2)
                    } else {
                        (q1, merged1)
                    };
                    retire = merged2;
                    new_awake = Some(q2);
                }
            }
        }
        // Heating.
        let mut preheats = Vec::new();
        for &z in &act.zones {
            if self.heater_on(z, s - 1) {
                continue;
            }
            let p = pb.preheat_duration(z, s);
            if p > 0 {
                preheats.push((z, s - p, s));
            }
        }
        if let Some(&(zone, ps, _)) = preheats.iter().find(|x| x.1 < pb.h0) {
            return Err(Phase2Reason::PreheatOutsidePlan {
                zone,
                preheat_start: ps,
            });
        }
        if let Some(&(zone, ps, _)) = preheats.iter().find(|x| !pb.operable(x.0, x.1)) {
            return Err(Phase2Reason::PreheatOperability {
                zone,
                preheat_start: ps,
            });
        }
        // Load pieces: (t, +energy, +peak) boundary events.
        let mut events: Vec<(i64, i64, i64)> = Vec::new();
        let mut piece = |x: i64, y: i64, energy: i64, peak: i64| {
            if x < y && (energy != 0 || peak != 0) {
                events.push((x, energy, peak));
                events.push((y, -energy, -peak));
            }
        };
        piece(s, e, act.energy, act.peak);
        if let Some((qa, qb)) = new_awake {
            let extra = pb.awake - pb.asleep;
            for (x, y) in uncovered(qa, qb, retire.iter().map(|&i| self.awake[i])) {
                piece(x, y, extra, extra);
            }
        }
        for &z in &act.zones {
            let zone = &pb.zones[z];
            let preheat = preheats
                .iter()
                .find(|x| x.0 == z)
                .map(|&(_, ps, pe)| (ps, pe, zone.preheat));
            for (x, y, power) in std::iter::once((s, e, zone.maintenance)).chain(preheat) {
                for (u, v, cur) in self.zone_draw[z].segments(x, y) {
                    if power > cur {
                        piece(u, v, power - cur, power - cur);
                    }
                }
            }
        }
        events.sort_unstable();
        let mut pieces: Vec<(i64, i64, i64, i64)> = Vec::new();
        let (mut energy, mut peak) = (0i64, 0i64);
        for (k, &(t, de, dp)) in events.iter().enumerate() {
            energy += de;
            peak += dp;
            if let Some(&(next, _, _)) = events.get(k + 1) {
                if next > t && (energy != 0 || peak != 0) {
                    pieces.push((t, next, energy, peak));
                }
            }
        }
        // Peak power.
        if let Some(max) = pb.max_peak {
            if let Some((v, at)) = self.peak_max.filter(|(v, _)| *v > max) {
                return Err(Phase2Reason::MaxPeakPower { at, peak_mw: v });
            }
            for &(x, y, _, dp) in &pieces {
                if let Some((v, at)) = self.peak.max_on(x, y) {
                    if v + dp > max {
                        return Err(Phase2Reason::MaxPeakPower {
                            at,
                            peak_mw: v + dp,
                        });
                    }
                }
            }
        }
        // Energy.
        let drain: Vec<(i64, i64, i64)> = pieces.iter().map(|p| (p.0, p.1, p.2)).collect();
        let energy = drain
            .iter()
            .map(|&(x, y, r)| i128::from(r).abs() * i128::from(y - x))
            .sum();
        let handover = match (act.mandatory, pb.handover_time, pb.handover_soc) {
            (false, Some(t), Some(min)) => Some((t, min)),
            _ => None,
        };
        let placement = Placement {
            act: a,
            start: s,
            duration: d,
            retire,
            new_awake,
            preheats,
        };
        if !soc {
            return Ok(Evaluated {
                placement,
                margin: i128::MAX,
                soc_reason: None,
                energy,
            });
        }
        let check = self.soc.check(&drain, handover.map(|h| h.0));
        let mut margin = check.min - pb.min_soc;
        let mut soc_reason = (margin < 0).then(|| Phase2Reason::MinSoc {
            at: check.min_at,
            soc_mj: clamp_i64(check.min),
        });
        if let (Some((_, min)), Some(level)) = (handover, check.at_probe) {
            let hm = level - min;
            if hm < 0 && soc_reason.is_none() {
                soc_reason = Some(Phase2Reason::HandoverSoc {
                    soc_mj: clamp_i64(level),
                });
            }
            margin = margin.min(hm);
        }
        Ok(Evaluated {
            placement,
            margin,
            soc_reason,
            energy,
        })
    }

    /// The first manual sleep overlapping `[a, b)`.
    fn sleep_overlapping(&self, (a, b): (i64, i64)) -> Option<usize> {
        self.sleeps.iter().find(|x| x.0 < b && a < x.1).map(|x| x.2)
    }

    /// Merges `q` with every awake period closer than `max(min_sleep, 1)`, repeatedly.
    fn merge(&self, mut q: (i64, i64)) -> ((i64, i64), Vec<usize>) {
        let gap = self.pb.min_sleep.max(1);
        let mut merged = vec![false; self.awake.len()];
        loop {
            let mut changed = false;
            for (i, p) in self.awake.iter().enumerate() {
                if !merged[i] && p.0 - q.1 < gap && q.0 - p.1 < gap {
                    merged[i] = true;
                    q = (q.0.min(p.0), q.1.max(p.1));
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        (
            q,
            merged
                .iter()
                .enumerate()
                .filter(|(_, m)| **m)
                .map(|(i, _)| i)
                .collect(),
        )
    }

    /// The critical points for activity `a` with duration `d` and starts in `[lo, hi]`.
    ///
    /// A generated piece `[s + o1, s + o2)` meets a fixed interval `[x, y)` iff
    /// `s < y - o1` and `s >= x - o2 + 1`, so a breakpoint `p` yields the point
    /// `p - o` for a start offset `o` and `p - o + 1` for an end offset. (Energy
    /// only needs the cells to keep every piece end inside one rate segment, which
    /// either point does.)
    fn critical_points(&self, a: usize, d: i64, lo: i64, hi: i64) -> Vec<i64> {
        let pb = self.pb;
        let act = &pb.acts[a];
        // (offset, +1 for an end offset)
        let mut offsets: Vec<(i64, i64)> = vec![(0, 0), (d, 1)];
        let mut preheat_lengths = Vec::new();
        if act.awake == AwakeMode::Required {
            offsets.extend([
                (-pb.wake, 0),
                (d + pb.shut, 1),
                (-pb.wake + pb.min_awake, 1),
                (d + pb.shut - pb.min_awake, 0),
            ]);
        }
        if !act.zones.is_empty() {
            // A preheat `[s - p, s)` ends at the start.
            offsets.push((0, 1));
        }
        for &z in &act.zones {
            for &(_, p) in &pb.zones[z].table {
                preheat_lengths.push(p);
                offsets.push((-p, 0));
            }
        }
        offsets.sort_unstable();
        offsets.dedup();
        preheat_lengths.sort_unstable();
        preheat_lengths.dedup();
        let omin = offsets.iter().map(|o| o.0).min().unwrap_or(0);
        let omax = offsets.iter().map(|o| o.0).max().unwrap_or(0);
        let gap = pb.min_sleep.max(1);
        let (xlo, xhi) = (lo + omin - gap - 2, hi + omax + gap + 2);
        let mut fixed: Vec<i64> = Vec::new();
        let in_range = |x: &i64| xlo <= *x && *x <= xhi;
        fixed.extend(self.net.points().iter().map(|p| p.0).filter(in_range));
        fixed.extend(self.peak.points().iter().map(|p| p.0).filter(in_range));
        for &z in &act.zones {
            fixed.extend(
                self.zone_draw[z]
                    .points()
                    .iter()
                    .map(|p| p.0)
                    .filter(in_range),
            );
            for &(x, y) in &self.zone_on[z] {
                fixed.extend([x, y, x + 1, y + 1].into_iter().filter(in_range));
            }
        }
        for &(x, y, _) in &self.sleeps {
            fixed.extend([x, y].into_iter().filter(in_range));
        }
        fixed.extend([pb.h0, pb.h1]);
        if let Some(t) = pb.handover_time {
            fixed.push(t);
        }
        for &(x, y) in &self.awake {
            fixed.extend([x, y, x - gap, y + gap].into_iter().filter(in_range));
        }
        fixed.sort_unstable();
        fixed.dedup();
        let mut points = Vec::with_capacity(fixed.len() * offsets.len() + 16);
        for &x in &fixed {
            for &(o, end) in &offsets {
                points.push(x - o + end);
            }
        }
        for &p in &preheat_lengths {
            points.push(pb.h0 + p);
        }
        // Local-time structure: table rows at tod(s), operability at tod(s - p).
        for &z in &act.zones {
            let zone = &pb.zones[z];
            for &(from, _) in &zone.table {
                points.extend(tod_points(pb, from, 0, lo, hi));
            }
            if let Some(periods) = &zone.operable {
                for &p in &preheat_lengths {
                    for &(from, to) in periods {
                        points.extend(tod_points(pb, from, p, lo, hi));
                        points.extend(tod_points(pb, (to + 1).rem_euclid(pb.sol), p, lo, hi));
                        points.extend(tod_points(pb, 0, p, lo, hi));
                    }
                }
            }
        }
        points
    }

    /// The best start in `cand` (nearest `preferred`, ties earlier) passing phase 2,
    /// and every try made.
    ///
    /// A cell that an upper bound on its lowest state of charge
    /// ([`State::failing_soc_bound`]) proves to fail on `min_soc` everywhere is not
    /// searched: its try carries the bound as its closeness (`Some`), and
    /// [`merge_tries_with`] computes exact numbers only for the cells that could
    /// end up reported (with [`State::cell_tries`]).
    pub fn search(
        &self,
        a: usize,
        d: i64,
        cand: &IntervalSet,
        preferred: i64,
    ) -> (Option<Evaluated>, Vec<(Try, Option<i64>)>) {
        let mut tries = Vec::new();
        let (Some(lo), Some(hi)) = (cand.first(), cand.intervals().last().map(|i| i.hi)) else {
            return (None, tries);
        };
        let mut cells = cells(cand, self.critical_points(a, d, lo, hi));
        let dist = |c: &(i64, i64)| {
            if c.0 > preferred {
                c.0 - preferred
            } else if c.1 < preferred {
                preferred - c.1
            } else {
                0
            }
        };
        cells.sort_by_key(|c| (dist(c), c.0));
        let mut best: Option<(i64, i64)> = None; // (distance, start)
        for cell in cells {
            if best.is_some_and(|b| dist(&cell) > b.0) {
                break;
            }
            let (ca, cb) = cell;
            if let Some(bound) = self.failing_soc_bound(a, d, ca, cb) {
                let closeness = clamp_i64(bound);
                tries.push((
                    Try {
                        starts: Interval::new(ca, cb),
                        duration: d,
                        reason: Some(Phase2Reason::MinSoc {
                            at: ca,
                            soc_mj: closeness,
                        }),
                        probe: ca,
                    },
                    Some(closeness),
                ));
                continue;
            }
            let cell_tries = self.cell_tries(a, d, ca, cb);
            for t in &cell_tries {
                if t.reason.is_none() {
                    let s = preferred.clamp(t.starts.lo, t.starts.hi);
                    let key = ((s - preferred).abs(), s);
                    if best.is_none_or(|b| key < b) {
                        best = Some(key);
                    }
                }
            }
            tries.extend(cell_tries.into_iter().map(|t| (t, None)));
        }
        let chosen = best.and_then(|(_, s)| self.evaluate(a, s, d).ok());
        (chosen, tries)
    }

    /// An upper bound below `min_soc` on the lowest state of charge for every start
    /// in `[ca, cb]` with duration `d`, from the activity's own energy alone (other
    /// generated pieces only drain more): the cell then fails on `min_soc`
    /// everywhere. `None` when the bound does not prove that, when the cell fails
    /// a structural or peak check (reported as such), or when no bound applies (an
    /// activity that does not drain, or awake periods that charge).
    fn failing_soc_bound(&self, a: usize, d: i64, ca: i64, cb: i64) -> Option<i128> {
        let pb = self.pb;
        let act = &pb.acts[a];
        if act.energy <= 0 || pb.awake < pb.asleep {
            return None;
        }
        let energy = i128::from(act.energy) * i128::from(d);
        let bound = self.soc.drain_bound(ca, cb.saturating_add(d), energy);
        // Structural and peak results are constant within a cell; they are
        // evaluated only when the bound would prune it.
        (bound < pb.min_soc && self.evaluate_inner(a, ca, d, false).is_ok()).then_some(bound)
    }

    /// The tries of one cell: its structural or peak reason, or the exact
    /// state-of-charge search (the part that passes, and the numbers of the start
    /// that came closest on either side).
    pub fn cell_tries(&self, a: usize, d: i64, ca: i64, cb: i64) -> Vec<Try> {
        let mut tries = Vec::new();
        let first = match self.evaluate(a, ca, d) {
            Err(reason) => {
                tries.push(Try {
                    starts: Interval::new(ca, cb),
                    duration: d,
                    reason: Some(reason),
                    probe: ca,
                });
                return tries;
            }
            Ok(ev) => ev,
        };
        // The cell's evaluations, so that reporting a probe's reason does not
        // evaluate it again (a handful per cell: a linear scan is fastest).
        let memo = std::cell::RefCell::new(vec![(ca, first.margin, first.soc_reason)]);
        let look = |s: i64| -> (i128, Option<Phase2Reason>) {
            if let Some(x) = memo.borrow().iter().find(|x| x.0 == s) {
                return (x.1, x.2.clone());
            }
            let (m, r) = self
                .evaluate(a, s, d)
                .map_or((i128::MIN, None), |ev| (ev.margin, ev.soc_reason));
            memo.borrow_mut().push((s, m, r.clone()));
            (m, r)
        };
        let margin = |s: i64| look(s).0;
        let (feasible, probe) = concave_feasible(ca, cb, &margin);
        let reason_at = |s: i64| look(s).1;
        match feasible {
            None => tries.push(Try {
                starts: Interval::new(ca, cb),
                duration: d,
                reason: reason_at(probe),
                probe,
            }),
            Some(iv) => {
                if iv.lo > ca {
                    tries.push(Try {
                        starts: Interval::new(ca, iv.lo - 1),
                        duration: d,
                        reason: reason_at(ca),
                        probe: ca,
                    });
                }
                tries.push(Try {
                    starts: iv,
                    duration: d,
                    reason: None,
                    probe: iv.lo,
                });
                if iv.hi < cb {
                    tries.push(Try {
                        starts: Interval::new(iv.hi + 1, cb),
                        duration: d,
                        reason: reason_at(cb),
                        probe: cb,
                    });
                }
            }
        }
        tries
    }
}

/// Plan times `s` in `[lo, hi + 1]` with `tod(s - shift) == tod`.
fn tod_points(pb: &Problem, tod: i64, shift: i64, lo: i64, hi: i64) -> Vec<i64> {
    // s - shift = tod - offset + k * sol
    let base = tod - pb.offset + shift;
    let k0 = (lo - base).div_euclid(pb.sol);
    let mut out = Vec::new();
    let mut s = base + k0 * pb.sol;
    while s <= hi + 1 {
        if s >= lo {
            out.push(s);
        }
        s += pb.sol;
    }
    out
}

/// Splits `set` at every point of `points` that falls strictly inside one of its
/// intervals: the cells `[a, b]` between consecutive critical points.
fn cells(set: &IntervalSet, mut points: Vec<i64>) -> Vec<(i64, i64)> {
    points.sort_unstable();
    points.dedup();
    let mut out = Vec::new();
    for iv in set.intervals() {
        let mut a = iv.lo;
        let from = points.partition_point(|&p| p <= iv.lo);
        for &p in &points[from..] {
            if p > iv.hi {
                break;
            }
            out.push((a, p - 1));
            a = p;
        }
        out.push((a, iv.hi));
    }
    out
}

/// For a concave integer function `g` on `[a, b]`: the interval where `g >= 0`
/// (if any), and the start of the highest value (a probe for reporting).
fn concave_feasible(a: i64, b: i64, g: &dyn Fn(i64) -> i128) -> (Option<Interval>, i64) {
    let (ga, gb) = (g(a), g(b));
    // Largest x in [from, to] with g(x) >= 0, given g(from) >= 0 and the feasible set
    // an interval.
    let last_ok = |from: i64, to: i64| {
        let (mut ok, mut bad) = (from, to + 1);
        while bad - ok > 1 {
            let mid = ok + (bad - ok) / 2;
            if g(mid) >= 0 { ok = mid } else { bad = mid }
        }
        ok
    };
    let first_ok = |from: i64, to: i64| {
        let (mut bad, mut ok) = (from - 1, to);
        while ok - bad > 1 {
            let mid = bad + (ok - bad) / 2;
            if g(mid) >= 0 { ok = mid } else { bad = mid }
        }
        ok
    };
    if ga >= 0 && gb >= 0 {
        return (Some(Interval::new(a, b)), a);
    }
    if ga >= 0 {
        return (Some(Interval::new(a, last_ok(a, b - 1))), a);
    }
    if gb >= 0 {
        return (Some(Interval::new(first_ok(a + 1, b), b)), b);
    }
    // Both ends fail. If g does not rise right after a (or does not fall right
    // before b), concavity puts the maximum at that end: nothing passes.
    if a == b || g(a + 1) <= ga {
        return (None, a);
    }
    if g(b - 1) <= gb {
        return (None, b);
    }
    // Otherwise find the maximum (first s with g(s + 1) <= g(s)).
    let (mut l, mut r) = (a, b);
    while l < r {
        let mid = l + (r - l) / 2;
        if g(mid + 1) > g(mid) {
            l = mid + 1
        } else {
            r = mid
        }
    }
    if g(l) < 0 {
        return (None, l);
    }
    (
        Some(Interval::new(first_ok(a + 1, l), last_ok(l, b - 1))),
        l,
    )
}

fn clamp_i64(x: i128) -> i64 {
    i64::try_from(x).unwrap_or(if x < 0 { i64::MIN } else { i64::MAX })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn concave_search_finds_exact_boundaries() {
        // Tent function peaking at 40: feasible where g >= 0.
        for (peak, width) in [(40i64, 5i64), (40, 0), (0, 3), (100, 200), (40, -1)] {
            let g = move |s: i64| i128::from(width - (s - peak).abs());
            let (iv, _) = concave_feasible(0, 100, &g);
            let brute: Vec<i64> = (0..=100).filter(|&s| g(s) >= 0).collect();
            match iv {
                None => assert!(brute.is_empty(), "{peak} {width}"),
                Some(iv) => {
                    assert_eq!(
                        (iv.lo, iv.hi),
                        (brute[0], *brute.last().unwrap()),
                        "{peak} {width}"
                    )
                }
            }
        }
        // Plateau at the maximum.
        let g = |s: i64| i128::from((s.min(60) - s.max(30)).min(0) + 1 - i64::from(s > 90) * 100);
        let (iv, _) = concave_feasible(0, 100, &g);
        assert!(iv.is_some());
    }

    #[test]
    fn cells_split_at_points() {
        let set: IntervalSet = [Interval::new(0, 10), Interval::new(20, 30)]
            .into_iter()
            .collect();
        assert_eq!(
            cells(&set, vec![5, 0, 21, 40, 10]),
            vec![(0, 4), (5, 9), (10, 10), (20, 20), (21, 30)]
        );
    }
}
