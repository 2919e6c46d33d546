//! The discrete timeline kinds: state, atomic, claimable and cumulative.
//!
//! Every query takes the candidate's duration `d` and a domain `[lo, hi]` of starts
//! and returns the valid starts within it. Occupancy is half-open `[start, end)`:
//! a candidate at `s` overlaps `[a, b)` exactly when `a - d < s < b`.

use super::{Interval, IntervalSet, StepFn};

/// Starts `s` in `[lo, hi]` for which `[s, s + d)` overlaps none of `busy`
/// (half-open intervals, any order). The atomic (unit resource) timeline.
pub fn atomic_valid(
    busy: impl IntoIterator<Item = (i64, i64)>,
    d: i64,
    lo: i64,
    hi: i64,
) -> IntervalSet {
    let forbidden: IntervalSet = busy
        .into_iter()
        .map(|(a, b)| Interval::new(a.saturating_sub(d).saturating_add(1), b.saturating_sub(1)))
        .filter(|iv| iv.lo <= hi && iv.hi >= lo)
        .collect();
    IntervalSet::single(lo, hi).subtract(&forbidden)
}

/// A unit resource's busy intervals (half-open `[start, end)`), sorted by start
/// ([`TaggedSpans`]), so that a query looks only at the intervals near its
/// range rather than at every placement on the resource (a windowless
/// activity's query over 30 sols made phase 1 quadratic in the plan).
#[derive(Clone, Debug, Default)]
pub struct UnitTimeline {
    busy: TaggedSpans<()>,
}

impl UnitTimeline {
    /// Marks `[s, e)` busy.
    pub fn add(&mut self, s: i64, e: i64) {
        self.busy.add(s, e, ());
    }

    /// Whether some busy interval overlaps `[from, to)`.
    pub fn overlaps(&self, from: i64, to: i64) -> bool {
        self.busy.overlapping(from, to).next().is_some()
    }

    /// [`atomic_valid`] over these intervals.
    pub fn valid(&self, d: i64, lo: i64, hi: i64) -> IntervalSet {
        let near = self.busy.overlapping(lo, hi.saturating_add(d));
        let valid = atomic_valid(near.map(|(a, b, ())| (a, b)), d, lo, hi);
        #[cfg(debug_assertions)]
        debug_assert_eq!(
            valid,
            atomic_valid(self.busy.spans.iter().map(|&(a, b, ())| (a, b)), d, lo, hi),
            "near {lo}..{hi}"
        );
        valid
    }
}

/// Intervals `[start, end)` with a tag each, sorted by start, so that a query
/// near a range looks only at those that can overlap it (a unit resource's
/// busy intervals, and the placed UHF intervals: a windowless activity's
/// phase 1 asked for every one of them, once per window).
#[derive(Clone, Debug)]
pub struct TaggedSpans<T> {
    spans: Vec<(i64, i64, T)>,
    /// The longest interval.
    longest: i64,
}

impl<T> Default for TaggedSpans<T> {
    fn default() -> Self {
        Self {
            spans: Vec::new(),
            longest: 0,
        }
    }
}

impl<T: Copy> TaggedSpans<T> {
    /// Adds `[s, e)` with `tag`, after those starting at or before `s`.
    pub fn add(&mut self, s: i64, e: i64, tag: T) {
        let i = self.spans.partition_point(|x| x.0 <= s);
        self.spans.insert(i, (s, e, tag));
        self.longest = self.longest.max(e - s);
    }

    /// The intervals that overlap `[from, to)`, by start.
    pub fn overlapping(&self, from: i64, to: i64) -> impl Iterator<Item = (i64, i64, T)> + '_ {
        let i = self
            .spans
            .partition_point(|x| x.0 < from.saturating_sub(self.longest));
        let j = self.spans.partition_point(|x| x.0 < to).max(i);
        self.spans[i..j].iter().copied().filter(move |x| x.1 > from)
    }
}

/// Starts `s` in `[lo, hi]` for which `usage <= limit` at every second of
/// `[s, s + d)`. The claimable timeline (sequence engines, peak power).
pub fn claimable_valid(usage: &StepFn, limit: i64, d: i64, lo: i64, hi: i64) -> IntervalSet {
    let forbidden: IntervalSet = usage
        .segments(lo, hi.saturating_add(d))
        .filter(|&(_, _, v)| v > limit)
        .map(|(a, b, _)| Interval::new(a.saturating_sub(d).saturating_add(1), b.saturating_sub(1)))
        .collect();
    IntervalSet::single(lo, hi).subtract(&forbidden)
}

