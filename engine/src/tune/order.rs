//! Orders of the activities and the priorities that realise them.
//!
//! An order is the list of plan activity indices in step order. The scheduler
//! sorts activities by `(priority, file index)`, so an order is realised by
//! priorities that are non-decreasing along it, strictly increasing wherever an
//! activity has a smaller file index than the one before it
//! ([`Rules::priorities`]).

use crate::model::Plan;

/// What every order considered keeps: the pinned activities' places and the
/// order of every pair linked by a dependency.
#[derive(Clone, Debug)]
pub(crate) struct Rules {
    /// The original step order.
    pub original: Vec<usize>,
    /// Each activity's place in the original step order.
    pub rank: Vec<usize>,
    /// The original priorities, in step order (non-decreasing).
    pub values: Vec<i64>,
    /// Per place: the pinned activity that keeps it.
    pub pinned_at: Vec<Option<usize>>,
    /// Per activity: pinned?
    pub pinned: Vec<bool>,
    /// Per activity: the activities that must come before it (the earlier one,
    /// in the original order, of each dependency pair it is in).
    pub before: Vec<Vec<usize>>,
    /// Per activity: the activities that must come after it.
    pub after: Vec<Vec<usize>>,
    /// File index of each activity (the scheduler's tie-break).
    n: usize,
}

impl Rules {
    /// The rules of `plan` with the activities `pinned` (plan indices).
    pub fn new(plan: &Plan, pinned: &[usize]) -> Self {
        let n = plan.activities.len();
        let mut original: Vec<usize> = (0..n).collect();
        original.sort_by_key(|&i| (plan.activities[i].priority, i));
        let mut rank = vec![0; n];
        for (k, &a) in original.iter().enumerate() {
            rank[a] = k;
        }
        let values = original
            .iter()
            .map(|&a| plan.activities[a].priority)
            .collect();
        let mut is_pinned = vec![false; n];
        for &p in pinned {
            is_pinned[p] = true;
        }
        let mut pinned_at = vec![None; n];
        for a in 0..n {
            if is_pinned[a] {
                pinned_at[rank[a]] = Some(a);
            }
        }
        let ids = plan.index_by_id();
        let mut before = vec![Vec::new(); n];
        let mut after = vec![Vec::new(); n];
        for (a, act) in plan.activities.iter().enumerate() {
            for dep in &act.after {
                let Some(&t) = ids.get(dep.activity.as_str()) else {
                    continue;
                };
                // The pair keeps the order the original has it in.
                let (first, second) = if rank[t] < rank[a] { (t, a) } else { (a, t) };
                if !before[second].contains(&first) {
                    before[second].push(first);
                    after[first].push(second);
                }
            }
        }
        for list in before.iter_mut().chain(after.iter_mut()) {
            list.sort_unstable_by_key(|&x| rank[x]);
        }
        Self {
            original,
            rank,
            values,
            pinned_at,
            pinned: is_pinned,
            before,
            after,
            n,
        }
    }

    /// Number of activities.
    pub fn len(&self) -> usize {
        self.n
    }

    /// Whether `order` keeps every pinned place and dependency pair.
    pub fn keeps(&self, order: &[usize]) -> bool {
        if order.len() != self.n {
            return false;
        }
        let mut pos = vec![usize::MAX; self.n];
        for (k, &a) in order.iter().enumerate() {
            if a >= self.n || pos[a] != usize::MAX {
                return false;
            }
            pos[a] = k;
        }
        self.pinned_at
            .iter()
            .enumerate()
            .all(|(k, p)| p.is_none_or(|p| pos[p] == k))
            && (0..self.n).all(|a| self.before[a].iter().all(|&b| pos[b] < pos[a]))
    }

    /// The priorities (by plan index) that realise `order`: the pinned
    /// activities keep theirs; every other place `k` takes the `k`-th smallest
    /// original priority when that sorts it right, else the nearest value that
    /// does (docs/semantics.md, "Priority tuning"). `None` when no integer
    /// priorities realise it with the pinned ones kept.
    pub fn priorities(&self, plan: &Plan, order: &[usize]) -> Option<Vec<i64>> {
        let n = order.len();
        // strict[k]: place k must have a larger priority than place k - 1.
        let strict: Vec<i128> = (0..n)
            .map(|k| i128::from(k > 0 && order[k] < order[k - 1]))
            .collect();
        let fixed = |k: usize| {
            self.pinned[order[k]].then(|| i128::from(plan.activities[order[k]].priority))
        };
        // Lower bounds from the pinned place before, upper from the one after.
        let mut lo = vec![i128::MIN; n];
        let mut last: Option<i128> = None;
        for k in 0..n {
            last = last.map(|v| v + strict[k]);
            if let Some(v) = fixed(k) {
                if last.is_some_and(|l| l > v) {
                    return None;
                }
                last = Some(v);
            }
            lo[k] = last.unwrap_or(i128::MIN);
        }
        let mut hi = vec![i128::MAX; n];
        let mut next: Option<i128> = None;
        for k in (0..n).rev() {
            if let Some(v) = fixed(k) {
                next = Some(v);
            }
            hi[k] = next.unwrap_or(i128::MAX);
            next = next.map(|v| v - strict[k]);
        }
        let mut out = vec![0i64; n];
        let mut prev: Option<i128> = None;
        for k in 0..n {
            let floor = prev.map_or(lo[k], |p| lo[k].max(p + strict[k]));
            if floor > hi[k] {
                return None;
            }
            let v = i128::from(self.values[k]).clamp(floor, hi[k]);
            out[order[k]] = i64::try_from(v).ok()?;
            prev = Some(v);
        }
        Some(out)
    }

