//! The simulation loop of one execution, whatever the policy: cycle after cycle,
//! the loop settles what ended, asks its [`Executive`] for the cycle's schedule,
//! when the next cycle is and what to start before it, runs the generated awake
//! and heating periods until then, and keeps the cycle. [`Sim`] is the whole state
//! between two cycles (cloned to resume a run: `Prefix`).

use std::borrow::Cow;

use super::cycle::{Dropped, Status};
use super::record::{Integrator, Record, union};
use super::resume::LastRun;
use super::{ActivityRun, Actuals, Cycle, Event, Execution, Guard, RunOutcome, Trigger};
use crate::error::Error;
use crate::model::{AwakeMode, CycleStart, EffectAt, HeaterHold, Plan};
use crate::scheduler::{Problem, RunOutcomes};

/// An execution policy, as the loop of [`Sim::run`] asks it at each cycle (the
/// cycle at `sim.t`): what the cycle schedules, when the next cycle is, and what
/// starts before it.
pub(super) trait Executive {
    /// The schedule the cycle at `sim.t` dispatches from.
    fn schedule<'p>(
        &'p self,
        problem: &Problem,
        plan: &'p Plan,
        sim: &mut Sim,
    ) -> Result<CycleSchedule<'p>, Error>;

    /// When the cycle after the one at `sim.t` is, and why (at or after
    /// `problem.h1`: none).
    fn next_cycle(&self, problem: &Problem, sim: &Sim) -> Next;

    /// Starts ([`Sim::start`]) what `schedule` has due before `next`, which
    /// an activity ending earlier may move; the dispatch events, in order.
    fn start(
        &self,
        problem: &Problem,
        plan: &Plan,
        sim: &mut Sim,
        schedule: &CycleSchedule<'_>,
        next: &mut Next,
    ) -> Vec<Event>;
}

/// What a cycle dispatches from: the plan it scheduled and the outcomes of its
/// run (borrowed when the policy scheduled once for the whole execution).
pub(super) struct CycleSchedule<'p> {
    /// The plan activity index of each of the cycle plan's activities.
    pub activity_of: Vec<usize>,
    /// Activities not yet started that the cycle left out, with why.
    pub dropped: Vec<(usize, Dropped)>,
    /// Where the cycle's run placed each activity, and what it generated.
    pub outcomes: Cow<'p, RunOutcomes>,
    /// The state the cycle's plan starts from (with the heaters already on),
    /// when the plan was built for the cycle (`None`: the plan as it is,
    /// scheduled once).
    pub start: Option<CycleStart>,
    /// Debug builds: the fingerprint of the cycle's plan.
    #[cfg(debug_assertions)]
    pub fingerprint: u64,
}

/// The next cycle: when, and why.
#[derive(Clone, Copy, Debug)]
pub(super) struct Next {
    pub time: i64,
    pub trigger: Trigger,
}

/// The state of an execution between cycles.
#[derive(Clone, Debug)]
pub(super) struct Sim {
    /// Actual duration by activity (`None`: its `duration`).
    pub actual: Vec<Option<i64>>,
    pub status: Vec<Status>,
    pub runs: Vec<Option<Started>>,
    /// The last cycle whose plan had each activity not yet started.
    pub last_cycle: Vec<Option<usize>>,
    /// Where the first cycle placed each activity (empty before it).
    pub predicted: Vec<Option<(i64, i64)>>,
    pub record: Record,
    pub integ: Integrator,
    pub cycles: Vec<Cycle>,
    /// The next cycle's time and trigger.
    pub t: i64,
    pub trigger: Trigger,
    /// The awake periods and heater demands of the latest cycle's schedule
    /// (what the next cycle finds on).
    pub prev_awake: Vec<(i64, i64)>,
    pub prev_heat: Vec<Heat>,
    /// The latest cycle's run, for the next cycle to keep what it can of it
    /// (the replanning policy's).
    pub last_run: Option<LastRun>,
    /// Steps the cycles' runs kept from the cycle before, and steps run in
    /// all (what tests read to see the shortcut at work).
    pub kept: usize,
    pub steps: usize,
    /// Kept placements that store data whose check of the store's capacity
    /// the earlier run proved (what tests read to see that proof at work).
    pub capacity_proved: usize,
    /// Kept steps that were the cycle before's last steps (what tests read
    /// to see that proof at work).
    pub kept_rest: usize,
    /// A fingerprint of every cycle's plan, to check
    /// [`Execution::cycle_plan`]'s rebuilt ones against (not the plans: the
    /// check must not make debug builds keep what release builds rebuild).
    #[cfg(debug_assertions)]
    pub plans: Vec<u64>,
}

