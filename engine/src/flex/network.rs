//! The Simple Temporal Network of a schedule: one event at the horizon start, a
//! start and an end event per placed activity, and the distance-graph edges of
//! every temporal constraint the placements rely on, each with its provenance.
//!
//! An edge `from -> to` of weight `w` means `t(to) - t(from) <= w`.

use std::collections::BTreeMap;

use crate::model::{AwakeMode, EffectAt, Plan};
use crate::scheduler::Schedule;

/// A time point of the network.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum TimePoint {
    /// The horizon start (time `horizon.start`, fixed).
    Origin,
    /// The start of an activity (index into `plan.activities`).
    Start(usize),
    /// The end of an activity.
    End(usize),
}

/// Why two placed activities keep the order the schedule gave them.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum OrderKind {
    /// They share this unit resource.
    Resource(String),
    /// One is a comm activity whose kind the other's `uhf_interactions` exclude.
    Uhf,
    /// One is a manual sleep, the other needs the rover awake.
    Sleep,
    /// An effect on this state and a requirement or another effect on it.
    State(String),
    /// The sequence engines they hold would exceed the limit together
    /// (resource flow: the later one runs on engines the earlier one frees).
    Engines,
    /// Their peak power would exceed the limit together (resource flow).
    PeakPower,
}

/// The plan rule behind an edge of the network: failures and conditions name these.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Constraint {
    /// Starts at or after `horizon.start`, ends at or before `horizon.end`.
    Horizon {
        /// Activity index.
        act: usize,
    },
    /// Starts inside window `window` (0-based), the one the schedule used.
    Window {
        /// Activity index.
        act: usize,
        /// Window index.
        window: usize,
    },
    /// Ends at or before the cutoff of window `window`.
    Cutoff {
        /// Activity index.
        act: usize,
        /// Window index.
        window: usize,
    },
    /// Its duration: the scheduled one, or the `duration_model` range.
    Duration {
        /// Activity index.
        act: usize,
    },
    /// `act` starts after `on` ends (with `min_delay`, `max_delay`, `meets`).
    Dependency {
        /// The dependent activity.
        act: usize,
        /// The activity it depends on.
        on: usize,
    },
    /// `first` before `second`, as scheduled.
    Order {
        /// The earlier activity.
        first: usize,
        /// The later activity.
        second: usize,
        /// What needs the order.
        kind: OrderKind,
    },
}

impl Constraint {
    /// The activities the constraint is about.
    pub fn activities(&self) -> Vec<usize> {
        match *self {
            Constraint::Horizon { act }
            | Constraint::Window { act, .. }
            | Constraint::Cutoff { act, .. }
            | Constraint::Duration { act } => vec![act],
            Constraint::Dependency { act, on } => vec![on, act],
            Constraint::Order { first, second, .. } => vec![first, second],
        }
    }
}

/// A distance-graph edge: `t(to) - t(from) <= w`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Edge {
    pub from: usize,
    pub to: usize,
    pub w: i64,
    pub why: Constraint,
}

/// The network of one schedule.
#[derive(Clone, Debug)]
pub(crate) struct Network {
    /// Horizon start (the origin's time).
    pub h0: i64,
    /// The placed activities in plan order; activity `placed[j]` has events
    /// `1 + 2j` (start) and `2 + 2j` (end).
    pub placed: Vec<usize>,
    /// Scheduled `(start, end)` of each placed activity.
    pub nominal: Vec<(i64, i64)>,
    /// Distance-graph edges (parallel edges kept: the tightest wins in paths).
    pub edges: Vec<Edge>,
    /// Placed activities with a `duration_model`: `(j, min, max)`.
    pub contingent: Vec<(usize, i64, i64)>,
}

impl Network {
    /// Number of events.
    pub fn len(&self) -> usize {
        1 + 2 * self.placed.len()
    }

    /// The event of index `e`.
    pub fn event(&self, e: usize) -> TimePoint {
        if e == 0 {
            TimePoint::Origin
        } else if e % 2 == 1 {
            TimePoint::Start(self.placed[(e - 1) / 2])
        } else {
            TimePoint::End(self.placed[(e - 2) / 2])
        }
    }

    /// The index of event `e` (`None` for an activity not placed).
    pub fn index(&self, e: TimePoint) -> Option<usize> {
        let slot = |a: usize| self.placed.binary_search(&a).ok();
        match e {
            TimePoint::Origin => Some(0),
            TimePoint::Start(a) => slot(a).map(|j| 1 + 2 * j),
            TimePoint::End(a) => slot(a).map(|j| 2 + 2 * j),
        }
    }

