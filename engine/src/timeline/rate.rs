//! Cumulative-rate timelines: a level integrated from a piecewise-constant rate,
//! capped above. State of charge is one (capped at the battery capacity); data
//! volume is the other, stored negated (`-D`, so the floor at 0 becomes a cap at 0).
//!
//! Rates are integers per second and change only at integer seconds, so the level
//! at integer seconds is exact: `L(t+1) = min(cap, L(t) + rate(t))`, and the
//! minimum over continuous time is attained at a breakpoint.

use super::StepFn;
use super::chunks::{Points, advance};

/// Result of checking a hypothetical extra drain against a rate timeline.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LevelCheck {
    /// Lowest level over the whole domain.
    pub min: i128,
    /// First time the lowest level is reached.
    pub min_at: i64,
    /// Level at the probe time, if one was asked for.
    pub at_probe: Option<i128>,
}

/// What [`Levels::drained`] found under a drain.
struct Drained {
    min: i128,
    min_at: i64,
    level: i128,
    i: usize,
    at_probe: Option<i128>,
}

/// A capped integrator of a piecewise-constant rate over `[start, end]`.
///
/// The rate changes with every placement, but many placements are made before the
/// levels are next asked for (replaying a schedule, steps that fail before phase 2,
/// placements that change only the other timeline), so the levels are derived on
/// first use after a change rather than on every change.
#[derive(Debug)]
pub struct RateTimeline {
    cap: i128,
    initial: i128,
    rate: StepFn,
    /// A lower bound on every level, kept without the levels: see
    /// [`Self::lowest_bound`].
    floor: i128,
    levels: std::sync::OnceLock<Levels>,
    /// The levels before the latest changes, and the span `[from, to)` the
    /// changes touched the rate in: the next derivation updates them in place
    /// there (a lock only because queries take `&self`; it is never contended).
    stale: std::sync::Mutex<Option<(Levels, i64, i64)>>,
    /// The drains added since the stale levels were current (kept only while
    /// there are stale levels): what [`Self::level_at_least`] subtracts.
    since: Since,
}

/// Drains added to a rate: pieces `[a, b)` of a rate taken away, and past
/// [`Since::PIECES`] of them one lump, `(earliest start, charge)`, that
/// counts in full before any time after its start (bounded memory for a
/// timeline changed many times between queries).
#[derive(Clone, Debug, Default)]
struct Since {
    pieces: Vec<(i64, i64, i64)>,
    lump: Option<(i64, i128)>,
}

impl Since {
    const PIECES: usize = 32;

    fn clear(&mut self) {
        self.pieces.clear();
        self.lump = None;
    }

    /// Adds a drain of `rate` (> 0) on `[a, b)` (`a < b`).
    fn push(&mut self, a: i64, b: i64, rate: i64) {
        if self.pieces.len() < Self::PIECES {
            self.pieces.push((a, b, rate));
            return;
        }
        let charge = i128::from(rate) * i128::from(b - a);
        self.lump = Some(match self.lump {
            Some((from, c)) => (from.min(a), c + charge),
            None => (a, charge),
        });
    }

    /// At least the charge the drains take before `t`.
    fn charge_before(&self, t: i64) -> i128 {
        let lump = self
            .lump
            .filter(|&(from, _)| from < t)
            .map_or(0, |(_, c)| c);
        drained_before(&self.pieces, t) + lump
    }
}

/// The charge pieces `[a, b)` of a rate taken away (`(a, b, rate)`; a
/// negative rate, charge given back, counts nothing) take before `t`.
fn drained_before(pieces: &[(i64, i64, i64)], t: i64) -> i128 {
    pieces
        .iter()
        .filter(|&&(_, _, r)| r > 0)
        .map(|&(a, b, r)| i128::from(r) * i128::from((b.min(t) - a).max(0)))
        .sum()
}

impl Clone for RateTimeline {
    fn clone(&self) -> Self {
        Self {
            cap: self.cap,
            initial: self.initial,
            rate: self.rate.clone(),
            floor: self.floor,
            levels: self.levels.clone(),
            stale: std::sync::Mutex::new(self.stale_levels().clone()),
            since: self.since.clone(),
        }
    }
}

/// The levels of a [`RateTimeline`] and the summaries its queries use.
///
/// Point `i` is the start of segment `i`: its time, the rate up to point
/// `i + 1`, the level there, and the charge lost to the cap before it (the
/// waste); the last point, `n`, is the domain end. The points are stored in
/// chunks ([`Points`]) and read through accessors.
#[derive(Clone, Debug)]
struct Levels {
    cap: i128,
    points: Points,
    /// For each segment, the last segment at or before it with a profile point at
    /// the cap (built on first use: only blame queries ask).
    last_full: std::sync::OnceLock<Vec<Option<usize>>>,
}

impl RateTimeline {
    /// Integrates `rate` from `initial` (at most `cap`), capped at `cap`.
    pub fn new(rate: StepFn, initial: i128, cap: i128) -> Self {
        let floor = initial
            + rate
                .segments(rate.start(), rate.end())
                .map(|(a, b, r)| i128::from(r.min(0)) * i128::from(b - a))
                .sum::<i128>();
        Self {
            cap,
            initial,
            rate,
            floor,
            levels: std::sync::OnceLock::new(),
            stale: std::sync::Mutex::new(None),
            since: Since::default(),
        }
    }

    /// The stale levels (a poisoned lock still holds consistent data: the only
    /// writer replaces the value whole).
    fn stale_levels(&self) -> std::sync::MutexGuard<'_, Option<(Levels, i64, i64)>> {
        self.stale
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// Adds `delta` to the rate on `[a, b)`.
    pub fn add_rate(&mut self, a: i64, b: i64, delta: i64) {
        if a >= b || delta == 0 {
            return;
        }
        if delta < 0 {
            let (a, b) = (a.max(self.rate.start()), b.min(self.rate.end()));
            self.floor += i128::from(delta) * i128::from((b - a).max(0));
        }
        self.rate.add(a, b, delta);
        let stale = self
            .stale
            .get_mut()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some(levels) = self.levels.take() {
            *stale = Some((levels, a, b));
            self.since.clear();
        } else if let Some((_, from, to)) = stale {
            *from = (*from).min(a);
            *to = (*to).max(b);
        }
        if delta < 0 && stale.is_some() {
            let (a, b) = (a.max(self.rate.start()), b.min(self.rate.end()));
            if a < b {
                self.since.push(a, b, -delta);
            }
        }
    }

