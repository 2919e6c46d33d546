//! The dispatch policy: the flexible schedule executed by its start and skip
//! conditions, in time order.

use std::collections::BTreeMap;

use super::{no_next, scheduled_once};
use crate::error::Error;
use crate::execute::sim::{CycleSchedule, Executive, Next, Sim, guard};
use crate::execute::{Event, Guard};
use crate::flex::{Flex, TimePoint};
use crate::model::Plan;
use crate::scheduler::{Problem, RunOutcomes};

/// The dispatching executive of a plan scheduled once, with its flexible form.
pub(super) struct Dispatch<'a> {
    pub outcomes: &'a RunOutcomes,
    pub flex: &'a Flex,
}

impl Executive for Dispatch<'_> {
    fn schedule<'p>(
        &'p self,
        _: &Problem,
        plan: &'p Plan,
        _: &mut Sim,
    ) -> Result<CycleSchedule<'p>, Error> {
        Ok(scheduled_once(plan, self.outcomes))
    }

    fn next_cycle(&self, problem: &Problem, _: &Sim) -> Next {
        no_next(problem)
    }

    /// [`dispatch`], over the whole horizon.
    fn start(
        &self,
        problem: &Problem,
        plan: &Plan,
        sim: &mut Sim,
        _: &CycleSchedule<'_>,
        _: &mut Next,
    ) -> Vec<Event> {
        dispatch(problem, plan, self.flex, sim)
    }
}

