//! The scheduler's state after some steps: every timeline, updated in place as
//! activities are placed. `Schedule::state_after(k)` rebuilds it for any step by
//! replaying placements (the trace stores deltas, not copies).

use super::problem::Problem;
use crate::model::{AwakeMode, EffectAt};
use crate::timeline::{RateTimeline, StateTimeline, StepFn, TaggedSpans, UnitTimeline};

/// A decided placement with everything phase 2 generated for it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Placement {
    /// Activity index.
    pub act: usize,
    /// Start.
    pub start: i64,
    /// Duration.
    pub duration: i64,
    /// Awake periods (indices into `State::awake`) merged into `new_awake`.
    pub retire: Vec<usize>,
    /// The new awake period replacing them, if the awake periods change.
    pub new_awake: Option<(i64, i64)>,
    /// Generated preheats `(zone, start, end)`.
    pub preheats: Vec<(usize, i64, i64)>,
}

/// The state of every timeline.
#[derive(Clone, Debug)]
pub struct State<'p> {
    /// The problem.
    pub problem: &'p Problem,
    /// `[start, end)` of each placed activity.
    pub placed: Vec<Option<(i64, i64)>>,
    /// The placed activities by `(start, activity)`, and the longest placed
    /// duration: what overlaps a span without a scan of every activity
    /// ([`State::placed_overlapping`]).
    by_start: std::collections::BTreeSet<(i64, usize)>,
    longest: i64,
    /// The scheduled member of each group.
    pub group_member: Vec<Option<usize>>,
    /// Busy intervals per unit resource.
    pub busy: Vec<UnitTimeline>,
    /// Sequence engines in use.
    pub engines: StepFn,
    /// State timelines.
    pub states: Vec<StateTimeline>,
    /// `-D`, capped at 0; its rate (bit/s) is minus the sum of data rates.
    pub data: RateTimeline,
    /// Data produced in `[h0, handover)` (bit).
    pub produced: i128,
    /// Placed comm activities `(start, end, (kind, act))`.
    pub comms: TaggedSpans<(usize, usize)>,
    /// Placed activities with a restricted `uhf_interactions` `(start, end, act)`.
    pub restricted: TaggedSpans<usize>,
    /// Awake periods, sorted, disjoint.
    pub awake: Vec<(i64, i64)>,
    /// Manual sleeps `(start, end, act)`, sorted by start.
    pub sleeps: Vec<(i64, i64, usize)>,
    /// The latest end among `sleeps[..=i]` (a running maximum).
    pub sleep_reach: Vec<i64>,
    /// Heater draw per zone (mW).
    pub zone_draw: Vec<StepFn>,
    /// Union of heater demand intervals per zone, sorted, merged.
    pub zone_on: Vec<Vec<(i64, i64)>>,
    /// Total peak power (mW).
    pub peak: StepFn,
    /// State of charge (mJ); its rate is the net charge rate (mW).
    pub soc: RateTimeline,
    /// The highest total peak power and its first time (cached).
    pub peak_max: Option<(i64, i64)>,
}

impl<'p> State<'p> {
    /// The state before step 1.
    pub fn new(problem: &'p Problem) -> Self {
        let groups = problem
            .acts
            .iter()
            .filter_map(|a| a.group)
            .max()
            .map_or(0, |g| g + 1);
        Self {
            problem,
            placed: vec![None; problem.acts.len()],
            by_start: std::collections::BTreeSet::new(),
            longest: 0,
            group_member: vec![None; groups],
            busy: vec![UnitTimeline::default(); problem.resource_count],
            engines: StepFn::constant(problem.h0, problem.h1, 0),
            states: problem
                .state_initial
                .iter()
                .map(|&v| StateTimeline::new(v))
                .collect(),
            data: RateTimeline::new(
                StepFn::constant(problem.h0, problem.h1, 0),
                -problem.data0,
                0,
            ),
            produced: 0,
            comms: TaggedSpans::default(),
            restricted: TaggedSpans::default(),
            awake: Vec::new(),
            sleeps: Vec::new(),
            sleep_reach: Vec::new(),
            zone_draw: vec![StepFn::constant(problem.h0, problem.h1, 0); problem.zones.len()],
            zone_on: vec![Vec::new(); problem.zones.len()],
            soc: RateTimeline::new(
                StepFn::constant(problem.h0, problem.h1, problem.rtg - problem.asleep),
                problem.soc0,
                problem.capacity,
            ),
            peak: StepFn::constant(problem.h0, problem.h1, problem.asleep),
            peak_max: Some((problem.asleep, problem.h0)),
        }
        .with_cycle_start()
    }