    /// The scheduled time of event `e`.
    pub fn nominal_time(&self, e: usize) -> i64 {
        if e == 0 {
            self.h0
        } else if e % 2 == 1 {
            self.nominal[(e - 1) / 2].0
        } else {
            self.nominal[(e - 2) / 2].1
        }
    }

    fn upper(&mut self, from: usize, to: usize, w: i64, why: Constraint) {
        self.edges.push(Edge { from, to, w, why });
    }

    /// `t(x) + c <= t(y)`.
    fn before(&mut self, x: usize, y: usize, c: i64, why: Constraint) {
        self.upper(y, x, -c, why);
    }
}

const fn start(j: usize) -> usize {
    1 + 2 * j
}

const fn end(j: usize) -> usize {
    2 + 2 * j
}

/// Builds the network of `sched` (a schedule of `plan`).
pub(crate) fn build(plan: &Plan, sched: &Schedule) -> Network {
    let problem = &sched.problem;
    let n_acts = problem.acts.len();
    let mut slot = vec![usize::MAX; n_acts];
    let mut placed = Vec::new();
    let mut nominal = Vec::new();
    for (a, slot_a) in slot.iter_mut().enumerate() {
        if let Some(p) = sched.placement(a) {
            *slot_a = placed.len();
            placed.push(a);
            nominal.push(p);
        }
    }
    let mut net = Network {
        h0: problem.h0,
        placed,
        nominal,
        edges: Vec::new(),
        contingent: Vec::new(),
    };
    let h0 = problem.h0;
    for j in 0..net.placed.len() {
        let a = net.placed[j];
        let act = &problem.acts[a];
        let (s, e) = net.nominal[j];
        let d = e - s;
        let horizon = Constraint::Horizon { act: a };
        net.before(0, start(j), 0, horizon.clone());
        net.upper(0, end(j), problem.h1 - h0, horizon);
        // The first window whose start range holds the start is the one used: an
        // earlier one holding it would have had that start feasible too.
        let used = act
            .windows
            .iter()
            .position(|w| w.start <= s && s <= w.end && w.cutoff.is_none_or(|c| e <= c));
        if let Some(wi) = used {
            let w = act.windows[wi];
            let why = Constraint::Window { act: a, window: wi };
            net.before(0, start(j), w.start - h0, why.clone());
            net.upper(0, start(j), w.end - h0, why);
            if let Some(c) = w.cutoff {
                net.upper(0, end(j), c - h0, Constraint::Cutoff { act: a, window: wi });
            }
        }
        let (lo, hi) = match plan.activities[a].duration_model {
            Some(m) => {
                // An optional activity is aborted at `start + duration`: its end
                // comes no later than that, whatever the model says.
                let (min, max) = if act.mandatory {
                    (m.min, m.max)
                } else {
                    (m.min.min(d), m.max.min(d))
                };
                if min < max {
                    net.contingent.push((j, min, max));
                }
                (min.min(d), max.max(d))
            }
            None => (d, d),
        };
        let why = Constraint::Duration { act: a };
        net.upper(start(j), end(j), hi, why.clone());
        net.before(start(j), end(j), lo, why);
        for dep in &act.after {
            let t = slot[dep.target];
            if t == usize::MAX {
                continue;
            }
            let why = Constraint::Dependency {
                act: a,
                on: dep.target,
            };
            net.before(end(t), start(j), dep.min_delay, why.clone());
            if let Some(max) = dep.max_delay {
                net.upper(end(t), start(j), max, why);
            }
        }
    }
    orders(plan, sched, &mut net);
    net
}

/// The order `(first, second)` of two placed activities that do not overlap.
fn ordered(net: &Network, x: usize, y: usize) -> (usize, usize) {
    if net.nominal[x].1 <= net.nominal[y].0 {
        (x, y)
    } else {
        (y, x)
    }
}

fn order(net: &mut Network, x: usize, y: usize, kind: OrderKind) {
    let (f, s) = ordered(net, x, y);
    debug_assert!(net.nominal[f].1 <= net.nominal[s].0, "overlapping order");
    let why = Constraint::Order {
        first: net.placed[f],
        second: net.placed[s],
        kind,
    };
    net.before(end(f), start(s), 0, why);
}

