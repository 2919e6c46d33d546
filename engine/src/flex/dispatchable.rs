//! Bounds and the minimum dispatchable network (Tsamardinos, Muscettola and Morris
//! 1998) of a consistent network.
//!
//! Bounds: one Dijkstra each way from the origin, with the scheduled times as the
//! potential (the schedule satisfies every edge, so reduced lengths are >= 0).
//!
//! Rigid components (events whose distance is fixed: zero-length cycles, whose
//! edges all have reduced length 0) collapse onto a leader, the end of an
//! uncertain duration if one is a member (it is observed, not set), else the
//! earliest member (ties: the earlier step);
//! members are linked to it and happen at its time plus their offset. On the
//! collapsed graph, an edge `A -> C` of the
//! all-pairs graph is dominated when some `B` on a shortest path from `A` to `C`
//! has `D(B, C) >= 0` (for `D(A, C) >= 0`: upper dominance) or `D(A, B) < 0` (for
//! `D(A, C) < 0`: lower dominance); the undominated edges are the minimum
//! dispatchable network. One Dijkstra per leader finds them, with the minimum
//! of `D(A, B)` over the intermediate nodes of the shortest-path DAG.
//!
//! Sparse: a distance `D(A, C)` no shorter than through the origin,
//! `D(A, O) + D(O, C) = ub_C - lb_A`, is dominated through the origin, and no
//! path through such a `C` leads to a distance shorter than through the origin,
//! so the search from `A` stops at it. Each search visits only the events whose
//! relation to `A` is tighter than their bounds alone.

use super::paths::{Dijkstra, Graph, components};

/// Bounds of every event and the minimum dispatchable network.
#[derive(Clone, Debug)]
pub(crate) struct Dispatchable {
    /// Leader of each event's rigid component, and its offset from it.
    pub leader: Vec<(usize, i64)>,
    /// The network's edges `(from, to, w)`: `t(to) - t(from) <= w`, sorted.
    pub edges: Vec<(usize, usize, i64)>,
}

/// Earliest and latest time of every event: `(lb, ub)`, absolute.
pub(crate) fn bounds(h0: i64, fwd: &Graph, rev: &Graph, nominal: &[i64]) -> (Vec<i64>, Vec<i64>) {
    let n = fwd.len();
    let mut dij = Dijkstra::new(n);
    dij.run(fwd, 0, nominal, |_, _| true);
    let ub: Vec<i64> = dij.dist.iter().map(|&d| h0.saturating_add(d)).collect();
    let neg: Vec<i64> = nominal.iter().map(|&t| -t).collect();
    dij.run(rev, 0, &neg, |_, _| true);
    let lb: Vec<i64> = dij.dist.iter().map(|&d| h0.saturating_sub(d)).collect();
    (lb, ub)
}

