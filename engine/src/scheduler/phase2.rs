//! Phase 2 of a scheduling step: the exact search over cells between critical
//! points for a start that passes the wake/sleep, heating, peak-power and energy
//! checks, within the starts phase 1 left.
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
use super::cells::{cells, concave_feasible, concave_nearest, tangent_bound};
use super::problem::Problem;
use super::state::{Placement, State, uncovered};
use super::trace::{Closeness, Phase2Reason, Rejected, Try};
use crate::model::AwakeMode;
use crate::timeline::{Interval, IntervalSet};

/// `State::search_outcome` (and the data category of phase 1) halves a span of
/// starts while it is at least this long and holds more than
/// [`SPAN_LEAF_BREAKPOINTS`] rate breakpoints ([`worth_halving`]). Debug builds
/// (the tests, on small plans) split down to single breakpoints, so that the
/// cross-checks against the cell-by-cell searches see every kind of span.
const SPAN_MIN_SECONDS: i64 = if cfg!(debug_assertions) { 2 } else { 64 };
/// See [`SPAN_MIN_SECONDS`].
const SPAN_LEAF_BREAKPOINTS: usize = if cfg!(debug_assertions) { 1 } else { 8 };
/// [`State::failing_cell_soc_bound`] bounds a cell at least this many seconds
/// wide (shorter ones cost about as much to search exactly). Debug builds bound
/// every cell of four starts, so that the cross-checks see the bound at work.
const TANGENT_CELL_SECONDS: i64 = if cfg!(debug_assertions) { 3 } else { 16 };

/// [`State::search`] bounds the state of charge over runs of this many
/// consecutive cells before it bounds a cell alone (debug builds: runs of
/// two, so that the cross-checks see runs and their cells).
const SPAN_CELLS: usize = if cfg!(debug_assertions) { 2 } else { 32 };

/// Whether the span of starts `[lo, hi]` is halved before its cells are
/// searched: it is at least [`SPAN_MIN_SECONDS`] long and more than
/// [`SPAN_LEAF_BREAKPOINTS`] of the rate breakpoints `points` (sorted) lie in
/// `[lo, reach]`, `reach` the last time the span's placements can touch.
pub(super) fn worth_halving(points: &[(i64, i64)], lo: i64, hi: i64, reach: i64) -> bool {
    hi - lo >= SPAN_MIN_SECONDS
        && points.partition_point(|p| p.0 <= reach) - points.partition_point(|p| p.0 < lo)
            > SPAN_LEAF_BREAKPOINTS
}

/// The room a passing placement leaves on energy, local in time (see
/// [`State::soc_budget`] and `RateTimeline::local_budget`): while the other
/// placements starting before `until` change at most `budget` charge, and
/// every state of charge stays above the minimum without the placement, it
/// still passes the state-of-charge minimum; and while those starting before
/// the handover time change at most the handover margin, it still passes the
/// handover minimum.
#[derive(Clone, Copy, Debug)]
pub struct SocBudget {
    /// Charge (mJ, absolute) the placements counted may change.
    pub budget: i128,
    /// Placements starting at or after this time are not counted.
    pub until: i64,
    /// `(handover time, margin)` when the handover minimum applies.
    pub handover: Option<(i64, i128)>,
}