/// The flexible schedule by its conditions: in time order (never before the last
/// event), the next event is the earliest actual end of a running activity or the
/// earliest start an enabled activity's condition allows (ends first at the same
/// time). An activity is enabled once every event of its `after` list with a
/// non-negative offset has happened (one with a negative offset binds only if its
/// event happened first; a zero offset from an activity the guard held back at
/// this instant counts as that instant) and every activity it waits for has
/// started. Its latest start is `min(ub, within...)` lowered by what the pending
/// activities it holds back need ([`Blocking`]); it starts at `max(lb, after...,
/// min(nom, latest))` (and not before a wait's time unless that activity has
/// ended), and is skipped when that is later than its latest start or the guard
/// does not let it start (once the others starting at that instant have
/// started). An activity some event of whose `after` list never happens does not
/// run. `docs/semantics.md` ("Execution policies") is the reading.
fn dispatch(problem: &Problem, plan: &Plan, flex: &Flex, sim: &mut Sim) -> Vec<Event> {
    // When each event happened, by `Times::slot`.
    let mut times = Times(vec![None; 1 + 2 * plan.activities.len()]);
    times.insert(TimePoint::Origin, problem.h0);
    let (waits, tightened): (Vec<crate::flex::Wait>, Vec<(usize, i64, i64)>) =
        match &flex.controllability {
            crate::flex::Controllability::Controllable { waits, tightened } => {
                (waits.clone(), tightened.clone())
            }
            _ => (Vec::new(), Vec::new()),
        };
    // On a controllable network the start bounds are the tightened ones (they hold
    // whatever the uncertain durations turn out to be).
    // Looked up once per activity, not per activity and event.
    let by_activity: BTreeMap<usize, (i64, i64)> =
        tightened.iter().map(|t| (t.0, (t.1, t.2))).collect();
    let bounds_of: Vec<(i64, i64)> = flex
        .activities
        .iter()
        .map(|fa| {
            by_activity
                .get(&fa.activity)
                .copied()
                .unwrap_or((fa.start.lb, fa.start.ub))
        })
        .collect();
    let bounds = |j: usize| bounds_of[j];
    let mut waits_of: Vec<Vec<crate::flex::Wait>> = vec![Vec::new(); flex.activities.len()];
    for w in &waits {
        if let Some(j) = flex.position(w.activity) {
            waits_of[j].push(*w);
        }
    }
    let blocking = Blocking::new(flex, &waits_of);
    let mut pending: Vec<usize> = (0..flex.activities.len()).collect();
    // Running activities whose end has not happened: (end, activity).
    let mut running: Vec<(i64, usize)> = Vec::new();
    let mut events = Vec::new();
    // Held back by the guard at an instant when others may still start: (index,
    // activity, time, guard).
    let mut deferred: Vec<(usize, usize, i64, Guard)> = Vec::new();
    let mut latest = vec![i64::MAX; flex.activities.len()];
    // The time of the last event: nothing starts before it.
    let mut clock = problem.h0;
    loop {
        // The latest start of each pending activity: its own bound and `within`
        // conditions, then (latest first) what an activity it must start before
        // needs of it.
        for &j in &pending {
            let (_, ub) = bounds(j);
            latest[j] = flex.activities[j]
                .condition
                .within
                .iter()
                .filter_map(|b| times.get(b.event).map(|x| x + b.offset))
                .fold(ub, i64::min);
        }
        blocking.propagate(&pending, &mut latest);
        // The earliest allowed start of each enabled pending activity.
        let mut next: Option<(i64, usize, usize)> = None; // (time, step, index)
        let mut skipped = Vec::new();
        for (i, &j) in pending.iter().enumerate() {
            let fa = &flex.activities[j];
            let a = fa.activity;
            let c = &fa.condition;
            let (lb, _) = bounds(j);
            let latest = latest[j];
            let mut t = lb.max(clock);
            let mut enabled = true;
            // Set when it may start only at the instant of an activity the guard
            // held back there (it may be what that one waits for).
            let mut only_at = None;
            for b in &c.after {
                match times.get(b.event) {
                    Some(x) => t = t.max(x + b.offset),
                    // A bound at or after the event needs it to have happened; one
                    // before it binds only if it happened first.
                    None if b.offset >= 0 => match b.event {
                        // Exactly at the start of one held back at this instant,
                        // as if it had started (it is tried again after).
                        TimePoint::Start(x) if b.offset == 0 => {
                            match deferred.iter().find(|d| d.1 == x) {
                                Some(&(_, _, at, _)) => {
                                    t = t.max(at);
                                    only_at = Some(at);
                                }
                                None => enabled = false,
                            }
                        }
                        _ => enabled = false,
                    },
                    None => {}
                }
            }
            for w in &waits_of[j] {
                match (
                    times.get(TimePoint::Start(w.on)),
                    times.get(TimePoint::End(w.on)),
                ) {
                    // Ended: nothing to wait for.
                    (_, Some(_)) => {}
                    (Some(s), None) => t = t.max(s + w.offset),
                    // Not started: a wait at or after its start needs it to
                    // have started; one before it binds only if it starts first.
                    (None, None) if w.offset >= 0 => enabled = false,
                    (None, None) => {}
                }
            }
            if !enabled {
                continue;
            }
            let t = t.max(fa.start.nom.min(latest));
            if only_at.is_some_and(|at| t != at) {
                continue;
            }
            if t > latest {
                skipped.push((i, a, latest));
                continue;
            }
            let key = (t, problem.step_of[a], i);
            if next.is_none_or(|n| key < n) {
                next = Some(key);
            }
        }
        if !skipped.is_empty() {
            for &(i, a, latest) in skipped.iter().rev() {
                pending.remove(i);
                events.push(Event::Held {
                    activity: a,
                    time: latest,
                    guard: Guard::Skipped,
                });
            }
            continue;
        }
        let end = running.iter().copied().min();
        // Held back at an earlier instant than the next event: final.
        let now = match (end, next) {
            (Some((e, _)), Some((t, ..))) => e.min(t),
            (Some((e, _)), None) => e,
            (None, Some((t, ..))) => t,
            (None, None) => i64::MAX,
        };
        deferred.retain(|&(_, a, t, g)| {
            if t < now {
                events.push(Event::Held {
                    activity: a,
                    time: t,
                    guard: g,
                });
                false
            } else {
                true
            }
        });
        match (end, next) {
            (Some((e, a)), n) if n.is_none_or(|n| e <= n.0) => {
                clock = e;
                times.insert(TimePoint::End(a), e);
                running.retain(|&(_, b)| b != a);
            }
            (_, Some((t, _, i))) => {
                clock = t;
                let j = pending.remove(i);
                let fa = &flex.activities[j];
                let a = fa.activity;
                if let Some(g) = guard(problem, plan, a, t, &sim.runs) {
                    // Tried again if another activity starts at this instant.
                    deferred.push((j, a, t, g));
                    continue;
                }
                let planned = fa.end.nom - fa.start.nom;
                // Same-time effects apply in the schedule's step order, as
                // the schedule that placed them assumed.
                let end = sim.start(problem, plan, a, t, planned, problem.step_of[a]);
                events.push(Event::Started {
                    activity: a,
                    time: t,
                });
                times.insert(TimePoint::Start(a), t);
                running.push((end, a));
                for (j, ..) in deferred.drain(..) {
                    pending.push(j);
                }
                pending.sort_unstable();
            }
            _ => break,
        }
    }
    for (_, a, t, g) in deferred {
        events.push(Event::Held {
            activity: a,
            time: t,
            guard: g,
        });
    }
    events
}