impl Sim {
    /// Before the first cycle of `plan` with the actual durations of `actuals`.
    pub fn new(problem: &Problem, plan: &Plan, actuals: &Actuals) -> Self {
        let n = plan.activities.len();
        Self {
            actual: actual_durations(plan, actuals),
            status: vec![Status::Waiting; n],
            runs: vec![None; n],
            last_cycle: vec![None; n],
            predicted: Vec::new(),
            record: Record::default(),
            integ: Integrator::new(problem),
            cycles: Vec::new(),
            t: problem.h0,
            trigger: Trigger::Start,
            prev_awake: Vec::new(),
            prev_heat: Vec::new(),
            last_run: None,
            kept: 0,
            steps: 0,
            capacity_proved: 0,
            kept_rest: 0,
            #[cfg(debug_assertions)]
            plans: Vec::new(),
        }
    }

    /// Runs every cycle left under `executive`, then the execution to the
    /// horizon end.
    pub fn run(
        mut self,
        problem: &Problem,
        plan: &Plan,
        executive: &impl Executive,
    ) -> Result<Execution, Error> {
        while self.cycle(problem, plan, executive)? {}
        Ok(self.finish(problem.clone(), plan))
    }

    /// Runs the cycle at `self.t` and what follows until the next one; `false`
    /// when there is none.
    pub fn cycle(
        &mut self,
        problem: &Problem,
        plan: &Plan,
        executive: &impl Executive,
    ) -> Result<bool, Error> {
        let t = self.t;
        // What ran so far is final up to the cycle.
        self.integ.advance(problem, &self.record, t);
        self.settle(t);
        let soc = self.integ.soc;
        let schedule = executive.schedule(problem, plan, self)?;
        let mut next = executive.next_cycle(problem, self);
        let events = executive.start(problem, plan, self, &schedule, &mut next);
        self.run_generated(problem, plan, &schedule, next.time);
        // Kept of the cycle's outcomes: what it placed and what not (its plan
        // and run are rebuilt on demand).
        let placements = &schedule.outcomes.placements;
        let mut placed = 0;
        let mut failed = Vec::new();
        for (&a, p) in schedule.activity_of.iter().zip(placements) {
            match p {
                Some(_) => placed += 1,
                None => failed.push(a),
            }
        }
        if self.cycles.is_empty() {
            self.predicted = vec![None; plan.activities.len()];
            for (&a, &p) in schedule.activity_of.iter().zip(placements) {
                self.predicted[a] = p;
            }
        }
        #[cfg(debug_assertions)]
        self.plans.push(schedule.fingerprint);
        let CycleSchedule { dropped, start, .. } = schedule;
        self.cycles.push(Cycle {
            time: t,
            trigger: self.trigger,
            soc,
            dropped,
            events,
            start,
            placed,
            failed,
        });
        if next.time >= problem.h1 {
            return Ok(false);
        }
        self.t = next.time;
        self.trigger = next.trigger;
        Ok(true)
    }

    /// The status of every started activity at `t`: ended, or executing and
    /// held until its planned end (at least past `t`).
    fn settle(&mut self, t: i64) {
        for (status, r) in self.status.iter_mut().zip(&self.runs) {
            if r.is_some() {
                *status = Status::at(r.as_ref(), t);
            }
        }
    }