/// Starts `s` in `[lo, hi]` for which `total + rate * |[s, s + d) ∩ [from, to)|
/// <= max`. The cumulative timeline (data produced before handover).
pub fn cumulative_valid(
    total: i128,
    max: i128,
    rate: i64,
    d: i64,
    (from, to): (i64, i64),
    (lo, hi): (i64, i64),
) -> IntervalSet {
    if rate <= 0 || to <= from {
        return if total <= max {
            IntervalSet::single(lo, hi)
        } else {
            IntervalSet::empty()
        };
    }
    if total > max {
        return IntervalSet::empty();
    }
    // The largest overlap allowed, in whole seconds.
    let allowed = (max - total) / i128::from(rate);
    let full = i128::from(d.min(to - from));
    if allowed >= full {
        return IntervalSet::single(lo, hi);
    }
    let allowed = i64::try_from(allowed).unwrap_or(0);
    // Overlap <= allowed: the activity ends early enough or starts late enough.
    let early = IntervalSet::single(lo, hi.min(from.saturating_add(allowed).saturating_sub(d)));
    let late = IntervalSet::single(lo.max(to.saturating_sub(allowed)), hi);
    early.union(&late)
}

/// A placed state effect: at `time`, activity `owner` (placed at `step`) sets the
/// state to `value`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StateChange {
    /// When the value changes.
    pub time: i64,
    /// The step that placed the effect (orders effects at the same time).
    pub step: usize,
    /// The value set.
    pub value: usize,
    /// The activity whose effect it is.
    pub owner: usize,
}

/// The distinct times of `effects` (sorted by `(time, step)`) with the value that
/// wins there (the later step).
fn effective(effects: &[StateChange]) -> Vec<(i64, usize)> {
    let mut out: Vec<(i64, usize)> = Vec::with_capacity(effects.len());
    for &StateChange {
        time: t, value: v, ..
    } in effects
    {
        match out.last_mut() {
            Some(last) if last.0 == t => last.1 = v,
            _ => out.push((t, v)),
        }
    }
    out
}

/// One named state: its initial value, the placed effects and requirements.
#[derive(Clone, Debug, Default)]
pub struct StateTimeline {
    initial: usize,
    /// Sorted by `(time, step)`.
    effects: Vec<StateChange>,
    /// Placed requirements `(start, end, value, owner)`.
    requirements: Vec<(i64, i64, usize, usize)>,
}

impl StateTimeline {
    /// A state holding `initial` until the first effect.
    pub fn new(initial: usize) -> Self {
        Self {
            initial,
            effects: Vec::new(),
            requirements: Vec::new(),
        }
    }

    /// Records an effect of activity `owner` placed at `step`.
    pub fn add_effect(&mut self, time: i64, step: usize, value: usize, owner: usize) {
        let at = self
            .effects
            .partition_point(|e| (e.time, e.step) <= (time, step));
        self.effects.insert(
            at,
            StateChange {
                time,
                step,
                value,
                owner,
            },
        );
    }

    /// Records a placed requirement of activity `owner` over `[start, end)`.
    pub fn add_requirement(&mut self, start: i64, end: i64, value: usize, owner: usize) {
        self.requirements.push((start, end, value, owner));
    }

    /// The placed effects, sorted by `(time, step)`.
    pub fn effects(&self) -> &[StateChange] {
        &self.effects
    }

    /// The distinct effect times with the value that wins there (the later step).
    fn effective(&self) -> Vec<(i64, usize)> {
        effective(&self.effects)
    }

    /// The value held at time `t`.
    pub fn value_at(&self, t: i64) -> usize {
        self.effective()
            .iter()
            .take_while(|e| e.0 <= t)
            .last()
            .map_or(self.initial, |e| e.1)
    }

    /// Maximal segments `(from, to, value)` of constant value, with `i64::MIN` and
    /// `i64::MAX` standing for the open ends.
    pub fn segments(&self) -> Vec<(i64, i64, usize)> {
        let eff = self.effective();
        let mut out = Vec::with_capacity(eff.len() + 1);
        let mut from = i64::MIN;
        let mut value = self.initial;
        for (t, v) in eff {
            if v != value {
                out.push((from, t, value));
                from = t;
                value = v;
            }
        }
        out.push((from, i64::MAX, value));
        out
    }