    /// This state for `problem`, a plan that compiles to the same plan-wide
    /// parameters (but for limits no timeline holds: `min_soc`, `max_peak`,
    /// the data and handover limits) and gives the same placements at every
    /// step this state has run (the steps two problems share,
    /// [`Problem::common_steps`], or those a relaxation keeps): those steps
    /// run on `problem` give this state, so it is copied, not replayed.
    pub(crate) fn rebased<'q>(&self, problem: &'q Problem) -> State<'q> {
        debug_assert!(
            self.problem.without_limits() == problem.without_limits()
                && self.placed.len() == problem.acts.len()
                && self.group_member.len() == State::new(problem).group_member.len(),
            "not a state of the same plan-wide problem"
        );
        State {
            problem,
            placed: self.placed.clone(),
            by_start: self.by_start.clone(),
            longest: self.longest,
            group_member: self.group_member.clone(),
            busy: self.busy.clone(),
            engines: self.engines.clone(),
            states: self.states.clone(),
            data: self.data.clone(),
            produced: self.produced,
            comms: self.comms.clone(),
            restricted: self.restricted.clone(),
            awake: self.awake.clone(),
            sleeps: self.sleeps.clone(),
            sleep_reach: self.sleep_reach.clone(),
            zone_draw: self.zone_draw.clone(),
            zone_on: self.zone_on.clone(),
            peak: self.peak.clone(),
            soc: self.soc.clone(),
            peak_max: self.peak_max,
        }
    }

    /// Applies what a cycle of an execution starts from (nothing otherwise): the
    /// awake period the rover is in, the heaters already on, and the data already
    /// produced towards the handover limit.
    fn with_cycle_start(mut self) -> Self {
        let problem = self.problem;
        if let Some((w, e)) = problem.awake0 {
            let extra = problem.awake - problem.asleep;
            let (a, b) = (problem.h0, e.min(problem.h1));
            if a < b {
                self.add_load(a, b, extra, extra);
            }
            self.awake.push((w, e));
        }
        for h in &problem.heaters {
            let end = h.end.min(problem.h1);
            if problem.h0 < end {
                self.raise_heat(h.zone, problem.h0, end, h.power);
            }
            // Without an owner the zone is on in the second before the cycle as
            // well: an activity starting at the cycle needs no preheat.
            if h.owner.is_none() {
                insert_merged(
                    &mut self.zone_on[h.zone],
                    (problem.h0 - 1, end.max(problem.h0)),
                );
            }
        }
        self.produced += problem.produced0;
        self.peak_max = self.peak.max_on(problem.h0, problem.h1);
        self
    }

    /// Zone `z`'s heater asked for `power` mW over `[a, b)`: the zone draws the
    /// largest power demanded of it at each instant.
    fn demand_heat(&mut self, z: usize, a: i64, b: i64, power: i64) {
        self.raise_heat(z, a, b, power);
        insert_merged(&mut self.zone_on[z], (a, b));
    }

    /// Raises zone `z`'s draw to at least `power` mW over `[a, b)`.
    fn raise_heat(&mut self, z: usize, a: i64, b: i64, power: i64) {
        let raise: Vec<(i64, i64, i64)> = self.zone_draw[z]
            .segments(a, b)
            .filter(|seg| seg.2 < power)
            .map(|(x, y, v)| (x, y, power - v))
            .collect();
        for (x, y, dv) in raise {
            self.zone_draw[z].add(x, y, dv);
            self.add_load(x, y, dv, dv);
        }
    }

    /// The state after the recorded `steps` (the first steps of a run of
    /// `problem`), replayed in order.
    pub fn replayed(problem: &'p Problem, steps: &[super::Step]) -> Self {
        let mut state = Self::new(problem);
        for step in steps {
            state.replay(step);
        }
        state
    }

    /// Adds `delta` mW of load on `[a, b)` (drains charge, adds peak).
    fn add_load(&mut self, a: i64, b: i64, energy: i64, peak: i64) {
        self.soc.add_rate(a, b, -energy);
        self.peak.add(a, b, peak);
        self.peak_max = self.peak_max_after_add(a, b, peak);
    }

    /// The largest peak and its first time after `peak` was added on `[a, b)`,
    /// from the one before, without reading the whole horizon (which made every
    /// placement linear in the plan): outside `[a, b)` nothing changed. A rise
    /// keeps the old maximum unless the range now reaches it (on a tie the
    /// earlier time wins; a range segment merged with its left neighbour can only
    /// tie, and the old first time is then earlier still). A fall keeps it unless
    /// it lay in the range: then the whole horizon is read again.
    fn peak_max_after_add(&self, a: i64, b: i64, peak: i64) -> Option<(i64, i64)> {
        let problem = self.problem;
        let (a, b) = (a.max(problem.h0), b.min(problem.h1));
        let whole = || self.peak.max_on(problem.h0, problem.h1);
        match self.peak_max {
            _ if a >= b || peak == 0 => self.peak_max,
            Some((v, t)) if peak > 0 => match self.peak.max_on(a, b) {
                Some((vr, tr)) if vr > v => Some((vr, tr)),
                Some((vr, tr)) if vr == v => Some((v, t.min(tr))),
                _ => Some((v, t)),
            },
            Some((v, t)) if !(a <= t && t < b) => Some((v, t)),
            _ => whole(),
        }
    }

    /// Replays a recorded step: re-derives its placement (deterministic) and applies
    /// it when the step scheduled its activity. Returns the evaluation applied
    /// (without its energy margin, which a recorded placement already passed).
    pub fn replay(&mut self, step: &super::Step) -> Option<super::Evaluated> {
        let super::Outcome::Scheduled { start, end } = step.outcome else {
            return None;
        };
        // The placement's generated pieces do not depend on the state of charge, so
        // the levels are not derived here (a whole replay derives them once, on use).
        let ev = if self.problem.acts[step.activity].held {
            self.held_placement(step.activity)
        } else {
            self.evaluate_inner(step.activity, start, end - start, false)
                .ok()?
        };
        self.apply(step.step, &ev.placement);
        Some(ev)
    }

    /// The placement of an activity still executing when a cycle starts: at its
    /// first window's start for its longest duration, generating nothing (no
    /// awake period, no preheat) and checking nothing. Applying it still adds
    /// its own load and its zones' maintenance draw ([`State::apply`]), so its
    /// `energy` is the charge those change, as for any evaluation: the
    /// explainer bounds what a step can do to a witness's energy margin by it.
    pub fn held_placement(&self, a: usize) -> super::Evaluated {
        let (start, end) = self.problem.held_span(a);
        let duration = end - start;
        let energy =
            super::phase2::drain_of_pieces(&self.load_pieces(a, start, duration, &[], None, &[]))
                .iter()
                .map(|&(x, y, r)| i128::from(r).abs() * i128::from(y - x))
                .sum();
        super::Evaluated {
            placement: Placement {
                act: a,
                start,
                duration,
                retire: Vec::new(),
                new_awake: None,
                preheats: Vec::new(),
            },
            margin: 0,
            soc_reason: None,
            energy,
        }
    }

    /// The placed activities whose `[start, end)` overlaps `[lo, hi)`, in activity
    /// order (those starting at most the longest placed duration before `lo`).
    pub fn placed_overlapping(&self, lo: i64, hi: i64) -> Vec<usize> {
        let mut out: Vec<usize> = self.placed_overlapping_unordered(lo, hi).collect();
        out.sort_unstable();
        debug_assert_eq!(
            out,
            (0..self.placed.len())
                .filter(|&x| self.placed[x].is_some_and(|(s, e)| s < hi && lo < e))
                .collect::<Vec<_>>(),
            "placed overlap index"
        );
        out
    }

    /// [`State::placed_overlapping`] in start order.
    pub fn placed_overlapping_unordered(
        &self,
        lo: i64,
        hi: i64,
    ) -> impl Iterator<Item = usize> + '_ {
        let range = if hi <= lo {
            self.by_start.range((0, 0)..(0, 0))
        } else {
            self.by_start
                .range((lo.saturating_sub(self.longest), 0)..(hi, 0))
        };
        range
            .map(|&(_, x)| x)
            .filter(move |&x| self.placed[x].is_some_and(|(s, e)| s < hi && lo < e))
    }

    /// Applies a placement decided at `step`.
    pub fn apply(&mut self, step: usize, p: &Placement) {
        let problem = self.problem;
        let act = &problem.acts[p.act];
        let (s, e) = (p.start, p.start + p.duration);
        self.placed[p.act] = Some((s, e));
        self.by_start.insert((s, p.act));
        self.longest = self.longest.max(e - s);
        if let Some(g) = act.group {
            self.group_member[g] = Some(p.act);
        }
        for &r in &act.resources {
            self.busy[r].add(s, e);
        }
        self.engines.add(s, e, act.engines);
        for r in &act.requires {
            self.states[r.state].add_requirement(s, e, r.value, p.act);
        }
        for effect in &act.effects {
            let t = if effect.at == EffectAt::Start { s } else { e };
            self.states[effect.state].add_effect(t, step, effect.value, p.act);
        }
        if act.data != 0 {
            self.data.add_rate(s, e, -act.data);
        }
        if let Some(ht) = problem.handover_time {
            let overlap = (e.min(ht) - s.max(problem.h0)).max(0);
            self.produced += i128::from(act.data.max(0)) * i128::from(overlap);
        }
        if let Some(k) = act.comm {
            self.comms.add(s, e, (k, p.act));
        }
        if act.uhf.is_some() {
            self.restricted.add(s, e, p.act);
        }
        if act.awake == AwakeMode::Forbidden {
            let at = self.sleeps.partition_point(|x| x.0 <= s);
            self.sleeps.insert(at, (s, e, p.act));
            self.sleep_reach.truncate(at);
            let mut reach = at.checked_sub(1).map_or(i64::MIN, |i| self.sleep_reach[i]);
            for x in &self.sleeps[at..] {
                reach = reach.max(x.1);
                self.sleep_reach.push(reach);
            }
        }
        if let Some((qa, qb)) = p.new_awake {
            let extra = problem.awake - problem.asleep;
            for part in uncovered(qa, qb, p.retire.iter().map(|&i| self.awake[i])) {
                self.add_load(part.0, part.1, extra, extra);
            }
            self.edit_awake(p);
        }
        for &z in &act.zones {
            let zone = &problem.zones[z];
            let mut demands = vec![(s, e, zone.maintenance)];
            if let Some(&(_, ps, pe)) = p.preheats.iter().find(|x| x.0 == z) {
                demands.push((ps, pe, zone.preheat));
            }
            for (a, b, power) in demands {
                self.demand_heat(z, a, b, power);
            }
            // Its preheat was already running when the cycle started.
            if problem.preheat_running(p.act, z, s) {
                insert_merged(&mut self.zone_on[z], (problem.h0 - 1, s));
            }
        }
        self.add_load(s, e, act.energy, act.peak);
        debug_assert_eq!(
            self.peak_max,
            self.peak.max_on(problem.h0, problem.h1),
            "the running peak maximum"
        );
    }

    /// Replaces the awake periods placement `p` retires with the one it
    /// creates (nothing when it creates none); the loads are not touched.
    pub fn edit_awake(&mut self, p: &Placement) {
        edit_periods(&mut self.awake, p);
    }

    /// Whether the heater of zone `z` is on over the second `t`.
    pub fn heater_on(&self, z: usize, t: i64) -> bool {
        let on = &self.zone_on[z];
        let i = on.partition_point(|x| x.1 <= t);
        on.get(i).is_some_and(|x| x.0 <= t)
    }
}

