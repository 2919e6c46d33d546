//! The lowest state of charge after each placing step of the run, from each of
//! a few times on: for the replay's witnesses, "the first step after `k` at
//! which the lowest level from time `t` on falls below `x`" without looking at
//! the witness again (a min tree per time over the placing steps).
//!
//! A witness draining `E` in all from time `lo` on lowers no level by more than
//! `E`, and none before `lo` (a capped integrator moves by at most the charge
//! changed, and only after the change). So it still passes the state-of-charge
//! minimum after step `j` when every level after step `j` is at or above the
//! minimum and every level from `lo` on at or above the minimum plus `E`; and
//! the handover minimum when the level at the handover time is at or above it
//! plus `E`. The times are a grid over the horizon: a witness looks up the
//! last grid time at or before its `lo` (a lower level from earlier on only
//! makes the rule stricter).

use crate::scheduler::State;

/// At most this many tree entries in all (the grid gets coarser on runs with
/// many placing steps): bounded memory whatever the plan.
const MAX_ENTRIES: usize = 1 << 20;

/// About the spacing of the grid times (seconds): see [`Floors::grid`].
const GRID_SECONDS: i64 = 3 * 3600;

/// See the module docs.
pub(super) struct Floors {
    h0: i64,
    /// Grid spacing (seconds).
    width: i64,
    /// The placing steps, ascending.
    steps: Vec<usize>,
    /// Leaves per tree (a power of two, at least `steps.len()`).
    cap: usize,
    /// Per grid time, a min tree over the placing steps of the lowest level
    /// from that time on (index 0: the lowest level of all).
    trees: Vec<Vec<i128>>,
    /// The grid times, and the lowest levels from them on after the step
    /// being recorded.
    times: Vec<i64>,
    lowest: Vec<i128>,
    /// The same for the level at the handover time, when there is one.
    handover: Option<Vec<i128>>,
}

impl Floors {
    /// An empty table (before the run is replayed).
    pub(super) fn empty() -> Self {
        Self {
            h0: 0,
            width: 1,
            steps: Vec::new(),
            cap: 1,
            trees: Vec::new(),
            times: Vec::new(),
            lowest: Vec::new(),
            handover: None,
        }
    }

    /// The grid for a run with `placing` placing steps.
    pub(super) fn grid(state: &State<'_>, placing: usize) -> Self {
        let problem = state.problem;
        let cap = placing.max(1).next_power_of_two();
        // A grid time every three hours or so: each step's record is a pass
        // over the levels and the grid, so a finer grid than the plan's
        // placements are apart costs more in records than it saves witnesses.
        let span = (problem.h1 - problem.h0).max(1);
        let every = usize::try_from((span + GRID_SECONDS - 1) / GRID_SECONDS).unwrap_or(usize::MAX);
        let times = (MAX_ENTRIES / (2 * cap)).min(every).clamp(16, 256);
        let width = (span + times as i64 - 1) / times as i64;
        Self {
            h0: problem.h0,
            width: width.max(1),
            steps: Vec::with_capacity(placing),
            cap,
            trees: vec![vec![i128::MAX; 2 * cap]; times],
            times: (0..times as i64)
                .map(|g| problem.h0 + g * width.max(1))
                .collect(),
            lowest: Vec::with_capacity(times),
            handover: problem.handover_time.map(|_| vec![i128::MAX; 2 * cap]),
        }
    }

    /// Records the levels after placing step `j` (in increasing order).
    pub(super) fn record(&mut self, state: &State<'_>, j: usize) {
        let r = self.steps.len();
        if r >= self.cap {
            return; // not expected: `grid` was told the count
        }
        self.steps.push(j);
        let soc = &state.soc;
        soc.lowest_from_each(&self.times, &mut self.lowest);
        for (tree, &lowest) in self.trees.iter_mut().zip(&self.lowest) {
            tree[self.cap + r] = lowest;
        }
        if let (Some(tree), Some(t)) = (self.handover.as_mut(), state.problem.handover_time) {
            tree[self.cap + r] = soc.level_at(t);
        }
    }

    /// Builds the trees once every placing step is recorded.
    pub(super) fn finish(&mut self) {
        for tree in self.trees.iter_mut().chain(self.handover.as_mut()) {
            for p in (1..self.cap).rev() {
                tree[p] = tree[2 * p].min(tree[2 * p + 1]);
            }
        }
    }

    /// The first placing step after `k` after which the lowest level of all is
    /// below `floor`, or the lowest level from the grid time at or before `lo`
    /// is below `floor + energy`, or (`handover`: its minimum) the level at the
    /// handover time below that minimum plus `energy` (`None`: no such step).
    pub(super) fn first_below(
        &self,
        k: usize,
        lo: i64,
        floor: i128,
        energy: i128,
        handover: Option<i128>,
    ) -> Option<usize> {
        if self.trees.is_empty() {
            return None;
        }
        let from = self.steps.partition_point(|&j| j <= k);
        let g = usize::try_from((lo - self.h0).max(0) / self.width)
            .unwrap_or(usize::MAX)
            .min(self.trees.len() - 1);
        let mut first = self.first_under(&self.trees[0], from, floor);
        first = first.min(self.first_under(&self.trees[g], from, floor.saturating_add(energy)));
        if let (Some(tree), Some(min)) = (&self.handover, handover) {
            first = first.min(self.first_under(tree, from, min.saturating_add(energy)));
        }
        self.steps.get(first).copied()
    }

    /// The first placing step after `k` after which some level is below
    /// `floor` (`usize::MAX`: none).
    pub(super) fn first_unsure(&self, k: usize, floor: i128) -> usize {
        let Some(all) = self.trees.first() else {
            return usize::MAX;
        };
        let from = self.steps.partition_point(|&j| j <= k);
        let first = self.first_under(all, from, floor);
        self.steps.get(first).copied().unwrap_or(usize::MAX)
    }

    /// The first leaf at or after `from` below `x` (`usize::MAX`: none).
    fn first_under(&self, tree: &[i128], from: usize, x: i128) -> usize {
        fn go(
            tree: &[i128],
            node: usize,
            lo: usize,
            hi: usize,
            from: usize,
            x: i128,
        ) -> Option<usize> {
            if hi <= from || tree[node] >= x {
                return None;
            }
            if hi - lo == 1 {
                return Some(lo);
            }
            let mid = (lo + hi) / 2;
            go(tree, 2 * node, lo, mid, from, x)
                .or_else(|| go(tree, 2 * node + 1, mid, hi, from, x))
        }
        go(tree, 1, 0, self.cap, from, x).unwrap_or(usize::MAX)
    }
}