/// A lower bound on the charge a span of starts drains ([`State::surely_drained`]).
#[derive(Clone, Copy, Debug)]
struct SurelyDrained {
    /// Charge drained (mJ, > 0).
    energy: i128,
    /// Every counted drain lies in `[from, until)`.
    from: i64,
    /// See `from`.
    until: i64,
}

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
    pub fn footprint(&self, problem: &Problem) -> (i64, i64) {
        let p = &self.placement;
        let e = p.start + p.duration;
        let (mut lo, mut hi) = (p.start, e);
        if problem.acts[p.act].awake == AwakeMode::Required {
            lo = lo.min(p.start - problem.wake);
            hi = hi.max(e + problem.shut);
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

/// What a placement generates besides the activity itself.
struct Generated {
    /// Indices of the awake periods the new one absorbs.
    retire: Vec<usize>,
    /// The awake period it creates (absorbing `retire`), if any.
    new_awake: Option<(i64, i64)>,
    /// `(zone, start, end)` of each preheat.
    preheats: Vec<(usize, i64, i64)>,
}

impl State<'_> {
    /// Whether activity `a` fits at start `s` with duration `d` (every phase-1
    /// category and phase 2), without searching: the explainer's quick re-check
    /// of a known placement.
    pub fn fits(&self, a: usize, s: i64, d: i64, scope: &Scope) -> bool {
        self.fitting(a, s, d, scope).is_some()
    }

    /// [`State::fits`], with the passing evaluation.
    pub fn fitting(&self, a: usize, s: i64, d: i64, scope: &Scope) -> Option<Evaluated> {
        self.fitting_inner(a, s, d, scope, true)
    }

    /// [`State::fitting`]; without `soc`, every check but the energy margin (the
    /// caller knows it holds; the margin is then `i128::MAX`).
    pub(super) fn fitting_inner(
        &self,
        a: usize,
        s: i64,
        d: i64,
        scope: &Scope,
        soc: bool,
    ) -> Option<Evaluated> {
        let act = &self.problem.acts[a];
        let in_window = act
            .windows
            .iter()
            .any(|w| self.window_range(a, w, d).contains(s));
        if !in_window || !self.phase1_point(a, s, d, scope) {
            return None;
        }
        self.evaluate_inner(a, s, d, soc)
            .ok()
            .filter(|ev| ev.margin >= 0)
    }

    /// Phase 2 at start `s` with duration `d`: the generated activities and every
    /// check. `Err` is a structural or peak reason (constant within a cell).
    pub fn evaluate(&self, a: usize, s: i64, d: i64) -> Result<Evaluated, Phase2Reason> {
        self.evaluate_inner(a, s, d, true)
    }

    /// The wake/sleep and heating checks of phase 2 at start `s` with duration
    /// `d`, and what the placement would generate: the awake periods it retires
    /// and the one it creates, and its preheats.
    fn structure(&self, a: usize, s: i64, d: i64) -> Result<Generated, Phase2Reason> {
        let problem = self.problem;
        let act = &problem.acts[a];
        let e = s + d;
        let mut retire = Vec::new();
        let mut new_awake = None;
        match act.awake {
            AwakeMode::Forbidden => {
                // Awake periods are sorted and disjoint: the first ending after
                // `s` is the only one that can overlap first.
                let i = self.awake.partition_point(|p| p.1 <= s);
                if self.awake.get(i).is_some_and(|p| p.0 < e) {
                    return Err(Phase2Reason::ForcedSleep { sleep: None });
                }
            }
            AwakeMode::Any => {}
            AwakeMode::Required => {
                let need = (s - problem.wake, e + problem.shut);
                if let Some(f) = self.sleep_overlapping(need) {
                    return Err(Phase2Reason::ForcedSleep { sleep: Some(f) });
                }
                let covering = self.awake.partition_point(|p| p.0 <= need.0);
                let covered = covering
                    .checked_sub(1)
                    .is_some_and(|i| need.1 <= self.awake[i].1);
                if !covered {
                    let (q1, merged1) = self.merge(need);
                    if let Some(f) = self.sleep_overlapping(q1) {
                        return Err(Phase2Reason::MinSleep { sleep: f });
                    }
                    let (q2, merged2) = if q1.1 - q1.0 < problem.min_awake {
                        let ext = if q1.0 + problem.min_awake <= problem.h1 {
                            (q1.0, q1.0 + problem.min_awake)
                        } else if q1.1 - problem.min_awake >= problem.h0 {
                            (q1.1 - problem.min_awake, q1.1)
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
            if self.heater_on(z, s - 1) || problem.preheat_running(a, z, s) {
                continue;
            }
            let p = problem.preheat_duration(z, s);
            if p > 0 {
                preheats.push((z, s - p, s));
            }
        }
        if let Some(&(zone, ps, _)) = preheats.iter().find(|x| x.1 < problem.h0) {
            return Err(Phase2Reason::PreheatOutsidePlan {
                zone,
                preheat_start: ps,
            });
        }
        if let Some(&(zone, ps, _)) = preheats.iter().find(|x| !problem.operable(x.0, x.1)) {
            return Err(Phase2Reason::PreheatOperability {
                zone,
                preheat_start: ps,
            });
        }
        Ok(Generated {
            retire,
            new_awake,
            preheats,
        })
    }

    /// Whether phase 2 at start `s` with duration `d` passes every check but the
    /// energy margin (what `evaluate_inner` without `soc` decides), building the
    /// load pieces only when an upper bound on the peak the placement adds does
    /// not already keep the total under the limit.
    fn structurally_ok(&self, a: usize, s: i64, d: i64) -> bool {
        let problem = self.problem;
        let ok = match (self.structure(a, s, d), problem.max_peak) {
            (Err(_), _) => false,
            (Ok(_), None) => true,
            (Ok(g), Some(max)) => {
                let most = self.peak_added_at_most(a, g.new_awake.is_some());
                match self.peak_max {
                    Some((v, _)) if v > max => false,
                    Some((v, _)) if v + most <= max => true,
                    None if most <= max => true,
                    _ => self.evaluate_inner(a, s, d, false).is_ok(),
                }
            }
        };
        debug_assert_eq!(
            ok,
            self.evaluate_inner(a, s, d, false).is_ok(),
            "structural shortcut"
        );
        ok
    }

    /// [`State::evaluate`]; without `soc`, only the structural and peak checks
    /// (the margin is then `i128::MAX` and there is no energy reason).
    pub(super) fn evaluate_inner(
        &self,
        a: usize,
        s: i64,
        d: i64,
        soc: bool,
    ) -> Result<Evaluated, Phase2Reason> {
        self.evaluate_with(a, s, d, soc, true)
    }

    /// The margin of activity `a` at start `s` with duration `d` in a cell
    /// whose structural and peak checks are known to pass (they are constant
    /// within a cell, and another start of it passed them): the peak check is
    /// left out. `i128::MIN` for a structural failure (it cannot happen, as
    /// debug builds check, with the peak check, against the full evaluation).
    fn margin_in_cell(&self, a: usize, s: i64, d: i64) -> (i128, Option<Phase2Reason>) {
        let got = self
            .evaluate_with(a, s, d, true, false)
            .map_or((i128::MIN, None), |ev| (ev.margin, ev.soc_reason));
        debug_assert_eq!(
            Ok(&got),
            self.evaluate(a, s, d)
                .map(|ev| (ev.margin, ev.soc_reason))
                .as_ref(),
            "a cell's structural or peak check is not constant"
        );
        got
    }

    /// [`State::evaluate_inner`]; without `peak`, the peak-power check is left
    /// out (the caller knows it passes).
    fn evaluate_with(
        &self,
        a: usize,
        s: i64,
        d: i64,
        soc: bool,
        peak: bool,
    ) -> Result<Evaluated, Phase2Reason> {
        let problem = self.problem;
        let Generated {
            retire,
            new_awake,
            preheats,
        } = self.structure(a, s, d)?;
        let pieces = self.load_pieces(a, s, d, &retire, new_awake, &preheats);
        // Peak power.
        if let Some(max) = problem.max_peak.filter(|_| peak) {
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
        let drain = drain_of_pieces(&pieces);
        let energy = drain
            .iter()
            .map(|&(x, y, r)| i128::from(r).abs() * i128::from(y - x))
            .sum();
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
        let (margin, soc_reason) = self.soc_margin(a, &drain);
        Ok(Evaluated {
            placement,
            margin,
            soc_reason,
            energy,
        })
    }

    /// The energy margin of a placement of activity `a` draining `drain` more
    /// (`min(lowest soc - min_soc, handover soc - handover min)`), and the
    /// energy reason when it is negative.
    fn soc_margin(&self, a: usize, drain: &[(i64, i64, i64)]) -> (i128, Option<Phase2Reason>) {
        let problem = self.problem;
        let handover = problem.handover_soc_of(a);
        let check = self.soc.check(drain, handover.map(|h| h.0));
        let mut margin = check.min - problem.min_soc;
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
        (margin, soc_reason)
    }

    /// Whether placement `p` of activity `a` keeps the handover minimum
    /// (`true` when none binds it): the one energy check of a kept placement
    /// whose levels against `min_soc` are proved otherwise. Read first from
    /// a lower bound on the level at the handover that needs no levels
    /// brought up to date (`RateTimeline::level_at_least` with the
    /// placement's drain); only where that bound
    /// falls short are the levels derived and the placement checked in full.
    pub(super) fn keeps_handover(&self, a: usize, p: &Placement) -> bool {
        let Some((at, min)) = self.problem.handover_soc_of(a) else {
            return true;
        };
        let pieces = self.load_pieces(a, p.start, p.duration, &p.retire, p.new_awake, &p.preheats);
        let drain = drain_of_pieces(&pieces);
        let exact = || {
            self.soc
                .check(&drain, Some(at))
                .at_probe
                .is_none_or(|level| level >= min)
        };
        if self.soc.level_at_least(at, &drain) >= min {
            debug_assert!(
                exact(),
                "the handover bound passed a placement that breaks it"
            );
            return true;
        }
        exact()
    }

    /// The load pieces (as [`Self::load_pieces`]) of placing activity `a` at
    /// `s` for `d` whatever its peak and energy checks say, or the structural
    /// reason it cannot be placed there at all.
    pub(super) fn load_if_placed(
        &self,
        a: usize,
        s: i64,
        d: i64,
    ) -> Result<Vec<(i64, i64, i64, i64)>, Phase2Reason> {
        let g = self.structure(a, s, d)?;
        Ok(self.load_pieces(a, s, d, &g.retire, g.new_awake, &g.preheats))
    }

    /// The charge drain `(from, to, mW)` of placement `p` in this state.
    pub fn drain_of(&self, p: &Placement) -> Vec<(i64, i64, i64)> {
        drain_of_pieces(&self.load_pieces(
            p.act,
            p.start,
            p.duration,
            &p.retire,
            p.new_awake,
            &p.preheats,
        ))
    }

    /// `ev` (a passing evaluation against an earlier state that drained
    /// `drain`) against this state, when nothing placed since can have changed
    /// anything but the state of charge: its new margin when it still passes.
    pub fn still_passing(&self, ev: &Evaluated, drain: &[(i64, i64, i64)]) -> Option<Evaluated> {
        let (margin, _) = self.soc_margin(ev.placement.act, drain);
        (margin >= 0).then(|| Evaluated {
            margin,
            ..ev.clone()
        })
    }

    /// For the explainer's witnesses: how much other placements may change
    /// the state of charge, and where, before the passing evaluation `ev`
    /// (of this state, draining `drain`) can stop passing on energy
    /// (`SocBudget`). `None` when
    /// no local budget exists (the drain is never absorbed, or no room).
    pub fn soc_budget(&self, ev: &Evaluated, drain: &[(i64, i64, i64)]) -> Option<SocBudget> {
        let problem = self.problem;
        let p = &ev.placement;
        let (budget, until) = self.soc.local_budget(drain, problem.min_soc)?;
        let handover = match problem.handover_soc_of(p.act) {
            Some((t, min)) => Some((t, self.soc.check(drain, Some(t)).at_probe? - min)),
            None => None,
        };
        Some(SocBudget {
            budget,
            until,
            handover,
        })
    }

    /// The load pieces `(from, to, extra drain, extra peak)` (mW) that placing
    /// activity `a` at `s` for `d` adds, with the awake period it creates
    /// (absorbing `retire`) and its preheats: sorted, disjoint, non-zero.
    pub(crate) fn load_pieces(
        &self,
        a: usize,
        s: i64,
        d: i64,
        retire: &[usize],
        new_awake: Option<(i64, i64)>,
        preheats: &[(usize, i64, i64)],
    ) -> Vec<(i64, i64, i64, i64)> {
        let problem = self.problem;
        let act = &problem.acts[a];
        let e = s + d;
        // Load pieces: (t, +energy, +peak) boundary events (the activity, an
        // awake period and a zone or two: room for them without regrowing).
        let mut events: Vec<(i64, i64, i64)> = Vec::with_capacity(8);
        let mut piece = |x: i64, y: i64, energy: i64, peak: i64| {
            if x < y && (energy != 0 || peak != 0) {
                events.push((x, energy, peak));
                events.push((y, -energy, -peak));
            }
        };
        piece(s, e, act.energy, act.peak);
        if let Some((qa, qb)) = new_awake {
            let extra = problem.awake - problem.asleep;
            for (x, y) in uncovered(qa, qb, retire.iter().map(|&i| self.awake[i])) {
                piece(x, y, extra, extra);
            }
        }
        for &z in &act.zones {
            let zone = &problem.zones[z];
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
        let mut pieces: Vec<(i64, i64, i64, i64)> = Vec::with_capacity(events.len());
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
        pieces
    }

    /// The first manual sleep overlapping `[a, b)`.
    fn sleep_overlapping(&self, (a, b): (i64, i64)) -> Option<usize> {
        // The first sleep ending after `a` is where the running maximum of the
        // ends first passes `a`; sleeps are sorted by start, so if it does not
        // start before `b`, no later one does.
        let i = self.sleep_reach.partition_point(|&r| r <= a);
        let found = self
            .sleeps
            .get(i)
            .filter(|x| x.0 < b && a < x.1)
            .map(|x| x.2);
        debug_assert_eq!(
            found,
            self.sleeps.iter().find(|x| x.0 < b && a < x.1).map(|x| x.2),
            "sleep lookup shortcut"
        );
        found
    }

    /// Merges `q` with every awake period closer than `max(min_sleep, 1)`, repeatedly.
    /// The periods are sorted and disjoint, so those merged are a contiguous run,
    /// widened until no neighbour is within reach.
    pub(super) fn merge(&self, mut q: (i64, i64)) -> ((i64, i64), Vec<usize>) {
        let gap = self.problem.min_sleep.max(1);
        let awake = &self.awake;
        #[cfg(debug_assertions)]
        let q0 = q;
        let (i, j) = loop {
            // Periods with p.1 > q.0 - gap and p.0 < q.1 + gap.
            let i = awake.partition_point(|p| p.1 <= q.0.saturating_sub(gap));
            let j = awake.partition_point(|p| p.0 < q.1.saturating_add(gap));
            if i >= j {
                break (i, i);
            }
            let wider = (q.0.min(awake[i].0), q.1.max(awake[j - 1].1));
            if wider == q {
                break (i, j);
            }
            q = wider;
        };
        let merged = (i..j).collect();
        #[cfg(debug_assertions)]
        {
            let mut q1 = q0;
            let mut m = vec![false; awake.len()];
            loop {
                let mut changed = false;
                for (k, p) in awake.iter().enumerate() {
                    if !m[k] && p.0 - q1.1 < gap && q1.0 - p.1 < gap {
                        m[k] = true;
                        q1 = (q1.0.min(p.0), q1.1.max(p.1));
                        changed = true;
                    }
                }
                if !changed {
                    break;
                }
            }
            let want: Vec<usize> = (0..awake.len()).filter(|&k| m[k]).collect();
            debug_assert_eq!((q, &merged), (q1, &want), "awake merge shortcut");
        }
        (q, merged)
    }

    /// Whether the peak-power part of [`State::structurally_ok`] for activity
    /// `a` passes at every start without looking at the peak timeline: no
    /// limit, or one that the highest peak so far plus everything the
    /// placement can add (its own peak, a new awake period's, every zone's
    /// heater) stays within.
    fn peak_surely_ok(&self, a: usize) -> bool {
        let problem = self.problem;
        let Some(max) = problem.max_peak else {
            return true;
        };
        self.peak_max.map_or(0, |(v, _)| v) + self.peak_added_at_most(a, true) <= max
    }

    /// The most peak power a placement of activity `a` adds anywhere: its own
    /// peak, every zone's heater at its higher power, and with `new_awake`
    /// the awake draw above asleep of a new awake period.
    fn peak_added_at_most(&self, a: usize, new_awake: bool) -> i64 {
        let problem = self.problem;
        let act = &problem.acts[a];
        let awake = if new_awake {
            (problem.awake - problem.asleep).max(0)
        } else {
            0
        };
        let heaters: i64 = act
            .zones
            .iter()
            .map(|&z| {
                problem.zones[z]
                    .preheat
                    .max(problem.zones[z].maintenance)
                    .max(0)
            })
            .sum();
        act.peak.max(0) + awake + heaters
    }

    /// Whether activity `a` with duration `d` surely passes the structural
    /// and peak checks ([`State::structurally_ok`]) at every start in
    /// `[lo, hi]`: a sufficient condition, decided over the whole span at
    /// once. An awake activity's needs `[s - wake, s + d + shutdown)` all lie
    /// in the span's hull, whose merge with the awake periods near it,
    /// widened by `min_awake` on both sides and merged again, holds every
    /// merged period a start can make (merging is monotone in the query), so
    /// no manual sleep meeting that keeps every sleep check passing; the
    /// `min_awake` extension fits the horizon for every start when it does
    /// for the latest (or the earliest, from the other end). A forbidden one
    /// meets no awake period anywhere in the span's reach. A heated zone needs
    /// its heater on before every start (one on-interval covering
    /// `[lo - 1, hi - 1]`); and the peak check passes whatever is placed
    /// ([`State::peak_surely_ok`]). `false` says nothing.
    fn surely_structural(&self, a: usize, d: i64, lo: i64, hi: i64) -> bool {
        let problem = self.problem;
        let act = &problem.acts[a];
        if !self.peak_surely_ok(a) {
            return false;
        }
        let ok = match act.awake {
            AwakeMode::Any => true,
            AwakeMode::Forbidden => {
                let i = self.awake.partition_point(|p| p.1 <= lo);
                self.awake.get(i).is_none_or(|p| p.0 >= hi + d)
            }
            AwakeMode::Required => {
                let hull = (lo - problem.wake, hi + d + problem.shut);
                let (q, _) = self.merge(hull);
                let (q2, _) = self.merge((q.0 - problem.min_awake, q.1 + problem.min_awake));
                let extends = hi - problem.wake + problem.min_awake <= problem.h1
                    || lo + d + problem.shut - problem.min_awake >= problem.h0;
                extends && self.sleep_overlapping(q2).is_none()
            }
        };
        ok && act.zones.iter().all(|&z| {
            let on = &self.zone_on[z];
            // The first on-interval `[x, y)` ending after `lo - 1`.
            let i = on.partition_point(|x| x.1 < lo);
            on.get(i).is_some_and(|x| x.0 < lo && hi - 1 < x.1)
        })
    }

    /// The critical points for activity `a` with duration `d` and starts in `[lo, hi]`.
    ///
    /// A generated piece `[s + o1, s + o2)` meets a fixed interval `[x, y)` iff
    /// `s < y - o1` and `s >= x - o2 + 1`, so a breakpoint `p` yields the point
    /// `p - o` for a start offset `o` and `p - o + 1` for an end offset. (Energy
    /// only needs the cells to keep every piece end inside one rate segment, which
    /// either point does.) The points from breakpoints are those in `(lo, hi]`,
    /// the only ones that split a cell of `[lo, hi]`; the local-time points may
    /// reach `hi + 1`.
    fn critical_points(&self, a: usize, d: i64, lo: i64, hi: i64) -> Vec<i64> {
        let problem = self.problem;
        let act = &problem.acts[a];
        // (offset, +1 for an end offset)
        let mut offsets: Vec<(i64, i64)> = vec![(0, 0), (d, 1)];
        let mut preheat_lengths = Vec::new();
        if act.awake == AwakeMode::Required {
            offsets.extend([
                (-problem.wake, 0),
                (d + problem.shut, 1),
                (-problem.wake + problem.min_awake, 1),
                (d + problem.shut - problem.min_awake, 0),
            ]);
        }
        if !act.zones.is_empty() {
            // A preheat `[s - p, s)` ends at the start.
            offsets.push((0, 1));
        }
        for &z in &act.zones {
            for &(_, p) in &problem.zones[z].table {
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
        let gap = problem.min_sleep.max(1);
        let (xlo, xhi) = (lo + omin - gap - 2, hi + omax + gap + 2);
        let mut fixed: Vec<i64> = Vec::new();
        let in_range = |x: &i64| xlo <= *x && *x <= xhi;
        // Every source is sorted by time: its points in range are one slice,
        // found by binary search (a search over a few cells of a long plan must
        // not scan every breakpoint of the plan).
        let points_in = |pts: &[(i64, i64)]| {
            let i = pts.partition_point(|p| p.0 < xlo);
            let j = pts.partition_point(|p| p.0 <= xhi);
            pts[i..j].iter().map(|p| p.0).collect::<Vec<i64>>()
        };
        // Sorted disjoint intervals whose points `[x - before, y + after]` may
        // fall in range: ends are sorted too, so they are one slice.
        let near = |ivs: &[(i64, i64)], before: i64, after: i64| {
            let i = ivs.partition_point(|p| p.1.saturating_add(after) < xlo);
            let j = ivs.partition_point(|p| p.0.saturating_sub(before) <= xhi);
            ivs[i..j.max(i)].to_vec()
        };
        fixed.extend(points_in(self.soc.rate().points()));
        fixed.extend(points_in(self.peak.points()));
        for &z in &act.zones {
            fixed.extend(points_in(self.zone_draw[z].points()));
            for (x, y) in near(&self.zone_on[z], 0, 1) {
                fixed.extend([x, y, x + 1, y + 1].into_iter().filter(in_range));
            }
        }
        for &(x, y, _) in &self.sleeps {
            fixed.extend([x, y].into_iter().filter(in_range));
        }
        fixed.extend([problem.h0, problem.h1]);
        if let Some(t) = problem.handover_time {
            fixed.push(t);
        }
        for (x, y) in near(&self.awake, gap, gap) {
            fixed.extend([x, y, x - gap, y + gap].into_iter().filter(in_range));
        }
        fixed.sort(); // sorted runs, one per source: merged
        fixed.dedup();
        #[cfg(debug_assertions)]
        {
            let all = |pts: &[(i64, i64)]| pts.iter().map(|p| p.0).collect::<Vec<_>>();
            let mut want: Vec<i64> = all(self.soc.rate().points());
            want.extend(all(self.peak.points()));
            for &z in &act.zones {
                want.extend(all(self.zone_draw[z].points()));
                for &(x, y) in &self.zone_on[z] {
                    want.extend([x, y, x + 1, y + 1]);
                }
            }
            for &(x, y) in &self.awake {
                want.extend([x, y, x - gap, y + gap]);
            }
            for &(x, y, _) in &self.sleeps {
                want.extend([x, y]);
            }
            want.retain(in_range);
            want.extend([problem.h0, problem.h1]);
            want.extend(problem.handover_time);
            want.sort();
            want.dedup();
            debug_assert_eq!(fixed, want, "critical points by binary search");
        }
        // Only points in `(lo, hi]` split a cell of starts in `[lo, hi]` (what
        // every caller searches); one sorted run per offset (`cells` merges the
        // runs), each the slice of `fixed` that the offset shifts into range.
        let mut points = Vec::with_capacity(fixed.len() * offsets.len() + 16);
        for &(o, end) in &offsets {
            let (from, to) = (lo + o - end, hi + o - end);
            let i = fixed.partition_point(|&x| x <= from);
            let j = fixed.partition_point(|&x| x <= to);
            points.extend(fixed[i..j].iter().map(|&x| x - o + end));
        }
        #[cfg(debug_assertions)]
        {
            let mut want: Vec<i64> = offsets
                .iter()
                .flat_map(|&(o, end)| fixed.iter().map(move |&x| x - o + end))
                .filter(|&p| lo < p && p <= hi)
                .collect();
            want.sort_unstable();
            let mut got = points.clone();
            got.sort_unstable();
            debug_assert_eq!(got, want, "the offsets' slices of the critical points");
        }
        for &p in &preheat_lengths {
            points.push(problem.h0 + p);
        }
        // A preheat already running when a cycle of an execution starts serves
        // its activity at its planned start only (`Problem::preheat_running`):
        // that start is a cell of its own.
        for h in problem.heaters.iter().filter(|h| h.owner == Some(a)) {
            points.extend([h.end, h.end + 1]);
        }
        // Local-time structure: table rows at tod(s), operability at tod(s - p).
        for &z in &act.zones {
            let zone = &problem.zones[z];
            for &(from, _) in &zone.table {
                points.extend(tod_points(problem, from, 0, lo, hi));
            }
            if let Some(periods) = &zone.operable {
                for &p in &preheat_lengths {
                    for &(from, to) in periods {
                        points.extend(tod_points(problem, from, p, lo, hi));
                        points.extend(tod_points(
                            problem,
                            (to + 1).rem_euclid(problem.clock.sol_length),
                            p,
                            lo,
                            hi,
                        ));
                        points.extend(tod_points(problem, 0, p, lo, hi));
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
    /// (`State::failing_soc_bound`) proves to fail on `min_soc` everywhere is not
    /// searched: its try carries the bound as its closeness (`Some`), and
    /// `merge_tries_with` (in `trace.rs`) computes exact numbers only for the cells that could
    /// end up reported (with [`State::cell_tries`]).
    ///
    /// A run of `SPAN_CELLS` adjacent cells that the bound proves failing
    /// together, and that surely pass the structural and peak checks
    /// (`State::surely_structural`, one check for the run), is one try
    /// carrying the run's bound: `merge_tries_with` splits it into its cells
    /// (`State::span_cells`) only when it could hold its range's closest
    /// start.
    pub fn search(
        &self,
        a: usize,
        d: i64,
        cand: &IntervalSet,
        preferred: i64,
    ) -> (Option<Evaluated>, Vec<(Try, Closeness)>) {
        let mut tries = Vec::new();
        let (Some(lo), Some(hi)) = (cand.first(), cand.intervals().last().map(|i| i.hi)) else {
            return (None, tries);
        };
        let min_soc = self.problem.min_soc;
        // The cells in time order, and their order of search (index).
        let cells = cells(cand, self.critical_points(a, d, lo, hi));
        let dist = |c: &(i64, i64)| distance(c.0, c.1, preferred);
        let mut by_distance: Vec<usize> = (0..cells.len()).collect();
        by_distance.sort_by_key(|&i| (dist(&cells[i]), cells[i].0));
        // What each run of `SPAN_CELLS` cells in time order is, on first use.
        let mut runs: Vec<Option<Run>> = vec![None; cells.len().div_ceil(SPAN_CELLS)];
        // The first and last cell of run `k`.
        let run_cells = |k: usize| (k * SPAN_CELLS, ((k + 1) * SPAN_CELLS).min(cells.len()) - 1);
        let mut run_of = |k: usize| -> Run {
            *runs[k].get_or_insert_with(|| {
                let (x, y) = run_cells(k);
                let (rlo, rhi) = (cells[x].0, cells[y].1);
                let Some(bound) = self.span_soc_bound(a, d, rlo, rhi) else {
                    return Run::Cells(None);
                };
                // One interval of starts, surely passing the structural checks.
                let adjacent = cells[x..=y].windows(2).all(|w| w[1].0 == w[0].1 + 1);
                if bound < min_soc && x < y && adjacent && self.surely_structural(a, d, rlo, rhi) {
                    Run::Failing(bound)
                } else {
                    Run::Cells(Some(bound))
                }
            })
        };
        // Cells of whole runs, searched (counted) but not recorded yet: a run
        // is one try only if the search reached every cell of it.
        let mut reached = vec![false; cells.len()];
        let mut best: Option<(i64, i64)> = None; // (distance, start)
        for i in by_distance {
            let cell = cells[i];
            if best.is_some_and(|b| dist(&cell) > b.0) {
                break;
            }
            let (cell_lo, cell_hi) = cell;
            let bound = match run_of(i / SPAN_CELLS) {
                Run::Failing(_) => {
                    reached[i] = true;
                    continue;
                }
                // A structural or peak failure: the cell's tries say which.
                Run::Cells(Some(b)) if b < min_soc => {
                    self.structurally_ok(a, cell_lo, d).then_some(b)
                }
                Run::Cells(_) => self.failing_soc_bound(a, d, cell_lo, cell_hi),
            };
            if let Some(bound) = bound {
                let (t, c) = pruned_try(cell_lo, cell_hi, d, bound);
                tries.push((t, Closeness::Cell(c)));
                continue;
            }
            let cell_tries = self.cell_tries(a, d, cell_lo, cell_hi);
            for t in &cell_tries {
                if t.reason.is_none() {
                    let s = preferred.clamp(t.starts.lo, t.starts.hi);
                    let key = ((s - preferred).abs(), s);
                    if best.is_none_or(|b| key < b) {
                        best = Some(key);
                    }
                }
            }
            tries.extend(cell_tries.into_iter().map(|t| (t, Closeness::Exact)));
        }
        for (k, run) in runs.iter().enumerate() {
            let Some(Run::Failing(bound)) = *run else {
                continue;
            };
            let (x, y) = run_cells(k);
            #[cfg(debug_assertions)]
            self.check_whole_run(a, d, &cells[x..=y]);
            if reached[x..=y].iter().all(|&r| r) {
                let (t, c) = pruned_try(cells[x].0, cells[y].1, d, bound);
                tries.push((t, Closeness::Cells(c)));
                continue;
            }
            // The search stopped inside the run: only the cells it reached.
            for i in (x..=y).filter(|&i| reached[i]) {
                let (t, c) = pruned_try(cells[i].0, cells[i].1, d, bound);
                tries.push((t, Closeness::Cell(c)));
            }
        }
        let chosen = best.and_then(|(_, s)| self.evaluate(a, s, d).ok());
        (chosen, tries)
    }

    /// Debug builds: every cell of a run that [`State::search`] records as
    /// one try passes the structural and peak checks, as
    /// [`State::surely_structural`] said.
    #[cfg(debug_assertions)]
    fn check_whole_run(&self, a: usize, d: i64, cells: &[(i64, i64)]) {
        for &(x, y) in cells {
            for s in [x, y] {
                debug_assert!(
                    self.evaluate_inner(a, s, d, false).is_ok(),
                    "a run recorded whole fails a structural check at {s}"
                );
            }
        }
    }

    /// The cells between critical points of a try of [`State::search`] that
    /// holds several cells of activity `a` with duration `d` (`[lo, hi]`),
    /// proved failing on `min_soc` and surely passing the structural checks:
    /// each a try failing on `min_soc` (its numbers to be computed).
    pub(super) fn span_cells(&self, a: usize, d: i64, lo: i64, hi: i64) -> Vec<Try> {
        let span = IntervalSet::from_intervals(vec![Interval::new(lo, hi)]);
        cells(&span, self.critical_points(a, d, lo, hi))
            .into_iter()
            .map(|(x, y)| pruned_try(x, y, d, i128::MAX).0)
            .collect()
    }

    /// Debug builds: the tries of every cell between critical points in
    /// `[lo, hi]` (what a try of [`State::search`] that holds several cells
    /// stands for).
    #[cfg(debug_assertions)]
    pub(super) fn span_tries(&self, a: usize, d: i64, lo: i64, hi: i64) -> Vec<Try> {
        self.span_cells(a, d, lo, hi)
            .into_iter()
            .flat_map(|t| self.cell_tries(a, d, t.starts.lo, t.starts.hi))
            .collect()
    }

    /// The charge activity `a` drains over duration `d`, when a bound on the
    /// state of charge applies: `None` for an activity that does not drain, or
    /// when awake periods charge.
    fn drain_of_duration(&self, a: usize, d: i64) -> Option<i128> {
        let problem = self.problem;
        let act = &problem.acts[a];
        (act.energy > 0 && problem.awake >= problem.asleep)
            .then(|| i128::from(act.energy) * i128::from(d))
    }

    /// When a bound proves that every start in `[lo, hi]` of activity `a` with
    /// duration `d` fails on energy, whatever else holds there (phase 1
    /// included): `Some(Some(bound))`, the bound on the lowest state of charge,
    /// when it is `min_soc`; `Some(None)` when it is the handover minimum (the
    /// level at the handover time is bounded as the lowest level is)
    /// (`RateTimeline::drain_bound` over the span: the activity drains
    /// somewhere inside it, and its generated pieces only drain more).
    pub(super) fn fails_on_energy(
        &self,
        a: usize,
        d: i64,
        lo: i64,
        hi: i64,
    ) -> Option<Option<i64>> {
        let problem = self.problem;
        let (energy, until) = (self.drain_of_duration(a, d)?, hi.saturating_add(d));
        let bound = self.soc.drain_bound(lo, until, energy);
        if bound < problem.min_soc {
            return Some(Some(clamp_i64(bound)));
        }
        let surely = self.surely_drained(a, d, lo, hi);
        if let Some(g) = surely {
            let bound = self.soc.drain_bound(g.from, g.until, g.energy);
            if bound < problem.min_soc {
                #[cfg(debug_assertions)]
                self.check_rejected_span(a, d, lo, hi, Some(bound));
                return Some(Some(clamp_i64(bound)));
            }
        }
        let (t, min) = problem.handover_soc_of(a)?;
        if self.soc.level_bound(lo, until, energy, t) < min {
            return Some(None);
        }
        let g = surely?;
        let fails = self.soc.level_bound(g.from, g.until, g.energy, t) < min;
        #[cfg(debug_assertions)]
        if fails {
            self.check_rejected_span(a, d, lo, hi, None);
        }
        fails.then_some(None)
    }

    /// A lower bound on the charge every start in `[lo, hi]` of activity `a`
    /// with duration `d` drains, generated load included, and the span it is
    /// drained in: the activity's own drain, the part of its wake-up,
    /// shutdown and activity time that no awake period of this state covers
    /// at any of those starts (a new awake period contains that need, and
    /// every period it meets is merged into it, so it drains at least the
    /// uncovered part), its maintenance heating above the zone's highest draw
    /// over the span, and its shortest preheat above that draw where no
    /// heater of the zone is on just before any start of the span. `None`
    /// when no bound applies ([`State::drain_of_duration`]) or the
    /// generated load adds nothing. A placement that fails a structural
    /// check fails anyway; one that passes drains at least this much inside
    /// the returned span (drain outside the plan horizon is not counted).
    fn surely_drained(&self, a: usize, d: i64, lo: i64, hi: i64) -> Option<SurelyDrained> {
        let problem = self.problem;
        let act = &problem.acts[a];
        let own = self.drain_of_duration(a, d)?;
        let (h0, h1) = (self.soc.rate().start(), self.soc.rate().end());
        // |[s + x, s + y) ∩ [h0, h1)| is concave in s: its least over the
        // span is at an end.
        let inside = |x: i64, y: i64| {
            let len = |s: i64| ((s + y).min(h1) - (s + x).max(h0)).max(0);
            len(lo).min(len(hi))
        };
        let (mut from, mut until) = (lo, hi.saturating_add(d));
        let mut extra: i128 = 0;
        let awake_extra = problem.awake - problem.asleep;
        if act.awake == AwakeMode::Required && awake_extra > 0 {
            let uncovered = self.least_uncovered_need(d, lo, hi, (h0, h1));
            if uncovered > 0 {
                extra += i128::from(awake_extra) * i128::from(uncovered);
                from = from.min(lo - problem.wake);
                until = until.max(hi + d + problem.shut);
            }
        }
        // Segments of a zone's draw looked at, at most, for its highest value.
        const DRAW_SEGMENTS: usize = 64;
        let highest = |z: usize, x: i64, y: i64| {
            let mut it = self.zone_draw[z].segments(x, y);
            let mut best: Option<i64> = None;
            for _ in 0..DRAW_SEGMENTS {
                match it.next() {
                    Some((_, _, v)) => best = Some(best.map_or(v, |b| b.max(v))),
                    None => return best,
                }
            }
            if it.next().is_some() { None } else { best }
        };
        let owns_heater = problem.heaters.iter().any(|h| h.owner == Some(a));
        for &z in &act.zones {
            let zone = &problem.zones[z];
            if let Some(cur) = highest(z, lo, hi.saturating_add(d)) {
                let power = zone.maintenance - cur;
                if power > 0 {
                    extra += i128::from(power) * i128::from(inside(0, d));
                }
            }
            if owns_heater {
                continue;
            }
            // The heater is on at `s - 1` for no start `s` of the span.
            let on = &self.zone_on[z];
            let i = on.partition_point(|x| x.1 < lo);
            if on.get(i).is_some_and(|x| x.0 < hi) {
                continue;
            }
            let shortest = if zone.table.first().is_none_or(|row| row.0 > 0) {
                0
            } else {
                zone.table.iter().map(|row| row.1).min().unwrap_or(0)
            };
            let longest = zone.longest_preheat();
            if shortest <= 0 {
                continue;
            }
            if let Some(cur) = highest(z, lo - longest, hi) {
                let power = zone.preheat - cur;
                if power > 0 {
                    extra += i128::from(power) * i128::from(inside(-shortest, 0));
                    from = from.min(lo - longest);
                }
            }
        }
        (extra > 0).then_some(SurelyDrained {
            energy: own + extra,
            from,
            until,
        })
    }

    /// The least part of an awake activity's need `[s - wake, s + d +
    /// shutdown)` inside the horizon `[h0, h1)` that no awake period covers,
    /// over the starts `s` in `[lo, hi]`: the need's length less the most
    /// coverage. Coverage is piecewise linear in `s`, bending only where an
    /// end of the need meets an end of a period, so with few periods in
    /// reach its maximum is taken there exactly; with many, the coverage is
    /// bounded by every period in reach together.
    fn least_uncovered_need(&self, d: i64, lo: i64, hi: i64, (h0, h1): (i64, i64)) -> i64 {
        /// Periods in reach evaluated exactly, at most.
        const EXACT_PERIODS: usize = 256;
        let problem = self.problem;
        let (before, after) = (problem.wake, d + problem.shut);
        let len = before + after;
        let (rlo, rhi) = (lo - before, hi + after);
        let i = self.awake.partition_point(|p| p.1 <= rlo);
        let j = self.awake.partition_point(|p| p.0 < rhi);
        let periods = &self.awake[i..j.max(i)];
        // Outside the horizon nothing is drained: count it as covered
        // (overlap with a period only over-counts coverage, which is safe).
        let edges = [(rlo - 1, h0.min(rhi)), (h1.max(rlo), rhi + 1)];
        let overlap =
            |(x, y): (i64, i64), s: i64| ((s + after).min(y) - (s - before).max(x)).max(0);
        // The periods are sorted and disjoint: those meeting the need at `s`
        // are one run, found by bisection.
        let covered_at = |s: i64| -> i64 {
            let first = periods.partition_point(|p| p.1 <= s - before);
            let inside: i64 = periods[first..]
                .iter()
                .take_while(|p| p.0 < s + after)
                .map(|&p| overlap(p, s))
                .sum();
            inside + edges.iter().map(|&e| overlap(e, s)).sum::<i64>()
        };
        let most = if periods.len() <= EXACT_PERIODS {
            let mut most = 0;
            let bends = periods
                .iter()
                .chain(edges.iter())
                .flat_map(|&(x, y)| [x + before, y + before, x - after, y - after]);
            for s in bends.chain([lo, hi]).map(|s| s.clamp(lo, hi)) {
                most = most.max(covered_at(s));
                if most >= len {
                    break;
                }
            }
            most
        } else {
            periods
                .iter()
                .chain(edges.iter())
                .map(|&(x, y)| (y.min(rhi) - x.max(rlo)).max(0))
                .sum()
        };
        (len - most).max(0)
    }

    /// [`State::search`]'s choice without its tries (a run that records
    /// outcomes only), found best-first over spans of `cand`, nearest
    /// `preferred` first. A span is skipped whole when the state-of-charge bound
    /// (`RateTimeline::drain_bound` over the span: the activity drains somewhere
    /// inside it, and its generated pieces only drain more) proves that every
    /// start in it fails on `min_soc`, or the same bound on the level at the
    /// handover time (`RateTimeline::level_bound`) proves that every start fails
    /// the handover minimum of an optional activity; otherwise it is halved,
    /// down to spans of a few rate breakpoints, whose cells are searched as
    /// `search` searches them.
    /// An activity that fails everywhere then costs about the number of places
    /// where it could have fit, not the number of cells in its windows.
    ///
    /// With `found_only` the rejected starts' record is not kept (it comes
    /// back empty), and a cell is searched only for its passing start nearest
    /// `preferred` ([`State::cell_nearest`]), not for the numbers of every
    /// part that fails.
    pub(crate) fn search_outcome(
        &self,
        a: usize,
        d: i64,
        cand: &IntervalSet,
        preferred: i64,
        found_only: bool,
    ) -> (Option<Evaluated>, Rejected) {
        let problem = self.problem;
        let mut rejected = Rejected::default();
        let ivs = cand.intervals();
        let (Some(first), Some(last)) = (cand.first(), ivs.last().map(|iv| iv.hi)) else {
            return (None, rejected);
        };
        let energy = self.drain_of_duration(a, d);
        let handover_gap = problem.handover_gap(a);
        let fails = |lo: i64, hi: i64| self.fails_on_energy(a, d, lo, hi);
        let skipped = |rejected: &mut Rejected, bound: Option<i64>, lo: i64| {
            rejected.add_skipped(bound, lo);
        };
        // The span's part of `cand`, as its first and last start.
        let clip = |lo: i64, hi: i64| {
            let i = ivs.partition_point(|iv| iv.hi < lo);
            let j = ivs.partition_point(|iv| iv.lo <= hi);
            (i < j).then(|| (ivs[i].lo.max(lo), ivs[j - 1].hi.min(hi)))
        };
        let dist = |lo: i64, hi: i64| distance(lo, hi, preferred);
        let rate = self.soc.rate().points();
        let splits = |lo: i64, hi: i64| energy.is_some() && worth_halving(rate, lo, hi, hi);
        let mut spans = std::collections::BinaryHeap::new();
        spans.push(std::cmp::Reverse((dist(first, last), first, last)));
        let mut best: Option<(i64, i64)> = None; // (distance, start)
        while let Some(std::cmp::Reverse((gap, lo, hi))) = spans.pop() {
            if best.is_some_and(|b| gap > b.0) {
                break;
            }
            if let Some(bound) = fails(lo, hi) {
                skipped(&mut rejected, bound, lo);
                continue;
            }
            if splits(lo, hi) {
                let mid = lo + (hi - lo) / 2;
                for (x, y) in [(lo, mid), (mid + 1, hi)] {
                    if let Some((x, y)) = clip(x, y) {
                        spans.push(std::cmp::Reverse((dist(x, y), x, y)));
                    }
                }
                continue;
            }
            let mut cells = cells(&cand.clip(lo, hi), self.critical_points(a, d, lo, hi));
            cells.sort_by_key(|&(x, y)| (dist(x, y), x));
            for (cell_lo, cell_hi) in cells {
                if best.is_some_and(|b| dist(cell_lo, cell_hi) > b.0) {
                    break;
                }
                if let Some(bound) = fails(cell_lo, cell_hi) {
                    skipped(&mut rejected, bound, cell_lo);
                    continue;
                }
                if found_only {
                    if let Some(s) = self.cell_nearest(a, d, cell_lo, cell_hi, preferred) {
                        let key = ((s - preferred).abs(), s);
                        if best.is_none_or(|b| key < b) {
                            best = Some(key);
                        }
                    }
                    continue;
                }
                let tries = self.cell_tries(a, d, cell_lo, cell_hi);
                rejected = rejected.join(Rejected::of_tries(tries.iter(), handover_gap));
                for t in tries.iter().filter(|t| t.reason.is_none()) {
                    let s = preferred.clamp(t.starts.lo, t.starts.hi);
                    let key = ((s - preferred).abs(), s);
                    if best.is_none_or(|b| key < b) {
                        best = Some(key);
                    }
                }
            }
        }
        let chosen = best.and_then(|(_, s)| self.evaluate(a, s, d).ok());
        if found_only {
            rejected = Rejected::default();
        }
        #[cfg(debug_assertions)]
        debug_assert_eq!(
            chosen.as_ref().map(|ev| ev.placement.start),
            self.search(a, d, cand, preferred)
                .0
                .map(|ev| ev.placement.start),
            "skipping spans changed the search's choice"
        );
        (chosen, rejected)
    }

    /// Every start in `cand` at which activity `a` with duration `d` passes
    /// phase 2 (exact: each cell between critical points is decided as the search
    /// decides it). The free slack of a flexible schedule.
    pub fn passing(&self, a: usize, d: i64, cand: &IntervalSet) -> IntervalSet {
        let (Some(lo), Some(hi)) = (cand.first(), cand.intervals().last().map(|i| i.hi)) else {
            return IntervalSet::empty();
        };
        let mut out = Vec::new();
        for (cell_lo, cell_hi) in cells(cand, self.critical_points(a, d, lo, hi)) {
            out.extend(
                self.cell_tries(a, d, cell_lo, cell_hi)
                    .into_iter()
                    .filter(|t| t.reason.is_none())
                    .map(|t| t.starts),
            );
        }
        IntervalSet::from_intervals(out)
    }

    /// An upper bound below `min_soc` on the lowest state of charge for every start
    /// in `[cell_lo, cell_hi]` with duration `d`, from the activity's own energy alone (other
    /// generated pieces only drain more): the cell then fails on `min_soc`
    /// everywhere. `None` when the bound does not prove that, when the cell fails
    /// a structural or peak check (reported as such), or when no bound applies (an
    /// activity that does not drain, or awake periods that charge).
    fn failing_soc_bound(&self, a: usize, d: i64, cell_lo: i64, cell_hi: i64) -> Option<i128> {
        let problem = self.problem;
        let energy = self.drain_of_duration(a, d)?;
        let plain = self
            .soc
            .drain_bound(cell_lo, cell_hi.saturating_add(d), energy);
        // The generated load's bound only where the activity's own drain does
        // not prove the cell failing: `merge_tries_with` asks for it
        // (`State::generated_cell_bound`) when the cell's turn comes.
        let bound = if plain < problem.min_soc {
            plain
        } else {
            let g = self.surely_drained(a, d, cell_lo, cell_hi)?;
            let bound = plain.min(self.soc.drain_bound(g.from, g.until, g.energy));
            #[cfg(debug_assertions)]
            if bound < problem.min_soc {
                self.check_rejected_span(a, d, cell_lo, cell_hi, Some(bound));
            }
            bound
        };
        // Structural and peak results are constant within a cell; they are
        // evaluated only when the bound would prune it.
        (bound < problem.min_soc && self.structurally_ok(a, cell_lo, d)).then_some(bound)
    }

    /// An upper bound on the lowest state of charge of every start in
    /// `[lo, hi]` of activity `a` with duration `d` that passes the
    /// structural checks: the lower of the activity's own drain's bound and
    /// the generated load's ([`State::surely_drained`]). `None` when no bound
    /// applies ([`State::drain_of_duration`]).
    fn span_soc_bound(&self, a: usize, d: i64, lo: i64, hi: i64) -> Option<i128> {
        let energy = self.drain_of_duration(a, d)?;
        let plain = self.soc.drain_bound(lo, hi.saturating_add(d), energy);
        let Some(g) = self.surely_drained(a, d, lo, hi) else {
            return Some(plain);
        };
        let bound = self.soc.drain_bound(g.from, g.until, g.energy);
        #[cfg(debug_assertions)]
        if bound < plain && bound < self.problem.min_soc {
            self.check_rejected_span(a, d, lo, hi, Some(bound));
        }
        Some(plain.min(bound))
    }

    /// [`State::span_soc_bound`] of one cell `[cell_lo, cell_hi]`: the cheap
    /// second bound `merge_tries_with` gives a cell that
    /// [`State::search`] pruned on a coarser bound (its run of cells', or its
    /// own drain's alone).
    pub(super) fn generated_cell_bound(
        &self,
        a: usize,
        d: i64,
        cell_lo: i64,
        cell_hi: i64,
    ) -> Option<i64> {
        self.span_soc_bound(a, d, cell_lo, cell_hi).map(clamp_i64)
    }

    /// Debug builds: every start in `[lo, hi]` of activity `a` with duration
    /// `d`, which the generated-load bound ([`State::surely_drained`]) proved
    /// failing, fails in the exhaustive search (no cell between critical
    /// points passes), and at each cell's ends and reported probe the lowest
    /// state of charge is at most `bound` (`Some`, on `min_soc`), or the
    /// level at the handover time is below its minimum (`None`).
    #[cfg(debug_assertions)]
    fn check_rejected_span(&self, a: usize, d: i64, lo: i64, hi: i64, bound: Option<i128>) {
        let problem = self.problem;
        let span = IntervalSet::from_intervals(vec![Interval::new(lo, hi)]);
        for (cell_lo, cell_hi) in cells(&span, self.critical_points(a, d, lo, hi)) {
            let tries = self.cell_tries(a, d, cell_lo, cell_hi);
            for t in &tries {
                debug_assert!(
                    t.reason.is_some(),
                    "the generated-load bound rejected passing starts {:?} of activity {a}",
                    t.starts
                );
                for s in [t.starts.lo, t.starts.hi, t.probe] {
                    let Ok(ev) = self.evaluate(a, s, d) else {
                        continue;
                    };
                    let handover = problem.handover_soc_of(a);
                    let check = self
                        .soc
                        .check(&self.drain_of(&ev.placement), handover.map(|h| h.0));
                    match (bound, handover, check.at_probe) {
                        (Some(b), _, _) => debug_assert!(
                            check.min <= b,
                            "the generated-load bound {b} is below the lowest level {} at {s}",
                            check.min
                        ),
                        (None, Some((_, min)), Some(level)) => debug_assert!(
                            level < min,
                            "the generated-load handover bound rejected a start passing it at {s}"
                        ),
                        (None, _, _) => debug_assert!(false, "a handover bound without a handover"),
                    }
                }
            }
        }
    }

    /// For a cell `[cell_lo, cell_hi]` that [`State::failing_soc_bound`]
    /// proved to fail on `min_soc` at every start (so every start's reason is
    /// `min_soc`): an upper bound on the lowest state of charge of every start,
    /// from its values at the cell's two first and two last starts. The lowest
    /// state of charge is concave in the start on a cell (module docs), so it
    /// lies below the tangents at both ends ([`tangent_bound`]); where it is a
    /// minimum of two linear pieces, that is its maximum. Four evaluations
    /// instead of the search for the maximum, which [`State::cell_tries`] makes;
    /// `None` on a cell too short to gain from it.
    pub(super) fn failing_cell_soc_bound(
        &self,
        a: usize,
        d: i64,
        cell_lo: i64,
        cell_hi: i64,
    ) -> Option<i64> {
        if cell_hi - cell_lo < TANGENT_CELL_SECONDS {
            return None;
        }
        let soc = |s: i64| match self.evaluate(a, s, d) {
            Ok(Evaluated {
                soc_reason: Some(Phase2Reason::MinSoc { soc_mj, .. }),
                ..
            }) => Some(i128::from(soc_mj)),
            _ => None,
        };
        let bound = tangent_bound(
            cell_lo,
            cell_hi,
            soc(cell_lo)?,
            soc(cell_lo + 1)?,
            soc(cell_hi - 1)?,
            soc(cell_hi)?,
        );
        Some(clamp_i64(bound))
    }

    /// The start in the cell `[cell_lo, cell_hi]` nearest `preferred` at which
    /// activity `a` with duration `d` passes phase 2, if any: the passing start
    /// [`State::cell_tries`] offers there, with as few evaluations as the
    /// margin's concavity on a cell allows ([`concave_nearest`], from the
    /// cell's start nearest `preferred`). A structural or peak failure there
    /// holds for the whole cell. Debug builds compare with the cell's tries.
    fn cell_nearest(
        &self,
        a: usize,
        d: i64,
        cell_lo: i64,
        cell_hi: i64,
        preferred: i64,
    ) -> Option<i64> {
        let p = preferred.clamp(cell_lo, cell_hi);
        let found = match self.evaluate(a, p, d) {
            // A structural or peak reason: the whole cell fails.
            Err(_) => None,
            Ok(ev) => {
                let margins = CellMargins::new(self, a, d, p, ev);
                concave_nearest(cell_lo, cell_hi, p, margins.margin(p), &|s| {
                    margins.margin(s)
                })
            }
        };
        #[cfg(debug_assertions)]
        {
            let want = self
                .cell_tries(a, d, cell_lo, cell_hi)
                .iter()
                .filter(|t| t.reason.is_none())
                .map(|t| preferred.clamp(t.starts.lo, t.starts.hi))
                .min_by_key(|&s| ((s - preferred).abs(), s));
            debug_assert_eq!(found, want, "the nearest passing start of a cell");
        }
        found
    }

    /// The tries of one cell: its structural or peak reason, or the exact
    /// state-of-charge search (the part that passes, and the numbers of the start
    /// that came closest on either side).
    pub fn cell_tries(&self, a: usize, d: i64, cell_lo: i64, cell_hi: i64) -> Vec<Try> {
        let mut tries = Vec::new();
        let first = match self.evaluate(a, cell_lo, d) {
            Err(reason) => {
                tries.push(Try {
                    starts: Interval::new(cell_lo, cell_hi),
                    duration: d,
                    reason: Some(reason),
                    probe: cell_lo,
                });
                return tries;
            }
            Ok(ev) => ev,
        };
        // (Reporting a probe's reason does not evaluate it again.)
        let margins = CellMargins::new(self, a, d, cell_lo, first);
        let (feasible, probe) = concave_feasible(cell_lo, cell_hi, &|s| margins.margin(s));
        let reason_at = |s: i64| margins.at(s).1;
        match feasible {
            None => tries.push(Try {
                starts: Interval::new(cell_lo, cell_hi),
                duration: d,
                reason: reason_at(probe),
                probe,
            }),
            Some(iv) => {
                if iv.lo > cell_lo {
                    tries.push(Try {
                        starts: Interval::new(cell_lo, iv.lo - 1),
                        duration: d,
                        reason: reason_at(cell_lo),
                        probe: cell_lo,
                    });
                }
                tries.push(Try {
                    starts: iv,
                    duration: d,
                    reason: None,
                    probe: iv.lo,
                });
                if iv.hi < cell_hi {
                    tries.push(Try {
                        starts: Interval::new(iv.hi + 1, cell_hi),
                        duration: d,
                        reason: reason_at(cell_hi),
                        probe: cell_hi,
                    });
                }
            }
        }
        tries
    }
}

/// A cell's margins and energy reasons by start, each evaluated once (a
/// handful per cell: a linear scan is fastest), for the searches of
/// [`State::cell_tries`] and [`State::cell_nearest`]. Built from a start of
/// the cell that passed the structural and peak checks, which hold for the
/// whole cell, so the others are evaluated without them
/// ([`State::margin_in_cell`]).
struct CellMargins<'s, 'p> {
    state: &'s State<'p>,
    a: usize,
    d: i64,
    seen: std::cell::RefCell<Vec<(i64, i128, Option<Phase2Reason>)>>,
}

impl<'s, 'p> CellMargins<'s, 'p> {
    /// The margins of activity `a` with duration `d` in a cell, with `ev` its
    /// full evaluation at start `s`.
    fn new(state: &'s State<'p>, a: usize, d: i64, s: i64, ev: Evaluated) -> Self {
        Self {
            state,
            a,
            d,
            seen: std::cell::RefCell::new(vec![(s, ev.margin, ev.soc_reason)]),
        }
    }

    /// The margin at start `s`.
    fn margin(&self, s: i64) -> i128 {
        if let Some(x) = self.seen.borrow().iter().find(|x| x.0 == s) {
            return x.1;
        }
        self.evaluated(s).0
    }

    /// The margin and energy reason at start `s`.
    fn at(&self, s: i64) -> (i128, Option<Phase2Reason>) {
        if let Some(x) = self.seen.borrow().iter().find(|x| x.0 == s) {
            return (x.1, x.2.clone());
        }
        self.evaluated(s)
    }

    /// Start `s` evaluated and kept.
    fn evaluated(&self, s: i64) -> (i128, Option<Phase2Reason>) {
        let (m, r) = self.state.margin_in_cell(self.a, s, self.d);
        self.seen.borrow_mut().push((s, m, r.clone()));
        (m, r)
    }
}

/// What [`State::search`] makes of a run of [`SPAN_CELLS`] cells.
#[derive(Clone, Copy, Debug)]
enum Run {
    /// Each cell on its own, with the run's bound on the lowest state of
    /// charge (when one applies).
    Cells(Option<i128>),
    /// One try: every start fails on `min_soc` (the bound) and passes the
    /// structural and peak checks.
    Failing(i128),
}

/// The try of starts `[lo, hi]` with duration `d` that a bound (below
/// `min_soc`) proves failing on `min_soc` at every start: its closeness is
/// the bound, until `merge_tries_with` asks for the numbers.
fn pruned_try(lo: i64, hi: i64, d: i64, bound: i128) -> (Try, i64) {
    let closeness = clamp_i64(bound);
    (
        Try {
            starts: Interval::new(lo, hi),
            duration: d,
            reason: Some(Phase2Reason::MinSoc {
                at: lo,
                soc_mj: closeness,
            }),
            probe: lo,
        },
        closeness,
    )
}

/// How far the starts `[lo, hi]` are from `preferred` at their nearest (0 when
/// they include it): the order both searches look at cells and spans in.
fn distance(lo: i64, hi: i64, preferred: i64) -> i64 {
    if lo > preferred {
        lo - preferred
    } else if hi < preferred {
        preferred - hi
    } else {
        0
    }
}

/// Plan times `s` in `[lo, hi + 1]` with `tod(s - shift) == tod`.
fn tod_points(problem: &Problem, tod: i64, shift: i64, lo: i64, hi: i64) -> Vec<i64> {
    // s - shift = tod - offset + k * sol
    let base = tod - problem.clock.offset + shift;
    let k0 = (lo - base).div_euclid(problem.clock.sol_length);
    let mut out = Vec::new();
    let mut s = base + k0 * problem.clock.sol_length;
    while s <= hi + 1 {
        if s >= lo {
            out.push(s);
        }
        s += problem.clock.sol_length;
    }
    out
}

fn clamp_i64(x: i128) -> i64 {
    i64::try_from(x).unwrap_or(if x < 0 { i64::MIN } else { i64::MAX })
}

/// The charge drain `(from, to, mW)` of load pieces `(from, to, mW drained,
/// mW of peak)` ([`State::load_pieces`]).
pub(crate) fn drain_of_pieces(pieces: &[(i64, i64, i64, i64)]) -> Vec<(i64, i64, i64)> {
    pieces
        .iter()
        .map(|&(x, y, energy, _)| (x, y, energy))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load::load_plan;

    /// A plan of `activities` (a JSON array) whose battery has 1 Wh of room
    /// above `min_soc` and no net charge asleep, awake drawing 100 W more.
    fn on_a_starved_battery(activities: &str) -> Problem {
        let text = format!(
            r#"{{
          "format": "solscope.plan/1",
          "horizon": {{ "start": 0, "end": 20000 }},
          "local_time": {{ "sol_length": 88775, "offset": 0 }},
          "battery": {{ "capacity": 2000.0, "initial": 1001.0, "min_soc": 1000.0 }},
          "power": {{ "rtg": 25.0, "asleep": 25.0, "awake": 125.0 }},
          "sleep": {{ "wakeup_duration": 300, "shutdown_duration": 300, "min_awake": 0, "min_sleep": 0 }},
          "activities": {activities}
        }}"#
        );
        let plan = load_plan(&text).expect("the plan loads").plan;
        Problem::compile(&plan).expect("compiles")
    }

    /// [`on_a_starved_battery`] with one activity: a 600 s activity at 1 W
    /// fits the 1 Wh of room on its own energy, but the 1,200 s awake it
    /// needs (with wake-up and shutdown) at 100 W above asleep do not.
    fn starved_problem() -> Problem {
        on_a_starved_battery(
            r#"[
            { "id": "look", "priority": 1, "duration": 600,
              "windows": [ { "start": 5000, "end": 10000 } ],
              "energy_rate": 1.0, "awake": "required" }
          ]"#,
        )
    }

    /// The generated-load bound proves a span failing that the activity's own
    /// drain does not, and only while no awake period covers the need.
    #[test]
    fn generated_load_proves_a_span_failing() {
        let problem = starved_problem();
        let mut state = State::new(&problem);
        let (lo, hi) = (5000, 10000);
        let own = state.drain_of_duration(0, 600).expect("drains");
        assert!(state.soc.drain_bound(lo, hi + 600, own) >= problem.min_soc);
        let g = state.surely_drained(0, 600, lo, hi).expect("a bound");
        // Awake from wake-up to shutdown: 1,200 s at 100 W above asleep.
        assert_eq!(g.energy, own + 100_000 * 1200);
        assert_eq!((g.from, g.until), (lo - 300, hi + 600 + 300));
        assert!(
            matches!(state.fails_on_energy(0, 600, lo, hi), Some(Some(b)) if i128::from(b) < problem.min_soc)
        );
        let cand = IntervalSet::from_intervals(vec![Interval::new(lo, hi)]);
        assert!(state.search(0, 600, &cand, lo).0.is_none());
        // An awake period covering the need of some start: no bound.
        state.awake = vec![(4500, 10700)];
        let g = state.surely_drained(0, 600, lo, hi);
        assert!(g.is_none(), "{g:?}");
        assert_eq!(state.fails_on_energy(0, 600, lo, hi), None);
        state.awake = vec![(4000, 5000)];
        let g = state.surely_drained(0, 600, lo, hi).expect("a bound");
        // A period covering 300 s of the need at s = 5000, less elsewhere:
        // 900 s stay uncovered at every start.
        assert_eq!(g.energy, own + 100_000 * 900);
    }

    /// A span of starts surely passes the structural checks when every start
    /// does, and not when a manual sleep meets some start's awake need.
    #[test]
    fn a_span_surely_passes_the_structural_checks_only_clear_of_a_sleep() {
        let problem = starved_problem();
        let mut state = State::new(&problem);
        let (lo, hi) = (5000, 6000);
        assert!(state.surely_structural(0, 600, lo, hi));
        for s in lo..=hi {
            assert!(state.evaluate_inner(0, s, 600, false).is_ok(), "{s}");
        }
        // The need of the last start is `[5700, 6900)`: a manual sleep from
        // 6800 meets it, not the first start's `[4700, 5900)`.
        state.sleeps = vec![(6800, 7500, 0)];
        state.sleep_reach = vec![7500];
        assert!(state.evaluate_inner(0, lo, 600, false).is_ok());
        assert!(state.evaluate_inner(0, hi, 600, false).is_err());
        assert!(!state.surely_structural(0, 600, lo, hi));
        assert!(state.surely_structural(0, 600, lo, 5800));
    }

    /// A recorded search of a failing activity holds a run of cells that
    /// surely passes the structural checks as one try (the merge's debug
    /// check compares its ranges with every cell's exact tries).
    #[test]
    fn a_failing_run_of_cells_is_one_try() {
        let problem = on_a_starved_battery(
            r#"[
            { "id": "look", "priority": 1, "duration": 600,
              "windows": [ { "start": 5000, "end": 6000 } ],
              "energy_rate": 1.0, "awake": "required" },
            { "id": "warm", "priority": 2, "duration": 200,
              "windows": [ { "start": 5200, "end": 5200 } ],
              "energy_rate": 0.5, "awake": "any" }
          ]"#,
        );
        let mut state = State::new(&problem);
        let warm = problem.acts.iter().position(|x| x.dur_max == 200);
        let warm = warm.expect("the second activity");
        let ev = state.evaluate(warm, 5200, 200).expect("it fits");
        state.apply(1, &ev.placement);
        let look = 1 - warm;
        let cand = IntervalSet::from_intervals(vec![Interval::new(5000, 6000)]);
        let (found, tries) = state.search(look, 600, &cand, 5000);
        assert!(found.is_none());
        assert!(
            tries.iter().any(|(_, c)| matches!(c, Closeness::Cells(_))),
            "{tries:?}"
        );
        let detail = super::super::Detail::Trace;
        let merged = super::super::run_step(&state, look, 2, &Scope::default(), detail);
        assert!(merged.found.is_none());
        assert!(!merged.trace.tries.is_empty());
    }
}
