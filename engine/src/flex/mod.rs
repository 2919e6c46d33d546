//! Flexible schedules: the Simple Temporal Network of a schedule, its bounds and
//! minimum dispatchable network, start and skip conditions, dynamic
//! controllability where durations are uncertain, and free slack (the scheduler's
//! own checks with every other placement fixed). docs/semantics.md, "Flexible
//! schedule", records each reading of the contract.

mod controllable;
mod dispatchable;
mod network;
mod paths;
mod slack;
mod text;

pub use network::{Constraint, OrderKind, TimePoint};
pub use text::{constraint_line, flex_text, time_point_name};

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use crate::model::Plan;
use crate::scheduler::Schedule;
use crate::timeline::IntervalSet;
use controllable::{Dc, Link};
use dispatchable::{bounds, dispatchable};
use paths::{Graph, bellman_ford};

/// Earliest, scheduled and latest time of one event.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EventBounds {
    /// Earliest time consistent with the network.
    pub lb: i64,
    /// The scheduled time.
    pub nom: i64,
    /// Latest time consistent with the network.
    pub ub: i64,
}

/// A bound an executed neighbour puts on an event: `t >= t(event) + offset`
/// (in `after`) or `t <= t(event) + offset` (in `within`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Bound {
    /// The neighbour event.
    pub event: TimePoint,
    /// Seconds after it (negative: before it).
    pub offset: i64,
}

/// When an activity starts under dispatch: at
/// `max(lb, after..., min(nom, ub, within...))` once every `after` neighbour has
/// happened, and it is skipped once `min(ub, within...)` has passed.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct StartCondition {
    /// Lower bounds from neighbours of the minimum dispatchable network.
    pub after: Vec<Bound>,
    /// Upper bounds from neighbours.
    pub within: Vec<Bound>,
}

/// A wait (dynamic controllability): `activity` does not start before
/// `start(on) + offset` unless `on` has ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Wait {
    /// The waiting activity (its start).
    pub activity: usize,
    /// The activity of uncertain duration it waits for.
    pub on: usize,
    /// Seconds after `on` starts.
    pub offset: i64,
}

/// Whether the executive can meet every constraint whatever the uncertain
/// durations turn out to be, deciding only from what has happened.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Controllability {
    /// No placed activity has a `duration_model`.
    Certain,
    /// Dynamically controllable: the bounds of the starts tightened for every
    /// outcome (`(activity, lb, ub)`), and the waits.
    Controllable {
        /// Tightened start bounds, per placed activity in plan order.
        tightened: Vec<(usize, i64, i64)>,
        /// Waits, sorted.
        waits: Vec<Wait>,
    },
    /// Not dynamically controllable.
    NotControllable {
        /// The activities on the negative cycle found.
        activities: Vec<usize>,
        /// The plan constraints met along it.
        constraints: Vec<Constraint>,
    },
}

/// One placed activity of a flexible schedule.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FlexActivity {
    /// Activity index.
    pub activity: usize,
    /// Its start: `[lb, ub]` is the total slack.
    pub start: EventBounds,
    /// Its end.
    pub end: EventBounds,
    /// Its start condition (skip once `min(ub, within...)` passes).
    pub condition: StartCondition,
    /// Activities adjacent to it in the minimum dispatchable network (one of
    /// its events is an end of one of [`Flex::dispatchable`]'s edges whose
    /// other end is theirs), sorted: a member of a rigid component has its
    /// leader, the leader every member.
    pub neighbours: Vec<usize>,
    /// Free slack: starts every check of the scheduler (both phases) accepts with
    /// every other placement fixed, and dependents' dependencies kept. `None`
    /// when not computed.
    pub free_slack: Option<IntervalSet>,
    /// The starts that pass phase 1 (and dependents) alone: a superset of
    /// `free_slack` whose extra part breaks wake/sleep, heating, peak power or
    /// energy.
    pub free_slack_phase1: Option<IntervalSet>,
}

/// An edge of the minimum dispatchable network: `t(to) - t(from) <= max`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct DispatchEdge {
    /// From.
    pub from: TimePoint,
    /// To.
    pub to: TimePoint,
    /// Upper bound on `t(to) - t(from)`.
    pub max: i64,
}

/// An edge of the temporal network as built: `t(to) - t(from) <= max`, with the
/// plan rule behind it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NetworkEdge {
    /// From.
    pub from: TimePoint,
    /// To.
    pub to: TimePoint,
    /// Upper bound on `t(to) - t(from)`.
    pub max: i64,
    /// The rule.
    pub why: Constraint,
}

