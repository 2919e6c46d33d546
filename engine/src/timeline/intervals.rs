//! Sorted disjoint integer interval sets: the currency of valid start times.

use serde::Serialize;

/// A closed integer interval `[lo, hi]` (both inclusive; empty when `lo > hi`).
///
/// Start-time sets are closed because window ends are inclusive; occupancy of an
/// activity is half-open `[start, end)` and is never stored as an `Interval`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
pub struct Interval {
    /// First member.
    pub lo: i64,
    /// Last member.
    pub hi: i64,
}

impl Interval {
    /// `[lo, hi]`.
    pub const fn new(lo: i64, hi: i64) -> Self {
        Self { lo, hi }
    }

    /// Whether it has no member.
    pub fn is_empty(&self) -> bool {
        self.lo > self.hi
    }

    /// Whether `t` is a member.
    pub fn contains(&self, t: i64) -> bool {
        self.lo <= t && t <= self.hi
    }

    /// Number of members.
    pub fn len(&self) -> i64 {
        if self.is_empty() {
            0
        } else {
            self.hi.saturating_sub(self.lo).saturating_add(1)
        }
    }

    /// Common members.
    pub fn intersect(&self, other: &Interval) -> Interval {
        Interval::new(self.lo.max(other.lo), self.hi.min(other.hi))
    }

    /// The member nearest `t` (ties cannot occur for one interval). `None` when empty.
    pub fn nearest(&self, t: i64) -> Option<i64> {
        (!self.is_empty()).then(|| t.clamp(self.lo, self.hi))
    }
}

/// A set of integers as sorted, disjoint, non-adjacent closed intervals.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash, Serialize)]
#[serde(transparent)]
pub struct IntervalSet {
    items: Vec<Interval>,
}

impl IntervalSet {
    /// The empty set.
    pub fn empty() -> Self {
        Self { items: Vec::new() }
    }

    /// One interval (empty set if the interval is empty).
    pub fn single(lo: i64, hi: i64) -> Self {
        let mut s = Self::empty();
        if lo <= hi {
            s.items.push(Interval::new(lo, hi));
        }
        s
    }

    /// The union of arbitrary (possibly overlapping, unsorted) intervals.
    pub fn from_intervals(mut items: Vec<Interval>) -> Self {
        items.retain(|i| !i.is_empty());
        items.sort_unstable();
        let mut out: Vec<Interval> = Vec::with_capacity(items.len());
        for i in items {
            match out.last_mut() {
                Some(last) if i.lo <= last.hi.saturating_add(1) => last.hi = last.hi.max(i.hi),
                _ => out.push(i),
            }
        }
        Self { items: out }
    }

    /// The intervals, sorted.
    pub fn intervals(&self) -> &[Interval] {
        &self.items
    }

    /// Whether the set has no member.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Whether `t` is a member.
    pub fn contains(&self, t: i64) -> bool {
        let idx = self.items.partition_point(|i| i.hi < t);
        self.items.get(idx).is_some_and(|i| i.lo <= t)
    }

    /// Number of members.
    pub fn count(&self) -> i64 {
        self.items
            .iter()
            .map(Interval::len)
            .fold(0, i64::saturating_add)
    }

    /// Smallest member.
    pub fn first(&self) -> Option<i64> {
        self.items.first().map(|i| i.lo)
    }

    /// Largest member.
    pub fn last(&self) -> Option<i64> {
        self.items.last().map(|i| i.hi)
    }

    /// Members of both sets.
    pub fn intersect(&self, other: &IntervalSet) -> IntervalSet {
        // One interval (a span, a window's range): a slice of the other set.
        if let [only] = other.items[..] {
            return self.clip(only.lo, only.hi);
        }
        if let [only] = self.items[..] {
            return other.clip(only.lo, only.hi);
        }
        let (a, b) = (&self.items, &other.items);
        let (mut i, mut j) = (0, 0);
        let mut out = Vec::with_capacity(a.len().max(b.len()));
        while i < a.len() && j < b.len() {
            let x = a[i].intersect(&b[j]);
            if !x.is_empty() {
                out.push(x);
            }
            if a[i].hi < b[j].hi {
                i += 1;
            } else {
                j += 1;
            }
        }
        IntervalSet { items: out }
    }

    /// Members of this set within `[lo, hi]`: the intervals that reach into it,
    /// found by binary search, with the two ends cut.
    pub fn clip(&self, lo: i64, hi: i64) -> IntervalSet {
        if lo > hi {
            return IntervalSet::empty();
        }
        let i = self.items.partition_point(|iv| iv.hi < lo);
        let j = self.items.partition_point(|iv| iv.lo <= hi);
        let mut items = self.items[i..j.max(i)].to_vec();
        if let Some(first) = items.first_mut() {
            first.lo = first.lo.max(lo);
        }
        if let Some(last) = items.last_mut() {
            last.hi = last.hi.min(hi);
        }
        IntervalSet { items }
    }