/// The minimum dispatchable network of the graph `fwd` (event 0 the origin at
/// `h0`), given its bounds and a feasible assignment `nominal`. A rigid
/// component's leader is an `observed` member if it has one (the end of an
/// uncertain duration: the executive cannot set it, only react to it), else its
/// earliest member, ties going to the lower `tie` (the step of the event's
/// activity: dispatch then starts simultaneous activities in the order the
/// schedule placed them).
pub(crate) fn dispatchable(
    h0: i64,
    fwd: &Graph,
    nominal: &[i64],
    lb: &[i64],
    ub: &[i64],
    tie: &[usize],
    observed: &[bool],
) -> Dispatchable {
    let n = fwd.len();
    let comp = components(fwd, |u, v, w| w + nominal[u] - nominal[v] == 0);
    let ncomp = comp.iter().map(|&c| c + 1).max().unwrap_or(0);
    // Leader: an observed member, else the earliest (ties: lowest index; the
    // origin leads its own).
    let key = |e: usize| (!observed[e], nominal[e], tie[e], e);
    let mut lead = vec![usize::MAX; ncomp];
    for (e, &c) in comp.iter().enumerate() {
        let l = lead[c];
        if l == usize::MAX || key(e) < key(l) {
            lead[c] = e;
        }
    }
    let leader: Vec<(usize, i64)> = (0..n)
        .map(|e| {
            let l = lead[comp[e]];
            (l, nominal[e] - nominal[l])
        })
        .collect();
    // The collapsed graph on leaders (compact indices), parallel edges merged.
    let leaders: Vec<usize> = {
        let mut v = lead.clone();
        v.sort_unstable();
        v
    };
    let mut compact = vec![usize::MAX; n];
    for (i, &l) in leaders.iter().enumerate() {
        compact[l] = i;
    }
    let mut cedges: Vec<(usize, usize, i64)> = Vec::new();
    for u in 0..n {
        for (v, w, _) in fwd.out(u) {
            let (lu, ou) = leader[u];
            let (lv, ov) = leader[v];
            if lu != lv {
                cedges.push((compact[lu], compact[lv], w + ou - ov));
            }
        }
    }
    cedges.sort_unstable();
    cedges.dedup_by(|b, a| a.0 == b.0 && a.1 == b.1);
    let m = leaders.len();
    let g = Graph::new(m, &cedges, false);
    let pot: Vec<i64> = leaders.iter().map(|&l| nominal[l]).collect();
    let clb: Vec<i64> = leaders.iter().map(|&l| lb[l]).collect();
    let cub: Vec<i64> = leaders.iter().map(|&l| ub[l]).collect();
    let origin = compact[0];
    let mut out: Vec<(usize, usize, i64)> = Vec::new();
    let mut dij = Dijkstra::new(m);
    let mut min_via = vec![i64::MAX; m];
    let mut indeg = vec![0usize; m];
    for a in 0..m {
        if a == origin {
            dij.run(&g, a, &pot, |_, _| true);
        } else {
            let lba = clb[a];
            dij.run(&g, a, &pot, |v, d| v != origin && d < cub[v] - lba);
        }
        let dist = &dij.dist;
        let settled = &dij.settled;
        // Topological order of the shortest-path DAG (Kahn): zero-length edges
        // between equal keys may settle out of order.
        for &u in settled {
            indeg[u] = 0;
            min_via[u] = i64::MAX;
        }
        let on_dag = |u: usize, v: usize, w: i64| {
            dist[u] != i64::MAX && dist[v] != i64::MAX && dist[u] + w == dist[v]
        };
        for &u in settled {
            for (v, w, _) in g.out(u) {
                if v != a && on_dag(u, v, w) {
                    indeg[v] += 1;
                }
            }
        }
        let mut queue: Vec<usize> = vec![a];
        let mut head = 0;
        while head < queue.len() {
            let u = queue[head];
            head += 1;
            let via_u = if u == a {
                i64::MAX
            } else {
                min_via[u].min(dist[u])
            };
            for (v, w, _) in g.out(u) {
                if v != a && on_dag(u, v, w) {
                    min_via[v] = min_via[v].min(via_u);
                    indeg[v] -= 1;
                    if indeg[v] == 0 {
                        queue.push(v);
                    }
                }
            }
        }
        debug_assert_eq!(queue.len(), settled.len(), "shortest-path DAG has a cycle");
        for &c in settled {
            if c == a {
                continue;
            }
            let d = dist[c];
            let dominated = if d >= 0 {
                min_via[c] <= d
            } else {
                min_via[c] < 0
            };
            if !dominated {
                out.push((leaders[a], leaders[c], d));
            }
        }
        if a != origin {
            // The edge to the origin, `-lb` relative: its intermediates are the
            // events reached (anything else on a shortest path to the origin
            // would be rigid with it).
            let d = h0 - clb[a];
            let dominated = settled.iter().any(|&b| {
                b != a
                    && dist[b] + (h0 - clb[b]) == d
                    && if d >= 0 { dist[b] <= d } else { dist[b] < 0 }
            });
            if !dominated {
                out.push((leaders[a], 0, d));
            }
        }
    }
    // Rigid components: each member linked both ways to its leader; a member is
    // executed with its leader, at the leader's time plus its offset.
    for (e, &(l, off)) in leader.iter().enumerate() {
        if l != e {
            out.push((l, e, off));
            out.push((e, l, -off));
        }
    }
    out.sort_unstable();
    Dispatchable { leader, edges: out }
}
