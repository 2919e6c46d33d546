//! Piecewise-constant functions of time: the storage behind claimable timelines
//! (sequence engines, peak power, heater draw) and the rate of cumulative-rate ones.

/// A piecewise-constant integer function on `[start, end)`.
///
/// `points[i] = (t, v)` means the value is `v` on `[t, points[i + 1].0)` (the last
/// segment runs to `end`). `points[0].0 == start` always.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StepFn {
    start: i64,
    end: i64,
    points: Vec<(i64, i64)>,
}

impl StepFn {
    /// The constant function `value` on `[start, end)`.
    pub fn constant(start: i64, end: i64, value: i64) -> Self {
        Self {
            start,
            end,
            points: vec![(start, value)],
        }
    }

    /// Domain start.
    pub fn start(&self) -> i64 {
        self.start
    }

    /// Domain end.
    pub fn end(&self) -> i64 {
        self.end
    }

    /// The breakpoints `(t, value from t)`.
    pub fn points(&self) -> &[(i64, i64)] {
        &self.points
    }

    /// Index of the segment containing `t` (clamped to the domain).
    fn index(&self, t: i64) -> usize {
        self.points.partition_point(|p| p.0 <= t).saturating_sub(1)
    }

    /// The value at `t` (clamped to the domain).
    pub fn value_at(&self, t: i64) -> i64 {
        self.points[self.index(t)].1
    }

    /// Adds `delta` on `[a, b)` (clipped to the domain).
    ///
    /// The points from the one before `a`'s segment to the one at `b` are
    /// rewritten in one splice (breakpoints at `a` and `b` added, equal
    /// neighbours merged): one move of the points after them, where inserting
    /// and removing one at a time moved them up to four times (a placement on
    /// a long plan's rate timeline moves every later breakpoint).
    pub fn add(&mut self, a: i64, b: i64, delta: i64) {
        let (a, b) = (a.max(self.start), b.min(self.end));
        if a >= b || delta == 0 {
            return;
        }
        let pts = &self.points;
        // `a`'s segment, and the first point at or after `b`.
        let lo = self.index(a);
        let hi = pts.partition_point(|p| p.0 < b);
        let from = lo.saturating_sub(1);
        // The new points, on the stack when few (most changes span a few
        // segments): no allocation per change.
        let mut new = Rewritten::with_capacity(hi - from + 3);
        let mut push = |p: (i64, i64)| {
            if new.last().is_none_or(|q| q.1 != p.1) {
                new.push(p);
            }
        };
        if from < lo {
            push(pts[from]);
        }
        if pts[lo].0 < a {
            push(pts[lo]);
        }
        push((a, pts[lo].1.saturating_add(delta)));
        for &(t, v) in &pts[lo + 1..hi] {
            push((t, v.saturating_add(delta)));
        }
        // From `b` on, the value is as it was (`b < end`, so a point is there
        // or one is added with the value of the segment it splits).
        let to = if pts.get(hi).is_some_and(|p| p.0 == b) {
            push(pts[hi]);
            hi + 1
        } else {
            if b < self.end {
                push((b, pts[hi - 1].1));
            }
            hi
        };
        replace(&mut self.points, from..to, new.as_slice());
    }

    /// The segments overlapping `[a, b)`, clipped: `(lo, hi, value)`.
    pub fn segments(&self, a: i64, b: i64) -> impl Iterator<Item = (i64, i64, i64)> + '_ {
        let (a, b) = (a.max(self.start), b.min(self.end));
        let first = self.index(a);
        let end = self.end;
        self.points[first..]
            .iter()
            .enumerate()
            .map(move |(k, &(t, v))| {
                let next = self.points.get(first + k + 1).map_or(end, |p| p.0);
                (t.max(a), next.min(b), v)
            })
            .take_while(move |&(lo, _, _)| lo < b)
            .filter(|&(lo, hi, _)| lo < hi)
    }

    /// The largest value on `[a, b)` and the first time it occurs, if non-empty.
    pub fn max_on(&self, a: i64, b: i64) -> Option<(i64, i64)> {
        let mut best: Option<(i64, i64)> = None;
        for (lo, _, v) in self.segments(a, b) {
            if best.is_none_or(|(bv, _)| v > bv) {
                best = Some((v, lo));
            }
        }
        best
    }
}

/// `points[range]` replaced by `new`: the points after the range moved once,
/// by the difference in length (`Vec::splice` does the same through a
/// general iterator protocol that costs more than the move on short lists).
fn replace(points: &mut Vec<(i64, i64)>, range: std::ops::Range<usize>, new: &[(i64, i64)]) {
    let (from, to) = (range.start, range.end);
    let len = points.len();
    if new.len() >= to - from {
        let grow = new.len() - (to - from);
        points.resize(len + grow, (0, 0));
        points.copy_within(to..len, to + grow);
    } else {
        points.drain(from + new.len()..to);
    }
    points[from..from + new.len()].copy_from_slice(new);
}