/// The flexible (dispatchable) form of a schedule.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Flex {
    /// Placed activities, in plan order.
    pub activities: Vec<FlexActivity>,
    /// Distance-graph edges of the network as built (parallel edges merged).
    pub network_edges: usize,
    /// The network as built (parallel edges kept), the uncertain durations as
    /// their ranges widened to the scheduled duration.
    pub network: Vec<NetworkEdge>,
    /// The minimum dispatchable network, sorted.
    pub dispatchable: Vec<DispatchEdge>,
    /// Events rigidly tied to an earlier one (a fixed duration, `meets`, a
    /// pinned window, an overridden state effect): `(member, leader, offset)`. A member happens exactly at its
    /// leader's time plus the offset, so it is executed with its leader.
    pub rigid: Vec<(TimePoint, TimePoint, i64)>,
    /// Dynamic controllability.
    pub controllability: Controllability,
}

impl Flex {
    /// The entry of activity `a`, if placed.
    pub fn activity(&self, a: usize) -> Option<&FlexActivity> {
        self.position(a).map(|i| &self.activities[i])
    }

    /// The index in `activities` of activity `a`, if placed.
    pub fn position(&self, a: usize) -> Option<usize> {
        self.activities
            .binary_search_by_key(&a, |x| x.activity)
            .ok()
    }
}

/// What [`flex_with`] computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FlexOptions {
    /// Compute the free slack (a replay of the schedule per activity).
    pub free_slack: bool,
}

impl Default for FlexOptions {
    fn default() -> Self {
        Self { free_slack: true }
    }
}

/// The free slack of placed activity `a` alone (`None` when it is not placed):
/// `(phase 1 only, every check)`, as [`FlexActivity`] reports them. One replay of
/// the schedule after its step: what an app asks for the selected activity.
pub fn free_slack_of(sched: &Schedule, a: usize) -> Option<(IntervalSet, IntervalSet)> {
    let placed = sched.placement(a)?;
    slack::free_slack(sched, a, placed, None)
}

/// The free slack of one activity: `(phase 1 only, every check)`, as
/// [`FlexActivity`] reports them.
pub type FreeSlack = (IntervalSet, IntervalSet);

/// The free slack of each of `activities` (their indices in the plan), as
/// [`free_slack_of`] gives it, computed in parallel on the current rayon pool
/// and begun in the order given (so a caller puts first what it wants first:
/// the app, the activities in view). Free slack costs one replay of the
/// schedule after each activity's step, so it is quadratic in the placed
/// activities (minutes at 10,000): hence the two controls.
///
/// - `cancel`, when set, stops the computation: no further activity is begun,
///   and those under way stop at their next few replayed steps. The result then
///   holds what was done.
/// - `on_done` is called with each activity's index and free slack as soon as
///   it is known (on the worker threads, in any order): what has been computed
///   so far, before the whole is done.
///
/// The result is in the order of `activities`: `None` for an activity that is
/// not placed or was not done before the cancel.
pub fn free_slack_each(
    sched: &Schedule,
    activities: &[usize],
    cancel: Option<&AtomicBool>,
    on_done: &(dyn Fn(usize, &FreeSlack) + Sync),
) -> Vec<Option<FreeSlack>> {
    let out: Mutex<Vec<Option<FreeSlack>>> = Mutex::new(vec![None; activities.len()]);
    let next = AtomicUsize::new(0);
    let cancelled = || cancel.is_some_and(|c| c.load(Ordering::Relaxed));
    // Each thread takes the next activity in order (rather than rayon's split
    // of the slice in halves), so the first ones are done first.
    rayon::broadcast(|_| {
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            if i >= activities.len() || cancelled() {
                return;
            }
            let a = activities[i];
            let Some(placed) = sched.placement(a) else {
                continue;
            };
            if let Some(fs) = slack::free_slack(sched, a, placed, cancel) {
                on_done(a, &fs);
                // A poisoned lock means another thread panicked: the panic
                // goes on to the caller through rayon; the value is still
                // good to write.
                let mut out = out
                    .lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner);
                out[i] = Some(fs);
            }
        }
    });
    out.into_inner()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

impl Flex {
    /// Puts `slack` as activity `a`'s free slack (as [`free_slack_each`] or
    /// [`free_slack_of`] gives it); `false` when `a` is not placed here.
    pub fn set_free_slack(&mut self, a: usize, slack: FreeSlack) -> bool {
        let Some(i) = self.position(a) else {
            return false;
        };
        let (p1, both) = slack;
        self.activities[i].free_slack_phase1 = Some(p1);
        self.activities[i].free_slack = Some(both);
        true
    }
}

