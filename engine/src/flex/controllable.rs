//! Dynamic controllability (Morris 2014, DCbackprop, on the labelled distance
//! graph of Morris 2006) where `duration_model`s make activity ends uncertain.
//!
//! Each uncertain duration `[l, u]` of an activity from start `A` to end `C` is put
//! in normal form: a helper event `H = A + l` and a contingent link `H => C` over
//! `[0, u - l]`, i.e. a lower-case edge `H -> C` of weight 0 and an upper-case edge
//! `C -> H` of weight `-(u - l)`. Back-propagation from every event with a
//! negative incoming edge, through non-negative edges, derives the ordinary edges
//! the executive must respect; meeting an event again on the current chain of
//! propagations is a semi-reducible negative cycle: not controllable. A path that
//! began with an upper-case edge and is still negative at an event `X` is a wait:
//! `X` may not happen before `A + l - w` unless `C` has happened.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

/// An edge label.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Label {
    Ordinary,
    /// Lower-case edge of contingent link `k`.
    Lower(usize),
    /// Upper-case edge of contingent link `k`.
    Upper(usize),
}

/// A contingent link: start event, end event, `[l, u]`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Link {
    pub start: usize,
    pub end: usize,
    pub min: i64,
    pub max: i64,
}

/// The result of the check.
#[derive(Clone, Debug)]
pub(crate) enum Dc {
    /// Controllable: the derived ordinary edges `(from, to, w)` (on the original
    /// events) and the waits `(event, link, offset)`: `event` not before
    /// `start(link) + offset` unless the link's end has happened.
    Controllable {
        derived: Vec<(usize, usize, i64)>,
        waits: Vec<(usize, usize, i64)>,
    },
    /// Not controllable: the events on the negative cycle, the ordinary input
    /// edges (indices) its paths use, and the contingent links (indices) they use.
    Not {
        events: Vec<usize>,
        edges: Vec<usize>,
        links: Vec<usize>,
    },
}

/// Where an edge comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Src {
    /// Ordinary input edge `i`.
    Input(usize),
    /// Part of contingent link `k` (its normal form).
    Link(usize),
    /// Derived by the propagation towards its target (`preds` explains it).
    Derived,
}

struct In {
    from: usize,
    w: i64,
    label: Label,
    src: Src,
}

/// Per propagation: for each node reached, the next node on its path towards the
/// source and the edge taken.
type Preds = HashMap<usize, (usize, Src)>;

struct Checker {
    incoming: Vec<Vec<In>>,
    negative: Vec<bool>,
    done: Vec<bool>,
    on_stack: Vec<bool>,
    stack: Vec<usize>,
    /// The paths of each stacked propagation.
    met: Vec<Preds>,
    /// The paths of each finished propagation, by source.
    preds: HashMap<usize, Preds>,
    derived: HashMap<(usize, usize), i64>,
    waits: HashMap<(usize, usize), i64>,
    links: Vec<Link>,
    helper0: usize,
    failure: Option<usize>,
}

/// Checks the network of `n` events with ordinary `edges` `(from, to, w)` (the
/// uncertain durations left out) and contingent `links`.
pub(crate) fn check(n: usize, edges: &[(usize, usize, i64)], links: &[Link]) -> Dc {
    let total = n + links.len();
    let mut incoming: Vec<Vec<In>> = (0..total).map(|_| Vec::new()).collect();
    for (i, &(u, v, w)) in edges.iter().enumerate() {
        incoming[v].push(In {
            from: u,
            w,
            label: Label::Ordinary,
            src: Src::Input(i),
        });
    }
    for (k, l) in links.iter().enumerate() {
        let h = n + k;
        let src = Src::Link(k);
        incoming[h].push(In {
            from: l.start,
            w: l.min,
            label: Label::Ordinary,
            src,
        });
        incoming[l.start].push(In {
            from: h,
            w: -l.min,
            label: Label::Ordinary,
            src,
        });
        incoming[l.end].push(In {
            from: h,
            w: 0,
            label: Label::Lower(k),
            src,
        });
        incoming[h].push(In {
            from: l.end,
            w: -(l.max - l.min),
            label: Label::Upper(k),
            src,
        });
    }
    let negative: Vec<bool> = incoming
        .iter()
        .map(|ins| ins.iter().any(|e| e.w < 0))
        .collect();
    let mut c = Checker {
        incoming,
        negative,
        done: vec![false; total],
        on_stack: vec![false; total],
        stack: Vec::new(),
        met: Vec::new(),
        preds: HashMap::new(),
        derived: HashMap::new(),
        waits: HashMap::new(),
        links: links.to_vec(),
        helper0: n,
        failure: None,
    };
    for v in 0..total {
        if c.negative[v] && !c.done[v] && !c.backprop(v) {
            return c.conflict(n);
        }
    }
    let map_helper = |x: usize, off: i64| -> (usize, i64) {
        if x >= n {
            (c.links[x - n].start, off + c.links[x - n].min)
        } else {
            (x, off)
        }
    };
    let mut derived: Vec<(usize, usize, i64)> = c
        .derived
        .iter()
        .map(|(&(u, v), &w)| {
            // u -> v with weight w, helpers replaced by their start plus l.
            let (u2, ou) = map_helper(u, 0);
            let (v2, ov) = map_helper(v, 0);
            (u2, v2, w + ou - ov)
        })
        .filter(|&(u, v, _)| u != v)
        .collect();
    derived.sort_unstable();
    derived.dedup_by(|b, a| a.0 == b.0 && a.1 == b.1);
    let mut waits: Vec<(usize, usize, i64)> = c
        .waits
        .iter()
        .filter(|&(&(x, _), _)| x < n)
        .map(|(&(x, k), &off)| (x, k, off))
        .collect();
    waits.sort_unstable();
    Dc::Controllable { derived, waits }
}