    /// Starts in `[lo, hi]` at which every placed requirement holds once the
    /// effects `own` (`(offset, value)`) of activity `owner`, placed at `step`,
    /// are added at `s + offset`: the check that removing an activity and placing
    /// it elsewhere leaves no requirement without the value it set (free slack).
    /// A requirement sees the state without its own activity's effects.
    pub fn requirements_hold_with(
        &self,
        own: &[(i64, usize)],
        step: usize,
        owner: usize,
        lo: i64,
        hi: i64,
    ) -> IntervalSet {
        if own.is_empty() || lo > hi {
            return IntervalSet::single(lo, hi);
        }
        // Whether each requirement holds is constant between these points.
        let mut times: Vec<i64> = self.effects.iter().map(|e| e.time).collect();
        for &(rs, re, _, _) in &self.requirements {
            times.push(rs);
            times.push(re);
        }
        let mut points = vec![lo, hi.saturating_add(1)];
        for &(o, _) in own {
            for &t in &times {
                for p in [t.saturating_sub(o), t.saturating_sub(o).saturating_add(1)] {
                    if lo < p && p <= hi {
                        points.push(p);
                    }
                }
            }
        }
        points.sort_unstable();
        points.dedup();
        let holds = |s: i64| {
            let mut all = self.effects.clone();
            for &(o, value) in own {
                all.push(StateChange {
                    time: s.saturating_add(o),
                    step,
                    value,
                    owner,
                });
            }
            all.sort_by_key(|e| (e.time, e.step));
            self.requirements.iter().all(|&(rs, re, value, req_owner)| {
                let seen: Vec<StateChange> = all
                    .iter()
                    .filter(|e| e.owner != req_owner)
                    .copied()
                    .collect();
                let effective = effective(&seen);
                let at_start = effective
                    .iter()
                    .take_while(|e| e.0 <= rs)
                    .last()
                    .map_or(self.initial, |e| e.1);
                at_start == value
                    && effective
                        .iter()
                        .filter(|e| rs < e.0 && e.0 < re)
                        .all(|e| e.1 == value)
            })
        };
        points
            .windows(2)
            .filter(|w| holds(w[0]))
            .map(|w| Interval::new(w[0], w[1] - 1))
            .collect()
    }

    /// Starts in `[lo, hi]` where the state holds `value` over `[s, s + d)`.
    pub fn requirement_valid(&self, value: usize, d: i64, lo: i64, hi: i64) -> IntervalSet {
        self.segments()
            .into_iter()
            .filter(|seg| seg.2 == value)
            .map(|(a, b, _)| Interval::new(a, b.saturating_sub(d)))
            .collect::<IntervalSet>()
            .clip(lo, hi)
    }

    /// Whether start `s` is one of [`Self::requirement_valid`]'s: the value
    /// held at `s` is `value` and no effect changes it before `s + d`. The
    /// point version, without building the state's segments.
    pub fn requirement_holds(&self, value: usize, d: i64, s: i64) -> bool {
        let holds = if d <= 0 {
            // A segment ending at `s` holds it too: the full version.
            self.requirement_valid(value, d, s, s).contains(s)
        } else {
            let from = self.effects.partition_point(|e| e.time <= s);
            let held = from
                .checked_sub(1)
                .map_or(self.initial, |k| self.effects[k].value);
            let end = s.saturating_add(d);
            // Effects at one time: the last (in step order) holds from then.
            let mut changes = self.effects[from..]
                .iter()
                .take_while(|e| e.time < end)
                .enumerate()
                .filter(|&(k, e)| {
                    self.effects
                        .get(from + k + 1)
                        .is_none_or(|next| next.time != e.time)
                });
            held == value && changes.all(|(_, e)| e.value == value)
        };
        debug_assert_eq!(
            holds,
            self.requirement_valid(value, d, s, s).contains(s),
            "a requirement's point check disagrees with its valid starts at {s}"
        );
        holds
    }

    /// Starts in `[lo, hi]` where this activity's effects on the state (`own`:
    /// `(offset, value)` sorted by offset, offsets 0 or `d`) change no value seen by
    /// a placed requirement. A requirement sees the state without its own
    /// activity's effects.
    pub fn effect_valid(&self, own: &[(i64, usize)], lo: i64, hi: i64) -> IntervalSet {
        self.effects_valid(own, false, lo, hi)
    }