/// The ordering constraints the placements rely on.
fn orders(plan: &Plan, sched: &Schedule, net: &mut Network) {
    let problem = &sched.problem;
    let n = net.placed.len();
    // Unit resources: consecutive users in time order (transitively all).
    let mut users: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    for j in 0..n {
        let mut names: Vec<&str> = plan.activities[net.placed[j]]
            .resources
            .iter()
            .map(String::as_str)
            .collect();
        names.sort_unstable();
        names.dedup();
        for r in names {
            users.entry(r).or_default().push(j);
        }
    }
    for (r, mut js) in users {
        js.sort_by_key(|&j| (net.nominal[j], j));
        for pair in js.windows(2) {
            order(net, pair[0], pair[1], OrderKind::Resource(r.to_string()));
        }
    }
    // UHF: every incompatible pair (comm activities are few).
    let comms: Vec<usize> = (0..n)
        .filter(|&j| problem.acts[net.placed[j]].comm.is_some())
        .collect();
    for x in 0..n {
        let ax = &problem.acts[net.placed[x]];
        if ax.uhf.is_none() {
            continue;
        }
        for &c in &comms {
            let kind = problem.acts[net.placed[c]].comm.unwrap_or_default();
            if c != x && !ax.allows(kind) {
                order(net, x, c, OrderKind::Uhf);
            }
        }
    }
    // Manual sleeps against activities that need the rover awake.
    let sleeps: Vec<usize> = (0..n)
        .filter(|&j| problem.acts[net.placed[j]].awake == AwakeMode::Forbidden)
        .collect();
    if !sleeps.is_empty() {
        for x in 0..n {
            if problem.acts[net.placed[x]].awake == AwakeMode::Required {
                for &z in &sleeps {
                    order(net, x, z, OrderKind::Sleep);
                }
            }
        }
    }
    state_orders(plan, sched, net);
    if let Some(limit) = problem.engines {
        let demand: Vec<i64> = (0..n)
            .map(|j| problem.acts[net.placed[j]].engines)
            .collect();
        flow(net, limit, &demand, OrderKind::Engines);
    }
    if let Some(max_peak) = problem.max_peak {
        let demand: Vec<i64> = (0..n).map(|j| problem.acts[net.placed[j]].peak).collect();
        let capacity = max_peak - baseline_peak(sched);
        flow(net, capacity, &demand, OrderKind::PeakPower);
    }
}

/// The highest total peak power of everything but the activities (asleep or awake
/// draw and heaters) over the schedule.
fn baseline_peak(sched: &Schedule) -> i64 {
    let problem = &sched.problem;
    let state = sched.state_after(sched.steps.len());
    let mut own = crate::timeline::StepFn::constant(problem.h0, problem.h1, 0);
    for (a, act) in problem.acts.iter().enumerate() {
        if let Some((s, e)) = state.placed[a] {
            own.add(s, e, act.peak);
        }
    }
    let mut times: Vec<i64> = state.peak.points().iter().map(|p| p.0).collect();
    times.extend(own.points().iter().map(|p| p.0));
    times
        .into_iter()
        .map(|t| state.peak.value_at(t) - own.value_at(t))
        .max()
        .unwrap_or(0)
}

/// A resource flow network (Artigues, Michelon and Reusser 2003) for a capacity
/// resource: in time order, each activity takes its demand first from capacity
/// never used, then from activities that already ended (earliest first), and is
/// ordered after each activity it takes from. Any times that keep these orders
/// keep the total demand within `capacity`, since every unit is held by one
/// activity at a time.
fn flow(net: &mut Network, capacity: i64, demand: &[i64], kind: OrderKind) {
    let n = net.placed.len();
    let mut by_start: Vec<usize> = (0..n).filter(|&j| demand[j] > 0).collect();
    by_start.sort_by_key(|&j| (net.nominal[j].0, j));
    let mut by_end = by_start.clone();
    by_end.sort_by_key(|&j| (net.nominal[j].1, j));
    let mut fresh = capacity.max(0);
    // Units freed by ended activities: (end, j, amount), in end order.
    let mut freed: std::collections::VecDeque<(i64, usize, i64)> = Default::default();
    let mut next_end = 0;
    let mut taken = vec![0; n];
    for &j in &by_start {
        let s = net.nominal[j].0;
        while next_end < by_end.len() && net.nominal[by_end[next_end]].1 <= s {
            let k = by_end[next_end];
            if taken[k] > 0 {
                freed.push_back((net.nominal[k].1, k, taken[k]));
            }
            next_end += 1;
        }
        let mut need = demand[j];
        let take = need.min(fresh);
        fresh -= take;
        need -= take;
        let mut from = Vec::new();
        while need > 0 {
            let Some(front) = freed.front_mut() else {
                // The schedule ran more together than the capacity left by the
                // highest baseline (only where the baseline was lower then):
                // these units are unbacked (docs/semantics.md).
                break;
            };
            let take = need.min(front.2);
            front.2 -= take;
            need -= take;
            from.push(front.1);
            if front.2 == 0 {
                freed.pop_front();
            }
        }
        taken[j] = demand[j] - need;
        from.sort_unstable();
        from.dedup();
        for k in from {
            order(net, k, j, kind.clone());
        }
    }
}

