//! Range minimum over a fixed sequence, for the levels' chunks.

/// An iterative segment tree answering "first minimum on `[l, r)`" in O(log n).
/// Leaves sit at `cap + i` for a power-of-two `cap`.
#[derive(Clone, Debug, Default)]
pub(super) struct MinTree {
    /// The number of values.
    n: usize,
    /// The leaves' count, a power of two at least `n`.
    cap: usize,
    /// Node `p`'s children are `2p` and `2p + 1`; leaf `i` is at `cap + i`.
    tree: Vec<(i128, usize)>,
}

impl MinTree {
    /// Rebuilds the tree over `values` in place (its storage reused).
    pub(super) fn rebuild(&mut self, values: impl ExactSizeIterator<Item = i128>) {
        let n = values.len();
        let cap = n.next_power_of_two();
        self.tree.clear();
        self.tree.resize(2 * cap, (i128::MAX, usize::MAX));
        for (i, v) in values.enumerate() {
            self.tree[cap + i] = (v, i);
        }
        for i in (1..cap).rev() {
            self.tree[i] = self.tree[2 * i].min(self.tree[2 * i + 1]);
        }
        (self.n, self.cap) = (n, cap);
    }

    /// `(min, first index)` over `[l, r)`; `None` when empty.
    pub(super) fn query(&self, l: usize, r: usize) -> Option<(i128, usize)> {
        let (mut l, mut r) = (l + self.cap, r.min(self.n) + self.cap);
        let mut best: Option<(i128, usize)> = None;
        let mut take = |x: (i128, usize)| {
            if best.is_none_or(|b| x < b) {
                best = Some(x);
            }
        };
        while l < r {
            if l & 1 == 1 {
                take(self.tree[l]);
                l += 1;
            }
            if r & 1 == 1 {
                r -= 1;
                take(self.tree[r]);
            }
            l >>= 1;
            r >>= 1;
        }
        best
    }
}