impl Checker {
    /// The conflict after a failed propagation: the chain of stacked
    /// propagations from the repeated event, and every input edge and link on
    /// their paths (derived edges expanded through the paths that made them).
    fn conflict(&self, n: usize) -> Dc {
        let from = self.failure.unwrap_or(0);
        let at = self.stack.iter().position(|&x| x == from).unwrap_or(0);
        let chain = &self.stack[at..];
        let mut edges = Vec::new();
        let mut links = Vec::new();
        let mut seen = std::collections::HashSet::new();
        // Work list of (node, source): the path from node to source.
        let mut work: Vec<(usize, usize)> = Vec::new();
        for (i, &src) in chain.iter().enumerate() {
            // The next propagation started at a node this one reached; the last
            // reached the repeated event.
            let next = chain.get(i + 1).copied().unwrap_or(from);
            work.push((next, src));
        }
        let stacked: HashMap<usize, &Preds> =
            self.stack.iter().copied().zip(self.met.iter()).collect();
        while let Some((node, src)) = work.pop() {
            if !seen.insert((node, src)) {
                continue;
            }
            let Some(preds) = stacked.get(&src).copied().or_else(|| self.preds.get(&src)) else {
                continue;
            };
            let mut x = node;
            let mut steps = 0;
            // At least one step: the path from the source back to itself is a cycle.
            while steps <= self.incoming.len() {
                steps += 1;
                let Some(&(y, how)) = preds.get(&x) else {
                    break;
                };
                match how {
                    Src::Input(i) => edges.push(i),
                    Src::Link(k) => links.push(k),
                    Src::Derived => work.push((x, y)),
                }
                x = y;
                if x == src {
                    break;
                }
            }
        }
        let mut events: Vec<usize> = chain
            .iter()
            .map(|&x| if x >= n { self.links[x - n].start } else { x })
            .collect();
        for v in [&mut events, &mut edges, &mut links] {
            v.sort_unstable();
            v.dedup();
        }
        Dc::Not {
            events,
            edges,
            links,
        }
    }