/// The flexible form of `sched`, a schedule of `plan`, with free slack.
pub fn flex(plan: &Plan, sched: &Schedule) -> Flex {
    flex_with(plan, sched, FlexOptions::default())
}

/// [`flex`] with options.
pub fn flex_with(plan: &Plan, sched: &Schedule, opts: FlexOptions) -> Flex {
    let net = network::build(plan, sched);
    let n = net.len();
    let h0 = net.h0;
    let nominal: Vec<i64> = (0..n).map(|e| net.nominal_time(e)).collect();
    let mut plain: Vec<(usize, usize, i64)> =
        net.edges.iter().map(|e| (e.from, e.to, e.w)).collect();
    plain.sort_unstable();
    plain.dedup_by(|b, a| a.0 == b.0 && a.1 == b.1);
    let network_edges = plain.len();
    let fwd = Graph::new(n, &plain, false);
    let rev = Graph::new(n, &plain, true);
    let (lb, ub) = bounds(h0, &fwd, &rev, &nominal);
    #[cfg(debug_assertions)]
    for e in 0..n {
        debug_assert!(
            lb[e] <= nominal[e] && nominal[e] <= ub[e],
            "nominal outside bounds"
        );
    }
    // With uncertain durations, dispatch runs on the controllable network.
    let (controllability, dispatch_on) = if net.contingent.is_empty() {
        (Controllability::Certain, None)
    } else {
        controllability(&net, &plain)
    };
    let dispatch_on_controllable = dispatch_on.is_some();
    let (dlb, dub, graph, potential) = match dispatch_on {
        None => (lb.clone(), ub.clone(), fwd, nominal.clone()),
        Some((edges, potential)) => {
            let g = Graph::new(n, &edges, false);
            let r = Graph::new(n, &edges, true);
            let (l, u) = bounds(h0, &g, &r, &potential);
            (l, u, g, potential)
        }
    };
    let tie: Vec<usize> = (0..n)
        .map(|e| {
            if e == 0 {
                0
            } else {
                sched.problem.step_of[net.placed[(e - 1) / 2]]
            }
        })
        .collect();
    // On a controllable network the uncertain ends are observed: they lead.
    let mut observed = vec![false; n];
    if dispatch_on_controllable {
        for &(j, ..) in &net.contingent {
            observed[2 + 2 * j] = true;
        }
    }
    let disp = dispatchable(h0, &graph, &potential, &dlb, &dub, &tie, &observed);
    let controllability = match controllability {
        Controllability::Controllable { waits, .. } => Controllability::Controllable {
            tightened: (0..net.placed.len())
                .map(|j| (net.placed[j], dlb[1 + 2 * j], dub[1 + 2 * j]))
                .collect(),
            waits,
        },
        other => other,
    };
    // Conditions and neighbours from the dispatchable edges.
    let mut after: Vec<Vec<Bound>> = vec![Vec::new(); n];
    let mut within: Vec<Vec<Bound>> = vec![Vec::new(); n];
    let mut adjacent: Vec<Vec<usize>> = vec![Vec::new(); n];
    for &(u, v, w) in &disp.edges {
        if u != 0 {
            after[u].push(Bound {
                event: net.event(v),
                offset: -w,
            });
        }
        if v != 0 {
            within[v].push(Bound {
                event: net.event(u),
                offset: w,
            });
        }
        adjacent[u].push(v);
        adjacent[v].push(u);
    }
    let act_of = |e: usize| (e >= 1).then(|| net.placed[(e - 1) / 2]);
    let slack: Vec<Option<FreeSlack>> = if opts.free_slack {
        free_slack_each(sched, &net.placed, None, &|_, _| {})
    } else {
        vec![None; net.placed.len()]
    };
    let activities = (0..net.placed.len())
        .map(|j| {
            let (s, e) = (1 + 2 * j, 2 + 2 * j);
            let a = net.placed[j];
            let mut condition = StartCondition::default();
            let (lead, off) = disp.leader[s];
            // The origin's bounds are `lb`/`ub`; the activity's own end follows its
            // start.
            // Members of its own rigid component follow it: they are not bounds.
            let keep = |b: &Bound| {
                b.event != TimePoint::Origin
                    && !is_own(b.event, a)
                    && net.index(b.event).is_none_or(|x| disp.leader[x].0 != s)
            };
            if lead != s && lead != 0 {
                // Rigid with its leader: it happens exactly `off` after it.
                let b = Bound {
                    event: net.event(lead),
                    offset: off,
                };
                condition.after.push(b);
                condition.within.push(b);
            } else if lead == s {
                // A lower bound before an event that itself always comes at or
                // after this start never binds: it is that event's upper bound.
                let later = |b: &Bound| {
                    b.offset < 0
                        && net.index(b.event).is_some_and(|x| {
                            after[x]
                                .iter()
                                .any(|c| c.event == TimePoint::Start(a) && c.offset >= 0)
                        })
                };
                condition.after = after[s]
                    .iter()
                    .copied()
                    .filter(|b| keep(b) && !later(b))
                    .collect();
                // An upper bound with a negative offset comes from an event that
                // always happens later: it bounds that event, not this start.
                condition.within = within[s]
                    .iter()
                    .copied()
                    .filter(|b| keep(b) && b.offset >= 0)
                    .collect();
            }
            condition.after.sort_unstable();
            condition.within.sort_unstable();
            // The activities one edge away in the dispatchable network: a member
            // of a rigid component is linked to its leader only (the leader's
            // own edges are not repeated for each member), so the lists together
            // are as long as the network. The origin is no activity.
            let mut neighbours: Vec<usize> = [s, e]
                .iter()
                .flat_map(|&x| adjacent[x].iter().copied())
                .filter_map(act_of)
                .filter(|&b| b != a)
                .collect();
            neighbours.sort_unstable();
            neighbours.dedup();
            let (free_slack_phase1, free_slack) = match &slack[j] {
                Some((p1, both)) => (Some(p1.clone()), Some(both.clone())),
                None => (None, None),
            };
            FlexActivity {
                activity: a,
                start: EventBounds {
                    lb: lb[s],
                    nom: nominal[s],
                    ub: ub[s],
                },
                end: EventBounds {
                    lb: lb[e],
                    nom: nominal[e],
                    ub: ub[e],
                },
                condition,
                neighbours,
                free_slack,
                free_slack_phase1,
            }
        })
        .collect();
    let dispatchable = disp
        .edges
        .iter()
        .map(|&(u, v, w)| DispatchEdge {
            from: net.event(u),
            to: net.event(v),
            max: w,
        })
        .collect();
    let network = net
        .edges
        .iter()
        .map(|e| NetworkEdge {
            from: net.event(e.from),
            to: net.event(e.to),
            max: e.w,
            why: e.why.clone(),
        })
        .collect();
    let rigid = (0..n)
        .filter(|&e| disp.leader[e].0 != e)
        .map(|e| (net.event(e), net.event(disp.leader[e].0), disp.leader[e].1))
        .collect();
    Flex {
        activities,
        network_edges,
        network,
        rigid,
        dispatchable,
        controllability,
    }
}