    /// A lower bound on the level at `t` (clamped to the domain) if `drain`
    /// (as for [`Self::check`]) were added, read without deriving the levels
    /// when changes made them stale: the stale level there less the charge
    /// the drains added since and `drain` take before `t` (a capped
    /// integrator is monotone in its rate, and falls by at most the charge
    /// drained; the cap only holds it down when it rises). From the level
    /// itself when the levels are current or there are none to start from.
    pub fn level_at_least(&self, t: i64, drain: &[(i64, i64, i64)]) -> i128 {
        let t = t.clamp(self.rate.start(), self.rate.end());
        let level = match self.levels.get() {
            Some(levels) => levels.level_at(t),
            None => {
                let stale = self
                    .stale_levels()
                    .as_ref()
                    .map(|(old, _, _)| old.level_at(t) - self.since.charge_before(t));
                stale.unwrap_or_else(|| self.level_at(t))
            }
        };
        level - drained_before(drain, t)
    }

    /// A lower bound on every level, in O(1) and without deriving the levels:
    /// the initial level plus the negative parts of the rate integrated over
    /// the domain, each change to the rate counted on its own. A capped
    /// integrator falls by at most `-min(rate, 0)` per second (the cap only
    /// holds it down when it rises), and the negative part of a sum of rates
    /// is at least the sum of their negative parts; a change undone later
    /// still counts, which only loosens the bound. So for data volume (its
    /// levels negated) `-lowest_bound()` bounds the most ever stored.
    pub fn lowest_bound(&self) -> i128 {
        self.floor
    }

    /// The rate.
    pub fn rate(&self) -> &StepFn {
        &self.rate
    }

    /// The cap.
    pub fn cap(&self) -> i128 {
        self.cap
    }

    fn levels(&self) -> &Levels {
        self.levels
            .get_or_init(|| match self.stale_levels().take() {
                Some((old, from, to)) => old.update(&self.rate, from, to),
                None => Levels::new(&self.rate, self.initial, self.cap),
            })
    }

    /// The level at time `t` (clamped to the domain).
    pub fn level_at(&self, t: i64) -> i128 {
        self.levels().level_at(t)
    }

    /// Breakpoints `(t, level)` including every time the level reaches the cap inside
    /// a segment, so that linear interpolation between them is exact.
    pub fn profile(&self) -> Vec<(i64, i128)> {
        self.levels().profile()
    }

    /// The last profile point at or before `t` where the level is at the cap (the
    /// battery was full), scanning back from `t` only.
    pub fn last_at_cap(&self, t: i64) -> Option<i64> {
        self.levels().last_at_cap(t)
    }

    /// The rate breakpoints (segment starts) and the domain end that lie in
    /// `[lo, hi]`, in order.
    pub fn breakpoints_in(&self, lo: i64, hi: i64) -> Vec<i64> {
        self.levels().points.times_in(lo, hi)
    }

    /// An upper bound on the lowest level if `energy` (> 0) more is drained over some
    /// span inside `[from, until)`: see [`Levels::drain_bound`].
    pub fn drain_bound(&self, from: i64, until: i64, energy: i128) -> i128 {
        self.levels().drain_bound(from, until, energy)
    }

    /// An upper bound on the level at `probe` if `energy` (> 0) more is drained
    /// over some span inside `[from, until)`: see [`Levels::level_bound`].
    pub fn level_bound(&self, from: i64, until: i64, energy: i128, probe: i64) -> i128 {
        self.levels().level_bound(from, until, energy, probe)
    }

    /// The starts in `[lo, hi]` for which draining at most `energy` more after the
    /// start provably keeps every level at or above `floor`: see
    /// [`Levels::surely_at_least`].
    pub fn surely_at_least(
        &self,
        lo: i64,
        hi: i64,
        energy: i128,
        floor: i128,
    ) -> Option<(i64, i64)> {
        self.levels().surely_at_least(lo, hi, energy, floor)
    }

    /// The lowest level from time `t` (clamped to the domain) to the end.
    pub fn lowest_from(&self, t: i64) -> i128 {
        self.levels().lowest_from(t)
    }

    /// The lowest level over `[lo, hi]` (`lo <= hi`).
    pub fn lowest_on(&self, lo: i64, hi: i64) -> i128 {
        self.levels().lowest_on(lo, hi)
    }

    /// [`Self::lowest_from`] for each of `times` (ascending), into `out`: one
    /// pass over the levels instead of a search per time.
    pub fn lowest_from_each(&self, times: &[i64], out: &mut Vec<i128>) {
        self.levels().lowest_from_each(times, out);
    }

    /// For the explainer's witnesses, with `drain` added (sorted, disjoint
    /// pieces) and the lowest level allowed `floor`: `(budget, until)` such that
    /// whatever other rate changes of at most `budget` total charge (absolute)
    /// are made before `until` (and any after it), the drained levels stay at
    /// or above `floor` from the drain's start to `until`, and from `until` on
    /// the drain's effect is gone (the levels equal those without it). `None`
    /// when the drain is not absorbed before the domain ends, or leaves no room.
    ///
    /// Why: a capped integrator moves by at most the charge changed (so do the
    /// drained levels, and the deficit at the drain's end by at most twice
    /// that), and after the drain the deficit shrinks by exactly the charge the
    /// unchanged trajectory loses to the cap, which the other changes reduce by
    /// at most what they change. So with changes of `c <= budget` the deficit,
    /// at most `deficit + 2c`, is absorbed once `deficit + 3 budget` is lost,
    /// which happens by `until`.
    pub fn local_budget(&self, drain: &[(i64, i64, i64)], floor: i128) -> Option<(i128, i64)> {
        self.levels().local_budget(drain, floor)
    }

    /// The profile ([`Self::profile`]) the levels would have if `drain` (sorted,
    /// disjoint `[a, b)` pieces with a rate subtracted from the timeline's rate,
    /// as for [`Self::check`]) were added: what a placement that was not made
    /// would have done to the level (the app draws it over the plot). Integrated
    /// afresh, so it costs one full integration.
    pub fn profile_with_drain(&self, drain: &[(i64, i64, i64)]) -> Vec<(i64, i128)> {
        let mut drained = Self::new(self.rate.clone(), self.initial, self.cap);
        for &(a, b, r) in drain {
            drained.add_rate(a, b, -r);
        }
        drained.profile()
    }