    /// Starts activity `a` at `s` for its scheduled `planned` seconds, in the
    /// cycle running; `seq` orders its effects among those of one instant.
    /// Returns when it ends.
    pub fn start(
        &mut self,
        problem: &Problem,
        plan: &Plan,
        a: usize,
        s: i64,
        planned: i64,
        seq: usize,
    ) -> i64 {
        let (end, aborted) = end_of(plan, a, s, planned, self.actual[a]);
        self.runs[a] = Some(Started {
            start: s,
            end,
            planned_end: s + planned,
            aborted,
            cycle: self.cycles.len(),
            seq,
        });
        self.status[a] = Status::Executing {
            start: s,
            hold: s + planned,
        };
        self.record.activity(problem, a, s, end);
        end
    }

    /// What the cycle's schedule generated runs until the next cycle at
    /// `next`, and so do the heaters that were already on; kept for the next
    /// cycle, if there is one.
    fn run_generated(
        &mut self,
        problem: &Problem,
        plan: &Plan,
        schedule: &CycleSchedule<'_>,
        next: i64,
    ) {
        let t = self.t;
        let keep = next < problem.h1;
        self.prev_awake.clear();
        self.prev_heat.clear();
        for h in schedule.start.iter().flat_map(|c| &c.heaters) {
            if let Some(z) = problem.zone_names.iter().position(|n| *n == h.zone) {
                if keep {
                    let owner = h
                        .owner
                        .as_ref()
                        .and_then(|id| plan.activities.iter().position(|a| &a.id == id));
                    self.prev_heat.push(Heat {
                        zone: z,
                        start: t,
                        end: h.end,
                        power: h.power_mw,
                        owner,
                    });
                }
                let b = h.end.min(next);
                if t < b {
                    self.record.heat.push((z, t, b, h.power_mw));
                }
            }
        }
        let out = &schedule.outcomes;
        for &(a, b) in &out.awake {
            if keep {
                self.prev_awake.push((a, b));
            }
            let (a, b) = (a.max(t), b.min(next));
            if a < b {
                self.record.awake.push((a, b));
            }
        }
        for &(zone, start, end, act) in &out.preheats {
            let power = problem.zones[zone].preheat;
            if keep {
                self.prev_heat.push(Heat {
                    zone,
                    start,
                    end,
                    power,
                    owner: schedule.activity_of.get(act).copied(),
                });
            }
            let (a, b) = (start.max(t), end.min(next));
            if a < b {
                self.record.heat.push((zone, a, b, power));
            }
        }
    }

    /// The execution, after the last cycle.
    pub fn finish(mut self, problem: Problem, plan: &Plan) -> Execution {
        let (h0, h1) = (problem.h0, problem.h1);
        self.integ.advance(&problem, &self.record, h1);
        let activities = (0..plan.activities.len())
            .map(|a| {
                let predicted = self.predicted.get(a).copied().flatten();
                let run = self.runs[a];
                ActivityRun {
                    outcome: match run {
                        None => RunOutcome::NotRun,
                        Some(r) if r.aborted => RunOutcome::Aborted,
                        Some(_) => RunOutcome::Completed,
                    },
                    predicted,
                    actual: run.map(|r| (r.start, r.end)),
                    cycle: run.map(|r| r.cycle),
                    duration: self.actual[a].unwrap_or(plan.activities[a].duration.max()),
                    last_cycle: if run.is_none() {
                        self.last_cycle[a]
                    } else {
                        None
                    },
                }
            })
            .collect();
        let mut profile = std::mem::take(&mut self.integ.profile);
        profile.awake = union(
            self.record
                .awake
                .iter()
                .map(|&(a, b)| (a.max(h0), b.min(h1)))
                .filter(|(a, b)| a < b)
                .collect(),
        );
        let out = Execution {
            cycles: self.cycles,
            activities,
            profile,
            violations: self.integ.violations,
            lowest_soc: self.integ.lowest,
            handover_soc: self.integ.at_handover,
            problem,
            runs: self.runs,
        };
        #[cfg(debug_assertions)]
        for (k, &kept) in self.plans.iter().enumerate() {
            debug_assert_eq!(
                out.cycle_plan(plan, k).map(|c| fingerprint(&c.plan)),
                Some(kept),
                "cycle {k}'s rebuilt plan differs from the one it scheduled"
            );
        }
        out
    }
}

