//! The plan a scheduling cycle at time `t` runs: the activities not yet started,
//! in the same step order, from the state the rover is really in at `t`
//! (docs/semantics.md, "Execution").

use super::sim::Started;
use crate::error::Error;
use std::sync::Arc;

use crate::model::{CycleStart, Duration, EffectAt, Plan, Window};
use crate::scheduler::{
    Act, Dep, HeatHold, Problem, Schedule, Win, compile_windows, schedule, schedule_compiled_until,
    step_numbers, value_index,
};
use crate::units::{BIT_PER_MBIT, MJ_PER_WH};

/// The plan a scheduling cycle scheduled ([`Execution::cycle_plan`]).
///
/// [`Execution::cycle_plan`]: super::Execution::cycle_plan
#[derive(Clone, Debug, PartialEq)]
pub struct CyclePlan {
    /// The cycle's own plan: the activities not yet started, and the ones
    /// still executing (placed first), from the state the rover was in.
    pub plan: Plan,
    /// The plan activity index of each of its activities.
    pub activity_of: Vec<usize>,
}

impl CyclePlan {
    /// The cycle plan's index of plan activity `a`, if the cycle had it.
    pub fn index_of(&self, a: usize) -> Option<usize> {
        self.activity_of.binary_search(&a).ok()
    }

    /// The cycle's scheduler run with its full step trace (the execution
    /// keeps only the outcomes).
    pub fn schedule(&self) -> Result<Schedule, Error> {
        schedule(&self.plan)
    }

    /// [`CyclePlan::schedule`] up to the step of the last of `acts` (cycle
    /// plan indices): the records of those steps and of every step before,
    /// which are all an explanation of them reads.
    pub(crate) fn schedule_through(&self, acts: &[usize]) -> Result<Schedule, Error> {
        let problem = Problem::compile(&self.plan)?;
        let until = acts
            .iter()
            .filter_map(|&a| problem.step_of.get(a).copied())
            .max()
            .unwrap_or(0);
        Ok(schedule_compiled_until(problem, until))
    }
}

/// Why an activity not yet started is left out of a cycle's plan (it can no
/// longer run).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Dropped {
    /// Another member of its group started (plan activity index).
    GroupMemberRan(usize),
    /// A dependency on an activity that ended at `end` leaves no start at or after
    /// the cycle (plan activity index of the target).
    DependencyPassed {
        /// The activity it depends on.
        on: usize,
        /// When that one ended.
        end: i64,
    },
    /// It depends on an activity that can no longer run.
    DependsOnDropped(usize),
}

/// What the execution knows at the cycle about one activity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Status {
    /// Not started.
    Waiting,
    /// Started at `start`, still executing at the cycle; holds until `hold`
    /// (`max(start + duration, t + 1)`).
    Executing { start: i64, hold: i64 },
    /// Ended (completed or aborted) at `end`.
    Ended { end: i64 },
}

impl Status {
    /// The status at a cycle at `t` of an activity that started as `run`
    /// before the cycle (`None`: not started).
    pub(super) fn at(run: Option<&Started>, t: i64) -> Self {
        match run {
            None => Status::Waiting,
            Some(r) if r.end <= t => Status::Ended { end: r.end },
            Some(r) => Status::Executing {
                start: r.start,
                hold: r.planned_end.max(t + 1),
            },
        }
    }
}

/// The cycle's plan and, for each of its activities, the plan activity it is.
pub(super) struct Built {
    pub plan: Plan,
    pub activity_of: Vec<usize>,
}

/// The plan activity index of each dependency's target (`None`: an unknown
/// id), by activity and dependency: looked up once per execution rather than
/// at every cycle.
#[derive(Clone, Debug)]
pub(super) struct Links {
    after: Vec<Vec<Option<usize>>>,
}

impl Links {
    pub(super) fn new(plan: &Plan) -> Self {
        let ids = plan.index_by_id();
        Self {
            after: plan
                .activities
                .iter()
                .map(|a| {
                    a.after
                        .iter()
                        .map(|d| ids.get(d.activity.as_str()).copied())
                        .collect()
                })
                .collect(),
        }
    }
}