    /// Pairs of activities whose relative order in `order` differs from the
    /// original.
    pub fn changes(&self, order: &[usize]) -> u64 {
        // Inversions of the original ranks along `order` (merge count).
        let mut ranks: Vec<usize> = order.iter().map(|&a| self.rank[a]).collect();
        inversions(&mut ranks)
    }

    /// The activities that can move: not pinned, and in some order the rules
    /// allow not at the same place (they are not linked by dependencies, even
    /// through others, to every other activity that is not pinned).
    pub fn movable(&self) -> Vec<usize> {
        let free: Vec<usize> = (0..self.n).filter(|&a| !self.pinned[a]).collect();
        let reach = |a: usize, next: &Vec<Vec<usize>>| {
            let mut seen = vec![false; self.n];
            let mut stack = vec![a];
            while let Some(x) = stack.pop() {
                for &y in &next[x] {
                    if !seen[y] {
                        seen[y] = true;
                        stack.push(y);
                    }
                }
            }
            seen
        };
        free.iter()
            .copied()
            .filter(|&a| {
                let later = reach(a, &self.after);
                let earlier = reach(a, &self.before);
                free.iter().any(|&b| b != a && !later[b] && !earlier[b])
            })
            .collect()
    }

    /// Every order the rules allow, in lexicographic order of the original
    /// ranks (the original first), at most `limit` of them; the flag says
    /// whether there were more.
    pub fn enumerate(&self, limit: usize) -> (Vec<Vec<usize>>, bool) {
        let mut out = Vec::new();
        let mut placed = vec![false; self.n];
        let mut order = Vec::with_capacity(self.n);
        let more = self.extend(&mut order, &mut placed, &mut out, limit);
        (out, more)
    }

    /// Depth-first: returns true when it stopped at the limit.
    fn extend(
        &self,
        order: &mut Vec<usize>,
        placed: &mut [bool],
        out: &mut Vec<Vec<usize>>,
        limit: usize,
    ) -> bool {
        let k = order.len();
        if k == self.n {
            if out.len() >= limit {
                return true;
            }
            out.push(order.clone());
            return false;
        }
        let ready = |a: usize, placed: &[bool]| self.before[a].iter().all(|&b| placed[b]);
        let choices: Vec<usize> = match self.pinned_at[k] {
            Some(p) => vec![p],
            None => self
                .original
                .iter()
                .copied()
                .filter(|&a| !self.pinned[a] && !placed[a])
                .collect(),
        };
        for a in choices {
            if !ready(a, placed) {
                continue;
            }
            order.push(a);
            placed[a] = true;
            let stop = self.extend(order, placed, out, limit);
            placed[a] = false;
            order.pop();
            if stop {
                return true;
            }
        }
        false
    }

    /// `order` with activity `a` moved to just before activity `b`.
    pub fn ahead(order: &[usize], a: usize, b: usize) -> Option<Vec<usize>> {
        let pa = order.iter().position(|&x| x == a)?;
        let pb = order.iter().position(|&x| x == b)?;
        if pb >= pa {
            return None;
        }
        let mut out = order.to_vec();
        let x = out.remove(pa);
        out.insert(pb, x);
        Some(out)
    }

    /// `order` with activity `b` moved to just after activity `a`.
    pub fn behind(order: &[usize], b: usize, a: usize) -> Option<Vec<usize>> {
        let pa = order.iter().position(|&x| x == a)?;
        let pb = order.iter().position(|&x| x == b)?;
        if pb >= pa {
            return None;
        }
        let mut out = order.to_vec();
        let x = out.remove(pb);
        out.insert(pa, x);
        Some(out)
    }
}