/// Debug builds: a hash of everything `plan` holds (its `Debug` form, which
/// prints every field), to tell a rebuilt cycle plan from the one scheduled.
#[cfg(debug_assertions)]
pub(super) fn fingerprint(plan: &Plan) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    format!("{plan:?}").hash(&mut h);
    h.finish()
}

/// When an activity started at `start` for a planned `planned` seconds ends,
/// and whether it is aborted: an optional one stops at `start + planned`.
pub(super) fn end_of(
    plan: &Plan,
    a: usize,
    start: i64,
    planned: i64,
    actual: Option<i64>,
) -> (i64, bool) {
    let end = start + actual.unwrap_or(planned);
    if !plan.activities[a].mandatory && end > start + planned {
        (start + planned, true)
    } else {
        (end, false)
    }
}

/// The actual duration of each activity under `actuals` (`None`: its
/// `duration`).
pub(super) fn actual_durations(plan: &Plan, actuals: &Actuals) -> Vec<Option<i64>> {
    plan.activities
        .iter()
        .map(|a| actuals.durations.get(&a.id).copied())
        .collect()
}

/// A started activity.
#[derive(Clone, Copy, Debug)]
pub(super) struct Started {
    pub start: i64,
    /// Actual end (the abort time when aborted).
    pub end: i64,
    /// `start` + the duration the cycle placed it for.
    pub planned_end: i64,
    pub aborted: bool,
    pub cycle: usize,
    /// Dispatch order (breaks ties between effects at one instant).
    pub seq: usize,
}

/// A heater demand of a cycle's schedule, or a heater already on at its start.
#[derive(Clone, Copy, Debug)]
pub(super) struct Heat {
    zone: usize,
    start: i64,
    end: i64,
    power: i64,
    /// The activity (plan index) whose preheat it is.
    owner: Option<usize>,
}

/// What the cycle at `sim.t` starts from: the executed state of charge and
/// data, the activities still executing, the awake period and the heaters
/// the rover is in.
pub(super) fn cycle_start(problem: &Problem, plan: &Plan, sim: &Sim) -> CycleStart {
    let t = sim.t;
    let status = &sim.status;
    let held: Vec<usize> = (0..status.len())
        .filter(|&a| matches!(status[a], Status::Executing { .. }))
        .collect();
    // The awake period the rover is in: on in the second before the cycle, to
    // its planned end in the latest schedule, and at least while an activity
    // that requires it is still executing (with its shutdown).
    let awake = (t > problem.h0)
        .then(|| sim.record.awake_since(t - 1))
        .flatten()
        .and_then(|since| {
            let planned = sim
                .prev_awake
                .iter()
                .filter(|&&(a, b)| a < t && t <= b)
                .map(|&(_, b)| b)
                .max();
            let running = held
                .iter()
                .filter(|&&a| problem.acts[a].awake == AwakeMode::Required)
                .filter_map(|&a| match status[a] {
                    Status::Executing { hold, .. } => Some(hold + problem.shut),
                    _ => None,
                })
                .max();
            let end = planned.max(running)?;
            (end > t).then_some((since, end))
        });
    let mut heaters: Vec<HeaterHold> = sim
        .prev_heat
        .iter()
        .filter(|h| h.start < t && t <= h.end)
        .map(|h| HeaterHold {
            zone: problem.zone_names[h.zone].clone(),
            end: h.end,
            power_mw: h.power,
            owner: h
                .owner
                .filter(|&o| matches!(status[o], Status::Waiting))
                .map(|o| plan.activities[o].id.clone()),
        })
        .collect();
    // A zone kept warm by an activity running in the second before the cycle is
    // on then too (an activity starting at the cycle needs no preheat; one still
    // executing keeps it on through its own placement).
    for (a, r) in sim.runs.iter().enumerate() {
        let Some(r) = r else { continue };
        if r.start < t && t <= r.end {
            for &z in &problem.acts[a].zones {
                heaters.push(HeaterHold {
                    zone: problem.zone_names[z].clone(),
                    end: t,
                    power_mw: problem.zones[z].maintenance,
                    owner: None,
                });
            }
        }
    }
    CycleStart {
        soc_mj: sim.integ.soc,
        data_bit: sim.integ.data,
        produced_bit: sim.integ.produced,
        held: held
            .iter()
            .map(|&a| plan.activities[a].id.clone())
            .collect(),
        awake,
        heaters,
    }
}