/// A not-controllable verdict reduced to a minimal conflict (deletion filter):
/// the input edges and links its paths used, each dropped in turn when the
/// network of the rest is still not controllable. Controllable verdicts pass
/// through.
fn minimal(n: usize, ordinary: &[(usize, usize, i64)], links: &[Link], dc: Dc) -> Dc {
    let Dc::Not {
        events,
        mut edges,
        links: mut used,
    } = dc
    else {
        return dc;
    };
    let not_dc = |e: &[usize], l: &[usize]| {
        let sub: Vec<(usize, usize, i64)> = e.iter().map(|&i| ordinary[i]).collect();
        let lk: Vec<Link> = l.iter().map(|&k| links[k]).collect();
        matches!(controllable::check(n, &sub, &lk), Dc::Not { .. })
    };
    // The paths found may not close a conflict on their own: then start from
    // every edge among the events they touch, and every link (reported as found
    // if even that is controllable).
    if !not_dc(&edges, &used) {
        let mut touched = vec![false; n];
        touched[0] = true;
        for &i in &edges {
            touched[ordinary[i].0] = true;
            touched[ordinary[i].1] = true;
        }
        for &k in &used {
            touched[links[k].start] = true;
            touched[links[k].end] = true;
        }
        let wider: Vec<usize> = (0..ordinary.len())
            .filter(|&i| touched[ordinary[i].0] && touched[ordinary[i].1])
            .collect();
        let all: Vec<usize> = (0..links.len()).collect();
        if not_dc(&wider, &all) {
            edges = wider;
            used = all;
        }
    }
    if not_dc(&edges, &used) {
        let mut i = 0;
        while i < edges.len() {
            let mut rest = edges.clone();
            rest.remove(i);
            if not_dc(&rest, &used) {
                edges = rest;
            } else {
                i += 1;
            }
        }
        let mut k = 0;
        while k < used.len() {
            let mut rest = used.clone();
            rest.remove(k);
            if not_dc(&edges, &rest) {
                used = rest;
            } else {
                k += 1;
            }
        }
    }
    Dc::Not {
        events,
        edges,
        links: used,
    }
}

