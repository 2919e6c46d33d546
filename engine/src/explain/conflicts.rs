//! Minimal conflicts and minimal relaxations from one sweep.
//!
//! Sweep the elementary segments between all interval endpoints of all categories;
//! on each segment the set of categories that block it is a bitmask. A set of
//! categories has an empty intersection exactly when it hits every segment's mask
//! (each start is blocked by one of them): the minimal conflicts are the minimal
//! hitting sets of the distinct masks. A set's removal leaves a start exactly when
//! it contains some segment's mask: the minimal relaxations are the minimal masks,
//! each with a witness start. With 8 categories the hitting sets are found by
//! checking the 255 non-empty subsets against the distinct masks (no rescheduling),
//! instead of the published tool's O(n 2^n) subset search by re-running.

use serde::Serialize;

use crate::scheduler::{Category, CategoryIntervals};

/// A minimal set of categories whose removal leaves a valid start.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Relaxation {
    /// The categories to relax.
    pub categories: Vec<Category>,
    /// A start that only these categories block (nearest the preferred time).
    pub witness: i64,
}

fn bit(c: Category) -> u16 {
    1 << (Category::ALL.iter().position(|x| *x == c).unwrap_or(0))
}

fn cats(mask: u16) -> Vec<Category> {
    Category::ALL
        .iter()
        .copied()
        .filter(|c| mask & bit(*c) != 0)
        .collect()
}

/// Minimal conflicts and relaxations over starts in `[lo, hi]`.
pub fn minimal_conflicts(
    categories: &[CategoryIntervals],
    lo: i64,
    hi: i64,
    preferred: i64,
) -> (Vec<Vec<Category>>, Vec<Relaxation>) {
    let mut points = vec![lo, hi.saturating_add(1)];
    for c in categories {
        for iv in c.valid.intervals() {
            points.push(iv.lo.max(lo));
            points.push(iv.hi.saturating_add(1).min(hi.saturating_add(1)));
        }
    }
    points.sort_unstable();
    points.dedup();
    // Distinct masks with the witness nearest `preferred`.
    let mut masks: Vec<(u16, i64)> = Vec::new();
    for w in points.windows(2) {
        let (a, b) = (w[0], w[1] - 1);
        if a > b || a < lo || a > hi {
            continue;
        }
        let mask = categories
            .iter()
            .filter(|c| !c.valid.contains(a))
            .fold(0u16, |m, c| m | bit(c.category));
        let witness = preferred.clamp(a, b);
        match masks.iter_mut().find(|m| m.0 == mask) {
            Some(m) => {
                if (witness - preferred).abs() < (m.1 - preferred).abs() {
                    m.1 = witness;
                }
            }
            None => masks.push((mask, witness)),
        }
    }
    if masks.iter().any(|m| m.0 == 0) {
        return (Vec::new(), Vec::new());
    }
    let universe = masks.iter().fold(0u16, |u, m| u | m.0);
    let mut subsets: Vec<u16> = (1..=universe).filter(|s| s & !universe == 0).collect();
    subsets.sort_by_key(|s| (s.count_ones(), *s));
    let mut conflicts: Vec<u16> = Vec::new();
    for s in subsets {
        if conflicts.iter().any(|c| c & s == *c) {
            continue; // contains a smaller conflict
        }
        if masks.iter().all(|m| m.0 & s != 0) {
            conflicts.push(s);
        }
    }
    let mut relax: Vec<(u16, i64)> = masks
        .iter()
        .copied()
        .filter(|m| !masks.iter().any(|o| o.0 != m.0 && o.0 & m.0 == o.0))
        .collect();
    relax.sort_by_key(|m| (m.0.count_ones(), m.0));
    (
        conflicts.into_iter().map(cats).collect(),
        relax
            .into_iter()
            .map(|(m, witness)| Relaxation {
                categories: cats(m),
                witness,
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::timeline::{Interval, IntervalSet};

    fn cat(category: Category, v: &[(i64, i64)]) -> CategoryIntervals {
        CategoryIntervals {
            category,
            valid: v
                .iter()
                .map(|&(a, b)| Interval::new(a, b))
                .collect::<IntervalSet>(),
        }
    }

    fn subset(a: usize, b: usize) -> bool {
        a & b == a
    }

    /// Brute force over subsets: a subset conflicts when no start in [lo, hi] is
    /// valid for all its categories.
    fn brute(cs: &[CategoryIntervals], lo: i64, hi: i64) -> Vec<Vec<Category>> {
        let n = cs.len();
        let conflict = |s: usize| {
            (lo..=hi).all(|t| (0..n).any(|i| s >> i & 1 == 1 && !cs[i].valid.contains(t)))
        };
        let mut out: Vec<usize> = Vec::new();
        let mut subsets: Vec<usize> = (1..1usize << n).collect();
        subsets.sort_by_key(|s| s.count_ones());
        for s in subsets {
            if conflict(s) && !out.iter().any(|o| subset(*o, s)) {
                out.push(s);
            }
        }
        let mut v: Vec<Vec<Category>> = out
            .into_iter()
            .map(|s| {
                let mut c: Vec<Category> = (0..n)
                    .filter(|i| s >> i & 1 == 1)
                    .map(|i| cs[i].category)
                    .collect();
                c.sort();
                c
            })
            .collect();
        v.sort();
        v
    }

    #[test]
    fn matches_subset_enumeration() {
        let cs = vec![
            cat(Category::Execution, &[(0, 10)]),
            cat(Category::Dependency, &[(20, 100)]),
            cat(Category::UnitResource, &[(0, 5), (30, 100)]),
            cat(Category::Uhf, &[(6, 100)]),
        ];
        let (mut conflicts, relax) = minimal_conflicts(&cs, 0, 100, 0);
        conflicts.sort();
        assert_eq!(conflicts, brute(&cs, 0, 100));
        // Relaxing execution alone: 30 is the first start all others allow.
        assert!(
            relax
                .iter()
                .any(|r| r.categories == vec![Category::Execution] && r.witness == 30)
        );
        // No conflict when the intersection is non-empty.
        let ok = vec![
            cat(Category::Execution, &[(0, 10)]),
            cat(Category::Uhf, &[(5, 100)]),
        ];
        assert_eq!(minimal_conflicts(&ok, 0, 100, 0), (Vec::new(), Vec::new()));
    }
}