/// The executed value of every state at `t` (`(state, value)` names): effects
/// at or before `t`, in time then dispatch order.
pub(super) fn state_values(
    problem: &Problem,
    plan: &Plan,
    runs: &[Option<Started>],
    t: i64,
) -> Vec<(String, String)> {
    let mut values = problem.state_initial.clone();
    let mut effects: Vec<(i64, usize, usize, usize)> = Vec::new();
    for (a, r) in runs.iter().enumerate() {
        let Some(r) = r else { continue };
        for e in &problem.acts[a].effects {
            let at = if e.at == EffectAt::Start {
                r.start
            } else {
                r.end
            };
            if at <= t {
                effects.push((at, r.seq, e.state, e.value));
            }
        }
    }
    effects.sort_unstable();
    for (_, _, s, v) in effects {
        values[s] = v;
    }
    plan.states
        .iter()
        .zip(values)
        .map(|((name, def), v)| (name.clone(), def.values[v].clone()))
        .collect()
}

/// Why activity `a` may not start at `s`, if it may not: the dispatch guard
/// every policy starts through.
pub(super) fn guard(
    problem: &Problem,
    plan: &Plan,
    a: usize,
    s: i64,
    runs: &[Option<Started>],
) -> Option<Guard> {
    let act = &problem.acts[a];
    for d in &act.after {
        let ended = runs[d.target].is_some_and(|r| r.end.saturating_add(d.min_delay) <= s);
        if !ended {
            return Some(Guard::Dependency(d.target));
        }
    }
    for (b, r) in runs.iter().enumerate() {
        let Some(r) = r else { continue };
        if b != a
            && r.start <= s
            && s < r.end
            && problem.acts[b]
                .resources
                .iter()
                .any(|x| act.resources.contains(x))
        {
            return Some(Guard::Resource(b));
        }
    }
    if let (Some(cap), true) = (problem.engines, act.engines > 0) {
        // Engines are hardware: those held by the activities executing at `s`
        // (for as long as they actually run) plus its own stay within the cap.
        let mut held = 0i64;
        let mut first = None;
        for (b, r) in runs.iter().enumerate() {
            let Some(r) = r else { continue };
            if b != a && r.start <= s && s < r.end && problem.acts[b].engines > 0 {
                held = held.saturating_add(problem.acts[b].engines);
                first.get_or_insert(b);
            }
        }
        if let Some(b) = first.filter(|_| held.saturating_add(act.engines) > cap) {
            return Some(Guard::Engines(b));
        }
    }
    if !act.requires.is_empty() {
        let values = state_values(problem, plan, runs, s);
        for req in &act.requires {
            let (name, def) = plan.states.iter().nth(req.state)?;
            let now = &values.iter().find(|(n, _)| n == name)?.1;
            if def.values[req.value] != *now {
                return Some(Guard::State(req.state, req.value));
            }
        }
    }
    None
}