/// Whether `e` is one of activity `a`'s own events.
fn is_own(e: TimePoint, a: usize) -> bool {
    matches!(e, TimePoint::Start(x) | TimePoint::End(x) if x == a)
}

/// Distance-graph edges `(from, to, w)`.
type Edges = Vec<(usize, usize, i64)>;

/// The verdict "not controllable" naming the plan rules behind `edges` (network
/// edges `(from, to, w)`, the built edge with that weight), the uncertain
/// durations `durations`, and the activities of the `events` and of all those.
fn not_controllable(
    net: &network::Network,
    edges: impl Iterator<Item = (usize, usize, i64)>,
    durations: impl Iterator<Item = usize>,
    events: &[usize],
) -> Controllability {
    let mut constraints: Vec<Constraint> = edges
        .filter_map(|(u, v, w)| {
            net.edges
                .iter()
                .find(|x| (x.from, x.to, x.w) == (u, v, w))
                .map(|x| x.why.clone())
        })
        .collect();
    constraints.extend(durations.map(|k| Constraint::Duration {
        act: net.placed[net.contingent[k].0],
    }));
    constraints.sort();
    constraints.dedup();
    let mut activities: Vec<usize> = events
        .iter()
        .filter(|&&e| e >= 1)
        .map(|&e| net.placed[(e - 1) / 2])
        .chain(constraints.iter().flat_map(Constraint::activities))
        .collect();
    activities.sort_unstable();
    activities.dedup();
    Controllability::NotControllable {
        activities,
        constraints,
    }
}

/// The dynamic controllability of the network, and when controllable the edges
/// to dispatch on (the ordinary edges, the uncertain durations as their ranges,
/// and the derived edges) with a feasible potential for them.
fn controllability(
    net: &network::Network,
    plain: &[(usize, usize, i64)],
) -> (Controllability, Option<(Edges, Vec<i64>)>) {
    let n = net.len();
    let links: Vec<Link> = net
        .contingent
        .iter()
        .map(|&(j, min, max)| Link {
            start: 1 + 2 * j,
            end: 2 + 2 * j,
            min,
            max,
        })
        .collect();
    let uncertain = |u: usize, v: usize| {
        links
            .iter()
            .any(|l| (u, v) == (l.start, l.end) || (u, v) == (l.end, l.start))
    };
    let ordinary: Vec<(usize, usize, i64)> = plain
        .iter()
        .copied()
        .filter(|&(u, v, _)| !uncertain(u, v))
        .collect();
    // Propagation recurses along chains of events: give it room.
    let dc = std::thread::scope(|scope| {
        std::thread::Builder::new()
            .stack_size(1 << 30)
            .spawn_scoped(scope, || {
                minimal(
                    n,
                    &ordinary,
                    &links,
                    controllable::check(n, &ordinary, &links),
                )
            })
            .map(|h| h.join())
    });
    let dc = match dc {
        Ok(Ok(dc)) => dc,
        // A thread that cannot start (or panicked) is reported, not hidden.
        _ => Dc::Not {
            events: Vec::new(),
            edges: Vec::new(),
            links: Vec::new(),
        },
    };
    match dc {
        Dc::Not {
            events,
            edges,
            links: used,
        } => (
            not_controllable(
                net,
                edges.iter().map(|&i| ordinary[i]),
                used.into_iter(),
                &events,
            ),
            None,
        ),
        Dc::Controllable { derived, waits } => {
            let mut edges = ordinary;
            for l in &links {
                edges.push((l.start, l.end, l.max));
                edges.push((l.end, l.start, -l.min));
            }
            edges.extend(derived);
            edges.sort_unstable();
            edges.dedup_by(|b, a| a.0 == b.0 && a.1 == b.1);
            let g = Graph::new(n, &edges, false);
            match bellman_ford(&g, 0) {
                Ok(dist) => {
                    let waits = waits
                        .into_iter()
                        .filter(|&(x, _, _)| x >= 1 && x % 2 == 1)
                        .map(|(x, k, offset)| Wait {
                            activity: net.placed[(x - 1) / 2],
                            on: net.placed[net.contingent[k].0],
                            offset,
                        })
                        .collect();
                    // The latest consistent times: a feasible potential.
                    let pot: Vec<i64> = dist.iter().map(|&d| net.h0.saturating_add(d)).collect();
                    (
                        Controllability::Controllable {
                            tightened: Vec::new(),
                            waits,
                        },
                        Some((edges, pot)),
                    )
                }
                Err(cycle) => (
                    not_controllable(
                        net,
                        cycle.iter().map(|&i| edges[i]),
                        std::iter::empty(),
                        &[],
                    ),
                    None,
                ),
            }
        }
    }
}