    /// Lowest level, and level at `probe`, if `drain` (sorted, disjoint `[a, b)`
    /// pieces with a rate subtracted from the timeline's rate) were added.
    pub fn check(&self, drain: &[(i64, i64, i64)], probe: Option<i64>) -> LevelCheck {
        self.levels().check(drain, probe)
    }
}

impl Levels {
    /// Integrates `rate` from `initial`, capped at `cap`.
    fn new(rate: &StepFn, initial: i128, cap: i128) -> Self {
        Self {
            cap,
            points: Points::new(rate, initial, cap),
            last_full: std::sync::OnceLock::new(),
        }
    }

    /// These levels updated in place to `rate`, a rate that is the same as
    /// theirs outside `[from, to)` ([`Points::update`]). Debug builds compare
    /// every point and every prefix and suffix minimum with a fresh
    /// integration, and the uncapped minimum on a few ranges.
    fn update(mut self, rate: &StepFn, from: i64, to: i64) -> Self {
        self.points.update(rate, self.cap, from, to);
        self.last_full = std::sync::OnceLock::new();
        #[cfg(debug_assertions)]
        self.check_against_fresh(rate);
        self
    }

    /// Debug builds: the points equal a fresh integration's (built from the
    /// start: no shift or tail to get wrong), and their prefix and suffix minima
    /// and some range minima of the uncapped trajectory equal those computed
    /// from its points by plain loops.
    #[cfg(debug_assertions)]
    fn check_against_fresh(&self, rate: &StepFn) {
        // (The first point's level is the initial level: nothing changes it.)
        let fresh = Points::new(rate, self.points.level(0), self.cap);
        let want: Vec<(i64, i64, i128, i128)> = fresh.iter().collect();
        self.points.check_flat();
        let got: Vec<_> = self.points.iter().collect();
        debug_assert_eq!(
            got, want,
            "incremental levels differ from a full integration"
        );
        let mut best = (i128::MAX, 0);
        for (i, p) in want.iter().enumerate() {
            if p.2 < best.0 {
                best = (p.2, i);
            }
            debug_assert_eq!(self.points.prefix_min(i), best, "prefix minimum at {i}");
        }
        let mut best = (i128::MAX, 0);
        for i in (0..want.len()).rev() {
            if want[i].2 <= best.0 {
                best = (want[i].2, i);
            }
            debug_assert_eq!(self.points.suffix_min(i), best, "suffix minimum at {i}");
        }
        let n = want.len();
        for (l, r) in [(0, n), (n / 3, n), (n / 4, n / 2 + 1), (n / 2, n / 2 + 2)] {
            let brute = (l..r.min(n)).fold(None, |b: Option<(i128, usize)>, i| {
                let v = want[i].2 + want[i].3;
                if b.is_none_or(|b| v < b.0) {
                    Some((v, i))
                } else {
                    b
                }
            });
            debug_assert_eq!(
                self.points.unc_min(l, r),
                brute,
                "uncapped minimum on [{l}, {r})"
            );
        }
    }

    /// The number of segments (the domain end is point `n`).
    fn n(&self) -> usize {
        self.points.len() - 1
    }

    /// Segment index containing `t` (the last segment for `t >= end`).
    fn index(&self, t: i64) -> usize {
        self.points.segment_at(t).0
    }

    /// The level at time `t` (clamped to the domain).
    fn level_at(&self, t: i64) -> i128 {
        self.level_and_waste_at(t).0
    }

    /// The level at `t` and the charge lost to the cap up to `t`.
    fn level_and_waste_at(&self, t: i64) -> (i128, i128) {
        self.level_and_waste_on(self.points.segment_at(t).1, t)
    }

    /// [`Self::level_and_waste_at`] with `i` the segment index of `t`.
    fn level_and_waste_in(&self, i: usize, t: i64) -> (i128, i128) {
        self.level_and_waste_on(self.points.point(i), t)
    }

    /// [`Self::level_and_waste_at`] with `point` the start of the segment of `t`.
    fn level_and_waste_on(&self, (ti, r, l, w): (i64, i64, i128, i128), t: i64) -> (i128, i128) {
        let t = t.clamp(self.points.first_time(), self.points.last_time());
        let dt = t - ti;
        let level = advance(l, r, dt, self.cap);
        let unc = l + i128::from(r) * i128::from(dt);
        (level, w + unc - level)
    }

    /// Breakpoints `(t, level)` including every time the level reaches the cap inside
    /// a segment, so that linear interpolation between them is exact.
    fn profile(&self) -> Vec<(i64, i128)> {
        let mut out = Vec::with_capacity(self.points.len() + 4);
        let mut prev: Option<(i64, i64, i128)> = None;
        for (t, r, l, _) in self.points.iter() {
            if let Some((t0, r0, l0)) = prev {
                out.extend(self.segment_points(t0, t, r0, l0).into_iter().flatten());
            }
            prev = Some((t, r, l));
        }
        if let Some((t, _, l)) = prev {
            out.push((t, l));
        }
        out
    }

    /// The profile points of the segment `[t0, t1)` at rate `r` from level `l`:
    /// its start, and where the level reaches the cap inside it (the whole
    /// seconds before and at, so that interpolation is exact at every whole
    /// second).
    fn segment_points(&self, t0: i64, t1: i64, r: i64, l: i128) -> [Option<(i64, i128)>; 3] {
        let mut out = [Some((t0, l)), None, None];
        if r > 0 && l < self.cap && l + i128::from(r) * i128::from(t1 - t0) > self.cap {
            let dt = (self.cap - l + i128::from(r) - 1) / i128::from(r);
            let tc = t0 + i64::try_from(dt).unwrap_or(t1 - t0);
            if tc - 1 > t0 {
                out[1] = Some((tc - 1, l + i128::from(r) * i128::from(tc - 1 - t0)));
            }
            if tc < t1 {
                out[2] = Some((tc, self.cap));
            }
        }
        out
    }

    /// [`Self::segment_points`] of segment `i`.
    fn segment_points_of(&self, i: usize) -> [Option<(i64, i128)>; 3] {
        let (t0, r, l, _) = self.points.point(i);
        self.segment_points(t0, self.points.time(i + 1), r, l)
    }