/// A scheduled effect on a state: `(time, step, event, j, value)`, the event of
/// placed activity `j` at which it applies and the value (index) it sets.
type EffectEvent = (i64, usize, usize, usize, usize);

/// State effects and requirements keep their relative order: the effects on each
/// state stay in their scheduled order (strictly where a later time has an earlier
/// step, so that same-time ties cannot change which value wins), and each
/// requirement interval keeps the effects that were before it before it, those
/// inside inside and those after after. An effect inside a requirement interval
/// that sets another value than the required one is harmless in the schedule only
/// because the next effect (a later step) sets the state again at the same
/// instant: the two stay at one instant, or the other value would hold inside
/// the interval once they drift apart.
fn state_orders(plan: &Plan, sched: &Schedule, net: &mut Network) {
    let problem = &sched.problem;
    let names: Vec<&String> = plan.states.keys().collect();
    let n = net.placed.len();
    let placed = net.placed.clone();
    // Per state: its effects.
    let mut effects: Vec<Vec<EffectEvent>> = vec![Vec::new(); names.len()];
    for j in 0..n {
        let a = net.placed[j];
        let step = problem.step_of[a];
        for eff in &problem.acts[a].effects {
            let (t, ev) = if eff.at == EffectAt::Start {
                (net.nominal[j].0, start(j))
            } else {
                (net.nominal[j].1, end(j))
            };
            effects[eff.state].push((t, step, ev, j, eff.value));
        }
    }
    for (st, list) in effects.iter_mut().enumerate() {
        list.sort_unstable();
        list.dedup();
        let kind = || OrderKind::State(names.get(st).map_or_else(String::new, |s| s.to_string()));
        for pair in list.windows(2) {
            let (p, q) = (pair[0], pair[1]);
            let strict = i64::from(p.0 < q.0 && p.1 > q.1);
            let why = Constraint::Order {
                first: placed[p.3],
                second: placed[q.3],
                kind: kind(),
            };
            net.before(p.2, q.2, strict, why);
        }
    }
    for j in 0..n {
        let a = net.placed[j];
        let (s, e) = net.nominal[j];
        for req in &problem.acts[a].requires {
            let list = &effects[req.state];
            let kind = || {
                OrderKind::State(
                    names
                        .get(req.state)
                        .map_or_else(String::new, |s| s.to_string()),
                )
            };
            let others: Vec<_> = list.iter().copied().filter(|x| x.3 != j).collect();
            let mut last_before = None;
            let mut first_after = None;
            let mut inside = Vec::new();
            // Inside effects of another value, each with the effect that
            // overrides it at the same instant.
            let mut overridden = Vec::new();
            for (i, &x) in others.iter().enumerate() {
                if x.0 <= s {
                    last_before = Some(x);
                } else if x.0 < e {
                    inside.push(x);
                    if x.4 != req.value {
                        if let Some(&y) = others.get(i + 1).filter(|y| y.0 == x.0) {
                            overridden.push((x, y));
                        }
                    }
                } else if first_after.is_none() {
                    first_after = Some(x);
                }
            }
            let why = |x: EffectEvent, first_is_effect: bool| Constraint::Order {
                first: if first_is_effect { placed[x.3] } else { a },
                second: if first_is_effect { a } else { placed[x.3] },
                kind: kind(),
            };
            if let Some(x) = last_before {
                net.before(x.2, start(j), 0, why(x, true));
            }
            if let (Some(x), Some(y)) = (inside.first(), inside.last()) {
                let (x, y) = (*x, *y);
                net.before(start(j), x.2, 1, why(x, false));
                net.before(y.2, end(j), 1, why(y, true));
            }
            if let Some(x) = first_after {
                net.before(end(j), x.2, 0, why(x, false));
            }
            // The overriding effect no later than the overridden one: with the
            // order of the effects, at the same instant.
            for (x, y) in overridden {
                let why = Constraint::Order {
                    first: placed[y.3],
                    second: placed[x.3],
                    kind: kind(),
                };
                net.before(y.2, x.2, 0, why);
            }
        }
    }
}