/// Which activities the cycle at `t` schedules, and their windows: what its
/// plan and its compiled form are both built from.
pub(super) struct Layout {
    /// The plan activity index of each of the cycle plan's activities.
    pub activity_of: Vec<usize>,
    /// Per plan activity: why it is left out, if it is.
    dropped: Vec<Option<Dropped>>,
    /// Per plan activity not started: its windows from `t` on, cut by its
    /// dependencies on activities that ended.
    windows: Vec<CycleWindows>,
}

/// An activity's windows in a cycle.
#[derive(Clone, Debug)]
enum CycleWindows {
    /// The plan gives none and nothing cut them: the whole cycle horizon.
    Horizon,
    /// The plan's, none starting before the cycle and nothing cutting them
    /// (no copy made).
    Plan,
    /// The plan's cut to the cycle and by dependencies on ended activities.
    Cut(Vec<Window>),
}

impl Layout {
    /// The layout of the cycle at `t` (`links`: those of `plan`).
    pub(super) fn new(plan: &Plan, links: &Links, t: i64, status: &[Status]) -> Self {
        let n = plan.activities.len();
        let started = |i: usize| !matches!(status[i], Status::Waiting);
        let mut dropped: Vec<Option<Dropped>> = vec![None; n];
        // Groups with a member that started keep no other member (the first
        // such member, in file order, is named).
        let mut ran_in_group: std::collections::BTreeMap<&str, usize> =
            std::collections::BTreeMap::new();
        for (j, a) in plan.activities.iter().enumerate() {
            if let Some(g) = a.group.as_deref().filter(|_| started(j)) {
                ran_in_group.entry(g).or_insert(j);
            }
        }
        if !ran_in_group.is_empty() {
            for (i, a) in plan.activities.iter().enumerate() {
                if started(i) {
                    continue;
                }
                if let Some(&by) = a.group.as_deref().and_then(|g| ran_in_group.get(g)) {
                    dropped[i] = Some(Dropped::GroupMemberRan(by));
                }
            }
        }
        // Windows from `t` on, cut by dependencies on activities that ended.
        let mut windows: Vec<CycleWindows> = vec![CycleWindows::Horizon; n];
        for (i, a) in plan.activities.iter().enumerate() {
            if started(i) || dropped[i].is_some() {
                continue;
            }
            // Nothing to cut: the whole cycle horizon, or the plan's windows
            // (no copy made).
            let ended =
                |j: &Option<usize>| j.is_some_and(|j| matches!(status[j], Status::Ended { .. }));
            if !links.after[i].iter().any(ended) {
                match &a.windows {
                    None => continue,
                    Some(ws) if ws.iter().all(|w| w.start >= t) => {
                        windows[i] = CycleWindows::Plan;
                        continue;
                    }
                    Some(_) => {}
                }
            }
            let horizon_last = plan.horizon.end - 1;
            let mut cut = a.windows.is_some();
            let mut ranges: Vec<Window> = match &a.windows {
                Some(ws) => ws.clone(),
                None => vec![Window {
                    start: plan.horizon.start,
                    end: horizon_last,
                    preferred: None,
                    cutoff: None,
                }],
            };
            for (d, &j) in a.after.iter().zip(&links.after[i]) {
                let Some(j) = j else {
                    continue;
                };
                if let Status::Ended { end } = status[j] {
                    cut = true;
                    let (min, max) = if d.meets {
                        (0, Some(0))
                    } else {
                        (d.min_delay.unwrap_or(0), d.max_delay)
                    };
                    let lo = end.saturating_add(min);
                    let hi = max.map_or(i64::MAX, |m| end.saturating_add(m));
                    ranges = clip(ranges, lo, hi);
                    if ranges.is_empty() {
                        dropped[i] = Some(Dropped::DependencyPassed { on: j, end });
                        break;
                    }
                }
            }
            if dropped[i].is_some() || !cut {
                continue;
            }
            // No start before the cycle: windows are clipped to `t` (a
            // preferred time before `t` becomes `t`, which ranks the
            // remaining starts the same way).
            ranges = clip(ranges, t, i64::MAX);
            windows[i] = CycleWindows::Cut(ranges);
        }
        // Dependents of dropped activities can no longer run either.
        loop {
            let mut changed = false;
            for i in 0..n {
                if started(i) || dropped[i].is_some() {
                    continue;
                }
                if let Some(j) = links.after[i]
                    .iter()
                    .flatten()
                    .copied()
                    .find(|&j| dropped[j].is_some())
                {
                    dropped[i] = Some(Dropped::DependsOnDropped(j));
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        // Ended and dropped activities are left out.
        let activity_of = (0..n)
            .filter(|&i| match status[i] {
                Status::Ended { .. } => false,
                Status::Executing { .. } => true,
                Status::Waiting => dropped[i].is_none(),
            })
            .collect();
        Self {
            activity_of,
            dropped,
            windows,
        }
    }

    /// The activities not yet started that the cycle leaves out, with why.
    pub(super) fn dropped(&self) -> Vec<(usize, Dropped)> {
        self.dropped
            .iter()
            .enumerate()
            .filter_map(|(i, d)| Some((i, d.clone()?)))
            .collect()
    }
}

/// The fields of a cycle's activity that are always the whole plan's
/// (resources, comm kinds and groups with the whole plan's indices), with
/// the others empty (what a cycle sets anew): the struct update syntax
/// would clone the whole activity, windows and dependencies included, only
/// to drop what the cycle replaces.
fn unchanged(base: &Act) -> Act {
    Act {
        dur_min: base.dur_min,
        dur_max: base.dur_max,
        mandatory: base.mandatory,
        windows: Vec::new(),
        resources: base.resources.clone(),
        engines: base.engines,
        energy: base.energy,
        peak: base.peak,
        data: base.data,
        awake: base.awake,
        zones: base.zones.clone(),
        after: Vec::new(),
        requires: base.requires.clone(),
        effects: Vec::new(),
        uhf: base.uhf.clone(),
        comm: base.comm,
        group: base.group,
        held: false,
    }
}

/// Builds the plan of the cycle at `t` (`links`: those of `plan`).
pub(super) fn cycle_plan(
    plan: &Plan,
    links: &Links,
    t: i64,
    status: &[Status],
    state_values: &[(String, String)],
    start: CycleStart,
) -> Built {
    let mut layout = Layout::new(plan, links, t, status);
    let mut activities = Vec::with_capacity(layout.activity_of.len());
    for &i in &layout.activity_of {
        let mut a = plan.activities[i].clone();
        match status[i] {
            Status::Ended { .. } => continue,
            Status::Executing { hold, .. } => {
                a.duration = Duration::Fixed(hold - t);
                a.windows = Some(vec![Window {
                    start: t,
                    end: t,
                    preferred: None,
                    cutoff: None,
                }]);
                a.after.clear();
                a.effects.retain(|e| e.at == EffectAt::End);
                a.duration_model = None;
            }
            Status::Waiting => {
                a.windows = match std::mem::replace(&mut layout.windows[i], CycleWindows::Horizon) {
                    CycleWindows::Horizon => None,
                    // Clipped as a cut would be (a preferred start given).
                    CycleWindows::Plan => a.windows.map(|ws| clip(ws, t, i64::MAX)),
                    CycleWindows::Cut(ws) => Some(ws),
                };
                // Dependencies on ended activities became windows.
                let mut targets = links.after[i].iter();
                a.after.retain(|_| {
                    targets
                        .next()
                        .copied()
                        .flatten()
                        .is_some_and(|j| !matches!(status[j], Status::Ended { .. }))
                });
            }
        }
        activities.push(a);
    }
    // Every plan-wide field as it is (cloning the activities would be wasted).
    let mut out = plan.without_activities();
    out.activities = activities;
    out.horizon.start = t;
    out.battery.initial = (start.soc_mj as f64 / MJ_PER_WH).clamp(0.0, out.battery.capacity);
    out.data.initial = (start.data_bit as f64 / BIT_PER_MBIT).max(0.0);
    if let Some(cap) = out.data.capacity {
        out.data.initial = out.data.initial.min(cap);
    }
    for (name, value) in state_values {
        if let Some(def) = out.states.get_mut(name) {
            def.initial = value.clone();
        }
    }
    // A handover already past binds nothing any more.
    if out.handover.is_some_and(|h| h.time < t) {
        out.handover = None;
    }
    out.cycle = Some(start);
    Built {
        plan: out,
        activity_of: layout.activity_of,
    }
}

/// The compiled plan of the cycle at `t` laid out as `layout`, derived from
/// `problem` (the whole plan's, compiled from `plan`) without building the
/// cycle's plan: what [`Problem::compile`] gives for [`cycle_plan`]'s plan,
/// which debug builds compare. An activity the cycle leaves as the whole plan
/// has it (its windows not cut, its dependencies all kept, its names
/// interned at the same indices) is shared, not copied.
#[allow(clippy::too_many_arguments)]
pub(super) fn cycle_problem(
    problem: &Problem,
    plan: &Plan,
    links: &Links,
    t: i64,
    status: &[Status],
    state_values: &[(String, String)],
    start: &CycleStart,
    layout: &Layout,
) -> Result<Problem, Error> {
    let mut index = vec![usize::MAX; plan.activities.len()];
    for (c, &i) in layout.activity_of.iter().enumerate() {
        index[i] = c;
    }
    // Resources, comm kinds and groups keep the whole plan's indices (a
    // scheduler run reads them as names only: which activities share one);
    // compiling the cycle's plan numbers them by first appearance in it
    // instead, which would copy every activity after one that no longer
    // comes first.
    let mut acts = Vec::with_capacity(layout.activity_of.len());
    for &i in &layout.activity_of {
        let base = &problem.acts[i];
        let act = match status[i] {
            Status::Ended { .. } => continue,
            Status::Executing { hold, .. } => Act {
                dur_min: hold - t,
                dur_max: hold - t,
                windows: vec![Win {
                    start: t,
                    end: t,
                    preferred: t,
                    cutoff: None,
                }],
                after: Vec::new(),
                effects: base
                    .effects
                    .iter()
                    .filter(|e| e.at == EffectAt::End)
                    .copied()
                    .collect(),
                held: true,
                ..unchanged(base)
            },
            Status::Waiting => {
                // `None`: the whole plan's (compiled the same).
                let windows = match &layout.windows[i] {
                    CycleWindows::Horizon => Some(compile_windows(None, t, problem.h1)),
                    CycleWindows::Plan => None,
                    CycleWindows::Cut(ws) => Some(compile_windows(Some(ws), t, problem.h1)),
                };
                // Dependencies on ended activities became windows.
                let after = cycle_deps(&base.after, &links.after[i], status, &index);
                if !base.held
                    && windows.as_ref().is_none_or(|w| *w == base.windows)
                    && after.is_none()
                {
                    acts.push(Arc::clone(base));
                    continue;
                }
                Act {
                    windows: windows.unwrap_or_else(|| base.windows.clone()),
                    after: after.unwrap_or_else(|| base.after.clone()),
                    held: false,
                    effects: base.effects.clone(),
                    ..unchanged(base)
                }
            }
        };
        acts.push(Arc::new(act));
    }
    // Activities still executing come first (they are not decided again),
    // then the whole plan's step order: both by (priority, index), the cycle
    // keeping the plan's order of indices.
    let mut order: Vec<usize> = Vec::with_capacity(acts.len());
    for held in [true, false] {
        order.extend(
            problem
                .order
                .iter()
                .map(|&i| index[i])
                .filter(|&c| c != usize::MAX && acts[c].held == held),
        );
    }
    let step_of = step_numbers(&order);
    let mut state_initial = problem.state_initial.clone();
    for (name, value) in state_values {
        let Some(k) = plan.states.keys().position(|n| n == name) else {
            continue;
        };
        state_initial[k] = value_index(plan, &format!("states.{name}.initial"), name, value)?;
    }
    let mut heaters = Vec::with_capacity(start.heaters.len());
    for h in &start.heaters {
        let zone = problem
            .zone_names
            .iter()
            .position(|n| *n == h.zone)
            .ok_or_else(|| {
                Error::invalid("cycle.heaters", format!("unknown zone \"{}\"", h.zone))
            })?;
        let owner = h.owner.as_deref().and_then(|id| {
            let a = plan.activities.iter().position(|a| a.id == id)?;
            Some(index[a]).filter(|&c| c != usize::MAX)
        });
        heaters.push(HeatHold {
            zone,
            end: h.end,
            power: h.power_mw,
            owner,
        });
    }
    // A handover already past binds nothing any more.
    let handover = plan.handover.is_some_and(|h| h.time >= t);
    Ok(Problem {
        h0: t,
        soc0: start.soc_mj,
        data0: start.data_bit,
        handover_time: problem.handover_time.filter(|_| handover),
        handover_soc: problem.handover_soc.filter(|_| handover),
        handover_data: problem.handover_data.filter(|_| handover),
        state_initial,
        zones: problem.zones.clone(),
        zone_names: problem.zone_names.clone(),
        acts,
        order,
        step_of,
        produced0: start.produced_bit,
        awake0: start.awake,
        heaters,
        ..*problem
    })
}

/// A waiting activity's dependencies in the cycle (`targets`: each one's
/// activity in the plan, if any): those on ended activities dropped (they
/// became windows), the others' targets renumbered; `None` when that
/// leaves them as they were.
fn cycle_deps(
    deps: &[Dep],
    targets: &[Option<usize>],
    status: &[Status],
    index: &[usize],
) -> Option<Vec<Dep>> {
    debug_assert_eq!(deps.len(), targets.len(), "a dependency without its link");
    let mut out: Option<Vec<Dep>> = None;
    for (k, (d, &j)) in deps.iter().zip(targets).enumerate() {
        let new = j
            .filter(|&j| !matches!(status[j], Status::Ended { .. }))
            .map(|j| {
                debug_assert_ne!(index[j], usize::MAX, "a dependency left out");
                Dep {
                    target: index[j],
                    ..*d
                }
            });
        match &mut out {
            Some(v) => v.extend(new),
            None if new != Some(*d) => {
                let mut v = Vec::with_capacity(deps.len());
                v.extend_from_slice(&deps[..k]);
                v.extend(new);
                out = Some(v);
            }
            None => {}
        }
    }
    out
}

/// `problem` with its resources, comm kinds and groups numbered by first
/// appearance among its activities, as compiling its plan numbers them
/// (debug builds and tests compare a cycle's problem with its plan's
/// compiled in full).
#[cfg(any(test, debug_assertions))]
pub(super) fn first_appearance(problem: &Problem) -> Problem {
    let (mut resources, mut kinds, mut groups) = (
        Renumber::default(),
        Renumber::default(),
        Renumber::default(),
    );
    let acts = problem
        .acts
        .iter()
        .map(|act| {
            let mut act = Act::clone(act);
            for r in &mut act.resources {
                *r = resources.of(*r);
            }
            for k in act.uhf.iter_mut().flatten() {
                *k = kinds.of(*k);
            }
            act.comm = act.comm.map(|k| kinds.of(k));
            act.group = act.group.map(|g| groups.of(g));
            Arc::new(act)
        })
        .collect();
    Problem {
        acts,
        resource_count: resources.next,
        ..problem.clone()
    }
}

/// Indices of one space of interned names, renumbered by first appearance.
#[cfg(any(test, debug_assertions))]
#[derive(Default)]
struct Renumber {
    map: Vec<usize>,
    next: usize,
}

#[cfg(any(test, debug_assertions))]
impl Renumber {
    /// The new index of old index `k`, the next one when `k` is new.
    fn of(&mut self, k: usize) -> usize {
        if k >= self.map.len() {
            self.map.resize(k + 1, usize::MAX);
        }
        if self.map[k] == usize::MAX {
            self.map[k] = self.next;
            self.next += 1;
        }
        self.map[k]
    }
}

/// Windows `ws` with their start ranges cut to `[lo, hi]`, those with
/// nothing left dropped.
fn clip(ws: Vec<Window>, lo: i64, hi: i64) -> Vec<Window> {
    ws.into_iter()
        .filter_map(|w| {
            let start = w.start.max(lo);
            let end = w.end.min(hi);
            (start <= end).then(|| Window {
                start,
                end,
                preferred: Some(w.preferred_start().clamp(start, end)),
                cutoff: w.cutoff,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::execute::{execute, sample_run};
    use crate::generate::{Profile, add_duration_models, generate_plan_with};

    /// Every cycle of sampled executions of generated plans of every profile
    /// (states, thermal zones with heaters left on, groups, resources and
    /// communication kinds first named by an activity that started,
    /// dependencies on ended activities): the problem derived from the whole
    /// plan's is the cycle's plan compiled in full. Some cycles renumber
    /// names and some share activities, so both paths are taken.
    #[test]
    fn cycle_problems_are_their_plans_compiled() {
        let (mut cycles, mut renumbered, mut shared, mut executing) = (0, 0, 0, 0);
        for (profile, activities, seed) in [
            (Profile::Standard, 150, 1),
            (Profile::Realistic, 150, 2),
            (Profile::Starved, 150, 3),
        ] {
            let plan =
                add_duration_models(generate_plan_with(profile, activities, 2, seed), 0.4, seed);
            let problem = Problem::compile(&plan).expect("compiles");
            let links = Links::new(&plan);
            for run in 0..2 {
                let ex = execute(&plan, &sample_run(&plan, seed, run)).expect("executes");
                for (k, c) in ex.cycles.iter().enumerate() {
                    let Some(start) = &c.start else { continue };
                    let (status, values) = ex.cycle_state(&plan, k);
                    let layout = Layout::new(&plan, &links, c.time, &status);
                    let derived = cycle_problem(
                        &problem, &plan, &links, c.time, &status, &values, start, &layout,
                    )
                    .expect("derives");
                    let built = cycle_plan(&plan, &links, c.time, &status, &values, start.clone());
                    assert_eq!(built.activity_of, layout.activity_of);
                    let full = Problem::compile(&built.plan).expect("compiles");
                    assert_eq!(
                        first_appearance(&derived),
                        full,
                        "{profile:?} seed {seed} run {run} cycle {k}"
                    );
                    // The whole plan's numbering schedules as the cycle's
                    // plan's own.
                    assert_eq!(
                        crate::scheduler::run_resuming(&derived, None).outcomes,
                        crate::scheduler::run_resuming(&full, None).outcomes,
                        "{profile:?} seed {seed} run {run} cycle {k}"
                    );
                    cycles += 1;
                    renumbered += usize::from(
                        derived
                            .acts
                            .iter()
                            .zip(&full.acts)
                            .any(|(x, y)| x.resources != y.resources || x.group != y.group),
                    );
                    shared += derived
                        .acts
                        .iter()
                        .zip(&layout.activity_of)
                        .filter(|&(x, &i)| Arc::ptr_eq(x, &problem.acts[i]))
                        .count();
                    executing += derived.acts.iter().filter(|x| x.held).count();
                }
            }
        }
        assert!(cycles > 100, "only {cycles} cycles");
        assert!(
            renumbered > 0,
            "no cycle's plan numbered a resource or group anew"
        );
        assert!(shared > 0, "no activity was shared");
        assert!(executing > 0, "no activity was executing at a cycle");
    }
}