    /// Members of either set: the two sorted lists merged in one pass.
    pub fn union(&self, other: &IntervalSet) -> IntervalSet {
        if other.items.is_empty() {
            return self.clone();
        }
        if self.items.is_empty() {
            return other.clone();
        }
        let (a, b) = (&self.items, &other.items);
        let mut out: Vec<Interval> = Vec::with_capacity(a.len() + b.len());
        let (mut i, mut j) = (0, 0);
        while i < a.len() || j < b.len() {
            let next = match (a.get(i), b.get(j)) {
                (Some(x), Some(y)) if x.lo <= y.lo => {
                    i += 1;
                    *x
                }
                (_, Some(y)) => {
                    j += 1;
                    *y
                }
                (Some(x), None) => {
                    i += 1;
                    *x
                }
                (None, None) => break,
            };
            match out.last_mut() {
                Some(last) if next.lo <= last.hi.saturating_add(1) => {
                    last.hi = last.hi.max(next.hi);
                }
                _ => out.push(next),
            }
        }
        IntervalSet { items: out }
    }

    /// Members of this set not in `other`.
    pub fn subtract(&self, other: &IntervalSet) -> IntervalSet {
        let mut out = Vec::new();
        let mut j = 0;
        for &iv in &self.items {
            let mut lo = iv.lo;
            while j < other.items.len() && other.items[j].hi < lo {
                j += 1;
            }
            let mut k = j;
            while lo <= iv.hi {
                match other.items.get(k) {
                    Some(o) if o.lo <= iv.hi => {
                        if o.lo > lo {
                            out.push(Interval::new(lo, o.lo - 1));
                        }
                        lo = o.hi.saturating_add(1);
                        k += 1;
                    }
                    _ => {
                        out.push(Interval::new(lo, iv.hi));
                        break;
                    }
                }
            }
        }
        IntervalSet { items: out }
    }

    /// The member nearest `t`, ties to the smaller.
    pub fn nearest(&self, t: i64) -> Option<i64> {
        let idx = self.items.partition_point(|i| i.hi < t);
        let right = self.items.get(idx).map(|i| i.lo.max(t));
        let left = idx
            .checked_sub(1)
            .and_then(|k| self.items.get(k))
            .map(|i| i.hi);
        match (left, right) {
            (Some(l), Some(r)) => Some(if t - l <= r - t { l } else { r }),
            (l, r) => l.or(r),
        }
    }
}

impl FromIterator<Interval> for IntervalSet {
    fn from_iter<T: IntoIterator<Item = Interval>>(iter: T) -> Self {
        IntervalSet::from_intervals(iter.into_iter().collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(v: &[(i64, i64)]) -> IntervalSet {
        v.iter().map(|&(a, b)| Interval::new(a, b)).collect()
    }

    #[test]
    fn union_merges_adjacent_and_overlapping() {
        assert_eq!(
            set(&[(5, 7), (0, 2), (3, 4), (10, 12), (11, 20)]),
            set(&[(0, 7), (10, 20)])
        );
        assert_eq!(set(&[(0, 2), (4, 5)]).intervals().len(), 2);
        assert!(set(&[(3, 2)]).is_empty());
    }

    #[test]
    fn set_operations_match_membership() {
        let mut next = crate::timeline::xorshift(0x2545_f491_4f6c_dd1d);
        let random = |next: &mut dyn FnMut(i64) -> i64| -> IntervalSet {
            (0..next(6))
                .map(|_| {
                    let lo = next(60) - 5;
                    Interval::new(lo, lo + next(12) - 1)
                })
                .collect()
        };
        for _ in 0..2000 {
            let (a, b) = (random(&mut next), random(&mut next));
            let (lo, hi) = (next(70) - 8, next(70) - 8);
            let (i, u, c) = (a.intersect(&b), a.union(&b), a.clip(lo, hi));
            for t in -12..72 {
                assert_eq!(
                    i.contains(t),
                    a.contains(t) && b.contains(t),
                    "{a:?} & {b:?}"
                );
                assert_eq!(
                    u.contains(t),
                    a.contains(t) || b.contains(t),
                    "{a:?} | {b:?}"
                );
                let inside = lo <= t && t <= hi;
                assert_eq!(
                    c.contains(t),
                    a.contains(t) && inside,
                    "{a:?} clip {lo}..{hi}"
                );
            }
            // Results are in normal form: sorted, disjoint, not adjacent, none empty.
            for s in [&i, &u, &c] {
                assert_eq!(*s, s.intervals().iter().copied().collect::<IntervalSet>());
            }
        }
    }

    #[test]
    fn intersect_subtract_and_nearest() {
        let a = set(&[(0, 10), (20, 30)]);
        let b = set(&[(5, 25)]);
        assert_eq!(a.intersect(&b), set(&[(5, 10), (20, 25)]));
        assert_eq!(a.subtract(&b), set(&[(0, 4), (26, 30)]));
        assert_eq!(
            a.subtract(&set(&[(-5, 0), (3, 3), (30, 40)])),
            set(&[(1, 2), (4, 10), (20, 29)])
        );
        assert_eq!(a.nearest(15), Some(10));
        assert_eq!(a.nearest(16), Some(20));
        assert_eq!(a.nearest(-3), Some(0));
        assert_eq!(a.nearest(99), Some(30));
        assert_eq!(a.nearest(22), Some(22));
        assert_eq!(IntervalSet::empty().nearest(1), None);
        assert_eq!(a.count(), 22);
        assert!(a.contains(20) && !a.contains(15));
    }
}