    /// The last profile point at or before `t` where the level is at the cap (the
    /// battery was full), scanning back from `t` only.
    fn last_at_cap(&self, t: i64) -> Option<i64> {
        let n = self.n();
        let (tn, _, ln, _) = self.points.point(n);
        if tn <= t && ln >= self.cap {
            return Some(tn);
        }
        if t < self.points.first_time() {
            return None;
        }
        let in_segment = |i: usize| {
            self.segment_points_of(i)
                .into_iter()
                .rev()
                .flatten()
                .find(|&(x, l)| x <= t && l >= self.cap)
                .map(|(x, _)| x)
        };
        let i = self.index(t);
        let last_full = self.last_full.get_or_init(|| {
            let mut last = None;
            (0..n)
                .map(|i| {
                    if self
                        .segment_points_of(i)
                        .into_iter()
                        .flatten()
                        .any(|p| p.1 >= self.cap)
                    {
                        last = Some(i);
                    }
                    last
                })
                .collect()
        });
        // Every point of the segments before `i` is before `t`.
        in_segment(i).or_else(|| {
            let j = last_full[..i].last().copied().flatten()?;
            in_segment(j)
        })
    }

    /// An upper bound on the lowest level if `energy` (> 0) more is drained over some
    /// span inside `[from, until)` (and any further drain anywhere): the levels
    /// before `from` can only fall, and at a time `t >= until` the level falls by
    /// at least `energy` less the charge the unchanged trajectory loses to the cap
    /// between `from` and `t` (the most the cap can give back). Taken at the lowest
    /// level from `until` on.
    fn drain_bound(&self, from: i64, until: i64, energy: i128) -> i128 {
        let n = self.n();
        let (f, at_from) = self.points.segment_at(from);
        let before = self.points.prefix_min(f).0;
        let i = self.points.time_pp_from(f, |x| x < until);
        if i > n || from < self.points.first_time() {
            return before;
        }
        let (m, idx) = self.points.suffix_min(i);
        let absorbed = self.points.waste(idx) - self.level_and_waste_on(at_from, from).1;
        before.min(m - (energy - absorbed).max(0))
    }

    /// An upper bound on the level at `probe` if `energy` (> 0) more is drained
    /// over some span inside `[from, until)` (and any further drain anywhere):
    /// more drain never raises a capped integrator, and when the span ends by
    /// `probe` the level there falls by at least `energy` less the charge the
    /// unchanged trajectory loses to the cap between `from` and `probe` (the most
    /// the cap can give back), as in [`Self::drain_bound`].
    fn level_bound(&self, from: i64, until: i64, energy: i128, probe: i64) -> i128 {
        let (level, waste) = self.level_and_waste_at(probe);
        if until > probe || from < self.points.first_time() || probe > self.points.last_time() {
            return level;
        }
        let absorbed = waste - self.level_and_waste_at(from).1;
        level - (energy - absorbed).max(0)
    }

    /// The starts `s` in `[lo, hi]` (one interval, or `None`) for which draining at
    /// most `energy` (>= 0) more, all of it at or after `s`, provably keeps every
    /// level at or above `floor`. A capped integrator falls by at most the extra
    /// drain, so a start in segment `i` is safe when the levels before it
    /// (the prefix minimum at `i`, which also bounds the segment's own start) and
    /// every level from the segment on less `energy` (the suffix minimum at `i`
    /// less `energy`) stay at `floor`. The first is true on a prefix of the
    /// segments and the second on a suffix, so the safe starts are one interval,
    /// found by two binary searches.
    fn surely_at_least(&self, lo: i64, hi: i64, energy: i128, floor: i128) -> Option<(i64, i64)> {
        let n = self.n();
        // Segments [i0, i1) are safe.
        let i0 = self.points.suffix_min_first(|m| m - energy >= floor).min(n);
        let i1 = self.points.prefix_min_pp(|m| m >= floor).min(n);
        if i0 >= i1 {
            return None;
        }
        let from = if i0 == 0 {
            lo
        } else {
            self.points.time(i0).max(lo)
        };
        let to = if i1 == n {
            hi
        } else {
            (self.points.time(i1) - 1).min(hi)
        };
        (from <= to).then_some((from, to))
    }

