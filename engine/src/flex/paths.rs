//! Shortest paths on the distance graph: a compact adjacency form, Dijkstra with
//! potentials (the scheduled times are a feasible potential of every network a
//! schedule satisfies), and the rigid components (zero-length cycles).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Adjacency in compressed form: the out-edges of `u` are
/// `to[off[u]..off[u + 1]]`, `w[...]`, `id[...]` (index of the source edge).
#[derive(Clone, Debug)]
pub(crate) struct Graph {
    pub off: Vec<usize>,
    pub to: Vec<usize>,
    pub w: Vec<i64>,
    pub id: Vec<usize>,
}

impl Graph {
    /// The graph of `edges` `(from, to, w)` on `n` nodes; with `reverse`, every
    /// edge reversed (same weight).
    pub fn new(n: usize, edges: &[(usize, usize, i64)], reverse: bool) -> Self {
        let mut deg = vec![0usize; n + 1];
        for &(u, v, _) in edges {
            deg[if reverse { v } else { u } + 1] += 1;
        }
        for i in 0..n {
            deg[i + 1] += deg[i];
        }
        let off = deg.clone();
        let mut fill = deg;
        let mut to = vec![0; edges.len()];
        let mut w = vec![0; edges.len()];
        let mut id = vec![0; edges.len()];
        for (k, &(u, v, x)) in edges.iter().enumerate() {
            let (a, b) = if reverse { (v, u) } else { (u, v) };
            let at = fill[a];
            fill[a] += 1;
            to[at] = b;
            w[at] = x;
            id[at] = k;
        }
        Self { off, to, w, id }
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.off.len() - 1
    }

    /// Out-edges of `u`: `(to, w, edge id)`.
    pub fn out(&self, u: usize) -> impl Iterator<Item = (usize, i64, usize)> + '_ {
        (self.off[u]..self.off[u + 1]).map(move |k| (self.to[k], self.w[k], self.id[k]))
    }
}

/// Reusable single-source shortest-path work space.
pub(crate) struct Dijkstra {
    /// Distance from the source (`i64::MAX` = not reached).
    pub dist: Vec<i64>,
    /// Nodes reached, in the order they were settled.
    pub settled: Vec<usize>,
    done: Vec<bool>,
    touched: Vec<usize>,
    heap: BinaryHeap<Reverse<(i64, usize)>>,
}

impl Dijkstra {
    pub fn new(n: usize) -> Self {
        Self {
            dist: vec![i64::MAX; n],
            settled: Vec::new(),
            done: vec![false; n],
            touched: Vec::new(),
            heap: BinaryHeap::new(),
        }
    }

    /// Shortest distances from `src` with the potential `pot` (every edge must
    /// satisfy `w + pot[u] - pot[v] >= 0`). A node `v` is relaxed only while
    /// `keep(v, d)` holds for its new distance `d` (a pruning rule that must be
    /// closed under extension: a path through a node it rejects never leads to a
    /// distance it keeps).
    pub fn run(&mut self, g: &Graph, src: usize, pot: &[i64], keep: impl Fn(usize, i64) -> bool) {
        for &u in &self.touched {
            self.dist[u] = i64::MAX;
            self.done[u] = false;
        }
        self.touched.clear();
        self.settled.clear();
        self.heap.clear();
        self.dist[src] = 0;
        self.touched.push(src);
        self.heap.push(Reverse((0, src)));
        while let Some(Reverse((key, u))) = self.heap.pop() {
            if self.done[u] {
                continue;
            }
            let du = key - pot[src] + pot[u];
            if du != self.dist[u] {
                continue;
            }
            self.done[u] = true;
            self.settled.push(u);
            for (v, w, _) in g.out(u) {
                debug_assert!(w + pot[u] - pot[v] >= 0, "potential not feasible");
                let d = du + w;
                if d < self.dist[v] && !self.done[v] && keep(v, d) {
                    if self.dist[v] == i64::MAX {
                        self.touched.push(v);
                    }
                    self.dist[v] = d;
                    self.heap.push(Reverse((d + pot[src] - pot[v], v)));
                }
            }
        }
    }
}

/// Bellman-Ford (queue-based) from `src`: the distances, or a negative cycle as
/// the list of edge ids around it.
pub(crate) fn bellman_ford(g: &Graph, src: usize) -> Result<Vec<i64>, Vec<usize>> {
    let n = g.len();
    let mut dist = vec![i64::MAX; n];
    let mut pred: Vec<Option<(usize, usize)>> = vec![None; n];
    let mut count = vec![0usize; n];
    let mut queued = vec![false; n];
    let mut queue = std::collections::VecDeque::new();
    dist[src] = 0;
    queue.push_back(src);
    queued[src] = true;
    while let Some(u) = queue.pop_front() {
        queued[u] = false;
        for (v, w, id) in g.out(u) {
            let d = dist[u].saturating_add(w);
            if d < dist[v] {
                dist[v] = d;
                pred[v] = Some((u, id));
                count[v] += 1;
                if count[v] > n {
                    return Err(cycle_from(&pred, v, n));
                }
                if !queued[v] {
                    queued[v] = true;
                    queue.push_back(v);
                }
            }
        }
    }
    Ok(dist)
}

/// The negative cycle on the predecessor chain from `v`.
fn cycle_from(pred: &[Option<(usize, usize)>], v: usize, n: usize) -> Vec<usize> {
    // Walk back n steps to land on the cycle.
    let mut x = v;
    for _ in 0..n {
        x = pred[x].map_or(x, |p| p.0);
    }
    let mut ids = Vec::new();
    let mut y = x;
    while let Some((p, id)) = pred[y] {
        ids.push(id);
        y = p;
        if y == x || ids.len() > n {
            break;
        }
    }
    ids.reverse();
    ids
}

/// Strongly connected components of the subgraph of edges `keep` accepts
/// (iterative Tarjan): the component index of every node.
pub(crate) fn components(g: &Graph, keep: impl Fn(usize, usize, i64) -> bool) -> Vec<usize> {
    let n = g.len();
    let mut index = vec![usize::MAX; n];
    let mut low = vec![0; n];
    let mut on_stack = vec![false; n];
    let mut comp = vec![usize::MAX; n];
    let mut stack = Vec::new();
    let mut next = 0;
    let mut ncomp = 0;
    for root in 0..n {
        if index[root] != usize::MAX {
            continue;
        }
        // (node, position in its out-edge list)
        let mut call = vec![(root, g.off[root])];
        index[root] = next;
        low[root] = next;
        next += 1;
        stack.push(root);
        on_stack[root] = true;
        while let Some(&(u, k)) = call.last() {
            if k < g.off[u + 1] {
                let (v, w) = (g.to[k], g.w[k]);
                if let Some(top) = call.last_mut() {
                    top.1 += 1;
                }
                if !keep(u, v, w) {
                    continue;
                }
                if index[v] == usize::MAX {
                    index[v] = next;
                    low[v] = next;
                    next += 1;
                    stack.push(v);
                    on_stack[v] = true;
                    call.push((v, g.off[v]));
                } else if on_stack[v] {
                    low[u] = low[u].min(index[v]);
                }
            } else {
                call.pop();
                if let Some(&(p, _)) = call.last() {
                    low[p] = low[p].min(low[u]);
                }
                if low[u] == index[u] {
                    while let Some(x) = stack.pop() {
                        on_stack[x] = false;
                        comp[x] = ncomp;
                        if x == u {
                            break;
                        }
                    }
                    ncomp += 1;
                }
            }
        }
    }
    comp
}