/// The time each event of the dispatch happened: a slot per event (the origin,
/// then each activity's start and end), not a map searched per condition.
struct Times(Vec<Option<i64>>);

impl Times {
    fn slot(e: TimePoint) -> usize {
        match e {
            TimePoint::Origin => 0,
            TimePoint::Start(a) => 1 + 2 * a,
            TimePoint::End(a) => 2 + 2 * a,
        }
    }

    fn get(&self, e: TimePoint) -> Option<i64> {
        self.0.get(Self::slot(e)).copied().flatten()
    }

    fn insert(&mut self, e: TimePoint, t: i64) {
        if let Some(x) = self.0.get_mut(Self::slot(e)) {
            *x = Some(t);
        }
    }
}

/// Which pending activities hold back which: `b` cannot start before `a` has
/// started when `b`'s condition has a non-negative offset from `a`'s start (or
/// from `a`'s end, or waits for `a`). When `b` must start by `t`, `a` must then
/// start by `t` minus the offset (minus `a`'s planned duration for its end), or
/// `b` would miss its deadline waiting for it. The dispatcher moves deadlines
/// back along these edges, latest first, before it picks the next start.
struct Blocking {
    /// Flex indices, each after every index it holds back (a reverse
    /// topological order; activities on a cycle, which can never be enabled,
    /// are left out).
    order: Vec<usize>,
    /// Per flex index: `(held, gap)`: the activity it holds back, and how long
    /// before that one's deadline it must start.
    held: Vec<Vec<(usize, i64)>>,
}

impl Blocking {
    /// `waits_of[k]`: the waits of the activity at flex index `k`.
    fn new(flex: &Flex, waits_of: &[Vec<crate::flex::Wait>]) -> Self {
        let n = flex.activities.len();
        // How long each activity is planned to run (a controllable network's
        // bounds already allow for the longest).
        let planned = |j: usize| {
            let fa: &crate::flex::FlexActivity = &flex.activities[j];
            fa.end.nom - fa.start.nom
        };
        let mut held: Vec<Vec<(usize, i64)>> = vec![Vec::new(); n];
        for (k, fa) in flex.activities.iter().enumerate() {
            for b in fa.condition.after.iter().filter(|b| b.offset >= 0) {
                let (j, gap) = match b.event {
                    TimePoint::Start(a) => match flex.position(a) {
                        Some(j) => (j, b.offset),
                        None => continue,
                    },
                    TimePoint::End(a) => match flex.position(a) {
                        Some(j) => (j, b.offset.saturating_add(planned(j))),
                        None => continue,
                    },
                    TimePoint::Origin => continue,
                };
                if j != k {
                    held[j].push((k, gap));
                }
            }
            for w in waits_of[k].iter().filter(|w| w.offset >= 0) {
                if let Some(j) = flex.position(w.on) {
                    held[j].push((k, w.offset));
                }
            }
        }
        // Kahn's algorithm on the reversed edges: an activity once every one it
        // holds back is placed.
        let mut out = vec![0usize; n];
        let mut holders: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (j, hs) in held.iter().enumerate() {
            out[j] = hs.len();
            for &(k, _) in hs {
                holders[k].push(j);
            }
        }
        let mut order: Vec<usize> = (0..n).filter(|&j| out[j] == 0).collect();
        let mut i = 0;
        while i < order.len() {
            for &j in &holders[order[i]] {
                out[j] -= 1;
                if out[j] == 0 {
                    order.push(j);
                }
            }
            i += 1;
        }
        Self { order, held }
    }

    /// Lowers `latest` of the pending activities by the deadlines of the pending
    /// ones they hold back.
    fn propagate(&self, pending: &[usize], latest: &mut [i64]) {
        let mut is_pending = vec![false; latest.len()];
        for &j in pending {
            is_pending[j] = true;
        }
        for &j in &self.order {
            if !is_pending[j] {
                continue;
            }
            for &(k, gap) in &self.held[j] {
                if is_pending[k] {
                    latest[j] = latest[j].min(latest[k].saturating_sub(gap));
                }
            }
        }
    }
}