    /// DCbackprop from `src`; false when a semi-reducible negative cycle is found
    /// (`self.failure` then names it).
    fn backprop(&mut self, src: usize) -> bool {
        if self.on_stack[src] {
            self.failure = Some(src);
            return false;
        }
        if self.done[src] {
            return true;
        }
        self.on_stack[src] = true;
        self.stack.push(src);
        let mut preds = Preds::new();
        let mut dist: HashMap<usize, i64> = HashMap::new();
        let mut heap = BinaryHeap::new();
        for e in &self.incoming[src] {
            if e.w < 0 && dist.get(&e.from).is_none_or(|&d| e.w < d) {
                dist.insert(e.from, e.w);
                preds.insert(e.from, (src, e.src));
                heap.push(Reverse((e.w, e.from, e.label)));
            }
        }
        self.met.push(preds);
        while let Some(Reverse((d, u, label))) = heap.pop() {
            if dist.get(&u).is_some_and(|&x| x < d) {
                continue;
            }
            if d >= 0 {
                if u != src && self.derived.get(&(u, src)).is_none_or(|&x| d < x) {
                    // Later propagations through `src` use it.
                    self.derived.insert((u, src), d);
                    self.incoming[src].push(In {
                        from: u,
                        w: d,
                        label: Label::Ordinary,
                        src: Src::Derived,
                    });
                }
                continue;
            }
            if label == Label::Ordinary
                && u != src
                && !self.links.iter().any(|l| l.end == u)
                && self.derived.get(&(u, src)).is_none_or(|&x| d < x)
            {
                // Still negative: the propagation goes on through `u`, but the
                // executive needs the bound itself too (`u` no earlier than
                // `-d` after `src`, e.g. a start that must wait until a
                // contingent end that follows it can no longer come too early).
                // Without it only the bounds derived further back hold.
                self.derived.insert((u, src), d);
            }
            if let Label::Upper(k) = label {
                // A wait: u not before H - d = start + l - d unless the end happened.
                let uncontrolled = self.links.iter().any(|l| l.end == u);
                if !uncontrolled && src == self.helper0 + k {
                    let mut off = self.links[k].min - d;
                    let mut x = u;
                    if x >= self.helper0 {
                        off -= self.links[x - self.helper0].min;
                        x = self.links[x - self.helper0].start;
                    }
                    let slot = self.waits.entry((x, k)).or_insert(off);
                    *slot = (*slot).max(off);
                }
            }
            if u == src {
                // Back at the source with a negative length: a semi-reducible
                // negative cycle.
                self.failure = Some(src);
                return false;
            }
            if self.negative[u] && !self.backprop(u) {
                return false;
            }
            let ins: Vec<(usize, i64, Label, Src)> = self.incoming[u]
                .iter()
                .map(|e| (e.from, e.w, e.label, e.src))
                .collect();
            for (from, w, elabel, esrc) in ins {
                if w < 0 {
                    continue;
                }
                if let (Label::Lower(a), Label::Upper(b)) = (elabel, label) {
                    if a == b {
                        continue; // unsuitable: the path began with this link's upper case
                    }
                }
                let nd = d + w;
                if dist.get(&from).is_none_or(|&x| nd < x) {
                    dist.insert(from, nd);
                    if let Some(m) = self.met.last_mut() {
                        m.insert(from, (u, esrc));
                    }
                    heap.push(Reverse((nd, from, label)));
                }
            }
        }
        self.stack.pop();
        if let Some(p) = self.met.pop() {
            self.preds.insert(src, p);
        }
        self.on_stack[src] = false;
        self.done[src] = true;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Events: 0 origin, 1 start of A, 2 end of A, 3 start of B. A lasts 1 to 2
    // hours (uncertain); both start within a day.
    const HOUR: i64 = 3600;

    fn base() -> (Vec<(usize, usize, i64)>, Vec<Link>) {
        let day = 24 * HOUR;
        let edges = vec![
            (0, 1, day),
            (1, 0, 0),
            (0, 3, day),
            (3, 0, 0),
            (0, 2, day + 2 * HOUR),
            (2, 0, 0),
        ];
        let links = vec![Link {
            start: 1,
            end: 2,
            min: HOUR,
            max: 2 * HOUR,
        }];
        (edges, links)
    }

    /// The tightest derived bound `t(v) - t(u) <= w`.
    fn derived_bound(dc: &Dc, u: usize, v: usize) -> Option<i64> {
        let Dc::Controllable { derived, .. } = dc else {
            return None;
        };
        derived
            .iter()
            .filter(|e| (e.0, e.1) == (u, v))
            .map(|e| e.2)
            .min()
    }

    #[test]
    fn b_at_least_an_hour_before_a_ends_must_start_by_a_start() {
        // t(B) <= t(end A) - 1 h: A may end after only 1 h, so B must start no
        // later than A starts: the derived edge start A -> start B of length 0.
        let (mut edges, links) = base();
        edges.push((2, 3, -HOUR));
        let dc = check(4, &edges, &links);
        assert_eq!(derived_bound(&dc, 1, 3), Some(0), "{dc:?}");
        // And if B must also start 10 min after A starts, no strategy works.
        edges.push((3, 1, -600));
        match check(4, &edges, &links) {
            Dc::Not {
                events,
                links: used,
                ..
            } => {
                assert!(events.contains(&3) || events.contains(&1), "{events:?}");
                assert_eq!(used, vec![0]);
            }
            other => panic!("expected not controllable, got {other:?}"),
        }
    }

    #[test]
    fn b_at_most_an_hour_before_a_ends_waits_an_hour_after_a_starts() {
        // t(B) >= t(end A) - 1 h: A may last 2 h, so B starts no earlier than 1 h
        // after A starts (the wait for A's end reduces to that plain bound, since
        // A lasts at least 1 h).
        let (mut edges, links) = base();
        edges.push((3, 2, HOUR));
        let dc = check(4, &edges, &links);
        assert_eq!(derived_bound(&dc, 3, 1), Some(-HOUR), "{dc:?}");
        // A bound of 30 min instead: B waits for A's end or 90 min after its start.
        let (mut edges, links) = base();
        edges.push((3, 2, HOUR / 2));
        let dc = check(4, &edges, &links);
        let Dc::Controllable { waits, .. } = &dc else {
            panic!("{dc:?}")
        };
        assert_eq!(waits, &vec![(3, 0, 3 * HOUR / 2)]);
    }

    #[test]
    fn certain_network_is_controllable_without_waits() {
        let (edges, _) = base();
        match check(4, &edges, &[]) {
            Dc::Controllable { waits, .. } => assert!(waits.is_empty()),
            other => panic!("{other:?}"),
        }
    }
}