/// Replaces the periods of `periods` (sorted, disjoint) that placement `p`
/// retires (by index) with the one it creates (nothing when it creates none).
pub fn edit_periods(periods: &mut Vec<(i64, i64)>, p: &Placement) {
    let Some((qa, qb)) = p.new_awake else {
        return;
    };
    let mut i = 0;
    periods.retain(|_| {
        i += 1;
        !p.retire.contains(&(i - 1))
    });
    let at = periods.partition_point(|x| x.0 < qa);
    periods.insert(at, (qa, qb));
}

/// Parts of `[a, b)` not covered by `covered` (sorted, disjoint).
pub fn uncovered(a: i64, b: i64, covered: impl Iterator<Item = (i64, i64)>) -> Vec<(i64, i64)> {
    let mut out = Vec::new();
    let mut t = a;
    for (x, y) in covered {
        if x > t {
            out.push((t, x.min(b)));
        }
        t = t.max(y);
    }
    if t < b {
        out.push((t, b));
    }
    out.retain(|p| p.0 < p.1);
    out
}

/// Inserts `[a, b)` into a sorted union of intervals, merging touching ones.
fn insert_merged(set: &mut Vec<(i64, i64)>, (a, b): (i64, i64)) {
    if a >= b {
        return;
    }
    let i = set.partition_point(|x| x.1 < a);
    let mut j = i;
    let (mut lo, mut hi) = (a, b);
    while j < set.len() && set[j].0 <= hi {
        lo = lo.min(set[j].0);
        hi = hi.max(set[j].1);
        j += 1;
    }
    set.splice(i..j, [(lo, hi)]);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uncovered_parts() {
        assert_eq!(
            uncovered(0, 100, [(10, 20), (50, 60)].into_iter()),
            vec![(0, 10), (20, 50), (60, 100)]
        );
        assert_eq!(uncovered(0, 100, [(0, 100)].into_iter()), vec![]);
    }

    /// A held activity's evaluation counts the charge its application
    /// drains (the explainer bounds a step's effect on the state of charge by
    /// it), though it generates nothing and checks nothing.
    #[test]
    fn held_placement_counts_its_own_drain() {
        let text = r#"{
          "format": "solscope.plan/1",
          "horizon": { "start": 0, "end": 20000 },
          "local_time": { "sol_length": 88775, "offset": 0 },
          "battery": { "capacity": 2000.0, "initial": 1500.0, "min_soc": 1000.0 },
          "power": { "rtg": 25.0, "asleep": 25.0, "awake": 125.0 },
          "sleep": { "wakeup_duration": 300, "shutdown_duration": 300, "min_awake": 0, "min_sleep": 0 },
          "activities": [
            { "id": "look", "priority": 1, "duration": 600,
              "windows": [ { "start": 5000, "end": 10000 } ],
              "energy_rate": 1.0, "awake": "any" }
          ]
        }"#;
        let mut plan = crate::load::load_plan(text).expect("the plan loads").plan;
        plan.cycle = Some(crate::model::CycleStart {
            held: vec!["look".to_owned()],
            ..Default::default()
        });
        let problem = super::super::Problem::compile(&plan).expect("compiles");
        let mut state = State::new(&problem);
        let ev = state.held_placement(0);
        assert_eq!((ev.placement.start, ev.placement.duration), (5000, 600));
        let before = state.soc.level_at(problem.h1);
        state.apply(1, &ev.placement);
        let drained = before - state.soc.level_at(problem.h1);
        // 600 s at 1 W.
        assert_eq!(drained, 600_000);
        assert_eq!(ev.energy, drained);
    }

    #[test]
    fn merged_insert() {
        let mut v = vec![(0, 10), (20, 30)];
        insert_merged(&mut v, (10, 20));
        assert_eq!(v, vec![(0, 30)]);
        insert_merged(&mut v, (40, 50));
        insert_merged(&mut v, (35, 36));
        assert_eq!(v, vec![(0, 30), (35, 36), (40, 50)]);
    }
}