/// The points a change to a [`StepFn`] rewrites: on the stack up to
/// [`Rewritten::INLINE`] of them, on the heap beyond.
struct Rewritten {
    inline: [(i64, i64); Rewritten::INLINE],
    len: usize,
    /// Used instead when more may come (empty otherwise: no allocation).
    heap: Vec<(i64, i64)>,
}

impl Rewritten {
    const INLINE: usize = 16;

    /// Room for at most `n` points.
    fn with_capacity(n: usize) -> Self {
        Self {
            inline: [(0, 0); Self::INLINE],
            len: 0,
            heap: if n > Self::INLINE {
                Vec::with_capacity(n)
            } else {
                Vec::new()
            },
        }
    }

    fn push(&mut self, p: (i64, i64)) {
        if self.heap.capacity() > 0 {
            self.heap.push(p);
        } else {
            self.inline[self.len] = p;
            self.len += 1;
        }
    }

    fn as_slice(&self) -> &[(i64, i64)] {
        if self.heap.capacity() > 0 {
            &self.heap
        } else {
            &self.inline[..self.len]
        }
    }

    fn last(&self) -> Option<&(i64, i64)> {
        self.as_slice().last()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn add_splits_and_coalesces() {
        let mut f = StepFn::constant(0, 100, 5);
        f.add(10, 20, 3);
        assert_eq!(f.points(), &[(0, 5), (10, 8), (20, 5)]);
        f.add(20, 30, 3);
        assert_eq!(f.points(), &[(0, 5), (10, 8), (30, 5)]);
        f.add(10, 30, -3);
        assert_eq!(f.points(), &[(0, 5)]);
        f.add(-50, 1000, 1);
        assert_eq!(f.points(), &[(0, 6)]);
        f.add(90, 200, 1);
        assert_eq!(f.points(), &[(0, 6), (90, 7)]);
        assert_eq!(f.value_at(89), 6);
        assert_eq!(f.value_at(90), 7);
    }

    proptest::proptest! {
        /// Random additions agree with a per-second model, and the points stay
        /// sorted, start at the domain start and never repeat a value.
        #[test]
        fn add_matches_a_per_second_model(
            start in -5i64..5,
            len in 1i64..40,
            adds in proptest::collection::vec((-10i64..50, 0i64..30, -3i64..4), 0..30),
        ) {
            let end = start + len;
            let mut f = StepFn::constant(start, end, 1);
            let mut model = vec![1i64; len as usize];
            for (a, w, delta) in adds {
                f.add(a, a + w, delta);
                for t in a.max(start)..(a + w).min(end) {
                    model[(t - start) as usize] += delta;
                }
                let pts = f.points();
                proptest::prop_assert_eq!(pts[0].0, start);
                for p in pts.windows(2) {
                    proptest::prop_assert!(p[0].0 < p[1].0 && p[0].1 != p[1].1, "{:?}", pts);
                }
                proptest::prop_assert!(pts.last().is_some_and(|p| p.0 < end));
                for t in start..end {
                    proptest::prop_assert_eq!(f.value_at(t), model[(t - start) as usize]);
                }
            }
        }
    }

    #[test]
    fn replace_grows_shrinks_and_keeps_the_rest() {
        let pts = |n: i64| (0..n).map(|i| (i, i)).collect::<Vec<_>>();
        for (range, new) in [
            (1..2, vec![(9, 9), (8, 8), (7, 7)]),
            (1..4, vec![(9, 9)]),
            (0..5, vec![]),
            (2..2, vec![(9, 9)]),
            (5..5, vec![(9, 9)]),
            (1..3, vec![(9, 9), (8, 8)]),
        ] {
            let mut got = pts(5);
            replace(&mut got, range.clone(), &new);
            let mut want = pts(5);
            want.splice(range, new);
            assert_eq!(got, want);
        }
    }

    #[test]
    fn segments_and_max() {
        let mut f = StepFn::constant(0, 100, 0);
        f.add(10, 20, 4);
        f.add(15, 40, 1);
        let segs: Vec<_> = f.segments(12, 30).collect();
        assert_eq!(segs, vec![(12, 15, 4), (15, 20, 5), (20, 30, 1)]);
        assert_eq!(f.max_on(0, 100), Some((5, 15)));
        assert_eq!(f.max_on(20, 100), Some((1, 20)));
        assert_eq!(f.max_on(50, 50), None);
    }
}