    /// `drain` clipped to the domain, without empty pieces (usually every
    /// piece is inside already: no copy then).
    fn clipped<'d>(&self, drain: &'d [(i64, i64, i64)]) -> std::borrow::Cow<'d, [(i64, i64, i64)]> {
        let (start, end) = (self.points.first_time(), self.points.last_time());
        if drain
            .iter()
            .all(|&(a, b, r)| start <= a && b <= end && a < b && r != 0)
        {
            return std::borrow::Cow::Borrowed(drain);
        }
        drain
            .iter()
            .map(|&(a, b, r)| (a.max(start), b.min(end), r))
            .filter(|&(a, b, r)| a < b && r != 0)
            .collect()
    }

    /// See [`RateTimeline::lowest_from`].
    fn lowest_from(&self, t: i64) -> i128 {
        let (i, p) = self.points.segment_at(t);
        let here = self.level_and_waste_on(p, t).0;
        if i < self.n() {
            here.min(self.points.suffix_min(i + 1).0)
        } else {
            here
        }
    }

    /// See [`RateTimeline::lowest_on`]: the levels are linear between the
    /// points, so the lowest is at an end of the span or at a point inside
    /// it.
    fn lowest_on(&self, lo: i64, hi: i64) -> i128 {
        let (a, b) = (
            self.points.time_pp(|t| t <= lo),
            self.points.time_pp(|t| t < hi),
        );
        (a..b.max(a))
            .map(|i| self.points.level(i))
            .fold(self.level_at(lo).min(self.level_at(hi)), i128::min)
    }

    /// [`Self::lowest_from`] for each of `times` (ascending), into `out`. The
    /// segment of each time is found by walking the points once; the lowest
    /// point level after a time's segment is the lowest of the points up to
    /// each later time's segment, gathered in one more walk and taken from
    /// the end.
    fn lowest_from_each(&self, times: &[i64], out: &mut Vec<i128>) {
        debug_assert!(times.is_sorted(), "times not ascending");
        let n = self.n();
        // The segment of each time, as `segment_at` finds it: the last point
        // of `[0, n)` at or before it (0 when before them all).
        let mut seg = Vec::with_capacity(times.len());
        let mut i = 0;
        for &t in times {
            while i + 1 < n && self.points.time(i + 1) <= t {
                i += 1;
            }
            seg.push(i);
        }
        // The lowest level of the points after each time's segment, up to and
        // with the next time's segment (the last: to the domain end).
        let mut bucket = vec![i128::MAX; times.len()];
        if let Some(&first) = seg.first() {
            let mut g = 0;
            for (idx, (_, _, level, _)) in (first + 1..).zip(self.points.iter_from(first + 1)) {
                while g + 1 < seg.len() && seg[g + 1] < idx {
                    g += 1;
                }
                bucket[g] = bucket[g].min(level);
            }
        }
        out.clear();
        out.resize(times.len(), 0);
        let mut after = i128::MAX;
        for g in (0..times.len()).rev() {
            after = after.min(bucket[g]);
            let here = self
                .level_and_waste_on(self.points.point(seg[g]), times[g])
                .0;
            out[g] = here.min(after);
            debug_assert_eq!(out[g], self.lowest_from(times[g]), "at {}", times[g]);
        }
    }

    /// The first point at or after `first` by which the unchanged trajectory
    /// has lost at least `x` to the cap since it lost `w_hi` (the waste never
    /// falls; `n + 1` when it never does).
    fn lost(&self, first: usize, w_hi: i128, x: i128) -> usize {
        self.points.waste_pp(|w| w - w_hi < x).max(first)
    }

    /// See [`RateTimeline::local_budget`].
    fn local_budget(&self, drain: &[(i64, i64, i64)], floor: i128) -> Option<(i128, i64)> {
        let n = self.n();
        let pieces = self.clipped(drain);
        let hi = pieces.last()?.1;
        let under = self.drained(&pieces, None, false);
        let mut i = under.i;
        while i + 1 < n && self.points.time(i + 1) <= hi {
            i += 1;
        }
        let (e_hi, w_hi) = self.level_and_waste_in(i, hi);
        let deficit = e_hi - under.level;
        if deficit < 0 {
            return None;
        }
        // Breakpoints after `hi`, and the first by which the unchanged
        // trajectory has lost `x` more to the cap since `hi`.
        let first = if self.points.last_time() <= hi {
            n + 1
        } else {
            i + 1
        };
        let absorbed = self.lost(first, w_hi, deficit);
        if absorbed > n {
            return None;
        }
        // The drained levels up to where the deficit is absorbed, exactly.
        let mut low = under.min;
        if let Some((u, _)) = self.points.unc_min(first, absorbed) {
            low = low.min(u - w_hi - deficit);
        }
        let budget = (low - floor) / 4;
        if budget <= 0 {
            return None;
        }
        let until = self.lost(first, w_hi, deficit + 3 * budget);
        if until > n {
            return None;
        }
        // From there to `until` the levels are unchanged, and every level
        // there is above `uncapped - w_hi - deficit - 3 budget`: less than that
        // is lost to the cap before `until`.
        if let Some((u, _)) = self.points.unc_min(absorbed, until) {
            low = low.min(u - w_hi - deficit - 3 * budget);
        }
        Some((budget.min(low - floor), self.points.time(until))).filter(|b| b.0 >= 0)
    }

    /// The walk under a drain (sorted, disjoint, clipped, non-empty pieces):
    /// the lowest level from the drain's start on (from the domain start with
    /// `with_before`), the level at its end and the segment the walk ended in,
    /// and the level at `probe` if it falls before the drain's end.
    fn drained(
        &self,
        pieces: &[(i64, i64, i64)],
        probe: Option<i64>,
        with_before: bool,
    ) -> Drained {
        let (lo, hi) = (pieces[0].0, pieces[pieces.len() - 1].1);
        let mut at_probe = probe.filter(|&p| p < lo).map(|p| self.level_at(p));
        let (i_lo, p_lo) = self.points.segment_at(lo);
        let mut level = self.level_and_waste_on(p_lo, lo).0;
        let (mut min, mut min_at) = (level, lo);
        if with_before {
            // Before the drain: unchanged.
            let (m, idx) = self.points.prefix_min(i_lo);
            if m <= min {
                (min, min_at) = (m, self.points.time(idx));
            }
        }

        // Under the drain: simulate over the merged breakpoints.
        let mut t = lo;
        let mut i = i_lo;
        let mut k = 0;
        // Point i + 1 (the segment's end) and the ones after it.
        let mut ahead = self.points.iter_from(i_lo + 1);
        let mut end_point = ahead.next();
        let mut seg_rate = p_lo.1;
        let mut seg_end = end_point.map_or(i64::MAX, |p| p.0);
        while t < hi {
            while seg_end <= t {
                i += 1;
                seg_rate = end_point.map_or(0, |p| p.1);
                end_point = ahead.next();
                seg_end = end_point.map_or(i64::MAX, |p| p.0);
            }
            while pieces[k].1 <= t {
                k += 1;
            }
            let (pa, pb, pr) = pieces[k];
            let (extra, next_piece) = if t < pa { (0, pa) } else { (pr, pb) };
            let next = seg_end.min(next_piece).min(hi);
            let r = seg_rate.saturating_sub(extra);
            if let Some(p) = probe.filter(|&p| t <= p && p < next) {
                at_probe = Some(advance(level, r, p - t, self.cap));
            }
            level = advance(level, r, next - t, self.cap);
            if level < min {
                (min, min_at) = (level, next);
            }
            t = next;
        }
        Drained {
            min,
            min_at,
            level,
            i,
            at_probe,
        }
    }

    /// Lowest level, and level at `probe`, if `drain` (sorted, disjoint `[a, b)`
    /// pieces with a rate subtracted from the timeline's rate) were added.
    fn check(&self, drain: &[(i64, i64, i64)], probe: Option<i64>) -> LevelCheck {
        let n = self.n();
        let pieces = self.clipped(drain);
        let Some(last) = pieces.last() else {
            let (min, idx) = self.points.prefix_min(n);
            return LevelCheck {
                min,
                min_at: self.points.time(idx),
                at_probe: probe.map(|p| self.level_at(p)),
            };
        };
        let hi = last.1;
        let Drained {
            mut min,
            mut min_at,
            mut level,
            mut i,
            mut at_probe,
        } = self.drained(&pieces, probe, true);

        // After the drain the rates are the same, and the deficit only shrinks by the
        // charge the unchanged trajectory loses to the cap: with W the cumulative
        // loss, E'(t) = E(t) - max(0, deficit - (W(t) - W(hi))). Before the deficit is
        // absorbed that is the uncapped trajectory E + W shifted down (a range
        // minimum); after it, the unchanged levels (a suffix minimum).
        // `i` is the segment the walk ended in; step to the one holding `hi`.
        while i + 1 < n && self.points.time(i + 1) <= hi {
            i += 1;
        }
        let (e_hi, w_hi) = self.level_and_waste_in(i, hi);
        let deficit = e_hi - level;
        if deficit >= 0 {
            // The number of breakpoints at or before `hi`.
            let first = if self.points.last_time() <= hi {
                n + 1
            } else {
                i + 1
            };
            let absorbed = self.lost(first, w_hi, deficit);
            if let Some((u, idx)) = self.points.unc_min(first, absorbed) {
                let v = u - w_hi - deficit;
                if v < min {
                    (min, min_at) = (v, self.points.time(idx));
                }
            }
            if absorbed <= n {
                let (m, idx) = self.points.suffix_min(absorbed);
                if m < min {
                    (min, min_at) = (m, self.points.time(idx));
                }
            }
            if let Some(p) = probe.filter(|&p| p >= hi) {
                let (e, w) = self.level_and_waste_at(p);
                at_probe = Some(e - (deficit - (w - w_hi)).max(0));
            }
            return LevelCheck {
                min,
                min_at,
                at_probe,
            };
        }
        // A surplus (negative drain): walk until the trajectories meet again.
        let mut i = self.index(hi);
        let mut t = hi;
        loop {
            if i >= n {
                break;
            }
            let (_, rate, _, _) = self.points.point(i);
            let (next, _, old_next, _) = self.points.point(i + 1);
            if let Some(p) = probe.filter(|&p| t <= p && (p < next || (i + 1 == n && p <= next))) {
                at_probe = Some(advance(level, rate, p - t, self.cap));
            }
            level = advance(level, rate, next - t, self.cap);
            i += 1;
            t = next;
            if level == old_next {
                let (m, idx) = self.points.suffix_min(i);
                if m < min {
                    (min, min_at) = (m, self.points.time(idx));
                }
                if let Some(p) = probe.filter(|&p| p > t) {
                    at_probe = Some(self.level_at(p));
                }
                break;
            }
            if level < min {
                (min, min_at) = (level, t);
            }
        }
        if at_probe.is_none() {
            at_probe = probe.map(|p| {
                if p >= self.points.last_time() {
                    level
                } else {
                    self.level_at(p)
                }
            });
        }
        LevelCheck {
            min,
            min_at,
            at_probe,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::timeline::xorshift;

    #[test]
    fn profile_with_drain_matches_check_and_leaves_the_timeline_alone() {
        let mut rate = StepFn::constant(0, 100, 5);
        rate.add(40, 60, -20);
        let tl = RateTimeline::new(rate, 500, 600);
        let before = tl.profile();
        let drain = [(10, 30, 7), (50, 70, 3)];
        let drained = tl.profile_with_drain(&drain);
        let check = tl.check(&drain, Some(65));
        let lowest = drained.iter().map(|p| p.1).min();
        assert_eq!(lowest, Some(check.min));
        let at = |t: i64| drained.iter().find(|p| p.0 == t).map(|p| p.1);
        assert_eq!(at(check.min_at), Some(check.min));
        // Per-second simulation at every profile point.
        let mut r = StepFn::constant(0, 100, 5);
        r.add(40, 60, -20);
        let brute = brute(&r, &drain, 500, 600);
        for &(t, level) in &drained {
            assert_eq!(level, brute[usize::try_from(t).unwrap_or(0)], "at {t}");
        }
        assert_eq!(tl.profile(), before);
        assert_eq!(tl.profile_with_drain(&[]), before);
    }

    /// Brute force: per-second simulation.
    fn brute(rate: &StepFn, drain: &[(i64, i64, i64)], initial: i128, cap: i128) -> Vec<i128> {
        let mut out = vec![initial];
        let mut l = initial;
        for t in rate.start()..rate.end() {
            let d: i64 = drain
                .iter()
                .filter(|p| p.0 <= t && t < p.1)
                .map(|p| p.2)
                .sum();
            l = advance(l, rate.value_at(t) - d, 1, cap);
            out.push(l);
        }
        out
    }

    #[test]
    fn capped_integration_matches_per_second() {
        let mut rate = StepFn::constant(0, 100, 3);
        rate.add(20, 40, -10);
        rate.add(60, 70, 50);
        let tl = RateTimeline::new(rate.clone(), 100, 150);
        let b = brute(&rate, &[], 100, 150);
        for t in 0..=100 {
            assert_eq!(tl.level_at(t), b[t as usize], "t={t}");
        }
        let drains: [&[(i64, i64, i64)]; 4] = [
            &[(10, 30, 5)],
            &[(0, 5, 100), (50, 65, 7)],
            &[(90, 100, 40)],
            &[(15, 16, 1000)],
        ];
        for drain in drains {
            let b = brute(&rate, drain, 100, 150);
            let min = *b.iter().min().unwrap();
            let at = b.iter().position(|&x| x == min).unwrap() as i64;
            for probe in [0, 17, 55, 66, 99, 100] {
                let c = tl.check(drain, Some(probe));
                assert_eq!(c.min, min, "{drain:?}");
                assert_eq!(c.min_at, at, "{drain:?}");
                assert_eq!(
                    c.at_probe,
                    Some(b[probe as usize]),
                    "{drain:?} probe {probe}"
                );
            }
        }
    }

    /// A random rate over `[0, 120)` and its timeline: `(rate, initial, cap, tl)`.
    fn random_timeline(next: &mut impl FnMut(i64) -> i64) -> (StepFn, i128, i128, RateTimeline) {
        let mut rate = StepFn::constant(0, 120, next(9) - 3);
        for _ in 0..next(6) {
            let a = next(120);
            rate.add(a, a + next(40), next(21) - 10);
        }
        let (cap, initial) = (100 + next(100) as i128, next(100) as i128);
        let initial = initial.min(cap);
        let tl = RateTimeline::new(rate.clone(), initial, cap);
        (rate, initial, cap, tl)
    }

    #[test]
    fn random_drains_match_per_second() {
        let mut next = xorshift(0x2545_f491_4f6c_dd1d);
        for _ in 0..300 {
            let (rate, initial, cap, tl) = random_timeline(&mut next);
            let mut drain = Vec::new();
            let mut t = next(60);
            for _ in 0..next(4) {
                let len = 1 + next(20);
                drain.push((t, t + len, next(15) - 2));
                t += len + next(10);
            }
            let b = brute(&rate, &drain, initial, cap);
            let min = *b.iter().min().unwrap();
            let probe = next(121);
            let c = tl.check(&drain, Some(probe));
            assert_eq!(c.min, min, "{drain:?}");
            assert_eq!(b[c.min_at as usize], min, "{drain:?}");
            assert_eq!(
                c.at_probe,
                Some(b[probe as usize]),
                "{drain:?} probe {probe}"
            );
        }
    }

    /// Runs `check` on 300 random timelines, each as made and then after
    /// each of two random changes to its rate (after its levels were
    /// derived), with its levels per second and the random source.
    fn on_changing_timelines(
        seed: u64,
        mut check: impl FnMut(&RateTimeline, &[i128], &mut dyn FnMut(i64) -> i64),
    ) {
        let mut next = xorshift(seed);
        for _ in 0..300 {
            let (mut rate, initial, cap, mut tl) = random_timeline(&mut next);
            for round in 0..3 {
                if round > 0 {
                    let (a, len, delta) = (next(120), 1 + next(30), next(21) - 10);
                    rate.add(a, a + len, delta);
                    tl.add_rate(a, a + len, delta);
                }
                let b = brute(&rate, &[], initial, cap);
                check(&tl, &b, &mut next);
            }
        }
    }

    /// The lowest level from each of many times, in one pass, is the lowest
    /// of the levels per second from that time on, through changes to the
    /// rate after the levels were first derived.
    #[test]
    fn lowest_from_each_matches_per_second() {
        on_changing_timelines(0x6a09_e667_f3bc_c908, |tl, b, next| {
            let mut times: Vec<i64> = (0..next(12)).map(|_| next(140) - 10).collect();
            times.sort_unstable();
            let mut out = Vec::new();
            tl.lowest_from_each(&times, &mut out);
            for (&t, &got) in times.iter().zip(&out) {
                let from = t.clamp(0, 120) as usize;
                let want = *b[from..].iter().min().unwrap();
                assert_eq!(got, want, "t={t} times {times:?}");
            }
        });
    }

    /// The lowest level over a span is the lowest of the levels per second
    /// in it, through changes to the rate after the levels were derived.
    #[test]
    fn lowest_on_matches_per_second() {
        on_changing_timelines(0xbb67_ae85_84ca_a73b, |tl, b, next| {
            for _ in 0..8 {
                let lo = next(121);
                let hi = lo + next(121 - lo + 1).min(120 - lo);
                let want = *b[lo as usize..=hi as usize].iter().min().unwrap();
                assert_eq!(tl.lowest_on(lo, hi), want, "[{lo}, {hi}]");
            }
        });
    }

    #[test]
    fn last_at_cap_matches_the_profile() {
        let mut rate = StepFn::constant(0, 100, 7);
        rate.add(20, 50, -12);
        rate.add(70, 80, -30);
        let tl = RateTimeline::new(rate.clone(), 0, 60);
        let profile = tl.profile();
        for t in -5..110 {
            let want = profile
                .iter()
                .rev()
                .find(|&&(x, l)| x <= t && l >= 60)
                .map(|p| p.0);
            assert_eq!(tl.last_at_cap(t), want, "t={t}");
        }
    }

    /// The level-free lower bound stays at or below every level through any
    /// changes to the rate, undone ones too, and is exact for a rate that
    /// never rises above zero.
    #[test]
    fn lowest_bound_bounds_every_level() {
        let mut next = xorshift(0x2f1d_3c5b_7a69_4e83);
        for _ in 0..300 {
            let (_, _, _, mut tl) = random_timeline(&mut next);
            for _ in 0..next(8) {
                let (a, len, delta) = (next(140) - 10, next(40), next(21) - 10);
                tl.add_rate(a, a + len, delta);
                if next(3) == 0 {
                    tl.add_rate(a, a + len, -delta);
                }
                let lowest = tl.profile().iter().map(|p| p.1).min().unwrap();
                assert!(
                    tl.lowest_bound() <= lowest,
                    "{} > {lowest}",
                    tl.lowest_bound()
                );
            }
        }
        let mut rate = StepFn::constant(0, 100, -2);
        rate.add(10, 30, -3);
        rate.add(40, 50, 2);
        let mut tl = RateTimeline::new(rate, 500, 600);
        tl.add_rate(60, 70, -1);
        assert_eq!(tl.lowest_bound(), 500 - 200 - 60 + 20 - 10);
        assert_eq!(tl.lowest_bound(), tl.lowest_from(0));
    }

    /// The galloping search from a point finds what the plain search finds,
    /// from every point and for every boundary (inside the points and past
    /// either end).
    #[test]
    fn time_search_from_a_point_matches_the_plain_search() {
        let mut next = xorshift(0x9e37_79b9_7f4a_7c15);
        for _ in 0..100 {
            let (_, _, _, tl) = random_timeline(&mut next);
            let points = &tl.levels().points;
            for i in 0..=points.len() {
                for until in -1..=122 {
                    assert_eq!(
                        points.time_pp_from(i, |x| x < until),
                        points.time_pp(|x| x < until),
                        "from point {i}, boundary {until}"
                    );
                }
            }
        }
    }

    #[test]
    fn drain_bound_bounds_every_placement() {
        let mut next = xorshift(0x9e37_79b9_7f4a_7c15);
        for _ in 0..300 {
            let (rate, initial, cap, tl) = random_timeline(&mut next);
            let (d, r) = (1 + next(20), 1 + next(12));
            let from = next(100);
            let to = from + next(10);
            let bound = tl.drain_bound(from, to + d, i128::from(r * d));
            for s in from..=to.min(120 - d) {
                // The activity's own drain, plus an arbitrary extra drain elsewhere.
                let extra = next(30);
                let drain = [(s, s + d, r), (s + d, (s + d + extra).min(120), next(5))];
                let drain: Vec<_> = drain.into_iter().filter(|p| p.0 < p.1).collect();
                let b = brute(&rate, &drain, initial, cap);
                let min = *b.iter().min().unwrap();
                assert!(min <= bound, "s={s} min={min} bound={bound}");
            }
        }
    }

    #[test]
    fn level_bound_bounds_every_placement() {
        let mut next = xorshift(0x2f6b_1c3d_9a85_e417);
        let mut below_level = 0;
        for _ in 0..400 {
            let (rate, initial, cap, tl) = random_timeline(&mut next);
            let (d, r) = (1 + next(20), 1 + next(12));
            let from = next(100);
            let to = from + next(10);
            let probe = next(125) - 2;
            let bound = tl.level_bound(from, to + d, i128::from(r * d), probe);
            below_level += usize::from(bound < tl.level_at(probe));
            for s in from..=to.min(120 - d) {
                // The activity's own drain, plus an arbitrary extra drain elsewhere.
                let (x, extra) = (next(120), next(30));
                let drain = [(s, s + d, r), (x, (x + extra).min(120), next(5))];
                let mut drain: Vec<_> = drain.into_iter().filter(|p| p.0 < p.1).collect();
                drain.sort_unstable();
                let b = brute(&rate, &drain, initial, cap);
                let at = b[probe.clamp(0, 120) as usize];
                assert!(at <= bound, "s={s} probe={probe} level={at} bound={bound}");
            }
        }
        // The bound does more than say "no higher than now" (the drain shows).
        assert!(below_level > 100, "{below_level}");
    }

    /// The level read from stale levels less the drains since is never
    /// above the level, through many changes between queries (past the
    /// pieces kept one by one), and it is the level when nothing drained;
    /// with a drain of its own, never above the drained level.
    #[test]
    fn level_at_least_bounds_the_level() {
        let mut next = xorshift(0x1f83_d9ab_fb41_bd6b);
        let (mut stale_reads, mut below, mut lumped) = (0, 0, 0);
        for _ in 0..200 {
            let (mut rate, initial, cap, mut tl) = random_timeline(&mut next);
            tl.level_at(0);
            for _ in 0..1 + next(120) {
                let (a, len, delta) = (next(130) - 5, 1 + next(40), next(21) - 12);
                rate.add(a, a + len, delta);
                tl.add_rate(a, a + len, delta);
                let t = next(140) - 10;
                let stale = tl.levels.get().is_none();
                let bound = tl.level_at_least(t, &[]);
                let level = brute(&rate, &[], initial, cap)[t.clamp(0, 120) as usize];
                assert!(bound <= level, "t={t}: {bound} > {level}");
                assert!(stale || bound == level);
                // With a drain of its own: never above the drained level.
                let drain = [(next(120), 120 + next(10), next(9) - 2)];
                let drained = brute(&rate, &drain, initial, cap)[t.clamp(0, 120) as usize];
                assert!(tl.level_at_least(t, &drain) <= drained, "t={t} {drain:?}");
                stale_reads += usize::from(stale);
                below += usize::from(bound < level);
                lumped += usize::from(tl.since.lump.is_some());
                if next(64) == 0 {
                    assert_eq!(tl.level_at(t), level);
                }
            }
        }
        assert!(
            stale_reads > 1000 && below > 100 && lumped > 100,
            "{stale_reads} {below} {lumped}"
        );
    }

    #[test]
    fn incremental_levels_match_a_fresh_integration() {
        let mut next = xorshift(0x5851_f42d_4c95_7f2d);
        for _ in 0..100 {
            let (_, initial, cap, mut tl) = random_timeline(&mut next);
            for _ in 0..8 {
                // Several changes between queries, at random places.
                for _ in 0..1 + next(3) {
                    let a = next(130) - 5;
                    tl.add_rate(a, a + 1 + next(50), next(21) - 10);
                }
                let fresh = RateTimeline::new(tl.rate().clone(), initial, cap);
                let drain = [(next(60), 60 + next(60), next(9))];
                assert_eq!(tl.check(&drain, Some(50)), fresh.check(&drain, Some(50)));
                assert_eq!(tl.profile(), fresh.profile());
                assert_eq!(tl.breakpoints_in(-10, 200), fresh.breakpoints_in(-10, 200));
            }
        }
    }

    /// `local_budget`'s promise, by brute force: any other changes of at most
    /// the budget before `until` (and any after it) keep the drained levels at
    /// or above the floor from the drain's start to `until`, and leave no trace
    /// of the drain from `until` on.
    #[test]
    fn local_budget_holds_under_any_change_within_it() {
        let mut next = xorshift(0x9e37_79b9_7f4a_7c15);
        let mut checked = 0;
        for _ in 0..3000 {
            let (rate, initial, cap, tl) = random_timeline(&mut next);
            let a = next(100);
            let drain = [(a, a + 1 + next(15), 1 + next(8))];
            let lowest = *brute(&rate, &drain, initial, cap)[a as usize..]
                .iter()
                .min()
                .unwrap();
            let floor = lowest - next(40) as i128;
            let Some((budget, until)) = tl.local_budget(&drain, floor) else {
                continue;
            };
            for _ in 0..20 {
                let mut other: Vec<(i64, i64, i64)> = Vec::new();
                let mut spent = 0i128;
                for _ in 0..1 + next(3) {
                    let x = next(until.max(1));
                    let (y, r) = (x + 1 + next(20), next(11) - 5);
                    let charge = i128::from(r.abs()) * i128::from(y - x);
                    if spent + charge <= budget {
                        spent += charge;
                        other.push((x, y, r));
                    }
                }
                // Anything at all from `until` on.
                let x = until + next(30);
                other.push((x, x + 1 + next(30), next(41) - 20));
                let without = brute(&rate, &other, initial, cap);
                let both: Vec<(i64, i64, i64)> = other.iter().chain(&drain).copied().collect();
                let with = brute(&rate, &both, initial, cap);
                for t in 0..=120usize {
                    let t_i = t as i64;
                    if t_i >= until {
                        assert_eq!(with[t], without[t], "t={t} until={until}");
                    } else if t_i >= a {
                        assert!(with[t] >= floor, "t={t} floor={floor} budget={budget}");
                    }
                }
                checked += 1;
            }
        }
        assert!(
            checked > 500,
            "too few cases with a local budget: {checked}"
        );
    }

    #[test]
    fn profile_marks_cap_hits() {
        let rate = StepFn::constant(0, 10, 7);
        let tl = RateTimeline::new(rate.clone(), 0, 20);
        assert_eq!(tl.profile(), vec![(0, 0), (2, 14), (3, 20), (10, 20)]);
    }
}