    /// [`Self::effect_valid`] checking only the effects at offset 0 (each still
    /// cut by the activity's next own effect): leaving out the effects at its end,
    /// the one part of the category that is not monotone in the duration.
    pub fn start_effects_valid(&self, own: &[(i64, usize)], lo: i64, hi: i64) -> IntervalSet {
        self.effects_valid(own, true, lo, hi)
    }

    fn effects_valid(
        &self,
        own: &[(i64, usize)],
        only_start: bool,
        lo: i64,
        hi: i64,
    ) -> IntervalSet {
        let mut bad = Vec::new();
        let mut all: Vec<i64> = self.effects.iter().map(|e| e.time).collect();
        all.dedup();
        // Effects at `s + offset` with `s >= lo` cannot reach a requirement that ends
        // by then.
        let earliest = own
            .iter()
            .map(|e| e.0)
            .min()
            .map_or(lo, |o| lo.saturating_add(o));
        let mut owned: Vec<i64> = Vec::new();
        for &(rs, re, req, owner) in &self.requirements {
            if re <= earliest {
                continue;
            }
            let times: &[i64] = if self.effects.iter().any(|e| e.owner == owner) {
                owned.clear();
                owned.extend(
                    self.effects
                        .iter()
                        .filter(|e| e.owner != owner)
                        .map(|e| e.time),
                );
                owned.dedup();
                &owned
            } else {
                &all
            };
            for (k, &(offset, value)) in own.iter().enumerate() {
                let next_own = own.get(k + 1).map(|e| e.0);
                if req == value || (only_start && offset != 0) {
                    continue;
                }
                // The effect at tau = s + offset holds on [tau, next) where next is the
                // first placed effect after tau (or our own next effect). A requirement
                // [rs, re) is hit iff rs < next and re > tau.
                let first = times.partition_point(|&e| e <= rs);
                let mut j = first;
                loop {
                    let seg_lo = if j == 0 { i64::MIN } else { times[j - 1] };
                    let seg_hi = times.get(j).copied().unwrap_or(i64::MAX);
                    if seg_lo >= re {
                        break;
                    }
                    // tau in [seg_lo, seg_hi) and tau < re, i.e. tau <= min(seg_hi, re) - 1.
                    let tau_lo = seg_lo;
                    let tau_hi = seg_hi.min(re).saturating_sub(1);
                    let mut s_lo = tau_lo.saturating_sub(offset);
                    let s_hi = tau_hi.saturating_sub(offset);
                    if let Some(n) = next_own {
                        // Our next effect cuts the span: need rs < s + n.
                        s_lo = s_lo.max(rs.saturating_sub(n).saturating_add(1));
                    }
                    bad.push(Interval::new(s_lo, s_hi));
                    if j >= times.len() {
                        break;
                    }
                    j += 1;
                }
            }
        }
        IntervalSet::single(lo, hi).subtract(&IntervalSet::from_intervals(bad))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(v: &[(i64, i64)]) -> IntervalSet {
        v.iter().map(|&(a, b)| Interval::new(a, b)).collect()
    }

    /// The sorted unit timeline against the scan of every interval.
    #[test]
    fn unit_timeline_matches_every_interval() {
        let mut next = crate::timeline::xorshift(0x9e37_79b9_7f4a_7c15);
        for _ in 0..200 {
            let mut unit = UnitTimeline::default();
            let mut all = Vec::new();
            for _ in 0..next(8) {
                // Any order, any length, overlaps allowed (held placements).
                let a = next(200);
                let long = next(4) == 0;
                let b = a + 1 + next(if long { 120 } else { 15 });
                unit.add(a, b);
                all.push((a, b));
            }
            for _ in 0..20 {
                let (d, lo) = (1 + next(30), next(220) - 10);
                let hi = lo + next(60);
                assert_eq!(
                    unit.valid(d, lo, hi),
                    atomic_valid(all.iter().copied(), d, lo, hi)
                );
                let to = lo + 1 + next(40);
                let want = all.iter().any(|&(a, b)| a < to && lo < b);
                assert_eq!(unit.overlaps(lo, to), want, "{all:?} {lo}..{to}");
            }
        }
    }

    /// Brute-force overlap test for the atomic timeline.
    #[test]
    fn atomic_matches_brute_force() {
        let busy = [(10, 20), (25, 26), (40, 60)];
        for d in 1..8 {
            let v = atomic_valid(busy, d, 0, 80);
            for s in 0..=80 {
                let ok = busy.iter().all(|&(a, b)| s + d <= a || s >= b);
                assert_eq!(v.contains(s), ok, "d={d} s={s}");
            }
        }
    }

    #[test]
    fn claimable_limits_usage() {
        let mut usage = StepFn::constant(0, 100, 0);
        usage.add(10, 20, 2);
        usage.add(15, 30, 1);
        // Limit 2: forbidden where usage 3 ([15, 20)).
        assert_eq!(
            claimable_valid(&usage, 2, 5, 0, 95),
            set(&[(0, 10), (20, 95)])
        );
        assert_eq!(
            claimable_valid(&usage, 0, 1, 0, 99),
            set(&[(0, 9), (30, 99)])
        );
        assert_eq!(claimable_valid(&usage, 3, 50, 0, 99), set(&[(0, 99)]));
    }

    #[test]
    fn cumulative_bounds_overlap() {
        // 10 already produced, max 40, rate 5: at most 6 s inside [100, 200).
        let v = cumulative_valid(10, 40, 5, 20, (100, 200), (0, 300));
        for s in 0..=300 {
            let overlap = ((s + 20).min(200) - s.max(100)).max(0);
            assert_eq!(v.contains(s), 10 + 5 * overlap <= 40, "s={s}");
        }
        assert!(cumulative_valid(50, 40, 5, 20, (100, 200), (0, 300)).is_empty());
        assert_eq!(
            cumulative_valid(0, 40, -5, 20, (100, 200), (0, 300)),
            set(&[(0, 300)])
        );
    }

    #[test]
    fn state_requirement_and_effects() {
        let mut st = StateTimeline::new(0);
        st.add_effect(100, 1, 1, 7);
        st.add_effect(200, 2, 0, 8);
        st.add_effect(200, 3, 1, 9); // same time, later step wins
        assert_eq!(st.value_at(150), 1);
        assert_eq!(st.value_at(250), 1);
        assert_eq!(st.requirement_valid(0, 10, 0, 500), set(&[(0, 90)]));
        assert_eq!(st.requirement_valid(1, 10, 0, 500), set(&[(100, 500)]));
        st.add_requirement(120, 140, 1, 5);
        // Setting 0 at s must not hit [120, 140): s >= 140, or s < 100 (the effect at
        // 100 takes over before the requirement).
        assert_eq!(
            st.effect_valid(&[(0, 0)], 0, 300),
            set(&[(0, 99), (140, 300)])
        );
        // With our own end effect restoring 1 after 10 s: also fine when s + 10 <= 120.
        assert_eq!(
            st.effect_valid(&[(0, 0), (10, 1)], 0, 300),
            set(&[(0, 110), (140, 300)])
        );
        // Setting 0 at the start and 0 again at the end 10 s later: the end effect
        // holds from s + 10 until the next effect, so every start in [90, 139]
        // breaks the requirement, and more than the start effect alone refuses.
        let both = st.effect_valid(&[(0, 0), (10, 0)], 0, 300);
        assert_eq!(both, set(&[(0, 89), (140, 300)]));
        // Leaving out the end effect checks the start effect alone, cut at s + 10:
        // the relaxation keeps what the full check refuses only for the end effect.
        let start = st.start_effects_valid(&[(0, 0), (10, 0)], 0, 300);
        assert_eq!(start, set(&[(0, 110), (140, 300)]));
        assert!(both.subtract(&start).is_empty());
    }

    #[test]
    fn a_requirement_ignores_its_owners_effects() {
        // Activity 1 requires "b" over [130, 160) and itself sets "a" at 130 (exempt).
        let mut st = StateTimeline::new(1);
        st.add_requirement(130, 160, 1, 1);
        st.add_effect(130, 1, 0, 1);
        // Setting "a" at 30 would hold until the next effect of another activity
        // (none): it reaches activity 1's requirement, so it is refused.
        assert!(!st.effect_valid(&[(30, 0)], 0, 0).contains(0));
        assert!(st.effect_valid(&[(0, 0), (10, 1)], 0, 0).contains(0));
    }
}
