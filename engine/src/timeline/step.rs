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

    /// Makes `t` a breakpoint (no-op outside the open domain) and returns its index.
    fn split(&mut self, t: i64) -> usize {
        let i = self.index(t);
        if self.points[i].0 == t || t <= self.start || t >= self.end {
            return if t >= self.end { self.points.len() } else { i };
        }
        let v = self.points[i].1;
        self.points.insert(i + 1, (t, v));
        i + 1
    }

    /// Adds `delta` on `[a, b)` (clipped to the domain).
    pub fn add(&mut self, a: i64, b: i64, delta: i64) {
        let (a, b) = (a.max(self.start), b.min(self.end));
        if a >= b || delta == 0 {
            return;
        }
        let i = self.split(a);
        let j = self.split(b);
        for p in &mut self.points[i..j] {
            p.1 = p.1.saturating_add(delta);
        }
        self.coalesce(i.saturating_sub(1), (j + 1).min(self.points.len()));
    }

    /// Merges equal neighbours among `points[from..to]`.
    fn coalesce(&mut self, from: usize, to: usize) {
        let mut k = to.min(self.points.len()).saturating_sub(1);
        while k > from {
            if self.points[k].1 == self.points[k - 1].1 {
                self.points.remove(k);
            }
            k -= 1;
        }
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