/// Number of pairs `i < j` with `v[i] > v[j]` (sorts `v`).
fn inversions(v: &mut [usize]) -> u64 {
    let n = v.len();
    if n < 2 {
        return 0;
    }
    let mid = n / 2;
    let mut count = inversions(&mut v[..mid]) + inversions(&mut v[mid..]);
    let mut merged = Vec::with_capacity(n);
    let (mut i, mut j) = (0, mid);
    while i < mid && j < n {
        if v[i] <= v[j] {
            merged.push(v[i]);
            i += 1;
        } else {
            merged.push(v[j]);
            count += (mid - i) as u64;
            j += 1;
        }
    }
    merged.extend_from_slice(&v[i..mid]);
    merged.extend_from_slice(&v[j..]);
    v.copy_from_slice(&merged);
    count
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan(priorities: &[i64], deps: &[(usize, usize)]) -> Plan {
        let acts: Vec<serde_json::Value> = priorities
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                let after: Vec<serde_json::Value> = deps
                    .iter()
                    .filter(|d| d.0 == i)
                    .map(|d| serde_json::json!({"activity": format!("a{}", d.1)}))
                    .collect();
                serde_json::json!({"id": format!("a{i}"), "priority": p, "duration": 10,
                                   "after": after})
            })
            .collect();
        serde_json::from_value(serde_json::json!({
            "format": "solscope.plan/1",
            "horizon": {"start": 0, "end": 1000},
            "battery": {"capacity": 10.0, "initial": 10.0, "min_soc": 0.0},
            "power": {"rtg": 0.0, "asleep": 0.0, "awake": 0.0},
            "activities": acts
        }))
        .expect("test plan")
    }

    /// The step order the scheduler derives from `priorities`.
    fn realised(priorities: &[i64]) -> Vec<usize> {
        let mut o: Vec<usize> = (0..priorities.len()).collect();
        o.sort_by_key(|&i| (priorities[i], i));
        o
    }

    #[test]
    fn every_order_is_realised_exactly_and_keeps_values_where_it_can() {
        // Ties in the original priorities: file order breaks them.
        let p = plan(&[5, 5, 7, 5], &[]);
        let rules = Rules::new(&p, &[]);
        assert_eq!(rules.original, [0, 1, 3, 2]);
        let (orders, more) = rules.enumerate(1000);
        assert!(!more);
        assert_eq!(orders.len(), 24);
        assert_eq!(orders[0], rules.original);
        for o in &orders {
            let pr = rules.priorities(&p, o).expect("realisable");
            assert_eq!(&realised(&pr), o, "{o:?} -> {pr:?}");
        }
        // A swap of two tied activities against file order renumbers.
        let pr = rules.priorities(&p, &[1, 0, 3, 2]).expect("realisable");
        assert_eq!(pr, [6, 5, 7, 6]);
        // Distinct values: the multiset is reassigned by place.
        let p = plan(&[10, 20, 30], &[]);
        let rules = Rules::new(&p, &[]);
        assert_eq!(rules.priorities(&p, &[2, 0, 1]), Some(vec![20, 30, 10]));
    }

    #[test]
    fn pinned_keep_place_and_value_dependencies_keep_order() {
        let p = plan(&[5, 5, 5, 9], &[(3, 0)]);
        // a1 pinned at place 1 with value 5.
        let rules = Rules::new(&p, &[1]);
        let (orders, _) = rules.enumerate(1000);
        assert!(!orders.is_empty());
        for o in &orders {
            assert_eq!(o[1], 1);
            let a0 = o.iter().position(|&x| x == 0);
            let a3 = o.iter().position(|&x| x == 3);
            assert!(a0 < a3);
            if let Some(pr) = rules.priorities(&p, o) {
                assert_eq!(pr[1], 5);
                assert_eq!(&realised(&pr), o);
            }
        }
        // a2 (file 2) ahead of the pinned a1 (value 5, file 1) needs a value
        // below 5, and a0 (file 0) after it one above.
        let pr = rules.priorities(&p, &[2, 1, 0, 3]).expect("realisable");
        assert_eq!(pr, [6, 5, 4, 9]);
        // Two pinned with equal values cannot have a later file index between.
        let p = plan(&[5, 6, 5], &[]);
        let rules = Rules::new(&p, &[0, 2]);
        assert_eq!(rules.original, [0, 2, 1]);
        assert!(rules.priorities(&p, &[0, 2, 1]).is_some());
        assert_eq!(rules.enumerate(10).0.len(), 1);
    }

    #[test]
    fn changes_count_pairs_out_of_original_order() {
        let p = plan(&[1, 2, 3, 4], &[]);
        let rules = Rules::new(&p, &[]);
        assert_eq!(rules.changes(&[0, 1, 2, 3]), 0);
        assert_eq!(rules.changes(&[3, 0, 1, 2]), 3);
        assert_eq!(rules.changes(&[3, 2, 1, 0]), 6);
    }

    #[test]
    fn movable_leaves_out_what_dependencies_fix() {
        // a0 -> a1 -> a2 chain, a3 free: every one can move relative to a3.
        let p = plan(&[1, 2, 3, 4], &[(1, 0), (2, 1)]);
        assert_eq!(Rules::new(&p, &[]).movable(), [0, 1, 2, 3]);
        // With a3 pinned, the chain is all that is free and fixed by itself.
        assert!(Rules::new(&p, &[3]).movable().is_empty());
    }
}
