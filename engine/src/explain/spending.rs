//! The charge a run's steps change, by step and by the time the change
//! starts at: "the first step after `k` by which the steps changing the rate
//! before time `t` have changed more than `budget`", for the replay's
//! witnesses (a merge-sort tree over the placing steps: O(log² n) a query).

/// One placing step: its index, the time its changes start at, the charge.
#[derive(Clone, Copy, Debug)]
struct Entry {
    step: usize,
    from: i64,
    charge: i128,
}

/// See the module docs.
pub(super) struct Spending {
    /// The placing steps in step order.
    entries: Vec<Entry>,
    /// Level `l`: each block of `2^l` entries (in step order) sorted by `from`,
    /// with the running charge within the block.
    levels: Vec<Vec<(i64, i128)>>,
}

impl Spending {
    /// `steps`: `(step, from, charge)` in increasing step order.
    pub(super) fn new(steps: impl IntoIterator<Item = (usize, i64, i128)>) -> Self {
        let entries: Vec<Entry> = steps
            .into_iter()
            .map(|(step, from, charge)| Entry { step, from, charge })
            .collect();
        let n = entries.len();
        let mut levels = Vec::new();
        let mut width = 1;
        loop {
            let mut level = Vec::with_capacity(n);
            for block in entries.chunks(width) {
                let at = level.len();
                level.extend(block.iter().map(|e| (e.from, e.charge)));
                let block = &mut level[at..];
                block.sort_unstable_by_key(|x| x.0);
                let mut sum = 0i128;
                for x in block.iter_mut() {
                    sum = sum.saturating_add(x.1);
                    x.1 = sum;
                }
            }
            levels.push(level);
            if width >= n {
                break;
            }
            width *= 2;
        }
        Self { entries, levels }
    }

    /// The first step after `k` by which the steps after `k` whose changes start
    /// before `until` have changed more than `budget` in all (`None`: never).
    pub(super) fn first_over(&self, k: usize, until: i64, budget: i128) -> Option<usize> {
        let from = self.entries.partition_point(|e| e.step <= k);
        let top = self.levels.len() - 1;
        let mut left = budget;
        self.find(top, 0, from, until, &mut left)
            .map(|r| self.entries[r].step)
    }

    /// Within block `b` of level `l`: the first entry at or after rank `from`
    /// that takes the running charge over `left`, else `None` with `left`
    /// reduced by the block's charge.
    fn find(&self, l: usize, b: usize, from: usize, until: i64, left: &mut i128) -> Option<usize> {
        let n = self.entries.len();
        let (lo, hi) = ((b << l).min(n), ((b + 1) << l).min(n));
        if hi <= from || lo >= hi {
            return None;
        }
        if from <= lo {
            let block = &self.levels[l][lo..hi];
            let below = block.partition_point(|x| x.0 < until);
            let charge = if below == 0 { 0 } else { block[below - 1].1 };
            if charge <= *left {
                *left -= charge;
                return None;
            }
            if l == 0 {
                return Some(lo);
            }
        }
        if l == 0 {
            return None;
        }
        self.find(l - 1, 2 * b, from, until, left)
            .or_else(|| self.find(l - 1, 2 * b + 1, from, until, left))
    }
}

#[cfg(test)]
mod tests {
    use super::Spending;

    /// The same answer as a scan over every step, on random inputs.
    #[test]
    fn first_over_matches_a_scan() {
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = |m: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % m
        };
        for _ in 0..300 {
            let n = usize::try_from(next(40)).unwrap_or(0);
            let mut step = 0;
            let steps: Vec<(usize, i64, i128)> = (0..n)
                .map(|_| {
                    step += 1 + usize::try_from(next(3)).unwrap_or(0);
                    (step, next(100) as i64, i128::from(next(20)))
                })
                .collect();
            let s = Spending::new(steps.iter().copied());
            for _ in 0..20 {
                let k = usize::try_from(next(step as u64 + 2)).unwrap_or(0);
                let until = next(110) as i64;
                let budget = i128::from(next(60));
                let mut sum = 0;
                let scan = steps.iter().find_map(|&(j, from, c)| {
                    if j > k && from < until {
                        sum += c;
                        (sum > budget).then_some(j)
                    } else {
                        None
                    }
                });
                assert_eq!(
                    s.first_over(k, until, budget),
                    scan,
                    "k {k} until {until} budget {budget}"
                );
            }
        }
    }
}
